"""Flexible-plant campaigns (issue 24 item 6): a tank's fill fraction, slosh frequency and
damping, and a panel's stiffness drawn per sample, the plant rebuilt by the builder.

Independent references: the distributions' closed forms (Kolmogorov–Smirnov against scipy's),
a plant built by hand with the builder (mass matrix bit-equal), and a direct
[`spacearm.simulate`] of that hand-built plant under a hand-built rigid-model controller whose
tracking error is computed here from the states and the reference (not from the run's records).
"""

import numpy as np
import pytest

import spacearm
from spacearm.campaign import (
    PARAMETER_NAMES,
    CampaignResult,
    CampaignSpec,
    Fixed,
    Flexibility,
    LogNormal,
    Panel,
    Perturbations,
    Scenario,
    Tank,
    Uniform,
    run_campaign,
)
from spacearm.campaign.scenario import plant
from spacearm.control import ComputedTorque, QuinticJoint
from spacearm.errors import ArgumentError
from spacearm.io.model_file import dumps_toml, loads_toml

NO_ERRORS = Perturbations(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
TANK = Tank(radius=0.3, height=0.8, density=1000.0, axial_acceleration=0.1, bottom=(0.0, 0.0, -0.35),
            lateral=(0.0, 1.0, 0.0), model="pendulum")
PANEL = Panel(hinge_position=(0.0, 0.9, 0.0), hinge_axis=(1.0, 0.0, 0.0), direction=(0.0, 1.0, 0.0), mass=15.0,
              size=(2.0, 1.0, 0.02), damping=0.2)


def _bus(builder=None):
    b = builder or spacearm.Robot.builder("bus", base_mass=400.0, base_inertia=[60.0, 70.0, 80.0])
    b.add_link("l1", joint="revolute", axis=(0, 0, 1), origin=(0.7, 0, 0.3), com=(0.5, 0, 0), mass=8.0,
               inertia=[0.02, 0.7, 0.7])
    return b


def _hand_plant(fill, zeta, k_panel, freq_scale=1.0):
    """The flexible plant written out with the builder, not through Flexibility."""
    b = _bus()
    tank = spacearm.slosh_parameters("cylinder", radius=0.3, fill_fraction=fill, tank_height=0.8, density=1000.0,
                                     axial_acceleration=0.1 * freq_scale**2, damping_ratio=zeta)
    tank.add_to(b, "fuel", center=(0.0, 0.0, -0.35 + tank.fill_height / 2), axis=(0, 0, 1), lateral=(0, 1, 0),
                model="pendulum")
    b.add_panel("panel", hinge_position=(0, 0.9, 0), hinge_axis=(1, 0, 0), direction=(0, 1, 0), mass=15.0,
                size=(2.0, 1.0, 0.02), stiffness=k_panel, damping=0.2)
    return b.build(), tank


@pytest.fixture(scope="module")
def bus():
    # As a campaign's workers see it: through the TOML text of the spec.
    return loads_toml(dumps_toml(_bus().build()))


def test_draws_follow_the_distributions_and_are_reproducible():
    from scipy import stats

    flex = Flexibility(tank=TANK, fill_fraction=Uniform(0.1, 0.9), slosh_frequency_scale=LogNormal(1.0, 0.1),
                       slosh_damping_ratio=Uniform(0.001, 0.01), panel=PANEL, panel_stiffness=LogNormal(25.0, 0.2))
    draws = [flex.draw(7, i) for i in range(2000)]
    fill = np.array([d["fill_fraction"] for d in draws])
    assert stats.kstest(fill, stats.uniform(loc=0.1, scale=0.8).cdf).pvalue > 1e-3
    k = np.array([d["panel_stiffness"] for d in draws])
    assert stats.kstest(np.log(k / 25.0), stats.norm(scale=0.2).cdf).pvalue > 1e-3
    s = np.array([d["slosh_frequency_scale"] for d in draws])
    assert stats.kstest(np.log(s), stats.norm(scale=0.1).cdf).pvalue > 1e-3
    # the parameters of one sample are not the same draw reused
    assert abs(np.corrcoef(fill, np.log(k))[0, 1]) < 0.1
    assert flex.draw(7, 3) == draws[3]
    assert flex.draw(8, 3) != draws[3]
    assert flex.nominal() == {"fill_fraction": 0.5, "slosh_frequency_scale": 1.0, "slosh_damping_ratio": 0.0055,
                              "panel_stiffness": 25.0}


def test_inertia_draws_are_unchanged_by_a_flexibility_recipe(bus):
    flex = Flexibility(tank=TANK, fill_fraction=Uniform(0.1, 0.9))
    rigid = CampaignSpec(dumps_toml(bus), 4, seed=3, perturbations=Perturbations())
    flexible = CampaignSpec(dumps_toml(bus), 4, seed=3, perturbations=Perturbations(), scenario=Scenario(flexibility=flex))
    for i in range(4):
        d = flexible.draw(i)
        assert {n: d[n] for n in PARAMETER_NAMES} == rigid.draw(i)
    assert flexible.param_names == PARAMETER_NAMES + ("fill_fraction", "slosh_frequency_scale", "slosh_damping_ratio")
    assert "flexibility" not in rigid.to_json()


def test_spec_round_trips_through_json(bus):
    flex = Flexibility(tank=TANK, fill_fraction=Uniform(0.1, 0.9), slosh_damping_ratio=0.005, panel=PANEL,
                       panel_stiffness=LogNormal(25.0, 0.2))
    spec = CampaignSpec(dumps_toml(bus), 5, seed=1, scenario=Scenario(duration=1.0, flexibility=flex))
    again = CampaignSpec.from_json(spec.to_json())
    assert again == spec
    shaped = CampaignSpec(dumps_toml(bus), 5, seed=1, scenario=Scenario(duration=1.0, flexibility=flex, shaping="zvd",
                                                                         shaping_damping=0.01))
    assert CampaignSpec.from_json(shaped.to_json()) == shaped != spec
    assert again.to_json() == spec.to_json()
    assert again.draw(2) == spec.draw(2)


def test_a_samples_plant_equals_the_plant_built_by_hand(bus):
    flex = Flexibility(tank=TANK, fill_fraction=Uniform(0.1, 0.9), slosh_frequency_scale=LogNormal(1.0, 0.1),
                       slosh_damping_ratio=Uniform(0.001, 0.01), panel=PANEL, panel_stiffness=Uniform(10.0, 40.0))
    spec = CampaignSpec(dumps_toml(bus), 3, seed=11, perturbations=NO_ERRORS, scenario=Scenario(flexibility=flex))
    rng = np.random.default_rng(0)
    for i in range(3):
        params = spec.draw(i)
        p = plant(bus, params, flex)
        hand, _ = _hand_plant(params["fill_fraction"], params["slosh_damping_ratio"], params["panel_stiffness"],
                              params["slosh_frequency_scale"])
        assert p.n_dof == hand.n_dof == 3
        assert list(p.actuated_dofs) == list(hand.actuated_dofs) == [True, False, False]
        x = hand.neutral_configuration(q=rng.uniform(-0.5, 0.5, 3))
        assert np.array_equal(p.mass_matrix(x), hand.mass_matrix(x))
        u = rng.normal(size=hand.nu)
        assert np.array_equal(p.passive_forces(x, u), hand.passive_forces(x, u))
        assert p.total_mass == hand.total_mass


def test_fill_fraction_campaign_on_threads_matches_a_direct_simulation(bus):
    flex = Flexibility(tank=TANK, fill_fraction=Uniform(0.1, 0.9), slosh_damping_ratio=0.005, panel=PANEL,
                       panel_stiffness=25.0)
    scenario = Scenario(duration=3.0, dt=1e-2, kp=4.0, kd=4.0, q_offset=0.8, flexibility=flex)
    result = run_campaign(bus, samples=4, seed=5, perturbations=NO_ERRORS, scenario=scenario, workers=2,
                          progress=False)
    assert result.run["backend"] == "threads" and result.n_ok == 4
    # The controller's model, by hand: the nominal (mid-range) fill, passive joints frozen.
    model, _ = _hand_plant(0.5, 0.005, 25.0)
    move = QuinticJoint([0.0], [0.8], 0.0, 0.75 * 3.0)
    errors = []
    for i, fill in enumerate(result.parameter("fill_fraction")):
        hand, _ = _hand_plant(fill, 0.005, 25.0)
        traj = spacearm.simulate(hand, 3.0, x0=hand.neutral_configuration(), dt=1e-2,
                                 controller=ComputedTorque(4.0, 4.0, move, model=model, passive="frozen"))
        q_ref, _, _ = move.evaluate(traj.t)
        err = np.abs(traj.x[:, 7] - q_ref[:, 0])
        errors.append(err.max())
        assert result.metrics[i, result.metric_names.index("tracking_error_max")] == pytest.approx(err.max(), rel=1e-9)
        assert result.metrics[i, result.metric_names.index("tracking_error_final")] == pytest.approx(err[-1], rel=1e-9,
                                                                                                     abs=1e-15)
    # the rigid-model controller does not track the flexible plant exactly: the metric measures something
    assert min(errors) > 1e-6
    assert np.ptp(errors) > 1e-3 * max(errors)  # and it depends on the drawn fill


def test_a_checkpoint_records_the_drawn_values(bus, tmp_path):
    flex = Flexibility(panel=PANEL, panel_stiffness=Uniform(10.0, 40.0))
    out = tmp_path / "flex.npz"
    r = run_campaign(bus, samples=3, seed=2, perturbations=NO_ERRORS, out=out, workers=0, progress=False,
                     scenario=Scenario(duration=0.5, dt=1e-2, flexibility=flex))
    back = CampaignResult.load(out)
    assert back.param_names[-1] == "panel_stiffness"
    expected = [flex.draw(2, i)["panel_stiffness"] for i in range(3)]
    assert np.array_equal(back.parameter("panel_stiffness"), expected)
    assert np.array_equal(back.metrics, r.metrics)


def test_bad_recipes_are_errors():
    with pytest.raises(ArgumentError, match="tank, a panel or both"):
        Flexibility()
    with pytest.raises(ArgumentError, match="low <= high"):
        Uniform(0.9, 0.1)
    with pytest.raises(ArgumentError, match="distribution"):
        Flexibility(tank=TANK, fill_fraction="half")
    with pytest.raises(ArgumentError, match="Tank.radius"):
        Tank(radius=-1.0, height=0.8, density=1000.0, axial_acceleration=0.1)
    with pytest.raises(ArgumentError, match="computed-torque"):
        Scenario(controller="pd", flexibility=Flexibility(panel=PANEL))
    assert Fixed(0.3).nominal == 0.3


def test_shaped_campaign_matches_a_direct_simulation_and_its_base_rate(bus):
    """Each sample's fill fraction, tracking error and largest base rate equal a direct simulate
    of the hand-built plant under a hand-built ZVD-shaped rigid-model controller; the error and
    |w0| are computed here from the states, the velocities and the shaped reference."""
    from spacearm.control import input_shaper

    flex = Flexibility(tank=TANK, fill_fraction=Uniform(0.1, 0.9), slosh_damping_ratio=0.005, panel=PANEL,
                       panel_stiffness=Uniform(15.0, 35.0))
    scenario = Scenario(duration=6.0, dt=1e-2, kp=4.0, kd=4.0, q_offset=0.8, motion_fraction=0.5, flexibility=flex,
                        shaping="zvd")
    result = run_campaign(bus, samples=3, seed=9, perturbations=NO_ERRORS, scenario=scenario, workers=0,
                          progress=False)
    assert result.n_ok == 3
    model, _ = _hand_plant(0.5, 0.005, 25.0)
    # the shaper's mode, by hand: the controller's model's first mode, actuated joint held
    w1 = model.natural_frequencies(model.neutral_configuration()).frequencies[0]
    assert w1 > 0.1
    move = input_shaper("zvd", frequency=w1).shape(QuinticJoint([0.0], [0.8], 0.0, 3.0))
    draws = [scenario.flexibility.draw(9, i) for i in range(3)]
    assert np.array_equal(result.parameter("fill_fraction"), [d["fill_fraction"] for d in draws])
    col = result.metric_names.index
    for i, d in enumerate(draws):
        hand, _ = _hand_plant(d["fill_fraction"], 0.005, d["panel_stiffness"])
        traj = spacearm.simulate(hand, 6.0, x0=hand.neutral_configuration(), dt=1e-2,
                                 controller=ComputedTorque(4.0, 4.0, move, model=model, passive="frozen"))
        q_ref, _, _ = move.evaluate(traj.t)
        err = np.abs(traj.x[:, 7] - q_ref[:, 0])
        rate = np.linalg.norm(traj.u[:, 3:6], axis=1)
        assert result.metrics[i, col("tracking_error_max")] == pytest.approx(err.max(), rel=1e-9)
        assert result.metrics[i, col("base_rate_max")] == pytest.approx(rate.max(), rel=1e-12)
        assert rate.max() > 1e-3  # the arm's reaction turns the base: the metric measures something
    # the shaped reference is what was flown: an unshaped controller gives another error
    plain = run_campaign(bus, samples=3, seed=9, perturbations=NO_ERRORS, progress=False, workers=0,
                         scenario=Scenario(duration=6.0, dt=1e-2, kp=4.0, kd=4.0, q_offset=0.8, motion_fraction=0.5,
                                           flexibility=flex))
    assert not np.allclose(plain.metric("tracking_error_max"), result.metric("tracking_error_max"), rtol=1e-3)


def test_base_rate_of_a_rigid_campaign_is_the_momentum_balance(bus):
    """On a rigid floating robot with zero momentum, w0 follows from the momentum map
    (H0 [v0; w0] = -H0m qd); the campaign's base_rate_max equals that, from the states alone."""
    scenario = Scenario(duration=1.0, dt=1e-2, kp=50.0, kd=14.0, q_offset=0.6)
    r = run_campaign(bus, samples=1, seed=0, perturbations=NO_ERRORS, scenario=scenario, workers=0, progress=False)
    traj = spacearm.simulate(bus, 1.0, x0=bus.neutral_configuration(), dt=1e-2,
                             controller=ComputedTorque(50.0, 14.0, QuinticJoint([0.0], [0.6], 0.0, 0.75), model=bus))
    rates = []
    for x, u in zip(traj.x, traj.u):
        blocks = bus.inertia_blocks(x)
        base = np.linalg.solve(blocks.H0, -blocks.H0m @ u[6:])
        rates.append(np.linalg.norm(base[3:6]))
    assert r.metric("base_rate_max")[0] == pytest.approx(max(rates), rel=1e-6)


def test_bad_shaping_is_an_error():
    with pytest.raises(ArgumentError, match="shaping must be"):
        Scenario(shaping="zvdd", shaping_frequency=1.0)
    with pytest.raises(ArgumentError, match="needs a flexibility recipe"):
        Scenario(shaping="zv")
    with pytest.raises(ArgumentError, match="shaping_frequency must be"):
        Scenario(shaping="zv", shaping_frequency=-1.0)
    with pytest.raises(ArgumentError, match="need shaping"):
        Scenario(shaping_frequency=1.0)
    # a rigid campaign's spec carries no shaping keys
    assert "shaping" not in Scenario().to_dict()
    assert Scenario(shaping="zv", shaping_frequency=1.0).to_dict()["shaping"] == "zv"


SPHERE = Tank(radius=0.35, height=0.7, density=1000.0, axial_acceleration=0.1, bottom=(0.0, 0.0, -0.4),
              lateral=(0.0, 1.0, 0.0), model="pendulum", shape="sphere")


def test_a_spherical_tank_puts_the_liquid_at_the_caps_centre_of_mass(bus):
    """A sample's plant with a spherical tank: its mass is the bus's plus the cap's ρπh²(3R − h)/3,
    and its CM (pendulums hanging at rest) is where the bus's CM and the cap's CM put it. The
    cap's fill height solves the volume fraction and its CM h(8R − 3h)/(4(3R − h)) above the pole:
    both computed here from the cap's geometry, not by the core."""
    from scipy.optimize import brentq

    flex = Flexibility(tank=SPHERE, fill_fraction=Uniform(0.2, 0.8))
    spec = CampaignSpec(dumps_toml(bus), 3, seed=4, perturbations=NO_ERRORS, scenario=Scenario(flexibility=flex))
    r_ = 0.35
    for i in range(3):
        params = spec.draw(i)
        f = params["fill_fraction"]
        h = brentq(lambda z: np.pi * z * z * (3 * r_ - z) / 3 - f * 4 / 3 * np.pi * r_**3, 0.0, 2 * r_, xtol=1e-15)
        m_liquid = 1000.0 * np.pi * h * h * (3 * r_ - h) / 3
        z_cm = -0.4 + h * (8 * r_ - 3 * h) / (4 * (3 * r_ - h))
        p = plant(bus, params, flex)
        assert p.total_mass == pytest.approx(bus.total_mass + m_liquid, rel=1e-12)
        x_bus, x = bus.neutral_configuration(), p.neutral_configuration()
        expected = (bus.total_mass * np.asarray(bus.center_of_mass(x_bus)) + m_liquid * np.array([0.0, 0.0, z_cm]))
        assert np.allclose(p.center_of_mass(x), expected / (bus.total_mass + m_liquid), atol=1e-12)
        # the pendulum's hinge is at the sphere's centre (docs/flexibility.md)
        assert list(p.actuated_dofs) == [True, False]
    # the cylinder default leaves the spec as it was; the sphere says so
    assert "shape" not in TANK.to_dict() and SPHERE.to_dict()["shape"] == "sphere"
    assert CampaignSpec.from_json(spec.to_json()) == spec
    with pytest.raises(ArgumentError, match="diameter"):
        Tank(radius=0.35, height=0.8, density=1000.0, axial_acceleration=0.1, shape="sphere")
    with pytest.raises(ArgumentError, match="Tank.shape"):
        Tank(radius=0.35, height=0.8, density=1000.0, axial_acceleration=0.1, shape="cone")


def test_a_drift_controller_on_its_own_plant_tracks_exactly(bus):
    """passive='drift' (collocated partial feedback linearization) on a plant equal to its model:
    the actuated joint's error obeys e'' + kd e' + kp e = 0 from e(0) = e'(0) = 0, so it stays at
    integration error; the frozen controller on the same plant errs by far more. The drift
    campaign's error equals a direct simulate under a hand-built drift controller."""
    flex = Flexibility(tank=TANK, fill_fraction=0.5, slosh_damping_ratio=0.005, panel=PANEL, panel_stiffness=25.0)
    kw = dict(duration=3.0, dt=1e-2, kp=4.0, kd=4.0, q_offset=0.8, flexibility=flex)
    drift = run_campaign(bus, samples=2, seed=5, perturbations=NO_ERRORS, scenario=Scenario(passive="drift", **kw),
                         workers=0, progress=False)
    frozen = run_campaign(bus, samples=2, seed=5, perturbations=NO_ERRORS, scenario=Scenario(**kw), workers=0,
                          progress=False)
    e_drift, e_frozen = drift.metric("tracking_error_max"), frozen.metric("tracking_error_max")
    assert drift.n_ok == frozen.n_ok == 2
    assert e_drift.max() < 1e-8 and e_frozen.min() > 1e-4
    model, _ = _hand_plant(0.5, 0.005, 25.0)
    move = QuinticJoint([0.0], [0.8], 0.0, 0.75 * 3.0)
    traj = spacearm.simulate(model, 3.0, x0=model.neutral_configuration(), dt=1e-2,
                             controller=ComputedTorque(4.0, 4.0, move, model=model, passive="drift"))
    q_ref, _, _ = move.evaluate(traj.t)
    assert e_drift[0] == pytest.approx(np.abs(traj.x[:, 7] - q_ref[:, 0]).max(), rel=1e-6, abs=1e-14)
    assert Scenario(passive="drift", **kw).to_dict()["passive"] == "drift" and "passive" not in Scenario().to_dict()
    with pytest.raises(ArgumentError, match="passive must be"):
        Scenario(passive="locked", flexibility=flex)
    with pytest.raises(ArgumentError, match="needs a flexibility recipe"):
        Scenario(passive="drift")


def test_the_cli_runs_flexible_plants_from_a_toml_recipe(tmp_path, capsys):
    # Issue 37 item 5: `spacearm campaign` had no option for tanks or panels. The recipe file is
    # Flexibility.to_dict() as TOML; the CLI's result equals the Python API's on the same recipe.
    from spacearm.campaign import run_campaign
    from spacearm.cli import main

    model = tmp_path / "bus.toml"
    model.write_text(dumps_toml(_bus().build()))
    recipe = tmp_path / "flex.toml"
    recipe.write_text(
        "fill_fraction = { kind = \"uniform\", low = 0.3, high = 0.7 }\n"
        "panel_stiffness = { kind = \"lognormal\", median = 10.0, sigma = 0.2 }\n"
        "[tank]\nradius = 0.3\nheight = 0.8\ndensity = 1000.0\naxial_acceleration = 0.1\nbottom = [0.0, 0.0, -0.35]\n"
        "lateral = [0.0, 1.0, 0.0]\n"
        "[panel]\nhinge_position = [0.0, 0.9, 0.0]\nhinge_axis = [1.0, 0.0, 0.0]\ndirection = [0.0, 1.0, 0.0]\n"
        "mass = 15.0\nsize = [2.0, 1.0, 0.02]\ndamping = 0.2\n")
    out = tmp_path / "c.npz"
    argv = ["campaign", str(model), "--samples", "3", "--duration", "0.2", "--dt", "0.01", "--workers", "0",
            "--no-progress", "--flexibility", str(recipe), "--out", str(out)]
    assert main(argv) == 0
    cli = spacearm.campaign.CampaignResult.load(out)
    assert {"fill_fraction", "panel_stiffness"} <= set(cli.param_names)
    flex = Flexibility(tank=TANK, panel=PANEL, fill_fraction=Uniform(0.3, 0.7), panel_stiffness=LogNormal(10.0, 0.2))
    api = run_campaign(loads_toml(model.read_text()), 3, seed=0, scenario=Scenario(duration=0.2, dt=0.01, flexibility=flex),
                       workers=0, progress=False)
    np.testing.assert_array_equal(cli.metrics, api.metrics)
    # A key the recipe does not know is a clear CLI error.
    recipe.write_text("fill = 0.5\n")
    assert main(argv[:-2] + ["--out", str(tmp_path / "d.npz")]) == 2
    assert "spacearm: error: --flexibility" in capsys.readouterr().err
