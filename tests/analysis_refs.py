"""Independent references for the analysis tests: a SymPy derivation of the generalized Jacobian
of a two-link planar free-floating arm written here from first principles (not with
spacearm.symbolic), Pinocchio-built J*, J_m and zero-momentum base maps, and a NumPy RK4 of the
base pose driven by Pinocchio's mass matrix."""

from __future__ import annotations

import functools

import numpy as np

import spacearm
from spacearm import interop

# Two-link planar arm on a free-floating base (joint axes along z, links along x).
TWO_LINK = dict(m0=60.0, i0=4.0, a=0.5, l1=1.0, m1=6.0, l2=0.8, m2=4.0, w=0.05)


def _bar_izz(m, l, w):
    return m * (l * l + w * w) / 12.0


def two_link_planar() -> spacearm.Robot:
    p = TWO_LINK
    b = spacearm.RobotBuilder("two_link", p["m0"], [p["i0"]] * 3)
    for i, (l, m, parent, origin) in enumerate(((p["l1"], p["m1"], "base", p["a"]), (p["l2"], p["m2"], "link1", p["l1"] / 2))):
        izz = _bar_izz(m, l, p["w"])
        b.add_link(f"link{i + 1}", parent=parent, axis=(0, 0, 1), origin=(origin, 0, 0), com=(l / 2, 0, 0), mass=m,
                   inertia=[m * p["w"] ** 2 / 6, izz, izz])
    b.add_point("tip", body="link2", offset=(p["l2"] / 2, 0, 0))
    b.set_end_effector("tip")
    return b.build()


@functools.lru_cache(maxsize=None)
def sympy_two_link():
    """(J*(q1, q2) 2×2, det J*(q1, q2)) as NumPy functions, derived from the zero-momentum
    conditions with the base at zero attitude: linear momentum zero ⇒ system CM fixed (r0 solved
    from it); angular momentum about the CM L = A θ̇ + B q̇ = 0 ⇒ θ̇ = −B q̇ / A; EE velocity
    ∂r_E/∂q q̇ + ∂r_E/∂θ θ̇."""
    import sympy as sp

    p = TWO_LINK
    th, q1, q2 = sp.symbols("theta q1 q2", real=True)
    m0, m1, m2 = (sp.nsimplify(p[k]) for k in ("m0", "m1", "m2"))
    a, l1, l2, w = (sp.nsimplify(p[k]) for k in ("a", "l1", "l2", "w"))
    i0 = sp.nsimplify(p["i0"])
    i1 = m1 * (l1**2 + w**2) / 12
    i2 = m2 * (l2**2 + w**2) / 12
    ex = lambda ang: sp.Matrix([sp.cos(ang), sp.sin(ang)])  # noqa: E731
    # Positions relative to the base CM, then shifted so that the system CM is at the origin.
    rel1 = a * ex(th) + l1 / 2 * ex(th + q1)
    j2 = a * ex(th) + l1 * ex(th + q1)
    rel2 = j2 + l2 / 2 * ex(th + q1 + q2)
    rel_e = j2 + l2 * ex(th + q1 + q2)
    M = m0 + m1 + m2
    r0 = -(m1 * rel1 + m2 * rel2) / M
    bodies = [(m0, i0, r0, th), (m1, i1, r0 + rel1, th + q1), (m2, i2, r0 + rel2, th + q1 + q2)]
    coords = [th, q1, q2]
    # L = Σ m (r × ṙ)_z + I φ̇ — linear in (θ̇, q̇1, q̇2): collect the coefficients.
    coeff = [0, 0, 0]
    for m, inertia, r, phi in bodies:
        for k, c in enumerate(coords):
            dr = r.diff(c)
            coeff[k] += m * (r[0] * dr[1] - r[1] * dr[0]) + inertia * phi.diff(c)
    A, B = coeff[0], sp.Matrix([coeff[1], coeff[2]]).T
    r_e = r0 + rel_e
    jq = r_e.jacobian([q1, q2])
    jth = r_e.diff(th)
    jstar = (jq - jth * B / A).subs(th, 0)
    det = jstar.det()
    f_j = sp.lambdify((q1, q2), jstar, "numpy")
    f_det = sp.lambdify((q1, q2), det, "numpy")
    return (lambda u, v: np.array(f_j(u, v), dtype=float)), (lambda u, v: float(f_det(u, v)))


def bisect(f, lo, hi, tol=1e-14):
    flo = f(lo)
    assert flo * f(hi) < 0, "no sign change in the bracket"
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        fm = f(mid)
        if fm * flo > 0:
            lo, flo = mid, fm
        else:
            hi = mid
    return 0.5 * (lo + hi)


class PinRef:
    """Pinocchio-side J*, J_m and zero-momentum base twist map (spacearm conventions and order)."""

    def __init__(self, robot):
        import pinocchio as pin

        self.pin = pin
        self.robot = robot
        self.model = interop.to_pinocchio(robot)
        self.data = self.model.createData()
        self.order = interop.engine_dof_order(robot)

    def _cols(self, mat):
        out = np.empty_like(mat)
        out[:, self.order] = mat
        return out

    def maps(self, x, point=None):
        pin, r = self.pin, self.robot
        q, _ = interop.to_pinocchio_state(r, x, np.zeros(r.nu))
        m = pin.crba(self.model, self.data, q)
        m = np.triu(m) + np.triu(m, 1).T
        base_pin = -np.linalg.solve(m[:6, :6], m[:6, 6:])  # pin base velocity per joint rate
        pin.computeJointJacobians(self.model, self.data, q)
        pin.updateFramePlacements(self.model, self.data)
        name = point or r.end_effector
        jac = pin.getFrameJacobian(self.model, self.data, self.model.getFrameId(name), pin.LOCAL_WORLD_ALIGNED)
        jstar = self._cols(jac[:, 6:] + jac[:, :6] @ base_pin)
        jm = self._cols(jac[:, 6:])
        rot = interop.pinocchio_transform(r, x)[:3, :3]
        # Pinocchio's base velocity is [R0ᵀ ṗ; ω_local]: back to [v0; ω0] in the inertial frame.
        base = self._cols(np.vstack([rot @ base_pin[:3], rot @ base_pin[3:]]))
        return jstar, jm, base


def quat_mul(a, b):
    """Hamilton product of [x, y, z, w] quaternions."""
    av, aw, bv, bw = a[:3], a[3], b[:3], b[3]
    return np.r_[aw * bv + bw * av + np.cross(av, bv), aw * bw - av @ bv]


def pin_integrate_base(robot, x0, q_of_t, qd_of_t, t_end, steps):
    """RK4 of [r0, quat] with ẋ0 from Pinocchio's mass matrix (zero momentum) and the given
    joint motion; independent of spacearm's kinematics and momentum map."""
    ref = PinRef(robot)
    h = t_end / steps

    def rate(t, y):
        x = np.r_[y[:3], y[3:7] / np.linalg.norm(y[3:7]), q_of_t(t)]
        _, _, base = ref.maps(x)
        tw = base @ qd_of_t(t)
        dq = 0.5 * quat_mul(np.r_[tw[3:], 0.0], x[3:7])
        return np.r_[tw[:3], dq]

    y = np.array(x0[:7], dtype=float)
    for k in range(steps):
        t = k * h
        k1 = rate(t, y)
        k2 = rate(t + h / 2, y + h / 2 * k1)
        k3 = rate(t + h / 2, y + h / 2 * k2)
        k4 = rate(t + h, y + h * k3)
        y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        y[3:7] /= np.linalg.norm(y[3:7])
    return y
