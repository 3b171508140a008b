"""What a slosh model with few modes leaves out (issue 37 item 8; docs/flexibility.md, "What a
truncated model leaves out"): the fixed mass keeps the liquid's CM with the modes kept, so its
first moment m0·l0 = −Σ_kept m_n l_n differs from the all-modes −Σ_all m_n l_n. The numbers the
docs quote are computed here from the closed forms (Abramson 1966) summed over 2000 zeros of J1'
(scipy, independent of the core), after the core's one- and three-mode values are checked
against the same closed forms."""

from __future__ import annotations

import pathlib
import re

import numpy as np
import pytest

import spacearm

scipy_special = pytest.importorskip("scipy.special")

DOC = pathlib.Path(__file__).resolve().parents[2] / "docs" / "flexibility.md"
R = 0.4


def _closed_form(h: float, n_zeros: int = 2000):
    xi = scipy_special.jnp_zeros(1, n_zeros)
    m = 2.0 * np.tanh(xi * h / R) / (xi * (xi**2 - 1.0) * h / R)  # m_n / m_L
    ell = h / 2.0 - (2.0 * R / xi) * np.tanh(xi * h / (2.0 * R))
    return m, ell


def _paragraph() -> str:
    text = DOC.read_text(encoding="utf-8")
    start = text.index("**What a truncated model leaves out.**")
    return text[start:text.index("\n\n", start)]


@pytest.mark.parametrize("h, words", [(0.08, "smaller"), (0.4, "more")])
def test_one_and_three_modes_miss_the_documented_share_of_the_lateral_moment(h, words):
    m, ell = _closed_form(h)
    first_all = float(np.sum(m * ell))
    # the series has converged: the terms past the 400th change it by < 1e-5 of it
    assert abs(np.sum((m * ell)[400:])) < 1e-5 * abs(first_all)
    para = " ".join(_paragraph().split())
    for n in (1, 3):
        p = spacearm.slosh_parameters("cylinder", radius=R, fill_height=h, density=850.0, axial_acceleration=0.7, modes=n)
        model = p.fixed_mass * p.fixed_height / p.liquid_mass
        # the core's fixed part keeps the CM with the kept modes: m0 l0 = −Σ_kept m_n l_n
        np.testing.assert_allclose(model, -np.sum(m[:n] * ell[:n]), rtol=1e-12)
        share = -model / first_all - 1.0
        assert share != 0.0 and (share < 0) == (words == "smaller")
        digits = 1 if abs(share) > 0.01 else 2
        quoted = f"{abs(share) * 100:.{digits}f} %"
        assert quoted in para, f"docs/flexibility.md should quote {quoted} for h = {h} m, {n} mode(s)"


def test_a_spheres_one_mode_pitch_inertia_is_below_the_three_mode_one_as_documented():
    # No I0 for a sphere: the pitch inertia is that of the point masses about the liquid's CM.
    para = " ".join(_paragraph().split())
    low, high = (float(v) for v in re.search(r"pitch inertia of a one-mode model is ([\d.]+)–([\d.]+) %", para).groups())
    shares = []
    for frac in (0.25, 0.5, 0.75):
        inertia = []
        for n in (1, 3):
            p = spacearm.slosh_parameters("sphere", radius=R, fill_fraction=frac, density=850.0, axial_acceleration=0.7, modes=n)
            assert p.fixed_inertia is None
            ml = np.array([(q.mass, q.height) for q in p.modes])
            # the parts' total mass is the liquid's and their CM the liquid's (two checks of the split)
            np.testing.assert_allclose(ml[:, 0].sum() + p.fixed_mass, p.liquid_mass, rtol=1e-12)
            assert abs(ml[:, 0] @ ml[:, 1] + p.fixed_mass * p.fixed_height) < 1e-12 * p.liquid_mass * R
            inertia.append(ml[:, 0] @ ml[:, 1] ** 2 + p.fixed_mass * p.fixed_height**2)
        shares.append(1.0 - inertia[0] / inertia[1])
    assert all(s > 0 for s in shares)
    assert round(min(shares) * 100, 1) == low and round(max(shares) * 100, 0) == high
