//! Soft capture: a robot and a free target model coupled by a grasp spring–damper (a wrist
//! impedance), integrated as one system by the core's integrators ([`crate::math::integrate`])
//! and recorded, body by body, by the simulation's recorder (docs/capture.md, "The captured
//! system").
//!
//! The robot is a [`Plant`] under a native controller (the joint law of the soft phase, e.g. the
//! hold law `ComputedTorque` with a constant reference); the target is a [`Plant`] with zero
//! torques. At every evaluation the impedance's wrench is computed from both states and applied
//! as a body wrench of each plant:
//!
//! - force `f = K (p − X) + D (ṗ − Ẋ)` at the robot's grasp point `X` (`p` the target's grasp
//!   point);
//! - couple `n = K_r θ + D_r (ω_t − ω_g)`, `θ` the rotation vector of `R_t (R_g R_0)ᵀ` (the
//!   gripper's frame `R_g` carried with the relative attitude `R_0 = R_g(0)ᵀ R_t(0)` it had at
//!   contact, to the target's grasped body `R_t`);
//!
//! `[f; n]` acts on the robot at `X` and `[−f; −n]` on the target's material point at `X`: an
//! internal wrench, so robot + target momentum is conserved (to the integrator's accuracy).
//!
//! Gains not given come from a frequency `ω` and a damping ratio `ζ` on the lightest direction of
//! the grasp: `K = ω² / g`, `D = 2ζω / g` with `g` the largest eigenvalue of the translational
//! (rotational) block of `G_r + G_t`, the inverse inertias at the two grasp points
//! ([`crate::algorithms::impulse::contact_response`]).
//!
//! The run's state is `y = [x_r; u_r; x_t; u_t]`; RK4 steps at `t_i = i·dt`, or the simulation's
//! one DOPRI5 loop ([`crate::sim::simulate::dopri5_loop`]) with error control over all of `y`
//! and samples every `dt`.

use nalgebra::{DMatrix, Matrix3, SymmetricEigen, Vector3, Vector6};

use crate::algorithms::impulse::{contact_response, BodyPoint, JointsAtImpact};
use crate::algorithms::kinematics::{check_body, forward_kinematics, point_jacobians, point_position};
use crate::algorithms::momentum::{conserved_drift, momentum_scales_from_data, MomentumScales};
use crate::algorithms::rnea::velocity_pass;
use crate::algorithms::wrench::ExternalWrench;
use crate::control::{Controller, ZeroTorque};
use crate::error::{check_finite, Result, SpacearmError};
use crate::math::rotations::rotation_vector;
use crate::model::data::Data;
use crate::model::Model;
use crate::math::integrate::{IntegratorKind, OdeSystem, Rk4};
use crate::scenario::modes::Mode;
use crate::sim::record::{onsets, Recorder};
use crate::sim::simulate::{
    admit_records, check_initial_state, dopri5_loop, finish_result, rk4_step_count, sample_count, DopriWords, Plant, Progress, SaturationEvent, SimOptions,
    SimResult, StepWatch,
};

/// The wrist impedance: translational and rotational stiffness and damping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GraspImpedance {
    /// `K`, N/m.
    pub stiffness: f64,
    /// `D`, N·s/m.
    pub damping: f64,
    /// `K_r`, N·m/rad.
    pub rotational_stiffness: f64,
    /// `D_r`, N·m·s/rad.
    pub rotational_damping: f64,
}

/// The impedance's gains: each one given, or `None` for the value from `frequency` (rad/s) and
/// `damping_ratio` (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImpedanceSpec {
    /// `ω`, rad/s (> 0).
    pub frequency: f64,
    /// `ζ` (≥ 0).
    pub damping_ratio: f64,
    /// `K`, or `None`.
    pub stiffness: Option<f64>,
    /// `D`, or `None`.
    pub damping: Option<f64>,
    /// `K_r`, or `None`.
    pub rotational_stiffness: Option<f64>,
    /// `D_r`, or `None`.
    pub rotational_damping: Option<f64>,
}

/// What [`soft_capture`] returns.
#[derive(Debug, Clone)]
pub struct SoftCaptureResult {
    /// The robot's records (its plant, its controller).
    pub robot: SimResult,
    /// The target's records (zero torques).
    pub target: SimResult,
    /// The impedance's wrench on the robot at `X`, `[f; n]` in 𝒥, one row of 6 per sample.
    pub wrench: Vec<f64>,
    /// The gains used.
    pub gains: GraspImpedance,
    /// Drift of robot + target linear momentum and angular momentum about the origin over the
    /// samples, relative to the largest sum of the two bodies' momentum scales (the one
    /// definition of drift, docs/simulation-core.md).
    pub drift: [f64; 2],
}

/// The coupled system as an ODE for the integrators.
struct SoftCapture<'a> {
    robot: Plant<'a>,
    target: Plant<'a>,
    robot_point: BodyPoint,
    target_point: BodyPoint,
    gains: GraspImpedance,
    rest: Matrix3<f64>,
    /// Dimensions of the robot's `[x; u]` and `x`, the target's `x`.
    ny_r: usize,
    nx_r: usize,
    nx_t: usize,
    /// The last wrench on the robot `[f; n]`.
    wrench: Vector6<f64>,
    pair: [ExternalWrench; 1],
}

/// Twist `[v; ω]` in 𝒥 of a world point `p` moving with `body`, from the body velocities in
/// `data` (at the base CM: `v_p = v_O + ω × (p − r0)`).
fn point_twist(data: &Data, body: usize, p: &Vector3<f64>) -> Vector6<f64> {
    let v = data.body_velocity[body];
    let (lin, ang) = (v.fixed_rows::<3>(0).into_owned(), v.fixed_rows::<3>(3).into_owned());
    let vp = lin + ang.cross(&(p - data.base_position));
    Vector6::new(vp.x, vp.y, vp.z, ang.x, ang.y, ang.z)
}

impl SoftCapture<'_> {
    /// The impedance's wrench at the state `y` (kinematics and body velocities of both plants'
    /// workspaces brought to `y`), and the two body wrenches set on the plants.
    fn couple(&mut self, y: &[f64]) -> Result<()> {
        let (yr, yt) = y.split_at(self.ny_r);
        let (xr, ur) = yr.split_at(self.nx_r);
        let (xt, ut) = yt.split_at(self.nx_t);
        forward_kinematics(&self.robot.model, &mut self.robot.data, xr)?;
        velocity_pass(&self.robot.model, &mut self.robot.data, ur);
        forward_kinematics(&self.target.model, &mut self.target.data, xt)?;
        velocity_pass(&self.target.model, &mut self.target.data, ut);
        let (rd, td) = (&self.robot.data, &self.target.data);
        let (gb, tb) = (self.robot_point.body, self.target_point.body);
        let x_point = point_position(rd, gb, &self.robot_point.offset);
        let p = point_position(td, tb, &self.target_point.offset);
        let (tw_r, tw_p) = (point_twist(rd, gb, &x_point), point_twist(td, tb, &p));
        let rt = td.body_to_world[tb];
        let theta = rotation_vector(&(rt * (rd.body_to_world[gb] * self.rest).transpose()));
        let g = &self.gains;
        let dv = tw_p - tw_r;
        let f = (p - x_point) * g.stiffness + dv.fixed_rows::<3>(0) * g.damping;
        let n = theta * g.rotational_stiffness + dv.fixed_rows::<3>(3) * g.rotational_damping;
        self.wrench = Vector6::new(f.x, f.y, f.z, n.x, n.y, n.z);
        let at_target = rt.transpose() * (x_point - td.com_in_world[tb]);
        self.pair[0] = ExternalWrench { body: gb, offset: self.robot_point.offset, force: f, torque: n };
        self.robot.set_body_wrenches(&self.pair)?;
        self.pair[0] = ExternalWrench { body: tb, offset: at_target, force: -f, torque: -n };
        self.target.set_body_wrenches(&self.pair)?;
        Ok(())
    }
}

impl StepWatch for SoftCapture<'_> {
    fn clear_step_flags(&mut self) {
        self.robot.clear_step_flags();
    }

    fn step_flags(&self) -> &[u8] {
        self.robot.step_flags()
    }

    fn take_nonfinite_stage(&mut self) -> bool {
        self.robot.take_nonfinite_stage()
    }

    fn watched_plant(&self) -> &Plant<'_> {
        &self.robot
    }

    fn watched_state<'y>(&self, y: &'y [f64]) -> &'y [f64] {
        &y[..self.ny_r]
    }

    fn begin_step(&mut self, t: f64, y: &[f64]) -> Result<()> {
        self.robot.sample(t, &y[..self.ny_r])
    }
}

impl OdeSystem for SoftCapture<'_> {
    fn dim(&self) -> usize {
        self.ny_r + self.target.dim()
    }

    fn project(&self, y: &mut [f64]) {
        let (yr, yt) = y.split_at_mut(self.ny_r);
        self.robot.project(yr);
        self.target.project(yt);
    }

    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<()> {
        if let Some(i) = y.iter().position(|v| !v.is_finite()) {
            self.robot.nonfinite_stage = true;
            return Err(SpacearmError::Simulation(format!(
                "the soft capture's state became non-finite at t = {t} s (entry {i} of [x_r; u_r; x_t; u_t]): the motion diverged — lower \
                 the impedance's gains or dt"
            )));
        }
        self.couple(y)?;
        let (yr, yt) = y.split_at(self.ny_r);
        let (dr, dt) = dy.split_at_mut(self.ny_r);
        self.robot.rhs(t, yr, dr)?;
        self.target.rhs(t, yt, dt)
    }
}

/// The records of both plants and of the wrench.
struct Recorders {
    robot: Recorder,
    target: Recorder,
    wrench: Vec<f64>,
    /// Per sample: robot + target `P` and `L_origin` (6), for the combined drift.
    ledger: Vec<f64>,
    scales: MomentumScales,
}

impl Recorders {
    fn record(&mut self, sys: &SoftCapture<'_>, t: f64, y: &[f64], dy: &[f64]) {
        let n = sys.ny_r;
        self.robot.record(&sys.robot, t, &y[..n], &dy[..n]);
        self.target.record(&sys.target, t, &y[n..], &dy[n..]);
        self.wrench.extend_from_slice(sys.wrench.as_slice());
        let (r, g) = (&self.robot.rec, &self.target.rec);
        let k = r.n_samples - 1;
        for c in 0..3 {
            self.ledger.push(r.linear_momentum[3 * k + c] + g.linear_momentum[3 * k + c]);
        }
        for c in 0..3 {
            self.ledger.push(r.angular_momentum_origin[3 * k + c] + g.angular_momentum_origin[3 * k + c]);
        }
        let (a, b) = (momentum_scales_from_data(sys.robot.model(), sys.robot.data()), momentum_scales_from_data(sys.target.model(), sys.target.data()));
        let sum = MomentumScales {
            linear: a.linear + b.linear,
            angular_about_origin: a.angular_about_origin + b.angular_about_origin,
            angular_about_com: a.angular_about_com + b.angular_about_com,
            energy: a.energy + b.energy,
        };
        self.scales = self.scales.max(sum);
    }
}

/// The gains of `spec` at the initial states (module docs).
fn gains_of(
    robot: &Model,
    x: &[f64],
    robot_point: BodyPoint,
    target: &Model,
    xt: &[f64],
    target_point: BodyPoint,
    spec: &ImpedanceSpec,
) -> Result<GraspImpedance> {
    let (w, z) = (spec.frequency, spec.damping_ratio);
    if !(w.is_finite() && w > 0.0 && z.is_finite() && z >= 0.0) {
        return Err(SpacearmError::argument(format!("frequency must be > 0 and damping_ratio >= 0, got {w}, {z}")));
    }
    let mut g = Matrix3::zeros();
    let mut g_rot = Matrix3::zeros();
    for (model, xx, pt) in [(robot, x, robot_point), (target, xt, target_point)] {
        let mut data = Data::new(model);
        forward_kinematics(model, &mut data, xx)?;
        let (j0, jm) = point_jacobians(model, &data, pt.body, &pt.offset)?;
        let mut j = DMatrix::zeros(6, model.nu());
        j.view_mut((0, 0), (6, 6)).copy_from(&j0);
        j.view_mut((0, 6), (6, model.n_dof())).copy_from(&jm);
        let r = contact_response(model, &mut data, xx, &j, JointsAtImpact::Free)?;
        g += r.delassus.fixed_view::<3, 3>(0, 0);
        g_rot += r.delassus.fixed_view::<3, 3>(3, 3);
    }
    let largest = |m: Matrix3<f64>| SymmetricEigen::new(m).eigenvalues.max();
    let (gl, gr) = (largest(g), largest(g_rot));
    let pick = |given: Option<f64>, default: f64, name: &str| -> Result<f64> {
        let v = given.unwrap_or(default);
        if !(v.is_finite() && v >= 0.0) {
            return Err(SpacearmError::argument(format!("impedance gains must be finite and >= 0, got {name} = {v}")));
        }
        Ok(v)
    };
    Ok(GraspImpedance {
        stiffness: pick(spec.stiffness, w * w / gl, "stiffness")?,
        damping: pick(spec.damping, 2.0 * z * w / gl, "damping")?,
        rotational_stiffness: pick(spec.rotational_stiffness, w * w / gr, "rotational_stiffness")?,
        rotational_damping: pick(spec.rotational_damping, 2.0 * z * w / gr, "rotational_damping")?,
    })
}

/// Integrate the soft capture of the target model (state `(x_target, u_target)`, grasp point
/// `target_point`) by the robot (state `(x, u)`, grasp point `robot_point`, joint law
/// `controller`) for `opts.duration` s (module docs). `opts`: the integrator, `dt`, tolerances,
/// `record_every`, joint limits and wheels of the robot's plant; the mode must be floating (the
/// soft phase is unactuated at the base). The rest pose is the relative attitude at the start.
#[allow(clippy::too_many_arguments)]
pub fn soft_capture(
    robot: &Model,
    x: &[f64],
    u: &[f64],
    robot_point: BodyPoint,
    target: &Model,
    x_target: &[f64],
    u_target: &[f64],
    target_point: BodyPoint,
    impedance: &ImpedanceSpec,
    opts: &SimOptions,
    controller: &mut dyn Controller,
    progress: Progress<'_>,
) -> Result<SoftCaptureResult> {
    opts.validate()?;
    opts.refuse_stop("soft_capture")?;
    opts.refuse_contact("soft_capture")?;
    if opts.mode != Mode::Floating {
        return Err(SpacearmError::argument(format!("the soft capture runs in floating mode (no base actuation), got mode '{}'", opts.mode.name())));
    }
    check_initial_state(robot, x, u)?;
    check_initial_state(target, x_target, u_target).map_err(|e| SpacearmError::argument(format!("the target's state: {e}")))?;
    check_body(robot, robot_point.body)?;
    check_body(target, target_point.body)?;
    check_finite("the robot's grasp offset", robot_point.offset.as_slice())?;
    check_finite("the target's grasp offset", target_point.offset.as_slice())?;
    let gains = gains_of(robot, x, robot_point, target, x_target, target_point, impedance)?;

    let mut zero = ZeroTorque;
    let target_opts = SimOptions { wheels: Some(Vec::new()), thrusters: None, ..opts.clone() };
    let robot_plant = Plant::new(robot, opts, controller)?;
    let target_plant = Plant::new(target, &target_opts, &mut zero)?;
    let samples = sample_count(opts);
    let per_sample = Recorder::values_per_sample_of(&robot_plant) + Recorder::values_per_sample_of(&target_plant) + 12;
    admit_records(opts.integrator, samples as f64, (samples * per_sample) as f64)?;

    // The rest attitude: gripper -> grasped body of the target, at contact.
    let mut dr = Data::new(robot);
    forward_kinematics(robot, &mut dr, x)?;
    let mut dt = Data::new(target);
    forward_kinematics(target, &mut dt, x_target)?;
    let rest = dr.body_to_world[robot_point.body].transpose() * dt.body_to_world[target_point.body];

    let mut recs = Recorders {
        robot: Recorder::for_plant(&robot_plant, samples),
        target: Recorder::for_plant(&target_plant, samples),
        wrench: Vec::with_capacity(6 * samples),
        ledger: Vec::with_capacity(6 * samples),
        scales: MomentumScales::default(),
    };
    let n_r = robot.n_dof();
    let mut sys = SoftCapture {
        ny_r: robot.nx() + robot.nu(),
        nx_r: robot.nx(),
        nx_t: target.nx(),
        robot: robot_plant,
        target: target_plant,
        robot_point,
        target_point,
        gains,
        rest,
        wrench: Vector6::zeros(),
        pair: [ExternalWrench { body: 0, offset: Vector3::zeros(), force: Vector3::zeros(), torque: Vector3::zeros() }],
    };
    let mut y: Vec<f64> = x.iter().chain(u).chain(x_target).chain(u_target).copied().collect();
    sys.project(&mut y);
    let dim = y.len();
    let mut dy = vec![0.0; dim];
    let mut events: Vec<SaturationEvent> = Vec::new();
    let mut prev_flags = vec![0u8; n_r + 6];
    let (mut n_steps, mut n_rejected) = (0usize, 0usize);
    let n_out = rk4_step_count(opts);
    let out_time = |k: usize| if k == n_out { opts.duration } else { k as f64 * opts.dt };
    let progress_every = opts.duration / 1000.0;
    let mut next_progress = 0.0;
    match opts.integrator {
        IntegratorKind::Rk4 => {
            let mut rk = Rk4::new(dim);
            for i in 0..n_out {
                let t = out_time(i);
                sys.robot.flags_step.fill(0);
                let record_now = i % opts.record_every == 0;
                if record_now {
                    sys.rhs(t, &y, rk.k1_mut())?;
                    recs.record(&sys, t, &y, rk.k1());
                }
                let t_next = out_time(i + 1);
                rk.step(&mut sys, t, t_next - t, &mut y, record_now)?;
                n_steps += 1;
                onsets(t, &mut prev_flags, &sys.robot.flags_step, &mut events);
                if t_next >= next_progress {
                    progress(t_next / opts.duration)?;
                    next_progress = t_next + progress_every;
                }
            }
            sys.rhs(opts.duration, &y, &mut dy)?;
            recs.record(&sys, opts.duration, &y, &dy);
        }
        IntegratorKind::Dopri5 => {
            let words = DopriWords { of_run: " of the soft capture", budget_remedy: "", stiff_remedy: "lower the impedance's gains or use rk4" };
            let run = dopri5_loop(&mut sys, &mut y, opts, &words, None, &mut *progress, &mut |sys, t, y, dy| recs.record(sys, t, y, dy))?;
            (n_steps, n_rejected, events) = (run.n_steps, run.n_rejected, run.events);
        }
    }
    progress(1.0)?;
    let drift = [
        conserved_drift(&recs.ledger_part(0), 3, recs.scales.linear),
        conserved_drift(&recs.ledger_part(3), 3, recs.scales.angular_about_origin),
    ];
    let robot_result = finish_result(&sys.robot, recs.robot, events, n_steps, n_rejected);
    let target_result = finish_result(&sys.target, recs.target, Vec::new(), n_steps, n_rejected);
    Ok(SoftCaptureResult { robot: robot_result, target: target_result, wrench: recs.wrench, gains, drift })
}

impl Recorders {
    /// Three columns of the ledger from `first`, row-major.
    fn ledger_part(&self, first: usize) -> Vec<f64> {
        self.ledger.chunks_exact(6).flat_map(|r| r[first..first + 3].iter().copied()).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algorithms::momentum::kinetic_energy;
    use crate::model::presets::{initial_configuration, spatial6};
    use crate::model::ModelBuilder;

    #[test]
    fn without_damping_momentum_and_energy_with_the_springs_are_conserved() {
        let robot = spatial6();
        let target = ModelBuilder::new("t", "t", 50.0, [[4.0, 0.1, 0.0], [0.1, 5.0, 0.0], [0.0, 0.0, 6.0]]).unwrap().build().unwrap();
        let mut x = initial_configuration(&robot);
        x[7..].iter_mut().enumerate().for_each(|(j, q)| *q += 0.2 * (j as f64).cos());
        let u: Vec<f64> = (0..robot.nu()).map(|k| 0.02 * (k as f64 * 0.9).sin()).collect();
        let ee = &robot.points()[robot.end_effector().unwrap()];
        let rp = BodyPoint { body: ee.body, offset: ee.offset };
        let mut d = Data::new(&robot);
        forward_kinematics(&robot, &mut d, &x).unwrap();
        let xp = point_position(&d, rp.body, &rp.offset);
        let xt = [xp.x + 0.5, xp.y, xp.z, 0.0, 0.0, 0.0, 1.0];
        let ut = [0.01, -0.02, 0.0, 0.05, 0.0, 0.2];
        let tp = BodyPoint { body: 0, offset: Vector3::new(-0.5, 0.0, 0.0) };
        let spec = ImpedanceSpec {
            frequency: 3.0,
            damping_ratio: 0.0,
            stiffness: None,
            damping: None,
            rotational_stiffness: None,
            rotational_damping: None,
        };
        let opts = SimOptions { integrator: IntegratorKind::Dopri5, duration: 2.0, dt: 0.01, rtol: 1e-11, atol: 1e-13, ..SimOptions::default() };
        let r = soft_capture(&robot, &x, &u, rp, &target, &xt, &ut, tp, &spec, &opts, &mut ZeroTorque, &mut |_| Ok(())).unwrap();
        assert!(r.gains.stiffness > 0.0 && r.gains.damping == 0.0);
        assert!(r.drift[0] < 1e-9 && r.drift[1] < 1e-9, "{:?}", r.drift);
        // T + ½ K |p − X|² + ½ K_r |θ|² at every sample.
        let (nr, nt) = (r.robot.records.n_samples, r.target.records.n_samples);
        assert_eq!(nr, nt);
        let (mut dr, mut dt) = (Data::new(&robot), Data::new(&target));
        let g = r.gains;
        let energy = |k: usize, dr: &mut Data, dt: &mut Data| {
            let (xr, ur) = (&r.robot.records.x[k * robot.nx()..(k + 1) * robot.nx()], &r.robot.records.u[k * robot.nu()..(k + 1) * robot.nu()]);
            let (xs, us) = (&r.target.records.x[k * 7..(k + 1) * 7], &r.target.records.u[k * 6..(k + 1) * 6]);
            let t = kinetic_energy(&robot, dr, xr, ur).unwrap() + kinetic_energy(&target, dt, xs, us).unwrap();
            forward_kinematics(&robot, dr, xr).unwrap();
            forward_kinematics(&target, dt, xs).unwrap();
            let (xp, p) = (point_position(dr, rp.body, &rp.offset), point_position(dt, tp.body, &tp.offset));
            let rest = {
                let (mut a, mut b) = (Data::new(&robot), Data::new(&target));
                forward_kinematics(&robot, &mut a, &x).unwrap();
                forward_kinematics(&target, &mut b, &xt).unwrap();
                a.body_to_world[rp.body].transpose() * b.body_to_world[0]
            };
            let theta = rotation_vector(&(dt.body_to_world[0] * (dr.body_to_world[rp.body] * rest).transpose()));
            t + 0.5 * g.stiffness * (p - xp).norm_squared() + 0.5 * g.rotational_stiffness * theta.norm_squared()
        };
        let e0 = energy(0, &mut dr, &mut dt);
        let mut worst: f64 = 0.0;
        let mut moved: f64 = 0.0;
        for k in 0..nr {
            worst = worst.max((energy(k, &mut dr, &mut dt) - e0).abs());
            moved = moved.max(r.wrench[6 * k..6 * k + 6].iter().map(|v| v.abs()).fold(0.0, f64::max));
        }
        assert!(moved > 1e-3, "the spring must act");
        assert!(worst < 1e-8 * e0, "energy drift {worst:e} of {e0:e}");
    }
}
