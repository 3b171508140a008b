"""Export a [`Robot`][spacearm.Robot] as an FMI co-simulation unit (docs/fmi.md).

The FMU's binary is the spacearm C library (``spacearm.fmi.library``), which exports the
``fmi2*`` and ``fmi3*`` functions; the model travels as ``resources/model.toml``, the stepper
options (mode, RK4 step, controller) as ``resources/options.toml`` and the instantiation token
(checked by the binary when it is instantiated) as ``resources/token.txt``;
``modelDescription.xml`` is written by the library from the same variable table its binary reads.
"""

from __future__ import annotations

import hashlib
import numbers
import platform
import re
import sys
import uuid
import zipfile
from pathlib import Path
from typing import Optional

import numpy as np

from .. import _core
from .._util.atomic import atomic_path
from .._util.spec import controller_spec
from ..errors import ArgumentError, SpacearmTypeError
from ..model.robot import Robot
from ..sim.simulation import MODES  # the core's mode table
from . import library

__all__ = ["export", "binary_folder"]


def binary_folder(fmi_version: int) -> str:
    """The folder under ``binaries/`` for this platform (FMI 3 §2.5.1.1, FMI 2 §2.3)."""
    machine = {"amd64": "x86_64", "arm64": "aarch64"}.get(platform.machine().lower(), platform.machine().lower())
    system = {"linux": "linux", "darwin": "darwin", "win32": "windows"}.get(sys.platform, sys.platform)
    if fmi_version == 3:
        return f"{machine}-{system}"
    fmi2 = {("x86_64", "linux"): "linux64", ("x86_64", "darwin"): "darwin64", ("x86_64", "windows"): "win64"}
    if (machine, system) not in fmi2:
        raise ArgumentError(f"FMI 2 names no binary folder for {machine} {system}; export with fmi_version=3")
    return fmi2[(machine, system)]


def _options_toml(lib, mode: str, dt: float, joint_limits: bool, controller) -> str:
    """The FMU's ``options.toml``: the run options and, as its ``[controller]`` table, the
    controller's spec as the core writes it (``ControllerSpec.to_toml()``), composed by the C
    library (``spacearm_options_with_controller``, docs/c-api.md)."""
    run = f'mode = "{mode}"\ndt = {float(dt)!r}\njoint_limits = {"true" if joint_limits else "false"}\n'
    if controller is None:
        return run
    # The core refuses what is not a controller and a Callback (Python code, which the FMU's
    # binary cannot call).
    return lib.options_with_controller(run, controller_spec(controller).to_toml())


def _number(name: str, value) -> float:
    """A real number argument as a float (a bool, a string or a complex number is refused)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise SpacearmTypeError(f"{name} must be a real number of seconds, got {value!r} ({type(value).__name__})")
    return float(value)


def export(robot: Robot, path, *, mode: str = "floating", controller=None, dt: float = 1e-3, fmi_version: int = 3,
           joint_limits: bool = True, stop_time: float = 1.0, model_identifier: Optional[str] = None) -> Path:
    """Write ``robot`` as a co-simulation FMU to ``path`` (``.fmu``) and return the path.

    Parameters
    ----------
    robot : Robot
        The plant.
    path : str or os.PathLike
        The file to write (atomically).
    mode : str
        A mode of [`spacearm.simulate`][spacearm.simulate]; the flying modes give the FMU the ``base_wrench`` inputs.
    controller : a native controller of spacearm.control, optional
        Any native law (``JointPD``, ``ComputedTorque``, ``ResolvedMotionRate``,
        ``AttitudeControl``, ``BaseThrusterControl``, ``CoordinatedFlying``, ``MomentumDamping``,
        ``Combined``, ``TorqueLimit``; not a ``Callback``), run inside the FMU at every RK4 stage
        as ``spacearm.simulate`` runs it; every finite number of its spec becomes an FMU
        parameter named by its path (``kp[k]``, ``kd[k]``, ``reference[k]`` of a joint PD with a
        set point; ``quat_ref[k]``, ``kp``, ``kd`` of an attitude law; docs/fmi.md). ``None``:
        only the ``tau`` inputs act.
    dt : float
        The FMU's RK4 step, s, between ``SPACEARM_MIN_DT`` = 1e-6 s and ``SPACEARM_MAX_DT`` = 10 s
        (docs/c-api.md); every communication step must be a multiple of it, of at most
        ``SPACEARM_MAX_STEPS_PER_CALL`` = 10⁶ RK4 steps.
    fmi_version : int
        3 (default) or 2.
    joint_limits : bool
        Whether the joints' effort and velocity limits apply (as in [`spacearm.simulate`][spacearm.simulate]).
    stop_time : float
        The default experiment's stop time, s.
    model_identifier : str, optional
        The binary's name (default: ``spacearm_`` and the model name, as an identifier).

    Raises
    ------
    MissingDependencyError
        The C library is not available (see ``spacearm.fmi.library``).
    ArgumentError
        An option out of its range (a ``dt`` outside [1e-6, 10] s, a ``stop_time`` that is not > 0),
        a ``controller`` that is not a native spacearm.control controller (a ``Callback``), or one
        the plant or the mode cannot run (the core's message).
    SpacearmTypeError
        An option of the wrong type (a ``dt`` that is a bool or not a number, a ``joint_limits`` that is
        not a bool).
    """
    if not isinstance(robot, Robot):
        raise SpacearmTypeError(f"export expects a spacearm.Robot, got {type(robot).__name__}")
    if isinstance(fmi_version, bool) or fmi_version not in (2, 3):
        raise ArgumentError(f"fmi_version must be 2 or 3, got {fmi_version!r}")
    if not isinstance(mode, str) or mode not in MODES:
        raise ArgumentError(f"mode must be one of {list(MODES)}, got {mode!r}")
    # Types here; the ranges of dt and stop_time are the C library's rules (dt within
    # [SPACEARM_MIN_DT, SPACEARM_MAX_DT], docs/c-api.md), answered when it writes the description.
    dt = _number("dt", dt)
    stop_time = _number("stop_time", stop_time)
    if not isinstance(joint_limits, (bool, np.bool_)):
        raise SpacearmTypeError(f"joint_limits must be True or False, got {joint_limits!r}")
    if model_identifier is not None and not isinstance(model_identifier, str):
        raise SpacearmTypeError(f"model_identifier must be a str or None, got {type(model_identifier).__name__}")
    identifier = model_identifier or "spacearm_" + re.sub(r"\W", "_", robot.name)
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", identifier):
        raise ArgumentError(f"model_identifier must be a C identifier, got {identifier!r}")
    lib = library.load()
    model_toml = _core.model_to_toml(robot.core_model)
    options_toml = _options_toml(lib, mode, dt, joint_limits, controller)
    digest = hashlib.sha256(f"{fmi_version}\0{identifier}\0{model_toml}\0{options_toml}".encode()).hexdigest()
    token = "{" + str(uuid.UUID(digest[:32])) + "}"
    description = lib.model_description(model_toml, options_toml, fmi_version, identifier, token, float(stop_time))
    binary = lib.file.read_bytes()
    suffix = lib.file.suffix
    folder = binary_folder(fmi_version)
    with atomic_path(path, suffix=".fmu") as tmp:
        with zipfile.ZipFile(tmp, "w", compression=zipfile.ZIP_DEFLATED) as z:
            z.writestr("modelDescription.xml", description)
            z.writestr(f"binaries/{folder}/{identifier}{suffix}", binary)
            z.writestr("resources/model.toml", model_toml)
            z.writestr("resources/options.toml", options_toml)
            # The binary checks the token an importer instantiates it with against this copy.
            z.writestr("resources/token.txt", token)
    return Path(path)
