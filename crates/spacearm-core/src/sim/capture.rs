//! The capture mission as one native run of phases (docs/capture.md): approach → capture →
//! post-capture → detumble, each phase a run of the simulation loop ([`simulate`]) or of the
//! soft-capture plant ([`crate::sim::soft_capture`]), the grasp the core's impulse
//! ([`crate::algorithms::impulse::grasp_impact`]) and model edit ([`ModelBuilder::attach_model`]),
//! the records of every phase put end to end and the momentum ledger of robot + target computed
//! from them ([`crate::sim::capture_ledger`]).
//!
//! 0. **approach** — [`ControllerSpec::ResolvedMotionRate`] of the robot's grasp point towards the
//!    target's grasp point, a [`PointReferenceSpec::FreeBody`] (paper eq. 110), in the flying mode
//!    [`ControllerSpec::Combined`] with [`ControllerSpec::MomentumDamping`] of the base, clamped by
//!    [`ControllerSpec::TorqueLimit`]; stopped by [`StopCondition::Gap`] when the two grasp points
//!    come within `capture_tolerance` (located within the step, [`crate::sim::events`]). The
//!    target's states are its free-body propagation at the recorded times.
//! 1. **capture** — `rigid`/`point`: the impulse, one sample after the jump at the same instant;
//!    `soft`: the wrist impedance for `soft_time` (samples every `dt / 5`), then a rigid lock.
//! 2. **post-capture** — the captured system (rigid, soft: the target attached on a fixed joint
//!    at its relative pose; point: the robot alone, the target flying off) with the joints
//!    braked (`kp = 0`), floating.
//! 3. **detumble** — the hold law [`ControllerSpec::ComputedTorque`] with a constant reference
//!    (in the flying mode with [`ControllerSpec::MomentumDamping`]), in `mode`.
//!
//! Rigid targets in empty space; `spacearm.capture.capture` runs captures in orbit and of jointed
//! targets by its own phases (docs/capture.md says which).

use nalgebra::{DVector, Matrix3, Vector3};

use crate::algorithms::impulse::{grasp_impact, BodyPoint, GraspContact, GraspImpact, JointsAtImpact};
use crate::algorithms::kinematics::{forward_kinematics, point_jacobians, point_position};
use crate::algorithms::rnea::joint_wrench;
use crate::control::spec::{no_external, BodySpec, ControllerSpec, Gains, InertiaSpec, JointReferenceSpec, PointReferenceSpec, PointSpec, TaskSpec};
use crate::error::{Result, SpacearmError};
use crate::math::integrate::IntegratorKind;
use crate::math::rotations::xyzw_from_matrix;
use crate::model::edit::Mount;
use crate::model::{Data, Model};
use crate::scenario::actuators::detect_reaction_wheels;
use crate::scenario::free_body::{FreeBody, FreeBodySpec};
use crate::scenario::modes::Mode;
use crate::sim::capture_ledger::{ledger, Ledger};
use crate::sim::capture_spec::{fmt_g, fmt_repr, CaptureSpec};
use crate::scenario::orbit::Orbit;
use crate::sim::options::{OrbitOptions, SimOptions, DEFAULT_MAX_STEPS};
use crate::sim::simulate::{check_initial_state, simulate, Progress, SimResult};
use crate::sim::soft_capture::{soft_capture, ImpedanceSpec};
use crate::sim::stop::{StopCondition, StopEvent};

/// The captured system after a rigid or soft grasp: the combined model (the target a link on a
/// fixed joint of the gripper) and its state at the grasp.
#[derive(Debug, Clone)]
pub struct CapturedSystem {
    /// The combined model.
    pub model: Model,
    /// Configuration at the grasp (the robot's: the payload adds no coordinate).
    pub x: Vec<f64>,
    /// Velocity just after the grasp.
    pub u: Vec<f64>,
    /// The target's link name.
    pub payload: String,
    /// The body it rides on.
    pub gripper: String,
}

/// A capture's momentum balance in orbit (docs/orbit.md, "Capture in orbit"), every array with
/// one row per sample.
#[derive(Debug, Clone)]
pub struct CaptureInOrbit {
    /// The external wrench on robot + target about the origin: the tidal wrenches and the
    /// thrusters', width 6.
    pub external_wrench: Vec<f64>,
    /// Its integral from 0 by the trapezoid rule over the samples, width 6.
    pub external_impulse: Vec<f64>,
    /// The chaser's system CM in ECI (the robot before the grasp, robot + target after), width 3.
    pub r_cm_eci: Vec<f64>,
    /// Its velocity in ECI, width 3.
    pub v_cm_eci: Vec<f64>,
    /// The target's CM relative to the robot's own CM in the robot's LVLH, width 6.
    pub target_lvlh: Vec<f64>,
}

/// A capture mission's records, every array row-major with one row per sample.
#[derive(Debug, Clone)]
pub struct CaptureRun {
    /// Sample times, s.
    pub t: Vec<f64>,
    /// Phase index per sample ([`crate::sim::capture_spec::PHASES`]).
    pub phase: Vec<i64>,
    /// Robot configurations (width `7 + N`).
    pub x: Vec<f64>,
    /// Robot velocities (width `6 + N`).
    pub u: Vec<f64>,
    /// Joint torques applied (width `N`).
    pub tau: Vec<f64>,
    /// Base wrench applied (width 6).
    pub base_wrench: Vec<f64>,
    /// Target states `[r, quat, v, ω]` (width 13).
    pub target: Vec<f64>,
    /// The wrench `[f; n]` holding the target (moment about its CM; zeros while it is free), width 6.
    pub grasp_wrench: Vec<f64>,
    /// Whether the target is a link of the captured system at each sample.
    pub combined: Vec<bool>,
    /// The momentum ledger of robot + target.
    pub ledger: Ledger,
    /// The grasp impact (for `soft`: the lock after the impedance phase).
    pub impact: GraspImpact,
    /// The target's configuration at the impact (its velocity after it is `impact.target_u_after`).
    pub impact_target_x: Vec<f64>,
    /// The captured system (`None` for a point contact).
    pub captured: Option<CapturedSystem>,
    /// Seconds after the detumble phase starts until every rate stays below `rate_tolerance` (inf: never).
    pub time_to_detumble: f64,
    /// `|ω0|` at the end, rad/s.
    pub residual_spin: f64,
    /// The event that ended the approach.
    pub approach_stop: Option<StopEvent>,
    /// In orbit: the momentum balance and the chaser's orbit (the ledger's drifts are then the
    /// balance's residuals).
    pub orbit: Option<CaptureInOrbit>,
    /// `(7 + N, 6 + N, N)` of the robot.
    pub dims: (usize, usize, usize),
}

/// Records put end to end, phase by phase.
#[derive(Default)]
struct Segments {
    t: Vec<f64>,
    phase: Vec<i64>,
    x: Vec<f64>,
    u: Vec<f64>,
    s: Vec<f64>,
    tau: Vec<f64>,
    bw: Vec<f64>,
    w: Vec<f64>,
    combined: Vec<bool>,
    /// In orbit: the tidal wrench about the origin per sample (the robot's or the captured
    /// system's, plus the free target's), width 6.
    gw: Vec<f64>,
    /// In orbit: the wrench at the left end of the interval ending at a sample, where it is not
    /// the previous sample's (a phase's run starts with its own thruster wrench).
    left: Vec<(usize, [f64; 6])>,
}

/// One phase's rows `range` of a run: times already shifted, the rest per row.
struct Rows<'a> {
    x: &'a [f64],
    u: &'a [f64],
    s: &'a [f64],
    tau: &'a [f64],
    bw: &'a [f64],
    w: &'a [f64],
}

impl Segments {
    fn add(&mut self, t: &[f64], phase: i64, rows: Rows<'_>, combined: bool) {
        self.t.extend_from_slice(t);
        self.phase.extend(std::iter::repeat_n(phase, t.len()));
        self.x.extend_from_slice(rows.x);
        self.u.extend_from_slice(rows.u);
        self.s.extend_from_slice(rows.s);
        self.tau.extend_from_slice(rows.tau);
        self.bw.extend_from_slice(rows.bw);
        self.w.extend_from_slice(rows.w);
        self.combined.extend(std::iter::repeat_n(combined, t.len()));
    }
}

/// The options of a phase's run: DOPRI5 with `rtol` (absolute `rtol · 1e-2`), samples every `dt`.
fn phase_options(mode: Mode, duration: f64, dt: f64, rtol: f64, stop: Vec<StopCondition>, orbit: Option<OrbitOptions>) -> SimOptions {
    SimOptions {
        mode,
        integrator: IntegratorKind::Dopri5,
        duration,
        dt,
        rtol,
        atol: rtol * 1e-2,
        record_every: 1,
        wheels: None,
        thrusters: None,
        joint_limits: true,
        max_steps: DEFAULT_MAX_STEPS,
        orbit,
        stop,
        contact: None,
    }
}

/// The hold law of the detumble for `model` (docs/capture.md): computed torque towards
/// `q_hold` on the actuated arm joints, with momentum damping in the flying mode, clamped to
/// `max_joint_torque`; `None` when nothing is driven.
fn hold_law(model: &Model, q_hold: &[f64], mode: Mode, kp: f64, kd: f64, spec: &CaptureSpec, thrusters: (f64, f64)) -> Option<ControllerSpec> {
    let wheels = detect_reaction_wheels(model);
    let actuated = model.actuated_dofs();
    let arm: Vec<f64> = (0..model.n_dof()).filter(|d| !wheels.contains(d) && actuated[*d]).map(|d| q_hold[d]).collect();
    let arm = (!arm.is_empty()).then(|| ControllerSpec::ComputedTorque {
        kp: Gains(vec![kp]),
        kd: Gains(vec![kd]),
        reference: JointReferenceSpec::Constant { q: arm },
        model: None,
        passive: "drift".into(),
    });
    let mut ctrl = arm;
    if mode == Mode::Flying {
        let base = ControllerSpec::MomentumDamping { time_constant: spec.time_constant, max_force: thrusters.0, max_torque: thrusters.1, model: None };
        ctrl = Some(match ctrl {
            Some(arm) => ControllerSpec::Combined { arm: Box::new(arm), base: Box::new(base) },
            None => base,
        });
    }
    ctrl.map(|c| limited(c, spec.max_joint_torque))
}

fn limited(c: ControllerSpec, limit: f64) -> ControllerSpec {
    if limit.is_finite() {
        ControllerSpec::TorqueLimit { controller: Box::new(c), limit }
    } else {
        c
    }
}

/// Run `controller` (or zero torques) on `plant` under `opts`.
fn run(plant: &Model, x: &[f64], u: &[f64], opts: &SimOptions, controller: Option<&ControllerSpec>, progress: Progress<'_>) -> Result<SimResult> {
    let none = ControllerSpec::None {};
    let mut c = controller.unwrap_or(&none).build(plant, &mut no_external)?;
    simulate(plant, x, u, opts, c.as_mut(), progress)
}

fn row(v: &[f64], width: usize, k: usize) -> &[f64] {
    &v[k * width..(k + 1) * width]
}

/// The first time after which every rate stays below `tolerance` (inf if never).
fn time_to_rest(t: &[f64], u: &[f64], nu: usize, first_rate: usize, tolerance: f64) -> f64 {
    let above = |k: usize| row(u, nu, k)[first_rate..].iter().fold(0.0_f64, |m, v| m.max(v.abs())) >= tolerance;
    match (0..t.len()).rev().find(|&k| above(k)) {
        None => t[0],
        Some(k) if k == t.len() - 1 => f64::INFINITY,
        Some(k) => t[k + 1],
    }
}

/// The target's 13-state while it rides on the gripper, from the combined model.
pub(crate) fn payload_state(model: &Model, data: &mut Data, x: &[f64], u: &[f64], body: usize) -> Result<[f64; 13]> {
    forward_kinematics(model, data, x)?;
    let (j0, jm) = point_jacobians(model, data, body, &Vector3::zeros())?;
    let tw = j0 * nalgebra::Vector6::from_column_slice(&u[..6]) + jm * DVector::from_column_slice(&u[6..]);
    let c = data.com_in_world[body];
    let q = xyzw_from_matrix(&data.body_to_world[body]);
    let mut s = [0.0; 13];
    s[..3].copy_from_slice(c.as_slice());
    s[3..7].copy_from_slice(&q);
    s[7..].copy_from_slice(tw.as_slice());
    Ok(s)
}

/// Every check of a capture before anything runs (docs/capture.md, "Grasps that are refused"):
/// the spec's values ([`CaptureSpec::validate`]), the states, the two grasp points, and for a
/// rigid target the reach ([`CaptureSpec::check_work_and_reach`]). Returns the robot's grasp
/// point and the target's, `(body, offset)` each.
pub fn check_capture(robot: &Model, x0: &[f64], u0: &[f64], target: &Model, spec: &CaptureSpec) -> Result<((usize, Vector3<f64>), (usize, Vector3<f64>))> {
    spec.validate()?;
    check_initial_state(robot, x0, u0)?;
    if target.n_dof() != 0 {
        let name = spec.name.as_deref().unwrap_or(target.name());
        if spec.in_orbit.orbit.is_some() {
            return Err(SpacearmError::argument(format!("target '{name}' is a jointed model: a capture in orbit needs a rigid target (not implemented for jointed ones)")));
        }
        if spec.kind != "point" {
            return Err(SpacearmError::argument(format!(
                "target '{name}' is a jointed model: kind='{}' attaches it as a payload, which needs a rigid target; use kind='point'",
                spec.kind
            )));
        }
    }
    let (tbody, toffset) = match &spec.grasp {
        Some(name) => {
            let k = target.point_index(name)?;
            (target.points()[k].body, target.points()[k].offset)
        }
        None => match target.points().first() {
            Some(p) => (p.body, p.offset),
            None => return Err(SpacearmError::argument(format!("target '{}' needs at least one grasp point", target.name()))),
        },
    };
    let (body, offset) = PointSpec::resolve(spec.point.as_ref(), robot)?;
    if target.n_dof() == 0 {
        spec.check_work_and_reach(robot, x0, u0, body, &offset, toffset.norm())?;
    }
    Ok(((body, offset), (tbody, toffset)))
}

/// Run the capture mission `spec` of the rigid `target` (a model with no joints, its named
/// points the grasp points) by `robot` from `(x0, u0)` (module docs).
pub fn run_capture(robot: &Model, x0: &[f64], u0: &[f64], target: &Model, spec: &CaptureSpec, progress: Progress<'_>) -> Result<CaptureRun> {
    let ((body, offset), (tbody, toffset)) = check_capture(robot, x0, u0, target, spec)?;
    let mode = spec.run_mode()?;
    if target.n_dof() != 0 {
        return Err(SpacearmError::argument(format!(
            "target '{}' is a jointed model: the core's capture mission takes a rigid target (spacearm.capture.capture runs jointed ones)",
            target.name()
        )));
    }
    let s0 = spec.target_state.clone();
    let (nx, nu, n) = (robot.nx(), robot.nu(), robot.n_dof());
    let dt = spec.dt;
    let kind = spec.kind.as_str();
    let inertia: Matrix3<f64> = target.base().inertia;
    let tidal = spec.tidal();
    let orbit_at = |t: f64| -> Result<Option<OrbitOptions>> {
        let Some(o) = spec.in_orbit.orbit else { return Ok(None) };
        // each phase's run starts from the orbit's point at its start time
        let orbit = if t == 0.0 {
            o
        } else {
            let (r, v) = o.state_at(t, 1e-13)?;
            Orbit::from_state(o.body, r, v, o.j2)?
        };
        Ok(Some(OrbitOptions { orbit, gravity_gradient: tidal }))
    };

    // ---- 0. approach ------------------------------------------------------------------------
    let reference = PointReferenceSpec::FreeBody {
        body: FreeBodySpec {
            inertia: InertiaSpec::Matrix(std::array::from_fn(|i| std::array::from_fn(|j| inertia[(i, j)]))),
            state: s0.clone(),
            offset: toffset.into(),
            step: 0.5 * dt,
        },
        point: spec.point.clone(),
        orbit: if tidal { spec.in_orbit.orbit } else { None },
    };
    let free = reference.free_body()?;
    let rmrc = ControllerSpec::ResolvedMotionRate {
        reference,
        gain: spec.rmrc_gain,
        max_damping: spec.rmrc_damping,
        threshold: crate::math::dls::DampingLaw::default().threshold,
        velocity_gain: spec.velocity_gain,
        point: spec.point.clone(),
        max_joint_rate: spec.max_joint_rate,
        task: TaskSpec::default(),
        strategy: "naive".into(),
    };
    let ctrl = match mode {
        Mode::Floating => rmrc,
        _ => ControllerSpec::Combined {
            arm: Box::new(rmrc),
            base: Box::new(ControllerSpec::MomentumDamping { time_constant: spec.time_constant, max_force: spec.max_force, max_torque: spec.max_torque, model: None }),
        },
    };
    let ctrl = limited(ctrl, spec.max_joint_torque);
    let stop = vec![StopCondition::Gap { point: Some(PointSpec::At(BodySpec::Index(body), offset.into())), tolerance: spec.capture_tolerance }];
    let approach = run(robot, x0, u0, &phase_options(mode, spec.approach_time, dt, spec.rtol, stop, orbit_at(0.0)?), Some(&ctrl), &mut *progress)?;
    let ra = &approach.records;
    let ka = ra.n_samples;
    let mut body_states = free.clone();
    let mut sa = Vec::with_capacity(13 * ka);
    for &t in &ra.t {
        sa.extend_from_slice(&body_states.state(t)?);
    }
    if approach.stop.is_none() {
        // The gap at every sample, for the message.
        let (mut dr, mut dtg) = (Data::new(robot), Data::new(target));
        let (mut best, mut at) = (f64::INFINITY, 0.0);
        for k in 0..ka {
            forward_kinematics(robot, &mut dr, row(&ra.x, nx, k))?;
            forward_kinematics(target, &mut dtg, &row(&sa, 13, k)[..7])?;
            let gap = (point_position(&dr, body, &offset) - point_position(&dtg, tbody, &toffset)).norm();
            if gap < best {
                (best, at) = (gap, ra.t[k]);
            }
        }
        return Err(SpacearmError::Simulation(format!(
            "the approach did not reach the grasp point: closest {} m at t = {} s (capture_tolerance {} m); lengthen approach_time, place the target within reach or raise rmrc_gain",
            fmt_g(best, 3),
            fmt_g(at, 3),
            fmt_repr(spec.capture_tolerance)
        )));
    }
    let mut seg = Segments::default();
    let zeros6 = vec![0.0; 6 * ka];
    seg.add(&ra.t, 0, Rows { x: &ra.x, u: &ra.u, s: &sa, tau: &ra.tau, bw: &ra.base_wrench, w: &zeros6 }, false);
    if spec.in_orbit.orbit.is_some() {
        // the robot's tidal wrench about the origin, and the free target's
        let mut gw = ra.gravity_wrench.clone().unwrap_or_else(|| vec![0.0; 6 * ka]);
        if tidal {
            let mut body_wrench = free.clone();
            for (k, &t) in ra.t.iter().enumerate() {
                let (f, m) = body_wrench.external_wrench(t, target.total_mass())?;
                for i in 0..3 {
                    gw[6 * k + i] += f[i];
                    gw[6 * k + 3 + i] += m[i];
                }
            }
        }
        seg.gw = gw;
    }
    let k = ka - 1;
    let mut t_cap = ra.t[k];
    let mut xc = row(&ra.x, nx, k).to_vec();
    let mut uc = row(&ra.u, nu, k).to_vec();
    let mut sc = row(&sa, 13, k).to_vec();

    // ---- 1. capture -------------------------------------------------------------------------
    let q_hold = xc[7..].to_vec();
    let robot_point = BodyPoint { body, offset };
    let target_point = BodyPoint { body: tbody, offset: toffset };
    let (mut drobot, mut dtarget) = (Data::new(robot), Data::new(target));
    let contact = if kind == "point" { GraspContact::Point { normal: None } } else { GraspContact::Rigid };
    if kind == "soft" {
        let hold = hold_law(robot, &q_hold, Mode::Floating, spec.kp, spec.kd, spec, (f64::INFINITY, f64::INFINITY));
        let opts = phase_options(Mode::Floating, spec.soft_time, dt / 5.0, spec.rtol, Vec::new(), None);
        let imp = ImpedanceSpec { frequency: 3.0, damping_ratio: 0.7, stiffness: None, damping: None, rotational_stiffness: None, rotational_damping: None };
        let none = ControllerSpec::None {};
        let mut c = hold.as_ref().unwrap_or(&none).build(robot, &mut no_external)?;
        let soft = soft_capture(robot, &xc, &uc, robot_point, target, &sc[..7], &sc[7..], target_point, &imp, &opts, c.as_mut(), &mut *progress)?;
        let (rr, rt) = (&soft.robot.records, &soft.target.records);
        let ks = rr.n_samples;
        let mut t = Vec::with_capacity(ks - 1);
        let mut s = Vec::with_capacity(13 * (ks - 1));
        let mut held = Vec::with_capacity(6 * (ks - 1));
        for j in 1..ks {
            t.push(t_cap + rr.t[j]);
            s.extend_from_slice(row(&rt.x, 7, j));
            s.extend_from_slice(row(&rt.u, 6, j));
            // the impedance's wrench on the target, moved from X to the target's CM
            forward_kinematics(robot, &mut drobot, row(&rr.x, nx, j))?;
            let x_pt = point_position(&drobot, body, &offset);
            let w = row(&soft.wrench, 6, j);
            let f = -Vector3::new(w[0], w[1], w[2]);
            let cm = Vector3::new(rt.x[7 * j], rt.x[7 * j + 1], rt.x[7 * j + 2]);
            let m = -Vector3::new(w[3], w[4], w[5]) + (x_pt - cm).cross(&f);
            held.extend_from_slice(f.as_slice());
            held.extend_from_slice(m.as_slice());
        }
        let bw = vec![0.0; 6 * (ks - 1)];
        seg.add(&t, 1, Rows { x: &rr.x[nx..], u: &rr.u[nu..], s: &s, tau: &rr.tau[n..], bw: &bw, w: &held }, false);
        t_cap += rr.t[ks - 1];
        xc = row(&rr.x, nx, ks - 1).to_vec();
        uc = row(&rr.u, nu, ks - 1).to_vec();
        sc = row(&s, 13, ks - 2).to_vec();
    }
    let impact = grasp_impact(
        robot,
        &mut drobot,
        &xc,
        &uc,
        robot_point,
        target,
        &mut dtarget,
        &sc[..7],
        &sc[7..],
        target_point,
        contact,
        spec.restitution,
        JointsAtImpact::Free,
        spec.capture_tolerance,
    )?;
    let impact_target_x = sc[..7].to_vec();
    uc = impact.u_after.as_slice().to_vec();
    sc = sc[..7].iter().chain(impact.target_u_after.iter()).copied().collect();
    let zn = vec![0.0; n];
    seg.add(&[t_cap], 1, Rows { x: &xc, u: &uc, s: &sc, tau: &zn, bw: &[0.0; 6], w: &[0.0; 6] }, kind != "point");
    if spec.in_orbit.orbit.is_some() {
        seg.gw.extend_from_slice(&[0.0; 6]);
    }

    // ---- 2. post-capture, 3. detumble ---------------------------------------------------------
    let captured = if kind != "point" { Some(attach(robot, &xc, &uc, target, &sc, body, spec.name.as_deref(), &impact)?) } else { None };
    let plant = captured.as_ref().map_or(robot, |c| &c.model);
    let payload_body = captured.as_ref().map(|c| plant.body_index(&c.payload)).transpose()?;
    let mut dplant = Data::new(plant);
    let (mut x_start, mut u_start) = (xc.clone(), uc.clone());
    let mut detumbled = (f64::INFINITY, 0.0);
    for (phase, duration, run_mode, kp) in [(2, spec.post_time, Mode::Floating, 0.0), (3, spec.detumble_time, mode, spec.kp)] {
        let ctrl = hold_law(plant, &q_hold, run_mode, kp, spec.kd, spec, (spec.max_force, spec.max_torque));
        let phase_orbit = orbit_at(t_cap)?;
        let res = run(plant, &x_start, &u_start, &phase_options(run_mode, duration, dt, spec.rtol, Vec::new(), phase_orbit), ctrl.as_ref(), &mut *progress)?;
        let r = &res.records;
        let kr = r.n_samples;
        let mut s = Vec::with_capacity(13 * kr);
        let mut w = Vec::with_capacity(6 * kr);
        let mut gw_target = vec![0.0; 6 * kr];
        match payload_body {
            Some(pb) => {
                for j in 0..kr {
                    let (xj, uj) = (row(&r.x, nx, j), row(&r.u, nu, j));
                    s.extend_from_slice(&payload_state(plant, &mut dplant, xj, uj, pb)?);
                    w.extend_from_slice(joint_wrench(plant, &mut dplant, xj, uj, row(&r.du, nu, j), pb)?.as_slice());
                }
            }
            None => {
                // the point contact's target flies off, free
                let mut fly = FreeBody::new(inertia, &sc, toffset, 0.5 * dt)?;
                if tidal {
                    fly = fly.in_orbit(&phase_orbit.expect("in orbit").orbit)?;
                }
                let mut fly_wrench = fly.clone();
                for &t in &r.t {
                    s.extend_from_slice(&fly.state(t - r.t[0])?);
                }
                if tidal {
                    for (j, &t) in r.t.iter().enumerate() {
                        let (f, m) = fly_wrench.external_wrench(t - r.t[0], target.total_mass())?;
                        gw_target[6 * j..6 * j + 3].copy_from_slice(f.as_slice());
                        gw_target[6 * j + 3..6 * j + 6].copy_from_slice(m.as_slice());
                    }
                }
                w.resize(6 * kr, 0.0);
            }
        }
        let t: Vec<f64> = r.t[1..].iter().map(|tj| t_cap + tj).collect();
        if spec.in_orbit.orbit.is_some() {
            let mut gw = r.gravity_wrench.clone().unwrap_or_else(|| vec![0.0; 6 * kr]);
            if tidal && payload_body.is_none() {
                for (a, b) in gw.iter_mut().zip(&gw_target) {
                    *a += b;
                }
            }
            if phase == 2 {
                // the grasp sample: the same instant as this run's first
                let last = seg.gw.len() - 6;
                seg.gw[last..].copy_from_slice(&gw[..6]);
            }
            // the run's own wrench at its start: the left end of its first interval (the
            // thrusters' wrench jumps between phases)
            let mut w0 = [0.0; 6];
            w0.copy_from_slice(&gw[..6]);
            let thr = thruster_wrench(plant, &mut dplant, &r.x[..nx], &r.base_wrench[..6])?;
            for i in 0..6 {
                w0[i] += thr[i];
            }
            seg.left.push((seg.t.len(), w0));
            seg.gw.extend_from_slice(&gw[6..]);
        }
        seg.add(&t, phase, Rows { x: &r.x[nx..], u: &r.u[nu..], s: &s[13..], tau: &r.tau[n..], bw: &r.base_wrench[6..], w: &w[6..] }, captured.is_some());
        let first_rate = if run_mode == Mode::Floating { 6 } else { 3 };
        let rest = if nu > first_rate { time_to_rest(&r.t, &r.u, nu, first_rate, spec.rate_tolerance) } else { r.t[0] };
        let last = row(&r.u, nu, kr - 1);
        // |ω0| as fused multiply-adds in order (the sum the Python door's numpy norm made)
        detumbled = (rest, last[5].mul_add(last[5], last[4].mul_add(last[4], last[3] * last[3])).sqrt());
        t_cap += r.t[kr - 1];
        x_start = row(&r.x, nx, kr - 1).to_vec();
        u_start = last.to_vec();
        sc = row(&s, 13, kr - 1).to_vec();
    }

    // ---- the ledger -----------------------------------------------------------------------------
    let mut ledger = ledger(robot, plant, target, &seg.x, &seg.u, &seg.s, &seg.combined)?;
    let orbit = match spec.in_orbit.orbit {
        Some(o) => Some(orbit_balance(robot, plant, &o, &seg, &mut ledger)?),
        None => None,
    };
    Ok(CaptureRun {
        t: seg.t,
        phase: seg.phase,
        x: seg.x,
        u: seg.u,
        tau: seg.tau,
        base_wrench: seg.bw,
        target: seg.s,
        grasp_wrench: seg.w,
        combined: seg.combined,
        ledger,
        impact,
        impact_target_x,
        captured,
        time_to_detumble: detumbled.0,
        residual_spin: detumbled.1,
        approach_stop: approach.stop,
        orbit,
        dims: (nx, nu, n),
    })
}

/// The thrusters' wrench about the origin, `[F0; r0 × F0 + N0]` (the force acts at the base CM).
fn thruster_wrench(model: &Model, data: &mut Data, x: &[f64], bw: &[f64]) -> Result<[f64; 6]> {
    forward_kinematics(model, data, x)?;
    let r0 = data.com_in_world[0];
    let f = Vector3::new(bw[0], bw[1], bw[2]);
    let m = r0.cross(&f);
    Ok([bw[0], bw[1], bw[2], m.x + bw[3], m.y + bw[4], m.z + bw[5]])
}

/// The momentum balance of a capture in orbit: the external wrench (tidal plus thrusters) at
/// every sample, its trapezoid integral, the residuals `|c(t) − c(0) − ∫ w dt|` of `P` and `L`
/// relative to the ledger's scales (which replace its drifts), and the chaser's orbit.
fn orbit_balance(robot: &Model, plant: &Model, orbit: &Orbit, seg: &Segments, ledger: &mut Ledger) -> Result<CaptureInOrbit> {
    let (nx, nu) = (robot.nx(), robot.nu());
    let n = seg.t.len();
    let (mut dr, mut dp) = (Data::new(robot), Data::new(plant));
    let mut ext = seg.gw.clone();
    let (mut r_cm, mut v_cm) = (Vec::with_capacity(3 * n), Vec::with_capacity(3 * n));
    let mut lvlh_points = Vec::with_capacity(n);
    for k in 0..n {
        let (xk, uk) = (row(&seg.x, nx, k), row(&seg.u, nu, k));
        let (owner, d) = if seg.combined[k] { (plant, &mut dp) } else { (robot, &mut dr) };
        let thr = thruster_wrench(owner, d, xk, row(&seg.bw, 6, k))?;
        for i in 0..6 {
            ext[6 * k + i] += thr[i];
        }
        let c = crate::algorithms::momentum::center_of_mass(owner, d, xk)?;
        let v = crate::algorithms::momentum::momentum(owner, d, xk, uk)?.linear / owner.total_mass();
        r_cm.extend_from_slice(c.as_slice());
        v_cm.extend_from_slice(v.as_slice());
        // the target relative to the robot's own CM (one reference through the grasp)
        let cr = crate::algorithms::momentum::center_of_mass(robot, &mut dr, xk)?;
        let vr = crate::algorithms::momentum::momentum(robot, &mut dr, xk, uk)?.linear / robot.total_mass();
        let sk = row(&seg.s, 13, k);
        lvlh_points.push((cr, vr, Vector3::new(sk[0], sk[1], sk[2]), Vector3::new(sk[7], sk[8], sk[9])));
    }
    let mut left: Vec<[f64; 6]> = (0..n).map(|k| std::array::from_fn(|i| ext[6 * k.saturating_sub(1) + i])).collect();
    for (j, w0) in &seg.left {
        left[*j] = *w0;
    }
    let mut impulse = vec![0.0; 6 * n];
    for k in 1..n {
        let h = seg.t[k] - seg.t[k - 1];
        for i in 0..6 {
            impulse[6 * k + i] = impulse[6 * (k - 1) + i] + 0.5 * h * (ext[6 * k + i] + left[k][i]);
        }
    }
    let residual = |c: &[f64], first: usize| -> f64 {
        (0..n)
            .map(|k| (0..3).map(|i| (c[3 * k + i] - c[i] - impulse[6 * k + first + i]).powi(2)).sum::<f64>().sqrt())
            .fold(f64::NEG_INFINITY, f64::max)
    };
    ledger.drift_p = residual(&ledger.p, 0) / ledger.scale_p.max(1e-300);
    ledger.drift_l = residual(&ledger.l, 3) / ledger.scale_l.max(1e-300);
    let track = orbit.propagate(&seg.t, 1e-13)?;
    let (mut r_eci, mut v_eci, mut target_lvlh) = (Vec::with_capacity(3 * n), Vec::with_capacity(3 * n), Vec::with_capacity(6 * n));
    for (k, ((ro, vo), (c, cd, p, pd))) in track.iter().zip(&lvlh_points).enumerate() {
        for i in 0..3 {
            r_eci.push(ro[i] + r_cm[3 * k + i]);
            v_eci.push(vo[i] + v_cm[3 * k + i]);
        }
        target_lvlh.extend_from_slice(&Orbit::run_to_lvlh(ro, vo, c, cd, p, pd));
    }
    Ok(CaptureInOrbit { external_wrench: ext, external_impulse: impulse, r_cm_eci: r_eci, v_cm_eci: v_eci, target_lvlh })
}

/// The combined model after a rigid grasp (the target a link on a fixed joint of the grasp
/// point's body at its relative pose; [`ModelBuilder::attach_model`]) and its state, after
/// checking that the impact left no relative twist.
#[allow(clippy::too_many_arguments)]
pub(crate) fn attach(robot: &Model, x: &[f64], u: &[f64], target: &Model, s: &[f64], body: usize, name: Option<&str>, impact: &GraspImpact) -> Result<CapturedSystem> {
    let rel = impact.relative_twist_after.norm();
    let scale = DVector::from_column_slice(&s[7..]).norm().max(DVector::from_column_slice(u).norm()).max(1e-300);
    if rel > 1e-8 * scale {
        return Err(SpacearmError::argument(format!("the target is not locked to the gripper (relative twist {}); apply grasp_impulse(kind='rigid') first", fmt_g(rel, 3))));
    }
    let mut dr = Data::new(robot);
    forward_kinematics(robot, &mut dr, x)?;
    let mut dt = Data::new(target);
    forward_kinematics(target, &mut dt, &s[..7])?;
    let (rb, pb) = (dr.body_to_world[body], dr.com_in_world[body]);
    let rt = dt.body_to_world[0];
    // `Rbᵀ a` as fused multiply-adds over the rows of `Rb` in order: the sums the Python door
    // made (numpy's BLAS), so that the captured system is placed bit for bit as before.
    let tmul = |a: &dyn Fn(usize) -> f64, i: usize| rb[(2, i)].mul_add(a(2), rb[(1, i)].mul_add(a(1), rb[(0, i)] * a(0)));
    let d = Vector3::new(s[0], s[1], s[2]) - pb;
    let origin = Vector3::from_fn(|i, _| tmul(&|k| d[k], i));
    let rotation = xyzw_from_matrix(&Matrix3::from_fn(|i, j| tmul(&|k| rt[(k, j)], i)));
    let gripper = robot.body_name(body).to_string();
    let payload = name.unwrap_or(target.name()).to_string();
    if robot.body_names().iter().any(|b| *b == payload) {
        return Err(SpacearmError::argument(format!("the robot already has a body named '{payload}'; pass name= for the payload")));
    }
    let mut b = robot.to_builder();
    let model_err = |e: crate::error::ModelError| SpacearmError::from(e);
    b.attach_model(target, &Mount::new(&gripper, origin.into(), rotation), &format!("{payload}_"), Some(&payload)).map_err(model_err)?;
    b.set_name(&format!("{}+{payload}", robot.name())).map_err(model_err)?;
    let model = b.build().map_err(model_err)?;
    Ok(CapturedSystem { model, x: x.to_vec(), u: u.to_vec(), payload, gripper })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algorithms::kinematics::forward_kinematics;
    use crate::model::ModelBuilder;

    fn scene(kind: &str) -> (Model, Vec<f64>, Vec<f64>, Model, CaptureSpec) {
        let robot = crate::model::presets::spatial6();
        let x0: Vec<f64> = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0].iter().copied().chain(robot.initial_q().iter().copied()).collect();
        let u0 = vec![0.0; robot.nu()];
        let mut b = ModelBuilder::new("target", "target", 50.0, [[4.0, 0.0, 0.0], [0.0, 5.0, 0.0], [0.0, 0.0, 6.0]]).unwrap();
        b.add_point("handle", "target", [-0.5, 0.0, 0.0]).unwrap();
        let target = b.build().unwrap();
        let mut d = Data::new(&robot);
        forward_kinematics(&robot, &mut d, &x0).unwrap();
        let ee = &robot.points()[robot.end_effector().unwrap()];
        let p = point_position(&d, ee.body, &ee.offset) + Vector3::new(0.6, 0.0, 0.0);
        let state = vec![p.x, p.y, p.z, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.05, 0.1];
        let text = format!("target_state = {state:?}\nkind = \"{kind}\"\ndetumble_time = 0.5\npost_time = 0.2\nsoft_time = 0.1\n");
        (robot, x0, u0, target, toml::from_str(&text).unwrap())
    }

    #[test]
    fn the_mission_conserves_its_ledger_and_grasps_at_the_tolerance() {
        for kind in ["rigid", "point", "soft"] {
            let (robot, x0, u0, target, spec) = scene(kind);
            let run = run_capture(&robot, &x0, &u0, &target, &spec, &mut |_| Ok(())).unwrap();
            let n = run.t.len();
            assert!(run.t.windows(2).all(|w| w[1] >= w[0]) && run.phase.windows(2).all(|w| w[1] >= w[0]), "{kind}: time and phase in order");
            assert_eq!((run.phase[0], run.phase[n - 1]), (0, 3));
            // the drift recomputed from the ledger's arrays by its definition
            let dev = |v: &[f64]| (0..n).map(|k| (0..3).map(|i| (v[3 * k + i] - v[i]).powi(2)).sum::<f64>().sqrt()).fold(0.0, f64::max);
            assert!(dev(&run.ledger.l) / run.ledger.scale_l < 1e-9 && run.ledger.drift_l < 1e-9, "{kind}: L drift {}", run.ledger.drift_l);
            assert!(dev(&run.ledger.p) / run.ledger.scale_p < 1e-9, "{kind}: P drift");
            assert!(run.ledger.l.iter().any(|v| v.abs() > 0.1), "{kind}: momentum in play");
            // the grasp: the two grasp points the tolerance apart at the approach's end
            let grasp_at = run.phase.iter().position(|&p| p == 1).unwrap() - 1;
            let stop = run.approach_stop.unwrap();
            assert_eq!(stop.t, run.t[grasp_at]);
            assert!((stop.value - 0.01).abs() < 1e-8, "{kind}: gap {}", stop.value);
            assert_eq!(run.captured.is_some(), kind != "point");
        }
    }

    #[test]
    fn bad_specs_are_refused_before_anything_runs() {
        let (robot, x0, u0, target, mut spec) = scene("rigid");
        spec.kind = "glue".into();
        let err = run_capture(&robot, &x0, &u0, &target, &spec, &mut |_| Ok(())).unwrap_err().to_string();
        assert!(err.contains("kind must be one of ['rigid', 'point', 'soft'], got 'glue'"), "{err}");
        let (_, _, _, _, mut far) = scene("rigid");
        far.target_state[0] = 1e5;
        let err = run_capture(&robot, &x0, &u0, &target, &far, &mut |_| Ok(())).unwrap_err().to_string();
        assert!(err.contains("the approach cannot reach the target"), "{err}");
    }
}
