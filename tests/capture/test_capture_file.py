"""CaptureResult.save and CaptureResult.load (issue 37 item 7b): the loaded result equals the
saved one — every array bit for bit, the scalars, the impact's every attribute, the models —
its summary and figure come from it, and damaged or foreign files are refused with the reason."""

from __future__ import annotations

import functools
import zipfile

import numpy as np
import pytest

import spacearm
from spacearm.capture import CaptureResult, capture
from spacearm.capture.sequence import _IMPULSE_FIELDS
from spacearm.io.model_file import dumps_toml


def _scene():
    robot = spacearm.presets.spatial6()
    x = robot.neutral_configuration()
    target = spacearm.Target(50.0, [4.0, 5.0, 6.0], grasp_points={"handle": (-0.5, 0.0, 0.0)})
    s = target.state(position=robot.point_position(x) + np.array([0.6, 0.0, 0.0]), angular_velocity=(0.0, 0.0, 0.1))
    return robot, target, s


@functools.lru_cache(maxsize=None)
def _run(kind: str, orbit: bool = False):
    robot, target, s = _scene()
    extra = {"orbit": spacearm.Orbit.circular(500e3, inclination=0.9)} if orbit else {}
    return capture(robot, target, s, mode="floating", kind=kind, detumble_time=1.0, soft_time=0.3, post_time=0.2,
                   max_joint_torque=20.0, **extra)


def _equal(a, b):
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a), np.asarray(b)
        return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()
    if isinstance(a, float) and isinstance(b, float) and np.isnan(a) and np.isnan(b):
        return True
    return a == b


@pytest.mark.parametrize("kind, orbit", [("rigid", False), ("point", False), ("soft", False), ("rigid", True)])
def test_load_returns_the_saved_result(tmp_path, kind, orbit):
    res = _run(kind, orbit)
    path = tmp_path / "cap.npz"
    res.save(path)
    back = CaptureResult.load(path)
    for key, value in res.arrays().items():
        if key in ("impulse", "du", "target_dtwist", "impact_point", "phase_names"):
            continue
        assert _equal(getattr(back, key), value), key
    for name in _IMPULSE_FIELDS:
        assert _equal(getattr(back.impact, name), getattr(res.impact, name)), name
    assert (back.soft_impact is None) == (res.soft_impact is None)
    for key in ("mode", "kind", "time_to_detumble", "residual_spin", "drift", "ledger", "gravity_gradient"):
        assert _equal(getattr(back, key), getattr(res, key)), key
    # The models: the same TOML, the same target (rigid: its inertia about the CM).
    assert dumps_toml(back.robot) == dumps_toml(res.robot)
    assert dumps_toml(back.target_model.body) == dumps_toml(res.target_model.body)
    assert back.target_model.name == res.target_model.name
    np.testing.assert_array_equal(back.target_model.inertia, res.target_model.inertia)
    assert (back.captured is None) == (res.captured is None) == (kind == "point")
    if res.captured is not None:
        assert dumps_toml(back.captured.robot) == dumps_toml(res.captured.robot)
        assert back.captured.payload == res.captured.payload and back.captured.gripper == res.captured.gripper
        assert _equal(back.captured.x, np.asarray(res.captured.x)) and _equal(back.captured.u, np.asarray(res.captured.u))
    assert back.in_orbit == orbit
    if orbit:
        assert _equal(np.asarray(back.orbit.r0), np.asarray(res.orbit.r0)) and back.orbit.j2 == res.orbit.j2
        assert back.orbit.body.mu == res.orbit.body.mu
    # Everything derived from it is the same: the summary (orbit figures included) and the
    # ledger; the figure draws from the loaded result.
    a, b = res.summary(), back.summary()
    assert a.keys() == b.keys()
    for key in a:
        assert _equal(a[key], b[key]), key
    if orbit:
        assert _equal(back.balance_residual(), res.balance_residual())
    fig = back.plot()
    assert any(len(line.get_xdata()) == len(res.t) for ax in fig.axes for line in ax.get_lines())


def test_load_refuses_damaged_and_foreign_files(tmp_path):
    res = _run("rigid")
    good = tmp_path / "cap.npz"
    res.save(good)
    raw = good.read_bytes()
    cut = tmp_path / "cut.npz"
    cut.write_bytes(raw[: len(raw) // 2])
    with pytest.raises(spacearm.ArgumentError, match="not a spacearm capture file"):
        CaptureResult.load(cut)
    # A trajectory file is not a capture.
    traj = spacearm.simulate(spacearm.presets.planar4(), 0.01, dt=1e-3)
    other = tmp_path / "traj.npz"
    traj.save(other)
    with pytest.raises(spacearm.ArgumentError, match="format tag 'spacearm.Trajectory/1'"):
        CaptureResult.load(other)
    # An entry removed: named.
    with np.load(good) as f:
        files = {k: f[k] for k in f.files}
    del files["grasp_wrench"]
    edited = tmp_path / "edited.npz"
    np.savez(edited, **files)
    with pytest.raises(spacearm.ArgumentError, match="no 'grasp_wrench'"):
        CaptureResult.load(edited)
    # An older file (the arrays only): the way out named.
    with np.load(good) as f:
        files = {k: f[k] for k in f.files if not k.startswith(("impact.", "captured.", "__meta__", "__captured"))}
    files["__format__"] = np.array("spacearm.CaptureResult/1")
    older = tmp_path / "older.npz"
    np.savez(older, **files)
    with pytest.raises(spacearm.ArgumentError, match="older spacearm"):
        CaptureResult.load(older)
    # A row count that disagrees with t.
    with np.load(good) as f:
        files = {k: f[k] for k in f.files}
    files["x"] = files["x"][:-1]
    short = tmp_path / "short.npz"
    np.savez(short, **files)
    with pytest.raises(spacearm.ArgumentError, match="'x' has shape"):
        CaptureResult.load(short)
    assert zipfile.is_zipfile(good)
