"""The one atomic writer: every file spacearm writes (``.toml``, ``.urdf``, ``.npz``, ``.csv``,
figures, animations, generated code, campaign results) goes through ``atomic_open`` or
``atomic_path``.

The data goes to a hidden temporary file beside the target, ``.<name>.<pid>.<random><suffix>``,
is flushed to disk, and is then renamed over the target in one step. An interrupted run (Ctrl-C,
a crash, a full disk, SIGKILL) therefore never leaves a truncated result: the target keeps its
previous content or gets the complete new one.

File mode: that of a normal file, whatever the writer. A new file gets ``0o666 & ~umask``
(``rw-r--r--`` under the usual umask 022), exactly as ``open(path, "w")`` would create it; a file
being replaced keeps its mode, as it would when rewritten in place.

Stale temporaries: a process killed while writing leaves its temporary behind. The temporary's
name carries the writer's process id, so the next write to the same path removes the
temporaries of writers that no longer run (a live writer's, e.g. a concurrent run's, is left
alone).
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import tempfile
import threading
from pathlib import Path
from typing import Iterator, Union

from ..errors import ArgumentError

__all__ = ["atomic_path", "atomic_open", "write_text", "new_file_mode", "check_writable"]

PathLike = Union[str, "os.PathLike[str]"]

_UMASK_LOCK = threading.Lock()


def new_file_mode() -> int:
    """The mode ``open(path, "w")`` gives a new file: ``0o666`` less the process umask."""
    try:  # Linux reports the umask without changing it
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("Umask:"):
                    return 0o666 & ~int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    with _UMASK_LOCK:  # elsewhere: read it by setting it, and put it back at once
        umask = os.umask(0o022)
        os.umask(umask)
    return 0o666 & ~umask


def _temporary_prefix(path: Path) -> str:
    return f".{path.name}."


def _remove_stale_temporaries(path: Path, directory: Path) -> None:
    """Remove the temporaries of ``path`` left by writers that no longer run."""
    prefix = _temporary_prefix(path)
    pattern = re.compile(re.escape(prefix) + r"(\d+)\.")
    try:
        names = [e.name for e in os.scandir(directory) if e.name.startswith(prefix)]
    except OSError:
        return
    for name in names:
        match = pattern.match(name)
        if match is None:
            continue
        pid = int(match.group(1))
        if pid == os.getpid() or _process_exists(pid):
            continue
        with contextlib.suppress(OSError):
            os.unlink(directory / name)


def _process_exists(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError, OSError):
        return True  # it exists but is another user's (or the id is odd): leave its file alone
    return True


def _naming_target(exc: OSError, path: Path) -> OSError:
    """The same error (same class and errno) naming the target rather than the temporary."""
    if exc.errno is None:
        return exc
    return type(exc)(exc.errno, exc.strerror, os.fspath(path))


def check_writable(path: PathLike) -> Path:
    """Check, before any work is done, that ``path`` can be written as a file: its directory
    exists (and is a directory) and ``path`` itself is not a directory. Raises the ``OSError``
    of the problem (``FileNotFoundError``, ``NotADirectoryError``, ``IsADirectoryError``),
    naming the path; returns it as a ``Path``. A command calls this on each output option
    before it computes, so that a typo costs an error message, not a lost run."""
    path = Path(path)
    directory = path.parent if str(path.parent) else Path(".")
    if not directory.exists():
        raise FileNotFoundError(errno.ENOENT, f"directory '{directory}' does not exist", os.fspath(path))
    if not directory.is_dir():
        raise NotADirectoryError(errno.ENOTDIR, f"'{directory}' is not a directory", os.fspath(path))
    if path.is_dir():
        raise IsADirectoryError(errno.EISDIR, "it is a directory", os.fspath(path))
    return path


@contextlib.contextmanager
def atomic_path(path: PathLike, suffix: str = ".tmp") -> Iterator[Path]:
    """Yield a temporary path in the target's directory; on success rename it onto ``path``.

    For writers that insist on a file name (e.g. matplotlib's ``PillowWriter``). ``suffix``
    lets the writer infer the format from the temporary name (``".gif"``, ``".png"``). Errors of
    the file system (a missing or read-only directory, a directory in the way, a full disk) are
    the ``OSError`` that Python raises (same class and errno), naming the target path.
    """
    path = check_writable(path)
    directory = path.parent if str(path.parent) else Path(".")
    try:
        mode = path.stat().st_mode & 0o7777
    except OSError:
        mode = new_file_mode()
    _remove_stale_temporaries(path, directory)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f"{_temporary_prefix(path)}{os.getpid()}.", suffix=suffix, dir=directory)
    except OSError as exc:
        raise _naming_target(exc, path) from None
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, mode)
        os.replace(tmp, path)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        if isinstance(exc, OSError) and exc.filename in (None, tmp):
            raise _naming_target(exc, path) from exc
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


def write_text(path: PathLike, text: str, suffix: str = ".tmp") -> Path:
    """Write ``text`` (UTF-8, ``\\n`` line ends) to ``path`` atomically; returns the path."""
    with atomic_open(path, "w", suffix=suffix) as f:
        f.write(text)
    return Path(path)
