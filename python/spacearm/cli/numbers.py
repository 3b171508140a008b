"""Comma-separated number lists on the command line, parsed by one function.

Every option of ``spacearm`` that takes several numbers (``--q``, ``--at``, ``--target``,
``--q0``, ``--joints``, ...) goes through ``parse_numbers``, so they all accept the same
spelling (``1,2,3``, ``-0.3, 0.3, 0``, ``1e-3,-2``) and report a bad value the same way: the
option, how many numbers it expects, what they mean and their unit.

Negative values: ``argparse`` treats an argument that starts with ``-`` as an option unless
it looks like a negative number. Up to Python 3.11 (at least) that means a single number
(``-0.3``), so ``--target -0.3,0.3,0`` fails with "expected one argument"; recent releases
accept anything starting ``-`` then a digit. The documented way that works in all of them is
the attached form
``--target=-0.3,0.3,0``; ``attach_negative_values`` rewrites ``--option -0.3,...`` into
that form before parsing. No ``spacearm`` option starts with ``-`` followed by a digit, so an
argument that does can only be a value.
"""

from __future__ import annotations

import re
from typing import List, Optional, Sequence

import numpy as np

from ..errors import ArgumentError

__all__ = ["CliError", "parse_numbers", "attach_negative_values"]

#: An argument that starts like a negative number: ``-1``, ``-0.3,0.3,0``, ``-.5``, ``-1e-3``.
_NEGATIVE_VALUE = re.compile(r"-\.?\d")


class CliError(ArgumentError):
    """A command-line argument is invalid (the message names it and what was expected)."""


def parse_numbers(text: str, option: str, count: Optional[int], meaning: str, unit: str,
                  integer: bool = False) -> np.ndarray:
    """The finite numbers of the comma-separated list ``text`` given to ``option``.

    ``count``: how many are required (``None``: any number, at least one). ``meaning`` says
    what they are (``"x,y,z,roll,pitch,yaw"``, ``"one per joint of 'ur5'"``) and ``unit`` their
    unit (``"m, rad"``); both appear in the error. ``integer``: the values must be whole
    numbers (returned as ``int``). Spaces around the values are ignored. Raises
    ``CliError`` (an [`ArgumentError`][spacearm.ArgumentError]).
    """
    kind = "integers" if integer else "numbers"
    expected = f"{option} expects {'' if count is None else f'{count} '}comma-separated {kind} ({meaning}; {unit})"
    items = [v.strip() for v in str(text).split(",")]
    if items and items[-1] == "" and len(items) > 1:  # a trailing comma is harmless
        items.pop()
    values = []
    for item in items:
        try:
            value = float(item)
        except ValueError:
            what = "an empty entry" if item == "" else f"'{item}' is not a number"
            raise CliError(f"{expected}, but in '{text}' {what}") from None
        if not np.isfinite(value):
            raise CliError(f"{expected}, but in '{text}' '{item}' is not finite")
        if integer and value != int(value):
            raise CliError(f"{expected}, but in '{text}' '{item}' is not an integer")
        values.append(value)
    if count is not None and len(values) != count:
        raise CliError(f"{expected}, got {len(values)} in '{text}'")
    return np.array(values, dtype=int if integer else float)


def attach_negative_values(argv: Sequence[str]) -> List[str]:
    """``argv`` with every ``--option VALUE`` whose VALUE starts like a negative number
    (``-0.3,0.3,0``, ``-1``) written as ``--option=VALUE``, which argparse reads as the
    option's value in every Python version. Arguments after ``--`` are left alone."""
    out: List[str] = []
    rest = list(argv)
    for i, arg in enumerate(rest):
        if arg == "--":
            return out + rest[i:]
        prev = out[-1] if out else ""
        if (_NEGATIVE_VALUE.match(arg) and prev.startswith("--") and prev != "--" and "=" not in prev):
            out[-1] = f"{prev}={arg}"
        else:
            out.append(arg)
    return out
