//! The records of a run: buffers allocated once per run ([`Recorder::new`]), one sample per
//! recorded instant, the drift of the conserved quantities, and the saturation onsets; shared by
//! [`crate::sim::simulate`] (both integrators) and the step-by-step [`crate::sim::stepper`].
//! The quantities and the drift's definition are in the docs of [`crate::sim::simulate`].

use crate::algorithms::passive::spring_energy_of_q;
use nalgebra::{Rotation3, UnitQuaternion, Vector3};

use crate::algorithms::kinematics::point_position;
use crate::analysis::cmg_envelope::envelope_fraction;
use crate::control::cmg_jacobian::{cluster_from_kinematics, cmg_jacobian_from_axes, singularity_measure};
use crate::control::{arm_dofs, TrackingKind};
use crate::model::cmg::{detect_cmgs, Cmg};
use crate::model::appendage::compliant_pairs;
use crate::algorithms::momentum::{center_of_mass_from_data, conserved_drift, momentum_from_data, momentum_scales_from_data, MomentumScales};
use crate::model::Model;
use crate::scenario::actuators::SaturationKind;
use crate::scenario::modes::Conserved;
use crate::error::Result;
use crate::math::integrate::IntegratorKind;
use crate::scenario::actuators::Actuators;
use crate::sim::plant::Plant;
use crate::collision::compliant::ContactForce;
use crate::sim::result::{Records, SaturationEvent, SimResult, CONTACT_FORCE_WIDTH};

/// A base CMG cluster's records at the kinematics `data` and the velocity `u`: its singularity
/// measure `det(A Aᵀ)/h̄⁶` (control/cmg_jacobian.rs) and its momentum-envelope fraction
/// `|H|/σ(Ĥ)` (analysis/cmg_envelope.rs); what [`Records::cmg_measure`] and
/// [`Records::cmg_envelope_fraction`] hold and what a record stop condition watches
/// ([`crate::sim::events`]).
pub(crate) fn cmg_records(model: &Model, data: &crate::model::data::Data, cmgs: &[Cmg], u: &[f64]) -> (f64, f64) {
    let (g, s, h) = cluster_from_kinematics(model, data, cmgs, u);
    (singularity_measure(&cmg_jacobian_from_axes(&g, &s, &h), &h), envelope_fraction(&g, &s, &h))
}

/// The records of one run and what is needed to extend them; [`Recorder::new`] is the one place
/// where record buffers are allocated.
#[derive(Debug, Clone)]
pub(crate) struct Recorder {
    pub(crate) rec: Records,
    ee: Option<(usize, Vector3<f64>)>,
    wheels: Vec<usize>,
    n_ref: usize,
    scales: MomentumScales,
    last_quat: Option<UnitQuaternion<f64>>,
    /// For [`Records::link_tracking_error`]: per joint reference entry, its motor dof and the
    /// deflection dof of its compliant joint, if it has one.
    link: Vec<(usize, Option<usize>)>,
    /// Whether the drift is a momentum balance against the recorded tidal wrench (an orbital
    /// run with the gravity gradient).
    pub(crate) balance: bool,
    /// The control-moment gyros whose singularity measure and envelope fraction are recorded
    /// (every CMG of the plant when all are on the base; none otherwise).
    cmgs: Vec<Cmg>,
    /// With a free target: robot + target angular momentum about their CM per sample (width
    /// 3; the drift's, not recorded) and the running maxima of the target's momentum scales.
    ledger_l_com: Vec<f64>,
    target_scales: MomentumScales,
}

impl Recorder {
    /// Buffers for `capacity` samples of what `plant` produces (its model's end effector, its
    /// wheels, its controller's reference and errors).
    pub(crate) fn for_plant(plant: &Plant<'_>, capacity: usize) -> Self {
        let c = &plant.controller;
        let mut rec = Recorder::new(plant.model(), capacity, &plant.wheels, c.reference_len(), c.tracking().is_some(), c.reports_attitude_error());
        if plant.closure.is_some() {
            rec.rec.constraint_wrench = Some(Vec::with_capacity(6 * capacity));
            rec.rec.constraint_error = Some(Vec::with_capacity(6 * capacity));
        }
        if c.reports_solve() {
            let r = &mut rec.rec;
            for v in [&mut r.solve_time, &mut r.solve_iterations, &mut r.solve_cost, &mut r.solve_converged] {
                *v = Some(Vec::with_capacity(capacity));
            }
        }
        rec.link = Recorder::link_joints(plant);
        rec.cmgs = Recorder::base_cmgs(plant.model());
        if !rec.cmgs.is_empty() {
            rec.rec.cmg_measure = Some(Vec::with_capacity(capacity));
            rec.rec.cmg_envelope_fraction = Some(Vec::with_capacity(capacity));
        }
        if !rec.link.is_empty() {
            rec.rec.link_tracking_error = Some(Vec::with_capacity(capacity));
        }
        if plant.orbit.is_some() {
            rec.rec.r_cm_eci = Some(Vec::with_capacity(3 * capacity));
            rec.rec.v_cm_eci = Some(Vec::with_capacity(3 * capacity));
            rec.rec.gravity_wrench = Some(Vec::with_capacity(6 * capacity));
            rec.balance = plant.has_gravity_gradient();
        }
        if plant.contact.is_some() {
            rec.rec.contact_count = Some(Vec::with_capacity(capacity));
            rec.rec.contact_normal_force = Some(Vec::with_capacity(capacity));
            rec.rec.contact_work = Some(Vec::with_capacity(capacity));
            if !plant.is_rigid() {
                rec.rec.contact_forces = Some(Vec::new()); // the compliant law's forces (a rigid run records its impulses)
            }
            if plant.is_rigid() {
                rec.rec.contact_impulse = Some(Vec::with_capacity(3 * capacity));
            }
        }
        if plant.target().is_some() {
            rec.rec.target_state = Some(Vec::with_capacity(13 * capacity));
            rec.rec.ledger_momentum = Some(Vec::with_capacity(6 * capacity));
            rec.rec.ledger_energy = Some(Vec::with_capacity(capacity));
        }
        rec
    }

    /// Values recorded per sample by a recorder of [`Recorder::for_plant`].
    pub(crate) fn values_per_sample_of(plant: &Plant<'_>) -> usize {
        let c = &plant.controller;
        let closure = if plant.closure.is_some() { 12 } else { 0 };
        let orbit = if plant.orbit.is_some() { 12 } else { 0 } + if plant.contact.is_some() { 3 } else { 0 } + if plant.is_rigid() { 3 } else { 0 } + if plant.target().is_some() { 20 } else { 0 };
        let link = usize::from(!Recorder::link_joints(plant).is_empty());
        let cmg = if Recorder::base_cmgs(plant.model()).is_empty() { 0 } else { 2 };
        let solve = if c.reports_solve() { 4 } else { 0 };
        solve + cmg + link + orbit + closure + Recorder::values_per_sample(plant.model(), plant.wheels.len(), c.reference_len(), c.tracking().is_some(), c.reports_attitude_error())
    }

    /// The plant's CMGs when every one is on the base (the cluster the steering law drives);
    /// empty otherwise.
    pub(crate) fn base_cmgs(model: &Model) -> Vec<Cmg> {
        let cmgs = detect_cmgs(model);
        if cmgs.iter().all(|c| c.parent_body == 0) {
            cmgs
        } else {
            Vec::new()
        }
    }

    /// The joints of a joint-space tracking controller's reference (one entry per actuated arm
    /// joint, ascending), each with the deflection dof of its compliant joint
    /// ([`compliant_pairs`]); empty unless the controller tracks joints and one of them is
    /// compliant (the link's error is then the motor's).
    fn link_joints(plant: &Plant<'_>) -> Vec<(usize, Option<usize>)> {
        let (model, c) = (plant.model(), &plant.controller);
        if c.tracking() != Some(TrackingKind::Joint) {
            return Vec::new();
        }
        let pairs = compliant_pairs(model);
        let dynamics = model.dof_dynamics();
        let joints: Vec<(usize, Option<usize>)> = arm_dofs(model.n_dof(), &plant.wheels)
            .into_iter()
            .filter(|&d| dynamics[d].actuated)
            .map(|d| (d, pairs.iter().find(|p| p.0 == d).map(|p| p.1)))
            .collect();
        if joints.len() != c.reference_len() || joints.iter().all(|j| j.1.is_none()) {
            return Vec::new();
        }
        joints
    }

    /// Values recorded per sample: the sum of the widths that [`Recorder::new`] reserves (keep
    /// the two in step).
    pub(crate) fn values_per_sample(model: &Model, n_wheels: usize, n_ref: usize, tracking: bool, attitude: bool) -> usize {
        let (nx, nu, n) = (model.nx(), model.nu(), model.n_dof());
        let ee = if model.end_effector().is_some() { 3 + 4 } else { 0 };
        1 + nx + 2 * nu + 2 * n + 6 + 3 + 3 + 3 + 1 + 3 + ee + n_ref + usize::from(tracking) + usize::from(attitude) + n_wheels
    }

    /// Buffers for `capacity` samples (reserved up front, so recording never reallocates).
    pub(crate) fn new(model: &Model, capacity: usize, wheels: &[usize], n_ref: usize, tracking: bool, attitude: bool) -> Self {
        let (nx, nu, n) = (model.nx(), model.nu(), model.n_dof());
        let v = |w: usize| Vec::with_capacity(capacity * w);
        let ee = model.end_effector().map(|i| (model.points()[i].body, model.points()[i].offset));
        Recorder {
            rec: Records {
                n_samples: 0,
                t: v(1),
                x: v(nx),
                u: v(nu),
                du: v(nu),
                tau: v(n),
                tau_cmd: v(n),
                base_wrench: v(6),
                linear_momentum: v(3),
                angular_momentum_origin: v(3),
                angular_momentum_com: v(3),
                energy: v(1),
                com: v(3),
                ee_position: ee.map(|_| v(3)),
                ee_quat: ee.map(|_| v(4)),
                reference: (n_ref > 0).then(|| v(n_ref)),
                tracking_error: tracking.then(|| v(1)),
                link_tracking_error: None,
                attitude_error: attitude.then(|| v(1)),
                wheel_speed: (!wheels.is_empty()).then(|| v(wheels.len())),
                solve_time: None,
                solve_iterations: None,
                solve_cost: None,
                solve_converged: None,
                cmg_measure: None,
                cmg_envelope_fraction: None,
                constraint_wrench: None,
                constraint_error: None,
                r_cm_eci: None,
                v_cm_eci: None,
                gravity_wrench: None,
                contact_count: None,
                contact_normal_force: None,
                contact_work: None,
                contact_forces: None,
                contact_impulse: None,
                target_state: None,
                ledger_momentum: None,
                ledger_energy: None,
            },
            balance: false,
            ee,
            wheels: wheels.to_vec(),
            n_ref,
            scales: MomentumScales::default(),
            last_quat: None,
            link: Vec::new(),
            cmgs: Vec::new(),
            ledger_l_com: Vec::new(),
            target_scales: MomentumScales::default(),
        }
    }

    /// Record the sample at `(t, y)`; the plant has just evaluated `dy = f(t, y)`, so its
    /// workspace holds the kinematics at `x` and the body velocities at `u`.
    pub(crate) fn record(&mut self, plant: &Plant<'_>, t: f64, y: &[f64], dy: &[f64]) {
        let (model, data) = (plant.model(), &plant.data);
        let nx = plant.nx;
        let r = &mut self.rec;
        r.n_samples += 1;
        r.t.push(t);
        r.x.extend_from_slice(&y[..nx]);
        let nu = model.nu();
        r.u.extend_from_slice(&y[nx..nx + nu]);
        r.du.extend_from_slice(&dy[nx..nx + nu]);
        r.tau.extend_from_slice(&plant.tau_applied);
        r.tau_cmd.extend_from_slice(&plant.cmd.tau);
        r.base_wrench.extend_from_slice(plant.wrench_applied.as_slice());
        // Momentum and energy from the body velocities (spatial, at the base CM), body by body,
        // with the scale of each sum's terms for the drift (module docs).
        let momentum = momentum_from_data(model, data);
        let rg = center_of_mass_from_data(model, data);
        let mut scales = momentum_scales_from_data(model, data);
        // The mechanical energy: kinetic plus the joint springs' potential (docs/flexibility.md).
        scales.energy += spring_energy_of_q(model, &y[7..nx]);
        let energy = scales.energy;
        r.linear_momentum.extend_from_slice(momentum.linear.as_slice());
        r.angular_momentum_origin.extend_from_slice(momentum.angular_about_origin.as_slice());
        r.angular_momentum_com.extend_from_slice(momentum.angular_about_com.as_slice());
        r.energy.push(energy);
        r.com.extend_from_slice(rg.as_slice());
        self.scales = self.scales.max(scales);
        if let Some((body, offset)) = self.ee {
            let pos = point_position(data, body, &offset);
            r.ee_position.as_mut().expect("allocated with ee").extend_from_slice(pos.as_slice());
            let mut q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(data.body_to_world[body]));
            if let Some(last) = self.last_quat {
                if last.coords.dot(&q.coords) < 0.0 {
                    q = UnitQuaternion::new_unchecked(-q.into_inner());
                }
            }
            self.last_quat = Some(q);
            let c = q.coords; // [i, j, k, w]
            r.ee_quat.as_mut().expect("allocated with ee").extend_from_slice(&[c[0], c[1], c[2], c[3]]);
        }
        if let Some(rf) = r.reference.as_mut() {
            rf.extend_from_slice(&plant.cmd.reference[..self.n_ref]);
        }
        if let Some(te) = r.tracking_error.as_mut() {
            te.push(plant.cmd.tracking_error);
        }
        if let Some(le) = r.link_tracking_error.as_mut() {
            // The link angle θ + δ against the same reference (module docs of compliant_pairs).
            let q = &y[7..nx];
            let err2: f64 = self.link.iter().enumerate().map(|(i, &(d, delta))| (plant.cmd.reference[i] - q[d] - delta.map_or(0.0, |e| q[e])).powi(2)).sum();
            le.push(err2.sqrt());
        }
        if let Some(ae) = r.attitude_error.as_mut() {
            ae.push(plant.cmd.attitude_error);
        }
        if let (Some(a), Some(b), Some(c), Some(d)) = (r.solve_time.as_mut(), r.solve_iterations.as_mut(), r.solve_cost.as_mut(), r.solve_converged.as_mut()) {
            let s = plant.cmd.solve;
            a.push(s.time);
            b.push(s.iterations);
            c.push(s.cost);
            d.push(s.converged);
        }
        if let Some(ws) = r.wheel_speed.as_mut() {
            for &d in &self.wheels {
                ws.push(y[nx + 6 + d]);
            }
        }
        if let (Some(m), Some(f)) = (r.cmg_measure.as_mut(), r.cmg_envelope_fraction.as_mut()) {
            let (measure, fraction) = cmg_records(model, data, &self.cmgs, &y[nx..]);
            m.push(measure);
            f.push(fraction);
        }
        if let (Some(c), Some(w), Some(e)) = (&plant.closure, r.constraint_wrench.as_mut(), r.constraint_error.as_mut()) {
            w.extend_from_slice(c.lambda.as_slice());
            e.extend_from_slice(c.error.as_slice());
        }
        if let (Some(rc), Some(vc), Some(gw)) = (r.r_cm_eci.as_mut(), r.v_cm_eci.as_mut(), r.gravity_wrench.as_mut()) {
            let (ro, vo) = plant.orbit_state;
            rc.extend_from_slice((ro + rg).as_slice());
            vc.extend_from_slice((vo + momentum.linear / model.total_mass()).as_slice());
            gw.extend_from_slice(if plant.has_gravity_gradient() { plant.gravity_wrench.as_slice() } else { &[0.0; 6] });
        }
        if let (Some(c), Some(count), Some(fn_), Some(work)) = (&plant.contact, r.contact_count.as_mut(), r.contact_normal_force.as_mut(), r.contact_work.as_mut()) {
            // The work: the state's last entry, the contact power integrated with the motion.
            count.push(c.count as f64);
            fn_.push(c.normal_force);
            work.push(y[nx + nu]);
            if let Some(rows) = r.contact_forces.as_mut() {
                contact_force_rows(r.n_samples - 1, &c.active, rows);
            }
            if let (Some(rigid), Some(imp)) = (&c.rigid, r.contact_impulse.as_mut()) {
                imp.extend_from_slice(rigid.impulse.as_slice());
            }
        }
        if let (Some(t), Some(ts), Some(lm), Some(le)) = (plant.target(), r.target_state.as_mut(), r.ledger_momentum.as_mut(), r.ledger_energy.as_mut()) {
            // Robot + target: the target's momentum and energy from its own state
            // (sim/free_target.rs), added to the robot's.
            let s = t.state(y);
            ts.extend_from_slice(s);
            let m = t.momentum(s);
            let (p, l) = (momentum.linear + m.linear, momentum.angular_about_origin + m.angular_about_origin);
            lm.extend_from_slice(p.as_slice());
            lm.extend_from_slice(l.as_slice());
            le.push(energy + m.energy);
            // About the CM of the two: L_origin − r_G × P.
            let mass = model.total_mass() + t.mass;
            let r_g = (rg * model.total_mass() + Vector3::new(s[0], s[1], s[2]) * t.mass) / mass;
            self.ledger_l_com.extend_from_slice((l - r_g.cross(&p)).as_slice());
            self.target_scales.linear = self.target_scales.linear.max(m.linear_scale);
            self.target_scales.angular_about_origin = self.target_scales.angular_about_origin.max(m.angular_scale);
            let arm = (Vector3::new(s[0], s[1], s[2]) - r_g).cross(&m.linear).norm();
            self.target_scales.angular_about_com = self.target_scales.angular_about_com.max(arm + m.spin_scale);
            self.target_scales.energy = self.target_scales.energy.max(m.energy);
        }
    }

    /// The scale of a conserved quantity's drift: the running maximum of its magnitude scale
    /// (with a free target, plus the running maximum of the target's).
    pub(crate) fn scale(&self, c: Conserved) -> f64 {
        let (s, t) = (&self.scales, &self.target_scales);
        match c {
            Conserved::LinearMomentum => s.linear + t.linear,
            Conserved::AngularMomentumOrigin => s.angular_about_origin + t.angular_about_origin,
            Conserved::AngularMomentumCom => s.angular_about_com + t.angular_about_com,
            Conserved::Energy => s.energy + t.energy,
        }
    }

    /// Drift of each conserved quantity over the recorded samples (see the module docs); in an
    /// orbital run with the gravity gradient, the residual of its balance instead
    /// ([`Recorder::balanced`]).
    pub(crate) fn drift(&self, conserved: &[Conserved]) -> Vec<(Conserved, f64)> {
        if self.balance {
            return conserved.iter().map(|&c| (c, conserved_drift(&self.balanced(c), if c == Conserved::Energy { 1 } else { 3 }, self.scale(c)))).collect();
        }
        let r = &self.rec;
        conserved
            .iter()
            .map(|&c| {
                if let (Some(lm), Some(le)) = (&r.ledger_momentum, &r.ledger_energy) {
                    // With a free target: robot + target is the system that conserves.
                    let pick = |from: usize| lm.chunks(6).flat_map(|row| row[from..from + 3].to_vec()).collect::<Vec<_>>();
                    let work = r.contact_work.as_deref().unwrap_or(&[]);
                    let d = match c {
                        Conserved::LinearMomentum => conserved_drift(&pick(0), 3, self.scale(c)),
                        Conserved::AngularMomentumOrigin => conserved_drift(&pick(3), 3, self.scale(c)),
                        Conserved::AngularMomentumCom => conserved_drift(&self.ledger_l_com, 3, self.scale(c)),
                        Conserved::Energy => conserved_drift(&le.iter().zip(work).map(|(e, w)| e - w).collect::<Vec<_>>(), 1, self.scale(c)),
                    };
                    return (c, d);
                }
                let d = match c {
                    Conserved::LinearMomentum => conserved_drift(&r.linear_momentum, 3, self.scale(c)),
                    Conserved::AngularMomentumOrigin => conserved_drift(&r.angular_momentum_origin, 3, self.scale(c)),
                    Conserved::AngularMomentumCom => conserved_drift(&r.angular_momentum_com, 3, self.scale(c)),
                    Conserved::Energy => match &r.contact_work {
                        // With contact the ledger energy − contact work is what is conserved.
                        Some(w) => conserved_drift(&r.energy.iter().zip(w).map(|(e, w)| e - w).collect::<Vec<_>>(), 1, self.scale(c)),
                        None => conserved_drift(&r.energy, 1, self.scale(c)),
                    },
                };
                (c, d)
            })
            .collect()
    }
}

impl Recorder {
    /// A momentum minus the integral of the tidal wrench since `t = 0` (trapezoid over the
    /// samples), per sample: constant when the balance `Δ(momentum) = ∫ wrench dt` holds. The
    /// force for `P`, the torque about `O` for `L_origin`, about the system CM
    /// (`N_O − r_g × F`) for `L_com`.
    pub(crate) fn balanced(&self, c: Conserved) -> Vec<f64> {
        let r = &self.rec;
        let gw = r.gravity_wrench.as_deref().unwrap_or(&[]);
        let values: &[f64] = match c {
            Conserved::LinearMomentum => &r.linear_momentum,
            Conserved::AngularMomentumOrigin => &r.angular_momentum_origin,
            Conserved::AngularMomentumCom => &r.angular_momentum_com,
            Conserved::Energy => return r.energy.clone(),
        };
        let rate = |k: usize| -> Vector3<f64> {
            let w = &gw[6 * k..6 * k + 6];
            let f = Vector3::new(w[0], w[1], w[2]);
            let n = Vector3::new(w[3], w[4], w[5]);
            match c {
                Conserved::LinearMomentum => f,
                Conserved::AngularMomentumOrigin => n,
                _ => n - Vector3::new(r.com[3 * k], r.com[3 * k + 1], r.com[3 * k + 2]).cross(&f),
            }
        };
        let mut out = Vec::with_capacity(values.len());
        let mut integral = Vector3::zeros();
        for k in 0..r.n_samples {
            if k > 0 {
                integral += 0.5 * (r.t[k] - r.t[k - 1]) * (rate(k) + rate(k - 1));
            }
            for i in 0..3 {
                out.push(values[3 * k + i] - integral[i]);
            }
        }
        out
    }
}

/// Saturation onsets: actuator kinds flagged in this step and not in the previous one.
pub(crate) fn onsets(t: f64, prev: &mut [u8], now: &[u8], events: &mut Vec<SaturationEvent>) {
    for (a, (p, &n)) in prev.iter_mut().zip(now).enumerate() {
        let new = n & !*p;
        if new != 0 {
            for kind in SaturationKind::ALL {
                if new & kind.bit() != 0 {
                    events.push(SaturationEvent { t, actuator: a, kind });
                }
            }
        }
        *p = n;
    }
}

/// Admission control of recorded samples ([`crate::admission`]), the one check of every entry
/// point that records ([`simulate`](crate::sim::simulate::simulate), [`crate::sim::rollout::rollout`], a recording
/// [`Rk4Stepper`](crate::sim::stepper::Rk4Stepper)): `samples` samples of `values` values in all, in `f64`, counted twice (the
/// records and the copy a caller converts them into), refused before any buffer is reserved,
/// with the way out for `integrator`.
pub fn admit_records(integrator: IntegratorKind, samples: f64, values: f64) -> Result<()> {
    let remedy = match integrator {
        IntegratorKind::Rk4 => "record fewer samples (record_every > 1 keeps every k-th step), or simulate a shorter duration",
        IntegratorKind::Dopri5 => {
            "use a coarser output grid (dt is DOPRI5's output interval; the step size adapts on its own), or simulate a shorter duration"
        }
    };
    crate::admission::admit(
        format_args!("recording {samples} samples ({values:.3e} values)"),
        2.0 * crate::admission::bytes_of::<f64>(values),
        remedy,
    )
}

/// The result of a run from its plant (counters, controller) and records.
pub(crate) fn finish_result(plant: &Plant<'_>, rec: Recorder, events: Vec<SaturationEvent>, n_steps: usize, n_rejected: usize) -> SimResult {
    // The mechanical energy (kinetic plus springs) is conserved without joint torques, base
    // wrench or joint dampers.
    let undamped = plant.model().dof_dynamics().iter().all(|d| d.damping == 0.0);
    let mut conserved = plant.mode.conserved(plant.controller.is_torque_free() && undamped);
    if plant.has_gravity_gradient() {
        // The tidal wrenches do work on the system: only the momentum balances are monitored.
        conserved.retain(|c| *c != Conserved::Energy);
    }
    let drift = rec.drift(&conserved);
    let drift_scales = conserved.iter().map(|&c| (c, rec.scale(c))).collect();
    let balance = rec.balance;
    SimResult {
        balance,
        reference_width: plant.controller.reference_len(),
        records: rec.rec,
        events,
        drift,
        drift_scales,
        n_steps,
        n_rejected,
        n_rhs_evals: plant.n_evals,
        actuator_names: Actuators::names(plant.model()),
        tracking: plant.controller.tracking(),
        controller: plant.controller.name().to_string(),
        dropped_wrench_max: plant.dropped_max,
        dropped_wrench_count: plant.dropped_count,
        wheel_dofs: plant.wheels.clone(),
        goal: plant.controller.goal_report(),
        stop: None,
    }
}

/// Append the rows of [`Records::contact_forces`] of sample `k`: one per contact that exerts a
/// force (`[k, body_a, body_b, p, n̂, f_n, f]`, the layout of [`CONTACT_FORCE_WIDTH`]).
fn contact_force_rows(k: usize, active: &[ContactForce], rows: &mut Vec<f64>) {
    for f in active {
        rows.extend_from_slice(&[k as f64, f.body[0] as f64, f.body[1] as f64]);
        rows.extend_from_slice(f.point.as_slice());
        rows.extend_from_slice(f.normal.as_slice());
        rows.push(f.normal_force);
        rows.extend_from_slice(f.force.as_slice());
    }
    debug_assert_eq!(rows.len() % CONTACT_FORCE_WIDTH, 0);
}
