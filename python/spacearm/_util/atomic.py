"""The one atomic writer: every file spacearm writes (``.toml``, ``.urdf``, ``.npz``, ``.csv``,
figures, animations, generated code, campaign results) goes through ``atomic_open`` or
``atomic_path``.

The target gets its content in one step, complete or not at all: an interrupted run (Ctrl-C, a
crash, a full disk, SIGKILL) never leaves a truncated result, the target keeps its previous
content or gets the complete new one.

``atomic_open`` (the writers that take a file object: ``.npz``, ``.csv``, ``.toml``, ``.urdf``,
generated code) writes, on Linux, into an **unnamed** file of the target's directory
(``O_TMPFILE``): the data has no name until it is complete, flushed to disk and linked in
(``linkat`` of ``/proc/self/fd/N``: onto the target when it does not exist yet; else onto a
temporary name that is at once renamed over the target). A writer killed while writing leaves
nothing behind. Where ``O_TMPFILE`` is not available (another system, a file system without it,
no ``/proc``) it falls back to a named temporary, below.

``atomic_path`` (writers that insist on a file name: matplotlib's animation writers, the FMU
zip) and the fallback write into a **named** temporary beside the target,
``.spacearm-tmp-<pid>-<random>-<name><suffix>``, flushed and renamed over the target. A process
killed while writing leaves that file behind; its name carries the writer's process id, so every
later write into the same directory removes the ``.spacearm-tmp-`` files of writers that no
longer run (a live writer's, e.g. a concurrent run's, is left alone). Such a file is never a
result: it may be deleted at any time.

File mode: that of a normal file, whatever the writer. A new file gets ``0o666 & ~umask``
(``rw-r--r--`` under the usual umask 022), exactly as ``open(path, "w")`` would create it; a file
being replaced keeps its mode, as it would when rewritten in place.
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import tempfile
import threading
from pathlib import Path
from typing import Iterator, Optional, Union

from ..errors import ArgumentError

__all__ = ["atomic_path", "atomic_open", "write_text", "new_file_mode", "check_writable", "TEMPORARY_PREFIX"]

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


TEMPORARY_PREFIX = ".spacearm-tmp-"
_TEMPORARY = re.compile(re.escape(TEMPORARY_PREFIX) + r"(\d+)-")
_NAME_CHARS = 96  # of the target's name kept in a temporary's name (the whole name stays < 255 bytes)


def _legacy_prefix(path: Path) -> str:
    """The temporaries' names of earlier versions: ``.<name>.<pid>.<random><suffix>`` (still swept)."""
    return f".{path.name}."


def _temporary_affixes(path: Path, suffix: str):
    return f"{TEMPORARY_PREFIX}{os.getpid()}-", f"-{path.name[:_NAME_CHARS]}{suffix}"


def _remove_stale_temporaries(path: Path, directory: Path) -> None:
    """Remove the ``.spacearm-tmp-`` files of ``directory`` left by writers that no longer run
    (and the older-style temporaries of ``path``)."""
    legacy = re.compile(re.escape(_legacy_prefix(path)) + r"(\d+)\.")
    try:
        names = [e.name for e in os.scandir(directory) if e.name.startswith((TEMPORARY_PREFIX, _legacy_prefix(path)))]
    except OSError:
        return
    for name in names:
        match = _TEMPORARY.match(name) or legacy.match(name)
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
    mode = _target_mode(path)
    _remove_stale_temporaries(path, directory)
    prefix, end = _temporary_affixes(path, suffix)
    try:
        fd, tmp = tempfile.mkstemp(prefix=prefix, suffix=end, dir=directory)
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


def _target_mode(path: Path) -> int:
    try:
        return path.stat().st_mode & 0o7777
    except OSError:
        return new_file_mode()


def _open_unnamed(directory: Path) -> Optional[int]:
    """A descriptor of a new unnamed file in ``directory`` (``O_TMPFILE``), or ``None`` where the
    system or the file system has none."""
    flag = getattr(os, "O_TMPFILE", None)
    if flag is None or not os.path.isdir("/proc/self/fd"):
        return None
    try:
        return os.open(directory, flag | os.O_RDWR | getattr(os, "O_CLOEXEC", 0), 0o600)
    except OSError as exc:
        if exc.errno in (errno.EOPNOTSUPP, errno.EISDIR, errno.EINVAL, errno.ENOSYS):
            return None  # a kernel or file system without O_TMPFILE
        raise


_CANNOT_LINK = (errno.ENOENT, errno.EPERM, errno.EACCES, errno.EXDEV, errno.EINVAL, errno.EOPNOTSUPP)


def _linkat_empty_path(fd: int, destination: Path) -> bool:
    """``linkat(fd, "", AT_FDCWD, destination, AT_EMPTY_PATH)`` (needs ``CAP_DAC_READ_SEARCH``):
    ``True`` if linked, ``False`` if the call is not available or not permitted; raises
    ``FileExistsError`` if ``destination`` exists."""
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        linkat = libc.linkat
    except (OSError, AttributeError):
        return False
    linkat.argtypes = (ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_int)
    if linkat(fd, b"", -100, os.fsencode(destination), 0x1000) == 0:  # AT_FDCWD, AT_EMPTY_PATH
        return True
    code = ctypes.get_errno()
    if code == errno.EEXIST:
        raise FileExistsError(code, os.strerror(code), os.fspath(destination))
    return False


def _link_unnamed(fd: int, destination: Path) -> bool:
    """Give the unnamed file ``fd`` the name ``destination``: ``True`` if linked, ``False``
    where this system cannot link it; raises ``FileExistsError`` if ``destination`` exists."""
    try:
        os.link(f"/proc/self/fd/{fd}", destination, follow_symlinks=True)  # linkat(AT_SYMLINK_FOLLOW)
        return True
    except FileExistsError:
        raise
    except OSError as exc:
        if exc.errno not in _CANNOT_LINK:
            raise
    return _linkat_empty_path(fd, destination)


def _publish_unnamed(fd: int, path: Path, directory: Path, suffix: str) -> None:
    """Give the complete unnamed file ``fd`` the name ``path``: linked onto it when it does not
    exist, else linked onto a temporary name and renamed over it. Where it cannot be linked (no
    ``/proc`` links and no ``AT_EMPTY_PATH``), its bytes are copied into a named temporary."""
    try:
        if _link_unnamed(fd, path):
            return
        _copy_into_named(fd, path, suffix)
        return
    except FileExistsError:
        pass
    prefix, end = _temporary_affixes(path, suffix)
    for _ in range(100):
        tmp = directory / f"{prefix}{os.urandom(6).hex()}{end}"
        try:
            if not _link_unnamed(fd, tmp):
                _copy_into_named(fd, path, suffix)
                return
            break
        except FileExistsError:
            continue
    else:
        raise FileExistsError(errno.EEXIST, "no free temporary name", os.fspath(path))
    try:
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def _copy_into_named(fd: int, path: Path, suffix: str) -> None:
    with atomic_path(path, suffix=suffix) as tmp:
        with open(tmp, "wb") as out:
            offset = 0
            while True:
                chunk = os.pread(fd, 1 << 20, offset)
                if not chunk:
                    break
                out.write(chunk)
                offset += len(chunk)
            out.flush()
            os.fsync(out.fileno())


@contextlib.contextmanager
def atomic_open(path: PathLike, mode: str = "w", suffix: str = ".tmp", **kwargs) -> Iterator:
    """Open a file for writing ``path`` (``mode`` ``"w"`` or ``"wb"``): unnamed (Linux
    ``O_TMPFILE``) or a named temporary beside ``path`` (module docstring); when the block ends
    without error the data is flushed to disk and the file put in place of ``path`` in one step.
    Errors of the file system are the ``OSError`` Python raises, naming the target."""
    if mode not in ("w", "wb"):
        raise ArgumentError(f"atomic_open mode must be 'w' or 'wb', got {mode!r}")
    if mode == "w":
        kwargs.setdefault("encoding", "utf-8")
        kwargs.setdefault("newline", "\n")
    path = check_writable(path)
    directory = path.parent if str(path.parent) else Path(".")
    try:
        fd = _open_unnamed(directory)
    except OSError as exc:
        raise _naming_target(exc, path) from None
    if fd is None:
        with atomic_path(path, suffix=suffix) as tmp:
            with open(tmp, mode, **kwargs) as f:
                yield f
                f.flush()
                os.fsync(f.fileno())
        return
    file_mode = _target_mode(path)
    _remove_stale_temporaries(path, directory)
    try:
        with open(fd, mode, closefd=True, **kwargs) as f:
            yield f
            f.flush()
            os.fsync(f.fileno())
            os.fchmod(f.fileno(), file_mode)
            _publish_unnamed(f.fileno(), path, directory, suffix)
    except OSError as exc:
        if exc.filename is None or str(exc.filename).startswith(("/proc/self/fd/", os.fspath(directory / TEMPORARY_PREFIX))):
            raise _naming_target(exc, path) from exc
        raise


def write_text(path: PathLike, text: str, suffix: str = ".tmp") -> Path:
    """Write ``text`` (UTF-8, ``\\n`` line ends) to ``path`` atomically; returns the path."""
    with atomic_open(path, "w", suffix=suffix) as f:
        f.write(text)
    return Path(path)
