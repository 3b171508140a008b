"""Admission control: requests too large for the machine are refused with a
``ResourceLimitError`` (a ``MemoryError`` and a ``SpacearmError``) that names the size and the
way out, before anything is allocated; a long chain builds and runs the O(N) algorithms without
the dense (6+N)² workspaces.

Every case runs in a child process whose address space is capped (``RLIMIT_AS``, 1.5 GiB): an
allocation of the sizes refused here (tens of GB to TB) would abort that process instead of
raising, and a model that still allocated its dense workspaces eagerly (3.2 GB at 20,000 links)
could not even be built. The reproductions are those of the hardening report.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

resource = pytest.importorskip("resource")

MEMORY_CAP = 3 << 29  # 1.5 GiB of address space for the child

CHILD = textwrap.dedent(r"""
    import json, resource, sys
    cap = int(sys.argv[1])
    resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
    import numpy as np
    import spacearm
    from spacearm import analysis
    from spacearm.io.model_file import loads_toml

    def chain(n):
        # A planar chain coiled by 3.6 degrees per joint (compact, well conditioned).
        parts = ['[model]\nname = "chain"\n[base]\nmass = 100.0\ninertia = [10.0, 10.0, 10.0]\n']
        for k in range(n):
            parent = "base" if k == 0 else f"l{k - 1}"
            parts.append(f'[[link]]\nname = "l{k}"\nparent = "{parent}"\ncom = [0.05, 0.0, 0.0]\nmass = 1.0\n'
                         'inertia = [0.01, 0.02, 0.02]\njoint = { type = "revolute", origin = [0.1, 0.0, 0.0], '
                         'rpy = [0.0, 0.0, 0.0628], axis = [0.0, 0.0, 1.0] }\n')
        return loads_toml("".join(parts), "chain.toml")

    def outcome(call):
        try:
            value = call()
        except spacearm.ResourceLimitError as exc:
            return {"refused": str(exc)}
        except Exception as exc:  # anything else is reported to the test, which fails on it
            return {"error": f"{type(exc).__name__}: {exc}"}
        return {"value": value}

    spatial6 = spacearm.presets.spatial6()
    long_chain = chain(20_000)
    x = long_chain.neutral_configuration()
    u = np.zeros(long_chain.nu)
    tau = np.zeros(long_chain.n_dof)
    tau[0] = 1.0
    mid_chain = chain(3_000)
    short_chain = chain(700)
    text_q = ('[model]\nname = "m"\ninitial_q = [' + ", ".join(["0.0"] * 10_000_000)
              + ']\n[base]\nmass = 100.0\ninertia = [10.0, 10.0, 10.0]\n')
    results = {
        "dopri5 dt=1e-9": outcome(lambda: spacearm.simulate(spatial6, 1.0, integrator="dopri5", dt=1e-9)),
        "dopri5 100 s dt=1e-6": outcome(lambda: spacearm.simulate(spatial6, 100.0, integrator="dopri5", dt=1e-6)),
        "rk4 100 s dt=1e-6": outcome(lambda: spacearm.simulate(spatial6, 100.0, dt=1e-6)),
        "aba 20000 links": outcome(lambda: float(long_chain.forward_dynamics(x, u, tau=tau)[6])),
        "crba 20000 links": outcome(lambda: long_chain.mass_matrix(x).shape),
        "J* 20000 links": outcome(lambda: long_chain.generalized_jacobian(x, point=(long_chain.n_bodies - 1, [0.0, 0.0, 0.0])).shape),
        "paper form 3000 links": outcome(lambda: mid_chain.mass_matrix(mid_chain.neutral_configuration(),
                                                                       method="paper").shape),
        "partials 700 links": outcome(lambda: short_chain.mass_matrix_partials(short_chain.neutral_configuration()).shape),
        "initial_q 1e7": outcome(lambda: loads_toml(text_q, "q.toml").n_dof),
        "grid 10^12": outcome(lambda: analysis.workspace(spacearm.presets.dual_arm(), resolution=10)),
        "peak MB": {"value": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024},
    }
    print(json.dumps(results))
""")


@pytest.fixture(scope="module")
def results():
    out = subprocess.run([sys.executable, "-c", CHILD, str(MEMORY_CAP)], capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-3000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("case, size, remedy", [
    ("dopri5 dt=1e-9", "TB", "coarser output grid"),
    ("dopri5 100 s dt=1e-6", "GB", "coarser output grid"),
    ("rk4 100 s dt=1e-6", "GB", "record_every"),
    ("crba 20000 links", "GB", "ABA"),
    ("J* 20000 links", "GB", "ABA"),
    ("paper form 3000 links", "multiply-adds", "crba"),
    ("partials 700 links", "GB", "mass_matrix_derivative"),
    ("initial_q 1e7", "GB", "model file"),
    ("grid 10^12", "B", "lower the resolution"),
])
def test_oversize_requests_are_refused_with_size_and_way_out(results, case, size, remedy):
    outcome = results[case]
    assert "refused" in outcome, outcome
    message = outcome["refused"]
    assert size in message and remedy in message, message


def test_long_chain_runs_aba_in_linear_memory(results):
    # From rest, with only tau_1 applied, qdd = H*^-1 tau: the first joint accelerates with the
    # sign of its torque (H*^-1 is positive definite).
    outcome = results["aba 20000 links"]
    assert "value" in outcome, outcome
    assert outcome["value"] > 0.0
    # Everything above ran under the 1.5 GiB cap; the dense H alone would be 3.2 GB.
    assert results["peak MB"]["value"] < MEMORY_CAP / 2**20
