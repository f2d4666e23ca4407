"""plinko_verify: a second, independent implementation of Plinko Arena's
engine (docs/engine-spec.md), in Python's standard library alone."""

from .board import Board
from .fairness import sha256_hex, drop_seed
from .simulate import simulate_drop, initial_conditions
from .versions import ENGINE_VERSION, ENGINE_VERSIONS, RISKS, MIN_ROWS, MAX_ROWS
from .verify import verify_drop

__all__ = ['Board', 'sha256_hex', 'drop_seed', 'simulate_drop', 'initial_conditions', 'verify_drop',
           'ENGINE_VERSION', 'ENGINE_VERSIONS', 'RISKS', 'MIN_ROWS', 'MAX_ROWS']
