"""plinko-verify: the same `verify` as `plinko verify` (cli/verify-command.js in
the game's repository): the same options, the same checks and the same JSON."""

import re
import sys

from .js_json import stringify
from .verify import verify_drop
from .versions import ENGINE_VERSION, ENGINE_VERSIONS, MIN_ROWS, MAX_ROWS, RISKS

MAX_SAFE_INTEGER = 9007199254740991

VERIFY_USAGE = 'plinko-verify verify --server-seed S --client-seed C --nonce N [--rows 16] [--risk medium] [--engine-version V]'
VECTORS_USAGE = 'plinko-verify vectors FILE'
REPLAY_USAGE = 'plinko-verify replay < drops.jsonl'
TRACE_USAGE = 'plinko-verify trace --drop-seed S [--rows 16] [--risk medium] [--engine-version V]'

VERIFY_HELP = '''usage: %s

Replays one drop from its seeds and prints one JSON object:
{ serverSeedHash, dropSeed, bucket, multiplier, ticks, stateHash, engineVersion }

  --server-seed S      the revealed server seed (required)
  --client-seed C      the drop's client seed (required; may be empty)
  --nonce N            the drop's nonce: a whole number, 0 or more (required)
  --rows N             rows of the board, %d to %d (default 16)
  --risk R             %s (default medium)
  --engine-version V   %s (default the newest): the drop's engineVersion
  -h, --help           this help''' % (VERIFY_USAGE, MIN_ROWS, MAX_ROWS, ', '.join(RISKS), ', '.join(ENGINE_VERSIONS))

VECTORS_HELP = '''usage: %s

Checks this implementation against a test-vector file of the specification
(docs/engine-spec-vectors.json): prints one line per vector, exit 1 on any mismatch.''' % VECTORS_USAGE

REPLAY_HELP = '''usage: %s

Replays drops given by their drop seeds, one JSON object a line on stdin:
{ "engineVersion": "2.0.0", "rows": 16, "risk": "medium", "dropSeed": "<64 hex digits>" }
and prints one line per drop, in order: { bucket, multiplier, ticks, stateHash }.
A line may also give "maxDropTicks": a tick cap of its own instead of the
version's, to check the cap rule on drops that reach it.''' % REPLAY_USAGE

TRACE_HELP = '''usage: %s

One drop, tick by tick: a JSON line per tick in flight with the ball's
state (x, y, vx, vy, angle, spin) and its state hash, then a line with the
outcome. The game's `node scripts/trace-drop.js` prints the same lines
from the JavaScript engine: diff the two to find the first tick that differs.''' % TRACE_USAGE

USAGE = '''usage:
  %s
  %s
  %s
  %s
  plinko-verify help [COMMAND]

plinko-verify COMMAND --help shows a command's options.''' % (VERIFY_USAGE, VECTORS_USAGE, REPLAY_USAGE, TRACE_USAGE)


class UsageError(Exception):
    pass


# name -> 'string' | 'boolean'; the one short option is -h for --help.
VERIFY_OPTIONS = {'help': 'boolean', 'server-seed': 'string', 'client-seed': 'string', 'nonce': 'string',
                  'rows': 'string', 'risk': 'string', 'engine-version': 'string'}
SHORT = {'h': 'help'}


def _tokens(argv, options):
    """node:util parseArgs({ strict: false, allowPositionals: true, tokens: true }) tokens: (kind, name, raw, value, inline)."""
    tokens = []
    args = list(argv)
    index = 0
    while index < len(args):
        arg = args[index]
        index += 1
        if arg == '--':
            tokens.append(('terminator', None, arg, None, False))
            tokens.extend(('positional', None, rest, rest, False) for rest in args[index:])
            break
        if arg.startswith('--'):
            name, equals, value = arg[2:].partition('=')
            if equals:
                tokens.append(('option', name, '--' + name, value, True))
            elif options.get(name) == 'string' and index < len(args):
                tokens.append(('option', name, arg, args[index], False))
                index += 1
            else:
                tokens.append(('option', name, arg, None, False))
            continue
        if arg.startswith('-') and len(arg) > 1:
            for letter in arg[1:]:
                tokens.append(('option', SHORT.get(letter, letter), '-' + letter, None, False))
            continue
        tokens.append(('positional', None, arg, arg, False))
    return tokens


def _names_an_option(value, options):
    if value.startswith('--'):
        name = value[2:].split('=')[0]
        return name in options and len(name) > 1
    if re.match(r'-[A-Za-z]', value):
        return value[1] in options or value[1] in SHORT
    return False


def parse_options(argv, options):
    tokens = _tokens(argv, options)
    if any(kind == 'option' and name == 'help' and value is None for kind, name, _, value, _ in tokens):
        return {'help': True}
    values = {}
    seen = set()
    for kind, name, raw, value, inline in tokens:
        if kind == 'terminator':
            continue
        if kind == 'positional':
            raise UsageError('unexpected argument "%s"' % value)
        spec = options.get(name)
        if spec is None or (len(name) == 1 and raw != '-' + name):
            raise UsageError('unknown option ' + raw)
        flag = '-' + name if len(name) == 1 else '--' + name
        if spec == 'boolean' and value is not None:
            raise UsageError('%s takes no value, got "%s"' % (flag, value))
        if spec == 'string' and (value is None or (not inline and _names_an_option(value, options))):
            raise UsageError(flag + ' needs a value')
        if name in seen:
            raise UsageError(flag + ' given twice: give it once')
        seen.add(name)
        values[name] = True if spec == 'boolean' else value
    return values


def integer_option(text, name, minimum=0, maximum=MAX_SAFE_INTEGER):
    if text is None:
        raise UsageError('--%s is required' % name)
    if not re.fullmatch(r'[0-9]+', text) or not (minimum <= int(text) <= maximum):
        raise UsageError('--%s must be a whole number from %d to %d, got "%s"' % (name, minimum, maximum, text))
    return int(text)


TRACE_OPTIONS = {'help': 'boolean', 'drop-seed': 'string', 'rows': 'string', 'risk': 'string', 'engine-version': 'string'}


def _board_options(options):
    rows = integer_option(options.get('rows', '16'), 'rows', MIN_ROWS, MAX_ROWS)
    risk = options.get('risk', 'medium')
    if risk not in RISKS:
        raise UsageError('--risk must be one of %s, got "%s"' % (', '.join(RISKS), risk))
    version = options.get('engine-version', ENGINE_VERSION)
    if version not in ENGINE_VERSIONS:
        raise UsageError('--engine-version must be one of %s, got "%s"' % (', '.join(ENGINE_VERSIONS), version))
    return rows, risk, version


def required_string(text, name):
    if text is None or text == '':
        raise UsageError('--%s is required' % name)
    return text


def verify_command(argv, out):
    options = parse_options(argv, VERIFY_OPTIONS)
    if options.get('help'):
        out.write(VERIFY_HELP + '\n')
        return
    server_seed = required_string(options.get('server-seed'), 'server-seed')
    client_seed = options.get('client-seed')
    if client_seed is None:
        required_string(None, 'client-seed')
    nonce = integer_option(options.get('nonce'), 'nonce')
    rows, risk, version = _board_options(options)
    result = verify_drop(server_seed, client_seed, nonce, rows, risk, version)
    out.write(stringify(result) + '\n')


def vectors_command(argv, out):
    from .vectors import check_vectors_file
    if argv in (['-h'], ['--help']):
        out.write(VECTORS_HELP + '\n')
        return
    if len(argv) != 1 or argv[0].startswith('-'):
        raise UsageError('vectors takes one file')
    try:
        ok = check_vectors_file(argv[0], out)
    except OSError as error:
        raise UsageError('cannot read %s: %s' % (argv[0], error.strerror or error))
    except (ValueError, KeyError, TypeError) as error:
        raise UsageError('%s is not a vectors file (%s: %s)' % (argv[0], type(error).__name__, error))
    if not ok:
        raise SystemExit(1)


def replay_command(argv, out):
    import json
    from .simulate import simulate_drop
    from .verify import board_of
    if argv in (['-h'], ['--help']):
        out.write(REPLAY_HELP + '\n')
        return
    if argv:
        raise UsageError('replay takes no arguments: drops come on stdin')
    for number, line in enumerate(sys.stdin, 1):
        if not line.strip():
            continue
        try:
            drop = json.loads(line)
            board = board_of(drop['engineVersion'], drop['rows'], drop['risk'])
            cap = drop.get('maxDropTicks')
            if cap is not None and not (type(cap) is int and cap >= 1):
                raise ValueError('maxDropTicks must be a whole number from 1')
            outcome = simulate_drop(board, drop['dropSeed'], max_ticks=cap)
        except (ValueError, KeyError, TypeError) as error:
            raise UsageError('line %d: not a drop (%s): %s' % (number, error, line.strip()[:200]))
        out.write(stringify(outcome) + '\n')


def trace_command(argv, out):
    from .simulate import simulate_drop
    from .state_hash import body_state_hash
    from .verify import board_of
    options = parse_options(argv, TRACE_OPTIONS)
    if options.get('help'):
        out.write(TRACE_HELP + '\n')
        return
    drop_seed = required_string(options.get('drop-seed'), 'drop-seed')
    rows, risk, version = _board_options(options)
    board = board_of(version, rows, risk)
    lines = []

    def on_tick(tick, state):
        x, y, vx, vy, angle, spin = state
        lines.append({'tick': tick, 'x': x, 'y': y, 'vx': vx, 'vy': vy, 'angle': angle, 'spin': spin,
                      'stateHash': body_state_hash(*state)})

    outcome = simulate_drop(board, drop_seed, on_tick)
    lines.pop()  # the landing tick is the outcome's line
    for line in lines:
        out.write(stringify(line) + '\n')
    out.write(stringify(dict({'tick': outcome['ticks'], 'landed': True}, **outcome)) + '\n')


COMMANDS = {
    'verify': (verify_command, VERIFY_USAGE, VERIFY_HELP),
    'vectors': (vectors_command, VECTORS_USAGE, VECTORS_HELP),
    'replay': (replay_command, REPLAY_USAGE, REPLAY_HELP),
    'trace': (trace_command, TRACE_USAGE, TRACE_HELP),
}


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    name, rest = (argv[0], argv[1:]) if argv else (None, [])
    if name in ('help', '--help', '-h'):
        if not rest:
            sys.stdout.write(USAGE + '\n')
            return 0
        if rest[0] not in COMMANDS or len(rest) > 1:
            reason = 'help takes one command, got %d' % len(rest) if len(rest) > 1 else 'unknown command "%s"' % rest[0]
            sys.stderr.write('plinko-verify: %s\n%s\n' % (reason, USAGE))
            return 2
        sys.stdout.write(COMMANDS[rest[0]][2] + '\n')
        return 0
    if name is None:
        sys.stderr.write('plinko-verify: a command is required\n%s\n' % USAGE)
        return 2
    if name not in COMMANDS:
        sys.stderr.write('plinko-verify: unknown command "%s"\n%s\n' % (name, USAGE))
        return 2
    run, usage, _ = COMMANDS[name]
    try:
        run(rest, sys.stdout)
    except UsageError as error:
        sys.stderr.write('plinko-verify %s: %s\nusage: %s\n(plinko-verify %s --help lists the options)\n' % (name, error, usage, name))
        return 2
    return 0


if __name__ == '__main__':
    sys.exit(main())
