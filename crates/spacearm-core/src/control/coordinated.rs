//! Coordinated base-and-arm control in the flying mode: an end-effector task plus base pose
//! regulation, through the flying-regime reduced EOM `H* q̈ + c* = τ − H0mᵀ H0⁻¹ F_b`
//! (docs/physics.md; the paper leaves the flying case open).
//!
//! 1. Base regulation (acceleration level): `ẍ0_des = [K_pb (r_ref − r0) − K_db v0;
//!    −K_pb e − K_db ω0]` with `e` the attitude error of [`super::attitude`].
//! 2. End-effector task: `a_des = p̈_ref + K_de (ṗ_ref − ṗ) + K_pe (p_ref − p)`. The point's
//!    acceleration is `p̈ = v̇0 + α0 × r_0X + J_mX,T q̈ + b` (`J_0X ẍ0 + J_mX q̈` plus the
//!    velocity-product term `b`, its acceleration at `u̇ = 0`), so with the base acceleration
//!    prescribed, `q̈_des = J⁺_λ (a_des − v̇0_des − α0_des × r_0X − b)` with `J = J_mX,T` (arm
//!    columns) and the damped least-squares inverse of [`crate::math::dls`] (the law of
//!    [`super::rmrc`]).
//! 3. Forces: the base wrench that produces `ẍ0_des` together with `q̈_des` comes from the base
//!    rows, `F_b = H0 ẍ0_des + H0m q̈_des + c0`, and the joint torques from the reduced EOM,
//!    `τ = H* q̈_des + c* + H0mᵀ H0⁻¹ F_b` (equal to the joint rows of `H u̇_des + c`; tested).
//!
//! With the exact model and no saturation both error dynamics are linear and decoupled
//! (`ë + K_d ė + K_p e = 0` for the end effector and for the base pose).
//!
//! **Passive joints** (no motor: slosh, panels, compliant joints' deflection; docs/flexibility.md)
//! are not commanded (zero torque): the law is the collocated partial feedback linearization. With
//! `ẍ0` prescribed and the actuated accelerations `q̈_A` chosen, the passive rows of
//! `H u̇ + c = f + Q` (`Q` the joints' springs and dampers, `τ_P = 0`) give
//! `q̈_P = H_PP⁻¹ (Q_P − c_P − H_P0 ẍ0 − H_PA q̈_A) = m_P − M q̈_A`, `M = H_PP⁻¹ H_PA`, so the point's
//! acceleration is affine in `q̈_A`: `p̈ = J_0X ẍ0 + J_P m_P + (J_A − J_P M) q̈_A + b`, and
//! `q̈_A = J_eff⁺_λ (a_des − J_0X ẍ0 − J_P m_P − b)` with `J_eff = J_A − J_P M` and the same damped
//! least squares. Then `F_b` from the base rows (as above, with the whole `q̈`) and
//! `τ_A = [H u̇_des + c − Q]_A` from the actuated rows. The rigid case (no passive joint) is the
//! law above, unchanged.

use nalgebra::{DMatrix, DVector, Vector3, Vector6};

use crate::algorithms::crba::crba_after_kinematics;
use crate::model::data::Data;
use crate::error::{Result, SpacearmError};
use crate::model::joint::JointType;
use crate::algorithms::kinematics::{check_body, forward_kinematics, point_position};
use crate::model::Model;
use crate::scenario::modes::Mode;
use crate::scenario::reference::CartesianLine;
use crate::algorithms::rnea::rnea_after_kinematics;
use crate::math::spatial::{angular, linear};

use super::attitude::AttitudeControl;
use super::computed_torque::ReducedInverseDynamics;
use super::controller::{require_mode, split_passive};
use crate::algorithms::passive::add_joint_passive_forces;
use crate::math::dls::{DampingLaw, RowSvd};
use super::{cholesky_solve_in_place, positive, Command, ControlContext, Controller, TrackingKind};

/// Gains of [`CoordinatedFlying`] (acceleration level, 1/s² and 1/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoordinatedGains {
    /// End-effector position gain, 1/s².
    pub kp_ee: f64,
    /// End-effector velocity gain, 1/s.
    pub kd_ee: f64,
    /// Base pose gain, 1/s².
    pub kp_base: f64,
    /// Base velocity gain, 1/s.
    pub kd_base: f64,
}

/// Coordinated end-effector and base-pose control (flying mode).
#[derive(Debug, Clone)]
pub struct CoordinatedFlying {
    line: CartesianLine,
    body: usize,
    offset: Vector3<f64>,
    /// Base pose to hold: `(r0, quat [x, y, z, w])`; `None`: the pose at the first evaluation.
    base_ref: Option<(Vector3<f64>, [f64; 4])>,
    gains: CoordinatedGains,
    damping: f64,
    threshold: f64,
    model: Option<Model>,
    data: Option<Data>,
    attitude: Option<AttitudeControl>,
    base_position_ref: Vector3<f64>,
    inner: Option<ReducedInverseDynamics>,
    arm: Vec<usize>,
    jac: Vec<Vector3<f64>>,
    jac_arm: DMatrix<f64>,
    qdd_arm: DVector<f64>,
    svd: RowSvd,
    qdd: Vec<f64>,
    /// Passive-joint workspaces (empty on a rigid plant): the actuated and passive arm dofs,
    /// `M = H_PP⁻¹ H_PA` (np × na, column-major), `m_P`, a copy of `H_PP` for each solve, the
    /// joint rows' `Q` (passive force, length N).
    passive: Option<PassiveWork>,
}

/// Workspaces of the partial feedback linearization of [`CoordinatedFlying`] (module docs).
#[derive(Debug, Clone)]
struct PassiveWork {
    act: Vec<usize>,
    pas: Vec<usize>,
    m: Vec<f64>,
    m_p: Vec<f64>,
    h_pp: Vec<f64>,
    q_force: Vec<f64>,
}

impl CoordinatedFlying {
    /// End-effector line for the point on `body` at `offset`; base pose reference (`None`: hold
    /// the initial pose); gains; damped-least-squares `damping` and `threshold` as in
    /// [`super::ResolvedMotionRate`].
    pub fn new(
        line: CartesianLine,
        body: usize,
        offset: Vector3<f64>,
        base_ref: Option<(Vector3<f64>, [f64; 4])>,
        gains: CoordinatedGains,
        damping: f64,
        threshold: f64,
    ) -> Self {
        CoordinatedFlying {
            line,
            body,
            offset,
            base_ref,
            gains,
            damping,
            threshold,
            model: None,
            data: None,
            attitude: None,
            base_position_ref: Vector3::zeros(),
            inner: None,
            arm: vec![],
            jac: vec![],
            jac_arm: DMatrix::zeros(3, 0),
            qdd_arm: DVector::zeros(0),
            svd: RowSvd::new(0),
            qdd: vec![],
            passive: None,
        }
    }

    fn latch_base_reference(&mut self, x: &[f64]) -> Result<()> {
        let (r, q) = match self.base_ref {
            Some(pose) => pose,
            None => (Vector3::new(x[0], x[1], x[2]), [x[3], x[4], x[5], x[6]]),
        };
        crate::error::check_finite("coordinated flying base position reference", r.as_slice())?;
        let mut att = AttitudeControl::new(q, self.gains.kp_base, self.gains.kd_base);
        att.set_reference(q)?;
        self.attitude = Some(att);
        self.base_position_ref = r;
        Ok(())
    }
}

/// Classical acceleration at `u̇ = 0` of a point fixed to `body` at world position `p`, from the
/// body velocities and accelerations of an RNEA pass at `u̇ = 0` (spatial, at the base CM `r0`):
/// `a = a_O + α × d + ω × (v_O + ω × d)`, `d = p − r0` (Featherstone §2.11).
pub(crate) fn point_acceleration_bias(data: &Data, body: usize, p: &Vector3<f64>) -> Vector3<f64> {
    let d = p - data.base_position;
    let v = data.body_velocity[body];
    let a = data.body_acceleration[body];
    let w = angular(&v);
    linear(&a) + angular(&a).cross(&d) + w.cross(&(linear(&v) + w.cross(&d)))
}

impl Controller for CoordinatedFlying {
    fn name(&self) -> &str {
        "coordinated_flying"
    }

    fn setup(&mut self, ctx: &ControlContext<'_>) -> Result<()> {
        require_mode(ctx, ctx.mode == Mode::Flying, "coordinated base-and-arm control needs the full base wrench of the 'flying' mode")?;
        if !ctx.wheel_dofs.is_empty() {
            return Err(SpacearmError::argument(
                "coordinated flying control does not drive reaction wheels; pass wheels=[] to treat them as joints held at constant speed",
            ));
        }
        let g = self.gains;
        for (what, v) in [("kp_ee", g.kp_ee), ("kd_ee", g.kd_ee), ("kp_base", g.kp_base), ("kd_base", g.kd_base)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SpacearmError::argument(format!("coordinated flying {what} must be finite and >= 0, got {v}")));
            }
        }
        positive("coordinated flying threshold", self.threshold)?;
        if !(self.damping.is_finite() && self.damping >= 0.0) {
            return Err(SpacearmError::argument(format!("coordinated flying max_damping must be finite and >= 0, got {}", self.damping)));
        }
        check_body(ctx.plant, self.body)?;
        if let Some((_, q)) = self.base_ref {
            crate::math::rotations::unit_quaternion_from_xyzw("coordinated flying base quaternion reference", &q)?;
        }
        let model = ctx.plant.clone();
        self.data = Some(Data::new(&model));
        let (act, pas) = split_passive(ctx);
        if pas.is_empty() {
            // Rigid: the reduced-EOM torques of every arm joint (all actuated).
            self.inner = Some(ReducedInverseDynamics::new(model.clone(), ctx)?);
            self.passive = None;
        } else {
            // Partial feedback linearization (module docs): τ_A from the actuated rows directly.
            self.inner = None;
            let (na, np) = (act.len(), pas.len());
            self.passive = Some(PassiveWork { m: vec![0.0; np * na], m_p: vec![0.0; np], h_pp: vec![0.0; np * np], q_force: vec![0.0; model.n_dof()], act: act.clone(), pas });
        }
        self.model = Some(model);
        self.arm = act;
        self.jac = vec![Vector3::zeros(); ctx.plant.n_dof()];
        self.jac_arm = DMatrix::zeros(3, self.arm.len());
        self.qdd_arm = DVector::zeros(self.arm.len());
        self.svd = RowSvd::new(self.arm.len());
        self.qdd = vec![0.0; ctx.plant.n_dof()];
        self.attitude = None;
        Ok(())
    }

    fn command(&mut self, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> Result<()> {
        if self.attitude.is_none() {
            self.latch_base_reference(x)?;
        }
        let (Some(model), Some(data), Some(att)) = (self.model.as_ref(), self.data.as_mut(), self.attitude.as_ref()) else {
            return Err(SpacearmError::Simulation("coordinated flying control used before setup".into()));
        };
        let g = self.gains;
        // 1. Base regulation.
        let r0 = Vector3::new(x[0], x[1], x[2]);
        let v0 = Vector3::new(u[0], u[1], u[2]);
        let w0 = Vector3::new(u[3], u[4], u[5]);
        let (e_att, angle) = att.error(&x[3..7]);
        let acc_lin = (self.base_position_ref - r0) * g.kp_base - v0 * g.kd_base;
        let acc_ang = -e_att * g.kp_base - w0 * g.kd_base;
        // 2. End-effector task: kinematics, velocity and u̇ = 0 acceleration of the point.
        forward_kinematics(model, data, x)?;
        // The joint block of H only for the passive rows (the rigid law needs the base rows).
        crba_after_kinematics(model, data, self.passive.is_some())?;
        rnea_after_kinematics(model, data, u, None, &[]);
        let p = point_position(data, self.body, &self.offset);
        let d = p - data.base_position;
        let vb = data.body_velocity[self.body];
        let p_dot = linear(&vb) + angular(&vb).cross(&d);
        let bias = point_acceleration_bias(data, self.body, &p);
        let (p_ref, v_ref, a_ref) = self.line.eval(t);
        let a_des = a_ref + (v_ref - p_dot) * g.kd_ee + (p_ref - p) * g.kp_ee;
        let rhs = a_des - acc_lin - acc_ang.cross(&d) - bias;
        // J_mX translational columns of the arm joints on the path to the point.
        for c in self.jac.iter_mut() {
            *c = Vector3::zeros();
        }
        let mut b = self.body;
        while b != 0 {
            if let Some(dof) = model.dof_of_body(b) {
                let k = data.joint_axis_in_world[b];
                self.jac[dof] = match model.links()[b - 1].joint.kind {
                    JointType::Revolute => k.cross(&(p - data.joint_position_in_world[b])),
                    _ => k,
                };
            }
            b = model.links()[b - 1].parent;
        }
        for (c, &dof) in self.arm.iter().enumerate() {
            for r in 0..3 {
                self.jac_arm[(r, c)] = self.jac[dof][r];
            }
        }
        let xdd0 = Vector6::new(acc_lin.x, acc_lin.y, acc_lin.z, acc_ang.x, acc_ang.y, acc_ang.z);
        let mut rhs = rhs;
        if let Some(w) = self.passive.as_mut() {
            // Passive rows (module docs): M = H_PP⁻¹ H_PA, m_P = H_PP⁻¹ (Q_P − c_P − H_P0 ẍ0);
            // J_eff = J_A − J_P M, and the drift J_P m_P leaves the task's right-hand side.
            let (na, np) = (w.act.len(), w.pas.len());
            let h = &data.mass_matrix;
            w.q_force.fill(0.0);
            add_joint_passive_forces(model, &x[7..], &u[6..], &mut w.q_force);
            for col in 0..=na {
                for (a, &pa) in w.pas.iter().enumerate() {
                    for (b, &pb) in w.pas.iter().enumerate() {
                        w.h_pp[a + b * np] = h[(6 + pa, 6 + pb)];
                    }
                }
                let z = if col < na { &mut w.m[col * np..(col + 1) * np] } else { &mut w.m_p[..] };
                for (a, &pa) in w.pas.iter().enumerate() {
                    z[a] = if col < na {
                        h[(6 + pa, 6 + w.act[col])]
                    } else {
                        w.q_force[pa] - data.tau[6 + pa] - h.fixed_view::<1, 6>(6 + pa, 0).transpose().dot(&xdd0)
                    };
                }
                if !cholesky_solve_in_place(&mut w.h_pp, np, z) {
                    return Err(SpacearmError::Singular("the passive-joint block H_PP of the mass matrix".into()));
                }
            }
            for (a, &pa) in w.pas.iter().enumerate() {
                let jp = self.jac[pa];
                rhs -= jp * w.m_p[a];
                for c in 0..na {
                    for r in 0..3 {
                        self.jac_arm[(r, c)] -= jp[r] * w.m[a + c * np];
                    }
                }
            }
        }
        self.svd.factor(&self.jac_arm);
        self.svd.solve(rhs.as_slice(), &DampingLaw { threshold: self.threshold, max_damping: self.damping }, &mut self.qdd_arm);
        for (c, &dof) in self.arm.iter().enumerate() {
            self.qdd[dof] = self.qdd_arm[c];
        }
        if let Some(w) = self.passive.as_ref() {
            let np = w.pas.len();
            for (a, &pa) in w.pas.iter().enumerate() {
                let mut v = w.m_p[a];
                for c in 0..w.act.len() {
                    v -= w.m[a + c * np] * self.qdd_arm[c];
                }
                self.qdd[pa] = v;
            }
        }
        // 3. Base rows: F_b = H0 ẍ0_des + H0m q̈_des + c0.
        let mut f_b = data.subtree_inertia[0] * xdd0 + data.tau.fixed_rows::<6>(0);
        for (j, qdd) in self.qdd.iter().enumerate() {
            f_b += data.mass_matrix.fixed_view::<6, 1>(0, 6 + j) * *qdd;
        }
        out.base_wrench = f_b;
        if let Some(w) = self.passive.as_ref() {
            // Actuated rows of H u̇_des + c − Q; zero on the passive joints.
            let h = &data.mass_matrix;
            for &d in &w.act {
                let mut t = data.tau[6 + d] - w.q_force[d] + h.fixed_view::<1, 6>(6 + d, 0).transpose().dot(&xdd0);
                for (j, qdd) in self.qdd.iter().enumerate() {
                    t += h[(6 + d, 6 + j)] * *qdd;
                }
                out.tau[d] = t;
            }
            for &p in &w.pas {
                out.tau[p] = 0.0;
            }
        } else {
            // Joint torques from the reduced EOM with that base wrench.
            let inner = self.inner.as_mut().ok_or_else(|| SpacearmError::Simulation("coordinated flying control used before setup".into()))?;
            inner.arm_torques(x, u, &self.qdd, out)?;
        }
        out.reference[..3].copy_from_slice(p_ref.as_slice());
        out.tracking_error = (p_ref - p).norm();
        out.attitude_error = angle;
        Ok(())
    }

    fn reference_len(&self) -> usize {
        3
    }

    fn tracking(&self) -> Option<TrackingKind> {
        Some(TrackingKind::Cartesian)
    }

    fn reports_attitude_error(&self) -> bool {
        true
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::algorithms::kinematics::point_jacobians;
    use nalgebra::UnitQuaternion;
    use crate::model::presets;

    /// Configuration advanced by `h` along constant `u` (u̇ = 0): exact for the base (constant
    /// v0, ω0 in 𝒥) and the joints.
    fn advance(x: &[f64], u: &[f64], h: f64) -> Vec<f64> {
        let mut y = x.to_vec();
        for i in 0..3 {
            y[i] += h * u[i];
        }
        let w = Vector3::new(u[3], u[4], u[5]);
        let dq = UnitQuaternion::from_scaled_axis(w * h);
        let q = UnitQuaternion::new_normalize(nalgebra::Quaternion::new(x[6], x[3], x[4], x[5]));
        let qn = dq * q;
        y[3] = qn.i;
        y[4] = qn.j;
        y[5] = qn.k;
        y[6] = qn.w;
        for i in 7..x.len() {
            y[i] += h * u[i - 1];
        }
        y
    }

    #[test]
    fn point_bias_acceleration_matches_finite_differences_of_the_point_velocity() {
        let model = presets::spatial6();
        let mut data = Data::new(&model);
        let mut x = presets::initial_configuration(&model);
        x[0] = 3.0;
        x[2] = -1.0;
        let u = vec![0.3, -0.2, 0.1, 0.4, -0.5, 0.3, 0.7, -0.4, 0.6, 0.5, -0.8, 0.9];
        let pt = &model.points()[model.end_effector().unwrap()];
        let (body, offset) = (pt.body, pt.offset);
        let velocity = |data: &mut Data, x: &[f64]| {
            forward_kinematics(&model, data, x).unwrap();
            let (j0, jm) = point_jacobians(&model, data, body, &offset).unwrap();
            let v = j0 * Vector6::from_column_slice(&u[0..6]) + jm * nalgebra::DVector::from_column_slice(&u[6..]);
            Vector3::new(v[0], v[1], v[2])
        };
        let h = 1e-5;
        let fd = (velocity(&mut data, &advance(&x, &u, h)) - velocity(&mut data, &advance(&x, &u, -h))) / (2.0 * h);
        forward_kinematics(&model, &mut data, &x).unwrap();
        rnea_after_kinematics(&model, &mut data, &u, None, &[]);
        let p = point_position(&data, body, &offset);
        let bias = point_acceleration_bias(&data, body, &p);
        assert!(bias.norm() > 0.1, "reference not trivial: {bias}");
        assert!((bias - fd).norm() < 1e-7 * fd.norm().max(1.0), "{bias} vs finite differences {fd}");
    }

    /// The flexible test arms' links: revolute, with the principal moments `inertia`; the
    /// closure takes `(name, parent, origin, axis, com, mass)`.
    pub(crate) fn revolute_links(inertia: [f64; 3]) -> impl Fn(&str, &str, [f64; 3], [f64; 3], [f64; 3], f64) -> crate::model::builder::LinkSpec {
        move |name, parent, origin, axis, com, mass| crate::model::builder::LinkSpec::new(name, parent, JointType::Revolute, origin, axis, com, mass, inertia)
    }

    /// The flexible test arms' fuel: a slosh pendulum "fuel" of `mass` kg on the base, pivot at
    /// (0, 0.1, 0.3) m, rod 0.4 m down, hinge x, 1.5 rad/s, damping 0.3.
    pub(crate) fn fuel_pendulum(mass: f64) -> crate::model::slosh::SloshSpec {
        use crate::model::slosh::{SloshModel, SloshRestoring, SloshSpec};
        SloshSpec {
            name: "fuel".into(),
            parent: "base".into(),
            model: SloshModel::Pendulum,
            mass,
            position: [0.0, 0.1, 0.3],
            axis: [0.0, 0.0, -1.0],
            hinge: Some([1.0, 0.0, 0.0]),
            length: Some(0.4),
            restoring: SloshRestoring::Frequency(1.5),
            damping: 0.3,
        }
    }

    /// Three actuated links (z, y, y) with a slosh pendulum on the base and a passive sprung
    /// elbow (rest ≠ 0) between the second and third, on the path to the end effector.
    pub(crate) fn flexible_spatial3() -> Model {
        use crate::model::builder::ModelBuilder;
        use crate::model::joint::JointDynamics;
        let mut b = ModelBuilder::new("flex3", "base", 150.0, [[15.0, 0.0, 0.0], [0.0, 18.0, 0.0], [0.0, 0.0, 20.0]]).unwrap();
        let link = revolute_links([0.05, 0.3, 0.3]);
        b.add_link(link("l1", "base", [0.6, 0.0, 0.2], [0.0, 0.0, 1.0], [0.0, 0.0, 0.2], 6.0)).unwrap();
        b.add_slosh(fuel_pendulum(25.0)).unwrap();
        b.add_link(link("l2", "l1", [0.0, 0.0, 0.4], [0.0, 1.0, 0.0], [0.4, 0.0, 0.0], 5.0)).unwrap();
        // A passive, sprung elbow on the path to the end effector (J_P ≠ 0).
        b.add_link(link("flex", "l2", [0.8, 0.0, 0.0], [0.0, 0.0, 1.0], [0.1, 0.0, 0.0], 1.0)).unwrap();
        b.set_joint_dynamics("flex", JointDynamics { actuated: false, stiffness: 40.0, damping: 0.5, rest: 0.1 }).unwrap();
        b.add_link(link("l3", "flex", [0.2, 0.0, 0.0], [0.0, 1.0, 0.0], [0.35, 0.0, 0.0], 3.0)).unwrap();
        b.build().unwrap()
    }

    /// The partial feedback linearization realizes, in the plant's own forward dynamics
    /// (mass-matrix route, springs and dampers included), the prescribed base acceleration and
    /// the desired point acceleration — computed here from the point Jacobians and the bias of
    /// the test above, not from the controller — with zero torque on the passive joints.
    #[test]
    fn passive_plant_gets_the_desired_base_and_point_accelerations_with_zero_passive_torque() {
        use crate::algorithms::dynamics::forward_dynamics_via_mass_matrix;
        use crate::scenario::actuators::Actuators;
        let m = flexible_spatial3();
        let dyn_ = m.dof_dynamics();
        let passive: Vec<usize> = (0..m.n_dof()).filter(|&d| !dyn_[d].actuated).collect();
        assert_eq!(passive.len(), 2);
        let mut x = vec![0.0; m.nx()];
        x[0..3].copy_from_slice(&[0.1, -0.2, 0.05]);
        let qb = UnitQuaternion::from_scaled_axis(Vector3::new(0.05, -0.02, 0.1));
        x[3..7].copy_from_slice(&[qb.i, qb.j, qb.k, qb.w]);
        for (j, v) in x[7..].iter_mut().enumerate() {
            *v = 0.3 + 0.25 * (j as f64 * 1.7).sin();
        }
        let u: Vec<f64> = (0..m.nu()).map(|i| 0.15 * ((i as f64) * 1.3 + 0.4).sin()).collect();
        let (body, offset) = (m.n_bodies() - 1, Vector3::new(0.5, 0.0, 0.0));
        let mut data = Data::new(&m);
        forward_kinematics(&m, &mut data, &x).unwrap();
        let p = point_position(&data, body, &offset);
        let target = p + Vector3::new(0.02, -0.03, 0.01);
        let gains = CoordinatedGains { kp_ee: 100.0, kd_ee: 20.0, kp_base: 25.0, kd_base: 10.0 };
        let line = CartesianLine::new(target, target, 0.0, 1.0).unwrap();
        let mut c = CoordinatedFlying::new(line, body, offset, None, gains, 0.05, 1e-4);
        let arm: Vec<usize> = (0..m.n_dof()).collect();
        let actuators = Actuators::new(&m, false, None);
        c.setup(&ControlContext { plant: &m, mode: Mode::Flying, wheel_dofs: &[], arm_dofs: &arm, actuators: &actuators }).unwrap();
        let mut out = Command::new(m.n_dof(), 3);
        c.command(0.3, &x, &u, &mut out).unwrap();
        for &d in &passive {
            assert_eq!(out.tau[d], 0.0);
        }
        let mut f = vec![0.0; m.nu()];
        f[..6].copy_from_slice(out.base_wrench.as_slice());
        f[6..].copy_from_slice(&out.tau);
        let ud = forward_dynamics_via_mass_matrix(&m, &mut data, &x, &u, &f, &[]).unwrap();
        // Base reference latched at x: ẍ0_des = −K_db [v0; ω0].
        for i in 0..6 {
            assert!((ud[i] + gains.kd_base * u[i]).abs() < 1e-10, "base row {i}: {} vs {}", ud[i], -gains.kd_base * u[i]);
        }
        forward_kinematics(&m, &mut data, &x).unwrap();
        let (j0, jm) = point_jacobians(&m, &data, body, &offset).unwrap();
        let twist = j0 * Vector6::from_column_slice(&u[..6]) + &jm * DVector::from_column_slice(&u[6..]);
        let pd = Vector3::new(twist[0], twist[1], twist[2]);
        let acc = j0 * Vector6::from_column_slice(&ud.as_slice()[..6]) + &jm * DVector::from_column_slice(&ud.as_slice()[6..]);
        rnea_after_kinematics(&m, &mut data, &u, None, &[]);
        let a = Vector3::new(acc[0], acc[1], acc[2]) + point_acceleration_bias(&data, body, &p);
        let a_des = (target - p) * gains.kp_ee - pd * gains.kd_ee;
        assert!((a - a_des).norm() < 1e-9 * a_des.norm().max(1.0), "{a} vs {a_des}");
        // The passive joints drift, so the rigid law (every joint commanded) would be wrong here.
        for &d in &passive {
            assert!(ud[6 + d].abs() > 1e-3, "passive joint {d} at rest");
        }
    }
}
