"""The drop's random stream (docs/engine-spec.md, section 3): seedrandom 3.0.5's
ARC4 generator keyed by the drop seed, and its doubles in [0, 1)."""

_MASK = 255


def _key_of(seed):
    """seedrandom's mixkey: the seed's UTF-16 code units folded into at most 256 key bytes."""
    units = seed.encode('utf-16-le')
    key = []
    smear = 0
    for j in range(len(units) // 2):
        code = units[2 * j] | (units[2 * j + 1] << 8)
        slot = j & _MASK
        # A slot not yet written reads as 0 (JavaScript: undefined * 19 is NaN, and NaN ^ s is s).
        smear ^= (key[slot] if slot < len(key) else 0) * 19
        value = (smear + code) & _MASK
        if slot < len(key):
            key[slot] = value
        else:
            key.append(value)
    return key


class Arc4Random:
    """RC4 keyed by the seed, its first 256 outputs dropped; next() gives doubles as seedrandom's prng()."""

    def __init__(self, seed):
        key = _key_of(seed) or [0]
        s = list(range(256))
        j = 0
        for i in range(256):
            t = s[i]
            j = (j + key[i % len(key)] + t) & _MASK
            s[i] = s[j]
            s[j] = t
        self._s = s
        self._i = 0
        self._j = 0
        self._bytes(256)

    def _bytes(self, count):
        """The next `count` RC4 outputs, big-endian, as one integer (seedrandom's g(count))."""
        s = self._s
        i = self._i
        j = self._j
        r = 0
        for _ in range(count):
            i = (i + 1) & _MASK
            t = s[i]
            j = (j + t) & _MASK
            s[i] = s[j]
            s[j] = t
            r = r * 256 + s[(s[i] + t) & _MASK]
        self._i = i
        self._j = j
        return r

    def next(self):
        """A double in [0, 1): 52 or 53 significant random bits over a power-of-two denominator."""
        n = self._bytes(6)
        d = 1 << 48
        x = 0
        while n < (1 << 52):
            n = (n + x) * 256
            d *= 256
            x = self._bytes(1)
        while n >= (1 << 53):
            n //= 2
            d //= 2
            x >>= 1
        # n + x < 2^53 and d is a power of two: the quotient is exact.
        return (n + x) / d
