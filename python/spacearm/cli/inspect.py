"""``spacearm inspect MODEL [--q Q1,Q2,...]``: the model summary (bodies, joints, total mass),
the passive joints and joint springs with the natural frequencies of their small oscillations
about the configuration (``Robot.natural_frequencies``, docs/flexibility.md) and, at the given
or initial configuration, ``H0``, ``H*`` and the end-effector ``J*`` with their conditioning.
Registered in ``spacearm.cli``.

Above ``FULL_REPORT_MAX_DOF`` joints the dense part is left out: printing the N×N ``H*``
and taking SVDs of it costs O(N²) text and O(N³) time (a 10,000-joint model took more than five
minutes), so a large model gets its summary table and ``H0`` (from the closed-form ``H0⁻¹`` of
eqs. 52–61, O(N)) with a line saying how to get the rest from Python.
"""

from __future__ import annotations

import sys

import numpy as np

from .model_options import add_model_arguments, joint_values
from ..model.robot import Robot

__all__ = ["add_parser", "run", "inspect", "FULL_REPORT_MAX_DOF"]

#: Models with more joints than this get the summary and ``H0`` only (module docstring).
FULL_REPORT_MAX_DOF = 50


def add_parser(sub) -> None:
    p = sub.add_parser("inspect", help="print a model summary and H0, H*, J* at a configuration")
    add_model_arguments(p)
    p.add_argument("--q", metavar="Q1,Q2,...", help="joint coordinates, one per joint (rad, or m for prismatic "
                                                    "joints; default: the model's initial q)")


def run(args, model_from_args) -> None:
    """Run ``spacearm inspect`` with parsed ``args``."""
    robot = model_from_args(args)
    inspect(robot, None if args.q is None else joint_values(args.q, "--q", robot))


def _matrix(name: str, m: np.ndarray, unit: str) -> str:
    rows = [f"{name}  [{unit}]  ({m.shape[0]}x{m.shape[1]})"]
    for row in m:
        # Adding 0.0 turns IEEE negative zeros into plain zeros for display.
        rows.append("  " + " ".join(f"{v + 0.0:11.4g}" for v in row))
    return "\n".join(rows)


def _conditioning(name: str, m: np.ndarray) -> str:
    s = np.linalg.svd(m, compute_uv=False)
    cond = s[0] / s[-1] if s[-1] > 0 else np.inf
    return f"  {name}: singular values [{', '.join(f'{v:.4g}' for v in s)}], condition number {cond:.4g}"


def _passive(robot: Robot, x, w) -> None:
    """The passive joints and joint springs, and the natural frequencies of their small
    oscillations at ``x`` with the actuated joints held (docs/flexibility.md)."""
    sprung = [link for link in robot.description.links if link.type != "fixed"
              and (not link.actuated or link.stiffness > 0 or link.damping > 0)]
    if not sprung:
        return
    w("passive joints and joint springs (stiffness N m/rad or N/m, damping N m s/rad or N s/m, rest rad or m):\n")
    for link in sprung:
        w(f"  {link.joint}: {'actuated' if link.actuated else 'passive'}, stiffness {link.stiffness:.6g}, "
          f"damping {link.damping:.6g}, rest {link.rest:.6g}\n")
    if not robot.actuated_dofs.all() and robot.n_dof <= FULL_REPORT_MAX_DOF:
        modes = robot.natural_frequencies(x, actuated="held")
        w("natural frequencies of the passive joints at this configuration, actuated joints held:\n")
        names = [link.joint for link in robot.description.links if link.type != "fixed"]
        for i, (omega, zeta) in enumerate(zip(modes.frequencies, modes.damping_ratios)):
            shape = modes.shapes[:, i]
            main = names[int(np.argmax(np.abs(shape)))]
            w(f"  mode {i + 1}: {omega:.6g} rad/s = {omega / (2 * np.pi):.6g} Hz, damping ratio {zeta:.4g}, mostly {main}\n")
    w("\n")


def _cmgs(robot: Robot, w) -> None:
    """The control-moment gyros the core recognizes (docs/cmg.md): dofs, axes, rotor, limits."""
    cmgs = robot.cmg_dofs
    if not cmgs:
        return
    w("control-moment gyros (axes in the parent frame at zero gimbal angle; rotor speed is the run's u0):\n")
    vec = (lambda v: "[" + ", ".join(f"{x:.3g}" for x in v) + "]")
    for name, c in cmgs.items():
        kind = "VSCMG (spin motor)" if c["variable_speed"] else "SGCMG (free rotor)"
        w(f"  {name}: {kind}, gimbal dof {c['gimbal']} about {vec(c['gimbal_axis'])}, rotor dof {c['rotor']} "
          f"spinning about {vec(c['spin_axis'])}, J_s {c['rotor_inertia']:.6g} kg m^2, "
          f"max gimbal rate {c['max_gimbal_rate']:.6g} rad/s, max wheel speed {c['max_wheel_speed']:.6g} rad/s\n")
    w("\n")


def _grippers(robot: Robot, w) -> None:
    """The grippers the core recognizes (docs/contact.md, "Grippers"): palm, finger joints."""
    from .. import _core

    grippers = _core.grippers(robot.core_model)
    if not grippers:
        return
    w("grippers (fingers along the palm's +z; joint value 0 = open):\n")
    for g in grippers:
        w(f"  {g['name']}: {len(g['finger_dofs'])} {g['kind']} fingers, dofs {list(g['finger_dofs'])}\n")
    w("\n")


def inspect(robot: Robot, q=None, out=None) -> None:
    """Print the model summary and the GJM quantities at ``q`` (default: initial angles)."""
    # Resolve the stream at call time, not at import time, so redirections of sys.stdout count.
    out = sys.stdout if out is None else out
    d = robot.description
    w = out.write
    w(f"model '{robot.name}': {robot.n_bodies} bodies, N = {robot.n_dof} joint DOF, total mass {robot.total_mass:.6g} kg\n\n")
    rows = [(d.base.name, "-", "-", "free", "-", d.base.mass)]
    for link in d.links:
        axis = "-" if link.type == "fixed" else "[" + ", ".join(f"{v:.3g}" for v in link.axis) + "]"
        rows.append((link.name, link.parent, link.joint, link.type, axis, link.mass))
    # Columns as wide as their longest name (URDF names such as 'shoulder_pan_joint' are long).
    widths = [max(16, 2 + max(len(r[k]) for r in rows)) for k in range(3)]
    w(f"{'body':<{widths[0]}}{'parent':<{widths[1]}}{'joint':<{widths[2]}}{'type':<10}{'axis (link frame)':<26}{'mass kg':>9}\n")
    for name, parent, joint, kind, axis, mass in rows:
        w(f"{name:<{widths[0]}}{parent:<{widths[1]}}{joint:<{widths[2]}}{kind:<10}{axis:<26}{mass:>9.4g}\n")
    if d.points:
        w("\npoints: " + ", ".join(f"{p.name} on {p.body} at [{', '.join(f'{v:.4g}' for v in p.offset)}]" for p in d.points))
        w(f"   (end effector: {robot.end_effector})\n")
    x = robot.neutral_configuration(q)
    qs = ", ".join(f"{v:.4g}" for v in x[7:])
    w(f"\nconfiguration: base at the origin aligned with the inertial frame, q = [{qs}]\n\n")
    _cmgs(robot, w)
    _grippers(robot, w)
    _passive(robot, x, w)
    np.set_printoptions(linewidth=160)
    if robot.n_dof > FULL_REPORT_MAX_DOF:
        h0 = np.linalg.inv(robot.base_inertia_inverse(x))
        h0 = 0.5 * (h0 + h0.T)
        w(_matrix("H0 (base inertia, eq. 30; inverse of the closed-form H0^-1, eqs. 52-61)", h0,
                  "kg | kg m | kg m^2 blocks") + "\n\n")
        w(f"H* ({robot.n_dof}x{robot.n_dof}) and J* are not printed for models of more than {FULL_REPORT_MAX_DOF} joints; "
          "in Python: robot.generalized_inertia(x), robot.generalized_jacobian(x)\n\n")
        w("conditioning:\n")
        w(_conditioning("H0", h0) + "\n")
        return
    h0 = robot.inertia_blocks(x).H0
    w(_matrix("H0 (base inertia, eq. 30)", h0, "kg | kg m | kg m^2 blocks") + "\n\n")
    if robot.n_dof > 0:
        hs = robot.generalized_inertia(x)
        w(_matrix("H* (generalized inertia, eq. 45)", hs, "kg m^2 between revolute joints") + "\n\n")
    if robot.end_effector is not None and robot.n_dof > 0:
        js = robot.generalized_jacobian(x)
        w(_matrix(f"J* of '{robot.end_effector}' (generalized Jacobian, eq. 110)", js, "linear rows m/rad, angular rows 1") + "\n")
        p = robot.point_position(x)
        w(f"  end-effector position: [{', '.join(f'{v:.6g}' for v in p)}] m\n\n")
    elif robot.n_dof > 0:
        parents = {link.parent for link in d.links}
        leaves = [link.name for link in d.links if link.name not in parents]
        w(f"J* (generalized Jacobian, eq. 110): not computed, '{robot.name}' has no end effector; its chain has "
          f"{len(leaves)} {'leaf' if len(leaves) == 1 else 'leaves'} ({', '.join(leaves)}): name the point to use with "
          "--end-effector POINT|LINK\n\n")
    w("conditioning:\n")
    w(_conditioning("H0", h0) + "\n")
    if robot.n_dof > 0:
        w(_conditioning("H*", hs) + "\n")
        if robot.end_effector is not None:
            w(_conditioning("J*", js) + "\n")
            _, jm = robot.point_jacobian(x)
            w(_conditioning("J_m (fixed-base Jacobian, for comparison)", jm) + "\n")
