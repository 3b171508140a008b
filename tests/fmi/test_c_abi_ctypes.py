"""The C ABI called from Python's ctypes, as MATLAB's ``loadlibrary``/``calllib`` calls it
(docs/c-api.md, "MATLAB"): the same entry points and row-major buffers. What is checked here is
the boundary (layouts, sizes, status codes, messages); the quantities themselves are checked
against independent sources in the core's tests and, from C, in crates/spacearm-c/tests/c.

Every quantity is compared with the Python binding's (``spacearm.Robot``), which reaches the
same core through PyO3 with numpy's C order: a transposed or misplaced buffer, a wrong size or a
mixed-up argument order shows as a difference.
"""

from __future__ import annotations

import ctypes

import numpy as np
import pytest

import spacearm
from spacearm.fmi import library

D = ctypes.POINTER(ctypes.c_double)


@pytest.fixture(scope="module")
def lib():
    lib = ctypes.CDLL(str(library.path()))
    lib.spacearm_last_error.restype = ctypes.c_char_p
    lib.spacearm_model_preset.argtypes = [ctypes.c_char_p, ctypes.POINTER(ctypes.c_void_p)]
    lib.spacearm_model_from_toml.argtypes = [ctypes.c_char_p, ctypes.POINTER(ctypes.c_void_p)]
    lib.spacearm_model_free.argtypes = [ctypes.c_void_p]
    lib.spacearm_model_free.restype = None
    for name in ("spacearm_model_n_dof", "spacearm_model_nx", "spacearm_model_nu"):
        getattr(lib, name).argtypes = [ctypes.c_void_p]
        getattr(lib, name).restype = ctypes.c_size_t
    lib.spacearm_mass_matrix.argtypes = [ctypes.c_void_p, D, D]
    lib.spacearm_generalized_inertia.argtypes = [ctypes.c_void_p, D, D]
    lib.spacearm_generalized_jacobian.argtypes = [ctypes.c_void_p, D, ctypes.c_size_t, D, D]
    lib.spacearm_generalized_bias.argtypes = [ctypes.c_void_p, D, D, D]
    lib.spacearm_reduced_forward_dynamics.argtypes = [ctypes.c_void_p, D, D, D, D, D]
    lib.spacearm_inertia_blocks.argtypes = [ctypes.c_void_p, D, D, D, D]
    lib.spacearm_model_point.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.POINTER(ctypes.c_size_t), D]
    lib.spacearm_abi_version.restype = ctypes.c_uint32
    lib.spacearm_status_name.argtypes = [ctypes.c_int32]
    lib.spacearm_status_name.restype = ctypes.c_char_p
    lib.spacearm_forward_dynamics.argtypes = [ctypes.c_void_p, D, D, D, D]
    lib.spacearm_inverse_dynamics.argtypes = [ctypes.c_void_p, D, D, D, D]
    return lib


def ptr(a: np.ndarray):
    return a.ctypes.data_as(D)


def generic_state(robot):
    rng = np.random.default_rng(3)
    q = robot.initial_q + rng.uniform(-0.5, 0.5, robot.n_dof)
    quat = rng.normal(size=4)
    x = robot.neutral_configuration(q, r0=(0.3, -0.2, 0.1), quat0=quat / np.linalg.norm(quat))
    u = rng.normal(size=robot.nu) * 0.3
    return x, u


def test_abi_version(lib):
    assert lib.spacearm_abi_version() == library.ABI_VERSION


@pytest.mark.parametrize("name", ["spatial6", "dual_arm"])
def test_the_quantities_through_ctypes_equal_the_bindings(lib, name):
    robot = spacearm.presets.get(name)
    handle = ctypes.c_void_p()
    assert lib.spacearm_model_preset(name.encode(), ctypes.byref(handle)) == 0
    try:
        n, nu = lib.spacearm_model_n_dof(handle), lib.spacearm_model_nu(handle)
        assert (n, lib.spacearm_model_nx(handle), nu) == (robot.n_dof, robot.nx, robot.nu)
        x, u = generic_state(robot)
        h = np.empty((nu, nu))
        assert lib.spacearm_mass_matrix(handle, ptr(x), ptr(h)) == 0
        assert np.allclose(h, robot.mass_matrix(x), rtol=1e-13, atol=1e-12)
        hs = np.empty((n, n))
        assert lib.spacearm_generalized_inertia(handle, ptr(x), ptr(hs)) == 0
        assert np.allclose(hs, robot.generalized_inertia(x), rtol=1e-12, atol=1e-12)
        h0, h0m, hm = np.empty((6, 6)), np.empty((6, n)), np.empty((n, n))
        assert lib.spacearm_inertia_blocks(handle, ptr(x), ptr(h0), ptr(h0m), ptr(hm)) == 0
        assert np.allclose(h0m, h[:6, 6:], atol=1e-12) and np.allclose(hm, h[6:, 6:], atol=1e-12)
        body, offset = ctypes.c_size_t(), np.empty(3)
        assert lib.spacearm_model_point(handle, None, ctypes.byref(body), ptr(offset)) == 0
        js = np.empty((6, n))
        assert lib.spacearm_generalized_jacobian(handle, ptr(x), body.value, ptr(offset), ptr(js)) == 0
        assert np.allclose(js, robot.generalized_jacobian(x), rtol=1e-12, atol=1e-12)
        cs = np.empty(n)
        assert lib.spacearm_generalized_bias(handle, ptr(x), ptr(u), ptr(cs)) == 0
        assert np.allclose(cs, robot.generalized_bias(x, u), rtol=1e-12, atol=1e-12)
        tau, w, du = np.linspace(-1, 1, n), np.array([3.0, -2, 1, 0.5, -0.4, 0.2]), np.empty(nu)
        assert lib.spacearm_reduced_forward_dynamics(handle, ptr(x), ptr(u), ptr(tau), ptr(w), ptr(du)) == 0
        assert np.allclose(du, robot.forward_dynamics(x, u, tau=tau, base_wrench=w), rtol=1e-10, atol=1e-10)
    finally:
        lib.spacearm_model_free(handle)


def test_errors_come_back_as_status_and_message(lib):
    handle = ctypes.c_void_p()
    assert lib.spacearm_model_from_toml(b"[base]\nmass = -1\n", ctypes.byref(handle)) != 0
    assert not handle.value
    assert lib.spacearm_last_error()
    # A success clears the message, in a call that returns a value too.
    assert lib.spacearm_model_preset(b"planar4", ctypes.byref(handle)) == 0
    assert lib.spacearm_model_preset(b"nope", ctypes.byref(ctypes.c_void_p())) == 5 and lib.spacearm_last_error()
    assert lib.spacearm_model_nx(handle) == 11 and lib.spacearm_last_error() == b""
    lib.spacearm_model_free(handle)
    assert lib.spacearm_model_preset(b"spatial6", ctypes.byref(handle)) == 0
    try:
        x = np.zeros(13)  # a zero quaternion
        h = np.empty((12, 12))
        assert lib.spacearm_mass_matrix(handle, ptr(x), ptr(h)) == 4  # SPACEARM_STATUS_NOT_UNIT_QUATERNION
        assert b"unit quaternion" in lib.spacearm_last_error()
        assert lib.spacearm_mass_matrix(handle, ptr(x), None) == 11  # SPACEARM_STATUS_NULL_POINTER
    finally:
        lib.spacearm_model_free(handle)


# ---- issue 38: the status contract ----

NON_FINITE, INVALID_MODEL, PARSE = 3, 1, 7


def test_every_int_has_a_status_name(lib):
    names = [lib.spacearm_status_name(s) for s in range(15)]
    assert len(set(names)) == 15 and b"unknown status" not in names
    for s in (-1, 15, 2**31 - 1, -2**31):
        assert lib.spacearm_status_name(s) == b"unknown status"


def test_a_model_rule_is_invalid_model_and_bad_syntax_is_parse(lib):
    handle = ctypes.c_void_p()
    text = b'[model]\nname = "neg"\n[base]\nmass = -100.0\ninertia = [10.0, 10.0, 10.0]\n'
    assert lib.spacearm_model_from_toml(text, ctypes.byref(handle)) == INVALID_MODEL and not handle.value
    assert b":4:" in lib.spacearm_last_error()  # the line of the mass
    with pytest.raises(spacearm.errors.ModelError):  # Python: ModelFileError, a ModelError
        spacearm.io.loads_toml(text.decode())
    assert lib.spacearm_model_from_toml(b"[model\nname = 1", ctypes.byref(handle)) == PARSE and not handle.value


@pytest.mark.parametrize("case", ["u=+1e300", "u=-1e300", "f=DBL_MAX", "du=DBL_MAX", "u=nan"])
def test_non_finite_results_are_refused_where_python_refuses_them(lib, case):
    """Where the binding raises NonFiniteError the C ABI answers NON_FINITE (with a message) and
    leaves the output as it was; before issue 38 it answered OK with NaN or inf."""
    robot = spacearm.presets.spatial6()
    x, u = generic_state(robot)
    f = np.zeros(robot.nu)
    big = np.finfo(float).max
    what, value = case.split("=")
    value = {"+1e300": 1e300, "-1e300": -1e300, "DBL_MAX": big, "nan": np.nan}[value]
    if what == "u":
        u = np.full(robot.nu, value)
    else:
        f = np.full(robot.nu, value)
    handle = ctypes.c_void_p()
    assert lib.spacearm_model_preset(b"spatial6", ctypes.byref(handle)) == 0
    try:
        for name, python in (("spacearm_forward_dynamics", lambda: robot.forward_dynamics(x, u, f)),
                             ("spacearm_inverse_dynamics", lambda: robot.inverse_dynamics(x, u, f))):
            if what == "du" and name == "spacearm_forward_dynamics" or what == "f" and name == "spacearm_inverse_dynamics":
                continue
            with pytest.raises(spacearm.errors.NonFiniteError):
                python()
            out = np.full(robot.nu, 7.0)
            assert getattr(lib, name)(handle, ptr(x), ptr(u), ptr(f), ptr(out)) == NON_FINITE, name
            assert b"finite" in lib.spacearm_last_error()
            assert (out == 7.0).all()
    finally:
        lib.spacearm_model_free(handle)
