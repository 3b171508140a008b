"""With compliant joints the tracking error of a joint-space controller is the motors'
(|q_ref − θ|) while the links deflect; the core records the links' error too,
``link_tracking_error`` = |q_ref − (θ + δ)| (issue 37 item 5d; docs/flexibility.md).

Closed form: on a clamped base, a PD motor following a reference of constant acceleration α
settles into a motion where motor and link turn together at α: the link's spring carries the
link's torque, k δ = −I α (I its inertia about the axis: δ = −I α / k, the link lags), and the PD
the whole torque, kp (q_ref − θ) = (J + I) α (J the rotor's). The link's error is then the
motor's plus the lag, (J + I) α / kp + I α / k.
"""

from __future__ import annotations

import numpy as np
import pytest

import spacearm


def _arm(k=40.0, damping=2.0):
    """A clamped base (1e12 kg), one rigid actuated joint about y, then a compliant joint about z."""
    b = spacearm.Robot.builder("compliant", base_mass=1e12, base_inertia=[1e12, 1e12, 1e12])
    b.add_link("a1", joint="revolute", axis=(0, 1, 0), origin=(0.2, 0, 0), com=(0.3, 0, 0), mass=1.0,
               inertia=[0.01, 0.05, 0.05])
    b.add_link("a2", parent="a1", joint="revolute", axis=(0, 0, 1), origin=(0.4, 0, 0), com=(0.5, 0, 0), mass=2.0,
               inertia=[0.01, 0.2, 0.2], compliant={"stiffness": k, "rotor_inertia": 0.05, "damping": damping})
    return b.build()


def test_link_error_is_the_motor_error_plus_the_steady_deflection():
    k, kp, kd, alpha, duration = 40.0, 200.0, 40.0, 0.5, 20.0
    robot = _arm(k)
    assert robot.joint_names == ["a1_joint", "a2_joint", "a2_joint_deflection"]
    i_link = 0.2 + 2.0 * 0.5**2  # a2 about its joint axis
    j_rotor = 0.05
    # The actuated joints a1_joint (held at 0.1) and a2_joint (q = α t² / 2): a quintic Hermite
    # through two knots is this quadratic exactly.
    ref = spacearm.control.SampledJoint(t=[0.0, duration], q=[[0.1, 0.0], [0.1, alpha * duration**2 / 2]],
                                        qd=[[0.0, 0.0], [0.0, alpha * duration]], qdd=[[0.0, alpha], [0.0, alpha]])
    traj = spacearm.simulate(robot, duration, x0=robot.neutral_configuration(q=[0.1, 0.0, 0.0]), dt=2e-3,
                             controller=spacearm.control.JointPD(kp=kp, kd=kd, reference=ref))
    delta = traj.q[:, 2]
    # The closed form (the transient has decayed by e^-28): the deflection from the link's
    # equation, the motor's error from the PD's.
    assert delta[-1] == pytest.approx(-i_link * alpha / k, rel=1e-6)
    motor_error = (j_rotor + i_link) * alpha / kp
    assert traj.tracking_error[-1] == pytest.approx(motor_error, rel=1e-6)
    assert traj.link_tracking_error[-1] == pytest.approx(motor_error + i_link * alpha / k, rel=1e-6)
    q_ref = traj.reference
    # At every sample: the recorded errors from the recorded angles (the rigid joint counts in
    # both, with its own angle).
    q = traj.q
    motor = np.hypot(q_ref[:, 0] - q[:, 0], q_ref[:, 1] - q[:, 1])
    link = np.hypot(q_ref[:, 0] - q[:, 0], q_ref[:, 1] - q[:, 1] - q[:, 2])
    np.testing.assert_allclose(traj.tracking_error, motor, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(traj.link_tracking_error, link, rtol=1e-12, atol=1e-15)
    assert np.max(np.abs(link - motor)) > 5e-3  # the two differ by the deflection
    # The summary, the CSV and the figure carry both.
    assert "link tracking error (motor + deflection)" in traj.summary()
    assert "link_tracking_error" in [c[0] for c in traj.columns()]
    ax = [a for a in traj.plot().axes if a.get_title().startswith("tracking error")][0]
    labels = [line.get_label() for line in ax.get_lines()]
    assert labels == ["motors (θ)", "links (θ + δ)"]
    np.testing.assert_array_equal(ax.get_lines()[1].get_ydata(), traj.link_tracking_error)


def test_no_link_error_without_a_compliant_joint_or_a_joint_controller():
    rigid = spacearm.presets.planar4()
    tr = spacearm.simulate(rigid, 0.01, dt=1e-3, controller=spacearm.control.JointPD(kp=1.0, kd=1.0, reference=[0.0] * 4))
    assert tr.has("tracking_error") and not tr.has("link_tracking_error")
    robot = _arm()
    tr = spacearm.simulate(robot, 0.01, dt=1e-3)  # no controller
    assert not tr.has("link_tracking_error")
    with pytest.raises(spacearm.NotFoundError, match="no compliant joint"):
        tr.link_tracking_error
