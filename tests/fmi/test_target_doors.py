"""A free target in the loop of contact through two doors of the core's loop (issue 35): the
same run — robot, rock, contact, 13-state — by ``spacearm.simulate(contact=, target=,
target_state=)`` and by the C stepper (``libspacearm_c`` through ctypes) reading an options file
that names the rock's model file (relative to the options file) and its 13-state, gives the same
robot and rock states, bit for bit, at every communication point. An FMU of such options is
refused with its reason (its variables carry the robot's state only)."""

from __future__ import annotations

import ctypes

import numpy as np
import pytest

import spacearm
from spacearm import _core
from spacearm.fmi import library

from target_scene import scene

DT = 2.0**-10
EVERY = 16
POINTS = 40
D = ctypes.POINTER(ctypes.c_double)


def _lib():
    lib = ctypes.CDLL(str(library.path()))
    lib.spacearm_last_error.restype = ctypes.c_char_p
    lib.spacearm_model_from_toml.argtypes = [ctypes.c_char_p, ctypes.POINTER(ctypes.c_void_p)]
    lib.spacearm_model_free.argtypes = [ctypes.c_void_p]
    lib.spacearm_stepper_new_from_file.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.POINTER(ctypes.c_void_p)]
    lib.spacearm_stepper_new.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.POINTER(ctypes.c_void_p)]
    lib.spacearm_stepper_reset.argtypes = [ctypes.c_void_p, D, D]
    lib.spacearm_stepper_step.argtypes = [ctypes.c_void_p, D, D, ctypes.c_size_t]
    lib.spacearm_stepper_state.argtypes = [ctypes.c_void_p, D, D]
    lib.spacearm_stepper_target_state.argtypes = [ctypes.c_void_p, D]
    lib.spacearm_stepper_free.argtypes = [ctypes.c_void_p]
    return lib


def test_the_c_stepper_and_simulate_run_a_free_target_under_contact_bit_for_bit(tmp_path):
    robot, rock, s0, u0, contact = scene()
    traj = spacearm.simulate(robot, POINTS * EVERY * DT, u0=u0, dt=DT, contact=contact, target=rock, target_state=s0)
    keep = slice(None, None, EVERY)
    want_x, want_u, want_s = traj.x[keep], traj.u[keep], traj["target"][keep]
    assert want_x.shape[0] == POINTS + 1
    assert (traj.contact_count > 0).any(), "the rock touched the tip"
    assert np.abs(want_s[-1, 7:10] - want_s[0, 7:10]).max() > 0.05, "and the contact changed its motion"

    # the options file: the run's description as the C door reads it, the rock's model beside it
    folder = tmp_path / "run"
    folder.mkdir()
    (folder / "rock.toml").write_text(_core.model_to_toml(rock.core_model))
    state = ", ".join(repr(float(v)) for v in s0)
    (folder / "options.toml").write_text(
        f'mode = "floating"\ndt = {DT!r}\ntarget = "rock.toml"\ntarget_state = [{state}]\n\n'
        '[contact]\npairs = [["l1", "target"]]\nstiffness = 2e4\ndamping = 30.0\nfriction = 0.4\nslip_velocity = 0.01\n')
    lib = _lib()

    def ok(status):
        assert status == 0, lib.spacearm_last_error().decode()

    model, stepper = ctypes.c_void_p(), ctypes.c_void_p()
    ok(lib.spacearm_model_from_toml(_core.model_to_toml(robot.core_model).encode(), ctypes.byref(model)))
    try:
        ok(lib.spacearm_stepper_new_from_file(model, str(folder / "options.toml").encode(), ctypes.byref(stepper)))
        x0, u = robot.neutral_configuration().astype(float), np.ascontiguousarray(u0, dtype=float)
        ok(lib.spacearm_stepper_reset(stepper, x0.ctypes.data_as(D), u.ctypes.data_as(D)))
        xs, us, ss = [], [], []
        for k in range(POINTS + 1):
            if k:
                ok(lib.spacearm_stepper_step(stepper, None, None, EVERY))
            x, u, s = np.empty(robot.nx), np.empty(robot.nu), np.empty(13)
            ok(lib.spacearm_stepper_state(stepper, x.ctypes.data_as(D), u.ctypes.data_as(D)))
            ok(lib.spacearm_stepper_target_state(stepper, s.ctypes.data_as(D)))
            xs.append(x)
            us.append(u)
            ss.append(s)
    finally:
        lib.spacearm_stepper_free(stepper)
        lib.spacearm_model_free(model)
    got_x, got_u, got_s = np.array(xs), np.array(us), np.array(ss)
    assert np.array_equal(got_x, want_x) and np.array_equal(got_u, want_u), \
        f"robot: max |dx| {np.abs(got_x - want_x).max():.3g}, |du| {np.abs(got_u - want_u).max():.3g}"
    assert np.array_equal(got_s, want_s), f"rock: max |ds| {np.abs(got_s - want_s).max():.3g}"


def test_an_fmu_of_options_with_a_target_is_refused(tmp_path):
    robot, rock, s0, _, _ = scene()
    lib = library.load()
    options = 'mode = "floating"\ntarget = "rock.toml"\ntarget_state = [0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0]\n'
    with pytest.raises(spacearm.errors.ArgumentError, match="an FMU with a free target .* is not implemented"):
        lib.model_description(_core.model_to_toml(robot.core_model), options, 3, "m", "tok", 1.0)
