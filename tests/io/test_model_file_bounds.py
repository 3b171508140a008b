"""Bounds of the model-file doors (issue 38): mesh files confined to the model's folder and its
package folders, mesh file names without control characters, errors that quote no line of a
file that is not a model, and compact numbers in messages. Each test fails on the behaviour
before (every path accepted, NUL and newline written into exported URDFs, a line of
/etc/shadow quoted, 131-digit numbers)."""

from __future__ import annotations

import re

import numpy as np
import pytest

import spacearm
from spacearm.io import load_toml, load_urdf, loads_urdf

INERTIAL = '<inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>'


def _urdf(filename: str) -> str:
    return (f'<robot name="r"><link name="base">{INERTIAL}<visual><geometry><mesh filename="{filename}"/></geometry>'
            '</visual></link></robot>')


@pytest.fixture()
def tree(tmp_path):
    """tmp/secret.stl (outside), tmp/robot/r.urdf's folder with meshes/a.stl, tmp/pkgs/pkg/meshes/b.stl."""
    (tmp_path / "secret.stl").write_text("solid secret\nendsolid\n")
    (tmp_path / "robot" / "meshes").mkdir(parents=True)
    (tmp_path / "robot" / "meshes" / "a.stl").write_text("solid a\nendsolid\n")
    (tmp_path / "pkgs" / "pkg" / "meshes").mkdir(parents=True)
    (tmp_path / "pkgs" / "pkg" / "meshes" / "b.stl").write_text("solid b\nendsolid\n")
    return tmp_path


def _load(tree, filename, **kwargs):
    path = tree / "robot" / "r.urdf"
    path.write_text(_urdf(filename))
    return load_urdf(path, package_dirs=[tree / "pkgs"], **kwargs)


@pytest.mark.parametrize("filename", [
    "../secret.stl", "meshes/../../secret.stl", "file://{tree}/secret.stl", "{tree}/secret.stl",
    "package://pkg/../../secret.stl", "package://pkg/meshes/../../../secret.stl",
])
def test_mesh_paths_outside_the_model_and_package_folders_are_refused(tree, filename):
    filename = filename.format(tree=tree)
    with pytest.raises(spacearm.ModelFileError, match=r"r\.urdf:1: mesh .* outside .*refused.*allow_outside_meshes=True"):
        _load(tree, filename)
    robot = _load(tree, filename, allow_outside_meshes=True)  # the user's explicit choice
    assert robot.description.geometries[0].file == str((tree / "secret.stl").resolve())


@pytest.mark.parametrize("filename, where", [
    ("meshes/a.stl", "robot/meshes/a.stl"), ("{tree}/robot/meshes/a.stl", "robot/meshes/a.stl"),
    ("file://{tree}/robot/meshes/a.stl", "robot/meshes/a.stl"), ("package://pkg/meshes/b.stl", "pkgs/pkg/meshes/b.stl"),
])
def test_mesh_paths_inside_are_resolved_as_before(tree, filename, where):
    robot = _load(tree, filename.format(tree=tree))
    assert robot.description.geometries[0].file == str(tree / where)


def test_a_symbolic_link_out_of_the_folder_is_outside(tree):
    link = tree / "robot" / "meshes" / "link.stl"
    try:
        link.symlink_to(tree / "secret.stl")
    except (OSError, NotImplementedError):
        pytest.skip("no symbolic links here")
    with pytest.raises(spacearm.ModelFileError, match="outside"):
        _load(tree, "meshes/link.stl")


def test_mesh_file_names_with_control_characters_are_refused(tmp_path):
    b = spacearm.Robot.builder("demo", base_mass=10.0, base_inertia=[1, 1, 1])
    for bad in ("a\x00.stl", "a\n.stl", "meshes/\r\nb.stl"):
        with pytest.raises(spacearm.ModelError, match="control characters"):
            b.add_geometry("base", "mesh", file=bad)
    # through a URDF: a newline given as a character reference
    with pytest.raises(spacearm.ModelFileError, match="control characters"):
        loads_urdf(_urdf("a&#10;b.stl"), allow_outside_meshes=True)
    b.add_geometry("base", "mesh", file="meshes/ok one.stl")
    xml = spacearm.io.to_urdf(b.build())
    assert 'filename="meshes/ok one.stl"' in xml


def test_errors_quote_no_line_of_a_file_that_is_not_a_model(tmp_path):
    shadow = tmp_path / "shadow"
    shadow.write_text("root:$6$SECRETHASH$abc:19000:0:99999:7:::\ndaemon:*:19000:0:99999:7:::\n")
    creds = tmp_path / "creds.toml"
    creds.write_text('[aws]\nkey = "SECRET-KEY"\n')
    for path in (shadow, creds):
        with pytest.raises(spacearm.ModelFileError) as info:
            load_toml(path)
        assert "SECRET" not in str(info.value) and "not a spacearm model file" in str(info.value), info.value
        with pytest.raises(spacearm.ModelFileError) as info:
            load_urdf(path)
        assert "SECRET" not in str(info.value)
    # a model file's own mistakes are still shown with their line
    model = tmp_path / "m.toml"
    model.write_text('[model]\nname = "m"\n\n[base]\nmass = = 3\n')
    with pytest.raises(spacearm.ModelFileError, match=r"m\.toml:5:\d+: .*\n 5 \| mass = = 3"):
        load_toml(model)


def test_huge_numbers_in_messages_are_compact():
    def long_runs(message):
        return re.findall(r"\d{18,}", message)

    b = spacearm.Robot.builder("demo", base_mass=10.0, base_inertia=[1, 1, 1])
    with pytest.raises(spacearm.ModelError) as info:
        b.add_geometry("base", "box", size=(1e130, 1, 1))
    assert "1e130" in str(info.value) and not long_runs(str(info.value)), info.value
    r = spacearm.presets.spatial6()
    x = r.neutral_configuration()
    x[3:7] = 1e51
    with pytest.raises(spacearm.QuaternionError) as info:
        r.forward_kinematics(x)
    assert not long_runs(str(info.value)) and "e51" in str(info.value), info.value
    with pytest.raises(spacearm.ModelFileError) as info:
        spacearm.io.loads_toml('[model]\nname = "a"\n[base]\nmass = -1e40\ninertia = [1, 1, 1]\n')
    first = str(info.value).splitlines()[0]
    assert not long_runs(first) and "-1e40" in first, info.value
    from spacearm._util.arrays import integer

    with pytest.raises(spacearm.ArgumentError) as info:
        integer("9" * 5000 + "x", "count")
    assert len(str(info.value)) < 150, info.value
    from spacearm._util.show import shown

    assert shown(10**130) == "~1e+130 (131 digits)" and shown(7) == "7" and shown(1e308) == "1e+308"
    assert shown(np.float64(0.1)) == "0.1" and len(shown("x" * 10_000)) == 80


def test_cli_refuses_outside_meshes_unless_allowed(tree, capsys):
    from spacearm.cli import main

    path = tree / "robot" / "r.urdf"
    path.write_text(_urdf("../secret.stl"))
    assert main(["inspect", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("spacearm: error:") and "outside" in err and "--allow-outside-meshes" in err, err
    assert main(["inspect", str(path), "--allow-outside-meshes"]) == 0
