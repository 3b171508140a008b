"""CMG parameters as uncertain inputs of a campaign (issue 34 item 4; docs/campaigns.md, "CMG
parameters"): the wheel speed, the rotor inertia and the gimbal-axis misalignment drawn per sample.

Independent references: the plant built by hand with ``RobotBuilder.add_cmg`` at the drawn rotor
inertia and with the misaligned axes written out by Rodrigues' formula (mass matrix equal to
rounding), and a direct ``spacearm.simulate`` of that hand-built plant under a hand-built
computed-torque controller, whose base attitude excursion is computed here from the states.
"""

import numpy as np
import pytest

import spacearm
from cmg_models import J_S, pyramid_axes
from spacearm.campaign import PARAMETER_NAMES, CampaignSpec, CmgUncertainty, Fixed, Perturbations, Scenario, Uniform, run_campaign
from spacearm.campaign.scenario import plant
from spacearm.control import ComputedTorque, QuinticJoint
from spacearm.errors import ArgumentError
from spacearm.io.model_file import dumps_toml, loads_toml

NO_ERRORS = Perturbations(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
GOAL = (0.0,) * 8 + (0.6, -0.5)  # the arm's two joints moved (the CMGs' entries are not arm joints: no reference)


def _sat(rotor_scale=1.0, misalignment=0.0):
    """The 4-CMG pyramid with a two-joint arm of tests/cmg_models.py, built by hand: the rotor
    inertia and the misaligned gimbal axis (ĝ turned by the angle about ŝ₀, Rodrigues) written out."""
    b = spacearm.Robot.builder("cmg-sat", base_mass=200.0, base_inertia=[30.0, 34.0, 38.0])
    for i, (g, s) in enumerate(zip(*pyramid_axes())):
        c, sn = np.cos(misalignment), np.sin(misalignment)
        g2 = c * g + sn * np.cross(s, g)  # s ⟂ g: the k(k·v) term of Rodrigues' formula is zero
        # The gimbal's principal axes turn with the unit: (ĝ, ŝ₀, ĝ × ŝ₀) → (ĝ', ŝ₀, ĝ' × ŝ₀).
        b.add_cmg(f"cmg{i + 1}", position=0.3 * np.cross(g, s), gimbal_axis=g2, spin_axis=s, rotor_inertia=rotor_scale * J_S,
                  rotor_transverse_inertia=0.6 * rotor_scale * J_S, gimbal_inertia=[0.02, 0.015, 0.018], rotor_mass=3.0,
                  gimbal_mass=1.5, max_wheel_speed=800.0)
    b.add_link("upper", joint="revolute", axis=(0, 1, 0), origin=(0.8, 0, 0.2), com=(0.5, 0, 0), mass=6.0, inertia=[0.02, 0.5, 0.5])
    b.add_link("fore", parent="upper", joint="revolute", axis=(0, 0, 1), origin=(1.0, 0, 0), com=(0.4, 0, 0), mass=4.0,
               inertia=[0.01, 0.2, 0.2])
    return b.build()


@pytest.fixture(scope="module")
def sat():
    return loads_toml(dumps_toml(_sat()))  # as a campaign's workers see it: through the spec's TOML


def test_draws_are_reproducible_and_leave_the_inertia_draws_alone(sat):
    cmg = CmgUncertainty(wheel_speed=Uniform(100.0, 600.0), rotor_inertia_scale=spacearm.campaign.LogNormal(1.0, 0.05),
                         gimbal_misalignment=spacearm.campaign.Normal(0.0, 0.01))
    plain = CampaignSpec(dumps_toml(sat), 4, seed=3)
    spec = CampaignSpec(dumps_toml(sat), 4, seed=3, scenario=Scenario(cmg=cmg))
    assert spec.param_names == PARAMETER_NAMES + ("cmg_wheel_speed", "cmg_rotor_inertia_scale", "cmg_gimbal_misalignment")
    speeds = []
    for i in range(4):
        d = spec.draw(i)
        assert {n: d[n] for n in PARAMETER_NAMES} == plain.draw(i)
        assert d == spec.draw(i) and 100.0 <= d["cmg_wheel_speed"] <= 600.0
        speeds.append(d["cmg_wheel_speed"])
    assert len(set(speeds)) == 4
    assert CampaignSpec.from_json(spec.to_json()) == spec and '"cmg":' not in plain.to_json() and '"cmg":' in spec.to_json()
    assert cmg.nominal() == {"cmg_wheel_speed": 350.0, "cmg_rotor_inertia_scale": 1.0, "cmg_gimbal_misalignment": 0.0}


def test_a_samples_plant_equals_the_plant_built_by_hand(sat):
    cmg = CmgUncertainty(rotor_inertia_scale=Uniform(0.8, 1.2), gimbal_misalignment=Uniform(-0.02, 0.02))
    spec = CampaignSpec(dumps_toml(sat), 3, seed=11, perturbations=NO_ERRORS, scenario=Scenario(cmg=cmg))
    rng = np.random.default_rng(0)
    for i in range(3):
        params = spec.draw(i)
        p = plant(sat, params, None, cmg)
        hand = _sat(params["cmg_rotor_inertia_scale"], params["cmg_gimbal_misalignment"])
        assert abs(params["cmg_gimbal_misalignment"]) > 1e-4 and params["cmg_rotor_inertia_scale"] != 1.0
        for name, c in p.cmg_dofs.items():
            h = hand.cmg_dofs[name]
            assert c["rotor_inertia"] == pytest.approx(h["rotor_inertia"], rel=1e-15)
            assert np.allclose(c["gimbal_axis"], h["gimbal_axis"], rtol=0, atol=1e-15)
            assert np.array_equal(c["spin_axis"], h["spin_axis"])
        x = hand.neutral_configuration(q=rng.uniform(-1, 1, hand.n_dof))
        h1, h2 = p.mass_matrix(x), hand.mass_matrix(x)
        assert np.linalg.norm(h1 - h2) <= 1e-14 * np.linalg.norm(h2)
        assert np.linalg.norm(h2 - sat.mass_matrix(x)) > 1e-6 * np.linalg.norm(h2)  # the edit changed something


def test_wheel_speed_campaign_matches_a_direct_simulation_and_stiffens_the_base(sat):
    """The arm laws leave the CMGs free (they are not arm joints); their spinning rotors stiffen the
    base against the arm's reaction: the more momentum they hold, the less the base turns."""
    scenario = Scenario(duration=1.0, dt=5e-3, kp=100.0, kd=20.0, q_goal=GOAL, cmg=CmgUncertainty(wheel_speed=Uniform(0.0, 600.0)))
    result = run_campaign(sat, samples=5, seed=4, perturbations=NO_ERRORS, scenario=scenario, workers=1, progress=False)
    assert result.run["backend"] == "threads" and result.n_ok == 5
    speeds = result.parameter("cmg_wheel_speed")
    excursion = result.metric("attitude_excursion_max")
    model = _sat()  # the controller's model: the nominal plant (no model holds a wheel speed)
    q0 = model.initial_q
    arm = model.actuated_arm_dofs
    assert arm == [8, 9]
    move = QuinticJoint(np.asarray(q0)[arm], np.asarray(GOAL)[arm], 0.0, 0.75)
    for i, w in enumerate(speeds):
        traj = spacearm.simulate(model, 1.0, x0=model.neutral_configuration(), u0=model.cmg_velocity(w), dt=5e-3,
                                 controller=ComputedTorque(100.0, 20.0, move, model=model))
        quat = traj.x[:, 3:7]
        angle = np.degrees(2 * np.arccos(np.clip(np.abs(quat @ quat[0]), 0, 1))).max()
        assert excursion[i] == pytest.approx(angle, rel=1e-9)
    order = np.argsort(speeds)
    assert np.all(np.diff(excursion[order]) < 0), (speeds[order], excursion[order])
    assert excursion[order][0] > 2 * excursion[order][-1]


def test_bad_recipes_are_errors(sat):
    with pytest.raises(ArgumentError, match="rotor_inertia_scale"):
        CmgUncertainty(rotor_inertia_scale=Uniform(-0.1, 1.0))
    with pytest.raises(ArgumentError, match="distribution"):
        CmgUncertainty(wheel_speed="fast")
    with pytest.raises(ArgumentError, match="CmgUncertainty"):
        Scenario(cmg=3.0)
    bare = spacearm.presets.planar4()
    with pytest.raises(ArgumentError, match="has none"):
        CmgUncertainty(rotor_inertia_scale=1.1).apply(bare, {"cmg_rotor_inertia_scale": 1.1, "cmg_gimbal_misalignment": 0.0})
    # a campaign on a model without CMGs is refused before any sample runs, not failed per sample
    with pytest.raises(ArgumentError, match="has none"):
        run_campaign(bare, samples=2, scenario=Scenario(cmg=CmgUncertainty(wheel_speed=10.0)), backend="in-process")
    assert Fixed(2.0).nominal == 2.0


def test_the_cli_reads_the_recipe_from_toml(sat, tmp_path, capsys):
    from spacearm.cli import main

    model = tmp_path / "sat.toml"
    model.write_text(dumps_toml(sat))
    recipe = tmp_path / "cmg.toml"
    recipe.write_text('wheel_speed = { kind = "uniform", low = 100.0, high = 500.0 }\nrotor_inertia_scale = 1.05\n')
    out = tmp_path / "c.npz"
    argv = ["campaign", str(model), "--samples", "2", "--duration", "0.1", "--dt", "0.01", "--workers", "0",
            "--no-progress", "--cmg", str(recipe), "--out", str(out)]
    assert main(argv) == 0
    cli = spacearm.campaign.CampaignResult.load(out)
    assert cli.param_names[-3:] == ("cmg_wheel_speed", "cmg_rotor_inertia_scale", "cmg_gimbal_misalignment")
    api = run_campaign(loads_toml(model.read_text()), 2, seed=0, workers=0, progress=False,
                       scenario=Scenario(duration=0.1, dt=0.01, cmg=CmgUncertainty(Uniform(100.0, 500.0), 1.05)))
    np.testing.assert_array_equal(cli.metrics, api.metrics)
    assert np.all((cli.parameter("cmg_wheel_speed") >= 100.0) & (cli.parameter("cmg_wheel_speed") <= 500.0))
    recipe.write_text("speed = 300.0\n")
    assert main(argv[:-2] + ["--out", str(tmp_path / "d.npz")]) == 2
    assert "spacearm: error: --cmg" in capsys.readouterr().err


def test_a_wheel_speed_beyond_the_rotors_limit_fails_that_sample_only(sat):
    # max_wheel_speed is 800 rad/s: the samples drawing more fail with the core's message, the others fly.
    scenario = Scenario(duration=0.05, dt=5e-3, q_goal=GOAL, cmg=CmgUncertainty(wheel_speed=Uniform(0.0, 1600.0)))
    result = run_campaign(sat, samples=6, seed=1, perturbations=NO_ERRORS, scenario=scenario, workers=1, progress=False)
    fast = result.params[:, result.param_names.index("cmg_wheel_speed")] > 800.0
    assert 0 < fast.sum() < 6 and result.n_failed == fast.sum() and result.n_ok == 6 - fast.sum()
    assert sorted(result.failures()) == np.flatnonzero(fast).tolist()
    assert all("max_wheel_speed" in message for message in result.failures().values())
