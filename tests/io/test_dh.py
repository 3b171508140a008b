"""Denavit–Hartenberg constructors (spacearm.io.dh, docs/dh.md), checked independently:

* end-effector and link-frame poses against the standard DH homogeneous-transform product
  computed here with numpy;
* mass matrices against the presets (planar4, and spatial6 re-expressed in DH frames with its
  inertias rotated here), to 1e-12;
* mass matrices of random tables (revolute and prismatic) against Pinocchio models built
  directly from the DH transforms.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import spacearm
from spacearm import presets
from spacearm.io import model_file
from spacearm.io.dh import robot_from_dh
from spacearm.rotations import quat_from_matrix, quat_to_matrix

PI = math.pi


# ---- the textbook DH transform ---------------------------------------------------------------


def dh_matrix(d, theta, a, alpha):
    """Classic DH: Rot_z(theta) Trans_z(d) Trans_x(a) Rot_x(alpha)."""
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    return np.array([
        [ct, -st * ca, st * sa, a * ct],
        [st, ct * ca, -ct * sa, a * st],
        [0.0, sa, ca, d],
        [0.0, 0.0, 0.0, 1.0],
    ])


def homogeneous(rot, pos):
    t = np.eye(4)
    t[:3, :3] = rot
    t[:3, 3] = pos
    return t


def dh_frames(table, q, types, t0):
    """World poses of DH frames 0..N for joint values q."""
    frames = [t0]
    for (d, theta, a, alpha), qi, kind in zip(table, q, types):
        if kind == "revolute":
            theta = theta + qi
        elif kind == "prismatic":
            d = d + qi
        frames.append(frames[-1] @ dh_matrix(d, theta, a, alpha))
    return frames


def random_quat(rng):
    v = rng.normal(size=4)
    return v / np.linalg.norm(v)


def configuration(robot, rng, base_pose=True):
    r0 = rng.normal(size=3) if base_pose else np.zeros(3)
    quat = random_quat(rng) if base_pose else np.array([0.0, 0.0, 0.0, 1.0])
    return robot.neutral_configuration(q=rng.uniform(-PI, PI, robot.n_dof), r0=r0, quat0=quat)


def bar(m, length, w):
    iyy = m * (length * length + w * w) / 12.0
    return np.diag([m * w * w / 6.0, iyy, iyy])


# ---- planar4 -----------------------------------------------------------------------------------


def planar4_classic(**kw):
    rows = [dict(d=0.0, theta=0.0, a=1.0, alpha=0.0, com=(-0.5, 0.0, 0.0), mass=10.0, inertia=bar(10.0, 1.0, 0.05))] * 4
    return robot_from_dh("planar4", rows, base_mass=100.0, base_inertia=[4.1667] * 3, joint1_origin=(0.25, 0, 0), **kw)


def test_classic_planar4_has_the_mass_matrix_of_the_preset():
    rng = np.random.default_rng(1)
    dh, preset = planar4_classic(), presets.planar4()
    assert dh.n_dof == 4 and dh.end_effector == "end_effector"
    for _ in range(20):
        x = configuration(preset, rng)
        np.testing.assert_allclose(dh.mass_matrix(x), preset.mass_matrix(x), rtol=0, atol=1e-12)
        np.testing.assert_allclose(dh.point_position(x), preset.point_position(x), rtol=0, atol=1e-12)


def test_classic_planar4_tip_is_the_dh_product():
    rng = np.random.default_rng(2)
    robot = planar4_classic()
    table = [(0.0, 0.0, 1.0, 0.0)] * 4
    for _ in range(20):
        x = configuration(robot, rng)
        t0 = homogeneous(quat_to_matrix(x[3:7]), x[:3]) @ homogeneous(np.eye(3), [0.25, 0, 0])
        tip = dh_frames(table, x[7:], ["revolute"] * 4, t0)[-1][:3, 3]
        np.testing.assert_allclose(robot.point_position(x), tip, rtol=0, atol=1e-12)


def test_paper_planar4_has_the_mass_matrix_of_the_preset():
    rng = np.random.default_rng(3)
    rows = [dict(joint_to_com=(0.5, 0, 0), com_to_next=(0.5, 0, 0), mass=10.0, inertia=bar(10.0, 1.0, 0.05))] * 4
    dh = robot_from_dh("planar4", rows, convention="paper", base_mass=100.0, base_inertia=[4.1667] * 3,
                       joint1_origin=(0.25, 0, 0))
    preset = presets.planar4()
    for _ in range(10):
        x = configuration(preset, rng)
        np.testing.assert_allclose(dh.mass_matrix(x), preset.mass_matrix(x), rtol=0, atol=1e-12)
        np.testing.assert_allclose(dh.point_position(x), preset.point_position(x), rtol=0, atol=1e-12)


# ---- spatial6 expressed in DH ---------------------------------------------------------------------

# Joint axes x, y, y, x, y, x of the preset, all pointing along +x from the base at q = 0.
# Classic DH table (derived by hand in docs/dh.md's spirit: z_{i-1} on joint i, x_i along the
# common normal), frame 0 with x0 = +z_base, z0 = +x_base, origin at joint 1:
SPATIAL6_DH = [  # (d, theta, a, alpha)
    (0.2, 0.0, 0.0, PI / 2),
    (0.0, PI / 2, 1.0, 0.0),
    (0.0, PI / 2, 0.0, PI / 2),
    (1.15, PI, 0.0, PI / 2),
    (0.0, PI, 0.0, PI / 2),
    (0.35, 0.0, 0.0, 0.0),
]
SPATIAL6_R0 = np.array([[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]])  # columns x0, y0, z0
SPATIAL6_J1 = np.array([0.6, 0.0, 0.0])
SPATIAL6_LENGTHS = [0.2, 1.0, 1.0, 0.15, 0.15, 0.2]
SPATIAL6_MASSES = [8.0, 15.0, 12.0, 4.0, 3.0, 3.0]


def spatial6_geometry():
    """At q = 0 (the preset's frames are all aligned with the base): joint positions,
    link CMs, and the DH frames from the numpy product."""
    starts = 0.6 + np.concatenate([[0.0], np.cumsum(SPATIAL6_LENGTHS)])
    joints = [np.array([s, 0.0, 0.0]) for s in starts]  # joint 1..6 and the tip
    coms = [np.array([s + length / 2, 0.0, 0.0]) for s, length in zip(starts, SPATIAL6_LENGTHS)]
    frames = dh_frames(SPATIAL6_DH, np.zeros(6), ["revolute"] * 6, homogeneous(SPATIAL6_R0, SPATIAL6_J1))
    return joints, coms, frames


def test_spatial6_dh_table_describes_the_preset_axes():
    joints, _, frames = spatial6_geometry()
    preset_axes = [(1, 0, 0), (0, 1, 0), (0, 1, 0), (1, 0, 0), (0, 1, 0), (1, 0, 0)]
    for i, axis in enumerate(preset_axes):
        # Joint i+1 turns about z_i, which passes through the joint.
        np.testing.assert_allclose(frames[i][:3, 2], axis, atol=1e-15)
        off = joints[i] - frames[i][:3, 3]
        np.testing.assert_allclose(np.cross(off, axis), 0.0, atol=1e-15)
    np.testing.assert_allclose(frames[6][:3, 3], joints[6], atol=1e-15)


def spatial6_rows(convention):
    joints, coms, frames = spatial6_geometry()
    rows = []
    for i, ((d, theta, a, alpha), m, length) in enumerate(zip(SPATIAL6_DH, SPATIAL6_MASSES, SPATIAL6_LENGTHS)):
        r_i = frames[i + 1][:3, :3]  # DH frame i+1 (link i+1) at q = 0
        inertia = r_i.T @ bar(m, length, 0.1) @ r_i  # the preset's inertia is in base-aligned axes
        if convention == "classic":
            com = r_i.T @ (coms[i] - frames[i + 1][:3, 3])
            rows.append(dict(d=d, theta=theta, a=a, alpha=alpha, com=com, mass=m, inertia=inertia))
        else:
            rows.append(dict(theta=theta, alpha=alpha, joint_to_com=r_i.T @ (coms[i] - joints[i]),
                             com_to_next=r_i.T @ (joints[i + 1] - coms[i]), mass=m, inertia=inertia))
    return rows


@pytest.mark.parametrize("convention", ["classic", "paper"])
def test_spatial6_in_dh_has_the_mass_matrix_of_the_preset(convention):
    rng = np.random.default_rng(4)
    dh = robot_from_dh("spatial6", spatial6_rows(convention), convention=convention, base_mass=500.0,
                       base_inertia=[68.33, 86.67, 101.67], joint1_origin=SPATIAL6_J1,
                       joint1_rotation=quat_from_matrix(SPATIAL6_R0))
    preset = presets.spatial6()
    for _ in range(20):
        x = configuration(preset, rng)
        np.testing.assert_allclose(dh.mass_matrix(x), preset.mass_matrix(x), rtol=0, atol=1e-12)
        np.testing.assert_allclose(dh.point_position(x), preset.point_position(x), rtol=0, atol=1e-12)
        np.testing.assert_allclose(dh.generalized_jacobian(x), preset.generalized_jacobian(x), rtol=0, atol=1e-12)


def test_spatial6_link_frames_are_the_dh_frames():
    rng = np.random.default_rng(5)
    dh = robot_from_dh("spatial6", spatial6_rows("classic"), base_mass=500.0, base_inertia=[68.33, 86.67, 101.67],
                       joint1_origin=SPATIAL6_J1, joint1_rotation=quat_from_matrix(SPATIAL6_R0))
    for _ in range(10):
        x = configuration(dh, rng)
        t0 = homogeneous(quat_to_matrix(x[3:7]), x[:3]) @ homogeneous(SPATIAL6_R0, SPATIAL6_J1)
        frames = dh_frames(SPATIAL6_DH, x[7:], ["revolute"] * 6, t0)
        kin = dh.forward_kinematics(x)
        for i in range(1, 7):
            np.testing.assert_allclose(kin.body_to_world[i], frames[i][:3, :3], rtol=0, atol=1e-12)
        np.testing.assert_allclose(dh.point_position(x), frames[6][:3, 3], rtol=0, atol=1e-12)


# ---- random tables against the DH product and Pinocchio ------------------------------------------


def random_physical_inertia(rng, m):
    a, b, c = rng.uniform(0.05, 1.0, 3)
    d = np.diag([m * (b * b + c * c), m * (a * a + c * c), m * (a * a + b * b)]) / 12.0
    r = quat_to_matrix(random_quat(rng))
    i = r @ d @ r.T
    return (i + i.T) / 2


def random_table(rng, n):
    rows, table, types = [], [], []
    for _ in range(n):
        kind = "prismatic" if rng.random() < 0.3 else "revolute"
        d, theta, a, alpha = rng.uniform(-0.5, 0.5), rng.uniform(-PI, PI), rng.uniform(-0.5, 0.8), rng.uniform(-PI, PI)
        m = rng.uniform(0.5, 10.0)
        rows.append(dict(type=kind, d=d, theta=theta, a=a, alpha=alpha, com=rng.normal(scale=0.2, size=3), mass=m,
                         inertia=random_physical_inertia(rng, m)))
        table.append((d, theta, a, alpha))
        types.append(kind)
    return rows, table, types


@pytest.mark.parametrize("seed", range(5))
def test_random_classic_tables_match_the_dh_product(seed):
    rng = np.random.default_rng(100 + seed)
    rows, table, types = random_table(rng, 5)
    origin, quat, tool = rng.normal(size=3), random_quat(rng), rng.normal(scale=0.1, size=3)
    robot = robot_from_dh("r", rows, base_mass=80.0, base_inertia=[5.0, 6.0, 7.0], joint1_origin=origin,
                          joint1_rotation=quat, tool_offset=tool)
    for _ in range(5):
        x = configuration(robot, rng)
        t0 = homogeneous(quat_to_matrix(x[3:7]), x[:3]) @ homogeneous(quat_to_matrix(quat), origin)
        frames = dh_frames(table, x[7:], types, t0)
        np.testing.assert_allclose(robot.point_position(x), frames[-1][:3, :3] @ tool + frames[-1][:3, 3], atol=1e-12)
        kin = robot.forward_kinematics(x)
        for i, row in enumerate(rows, start=1):
            np.testing.assert_allclose(kin.body_to_world[i], frames[i][:3, :3], atol=1e-12)
            np.testing.assert_allclose(kin.com_in_world[i], frames[i][:3, :3] @ row["com"] + frames[i][:3, 3], atol=1e-12)


def pinocchio_from_dh(pin, rows, table, types, base_mass, base_inertia, origin, quat):
    """A Pinocchio model built straight from the DH transforms: joint i sits in DH frame i-1
    (turning about or sliding along its z), link i's inertia is carried by joint i through the
    constant transform from the joint frame to DH frame i."""
    model = pin.Model()
    base = model.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "base")
    model.appendBodyToJoint(base, pin.Inertia(base_mass, np.zeros(3), np.diag(base_inertia)), pin.SE3.Identity())
    parent, placement = base, pin.SE3(quat_to_matrix(quat), np.asarray(origin))
    for k, (row, (d, theta, a, alpha), kind) in enumerate(zip(rows, table, types)):
        jm = pin.JointModelRZ() if kind == "revolute" else pin.JointModelPZ()
        jid = model.addJoint(parent, jm, placement, f"j{k}")
        t = dh_matrix(d, theta, a, alpha)  # joint frame -> DH frame i (at q = 0)
        rot, pos = t[:3, :3], t[:3, 3]
        inertia = pin.Inertia(row["mass"], pos + rot @ row["com"], rot @ row["inertia"] @ rot.T)
        model.appendBodyToJoint(jid, inertia, pin.SE3.Identity())
        parent, placement = jid, pin.SE3(rot, pos)
    model.gravity.linear[:] = 0.0
    return model


@pytest.mark.parametrize("seed", range(4))
def test_random_classic_tables_match_pinocchio(seed):
    pin = pytest.importorskip("pinocchio")
    rng = np.random.default_rng(200 + seed)
    rows, table, types = random_table(rng, 4)
    origin, quat = rng.normal(size=3), random_quat(rng)
    base_inertia = [5.0, 6.0, 7.0]
    robot = robot_from_dh("r", rows, base_mass=80.0, base_inertia=base_inertia, joint1_origin=origin,
                          joint1_rotation=quat)
    model = pinocchio_from_dh(pin, rows, table, types, 80.0, base_inertia, origin, quat)
    data = model.createData()
    for _ in range(5):
        x = configuration(robot, rng)
        m = pin.crba(model, data, x)
        m = np.triu(m) + np.triu(m, 1).T
        r0 = quat_to_matrix(x[3:7])
        t = np.eye(robot.nu)
        t[:3, :3] = r0
        t[3:6, 3:6] = r0
        np.testing.assert_allclose(robot.mass_matrix(x), t @ m @ t.T, rtol=0, atol=1e-10)


# ---- the two conventions agree, options, errors -----------------------------------------------------


def test_paper_convention_equals_classic_for_the_same_arm():
    rng = np.random.default_rng(6)
    rows, table, types = random_table(rng, 4)
    # The same arm in the paper's convention: a_i and b_i from the DH geometry.
    paper = []
    for row, (d, theta, a, alpha) in zip(rows, table):
        ca, sa = math.cos(alpha), math.sin(alpha)
        origin_i = np.array([a, d * sa, d * ca])  # DH origin i from joint i, in frame i
        paper.append(dict(type=row["type"], theta=theta, alpha=alpha, joint_to_com=origin_i + row["com"],
                          com_to_next=-np.asarray(row["com"]), mass=row["mass"], inertia=row["inertia"]))
    kw = dict(base_mass=80.0, base_inertia=[5.0, 6.0, 7.0], joint1_origin=(0.1, 0.2, 0.3), joint1_rpy=(0.1, 0.2, 0.3))
    classic = robot_from_dh("c", rows, **kw)
    other = robot_from_dh("p", paper, convention="paper", **kw)
    for _ in range(5):
        x = configuration(classic, rng)
        np.testing.assert_allclose(classic.mass_matrix(x), other.mass_matrix(x), rtol=0, atol=1e-12)
        np.testing.assert_allclose(classic.point_position(x), other.point_position(x), rtol=0, atol=1e-12)


def test_names_limits_and_initial_q():
    rows = [dict(name="upper", joint_name="shoulder", d=0, theta=0, a=1, alpha=0, com=(-0.5, 0, 0), mass=1,
                 inertia=[0.01, 0.1, 0.1], limits=dict(lower=-1, upper=1)),
            dict(d=0, theta=0, a=1, alpha=0, com=(-0.5, 0, 0), mass=1, inertia=[0.01, 0.1, 0.1])]
    robot = spacearm.io.robot_from_dh("named", rows, base_mass=10, base_inertia=[1, 1, 1], initial_q=[0.1, 0.2],
                                   tip_point="hand")
    d = robot.describe()
    assert [link["name"] for link in d["links"]] == ["upper", "link2"]
    assert [link["joint"] for link in d["links"]] == ["shoulder", "joint2"]
    assert d["links"][0]["limits"][:2] == [-1.0, 1.0]
    assert robot.end_effector == "hand"
    np.testing.assert_allclose(robot.initial_q, [0.1, 0.2])
    assert robot_from_dh("n", rows, base_mass=10, base_inertia=[1, 1, 1], tip_point=None).end_effector is None


def test_dh_model_round_trips_through_toml():
    robot = robot_from_dh("spatial6", spatial6_rows("classic"), base_mass=500.0, base_inertia=[68.33, 86.67, 101.67],
                          joint1_origin=SPATIAL6_J1, joint1_rotation=quat_from_matrix(SPATIAL6_R0))
    text = model_file.dumps_toml(robot)
    assert model_file.dumps_toml(model_file.loads_toml(text)) == text


GOOD = dict(d=0.0, theta=0.0, a=1.0, alpha=0.0, com=(-0.5, 0.0, 0.0), mass=1.0, inertia=[0.01, 0.1, 0.1])


@pytest.mark.parametrize(
    "rows, kwargs, match",
    [
        ([], {}, "no links"),
        ([dict(GOOD, mas=1.0)], {}, r"DH link 1: unknown key\(s\) \['mas'\]"),
        ([GOOD, dict(GOOD, joint_to_com=(1, 0, 0))], {}, "DH link 2: unknown key"),
        ([{k: v for k, v in GOOD.items() if k != "alpha"}], {}, r"DH link 1: missing \['alpha'\]"),
        ([GOOD], dict(convention="paper"), "unknown key"),
        ([GOOD], dict(convention="craig"), "convention must be 'classic' or 'paper'"),
        ([dict(GOOD, mass=-1.0)], {}, r"link 'link1'.*>= 0"),
        ([dict(GOOD, inertia=[1.0, 1.0, 3.0])], {}, "triangle"),
        ([dict(GOOD, d=float("nan"))], {}, r"DH link 1 \('link1'\).*finite"),
        ([dict(GOOD, d="far")], {}, "d must be a number"),
        ([dict(GOOD, type="ball")], {}, "joint type must be"),
        ([dict(GOOD, limits=dict(lower=1, upper=-1))], {}, "lower <= upper"),
        ([dict(GOOD, limits=dict(min=1))], {}, "unknown limit keys"),
        ([GOOD], dict(joint1_rotation=[0, 0, 0, 2]), "unit quaternion"),
        ([GOOD], dict(joint1_rotation=[0, 0, 0, 1], joint1_rpy=[0, 0, 0]), "not both"),
        ([GOOD], dict(initial_q=[0.0, 0.0]), "initial"),
        ([GOOD, dict(GOOD, name="link1")], {}, "used twice"),
        ([GOOD], dict(base_mass=0.0), "> 0"),
        ([dict(GOOD, inertia=np.full((3, 3), 1e200))], {}, "exceeds"),
        ("not a list", {}, "list of dicts"),
        ([3], {}, "each DH row is a dict"),
    ],
)
def test_bad_tables_raise_model_error(rows, kwargs, match):
    kw = dict(base_mass=10.0, base_inertia=[1.0, 1.0, 1.0])
    kw.update(kwargs)
    with pytest.raises(spacearm.ModelError, match=match):
        robot_from_dh("bad", rows, **kw)


def test_the_extension_refuses_an_unknown_convention_itself():
    # The one extension entry point takes the convention as an argument: a name other than
    # "classic" or "paper" is refused there too (not only by robot_from_dh), and the same rows
    # are read as either convention's tuples.
    from spacearm import _core

    args = ("bad", "base", 10.0, np.eye(3).tolist())
    tail = ([0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0], [0.0, 0.0, 0.0], None)
    classic_row = (None, None, "revolute", 0.0, 0.0, 1.0, 0.0, [0.0, 0.0, 0.0], 1.0, np.eye(3).tolist(), None)
    with pytest.raises(spacearm.ModelError, match="DH convention must be 'classic' or 'paper', got 'craig'"):
        _core.model_from_dh("craig", *args, [classic_row], *tail)
    assert _core.model_from_dh("classic", *args, [classic_row], *tail).n_dof == 1
    with pytest.raises(ValueError, match="length 10"):
        _core.model_from_dh("paper", *args, [classic_row], *tail)  # an 11-tuple is not a paper row
