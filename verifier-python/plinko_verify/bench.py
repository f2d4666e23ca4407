"""Drops per second of this implementation: python3 -m plinko_verify.bench [--drops N] [--engine-version V] [--rows R]

Prints one line per board and version: the figure is for auditors sizing a
re-verification of a ledger, not a goal (the JavaScript engine is the fast one)."""

import argparse
import hashlib
import time

from .simulate import simulate_drop
from .verify import board_of
from .versions import ENGINE_VERSIONS


def main():
    parser = argparse.ArgumentParser(prog='python3 -m plinko_verify.bench')
    parser.add_argument('--drops', type=int, default=500)
    parser.add_argument('--engine-version', choices=ENGINE_VERSIONS, action='append')
    parser.add_argument('--rows', type=int, action='append')
    args = parser.parse_args()
    for version in args.engine_version or ENGINE_VERSIONS:
        for rows in args.rows or (8, 16):
            board = board_of(version, rows, 'medium')
            seeds = [hashlib.sha256(('bench:%d' % i).encode()).hexdigest() for i in range(args.drops)]
            ticks = 0
            start = time.perf_counter()
            for seed in seeds:
                ticks += simulate_drop(board, seed)['ticks']
            elapsed = time.perf_counter() - start
            print('engine %s, %2d rows: %7.0f drops/s (%d drops, %.0f ticks each, %.1f µs per tick)' % (
                version, rows, args.drops / elapsed, args.drops, ticks / args.drops, elapsed / ticks * 1e6))


if __name__ == '__main__':
    main()
