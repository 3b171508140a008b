"""Draw the Kane–Ryan–Banerjee spin-up figure of docs/flexibility.md and print the beam
convergence tables (about a minute):

    python docs/figures/make_beam_figures.py

The beam (L = 10 m, EI = 1.4e4 N m², ρA = 1.2 kg/m) on a hub spun up to 6 rad/s over 15 s,
the hub's motion prescribed: spacearm's rigid-finite-element chain (N = 4, 12) against the
assumed-modes reference with geometric stiffening and the same model without it (which
diverges). The simulations are the validation test's own (tests/model/test_appendages.py), so
the figure shows what CI checks.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
OUT = HERE / "flexibility_krb_spinup.png"
spec = importlib.util.spec_from_file_location("test_appendages", HERE.parents[1] / "tests" / "model" / "test_appendages.py")
t = importlib.util.module_from_spec(spec)
spec.loader.exec_module(t)


def main() -> None:
    want = t.BETA1**2 * np.sqrt(t.EI / (t.RHO_A * t.L**4))
    print("| N | ω₁ (rad/s) | error |")
    print("| --- | --- | --- |")
    for n in (2, 4, 8, 16, 32):
        w = t.cantilever(n).natural_frequencies().frequencies[0]
        print(f"| {n} | {w:.5f} | {(w - want) / want:+.2e} |")
    print(f"| Euler–Bernoulli | {want:.5f} | |")

    times = np.linspace(0, t.T_END, 401)
    ref = t.krb_assumed_modes(times)
    lin = t.krb_assumed_modes(times, stiffening=False)
    print("\n| N | peak tip deflection (m) | at t (s) | max deviation from reference / peak |")
    print("| --- | --- | --- | --- |")
    runs = {}
    for n in (2, 4, 8, 12):
        tip = t.krb_spacearm(n, times)
        runs[n] = tip
        k = int(np.argmin(tip))
        print(f"| {n} | {tip[k]:.4f} | {times[k]:.2f} | {np.max(np.abs(tip - ref)) / np.max(np.abs(ref)):.2e} |")
    k = int(np.argmin(ref))
    print(f"| assumed modes (3 modes of 6 trial functions, stiffened) | {ref[k]:.4f} | {times[k]:.2f} | |")

    fig, ax = plt.subplots(figsize=(7.5, 4.0), constrained_layout=True)
    ax.plot(times, ref, "k-", lw=2.5, label="assumed modes with geometric stiffening (reference)")
    ax.plot(times, runs[4], "C1--", label="spacearm RFEM, N = 4")
    ax.plot(times, runs[12], "C0-", lw=1.2, label="spacearm RFEM, N = 12")
    cut = np.abs(lin) < 2.0
    ax.plot(times[cut], lin[cut], "C3:", lw=2, label="assumed modes without stiffening (diverges)")
    ax.axvline(t.T_UP, color="0.6", lw=0.8)
    ax.set_ylim(-1.5, 1.0)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("tip deflection in the hub frame (m)")
    ax.set_title("Kane–Ryan–Banerjee spin-up beam: Ω → 6 rad/s over 15 s")
    ax.legend(loc="lower left", fontsize=8)
    fig.savefig(OUT, dpi=110)
    print("wrote", OUT)


if __name__ == "__main__":
    main()
