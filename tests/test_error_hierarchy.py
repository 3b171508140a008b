"""Every error spacearm raises is a :class:`spacearm.SpacearmError` with the builtin base that
``spacearm.errors`` documents.

Three checks: the Python package raises no bare builtin exception (a static scan of its source);
every class has the builtin bases of the table in ``spacearm.errors``' docstring; and every error
kind of the Rust core reaches Python as its class (the binding's mapping read from its source,
then each kind triggered through the public API).
"""

from __future__ import annotations

import ast
import builtins
import pathlib
import pickle
import re

import numpy as np
import pytest

import spacearm
import spacearm.analysis
import spacearm.analysis.free_floating
from spacearm import errors, presets

ROOT = pathlib.Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "python" / "spacearm"
BINDINGS = ROOT / "crates" / "spacearm-py" / "src"

# Builtin exceptions that must not be raised bare: each has a spacearm.errors class to use.
# (NotImplementedError stays allowed: it marks an abstract method, a programming error.)
BARE = {
    "Exception", "ValueError", "TypeError", "KeyError", "IndexError", "LookupError", "RuntimeError",
    "ArithmeticError", "FloatingPointError", "ZeroDivisionError", "OverflowError", "ImportError",
    "ModuleNotFoundError",
}


def bare_raises(source: str) -> list:
    """Line numbers of ``raise X(...)`` / ``raise X`` with X a builtin of :data:`BARE`."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Raise) and node.exc is not None:
            target = node.exc.func if isinstance(node.exc, ast.Call) else node.exc
            if isinstance(target, ast.Name) and target.id in BARE:
                found.append((node.lineno, target.id))
    return sorted(found)


def test_the_scan_finds_bare_raises():
    src = "def f(x):\n    if x:\n        raise ValueError('x')\n    raise KeyError\n"
    assert bare_raises(src) == [(3, "ValueError"), (4, "KeyError")]
    assert bare_raises("raise ShapeError('x')\nraise\nraise exc from None\n") == []


def test_no_bare_builtin_raise_in_the_package():
    offenders = []
    for path in sorted(PACKAGE.rglob("*.py")):
        for line, name in bare_raises(path.read_text(encoding="utf-8")):
            offenders.append(f"{path.relative_to(ROOT)}:{line}: raise {name}")
    assert not offenders, "bare builtin raises (use a spacearm.errors class):\n" + "\n".join(offenders)


def test_the_library_raises_subclasses_not_the_base_class():
    # A plain SpacearmError has no builtin base (``except ValueError`` misses it). The command
    # line (spacearm.cli) may raise it: main() reports every SpacearmError the same way.
    offenders = []
    for path in sorted(PACKAGE.rglob("*.py")):
        if path.name.startswith("cli") or "cli" in path.relative_to(PACKAGE).parts:
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Raise) and isinstance(node.exc, ast.Call) and getattr(node.exc.func, "id", None) == "SpacearmError":
                offenders.append(f"{path.relative_to(ROOT)}:{node.lineno}")
    assert not offenders, "raise a SpacearmError subclass (spacearm.errors):\n" + "\n".join(offenders)


# ---- the classes -------------------------------------------------------------------------------
# class -> the builtin exceptions it must be an instance of (the table in errors.py's docstring).
BASES = {
    "ModelError": {ValueError},
    "ModelFileError": {ValueError},
    "ShapeError": {ValueError},
    "NonFiniteError": {ValueError},
    "QuaternionError": {ValueError},
    "ArgumentError": {ValueError},
    "SpacearmTypeError": {TypeError},
    "NotFoundError": {KeyError, LookupError, ValueError},
    "SingularError": {ArithmeticError},
    "SimulationError": {RuntimeError},
    "ResourceLimitError": {MemoryError},
    "CampaignError": {RuntimeError},
    "MissingDependencyError": {ImportError},
}


def builtin_ancestors(cls) -> set:
    return {c for c in cls.__mro__ if getattr(builtins, c.__name__, None) is c} - {Exception, BaseException, object}


@pytest.mark.parametrize("name", sorted(BASES))
def test_class_has_its_documented_builtin_bases(name):
    cls = getattr(errors, name)
    assert issubclass(cls, errors.SpacearmError)
    assert name in errors.__all__ and getattr(spacearm, name) is cls
    # The builtin ancestors are exactly those documented (no accidental extra base).
    assert builtin_ancestors(cls) == BASES[name]
    assert f"| `{name}` |" in errors.__doc__


@pytest.mark.parametrize("name", sorted(BASES))
def test_class_pickles_and_prints_its_message(name):
    # Campaign workers send errors between processes; the CLI prints str(error).
    error = getattr(errors, name)("link 'x': mass must be > 0")
    copy = pickle.loads(pickle.dumps(error))
    assert type(copy) is type(error) and str(copy) == str(error) == "link 'x': mass must be > 0"


def test_every_class_is_in_the_table():
    classes = {n for n in errors.__all__ if n != "SpacearmError" and not issubclass(getattr(errors, n), Warning)}
    assert classes == set(BASES)


def test_not_found_error_is_a_key_error_that_prints_its_message():
    robot = presets.planar4()
    for kind in (KeyError, LookupError, ValueError, errors.SpacearmError):
        with pytest.raises(kind):
            robot.body_index("nope")
    with pytest.raises(errors.NotFoundError) as info:
        robot.body_index("nope")
    message = str(info.value)
    assert "nope" in message and not message.startswith("'")  # not KeyError's quoted repr


# ---- the Rust core's error kinds ----------------------------------------------------------------
def core_error_variants() -> list:
    """Variant names of the core's ``SpacearmError`` enum, read from its source."""
    (path,) = [p for p in (ROOT / "crates" / "spacearm-core" / "src").rglob("*.rs")
               if re.search(r"pub enum SpacearmError\b", p.read_text(encoding="utf-8"))]
    body = path.read_text(encoding="utf-8").split("pub enum SpacearmError", 1)[1]
    body = body[: body.index("\n}")]
    return re.findall(r"^    ([A-Z]\w*)\b", body, flags=re.M)  # variants sit at one indentation level


def binding_mapping() -> dict:
    """``kind -> Python class name`` as the extension raises them (the core's table of error
    kinds, error.rs ``ErrorKind``, exported as ``_core.ERROR_KINDS``)."""
    return {name: cls.__name__ for name, _code, cls in spacearm._core.ERROR_KINDS}


def test_the_binding_maps_every_core_error_kind_onto_a_spacearm_error_class():
    variants = core_error_variants()
    assert len(variants) >= 9, variants
    mapping = binding_mapping()
    assert list(mapping) == variants  # one kind per variant, in the enum's order
    for variant, cls in mapping.items():
        assert issubclass(getattr(errors, cls), errors.SpacearmError), (variant, cls)
        assert getattr(errors, cls) is getattr(spacearm._core, cls)


def c_statuses() -> dict:
    """``NAME -> code`` of the C header's status enum (``SPACEARM_STATUS_NAME = code``)."""
    header = (ROOT / "crates" / "spacearm-c" / "include" / "spacearm.h").read_text(encoding="utf-8")
    return {name: int(code) for name, code in re.findall(r"SPACEARM_STATUS_(\w+) = (\d+)", header)}


def c_api_table() -> dict:
    """``code -> (NAME, Python class or "")`` of the status table of docs/c-api.md."""
    text = (ROOT / "docs" / "c-api.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| (\d+) `(\w+)` \|.*\| *(?:`(\w+)`[^|]*)? *\|$", text, flags=re.M)
    return {int(code): (name, cls) for code, name, cls in rows}


def test_every_core_error_kind_is_a_distinct_c_status_and_a_distinct_python_class():
    kinds = spacearm._core.ERROR_KINDS
    assert [name for name, _, _ in kinds] == core_error_variants()
    codes = [code for _, code, _ in kinds]
    classes = [cls for _, _, cls in kinds]
    assert len(set(codes)) == len(kinds) and 0 not in codes
    assert len(set(classes)) == len(kinds)
    header, table = c_statuses(), c_api_table()
    assert header["OK"] == 0 and len(table) >= len(kinds), table
    for name, code, cls in kinds:
        # The status of that code in the header is the kind's name (InvalidModel ~ INVALID_MODEL),
        # and docs/c-api.md's table gives the same status and class.
        snake = re.sub(r"(?<!^)(?=[A-Z])", "_", name).upper()
        assert header[snake] == code, (name, code)
        assert table[code] == (snake, cls.__name__), (name, table[code])
        assert cls.__module__ == "spacearm.errors" and getattr(errors, cls.__name__) is cls
    # The statuses only the C ABI has (a NULL pointer, a short buffer, I/O, a panic) are no kind.
    assert set(header.values()) - set(codes) == {0, 11, 12, 13, 14}


def test_the_bindings_raise_no_builtin_python_exception_directly():
    offenders = []
    for path in sorted(BINDINGS.glob("*.rs")):
        for k, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if re.search(r"\bPy(Value|Runtime|Type|Key|Index|Lookup|Arithmetic|Exception)Error\b|PyException::", line):
                offenders.append(f"{path.relative_to(ROOT)}:{k}: {line.strip()}")
    assert not offenders, "\n".join(offenders)


def _diverging_simulation():
    robot = presets.planar4()
    spacearm.simulate(robot, 1.0, integrator="dopri5", dt=0.5, max_steps=2)


# Each core error kind triggered through the public API, with the class it must arrive as.
# (Singular has no trigger: a validated model's H0 and H* are positive definite.)
KINDS = {
    "InvalidModel": (lambda: spacearm.RobotBuilder("m", -1.0, [1, 1, 1]).build(), errors.ModelError),
    "Dimension": (lambda: presets.planar4().mass_matrix(np.zeros(3)), errors.ShapeError),
    "NonFinite": (lambda: presets.planar4().mass_matrix(np.full(11, np.nan)), errors.NonFiniteError),
    "NotUnitQuaternion": (lambda: presets.planar4().mass_matrix(np.r_[0, 0, 0, 0, 0, 0, 2.0, np.zeros(4)]),
                          errors.QuaternionError),
    "NotFound": (lambda: presets.planar4().body_index("nope"), errors.NotFoundError),
    "Parse": (lambda: spacearm.io.loads_toml("[model\nname = 1"), errors.ModelFileError),
    "InvalidArgument": (lambda: spacearm.analysis.reaction_null_space(presets.planar4(), base_motion="twist"),
                        errors.ArgumentError),
    "Simulation": (_diverging_simulation, errors.SimulationError),
}


@pytest.mark.parametrize("variant", sorted(KINDS))
def test_core_error_kind_arrives_as_its_class(variant):
    trigger, cls = KINDS[variant]
    assert binding_mapping()[variant] == cls.__name__
    with pytest.raises(cls):
        trigger()


# ---- the Python-side conversions ------------------------------------------------------------------
def test_python_side_errors_have_their_classes():
    robot = presets.planar4()
    x, u = robot.neutral_configuration(), robot.zero_velocity()
    with pytest.raises(errors.SpacearmTypeError):
        spacearm.Robot("planar4")
    with pytest.raises(errors.SpacearmTypeError):
        robot.forward_dynamics(x, u, wrenches=[(1, [0, 0, 1])])
    with pytest.raises(errors.ArgumentError, match="not both"):
        robot.forward_dynamics(x, u, np.zeros(robot.nu), tau=np.zeros(robot.n_dof))
    with pytest.raises(errors.ArgumentError, match="method"):
        robot.forward_dynamics(x, u, method="nope")
    with pytest.raises(errors.ArgumentError, match="method"):
        robot.mass_matrix(x, method="nope")
    with pytest.raises(errors.ArgumentError, match="inputs"):
        robot.linearize(x, u, inputs="nope")
    with pytest.raises(errors.SpacearmTypeError):
        spacearm.io.model_file.loads_toml(42)


def test_scalar_options_of_the_wrong_kind_are_spacearm_errors():
    # float() itself would raise ValueError ('a') or TypeError ([3]): the same builtin bases,
    # as spacearm errors naming the argument.
    robot = presets.planar4()
    x = robot.neutral_configuration()
    cases = [
        (lambda v: spacearm.RobotBuilder("b", v, [1, 1, 1]), "base_mass"),
        (lambda v: spacearm.RobotBuilder("b", 1.0, [1, 1, 1]).add_link("l", parent="base", mass=v, inertia=[1, 1, 1]), "mass"),
        (lambda v: spacearm.RobotBuilder("b", 1.0, [1, 1, 1]).add_link("l", parent="base", mass=1.0, inertia=[1, 1, 1],
                                                                        limits={"effort": v}), "limit effort"),
        (lambda v: spacearm.analysis.reaction_null_space(robot, x, tolerance=v), "tolerance"),
        (lambda v: spacearm.analysis.detect(robot, x, threshold=v), "threshold"),
        (lambda v: spacearm.analysis.damping(0.1, 0.2, v), "max_damping"),
    ]
    integers = [
        (lambda v: spacearm.analysis.workspace(robot, resolution=v), "resolution"),
        (lambda v: spacearm.analysis.workspace(robot, random_samples=v), "random_samples"),
        (lambda v: spacearm.analysis.singularity_map(robot, resolution=v), "resolution"),
    ]
    for call, name in cases + integers:
        with pytest.raises(errors.ArgumentError, match=name):
            call("a")
        with pytest.raises(errors.SpacearmTypeError, match=name):
            call([3])  # (None means "not given" for some options)
    for call, name in integers:
        with pytest.raises(errors.ArgumentError, match=f"{name} must be an integer, got 2.5"):
            call(2.5)
    with pytest.raises(errors.SpacearmTypeError, match="base_motion"):
        spacearm.analysis.reaction_null_space(robot, x, base_motion=3)
    with pytest.raises(errors.ArgumentError, match="joints"):
        spacearm.analysis.singularity_map(robot, joints=("a", 1))
    with pytest.raises(errors.ArgumentError, match="t_end"):
        spacearm.analysis.free_floating.integrate_prescribed(robot, np.zeros, np.zeros, "x", 0.1)
    with pytest.raises(errors.ArgumentError, match="base_mass"):
        spacearm.io.robot_from_dh("d", [dict(d=0, theta=0, a=1, alpha=0, com=(0, 0, 0), mass=1.0, inertia=[1, 1, 1])],
                               base_mass="x", base_inertia=[1, 1, 1])
    with pytest.raises(errors.ModelError, match="limits"):
        spacearm.io.robot_from_dh("d", [dict(d=0, theta=0, a=1, alpha=0, com=(0, 0, 0), mass=1.0, inertia=[1, 1, 1],
                                          limits={"effort": "x"})], base_mass=1.0, base_inertia=[1, 1, 1])
    with pytest.raises(errors.SpacearmTypeError, match="path"):
        spacearm.io.load_toml(None)


def test_the_extension_imports_no_module_of_the_package():
    # The extension defines its exception classes (errors_py.rs) and converts arrays with numpy
    # (convert.rs); spacearm.errors re-exports the classes. Importing a module of the package
    # from the extension would tie the FFI to the package's layout.
    offenders = []
    for path in sorted(BINDINGS.glob("*.rs")):
        for k, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            for module in re.findall(r"import\(\"(spacearm[\w.]*)\"\)", line):
                if module != "spacearm._core":
                    offenders.append(f"{path.relative_to(ROOT)}:{k}: {module}")
    assert not offenders, "\n".join(offenders)
    assert errors.ShapeError is spacearm._core.ShapeError
    assert errors.ShapeError.__module__ == "spacearm.errors"
