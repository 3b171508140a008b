"""Reading ``.npz`` files written by spacearm (trajectories, campaign results) with one rule for
damaged files: a truncated or corrupt archive (an interrupted copy, a full disk at the time of an
older version's write) raises [`ArgumentError`][spacearm.ArgumentError] naming the file and what is
wrong with it, instead of ``zipfile.BadZipFile``, ``EOFError`` or ``zlib.error`` from deep inside
numpy. Errors of the file system (a missing file, no permission) stay the ``OSError`` Python
raises.
"""

from __future__ import annotations

import contextlib
import os
import zipfile
import zlib
from typing import Dict, Iterator, Union

import numpy as np

from ..errors import ArgumentError

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


@contextlib.contextmanager
def open_npz(path: PathLike, what: str) -> Iterator[NpzArrays]:
    """Read every array of the ``.npz`` file ``path`` (a ``what`` file, for the message), without
    pickles."""
    try:
        with np.load(path, allow_pickle=False) as archive:
            arrays = NpzArrays({name: archive[name] for name in archive.files})
    except OSError:
        raise
    except _DAMAGED as exc:
        raise ArgumentError(f"'{os.fspath(path)}': not a {what} file (truncated, corrupt or of another format: "
                            f"{type(exc).__name__}: {exc})") from None
    yield arrays
