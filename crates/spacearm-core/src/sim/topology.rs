//! Topology events in one run (docs/events.md): the robot welds the run's free target to one of
//! its bodies ([`TopologyEvent::Attach`]) and releases a rigid link ([`TopologyEvent::Detach`]),
//! each a core event that continues the run in ONE trajectory with the model edited
//! ([`crate::model::edit`]: `attach_model`, `remove_subtree`) and the state mapped across it.
//!
//! **The second system** is the capture's target ([`crate::sim::capture`]): a rigid model (no
//! joints; its named points the grasp points) with the 13-state `s = [r, quat, v, ω]` (CM, attitude,
//! CM velocity and angular velocity in 𝒥), propagated torque-free by
//! [`FreeBody`] while it flies (its `P` and `L` exactly constant), and a link of the robot on a
//! fixed joint while attached (its state then read from the robot's,
//! [`crate::sim::capture::payload_state`]). Between events the robot (with or without the target)
//! is integrated by the simulation loop ([`simulate`]); the records of the segments are put end
//! to end, the event's instant recorded twice (before and after the jump).
//!
//! **Attach** (docs/capture.md, "The grasp impact"; paper eqs. 104–108, docs/equations.md): at
//! the robot's point `X` (Jacobian `J_X`) and the target's material point at `X`, the rigid
//! weld's impulse with restitution 0,
//! `Λ = −(G_r + G_t)⁻¹ v_rel⁻`, `G = J_X H⁻¹ J_Xᵀ` each, `Δu_r = H_r⁻¹ J_Xᵀ Λ`,
//! `Δu_t = −H_t⁻¹ J_tᵀ Λ` ([`grasp_impact`]): the impulses are equal and opposite, so `P` and `L`
//! of robot + target are continuous to rounding; then the target becomes a link on a fixed joint
//! at its relative pose ([`crate::sim::capture::attach`]). At a commanded time, or when every
//! given threshold holds: `g = max(gap/gap₀, |Δv|/v₀, |Δω|/ω₀) − 1 ≤ 0` (`gap = |X − p|`, `Δv`,
//! `Δω` the relative twist at `X`), located within the RK4 step by the Illinois regula falsi
//! ([`locate_root`], as the stop conditions are, [`crate::sim::events`]).
//!
//! **Detach** at a commanded time: the link (a fixed joint, no link below it) is removed
//! (`remove_subtree`); the robot's `u` is kept, the link's twist is its 13-state: a plain split
//! conserves `P`, `L` and the kinetic energy exactly. A separation impulse `ĵ` along the unit
//! `d` acts at the link's CM: `Δv_t = ĵ d / m_t` on the link, `Δu_r = H_r⁻¹ J_cᵀ [−ĵ d; 0]` on the
//! robot (`J_c` the Jacobian of the parent body at that point): equal and opposite, `P` and `L`
//! continuous.
//!
//! **Contact** (docs/events.md, "Events with contact"): with the run's contact, a flying target
//! that has collision shapes is integrated WITH the robot in the loop of contact
//! ([`crate::sim::free_target`], [`Flight::InLoop`]): a threshold attach is then the grasp on
//! contact, watched on the integrator's state. Per segment the contact is the run's, less the
//! pairs that name a second system that is welded or has no shapes ([`segment_contact`]); the
//! contact forces are internal to robot + target, so the ledger is continuous through the
//! events as without contact.
//!
//! Controllers are rebuilt on the edited model after each event (their internal state starts
//! anew). Not handled (refused with a message): DOPRI5 with a threshold attach, stop
//! conditions and orbits together with events, a jointed target, releasing a link on a
//! moving joint or with links below it.

use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector6};

use crate::algorithms::impulse::{contact_response, grasp_impact, BodyPoint, GraspContact, JointsAtImpact};
use crate::algorithms::kinematics::{forward_kinematics, point_jacobians, point_position};
use crate::algorithms::momentum::{kinetic_energy, momentum};
use crate::algorithms::rnea::velocity_pass;
use crate::control::spec::PointSpec;
use crate::control::Controller;
use crate::error::{Result, SpacearmError};
use crate::math::integrate::{IntegratorKind, Rk4};
use crate::math::rotations::matrix_from_xyzw;
use crate::model::geometry::GeometryRole;
use crate::model::joint::JointType;
use crate::model::{Data, Model, ModelBuilder};
use crate::scenario::free_body::FreeBody;
use crate::sim::capture::{attach, payload_state};
use crate::sim::contact::ContactSpec;
use crate::sim::events::locate_root;
use crate::sim::options::SimOptions;
use crate::sim::plant::Plant;
use crate::sim::result::{Records, SimResult};
use crate::sim::simulate::{check_initial_state, rk4_step_count, sample_count, simulate, simulate_with_target, Progress};
use crate::sim::stepper::Rk4Stepper;
pub use crate::sim::topology_spec::{validate, TopologyEvent};

/// Builds the run's controller on a model (the entry point's: a [`crate::control::spec::ControllerSpec`] with the
/// door's external controllers), once per segment.
pub type ControllerFactory<'a> = &'a mut dyn FnMut(&Model) -> Result<Box<dyn Controller>>;

/// One event as it happened.
#[derive(Debug, Clone, PartialEq)]
pub struct TopologyRecord {
    /// Index of the event in the run's list.
    pub event: usize,
    /// `"attach"` or `"detach"`.
    pub kind: &'static str,
    /// The time, s.
    pub t: f64,
    /// The link attached or released.
    pub body: String,
    /// The impulse `[f̂; n̂]` in 𝒥: attach, on the robot at its point `X` (the target gets the
    /// opposite); detach, on the released link at its CM (the robot gets the opposite).
    pub impulse: [f64; 6],
    /// The point where it acts, in 𝒥.
    pub point: [f64; 3],
    /// Robot + target `[P; L]` (L about the origin of 𝒥) just before.
    pub momentum_before: [f64; 6],
    /// The same just after.
    pub momentum_after: [f64; 6],
    /// Robot + target kinetic energy just before, J.
    pub energy_before: f64,
    /// The same just after.
    pub energy_after: f64,
    /// Attach: the distance between the two points, m (detach: 0).
    pub gap: f64,
}

/// A run with topology events.
#[derive(Debug, Clone)]
pub struct TopologyRun {
    /// The robot's records, segment after segment (the model of each segment's: with the target
    /// while it is attached), times from the run's start; drifts the largest of the segments'.
    pub result: SimResult,
    /// The second system's 13-state per sample (NaN where there is none yet).
    pub target: Vec<f64>,
    /// Whether it is a link of the robot at each sample.
    pub attached: Vec<bool>,
    /// The run's phase at each sample: how many events have happened (0 before the first).
    pub phase: Vec<usize>,
    /// Robot + target `[P; L_origin]` per sample (width 6).
    pub ledger_momentum: Vec<f64>,
    /// Robot + target mechanical energy (the records' energy plus the free target's kinetic
    /// energy) per sample, J.
    pub ledger_energy: Vec<f64>,
    /// The events that happened, in order.
    pub events: Vec<TopologyRecord>,
    /// The model at the run's end.
    pub final_model: Model,
}

/// Where the second system is.
#[allow(clippy::large_enum_variant)]
enum Second {
    /// None yet.
    None,
    /// Flying: its model and how it moves.
    Free { model: Model, flight: Flight },
    /// A link of the robot (its index in the current model), with the model it flies as.
    Attached { model: Model, link: String },
}

/// How a flying second system moves (module docs, "Contact"): torque-free in closed form, or
/// integrated with the robot in the loop of the run's contact.
#[allow(clippy::large_enum_variant)]
enum Flight {
    /// Torque-free ([`FreeBody`]), its clock started at run time `t0`.
    Body { body: FreeBody, t0: f64 },
    /// In the loop of contact ([`crate::sim::free_target`]): its 13-state at the start of the
    /// segment to run (at the last segment's end once it has run).
    InLoop { state: Vec<f64> },
}

impl Flight {
    /// `model` at the 13-state `s` at run time `t0`: in the loop when the run has contact and
    /// the body has collision shapes to touch with, else torque-free.
    fn new(model: &Model, s: &[f64], t0: f64, opts: &SimOptions) -> Result<Self> {
        if opts.contact.is_some() && model.geometries().iter().any(|g| g.role == GeometryRole::Collision) {
            Ok(Flight::InLoop { state: s.to_vec() })
        } else {
            Ok(Flight::Body { body: FreeBody::new(model.base().inertia, s, Vector3::zeros(), 0.5 * opts.dt)?, t0 })
        }
    }

    /// The 13-state at run time `t` (in the loop: `t` is the current segment's start).
    fn state(&mut self, t: f64) -> Result<Vec<f64>> {
        match self {
            Flight::Body { body, t0 } => Ok(body.state(t - *t0)?.to_vec()),
            Flight::InLoop { state } => Ok(state.clone()),
        }
    }
}

/// The names by which a contact description may name the second system `model`: `"target"`,
/// its model's and body's names, its geometries' names (and, attached as `link`, the link's).
fn second_names(model: &Model, link: Option<&str>) -> Vec<String> {
    let mut names = vec!["target".to_string(), model.name().to_string(), model.body_names()[0].clone()];
    names.extend(model.geometries().iter().map(|g| g.name.clone()));
    if let Some(l) = link {
        names.push(l.to_string());
        names.extend(model.geometries().iter().map(|g| format!("{l}_{}", g.name)));
    }
    names
}

/// The contact of a segment (module docs, "Contact"): the run's, whole while the second system
/// is in the loop of it (or there is none); else without the pairs that name it (a welded or
/// shapeless target touches nothing by them) — `None` when no pair is left, or when the pairs
/// were all pairs of bodies and the robot has fewer than two collision shapes.
fn segment_contact(contact: Option<&ContactSpec>, second: &Second, model: &Model) -> Option<ContactSpec> {
    let spec = contact?;
    let names = match second {
        Second::None | Second::Free { flight: Flight::InLoop { .. }, .. } => return Some(spec.clone()),
        Second::Free { model: tm, .. } => second_names(tm, None),
        Second::Attached { model: tm, link } => second_names(tm, Some(link)),
    };
    match &spec.pairs {
        None => (model.geometries().iter().filter(|g| g.role == GeometryRole::Collision).count() >= 2).then(|| spec.clone()),
        Some(list) => {
            let kept: Vec<[String; 2]> = list.iter().filter(|p| !p.iter().any(|n| names.contains(n))).cloned().collect();
            (!kept.is_empty()).then(|| ContactSpec { pairs: Some(kept), ..spec.clone() })
        }
    }
}

fn target_momentum(model: &Model, s: &[f64]) -> ([f64; 6], f64) {
    let m = model.total_mass();
    let r = Vector3::new(s[0], s[1], s[2]);
    let v = Vector3::new(s[7], s[8], s[9]);
    let w = Vector3::new(s[10], s[11], s[12]);
    let rot = matrix_from_xyzw(&[s[3], s[4], s[5], s[6]]);
    let iw: Matrix3<f64> = rot * model.base().inertia * rot.transpose();
    let p = m * v;
    let l = r.cross(&p) + iw * w;
    ([p.x, p.y, p.z, l.x, l.y, l.z], 0.5 * (m * v.norm_squared() + w.dot(&(iw * w))))
}

fn robot_momentum(model: &Model, x: &[f64], u: &[f64]) -> Result<([f64; 6], f64)> {
    let mut d = Data::new(model);
    let h = momentum(model, &mut d, x, u)?;
    let (p, l) = (h.linear, h.angular_about_origin);
    Ok(([p.x, p.y, p.z, l.x, l.y, l.z], kinetic_energy(model, &mut d, x, u)?))
}

fn add6(a: [f64; 6], b: [f64; 6]) -> [f64; 6] {
    std::array::from_fn(|i| a[i] + b[i])
}

/// The grasp point of `target` named `grasp` (else its first point, else its CM).
fn grasp_point(target: &Model, grasp: Option<&str>) -> Result<BodyPoint> {
    let p = match grasp {
        Some(name) => {
            let k = target.point_index(name)?;
            Some(&target.points()[k])
        }
        None => target.points().first(),
    };
    Ok(p.map_or(BodyPoint { body: 0, offset: Vector3::zeros() }, |p| BodyPoint { body: p.body, offset: p.offset }))
}

/// Run `robot` from `(x0, u0)` under `opts` (a run of `opts.duration`) and the controller
/// `controller` builds, with the free `target` at `target_state` (13) if given and the
/// topology `events` (module docs). With the run's contact, a flying target that has collision
/// shapes is integrated with the robot in the loop of contact ([`crate::sim::free_target`])
/// and the events continue that run (module docs, "Contact").
#[allow(clippy::too_many_arguments)]
pub fn simulate_with_events(
    robot: &Model,
    x0: &[f64],
    u0: &[f64],
    opts: &SimOptions,
    controller: ControllerFactory<'_>,
    target: Option<(&Model, &[f64])>,
    events: &[TopologyEvent],
    progress: Progress<'_>,
) -> Result<TopologyRun> {
    opts.validate()?;
    validate(events)?;
    check_initial_state(robot, x0, u0)?;
    let refuse = |what: &str| Err(SpacearmError::argument(format!("topology events with {what} are not implemented; run without events= or without {what}")));
    if !opts.stop.is_empty() {
        return refuse("stop conditions");
    }
    if opts.orbit.is_some() {
        return refuse("an orbit");
    }
    let located = events.iter().any(|e| matches!(e, TopologyEvent::Attach { at: None, .. }));
    if opts.integrator != IntegratorKind::Rk4 && located {
        return Err(SpacearmError::argument(
            "topology events: an attach located by thresholds is not implemented with integrator='dopri5'; use integrator='rk4', or give the attach a commanded time at=",
        ));
    }
    let rigid = opts.contact.as_ref().is_some_and(|c| c.kind == crate::sim::contact::ContactKind::Rigid);
    if rigid && target.is_some() {
        return Err(crate::sim::contact::rigid_with_target_refused());
    }
    if located && rigid {
        // the location re-takes a step without its rigid impulses (sim/rigid_contact.rs)
        return Err(SpacearmError::argument(
            "topology events: an attach located by thresholds is not implemented with rigid contact (kind='rigid'): locating it re-takes a step without the rigid impulses; give the attach a commanded time at=, or use the compliant law",
        ));
    }
    let mut second = match target {
        Some((model, state)) => {
            if model.n_dof() != 0 {
                return Err(SpacearmError::argument(format!("target '{}' is a jointed model: topology events take a rigid target", model.name())));
            }
            crate::error::check_vector("target_state", state, 13)?;
            Second::Free { model: model.clone(), flight: Flight::new(model, state, 0.0, opts)? }
        }
        None => Second::None,
    };
    let mut model = robot.clone();
    let (mut x, mut u) = (x0.to_vec(), u0.to_vec());
    let mut t0 = 0.0;
    let mut run = Rows::default();
    let mut records: Vec<TopologyRecord> = Vec::new();
    let mut k = 0;
    let duration = opts.duration;
    loop {
        let next = events.get(k);
        let (t_end, threshold) = match next {
            Some(e @ TopologyEvent::Attach { at: None, .. }) => (events[k + 1..].iter().find_map(|e| e.at()).map_or(duration, |t| t.min(duration)), Some(e)),
            Some(e) => (e.at().expect("a commanded time").min(duration), None),
            None => (duration, None),
        };
        let seg_opts = SimOptions { duration: t_end - t0, contact: segment_contact(opts.contact.as_ref(), &second, &model), ..opts.clone() };
        let mut ctrl = controller(&model)?;
        let mut seg_progress = |f: f64| progress((t0 + f * (t_end - t0)) / duration);
        // the second system in the loop of contact this segment: its model and 13-state
        let in_loop = match &second {
            Second::Free { model: tm, flight: Flight::InLoop { state } } => Some((tm, state.as_slice())),
            _ => None,
        };
        if t_end <= t0 {
            return Err(SpacearmError::Simulation(format!("event {k} ({}) at t = {t0} s: no time left before it", next.map_or("end", |e| e.kind()))));
        }
        let (mut res, happened) = match threshold {
            Some(TopologyEvent::Attach { point, grasp, gap, speed, rate, .. }) => {
                let Second::Free { model: tm, flight } = &second else {
                    return Err(SpacearmError::argument(format!("event {k} (attach): there is no free target to attach (pass target= and target_state=)")));
                };
                let limits = [gap.unwrap_or(f64::INFINITY), speed.unwrap_or(f64::INFINITY), rate.unwrap_or(f64::INFINITY)];
                let plant = match in_loop {
                    Some((tm, s)) => Plant::with_target(&model, &seg_opts, ctrl.as_mut(), tm, s)?,
                    None => Plant::new(&model, &seg_opts, ctrl.as_mut())?,
                };
                let source = match flight {
                    Flight::Body { body, t0: tb0 } => WatchedTarget::Body { body: body.clone(), clock: t0 - tb0 },
                    Flight::InLoop { .. } => WatchedTarget::InLoop { offset: plant.target().map_or(0, |t| t.offset) },
                };
                let watch = AttachWatch::new(&model, point.as_ref(), tm, grasp.as_deref(), limits, source)?;
                run_located(plant, &x, &u, &seg_opts, watch, &mut seg_progress)?
            }
            _ => match in_loop {
                Some((tm, s)) => (simulate_with_target(&model, &x, &u, &seg_opts, ctrl.as_mut(), tm, s, &mut seg_progress)?, None),
                None => (simulate(&model, &x, &u, &seg_opts, ctrl.as_mut(), &mut seg_progress)?, None),
            },
        };
        let t_seg = res.records.t[res.records.n_samples - 1];
        let (nx, nu) = (model.nx(), model.nu());
        let last = res.records.n_samples - 1;
        x = res.records.x[last * nx..].to_vec();
        u = res.records.u[last * nu..].to_vec();
        run.rows_of(&model, &mut second, t0, &mut res, opts.contact.is_some(), records.len())?;
        let is_attached = matches!(second, Second::Attached { .. });
        run.segments.push((t0, res, is_attached));
        // a commanded event's time exactly (the segment's steps land on its duration)
        t0 = if threshold.is_none() { t_end } else { t0 + t_seg };
        // the event, if one happens here
        let fire = match next {
            Some(TopologyEvent::Attach { at: None, .. }) => happened.is_some_and(|_| t0 < duration * (1.0 - 1e-14)),
            Some(e) => e.at().is_some_and(|t| t < duration * (1.0 - 1e-14) && t0 >= t * (1.0 - 1e-14)),
            None => false,
        };
        if !fire {
            if let (Some(TopologyEvent::Attach { at: None, .. }), true) = (next, t0 < duration * (1.0 - 1e-14)) {
                let t_next = events[k + 1..].iter().find_map(|e| e.at()).unwrap_or(duration);
                return Err(SpacearmError::Simulation(format!(
                    "event {k} (attach) did not happen before the next event's time {t_next} s: its thresholds never held; loosen them or \
                     give the attach a commanded time at="
                )));
            }
            break;
        }
        let e = next.expect("an event");
        let (new_model, rec) = match e {
            TopologyEvent::Attach { point, grasp, .. } => {
                let Second::Free { model: tm, flight } = &mut second else {
                    return Err(SpacearmError::argument(format!("event {k} (attach) at t = {t0} s: there is no free target to attach (pass target= and target_state=, or release a link first)")));
                };
                let s = flight.state(t0)?;
                let (rb, ro) = PointSpec::resolve(point.as_ref(), &model)?;
                let tg = grasp_point(tm, grasp.as_deref())?;
                let (mr, er) = robot_momentum(&model, &x, &u)?;
                let (mt, et) = target_momentum(tm, &s);
                let (mut dr, mut dt) = (Data::new(&model), Data::new(tm));
                // no gap refusal: a commanded weld holds the target where it is, a located one
                // is at its threshold (to rounding)
                let tol = f64::INFINITY;
                let impact = grasp_impact(&model, &mut dr, &x, &u, BodyPoint { body: rb, offset: ro }, tm, &mut dt, &s[..7], &s[7..], tg, GraspContact::Rigid, 0.0, JointsAtImpact::Free, tol)?;
                let s_after: Vec<f64> = s[..7].iter().chain(impact.target_u_after.iter()).copied().collect();
                let captured = attach(&model, &x, impact.u_after.as_slice(), tm, &s_after, rb, None, &impact)?;
                u = captured.u.clone();
                let (ma, ea) = robot_momentum(&captured.model, &x, &u)?;
                let rec = TopologyRecord {
                    event: k,
                    kind: "attach",
                    t: t0,
                    body: captured.payload.clone(),
                    impulse: std::array::from_fn(|i| impact.impulse[i]),
                    point: impact.point.into(),
                    momentum_before: add6(mr, mt),
                    momentum_after: ma,
                    energy_before: er + et,
                    energy_after: ea,
                    gap: impact.gap,
                };
                second = Second::Attached { model: tm.clone(), link: captured.payload.clone() };
                (captured.model, rec)
            }
            TopologyEvent::Detach { body, impulse, direction, .. } => {
                let link = match (body, &second) {
                    (Some(b), _) => b.clone(),
                    (None, Second::Attached { link, .. }) => link.clone(),
                    (None, _) => return Err(SpacearmError::argument(format!("event {k} (detach) at t = {t0} s: no target is attached; name the link to release (body=)"))),
                };
                if matches!(second, Second::Free { .. }) {
                    return Err(SpacearmError::argument(format!(
                        "event {k} (detach) at t = {t0} s: the run already has a free target (one second system at a time is implemented); attach it first"
                    )));
                }
                let (released, edited, rec) = detach(&model, &x, &mut u, &link, *impulse, direction.as_ref(), &second, k, t0)?;
                let mut rec = rec;
                rec.event = k;
                second = Second::Free { flight: Flight::new(&released.0, &released.1, t0, opts)?, model: released.0 };
                (edited, rec)
            }
        };
        model = new_model;
        records.push(rec);
        k += 1;
    }
    run.finish(records, model)
}

/// The rows of a run with events beside the robot's records: the second system's 13-state, the
/// ledger, whether it is attached and the phase (events that happened) per sample, and the
/// segments themselves.
#[derive(Default)]
struct Rows {
    segments: Vec<(f64, SimResult, bool)>,
    target: Vec<f64>,
    attached: Vec<bool>,
    phase: Vec<usize>,
    ledger_momentum: Vec<f64>,
    ledger_energy: Vec<f64>,
}

impl Rows {
    /// Add the rows of the segment `res` that started at run time `t0` on `model` with
    /// `second` (after `phase` events): the ledger is the records' `[P; L]` and energy plus the
    /// flying target's (in the loop of contact: the recorder's, robot + target, whose target rows
    /// leave the records here); with the run's `contact`, a segment without contact records
    /// zeros for them.
    fn rows_of(&mut self, model: &Model, second: &mut Second, t0: f64, res: &mut SimResult, contact: bool, phase: usize) -> Result<()> {
        let r = &mut res.records;
        let n = r.n_samples;
        let (nx, nu) = (model.nx(), model.nu());
        let attached = matches!(second, Second::Attached { .. });
        self.attached.extend(std::iter::repeat_n(attached, n));
        self.phase.extend(std::iter::repeat_n(phase, n));
        if contact && r.contact_count.is_none() {
            (r.contact_count, r.contact_normal_force, r.contact_work) = (Some(vec![0.0; n]), Some(vec![0.0; n]), Some(vec![0.0; n]));
        }
        if contact && r.contact_forces.is_none() {
            r.contact_forces = Some(Vec::new()); // no acting contact: no rows
        }
        if let (Some(ts), Some(lm), Some(le)) = (r.target_state.take(), r.ledger_momentum.take(), r.ledger_energy.take()) {
            if let Second::Free { flight: Flight::InLoop { state }, .. } = second {
                state.copy_from_slice(&ts[13 * (n - 1)..]);
            }
            self.target.extend(ts);
            self.ledger_momentum.extend(lm);
            self.ledger_energy.extend(le);
            return Ok(());
        }
        let mut d = Data::new(model);
        for j in 0..n {
            let (s, free): ([f64; 13], [f64; 7]) = match &mut *second {
                Second::None => ([f64::NAN; 13], [0.0; 7]),
                Second::Free { model: tm, flight } => {
                    let s: [f64; 13] = flight.state(t0 + r.t[j])?.try_into().map_err(|_| SpacearmError::Simulation("a 13-state".into()))?;
                    let (h, e) = target_momentum(tm, &s);
                    (s, std::array::from_fn(|i| if i < 6 { h[i] } else { e }))
                }
                Second::Attached { link, .. } => (payload_state(model, &mut d, &r.x[j * nx..(j + 1) * nx], &r.u[j * nu..(j + 1) * nu], model.body_index(link)?)?, [0.0; 7]),
            };
            self.target.extend_from_slice(&s);
            let (p, l) = (&r.linear_momentum[3 * j..3 * j + 3], &r.angular_momentum_origin[3 * j..3 * j + 3]);
            self.ledger_momentum.extend((0..6).map(|i| if i < 3 { p[i] } else { l[i - 3] } + free[i]));
            self.ledger_energy.push(r.energy[j] + free[6]);
        }
        Ok(())
    }

    /// The segments put end to end (module docs), with the events that happened and the model
    /// at the end.
    fn finish(self, events: Vec<TopologyRecord>, model: Model) -> Result<TopologyRun> {
        let mut out: Option<SimResult> = None;
        let starts: Vec<f64> = self.segments.iter().map(|s| s.0).skip(1).collect();
        for (i, (t0, res, _)) in self.segments.into_iter().enumerate() {
            let mut res = shifted(res, t0);
            if let (Some(&next), Some(last)) = (starts.get(i), res.records.t.last_mut()) {
                // the segment's end is the next one's start, the event's instant, to the bit
                *last = next;
            }
            out = Some(match out {
                None => res,
                Some(mut acc) => {
                    append(&mut acc, res);
                    acc
                }
            });
        }
        let result = out.ok_or_else(|| SpacearmError::Simulation("the run recorded nothing".into()))?;
        Ok(TopologyRun {
            result,
            target: self.target,
            attached: self.attached,
            phase: self.phase,
            ledger_momentum: self.ledger_momentum,
            ledger_energy: self.ledger_energy,
            events,
            final_model: model,
        })
    }
}

/// Release `link` from `model` at `(x, u)` (module docs): the released rigid model with its
/// 13-state, the edited model (and `u` mapped across it), and the event's record.
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
fn detach(
    model: &Model,
    x: &[f64],
    u: &mut [f64],
    link: &str,
    impulse: f64,
    direction: Option<&[f64; 3]>,
    second: &Second,
    k: usize,
    t: f64,
) -> Result<((Model, Vec<f64>), Model, TopologyRecord)> {
    let b = model.body_index(link)?;
    if b == 0 {
        return Err(SpacearmError::argument(format!("event {k} (detach): '{link}' is the base; name a link")));
    }
    let l = &model.links()[b - 1];
    if l.joint.kind != JointType::Fixed || model.links().iter().any(|o| o.parent == b) {
        return Err(SpacearmError::argument(format!(
            "event {k} (detach): releasing link '{link}' (a {} joint{}) is not implemented: only a rigid link on a fixed joint with no link below it is released",
            l.joint.kind.as_str(),
            if model.links().iter().any(|o| o.parent == b) { ", with links below it" } else { "" }
        )));
    }
    let parent = l.parent;
    let mut d = Data::new(model);
    let mut s = payload_state(model, &mut d, x, u, b)?.to_vec();
    let (mb, eb) = robot_momentum(model, x, u)?;
    // the released link as a rigid model: the attached target's own, or one from the link
    let free = match second {
        Second::Attached { model: tm, link: l2 } if l2 == link => tm.clone(),
        _ => {
            let mp = model.mass_properties(b);
            let inertia = std::array::from_fn(|i| std::array::from_fn(|j| mp.inertia[(i, j)]));
            let mut mb = ModelBuilder::new(link, link, mp.mass, inertia).map_err(SpacearmError::from)?;
            for p in model.points().iter().filter(|p| p.body == b) {
                mb.add_point(&p.name, link, p.offset.into()).map_err(SpacearmError::from)?;
            }
            mb.build().map_err(SpacearmError::from)?
        }
    };
    let edited = model.remove_subtree(link).map_err(SpacearmError::from)?;
    forward_kinematics(model, &mut d, x)?;
    let c = d.com_in_world[b];
    let (c_parent, r_parent) = (d.com_in_world[parent], d.body_to_world[parent]);
    let mut lam = [0.0; 6];
    if impulse > 0.0 {
        let dir = match direction {
            Some(v) => Vector3::from(*v),
            None => c - c_parent,
        };
        let n = dir.norm();
        if !n.is_finite() || n <= 1e-12 * (1.0 + c.norm()) {
            return Err(SpacearmError::argument(format!(
                "event {k} (detach): the separation impulse needs a direction (the link's CM is at its parent's); give direction="
            )));
        }
        let f = dir * (impulse / n);
        let m = free.total_mass();
        for i in 0..3 {
            s[7 + i] += f[i] / m;
            lam[i] = f[i];
        }
        // the robot takes −f at the link's CM, on the parent body (the body indices below the
        // removed link are unchanged: it had none below it and later links keep their order)
        let pb = if parent < b { parent } else { parent - 1 };
        let mut de = Data::new(&edited);
        forward_kinematics(&edited, &mut de, x)?;
        let offset = r_parent.transpose() * (c - c_parent);
        let (j0, jm) = point_jacobians(&edited, &de, pb, &offset)?;
        let mut j = DMatrix::zeros(6, edited.nu());
        j.view_mut((0, 0), (6, 6)).copy_from(&j0);
        j.view_mut((0, 6), (6, edited.n_dof())).copy_from(&jm);
        let resp = contact_response(&edited, &mut de, x, &j, JointsAtImpact::Free)?;
        let du = &resp.response * DVector::from_column_slice(&[-f.x, -f.y, -f.z, 0.0, 0.0, 0.0]);
        for (ui, di) in u.iter_mut().zip(du.iter()) {
            *ui += di;
        }
    }
    let (mr, er) = robot_momentum(&edited, x, u)?;
    let (mt, et) = target_momentum(&free, &s);
    let rec = TopologyRecord {
        event: k,
        kind: "detach",
        t,
        body: link.to_string(),
        impulse: lam,
        point: c.into(),
        momentum_before: mb,
        momentum_after: add6(mr, mt),
        energy_before: eb,
        energy_after: er + et,
        gap: 0.0,
    };
    Ok(((free, s), edited, rec))
}

/// Where a threshold attach reads the flying target's 13-state.
enum WatchedTarget {
    /// Torque-free: at `clock + t` on its clock.
    Body { body: FreeBody, clock: f64 },
    /// In the loop of contact: in the ODE state at `offset`.
    InLoop { offset: usize },
}

/// The watch of a threshold attach: `g = max(gap/gap₀, |Δv|/v₀, |Δω|/ω₀) − 1` at `(t, y)`.
struct AttachWatch<'m> {
    model: &'m Model,
    data: Data,
    point: BodyPoint,
    /// The target's grasp point, from its CM in its axes.
    grasp: Vector3<f64>,
    target: WatchedTarget,
    limits: [f64; 3],
}

impl<'m> AttachWatch<'m> {
    fn new(model: &'m Model, point: Option<&PointSpec>, target: &Model, grasp: Option<&str>, limits: [f64; 3], source: WatchedTarget) -> Result<Self> {
        let (b, offset) = PointSpec::resolve(point, model)?;
        let tg = grasp_point(target, grasp)?;
        if tg.body != 0 {
            return Err(SpacearmError::argument("the target's grasp point must be on its base (a rigid target)"));
        }
        Ok(AttachWatch { model, data: Data::new(model), point: BodyPoint { body: b, offset }, grasp: tg.offset, target: source, limits })
    }

    /// `g` at segment time `t`, robot state `y = [x; u; …]`.
    fn g(&mut self, t: f64, y: &[f64]) -> Result<f64> {
        let (nx, nu) = (self.model.nx(), self.model.nu());
        forward_kinematics(self.model, &mut self.data, &y[..nx])?;
        velocity_pass(self.model, &mut self.data, &y[nx..nx + nu]);
        let xp = point_position(&self.data, self.point.body, &self.point.offset);
        let tw = self.data.body_velocity[self.point.body];
        let w_r = Vector3::new(tw[3], tw[4], tw[5]);
        let v_r = Vector3::new(tw[0], tw[1], tw[2]) + w_r.cross(&(xp - self.data.base_position));
        let s = match &mut self.target {
            WatchedTarget::Body { body, clock } => body.state(*clock + t)?,
            WatchedTarget::InLoop { offset } => std::array::from_fn(|i| y[*offset + i]),
        };
        let p = Vector3::new(s[0], s[1], s[2]) + matrix_from_xyzw(&[s[3], s[4], s[5], s[6]]) * self.grasp;
        let (rt, vt, wt) = (Vector3::new(s[0], s[1], s[2]), Vector3::new(s[7], s[8], s[9]), Vector3::new(s[10], s[11], s[12]));
        let rel = Vector6::from_iterator((v_r - (vt + wt.cross(&(xp - rt)))).iter().chain((w_r - wt).iter()).copied());
        let dv = rel.fixed_rows::<3>(0).norm();
        let dw = rel.fixed_rows::<3>(3).norm();
        Ok(((xp - p).norm() / self.limits[0]).max(dv / self.limits[1]).max(dw / self.limits[2]) - 1.0)
    }
}

/// The RK4 run of one segment watched by a threshold attach: `g` at every step's end, the step
/// in which it first holds re-taken from its start with shorter steps to locate `t*`
/// ([`locate_root`]); the run ends there. Returns the result and `Some(t*)` when it held.
fn run_located(plant: Plant<'_>, x: &[f64], u: &[f64], opts: &SimOptions, mut watch: AttachWatch<'_>, progress: Progress<'_>) -> Result<(SimResult, Option<f64>)> {
    let n_steps = rk4_step_count(opts);
    let mut stepper = Rk4Stepper::new(plant, x, u, Some((sample_count(opts), opts.record_every)))?;
    let y0 = stepper.full_state().to_vec();
    crate::sim::step_limit::check_rk4_step(stepper.plant_mut(), 0.0, &y0, opts.dt.min(opts.duration))?;
    let mut g_prev = watch.g(0.0, &y0)?;
    if g_prev <= 0.0 {
        let res = stepper.finish()?;
        return Ok((res, Some(0.0)));
    }
    let dim = y0.len();
    let (mut y_prev, mut y_try) = (y0.clone(), vec![0.0; dim]);
    let mut rk = Rk4::new(dim);
    let mut t_prev = 0.0;
    let mut found = None;
    for i in 0..n_steps {
        let t_next = if i + 1 == n_steps { opts.duration } else { (i + 1) as f64 * opts.dt };
        y_prev.copy_from_slice(stepper.full_state());
        stepper.step_to(t_next)?;
        let g_next = watch.g(t_next, stepper.full_state())?;
        if g_next <= 0.0 {
            let plant = stepper.plant_mut();
            let mut g_at = |t: f64| -> Result<f64> {
                rk.step_from(&mut *plant, t_prev, &y_prev, t, &mut y_try)?;
                watch.g(t, &y_try)
            };
            let (t_s, _) = locate_root(&mut g_at, (t_prev, g_prev), (t_next, g_next))?;
            stepper.land_retaken(&mut rk, (t_prev, &y_prev), t_s, t_next, &mut y_try)?;
            found = Some(t_s);
            break;
        }
        progress(t_next / opts.duration)?;
        g_prev = g_next;
        t_prev = t_next;
    }
    Ok((stepper.finish()?, found))
}

fn shifted(mut res: SimResult, t0: f64) -> SimResult {
    for t in &mut res.records.t {
        *t += t0;
    }
    for e in &mut res.events {
        e.t += t0;
    }
    res
}

/// Append `b`'s samples, events and counters to `a`; drifts the larger of the two.
fn append(a: &mut SimResult, b: SimResult) {
    append_records(&mut a.records, b.records);
    a.events.extend(b.events);
    for (c, d) in &mut a.drift {
        if let Some((_, e)) = b.drift.iter().find(|(k, _)| k == c) {
            *d = d.max(*e);
        }
    }
    for (c, d) in &mut a.drift_scales {
        if let Some((_, e)) = b.drift_scales.iter().find(|(k, _)| k == c) {
            *d = d.max(*e);
        }
    }
    a.n_steps += b.n_steps;
    a.n_rejected += b.n_rejected;
    a.n_rhs_evals += b.n_rhs_evals;
    a.dropped_wrench_max = a.dropped_wrench_max.max(b.dropped_wrench_max);
    a.dropped_wrench_count += b.dropped_wrench_count;
    a.goal = b.goal;
}

/// Every field of `b` after `a`'s (an optional one kept only when both have it).
fn append_records(a: &mut Records, b: Records) {
    let Records {
        n_samples,
        t,
        x,
        u,
        du,
        tau,
        tau_cmd,
        base_wrench,
        linear_momentum,
        angular_momentum_origin,
        angular_momentum_com,
        energy,
        com,
        ee_position,
        ee_quat,
        reference,
        tracking_error,
        link_tracking_error,
        attitude_error,
        wheel_speed,
        solve_time,
        solve_iterations,
        solve_cost,
        solve_converged,
        cmg_measure,
        cmg_envelope_fraction,
        r_cm_eci,
        v_cm_eci,
        gravity_wrench,
        contact_count,
        contact_normal_force,
        contact_work,
        contact_forces,
        contact_impulse,
        target_state,
        ledger_momentum,
        ledger_energy,
        constraint_wrench,
        constraint_error,
    } = b;
    // The contact rows' first entry is their sample's index: shifted by `a`'s samples.
    let shift = a.n_samples as f64;
    let contact_forces = contact_forces.map(|mut rows| {
        rows.chunks_mut(crate::sim::result::CONTACT_FORCE_WIDTH).for_each(|r| r[0] += shift);
        rows
    });
    a.n_samples += n_samples;
    for (to, from) in [
        (&mut a.t, t),
        (&mut a.x, x),
        (&mut a.u, u),
        (&mut a.du, du),
        (&mut a.tau, tau),
        (&mut a.tau_cmd, tau_cmd),
        (&mut a.base_wrench, base_wrench),
        (&mut a.linear_momentum, linear_momentum),
        (&mut a.angular_momentum_origin, angular_momentum_origin),
        (&mut a.angular_momentum_com, angular_momentum_com),
        (&mut a.energy, energy),
        (&mut a.com, com),
    ] {
        to.extend(from);
    }
    for (to, from) in [
        (&mut a.ee_position, ee_position),
        (&mut a.ee_quat, ee_quat),
        (&mut a.reference, reference),
        (&mut a.tracking_error, tracking_error),
        (&mut a.link_tracking_error, link_tracking_error),
        (&mut a.attitude_error, attitude_error),
        (&mut a.wheel_speed, wheel_speed),
        (&mut a.solve_time, solve_time),
        (&mut a.solve_iterations, solve_iterations),
        (&mut a.solve_cost, solve_cost),
        (&mut a.solve_converged, solve_converged),
        (&mut a.cmg_measure, cmg_measure),
        (&mut a.cmg_envelope_fraction, cmg_envelope_fraction),
        (&mut a.r_cm_eci, r_cm_eci),
        (&mut a.v_cm_eci, v_cm_eci),
        (&mut a.gravity_wrench, gravity_wrench),
        (&mut a.contact_count, contact_count),
        (&mut a.contact_normal_force, contact_normal_force),
        (&mut a.contact_work, contact_work),
        (&mut a.contact_forces, contact_forces),
        (&mut a.contact_impulse, contact_impulse),
        (&mut a.target_state, target_state),
        (&mut a.ledger_momentum, ledger_momentum),
        (&mut a.ledger_energy, ledger_energy),
        (&mut a.constraint_wrench, constraint_wrench),
        (&mut a.constraint_error, constraint_error),
    ] {
        match (to.as_mut(), from) {
            (Some(v), Some(w)) => v.extend(w),
            _ => *to = None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::ZeroTorque;
    use crate::model::builder::LinkSpec;
    use crate::model::edit::Mount;
    use crate::scenario::modes::Mode;

    fn zero(_: &Model) -> Result<Box<dyn Controller>> {
        Ok(Box::new(ZeroTorque))
    }

    /// A box target with a handle, at `r` moving at `v`, spinning at `w`.
    fn target(r: [f64; 3], v: [f64; 3], w: [f64; 3]) -> (Model, Vec<f64>) {
        let mut b = ModelBuilder::new("target", "target", 50.0, [[4.0, 0.0, 0.0], [0.0, 5.0, 0.0], [0.0, 0.0, 6.0]]).unwrap();
        b.add_point("handle", "target", [-0.5, 0.0, 0.0]).unwrap();
        let s = [r[0], r[1], r[2], 0.0, 0.0, 0.0, 1.0, v[0], v[1], v[2], w[0], w[1], w[2]];
        (b.build().unwrap(), s.to_vec())
    }

    fn robot() -> (Model, Vec<f64>, Vec<f64>) {
        let robot = crate::model::presets::spatial6();
        let x0: Vec<f64> = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0].iter().copied().chain(robot.initial_q().iter().copied()).collect();
        let mut u0 = vec![0.0; robot.nu()];
        u0[0] = 0.02;
        u0[5] = 0.01;
        for (i, v) in u0[6..].iter_mut().enumerate() {
            *v = 0.05 * (i as f64 + 1.0) * if i % 2 == 0 { 1.0 } else { -1.0 };
        }
        (robot, x0, u0)
    }

    fn ee(robot: &Model, x: &[f64]) -> Vector3<f64> {
        let mut d = Data::new(robot);
        forward_kinematics(robot, &mut d, x).unwrap();
        let p = &robot.points()[robot.end_effector().unwrap()];
        point_position(&d, p.body, &p.offset)
    }

    fn opts(duration: f64, dt: f64) -> SimOptions {
        SimOptions { mode: Mode::Floating, duration, dt, ..SimOptions::default() }
    }

    fn rel(a: &[f64], b: &[f64]) -> f64 {
        let d: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>().sqrt();
        d / a.iter().map(|x| x * x).sum::<f64>().sqrt()
    }

    #[test]
    fn momentum_is_continuous_through_attach_detach_and_redock_and_the_impulses_are_the_jumps() {
        let (robot, x0, u0) = robot();
        let p = ee(&robot, &x0);
        let (tm, s0) = target([p.x + 0.6, p.y, p.z], [-0.05, 0.01, 0.0], [0.0, 0.05, 0.1]);
        let events = [
            TopologyEvent::Attach { at: Some(0.3), point: None, grasp: None, gap: None, speed: None, rate: None },
            TopologyEvent::Detach { at: 0.6, body: None, impulse: 2.0, direction: Some([1.0, 0.5, 0.0]) },
            TopologyEvent::Attach { at: Some(0.9), point: None, grasp: Some("handle".into()), gap: None, speed: None, rate: None },
        ];
        let run = simulate_with_events(&robot, &x0, &u0, &opts(1.2, 0.01), &mut zero, Some((&tm, &s0)), &events, &mut |_| Ok(())).unwrap();
        assert_eq!(run.events.len(), 3);
        let n = run.result.records.n_samples;
        assert_eq!(run.attached.len(), n);
        let m_t = tm.total_mass();
        for ev in &run.events {
            // continuous to rounding, a non-trivial momentum
            let h: f64 = ev.momentum_before.iter().map(|v| v * v).sum::<f64>().sqrt();
            assert!(h > 1.0, "{}: momentum in play {h}", ev.kind);
            assert!(rel(&ev.momentum_before, &ev.momentum_after) < 1e-12, "{} at {}: {:?} vs {:?}", ev.kind, ev.t, ev.momentum_before, ev.momentum_after);
            // the event's two samples: the ledger continuous, the target's momentum jumps by the impulse
            let k = run.result.records.t.iter().position(|&t| t == ev.t).unwrap();
            assert_eq!(run.result.records.t[k + 1], ev.t, "the event's instant recorded twice");
            let (lb, la) = (&run.ledger_momentum[6 * k..6 * k + 6], &run.ledger_momentum[6 * k + 6..6 * k + 12]);
            assert!(rel(lb, la) < 1e-12, "{}: ledger {lb:?} vs {la:?}", ev.kind);
            let (sb, sa) = (&run.target[13 * k..13 * k + 13], &run.target[13 * k + 13..13 * k + 26]);
            let dp: Vec<f64> = (7..10).map(|i| m_t * (sa[i] - sb[i])).collect();
            let sign = if ev.kind == "attach" { -1.0 } else { 1.0 };
            let want: Vec<f64> = ev.impulse[..3].iter().map(|f| sign * f).collect();
            assert!(want.iter().map(|v| v.abs()).sum::<f64>() > 0.1, "{}: an impulse {:?}", ev.kind, ev.impulse);
            assert!(rel(&want, &dp) < 1e-9, "{}: Δ(m v_t) {dp:?} vs impulse {want:?}", ev.kind);
            assert_eq!((run.attached[k], run.attached[k + 1]), (ev.kind == "detach", ev.kind == "attach"));
        }
        // the separation impulse as asked: 2 N·s along (1, 0.5, 0)
        let f = &run.events[1].impulse;
        assert!((f[0].hypot(f[1]) - 2.0).abs() < 1e-12 && (f[1] / f[0] - 0.5).abs() < 1e-12);
        // the whole ledger drifts only by the integration error between the events
        let dev = (0..n).map(|j| rel(&run.ledger_momentum[..6], &run.ledger_momentum[6 * j..6 * j + 6])).fold(0.0, f64::max);
        assert!(dev < 1e-6, "ledger drift {dev} (RK4 at dt = 0.01 s between the events)");
        // and the robot's own records jump at each event (the ledger is not the records)
        let k = run.result.records.t.iter().position(|&t| t == 0.3).unwrap();
        assert!(rel(&run.result.records.linear_momentum[3 * k..3 * k + 3], &run.result.records.linear_momentum[3 * k + 3..3 * k + 6]) > 1e-3);
    }

    #[test]
    fn a_release_without_impulse_keeps_the_energy_and_the_released_body_flies_free() {
        let (robot, x0, u0) = robot();
        let ee_body = robot.points()[robot.end_effector().unwrap()].body;
        let spec = LinkSpec::payload("pod", &Mount::new(robot.body_name(ee_body), [0.1, 0.05, 0.0], [0.0, 0.0, 0.0, 1.0]), 8.0, [[0.2, 0.0, 0.0], [0.0, 0.3, 0.0], [0.0, 0.0, 0.25]]);
        let robot = robot.attach_body(spec, None).unwrap();
        let events = [TopologyEvent::Detach { at: 0.25, body: Some("pod".into()), impulse: 0.0, direction: None }];
        let run = simulate_with_events(&robot, &x0, &u0, &opts(0.5, 0.01), &mut zero, None, &events, &mut |_| Ok(())).unwrap();
        let ev = &run.events[0];
        assert!(ev.energy_before > 1e-3, "energy in play {}", ev.energy_before);
        assert!((ev.energy_after - ev.energy_before).abs() < 1e-12 * ev.energy_before, "{} vs {}", ev.energy_before, ev.energy_after);
        assert!(rel(&ev.momentum_before, &ev.momentum_after) < 1e-12);
        let k = run.result.records.t.iter().position(|&t| t == 0.25).unwrap();
        let (eb, ea) = (run.ledger_energy[k], run.ledger_energy[k + 1]);
        assert!((eb - ea).abs() < 1e-12 * eb, "{eb} vs {ea}");
        // the robot's own energy dropped by the pod's kinetic energy
        assert!(run.result.records.energy[k] - run.result.records.energy[k + 1] > 1e-6);
        assert_eq!(run.final_model.n_bodies(), robot.n_bodies() - 1);
        // after the release the pod's CM moves in a straight line at constant speed
        let last = run.result.records.n_samples - 1;
        let (s1, s2) = (&run.target[13 * (k + 1)..13 * (k + 2)], &run.target[13 * last..13 * last + 13]);
        let dt = run.result.records.t[last] - 0.25;
        for i in 0..3 {
            assert!((s2[i] - (s1[i] + dt * s1[7 + i])).abs() < 1e-12, "free flight");
        }
        // before the release the pod is a link of the robot, no second system
        assert!(run.target[..13 * (k + 1)].iter().all(|a| a.is_nan()) && !run.attached[k]);
    }

    #[test]
    fn a_threshold_attach_is_located_at_the_closed_form_time() {
        // the robot drifts rigidly (no rates but the base's translation); the target comes at it
        // along the line of the grasp points: the gap falls linearly, gap(t) = d0 − |v_rel| t
        let (robot, x0, _) = robot();
        let mut u0 = vec![0.0; robot.nu()];
        u0[0] = 0.01;
        let p = ee(&robot, &x0);
        let (d0, v, g0) = (0.3, -0.07, 0.02);
        let (tm, s0) = target([p.x + 0.5 + d0, p.y, p.z], [v, 0.0, 0.0], [0.0; 3]);
        let t_star = (d0 - g0) / (0.01 - v);
        let events = [TopologyEvent::Attach { at: None, point: None, grasp: None, gap: Some(g0), speed: None, rate: None }];
        for dt in [0.05, 0.013] {
            let run = simulate_with_events(&robot, &x0, &u0, &opts(6.0, dt), &mut zero, Some((&tm, &s0)), &events, &mut |_| Ok(())).unwrap();
            let ev = &run.events[0];
            assert!((ev.t - t_star).abs() < 1e-12, "dt {dt}: {} vs {t_star}", ev.t);
            assert!((ev.gap - g0).abs() < 1e-12, "gap {}", ev.gap);
            assert!(*run.result.records.t.last().unwrap() > 5.99);
        }
    }

    #[test]
    fn a_tumbling_capture_is_located_to_the_steps_accuracy() {
        // a spinning robot and a tumbling target: the event time converges as the step shrinks
        let (robot, x0, mut u0) = robot();
        for (i, v) in u0[6..].iter_mut().enumerate() {
            *v = 0.01 * (i as f64 + 1.0);
        }
        let p = ee(&robot, &x0);
        let (tm, s0) = target([p.x + 0.5 + 0.15, p.y + 0.02, p.z], [-0.1, 0.0, 0.0], [0.0, 0.0, 0.05]);
        let events = [TopologyEvent::Attach { at: None, point: None, grasp: None, gap: Some(0.09), speed: Some(1.0), rate: None }];
        let t_of = |dt: f64| simulate_with_events(&robot, &x0, &u0, &opts(3.0, dt), &mut zero, Some((&tm, &s0)), &events, &mut |_| Ok(())).unwrap().events.first().map_or(f64::NAN, |e| e.t);
        let (coarse, fine, finest) = (t_of(0.02), t_of(0.005), t_of(0.00125));
        assert!(coarse > 0.1 && coarse < 3.0, "{coarse} {fine} {finest}");
        let (e1, e2) = ((coarse - finest).abs(), (fine - finest).abs());
        assert!(e1 < 1e-6 && e2 < e1 / 20.0 + 1e-13, "event time errors {e1:e}, {e2:e} (RK4: O(h⁴))");
    }

    /// A floating base (ball 0.3) with a hinged arm whose tip ball (0.1, its surface point
    /// "tip") points along x, and a 2 kg ball target (0.2) with its "handle" on the surface
    /// facing the tip, coming at it along x at 0.1 m/s: contact stops it on the tip.
    fn contact_scene() -> (Model, Model, Vec<f64>, SimOptions) {
        use crate::model::geometry::{GeometrySpec, Shape};
        use crate::model::joint::JointType as J;
        let ball = |body: &str, radius: f64, origin: [f64; 3]| GeometrySpec {
            name: None,
            body: body.into(),
            role: GeometryRole::Collision,
            shape: Shape::Sphere { radius },
            origin,
            rotation: [0.0, 0.0, 0.0, 1.0],
            rgba: None,
        };
        let mut b = ModelBuilder::new("bus", "base", 100.0, [[3.6, 0.0, 0.0], [0.0, 3.6, 0.0], [0.0, 0.0, 3.6]]).unwrap();
        b.add_link(LinkSpec::new("l1", "base", J::Revolute, [0.5, 0.0, 0.0], [0.0, 0.0, 1.0], [0.3, 0.0, 0.0], 3.0, [0.02, 0.1, 0.1])).unwrap();
        b.add_geometry(ball("base", 0.3, [0.0; 3])).unwrap();
        b.add_geometry(ball("l1", 0.1, [0.3, 0.0, 0.0])).unwrap();
        b.add_point("tip", "l1", [0.4, 0.0, 0.0]).unwrap();
        let robot = b.build().unwrap();
        let mut t = ModelBuilder::new("rock", "rock", 2.0, [[0.08, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 0.12]]).unwrap();
        t.add_geometry(ball("rock", 0.2, [0.0; 3])).unwrap();
        t.add_point("handle", "rock", [-0.2, 0.0, 0.0]).unwrap();
        let s0 = vec![1.45, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, -0.1, 0.0, 0.0, 0.0, 0.0, 0.0];
        let mut c: crate::sim::contact::ContactSpec = toml::from_str("stiffness = 2e4\ndamping = 30.0\nfriction = 0.4\nslip_velocity = 0.01").unwrap();
        c.pairs = Some(vec![["l1".into(), "target".into()]]);
        let o = SimOptions { mode: Mode::Floating, duration: 1.2, dt: 1e-3, contact: Some(c), ..SimOptions::default() };
        (robot, t.build().unwrap(), s0, o)
    }

    #[test]
    fn a_grasp_on_contact_and_a_release_keep_momentum_and_energy_in_one_run_with_contact() {
        let (robot, rock, s0, o) = contact_scene();
        let x0 = vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        // the robot drifts and turns a little; the rock spins
        let u0 = vec![0.01, 0.0, 0.0, 0.0, 0.0, 0.005, 0.0];
        let mut s0 = s0;
        s0[10..13].copy_from_slice(&[0.05, 0.0, 0.0]);
        let events = [
            TopologyEvent::Attach { at: None, point: Some(PointSpec::Named("tip".into())), grasp: Some("handle".into()), gap: Some(0.01), speed: Some(0.01), rate: None },
            TopologyEvent::Detach { at: 0.9, body: None, impulse: 0.0, direction: None },
        ];
        let run = simulate_with_events(&robot, &x0, &u0, &o, &mut zero, Some((&rock, &s0)), &events, &mut |_| Ok(())).unwrap();
        assert_eq!(run.events.len(), 2, "{:?}", run.events);
        let rec = &run.result.records;
        let n = rec.n_samples;
        assert_eq!((run.phase.len(), run.attached.len(), run.target.len(), run.ledger_energy.len()), (n, n, 13 * n, n));
        let (ta, td) = (run.events[0].t, run.events[1].t);
        // the grasp came on contact: the contact force acted in phase 0, before the weld
        let count = rec.contact_count.as_ref().unwrap();
        let touching: Vec<f64> = (0..n).filter(|&j| count[j] > 0.0).map(|j| rec.t[j]).collect();
        assert!(!touching.is_empty() && touching[0] < ta && touching[0] > 0.3, "contact at {:?}, attach at {ta}", touching.first());
        // it stopped the rock on the tip: no relative speed above the threshold at the weld
        assert!(run.events[0].gap < 0.01 && ta < 0.7, "gap {} at {ta}", run.events[0].gap);
        // no contact while welded (its pairs name the target), contact in the loop again after
        // the release (they still touch: the contact pushes them apart)
        for j in 0..n {
            let expected = if rec.t[j] < ta || (rec.t[j] == ta && !run.attached[j]) { 0 } else if rec.t[j] < td || (rec.t[j] == td && run.attached[j]) { 1 } else { 2 };
            assert_eq!(run.phase[j], expected, "sample {j} at {}", rec.t[j]);
            assert_eq!(run.attached[j], expected == 1);
            if expected == 1 {
                assert_eq!(count[j], 0.0);
            }
        }
        assert!((0..n).any(|j| run.phase[j] == 2 && count[j] > 0.0), "contact in the loop after the release");
        for ev in &run.events {
            let h: f64 = ev.momentum_before.iter().map(|v| v * v).sum::<f64>().sqrt();
            assert!(h > 0.1, "{}: momentum in play {h}", ev.kind);
            assert!(rel(&ev.momentum_before, &ev.momentum_after) < 1e-12, "{} at {}: {:?} vs {:?}", ev.kind, ev.t, ev.momentum_before, ev.momentum_after);
            // the ledger's two samples at the event's instant
            let k = rec.t.iter().position(|&t| t == ev.t).unwrap();
            assert_eq!(rec.t[k + 1], ev.t);
            assert!(rel(&run.ledger_momentum[6 * k..6 * k + 6], &run.ledger_momentum[6 * k + 6..6 * k + 12]) < 1e-12, "{}: ledger", ev.kind);
        }
        // the release without a separation impulse keeps the kinetic energy
        let ev = &run.events[1];
        assert!(ev.energy_before > 1e-3);
        assert!((ev.energy_after - ev.energy_before).abs() < 1e-12 * ev.energy_before, "{} vs {}", ev.energy_before, ev.energy_after);
        let k = rec.t.iter().position(|&t| t == td).unwrap();
        assert!((run.ledger_energy[k] - run.ledger_energy[k + 1]).abs() < 1e-12 * run.ledger_energy[k]);
        // the attach's impulse is the jump of the rock's momentum (from its rows), equal and
        // opposite to the robot's: the ledger, computed from the records and the rows, continuous
        let k = rec.t.iter().position(|&t| t == ta).unwrap();
        let (sb, sa) = (&run.target[13 * k..13 * k + 13], &run.target[13 * k + 13..13 * k + 26]);
        let dp: Vec<f64> = (7..10).map(|i| 2.0 * (sa[i] - sb[i])).collect();
        let want: Vec<f64> = run.events[0].impulse[..3].iter().map(|f| -f).collect();
        assert!(rel(&want, &dp) < 1e-9, "Δ(m v) {dp:?} vs impulse {want:?}");
        // over the whole run, robot + rock keep their momentum to the integration error (the
        // contact forces are internal)
        let dev = (0..n).map(|j| rel(&run.ledger_momentum[..6], &run.ledger_momentum[6 * j..6 * j + 6])).fold(0.0, f64::max);
        assert!(dev < 1e-8, "ledger drift {dev}");
    }

    #[test]
    fn events_the_run_cannot_do_are_refused_with_their_reason() {
        let (robot, x0, u0) = robot();
        let attach = TopologyEvent::Attach { at: Some(0.1), point: None, grasp: None, gap: None, speed: None, rate: None };
        let err = |o: &SimOptions, ev: &[TopologyEvent]| simulate_with_events(&robot, &x0, &u0, o, &mut zero, None, ev, &mut |_| Ok(())).unwrap_err().to_string();
        let e = err(&opts(0.3, 0.01), std::slice::from_ref(&attach));
        assert!(e.contains("no free target to attach"), "{e}");
        let e = err(&opts(0.3, 0.01), &[TopologyEvent::Detach { at: 0.1, body: Some(robot.body_name(2).to_string()), impulse: 0.0, direction: None }]);
        assert!(e.contains("is not implemented: only a rigid link on a fixed joint"), "{e}");
        let e = err(&SimOptions { stop: vec![crate::sim::stop::StopCondition::Time { t: 0.1 }], ..opts(0.3, 0.01) }, &[attach]);
        assert!(e.contains("stop conditions are not implemented"), "{e}");
        let rigid: crate::sim::contact::ContactSpec = toml::from_str("kind = \"rigid\"").unwrap();
        let located = TopologyEvent::Attach { at: None, point: None, grasp: None, gap: Some(0.1), speed: None, rate: None };
        let e = err(&SimOptions { contact: Some(rigid), ..opts(0.3, 0.01) }, &[located]);
        assert!(e.contains("an attach located by thresholds is not implemented with rigid contact (kind='rigid')"), "{e}");
    }
}
