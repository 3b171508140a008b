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
    assert lib.spacearm_model_preset(b"spatial6", ctypes.byref(handle)) == 0
    try:
        x = np.zeros(13)  # a zero quaternion
        h = np.empty((12, 12))
        assert lib.spacearm_mass_matrix(handle, ptr(x), ptr(h)) == 4  # SPACEARM_STATUS_NOT_UNIT_QUATERNION
        assert b"unit quaternion" in lib.spacearm_last_error()
        assert lib.spacearm_mass_matrix(handle, ptr(x), None) == 11  # SPACEARM_STATUS_NULL_POINTER
    finally:
        lib.spacearm_model_free(handle)
