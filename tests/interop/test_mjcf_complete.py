"""The complete MJCF export (geoms, sites, actuators, base thrusters, meshes) checked in MuJoCo
on the UR5 mounted on the shipped bus: the model loads with its shapes and motors, its mass
matrix and its forward dynamics under actuator controls equal spacearm's, and a torque history
simulated in MuJoCo follows spacearm's native simulation to integration tolerance."""

import numpy as np
import pytest

import spacearm
from spacearm.errors import ArgumentError
from spacearm.interop import mujoco as smj

from robot_data import robot_urdf

mujoco = pytest.importorskip("mujoco")


@pytest.fixture(scope="module")
def ur5_on_bus():
    bus = spacearm.io.load_toml(spacearm.examples.path("spacecraft_bus"))
    return spacearm.io.load_urdf(robot_urdf("ur_description/urdf/ur5_robot.urdf"), mount_on=bus, at=(0.6, 0, 0, 0, 0, 0))


def _state(robot, rng):
    x = robot.neutral_configuration(rng.uniform(-1.5, 1.5, robot.n_dof), r0=rng.normal(size=3))
    q = rng.normal(size=4)
    x[3:7] = q / np.linalg.norm(q)
    return x, rng.normal(scale=0.3, size=robot.nu)


def test_the_model_loads_with_its_shapes_sites_and_motors(ur5_on_bus, tmp_path):
    robot = ur5_on_bus
    m = smj.to_mujoco(robot, geometry=("collision",), base_actuators=True)
    collision = [g for g in robot.description.geometries if g.role == "collision"]
    assert m.ngeom == len(collision) == 8 and m.nmesh == 7
    assert {mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, k) for k in range(m.ngeom)} == {g.name for g in collision}
    assert set(np.asarray(m.geom_group)) == {3} and not np.any(m.geom_contype)
    assert m.nu == robot.n_dof + 6
    names = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_ACTUATOR, k) for k in range(m.nu)]
    assert names[:6] == [f"{j}_motor" for j in robot.joint_names] and names[6:] == [
        "base_fx", "base_fy", "base_fz", "base_tx", "base_ty", "base_tz"]
    effort = [link.limits.effort for link in robot.description.links if link.dof is not None]
    np.testing.assert_array_equal(m.actuator_ctrlrange[:6, 1], effort)
    sites = {mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_SITE, k) for k in range(m.nsite)}
    assert set(robot.point_names) <= sites
    # The geoms have no mass: MuJoCo's body masses are spacearm's.
    bodies = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, k) for k in range(1, m.nbody)]
    masses = {smj.mjcf_body_name(n): robot.description.link(n).mass if n != robot.body_names[0]
              else robot.description.base.mass for n in robot.body_names}
    np.testing.assert_allclose(m.body_mass[1:], [masses[b] for b in bodies], rtol=1e-15)
    # The saved file is self-contained: its meshes beside it.
    path = tmp_path / "ur5_bus.xml"
    smj.save_mjcf(robot, path, geometry=("collision",))
    assert len(list((tmp_path / "ur5_bus_meshes").iterdir())) == 7
    assert mujoco.MjModel.from_xml_path(str(path)).ngeom == 8


def test_mass_matrix_and_forward_dynamics_under_the_actuators(ur5_on_bus):
    robot = ur5_on_bus
    m = smj.to_mujoco(robot, geometry=(), base_actuators=True)
    d = mujoco.MjData(m)
    rng = np.random.default_rng(7)
    for _ in range(3):
        x, u = _state(robot, rng)
        tau = rng.uniform(-20, 20, robot.n_dof)
        wrench = rng.normal(scale=5.0, size=6)
        d.qpos[:], d.qvel[:] = smj.to_mujoco_state(robot, x, u)
        d.ctrl[:] = smj.actuator_controls(robot, tau, wrench, base_actuators=True)
        mujoco.mj_forward(m, d)
        full = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, d, full)
        h = robot.mass_matrix(x)
        np.testing.assert_allclose(smj.mass_matrix_from_mujoco(robot, x, full), h, rtol=1e-11, atol=1e-11 * np.abs(h).max())
        # The motors' generalized force is spacearm's [F0, N0, τ] (base wrench in 𝒥).
        f = np.concatenate([wrench, tau])
        np.testing.assert_allclose(smj.from_mujoco_force(robot, x, d.qfrc_actuator), f, atol=1e-12)
        du = robot.forward_dynamics(x, u, tau=tau, base_wrench=wrench)
        np.testing.assert_allclose(smj.acceleration_from_mujoco(robot, x, d.qacc), du, rtol=1e-8, atol=1e-9)


def test_a_torque_history_simulated_in_mujoco_follows_spacearm(ur5_on_bus):
    """Joint torques τ(t_k) held over each step of dt = 2 ms for 0.6 s, floating base: MuJoCo's
    RK4 and spacearm's native RK4 (Simulator) from the same start agree to integration
    tolerance (both 4th order: the gap shrinks 16-fold when dt halves)."""
    robot = ur5_on_bus
    m = smj.to_mujoco(robot, geometry=())
    rng = np.random.default_rng(11)
    x0, u0 = _state(robot, rng)
    u0 *= 0.5
    amp, omega = rng.uniform(5, 20, robot.n_dof), rng.uniform(2, 6, robot.n_dof)

    def gap(dt, steps):
        sim = spacearm.Simulator(robot, dt=dt, mode="floating", joint_limits=False)
        sim.reset(x0, u0)
        m.opt.timestep = dt
        d = mujoco.MjData(m)
        d.qpos[:], d.qvel[:] = smj.to_mujoco_state(robot, x0, u0)
        for k in range(steps):
            tau = amp * np.sin(omega * k * dt)
            sim.step(tau)
            d.ctrl[:] = smj.actuator_controls(robot, tau)
            mujoco.mj_step(m, d)
        x, u = smj.from_mujoco_state(robot, d.qpos, d.qvel)
        s = sim.state
        return max(np.abs(s[:3] - x[:3]).max(), np.abs(s[7:robot.nx] - x[7:]).max(),
                   1 - abs(s[3:7] @ x[3:7]), np.abs(s[robot.nx:] - u).max()), np.abs(s[7:robot.nx] - x0[7:]).max()

    coarse, moved = gap(0.004, 150)
    fine, _ = gap(0.002, 300)
    assert moved > 0.05  # the arm moved
    assert fine < 1e-7, fine
    assert fine < coarse / 4 or fine < 1e-12, (coarse, fine)


def test_effort_limits_and_bad_meshes(tmp_path):
    b = spacearm.Robot.builder("p", base_mass=100.0, base_inertia=[10, 10, 10])
    b.add_link("a", parent="base", joint="revolute", axis=(0, 0, 1), origin=(0.5, 0, 0), com=(0.5, 0, 0),
               mass=5.0, inertia=[0.01, 0.4, 0.4], limits={"effort": 3.0})
    b.add_geometry("a", "mesh", file=str(tmp_path / "missing.stl"))
    robot = b.build()
    with pytest.raises(spacearm.ModelFileError, match="missing.stl' of the model does not exist"):
        smj.to_mujoco(robot)
    m = smj.to_mujoco(robot, geometry=())
    np.testing.assert_array_equal(m.actuator_ctrlrange[0], [-3.0, 3.0])
    dae = tmp_path / "x.dae"
    dae.write_text("not read: a path-only export refuses the format first")
    with pytest.raises(ArgumentError, match="MuJoCo reads .stl, .obj meshes, not '.dae'"):
        smj.to_mjcf(spacearm.RobotBuilder.from_robot(robot, geometry=False).add_geometry("a", "mesh", file=str(dae)).build())


def test_the_real_arm_with_its_collada_meshes_exports_in_one_call(ur5_on_bus, tmp_path):
    # Issue 37 item 2: the UR5's visual meshes are COLLADA, which MuJoCo cannot read; the export
    # refused them and named spacearm.io.mesh.with_mesh_format, which failed as written. Now
    # save_mjcf converts them (to STL, beside the MJCF) and MuJoCo loads the file as it is.
    collada = pytest.importorskip("collada")
    path = tmp_path / "ur5_bus.xml"
    smj.save_mjcf(ur5_on_bus, path)
    m = mujoco.MjModel.from_xml_path(str(path))
    dae = sorted({g.file for g in ur5_on_bus.description.geometries if g.shape == "mesh" and g.file.endswith(".dae")})
    assert dae and m.ngeom == len(ur5_on_bus.description.geometries)
    # Each COLLADA mesh arrives whole: its triangle count, read by pycollada directly, is a
    # MuJoCo mesh's face count.
    faces = set(int(n) for n in m.mesh_facenum)
    for file in dae:
        triangles = sum(len(p) for geom in collada.Collada(file).geometries for p in geom.primitives)
        assert triangles in faces, file
    # The message of a path-only export names what converts them, and the module it used to
    # name is reachable as written.
    with pytest.raises(ArgumentError, match=r"save_mjcf\(robot, path\) converts it"):
        smj.to_mjcf(ur5_on_bus)
    assert callable(spacearm.io.mesh.with_mesh_format)
