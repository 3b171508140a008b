"""Property-based checks of the array boundary (issue 38, item 5; docs/batch.md "The array
boundary"): hypothesis draws, for every array argument of the per-state methods, a memory
layout (C or Fortran order, a step per axis, positive or negative, an odd byte offset,
read-only), a real dtype and byte order, and a batch size, and checks

- valid: the call equals, bit for bit, the call on the canonical C-ordered float64 copy of
  the same values (``np.array(a, dtype=float, order="C")``, a fresh aligned array);
- invalid (a wrong shape, a complex, object or string array, a ragged list): the call raises a
  ``spacearm.SpacearmError``, never another exception.

Seeded (``derandomize``) and bounded, so that it runs in seconds in CI and finds the next
layout defect, not a different one each run.
"""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from spacearm import SpacearmError, presets

from test_array_layouts import METHODS

SETTINGS = settings(max_examples=150, derandomize=True, deadline=None, suppress_health_check=[HealthCheck.too_slow])

ROBOT = presets.spatial6()
WIDTH = {"x": ROBOT.nx, "u": ROBOT.nu, "du": ROBOT.nu, "f": ROBOT.nu, "tau": ROBOT.n_dof, "base_wrench": 6,
         "qd": ROBOT.n_dof, "P": 3, "L": 3}


def _values(name, rows, rng):
    """Valid values of argument `name`: `rows` rows, or one vector when `rows` is None."""
    shape = (WIDTH[name],) if rows is None else (rows, WIDTH[name])
    if name != "x":
        return rng.normal(size=shape)
    x = np.zeros(shape)
    quat = rng.normal(size=shape[:-1] + (4,))
    x[..., 3:7] = quat / np.linalg.norm(quat, axis=-1, keepdims=True)
    x[..., 0:3] = rng.normal(size=shape[:-1] + (3,))
    x[..., 7:] = rng.uniform(-1, 1, shape[:-1] + (ROBOT.n_dof,))
    return x


@st.composite
def layouts(draw, values, allow_other_dtypes):
    """`values` (float64) laid out in memory as drawn; returns the array handed to the call."""
    dtypes = ["<f8", ">f8"] + (["<f4", ">f4", "<i8", ">i4", "|u1", "|b1", "<f2"] if allow_other_dtypes else [])
    dtype = np.dtype(draw(st.sampled_from(dtypes)))
    # The first choice of each is what hypothesis tries first and shrinks towards: the layouts
    # that are easiest to misread (Fortran order, contiguous, at an odd byte offset).
    order = draw(st.sampled_from("FC"))
    steps = [draw(st.sampled_from([1, -1, 2, 3, -2])) for _ in range(values.ndim)]
    offset = draw(st.sampled_from([0, 1, 3, 8]))
    read_only = draw(st.booleans())
    typed = values.astype(dtype)
    big_shape = tuple(n * abs(s) for n, s in zip(values.shape, steps))
    count = int(np.prod(big_shape))
    buf = np.zeros(count * dtype.itemsize + offset, dtype=np.uint8)
    big = np.ndarray(big_shape, dtype=dtype, buffer=buf.data, offset=offset, order=order)
    view = big[tuple(slice(None, None, s) for s in steps)]
    view[...] = typed
    if read_only:
        view.setflags(write=False)
    return view


@st.composite
def calls(draw, allow_other_dtypes):
    method, names, keywords = draw(st.sampled_from(METHODS))
    rows = draw(st.sampled_from([5, 2, 1, None]))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    # Each argument one vector or `rows` rows (a one-vector argument is shared by every row).
    values = {k: _values(k, rows if (rows is not None and draw(st.booleans())) else None, rng) for k in names}
    if rows is not None and all(v.ndim == 1 for v in values.values()):
        values["x"] = _values("x", rows, rng)
    laid = {}
    for k, v in values.items():
        # x keeps float64 values: another dtype would round the quaternion off unit norm.
        laid[k] = draw(layouts(v, allow_other_dtypes and k != "x"))
    return method, names, keywords, laid


def _call(method, names, keywords, values):
    args = [values[k] for k in names if k not in keywords]
    kwargs = {k: values[k] for k in keywords}
    return getattr(ROBOT, method)(*args, **kwargs)


def _parts(result):
    return [np.asarray(p) for p in result] if isinstance(result, tuple) else [np.asarray(result)]


@SETTINGS
@given(calls(allow_other_dtypes=True))
def test_any_layout_and_real_dtype_equals_the_canonical_call(call):
    method, names, keywords, laid = call
    canonical = {k: np.array(v, dtype=np.float64, order="C") for k, v in laid.items()}
    expected = _parts(_call(method, names, keywords, canonical))
    got = _parts(_call(method, names, keywords, laid))
    for g, e in zip(got, expected):
        assert g.shape == e.shape
        assert np.array_equal(g, e), (method, {k: (v.dtype.str, v.strides, v.flags.aligned) for k, v in laid.items()})


BAD_KINDS = ["extra axis", "wrong width", "complex", "object", "strings", "ragged", "scalar", "datetime"]


def _bad(kind, good):
    if kind == "extra axis":
        return good[None, None]
    if kind == "wrong width":
        return good[..., :-1]
    if kind == "complex":
        return good + 1j
    if kind == "object":
        return good.astype(object)
    if kind == "strings":
        return good.astype(str)
    if kind == "ragged":
        return [list(good.ravel()), [1.0]]
    if kind == "scalar":
        return np.float64(1.0)
    return good.astype("datetime64[s]")


@SETTINGS
@given(calls(allow_other_dtypes=False), st.sampled_from(BAD_KINDS), st.data())
def test_an_invalid_array_is_a_spacearm_error(call, kind, data):
    method, names, keywords, laid = call
    victim = data.draw(st.sampled_from(names))
    laid = dict(laid)
    laid[victim] = _bad(kind, np.asarray(laid[victim], dtype=float))
    with pytest.raises(SpacearmError):
        _call(method, names, keywords, laid)
