"""JSON text exactly as JavaScript's JSON.stringify writes it (no spaces; numbers in ECMAScript's Number::toString form)."""

import json
import math


def js_number(value):
    """ECMAScript Number::toString for a finite double (the shortest digits that round-trip, as repr)."""
    if isinstance(value, bool):
        raise TypeError('not a number')
    if isinstance(value, int):
        value = float(value)
    if not math.isfinite(value):
        return 'null'
    if value == 0:
        return '0'  # JSON.stringify(-0) is "0"
    text = repr(value)
    mantissa, _, exponent = text.partition('e')
    digits = mantissa.replace('-', '').replace('.', '')
    point = mantissa.replace('-', '').find('.')
    point = len(mantissa.replace('-', '')) if point < 0 else point
    # decimal exponent n: the value is 0.d1d2...dk × 10^n
    n = point + (int(exponent) if exponent else 0)
    stripped = digits.lstrip('0')
    n -= len(digits) - len(stripped)
    digits = stripped.rstrip('0') or '0'
    k = len(digits)
    sign = '-' if value < 0 else ''
    if k <= n <= 21:
        return sign + digits + '0' * (n - k)
    if 0 < n <= 21:
        return sign + digits[:n] + '.' + digits[n:]
    if -6 < n <= 0:
        return sign + '0.' + '0' * (-n) + digits
    e = n - 1
    exponent_text = ('+' if e >= 0 else '-') + str(abs(e))
    if k == 1:
        return sign + digits + 'e' + exponent_text
    return sign + digits[0] + '.' + digits[1:] + 'e' + exponent_text


def stringify(obj):
    """JSON.stringify(obj) for dicts (insertion order), strings, numbers, booleans and None."""
    if obj is None or obj is True or obj is False:
        return json.dumps(obj)
    if isinstance(obj, (int, float)):
        return js_number(obj)
    if isinstance(obj, str):
        return json.dumps(obj, ensure_ascii=False)
    if isinstance(obj, dict):
        return '{' + ','.join(json.dumps(str(k), ensure_ascii=False) + ':' + stringify(v) for k, v in obj.items()) + '}'
    if isinstance(obj, (list, tuple)):
        return '[' + ','.join(stringify(v) for v in obj) + ']'
    raise TypeError('cannot stringify %r' % (obj,))
