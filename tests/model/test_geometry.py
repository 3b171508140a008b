"""Geometry in the model (docs/geometry.md): the builder's rules, editing, the model file, the
presets and the target; URDF visuals and collisions placed as Pinocchio places them."""

import numpy as np
import pytest

import spacearm
from spacearm.errors import ArgumentError, ModelError
from spacearm.rotations import quat_from_rpy, quat_to_matrix

from pathlib import Path

from robot_data import robot_urdf, robots_dir


def _robot():
    b = spacearm.Robot.builder("g", base_mass=100.0, base_inertia=[10, 12, 14])
    b.add_link("arm", parent="base", joint="revolute", axis=(0, 0, 1), origin=(0.5, 0, 0), com=(0.5, 0, 0),
               mass=5.0, inertia=[0.01, 0.4, 0.4])
    return b


def test_builder_holds_each_shape_with_its_placement():
    b = _robot()
    b.add_geometry("base", "box", size=(1.0, 0.8, 0.6), rgba=(0.9, 0.7, 0.3, 1.0))
    b.add_geometry("arm", "capsule", radius=0.05, length=0.9, rpy=(0, np.pi / 2, 0), name="rod")
    b.add_geometry("arm", "cylinder", radius=0.06, length=1.0, role="collision", origin=(0, 0, 0.1))
    b.add_geometry("arm", "sphere", radius=0.1)
    b.add_geometry("arm", "mesh", file="hand.stl", scale=(0.001, 0.001, 0.001))
    g = b.build().description.geometries
    assert [x.name for x in g] == ["base_visual0", "rod", "arm_collision0", "arm_visual1", "arm_visual2"]
    assert [x.shape for x in g] == ["box", "capsule", "cylinder", "sphere", "mesh"]
    np.testing.assert_array_equal(g[0].size, [1.0, 0.8, 0.6])
    assert g[0].radius is None and g[0].file is None
    assert (g[1].radius, g[1].length) == (0.05, 0.9)
    # Ry(π/2) turns the capsule's z axis onto the body's x.
    np.testing.assert_allclose(quat_to_matrix(g[1].rotation) @ [0, 0, 1], [1, 0, 0], atol=1e-15)
    assert g[2].role == "collision" and g[2].body_index == 1
    np.testing.assert_array_equal(g[2].origin, [0, 0, 0.1])
    assert g[4].file == "hand.stl"
    np.testing.assert_array_equal(g[4].scale, [0.001] * 3)
    np.testing.assert_array_equal(g[3].rgba, [0.7, 0.7, 0.7, 1.0])
    assert not g[0].origin.flags.writeable


@pytest.mark.parametrize("kwargs, message", [
    (dict(body="ghost", shape="sphere", radius=1.0), "not a body of the model"),
    (dict(body="arm", shape="sphere", radius=0.0), "sphere radius must be a finite length > 0"),
    (dict(body="arm", shape="box", radius=1.0), "a box takes size, not `radius`"),
    (dict(body="arm", shape="cylinder", radius=1.0), "a cylinder needs `length`"),
    (dict(body="arm", shape="cone", radius=1.0), "shape must be"),
    (dict(body="arm", shape="sphere", radius=1.0, role="both"), "role must be 'visual' or 'collision'"),
    (dict(body="arm", shape="sphere", radius=1.0, rgba=(0, 0, 0, 2)), "rgba must be 4 numbers in [0, 1]"),
    (dict(body="arm", shape="mesh", file="a.stl", scale=(1, 0, 1)), "mesh scale"),
    (dict(body="arm", shape="sphere", radius=1.0, rotation=(0, 0, 0, 3)), "geometry rotation"),
])
def test_bad_geometry_is_refused_by_name(kwargs, message):
    with pytest.raises(ModelError, match=message.replace("[", r"\[").replace("]", r"\]")):
        _robot().add_geometry(**kwargs)


def test_geometry_names_are_unique_and_rotation_or_rpy():
    b = _robot().add_geometry("arm", "sphere", radius=1.0, name="g")
    with pytest.raises(ModelError, match="geometry name 'g' is used twice"):
        b.add_geometry("base", "sphere", radius=1.0, name="g")
    with pytest.raises(ArgumentError, match="rotation or rpy"):
        b.add_geometry("base", "sphere", radius=1.0, rotation=(0, 0, 0, 1), rpy=(0, 0, 0))


def test_editing_keeps_geometry_and_removing_a_body_drops_its_own():
    robot = _robot().add_geometry("base", "box", size=(1, 1, 1)).add_geometry("arm", "sphere", radius=0.1).build()
    again = robot.to_builder().build()
    assert [g.name for g in again.description.geometries] == ["base_visual0", "arm_visual0"]
    assert again.description.geometries[1].radius == 0.1
    kept = robot.to_builder().remove_body("arm").build()
    assert [g.name for g in kept.description.geometries] == ["base_visual0"]


def test_model_files_round_trip_geometry():
    robot = _robot().add_geometry("arm", "capsule", radius=0.05, length=0.9, rpy=(0.1, 0.2, 0.3), rgba=(0, 1, 0, 0.5)).build()
    back = spacearm.io.loads_toml(spacearm.io.dumps_toml(robot))
    a, b = robot.description.geometries[0], back.description.geometries[0]
    assert (a.name, a.shape, a.radius, a.length) == (b.name, b.shape, b.radius, b.length)
    np.testing.assert_array_equal(a.rotation, b.rotation)
    np.testing.assert_array_equal(a.rgba, b.rgba)


def test_presets_bus_and_target_have_shapes():
    for name in ("planar4", "spatial6", "dual_arm", "spatial7", "ets7"):
        robot = spacearm.presets.get(name)
        bodies = {g.body for g in robot.description.geometries}
        assert bodies == set(robot.body_names), name
    # planar4's base is SPART's 0.5 m cube; its links the 1 m × 0.05 m bars of their inertia.
    g = spacearm.presets.planar4().description.geometries
    np.testing.assert_allclose(g[0].size, [0.5] * 3, rtol=1e-4)
    np.testing.assert_allclose(g[1].size, [1.0, 0.05, 0.05])
    bus = spacearm.io.load_toml(_bus())
    assert [(g.body, g.shape) for g in bus.description.geometries] == [("bus", "box")]
    # A target's default shape: the uniform box of its principal moments, m (b² + c²)/12 = I.
    t = spacearm.Target(200.0, [20.0, 30.0, 40.0])
    (g,) = t.body.description.geometries
    a, b, c = g.size
    np.testing.assert_allclose([200 * (b * b + c * c) / 12, 200 * (a * a + c * c) / 12, 200 * (a * a + b * b) / 12],
                               [20, 30, 40], rtol=1e-12)
    t = spacearm.Target(200.0, [20.0, 30.0, 40.0], shape={"shape": "cylinder", "radius": 0.5, "length": 1.2})
    assert t.body.description.geometries[0].shape == "cylinder"
    with pytest.raises(ArgumentError, match="shape must be a mapping"):
        spacearm.Target(200.0, [20.0, 30.0, 40.0], shape="sphere")


def _bus():
    return spacearm.examples.path("spacecraft_bus")


def test_the_preset_files_draw_the_presets():
    for name in set(spacearm.examples.NAMES) & set(spacearm.presets.NAMES):
        a = spacearm.io.load_toml(spacearm.examples.path(name)).description.geometries
        b = spacearm.presets.get(name).description.geometries
        assert [(g.name, g.body, g.shape) for g in a] == [(g.name, g.body, g.shape) for g in b], name
        for ga, gb in zip(a, b):
            np.testing.assert_array_equal(ga.origin, gb.origin)
            np.testing.assert_array_equal(ga.rotation, gb.rotation)


def test_urdf_visuals_are_placed_as_pinocchio_places_them():
    """The UR5: every geometry's pose, from spacearm's body poses and the geometry's placement,
    equals Pinocchio's (buildGeomFromUrdf, updateGeometryPlacements) at a random
    configuration; both measured from the URDF frame of base_link."""
    pin = pytest.importorskip("pinocchio")
    path = robot_urdf("ur_description/urdf/ur5_robot.urdf")
    robot = spacearm.io.load_urdf(path)
    model = pin.buildModelFromUrdf(path)
    rng = np.random.default_rng(3)
    q = rng.uniform(-2, 2, robot.n_dof)
    data = model.createData()
    results = {}
    for kind, role in ((pin.GeometryType.VISUAL, "visual"), (pin.GeometryType.COLLISION, "collision")):
        geom = pin.buildGeomFromUrdf(model, path, kind, package_dirs=[str(Path(robots_dir()).parents[1])])
        gdata = pin.GeometryData(geom)
        pin.forwardKinematics(model, data, q)  # spacearm's q order is the URDF's depth-first order here
        pin.updateGeometryPlacements(model, data, geom, gdata)
        pin.updateFramePlacements(model, data)
        ref = data.oMf[model.getFrameId("base_link")]
        results[role] = [(ref.inverse() * gdata.oMg[k]) for k in range(len(geom.geometryObjects))]
    x = robot.neutral_configuration(q)
    k = robot.forward_kinematics(x)
    ref = robot.point_position(x, "base_link")
    got = {"visual": [], "collision": []}
    for g in robot.description.geometries:
        b = g.body_index
        r = k.body_to_world[b]
        got[g.role].append((r @ g.origin + k.com_in_world[b] - ref, r @ quat_to_matrix(g.rotation)))
    for role in ("visual", "collision"):
        assert len(got[role]) == len(results[role]) > 5
        for (p, rot), m in zip(got[role], results[role]):
            np.testing.assert_allclose(p, m.translation, atol=1e-12)
            np.testing.assert_allclose(rot, m.rotation, atol=1e-12)


def test_urdf_export_writes_geometry_that_reads_back():
    robot = spacearm.presets.ets7()
    back = spacearm.io.loads_urdf(spacearm.io.to_urdf(robot), fixed="keep")
    for a, b in zip(robot.description.geometries, back.description.geometries, strict=True):
        assert (a.name, a.body, a.shape, a.radius, a.length) == (b.name, b.body, b.shape, b.radius, b.length)
        np.testing.assert_allclose(a.origin, b.origin, atol=1e-15)
        np.testing.assert_allclose(quat_to_matrix(a.rotation), quat_to_matrix(b.rotation), atol=1e-15)
        np.testing.assert_array_equal(a.rgba, b.rgba)


def test_urdf_materials_and_relative_meshes(tmp_path):
    (tmp_path / "m").mkdir()
    (tmp_path / "m" / "part.stl").write_text("solid x\nendsolid x\n")
    text = f"""<robot name="r"><material name="blue"><color rgba="0 0 1 1"/></material>
      <link name="a"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1"/></inertial>
        <visual><origin xyz="0 0 0.5" rpy="0.1 0.2 0.3"/><geometry><box size="1 2 3"/></geometry><material name="blue"/></visual>
        <visual><geometry><mesh filename="m/part.stl" scale="2 2 2"/></geometry><material name="x"><color rgba="1 0 0 1"/></material></visual>
        <collision><geometry><capsule radius="0.1" length="0.4"/></geometry></collision></link></robot>"""
    path = tmp_path / "r.urdf"
    path.write_text(text)
    g = spacearm.io.load_urdf(path).description.geometries
    np.testing.assert_array_equal(g[0].rgba, [0, 0, 1, 1])
    np.testing.assert_allclose(quat_to_matrix(g[0].rotation), quat_to_matrix(quat_from_rpy(0.1, 0.2, 0.3)), atol=1e-15)
    assert g[1].file == str(tmp_path / "m" / "part.stl")
    np.testing.assert_array_equal(g[1].rgba, [1, 0, 0, 1])
    assert (g[2].role, g[2].shape) == ("collision", "capsule")
    with pytest.raises(spacearm.ModelFileError, match=r":3: link 'a' <visual>: unknown geometry <cone>"):
        spacearm.io.loads_urdf(text.replace("<box size=\"1 2 3\"/>", "<cone/>"))
