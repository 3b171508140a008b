"""The example model files shipped inside the package (``spacearm.examples``, docs/api/examples.md):
they are found by name from any directory, load, and are the models their comments describe
(checked against closed forms and the presets, not against the files themselves)."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

import spacearm
from spacearm import examples, presets


def test_every_shipped_name_is_a_loadable_file_inside_the_package():
    package = os.path.dirname(spacearm.__file__)
    assert {"spacecraft_bus", "spatial6_wheels"} <= set(examples.NAMES)
    for name in examples.NAMES:
        path = examples.path(name)
        assert path.is_file() and str(path).startswith(package)
        assert examples.path(name + ".toml") == path
        robot = spacearm.io.load_toml(path)
        assert robot.name == name


def test_the_preset_files_are_the_presets():
    x_rng = np.random.default_rng(3)
    for name in set(examples.NAMES) & set(presets.NAMES):
        from_file, preset = spacearm.io.load_toml(examples.path(name)), presets.get(name)
        x = preset.neutral_configuration()
        x[7:] = x_rng.uniform(-1, 1, preset.n_dof)
        np.testing.assert_allclose(from_file.mass_matrix(x), preset.mass_matrix(x), rtol=1e-9, atol=1e-12)


def test_the_bus_is_a_uniform_box_of_500_kg():
    bus = spacearm.io.load_toml(examples.path("spacecraft_bus")).description.base
    a, b, c = 1.2, 1.1, 1.0  # its documented size, m
    assert bus.mass == 500.0
    np.testing.assert_allclose(np.diag(bus.inertia), 500 / 12 * np.array([b * b + c * c, a * a + c * c, a * a + b * b]),
                               rtol=1e-4)


def test_the_wheel_model_has_three_wheels_on_spatial6():
    wheels = spacearm.io.load_toml(examples.path("spatial6_wheels"))
    assert wheels.n_dof == presets.spatial6().n_dof + 3


@pytest.mark.parametrize("bad", ["nope", "spacecraft_bus.urdf", "", "../spatial6"])
def test_an_unknown_name_is_refused_with_the_list(bad):
    with pytest.raises(spacearm.errors.NotFoundError, match="spacecraft_bus, spatial6"):
        examples.path(bad)


def test_a_name_that_is_not_text_is_a_type_error():
    with pytest.raises(spacearm.errors.SpacearmTypeError, match="must be a str"):
        examples.path(3)


def test_the_cli_takes_the_names_from_any_directory(tmp_path):
    env = dict(os.environ, PYTHONPATH=os.path.dirname(os.path.dirname(spacearm.__file__)))
    out = subprocess.run([sys.executable, "-m", "spacearm", "inspect", "spatial6_wheels"], cwd=tmp_path, env=env,
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert "model 'spatial6_wheels'" in out.stdout and "N = 9 joint DOF" in out.stdout
