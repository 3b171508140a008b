"""The spacearm C library (``libspacearm_c``, crates/spacearm-c; docs/c-api.md) through
``ctypes``: the few entry points Python calls (the FMU's binary is the same file, see
``spacearm.fmi.fmu``). Where the library is, is [`spacearm.c`][spacearm.c]'s answer
(``spacearm.c.library_path``: ``SPACEARM_C_LIBRARY``, a source checkout's ``target/release/``,
the copy a wheel ships in ``spacearm/c/lib/``); without one, ``path`` raises its
[`MissingDependencyError`][spacearm.errors.MissingDependencyError] saying how to get it.
"""

from __future__ import annotations

import ctypes
from functools import lru_cache
from pathlib import Path

from .. import errors
from ..c import LIBRARY_NAME
from ..c import library_path as path
from ..errors import MissingDependencyError

__all__ = ["path", "load", "ABI_VERSION", "LIBRARY_NAME"]

#: The version of the C ABI these declarations follow (``SPACEARM_ABI_VERSION`` of
#: crates/spacearm-c/include/spacearm.h); a library of another version is refused.
ABI_VERSION = 1


#: The Python class of each SpacearmStatus code (docs/c-api.md, "Errors"): the same kinds as
#: the core's errors, which the extension maps the same way.
_ERRORS = {
    1: errors.ModelError, 2: errors.ShapeError, 3: errors.NonFiniteError, 4: errors.QuaternionError,
    5: errors.NotFoundError, 6: errors.SingularError, 7: errors.ModelFileError, 8: errors.ArgumentError,
    9: errors.SimulationError, 10: errors.ResourceLimitError, 11: errors.ArgumentError, 12: errors.ArgumentError,
    13: errors.ArgumentError, 14: errors.ArgumentError,
}


class _Library:
    """The loaded library with the signatures Python uses."""

    def __init__(self, file: Path):
        lib = ctypes.CDLL(str(file))
        lib.spacearm_abi_version.restype = ctypes.c_uint32
        lib.spacearm_abi_version.argtypes = []
        found = lib.spacearm_abi_version()
        if found != ABI_VERSION:
            raise MissingDependencyError(f"the C library '{file}' has ABI version {found}; this spacearm needs {ABI_VERSION} "
                                         "(rebuild it from the same source)")
        lib.spacearm_last_error.restype = ctypes.c_char_p
        lib.spacearm_last_error.argtypes = []
        lib.spacearm_fmu_model_description.restype = ctypes.c_int
        lib.spacearm_fmu_model_description.argtypes = [
            ctypes.c_char_p, ctypes.c_char_p, ctypes.c_uint32, ctypes.c_char_p, ctypes.c_char_p, ctypes.c_double,
            ctypes.c_char_p, ctypes.c_size_t, ctypes.POINTER(ctypes.c_size_t)]
        lib.spacearm_options_with_controller.restype = ctypes.c_int
        lib.spacearm_options_with_controller.argtypes = [
            ctypes.c_char_p, ctypes.c_char_p, ctypes.c_char_p, ctypes.c_size_t, ctypes.POINTER(ctypes.c_size_t)]
        self.lib = lib
        self.file = file

    def check(self, status: int) -> None:
        """Raise the error of a failed call (a status other than 0)."""
        if status != 0:
            message = (self.lib.spacearm_last_error() or b"").decode("utf-8", "replace")
            raise _ERRORS.get(status, errors.ArgumentError)(message)

    def _text(self, fn, *args) -> str:
        """The text a ``(args..., buf, len, needed)`` entry point writes (asked its size first)."""
        needed = ctypes.c_size_t(0)
        status = fn(*args, None, 0, ctypes.byref(needed))
        if status != 12:  # SPACEARM_STATUS_BUFFER_TOO_SMALL: the size is in `needed`
            self.check(status)
        buf = ctypes.create_string_buffer(needed.value)
        self.check(fn(*args, buf, needed.value, ctypes.byref(needed)))
        return buf.value.decode()

    def options_with_controller(self, options_toml: str, controller_toml: str) -> str:
        """The stepper options ``options_toml`` with the controller spec document ``controller_toml``
        (``ControllerSpec.to_toml()``) as their ``[controller]`` table (docs/c-api.md)."""
        return self._text(self.lib.spacearm_options_with_controller, options_toml.encode(), controller_toml.encode())

    def model_description(self, model_toml: str, options_toml: str, fmi_version: int, identifier: str, token: str,
                          stop_time: float) -> str:
        """The ``modelDescription.xml`` the library writes for these resources."""
        args = [model_toml.encode(), options_toml.encode(), fmi_version, identifier.encode(), token.encode(), stop_time]
        return self._text(self.lib.spacearm_fmu_model_description, *args)


@lru_cache(maxsize=None)
def _load(file: str) -> _Library:
    return _Library(Path(file))


def load() -> _Library:
    """The library, loaded once per path."""
    return _load(str(path()))
