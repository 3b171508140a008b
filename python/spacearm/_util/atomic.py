"""Atomic output files: write to a temporary file beside the target, then rename over it.

An interrupted run (Ctrl-C, a crash, a full disk) therefore never leaves a truncated result
file: the target either keeps its previous content or gets the complete new one.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path
from typing import Iterator, Union

from ..errors import ArgumentError

__all__ = ["atomic_path", "atomic_open"]

PathLike = Union[str, "os.PathLike[str]"]


@contextlib.contextmanager
def atomic_path(path: PathLike, suffix: str = ".tmp") -> Iterator[Path]:
    """Yield a temporary path in the target's directory; on success rename it onto ``path``.

    For writers that insist on a file name (e.g. matplotlib's ``PillowWriter``). ``suffix``
    lets the writer infer the format from the temporary name (``".gif"``, ``".png"``). The
    new file gets the mode of the file it replaces, or rw-r--r--.
    """
    path = Path(path)
    directory = path.parent if str(path.parent) else Path(".")
    if not directory.is_dir():
        raise FileNotFoundError(f"cannot write {path}: directory {directory} does not exist")
    try:
        mode = path.stat().st_mode & 0o777
    except OSError:
        mode = 0o644
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=suffix, dir=directory)
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, mode)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


@contextlib.contextmanager
def atomic_open(path: PathLike, mode: str = "w", suffix: str = ".tmp", **kwargs) -> Iterator:
    """Open a temporary file beside ``path`` for writing (``mode`` ``"w"`` or ``"wb"``);
    when the block ends without error the data is flushed to disk and the file renamed onto
    ``path``."""
    if mode not in ("w", "wb"):
        raise ArgumentError(f"atomic_open mode must be 'w' or 'wb', got {mode!r}")
    if mode == "w":
        kwargs.setdefault("encoding", "utf-8")
        kwargs.setdefault("newline", "\n")
    with atomic_path(path, suffix=suffix) as tmp:
        with open(tmp, mode, **kwargs) as f:
            yield f
            f.flush()
            os.fsync(f.fileno())
