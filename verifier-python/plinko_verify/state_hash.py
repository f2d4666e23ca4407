"""The state hash (docs/engine-spec.md, section 10): two 32-bit murmur3-style
lanes over 32-bit words; a double goes in as its IEEE-754 bits, low word first."""

import struct

_M = 0xFFFFFFFF


def _rotl(v, n):
    return ((v << n) | (v >> (32 - n))) & _M


def _fmix(h):
    h ^= h >> 16
    h = (h * 0x85EBCA6B) & _M
    h ^= h >> 13
    h = (h * 0xC2B2AE35) & _M
    h ^= h >> 16
    return h


class StateHasher:
    def __init__(self):
        self.h1 = 0x811C9DC5
        self.h2 = 0x1B873593
        self.length = 0

    def add_int32(self, word):
        word &= _M
        k = (word * 0xCC9E2D51) & _M
        k = _rotl(k, 15)
        k = (k * 0x1B873593) & _M
        h1 = _rotl(self.h1 ^ k, 13)
        self.h1 = (h1 * 5 + 0xE6546B64) & _M
        m = (word * 0x85EBCA6B) & _M
        m = _rotl(m, 13)
        m = (m * 0xC2B2AE35) & _M
        h2 = _rotl(self.h2 ^ m, 17)
        self.h2 = (h2 * 9 + 0x27D4EB2F) & _M
        self.length += 1
        return self

    def add_float64(self, value):
        low, high = struct.unpack('<II', struct.pack('<d', value))
        return self.add_int32(low).add_int32(high)

    def digest_hex(self):
        h1 = _fmix(self.h1 ^ self.length)
        h2 = _fmix(self.h2 ^ self.length ^ h1)
        return '%08x%08x' % (h1, h2)


def body_state_hash(x, y, vx, vy, angle, spin):
    """The hash of one ball's state: x, y, vx, vy, angle, angular velocity."""
    h = StateHasher()
    for value in (x, y, vx, vy, angle, spin):
        h.add_float64(value)
    return h.digest_hex()
