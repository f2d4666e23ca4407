"""verify_drop: the commitment, the drop seed and the outcome of one drop from its revealed seeds."""

from .board import Board
from .fairness import sha256_hex, drop_seed
from .simulate import simulate_drop
from .versions import ENGINE_VERSION


def verify_drop(server_seed, client_seed, nonce, rows=16, risk='medium', engine_version=ENGINE_VERSION):
    board = board_of(engine_version, rows, risk)
    seed = drop_seed(server_seed, client_seed, nonce)
    outcome = simulate_drop(board, seed)
    return {
        'serverSeedHash': sha256_hex(server_seed),
        'dropSeed': seed,
        'bucket': outcome['bucket'],
        'multiplier': outcome['multiplier'],
        'ticks': outcome['ticks'],
        'stateHash': outcome['stateHash'],
        'engineVersion': engine_version,
    }


_boards = {}


def board_of(version, rows, risk):
    """Boards are built once per (version, rows, risk): building the grid costs more than a drop."""
    key = (version, rows, risk)
    board = _boards.get(key)
    if board is None:
        board = _boards[key] = Board(version, rows, risk)
    return board
