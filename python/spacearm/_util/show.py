"""User values in error messages, shown compactly: a message that quotes what it refused must
stay one readable line, whatever the value (a 130-digit integer, a float near 1e308, a
megabyte-long string)."""

from __future__ import annotations

import numbers

__all__ = ["shown"]

_MAX_DIGITS = 15
_MAX_CHARS = 80


def shown(value) -> str:
    """``value`` as a message quotes it: an integer of more than 15 digits as ``~1.23457e+129
    (130 digits)``, a float with 6 significant digits (``%.6g``), a string or any other
    value as its ``repr`` cut to 80 characters (``...`` marks the cut)."""
    if isinstance(value, bool):
        return repr(value)
    if isinstance(value, numbers.Integral):
        v = int(value)
        digits = len(str(abs(v))) if abs(v) < 10 ** 4000 else None
        if digits is not None and digits <= _MAX_DIGITS:
            return str(v)
        try:
            approx = f"~{float(v):.6g}"
        except OverflowError:
            approx = "-huge" if v < 0 else "huge"
        return f"{approx} ({digits if digits is not None else 'more than 4000'} digits)"
    if isinstance(value, numbers.Real):
        return f"{float(value):.6g}"
    text = repr(value)
    return text if len(text) <= _MAX_CHARS else text[: _MAX_CHARS - 3] + "..."
