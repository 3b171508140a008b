"""Reading ``.npz`` files written by spacearm (trajectories, campaign results) with one rule for
damaged files: a truncated or corrupt archive (an interrupted copy, a full disk at the time of an
older version's write) raises [`ArgumentError`][spacearm.ArgumentError] naming the file and what is
wrong with it, instead of ``zipfile.BadZipFile``, ``EOFError`` or ``zlib.error`` from deep inside
numpy. Errors of the file system (a missing file, no permission) stay the ``OSError`` Python
raises.

Sizes are checked before anything is inflated: the sizes the archive declares for its members
(the zip directory's, which also bound what is read) and the shape × item size each ``.npy``
header declares, against ``_core.MEMORY_LIMIT_BYTES`` (2 GiB, the core's limit of one request),
so that a small archive of a huge array (a decompression bomb) is refused with a
[`ResourceLimitError`][spacearm.errors.ResourceLimitError] instead of being inflated in full.
"""

from __future__ import annotations

import contextlib
import math
import os
import zipfile
import zlib
from typing import Dict, Iterator, Union

import numpy as np

from .. import _core
from ..errors import ArgumentError, ResourceLimitError, SpacearmError
from .show import shown

__all__ = ["open_npz"]

PathLike = Union[str, "os.PathLike[str]"]

# What numpy raises on a damaged archive: the zip directory is missing or broken (BadZipFile),
# a member ends early (EOFError), its compressed stream is broken (zlib.error), a member is not
# a valid .npy (ValueError), or the archive's directory names a member that is not there
# (KeyError).
_DAMAGED = (zipfile.BadZipFile, EOFError, zlib.error, ValueError, KeyError)


class NpzArrays(Dict[str, np.ndarray]):
    """Every array of an ``.npz`` file, read into memory; ``files`` lists their names (as for
    numpy's ``NpzFile``)."""

    @property
    def files(self):
        return list(self.keys())


#: The most bytes the arrays of one archive may hold once read (the core's limit of one request).
_LIMIT = int(_core.MEMORY_LIMIT_BYTES)


def _size(n: int) -> str:
    if n >= 10 ** 18:
        return f"{shown(n)} bytes"
    return f"{n / 1e9:.3g} GB" if n >= 1e8 else f"{n / 1e6:.3g} MB"


def _check_sizes(path: PathLike, what: str) -> None:
    """Refuse, before reading any array, an archive whose members declare more than ``_LIMIT``
    bytes in all (the zip directory's sizes), or a ``.npy`` member whose header declares more
    data than the member holds (a shape that would allocate what is not there)."""
    name = os.fspath(path)
    total = 0
    with zipfile.ZipFile(name) as zf:
        for info in zf.infolist():
            total += int(info.file_size)
            if total > _LIMIT:
                raise ResourceLimitError(
                    f"'{name}': the arrays of this {what} file would take more than {_size(total)} once decompressed "
                    f"(member '{info.filename[:80]}' alone {_size(info.file_size)}; the limit of one request is "
                    f"{_size(_LIMIT)}): refused before decompressing (a damaged file or a decompression bomb?)")
            if not info.filename.endswith(".npy"):
                continue
            with zf.open(info) as fh:
                version = np.lib.format.read_magic(fh)
                read = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
                shape, _, dtype = read(fh)
            declared = math.prod(int(n) for n in shape) * int(dtype.itemsize)
            if declared > int(info.file_size):
                raise ArgumentError(
                    f"'{name}': member '{info.filename[:80]}' of this {what} file declares an array of shape "
                    f"({', '.join(shown(n) for n in shape[:8])}{', ...' if len(shape) > 8 else ''}) ({_size(declared)}) "
                    f"but holds {int(info.file_size)} bytes: a damaged or forged file")


@contextlib.contextmanager
def open_npz(path: PathLike, what: str) -> Iterator[NpzArrays]:
    """Read every array of the ``.npz`` file ``path`` (a ``what`` file, for the message), without
    pickles, after checking the sizes it declares (``_check_sizes``)."""
    try:
        _check_sizes(path, what)
        with np.load(path, allow_pickle=False) as archive:
            arrays = NpzArrays({name: archive[name] for name in archive.files})
    except (OSError, SpacearmError):
        raise
    except _DAMAGED as exc:
        raise ArgumentError(f"'{os.fspath(path)}': not a {what} file (truncated, corrupt or of another format: "
                            f"{type(exc).__name__}: {exc})") from None
    yield arrays
