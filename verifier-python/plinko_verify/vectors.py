"""Checks this implementation against the specification's test vectors (docs/engine-spec-vectors.json)."""

import json
import struct

from .board import Board
from .fairness import sha256_hex, drop_seed
from .random_stream import Arc4Random
from .simulate import simulate_drop, initial_conditions
from .state_hash import StateHasher, body_state_hash

TRACE_TICKS = (1, 10, 100)


def _double(value):
    """A vector's number as a double; JSON has no -0, so the file writes it as the string "-0"."""
    return -0.0 if value == '-0' else float(value)


def _same(a, b):
    """Bit-for-bit equality of two doubles (so 0 and -0 differ)."""
    return struct.pack('<d', _double(a)) == struct.pack('<d', _double(b))


def check_vectors(vectors):
    """Yields (name, ok, detail) for every vector."""
    for seed in vectors['seeds']:
        name = 'seed %r/%r/%d' % (seed['serverSeed'], seed['clientSeed'], seed['nonce'])
        got = (sha256_hex(seed['serverSeed']), drop_seed(seed['serverSeed'], seed['clientSeed'], seed['nonce']))
        yield name, got == (seed['serverSeedHash'], seed['dropSeed']), got
    for stream in vectors['random']:
        rng = Arc4Random(stream['seed'])
        got = [rng.next() for _ in stream['doubles']]
        yield 'random %r' % stream['seed'], all(_same(a, b) for a, b in zip(got, stream['doubles'])), got
    for case in vectors['stateHash']:
        hasher = StateHasher()
        for value in case['doubles']:
            hasher.add_float64(_double(value))
        got = hasher.digest_hex()
        yield 'state hash of %r' % (case['doubles'],), got == case['hash'], got
    for version, data in vectors['versions'].items():
        for expected in data['boards']:
            board = Board(version, expected['rows'], 'medium')
            got = {
                'width': board.width, 'pegs': len(board.pegs),
                'firstPeg': board.pegs[0], 'lastPeg': board.pegs[-1], 'walls': board.walls,
                'dropZone': (board.drop_min_x, board.drop_max_x, board.drop_y),
                'bucketLineY': board.bucket_line_y, 'bucketLeftX': board.bucket_left_x, 'bucketWidth': board.bucket_width,
                'grid': {'minX': board.grid_min_x, 'minY': board.grid_min_y, 'columns': board.grid_columns,
                         'rows': board.grid_rows, 'listed': sum(len(cell) for cell in board.cells)},
            }
            want = dict(expected, firstPeg=(expected['firstPeg']['x'], expected['firstPeg']['y']),
                        lastPeg=(expected['lastPeg']['x'], expected['lastPeg']['y']),
                        dropZone=(expected['dropZone']['minX'], expected['dropZone']['maxX'], expected['dropZone']['y']))
            ok = (got['pegs'] == want['pegs'] and got['grid'] == want['grid']
                  and all(_same(got[k], want[k]) for k in ('width', 'bucketLineY', 'bucketLeftX', 'bucketWidth'))
                  and all(_same(a, b) for k in ('firstPeg', 'lastPeg', 'dropZone') for a, b in zip(got[k], want[k]))
                  and len(got['walls']) == len(want['walls'])
                  and all(_same(a, b) for gw, ww in zip(got['walls'], want['walls']) for a, b in zip(gw, ww)))
            yield '%s board rows %d' % (version, expected['rows']), ok, got
        for drop in data['drops']:
            name = '%s drop rows %d %s nonce %d' % (version, drop['rows'], drop['risk'], drop['nonce'])
            seed = drop_seed(drop['serverSeed'], drop['clientSeed'], drop['nonce'])
            board = Board(version, drop['rows'], drop['risk'])
            start = initial_conditions(board, seed)
            keys = ('x', 'y', 'vx', 'vy', 'angle', 'angularVelocity')
            trace = {}

            def on_tick(tick, state, trace=trace):
                if tick in TRACE_TICKS:
                    trace[str(tick)] = body_state_hash(*state)

            outcome = simulate_drop(board, seed, on_tick)
            # A tick the ball landed on is not "in flight": the vectors list ticks before landing.
            trace.pop(str(outcome['ticks']), None)
            got = dict(outcome, dropSeed=seed, stateHashAfterTick=trace)
            ok = (seed == drop['dropSeed'] and all(_same(a, drop['initial'][k]) for a, k in zip(start, keys))
                  and trace == drop['stateHashAfterTick']
                  and (outcome['bucket'], outcome['ticks'], outcome['stateHash']) == (drop['bucket'], drop['ticks'], drop['stateHash'])
                  and _same(outcome['multiplier'], drop['multiplier']))
            yield name, ok, got


def check_vectors_file(path, out):
    with open(path, encoding='utf-8') as file:
        vectors = json.load(file)
    failures = 0
    count = 0
    for name, ok, detail in check_vectors(vectors):
        count += 1
        if ok:
            out.write('ok    %s\n' % name)
        else:
            failures += 1
            out.write('FAIL  %s: got %r\n' % (name, detail))
    out.write('%d vectors, %d failed\n' % (count, failures))
    return failures == 0
