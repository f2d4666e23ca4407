"""Provably fair seeds (docs/engine-spec.md, section 2)."""

import hashlib
import hmac


def utf8(text):
    """UTF-8 bytes; a lone surrogate becomes U+FFFD, as TextEncoder does."""
    return ''.join('\ufffd' if 0xD800 <= ord(ch) <= 0xDFFF else ch for ch in text).encode('utf-8')


def sha256_hex(text):
    return hashlib.sha256(utf8(text)).hexdigest()


def drop_seed(server_seed, client_seed, nonce):
    """HMAC-SHA256(key = server seed, message = client seed + ":" + nonce in decimal), 64 hex digits."""
    if not server_seed:
        raise ValueError('serverSeed must be a non-empty string')
    message = client_seed + ':' + str(nonce)
    return hmac.new(utf8(server_seed), utf8(message), hashlib.sha256).hexdigest()
