//! The cost terms of an optimal-control problem ([`CostSpec`], serde data of the run
//! description [`super::problem::ProblemSpec`]) and their derivatives in the tangent space
//! ([`super::state`]). Each term is a weighted least-squares residual `ℓ = ½ Σᵢ wᵢ rᵢ²`; its
//! gradient is exact, its Hessian the Gauss–Newton `Jᵀ W J` (docs/mpc.md):
//!
//! * `state`: `r = z ⊖ z_ref` (`2(6+N)` weights on `[δr0, δθ, δq, δv0, δω0, δq̇]`), with
//!   `J = blkdiag(E₃, J_l⁻¹(r_θ), E)` (`r_θ = log(quat ⊗ quat_ref*)`, the inverse left
//!   Jacobian of SO(3));
//! * `joint`: the same on `q` and `q̇` only;
//! * `base_attitude`: the same on `δθ` and `ω0` only — the base attitude disturbance (a
//!   reactionless objective when the reference is the initial attitude);
//! * `point`: `r = p(x) − p_target` of a point fixed to a body, `J = [E₃, −(p − r0)~, J_m]` in
//!   the configuration's tangent coordinates (the point Jacobian, paper eqs. 104–108, whose
//!   tangent derivative is the velocity Jacobian because `δẋ = u`, docs/derivatives.md);
//! * `control`: `r = c − c_ref` (the torque and thrust regularization).
//!
//! A point's target is fixed, or moving ([`PointTarget`]): the point of a torque-free rigid body
//! (a tumbling target's grasp point, propagated by [`crate::scenario::free_body`], the capture's
//! and RMRC's propagation) or of one in orbit (its tidal, Clohessy–Wiltshire-like motion relative
//! to the orbit's point, [`FreeBodyTarget`]), evaluated at every knot's time `t₀ + k h` when the problem's start
//! time `t₀` is set ([`Cost::retime`]); the Jacobian is the fixed target's (the target does not
//! depend on the state).

use nalgebra::{DMatrix, DVector, Vector3};
use serde::{Deserialize, Serialize};

use super::state::{so3_left_jacobian_inverse, StateSpace};
use crate::algorithms::kinematics::{forward_kinematics, point_jacobians, point_position};
use crate::error::{Result, SpacearmError};
use crate::model::{Data, Model};
use crate::scenario::free_body::{FreeBody, FreeBodySpec};
use crate::scenario::orbit::Orbit;

/// One number for all, or one each.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Numbers {
    /// The same value for every entry.
    One(f64),
    /// One value per entry.
    Each(Vec<f64>),
}

impl Numbers {
    /// The values for `len` entries, each finite (or `±∞` when `infinite_ok`) and, when
    /// `nonnegative`, `≥ 0`; `what` names them in errors.
    pub fn expand(&self, len: usize, what: &str, nonnegative: bool, infinite_ok: bool) -> Result<Vec<f64>> {
        let v = match self {
            Numbers::One(x) => vec![*x; len],
            Numbers::Each(v) if v.len() == len => v.clone(),
            Numbers::Each(v) => return Err(SpacearmError::argument(format!("{what}: expected one number or {len}, got {}", v.len()))),
        };
        for x in &v {
            if x.is_nan() || (!infinite_ok && x.is_infinite()) {
                return Err(SpacearmError::argument(format!("{what} must be finite numbers, got {x}")));
            }
            if nonnegative && *x < 0.0 {
                return Err(SpacearmError::argument(format!("{what} must be ≥ 0, got {x}")));
            }
        }
        Ok(v)
    }
}

/// A body by index (0 is the base) or by name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum BodyRef {
    /// The body's index.
    Index(usize),
    /// The body's (link's) name.
    Name(String),
}

/// Where a point cost's point should be: a fixed point (`[x, y, z]`, m, in 𝒥) or a moving one
/// (`{kind = "free_body", ...}`, [`MovingPoint`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum PointTarget {
    /// A fixed point, m, in 𝒥.
    Fixed([f64; 3]),
    /// A moving point.
    Moving(MovingPoint),
}

impl<'de> Deserialize<'de> for PointTarget {
    /// Three numbers, or a table read as a [`MovingPoint`] (whose own errors then name the field).
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        use serde::de::Error;
        let v = toml::Value::deserialize(d)?;
        if v.is_table() {
            return MovingPoint::deserialize(v).map(PointTarget::Moving).map_err(D::Error::custom);
        }
        <[f64; 3]>::deserialize(v)
            .map(PointTarget::Fixed)
            .map_err(|e| D::Error::custom(format!("a point cost's target must be three numbers (m, in 𝒥) or a moving target {{kind = \"free_body\", ...}}: {e}")))
    }
}

/// A moving target point (serde tag `kind`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum MovingPoint {
    /// A point fixed to a free rigid body ([`FreeBody`]): a tumbling target's grasp point,
    /// torque-free or in orbit.
    FreeBody(FreeBodyTarget),
}

/// A free body's point as a moving target: the body ([`FreeBodySpec`], its fields side by side
/// with `orbit` in the table) and, in orbit, the run's orbit (the body's state relative to the
/// orbit's point `O` at time 0, ECI axes, docs/orbit.md): the body then moves under gravity's
/// tidal part — the exact relative two-body (+ J2) acceleration, whose linearization about a
/// circular orbit is the Clohessy–Wiltshire (Hill) motion — and turns under the gravity-gradient
/// torque ([`FreeBody::in_orbit`], the RMRC's and the capture's propagation). An unknown key is
/// refused by name (`deny_unknown_fields` here: the flattened body's own is not consulted).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FreeBodyTarget {
    /// The body and its point; its `state` at time 0 of the references' clock.
    #[serde(flatten)]
    pub body: FreeBodySpec,
    /// The run's orbit (`None`: torque-free).
    #[serde(default)]
    pub orbit: Option<Orbit>,
}

impl FreeBodyTarget {
    /// The body, in orbit when an orbit is given (checked).
    pub fn build(&self) -> Result<FreeBody> {
        self.body.build_in(self.orbit.as_ref())
    }
}

/// A point cost's target checked: fixed, or a free body with its point at every knot.
#[derive(Debug, Clone)]
pub enum Target {
    /// A fixed point, m.
    Fixed(Vector3<f64>),
    /// A point on a free body, and its positions at the knots' times ([`Cost::retime`]).
    FreeBody {
        /// The body and its point.
        body: Box<FreeBody>,
        /// The point at `t₀ + k h`, `k = 0..=T`.
        knots: Vec<Vector3<f64>>,
    },
}

impl Target {
    /// The target at knot `k`.
    #[inline]
    fn at(&self, k: usize) -> Vector3<f64> {
        match self {
            Target::Fixed(p) => *p,
            Target::FreeBody { knots, .. } => knots[k],
        }
    }
}

fn zero() -> Numbers {
    Numbers::One(0.0)
}

fn identity_quaternion() -> [f64; 4] {
    [0.0, 0.0, 0.0, 1.0]
}

/// A cost term as data (module docs); the serde tag `kind` names it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum CostSpec {
    /// `½ Σ wᵢ (z ⊖ z_ref)ᵢ²` over the whole state.
    State {
        /// `2(6+N)` weights (or one) on `[δr0, δθ, δq, δv0, δω0, δq̇]`.
        weights: Numbers,
        /// `z_ref = [x_ref (7+N); u_ref (6+N)]`.
        reference: Vec<f64>,
    },
    /// `½ Σ w_q (q − q_ref)² + ½ Σ w_q̇ (q̇ − q̇_ref)²`.
    Joint {
        /// Weights on the joint positions (one or N), 1/rad².
        weight_q: Numbers,
        /// The joint positions `q_ref` (N).
        reference: Vec<f64>,
        /// Weights on the joint rates (one or N; default 0).
        #[serde(default = "zero")]
        weight_qd: Numbers,
        /// The joint rates `q̇_ref` (N; default zeros).
        #[serde(default)]
        velocity_reference: Option<Vec<f64>>,
    },
    /// `½ w |log(quat ⊗ quat_ref*)|² + ½ w_ω |ω0|²`: the base attitude disturbance.
    BaseAttitude {
        /// Weight on the attitude error.
        weight: f64,
        /// Weight on the base angular velocity (default 0).
        #[serde(default)]
        rate_weight: f64,
        /// `quat_ref` `[x, y, z, w]` (default: the identity).
        #[serde(default = "identity_quaternion")]
        reference: [f64; 4],
    },
    /// `½ Σ wᵢ (p(x) − p_target)ᵢ²` of a point fixed to a body.
    Point {
        /// The body (index, 0 the base, or link name).
        body: BodyRef,
        /// The point's offset from the body's CM in its frame, m (default: the CM).
        #[serde(default)]
        offset: [f64; 3],
        /// The target: a fixed position in 𝒥 (m) or a moving point ([`PointTarget`]).
        target: PointTarget,
        /// Weights (one or three), 1/m².
        weight: Numbers,
    },
    /// `½ Σ wᵢ (c − c_ref)ᵢ²` on the controls (running costs only).
    Control {
        /// Weights (one or m).
        weights: Numbers,
        /// `c_ref` (m; default zeros).
        #[serde(default)]
        reference: Option<Vec<f64>>,
    },
}

/// A cost term checked against a model and its controls.
#[derive(Debug, Clone)]
pub enum Cost {
    /// `½ Σ wᵢ (z ⊖ z_ref)ᵢ²` (`state`, `joint`, `base_attitude`).
    Tangent {
        /// Weights (`nd`).
        weights: Vec<f64>,
        /// `z_ref`.
        reference: Vec<f64>,
    },
    /// A point's position.
    Point {
        /// Body index.
        body: usize,
        /// Offset, m.
        offset: Vector3<f64>,
        /// The target (fixed or moving).
        target: Target,
        /// Weights.
        weights: Vector3<f64>,
    },
    /// The controls.
    Control {
        /// Weights (`m`).
        weights: Vec<f64>,
        /// `c_ref`.
        reference: Vec<f64>,
    },
}

fn check_len(what: &str, v: &[f64], len: usize) -> Result<()> {
    if v.len() != len {
        return Err(SpacearmError::argument(format!("{what}: expected {len} numbers, got {}", v.len())));
    }
    if let Some(x) = v.iter().find(|x| !x.is_finite()) {
        return Err(SpacearmError::argument(format!("{what} must be finite, got {x}")));
    }
    Ok(())
}

impl CostSpec {
    /// The term checked against `model` with `m` controls; `terminal`: a terminal cost (no controls).
    pub fn build(&self, model: &Model, m: usize, terminal: bool) -> Result<Cost> {
        let s = StateSpace { n: model.n_dof() };
        let n = s.n;
        let neutral_z = || {
            let mut z = vec![0.0; s.nz()];
            z[6] = 1.0;
            z
        };
        Ok(match self {
            CostSpec::State { weights, reference } => {
                check_len("a state cost's reference [x; u]", reference, s.nz())?;
                let q = &reference[3..7];
                let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
                if (norm - 1.0).abs() > 1e-6 {
                    return Err(SpacearmError::argument(format!("a state cost's reference quaternion must have norm 1, got {norm}")));
                }
                Cost::Tangent { weights: weights.expand(s.nd(), "a state cost's weights", true, false)?, reference: reference.clone() }
            }
            CostSpec::Joint { weight_q, reference, weight_qd, velocity_reference } => {
                check_len("a joint cost's reference", reference, n)?;
                let mut z = neutral_z();
                z[7..7 + n].copy_from_slice(reference);
                if let Some(v) = velocity_reference {
                    check_len("a joint cost's velocity_reference", v, n)?;
                    z[s.nx() + 6..].copy_from_slice(v);
                }
                let mut w = vec![0.0; s.nd()];
                w[6..6 + n].copy_from_slice(&weight_q.expand(n, "a joint cost's weight_q", true, false)?);
                w[12 + n..].copy_from_slice(&weight_qd.expand(n, "a joint cost's weight_qd", true, false)?);
                Cost::Tangent { weights: w, reference: z }
            }
            CostSpec::BaseAttitude { weight, rate_weight, reference } => {
                let norm = reference.iter().map(|v| v * v).sum::<f64>().sqrt();
                if !(weight.is_finite() && *weight >= 0.0 && rate_weight.is_finite() && *rate_weight >= 0.0) {
                    return Err(SpacearmError::argument(format!("a base_attitude cost's weights must be finite and ≥ 0, got {weight}, {rate_weight}")));
                }
                if !norm.is_finite() || (norm - 1.0).abs() > 1e-6 {
                    return Err(SpacearmError::argument(format!("a base_attitude cost's reference quaternion must have norm 1, got {norm}")));
                }
                let mut z = neutral_z();
                z[3..7].copy_from_slice(reference);
                let mut w = vec![0.0; s.nd()];
                w[3..6].fill(*weight);
                w[9 + n..12 + n].fill(*rate_weight);
                Cost::Tangent { weights: w, reference: z }
            }
            CostSpec::Point { body, offset, target, weight } => {
                let body = match body {
                    BodyRef::Index(i) if *i < model.n_bodies() => *i,
                    BodyRef::Index(i) => return Err(SpacearmError::argument(format!("a point cost's body {i} does not exist (0..={})", model.n_bodies() - 1))),
                    BodyRef::Name(name) => model.body_index(name)?,
                };
                check_len("a point cost's offset", offset, 3)?;
                let target = match target {
                    PointTarget::Fixed(p) => {
                        check_len("a point cost's target", p, 3)?;
                        Target::Fixed(Vector3::from(*p))
                    }
                    PointTarget::Moving(MovingPoint::FreeBody(spec)) => Target::FreeBody { body: Box::new(spec.build()?), knots: Vec::new() },
                };
                let w = weight.expand(3, "a point cost's weight", true, false)?;
                Cost::Point { body, offset: Vector3::from(*offset), target, weights: Vector3::new(w[0], w[1], w[2]) }
            }
            CostSpec::Control { weights, reference } => {
                if terminal {
                    return Err(SpacearmError::argument("a control cost cannot be a terminal cost (there is no control at the last knot)"));
                }
                let reference = match reference {
                    Some(r) => {
                        check_len("a control cost's reference", r, m)?;
                        r.clone()
                    }
                    None => vec![0.0; m],
                };
                Cost::Control { weights: weights.expand(m, "a control cost's weights", true, false)?, reference }
            }
        })
    }
}

impl Cost {
    /// Whether the term depends on time (a moving target).
    pub fn is_timed(&self) -> bool {
        matches!(self, Cost::Point { target: Target::FreeBody { .. }, .. })
    }

    /// Evaluate a moving target at the `knots` times `t0 + k h` (`k = 0..knots`; `t0 ≥ 0`, the
    /// references' clock); a fixed term is unchanged.
    pub fn retime(&mut self, t0: f64, h: f64, knots: usize) -> Result<()> {
        if let Cost::Point { target: Target::FreeBody { body, knots: points }, .. } = self {
            points.clear();
            for k in 0..knots {
                points.push(body.point(t0 + k as f64 * h)?.0);
            }
        }
        Ok(())
    }
}

/// Workspaces of the cost terms.
pub struct CostWork {
    space: StateSpace,
    data: Data,
    r: Vec<f64>,
}

impl CostWork {
    /// Workspaces for `model`.
    pub fn new(model: &Model) -> Self {
        let space = StateSpace { n: model.n_dof() };
        CostWork { space, data: Data::new(model), r: vec![0.0; space.nd()] }
    }
}

/// The total cost of `costs` at knot `k`'s `(z, c)` times `scale` (`c`: empty at the terminal knot).
pub fn cost_value(model: &Model, work: &mut CostWork, costs: &[Cost], k: usize, z: &[f64], c: &[f64], scale: f64) -> Result<f64> {
    let mut total = 0.0;
    let mut kinematics = false;
    for cost in costs {
        total += match cost {
            Cost::Tangent { weights, reference } => {
                work.space.diff(reference, z, &mut work.r);
                0.5 * weights.iter().zip(&work.r).map(|(w, r)| w * r * r).sum::<f64>()
            }
            Cost::Point { body, offset, target, weights } => {
                if !kinematics {
                    forward_kinematics(model, &mut work.data, &z[..work.space.nx()])?;
                    kinematics = true;
                }
                let r = point_position(&work.data, *body, offset) - target.at(k);
                0.5 * weights.component_mul(&r).dot(&r)
            }
            Cost::Control { weights, reference } => 0.5 * weights.iter().zip(c).zip(reference).map(|((w, c), r)| w * (c - r) * (c - r)).sum::<f64>(),
        };
    }
    Ok(scale * total)
}

/// Add `scale` times the gradients and Gauss–Newton Hessians of `costs` at knot `k`'s `(z, c)` to `lz`,
/// `lc`, `lzz`, `lcc` (module docs); returns the cost times `scale`.
#[allow(clippy::too_many_arguments)]
pub fn cost_derivatives(
    model: &Model,
    work: &mut CostWork,
    costs: &[Cost],
    k: usize,
    z: &[f64],
    c: &[f64],
    scale: f64,
    lz: &mut DVector<f64>,
    lc: &mut DVector<f64>,
    lzz: &mut DMatrix<f64>,
    lcc: &mut DMatrix<f64>,
) -> Result<f64> {
    let space = work.space;
    let mut total = 0.0;
    let mut kinematics = false;
    for cost in costs {
        match cost {
            Cost::Tangent { weights, reference } => {
                space.diff(reference, z, &mut work.r);
                total += 0.5 * weights.iter().zip(&work.r).map(|(w, r)| w * r * r).sum::<f64>() * scale;
                // J = blkdiag(E, J_l⁻¹(r_θ), E): every entry but the attitude's is diagonal.
                for (i, (w, r)) in weights.iter().zip(&work.r).enumerate() {
                    if (3..6).contains(&i) {
                        continue;
                    }
                    lz[i] += scale * w * r;
                    lzz[(i, i)] += scale * w;
                }
                let wa = nalgebra::Matrix3::from_diagonal(&Vector3::new(weights[3], weights[4], weights[5]));
                if wa.iter().any(|v| *v != 0.0) {
                    let rt = Vector3::new(work.r[3], work.r[4], work.r[5]);
                    let j = so3_left_jacobian_inverse(&rt);
                    let g = j.transpose() * wa * rt * scale;
                    let h = j.transpose() * wa * j * scale;
                    for a in 0..3 {
                        lz[3 + a] += g[a];
                        for b in 0..3 {
                            lzz[(3 + a, 3 + b)] += h[(a, b)];
                        }
                    }
                }
            }
            Cost::Point { body, offset, target, weights } => {
                if !kinematics {
                    forward_kinematics(model, &mut work.data, &z[..space.nx()])?;
                    kinematics = true;
                }
                let p = point_position(&work.data, *body, offset);
                let r = p - target.at(k);
                total += 0.5 * weights.component_mul(&r).dot(&r) * scale;
                let (j0, jm) = point_jacobians(model, &work.data, *body, offset)?;
                // Tangent columns [δr0, δθ, δq] of the configuration: the linear rows.
                let mut j = DMatrix::zeros(3, space.nu());
                j.view_mut((0, 0), (3, 6)).copy_from(&j0.fixed_view::<3, 6>(0, 0));
                j.view_mut((0, 6), (3, space.n)).copy_from(&jm.rows(0, 3));
                let wj = DMatrix::from_diagonal(&DVector::from_column_slice(weights.as_slice())) * &j;
                let g = wj.transpose() * DVector::from_column_slice(r.as_slice()) * scale;
                let h = j.transpose() * wj * scale;
                let nu = space.nu();
                let mut lzx = lz.rows_mut(0, nu);
                lzx += g;
                let mut lzzx = lzz.view_mut((0, 0), (nu, nu));
                lzzx += h;
            }
            Cost::Control { weights, reference } => {
                for (i, ((w, ci), r)) in weights.iter().zip(c).zip(reference).enumerate() {
                    total += 0.5 * w * (ci - r) * (ci - r) * scale;
                    lc[i] += scale * w * (ci - r);
                    lcc[(i, i)] += scale * w;
                }
            }
        }
    }
    Ok(total)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;
    use crate::scenario::free_body::InertiaSpec;

    /// A body spinning about its principal axis z at 0.1 rad/s, drifting at `v`: its point at
    /// `offset` is `r₀ + v t + Rz(ω t) offset` in closed form.
    fn spinning(offset: [f64; 3]) -> MovingPoint {
        MovingPoint::FreeBody(FreeBodyTarget {
            body: FreeBodySpec {
                inertia: InertiaSpec::Principal([3.0, 4.0, 5.0]),
                state: vec![1.0, 0.2, -0.1, 0.0, 0.0, 0.0, 1.0, 0.01, -0.02, 0.0, 0.0, 0.0, 0.1],
                offset,
                step: 1e-3,
            },
            orbit: None,
        })
    }

    fn point_cost(target: PointTarget) -> CostSpec {
        CostSpec::Point { body: BodyRef::Index(6), offset: [0.0, 0.0, 0.1], target, weight: Numbers::Each(vec![1.0, 2.0, 3.0]) }
    }

    #[test]
    fn a_free_body_target_is_its_point_at_every_knots_time() {
        let model = presets::spatial6();
        let mut cost = point_cost(PointTarget::Moving(spinning([0.3, 0.0, 0.05]))).build(&model, 6, false).unwrap();
        assert!(cost.is_timed());
        let (t0, h, knots) = (2.5, 0.05, 11);
        cost.retime(t0, h, knots).unwrap();
        let Cost::Point { target, .. } = &cost else { unreachable!() };
        for k in 0..knots {
            let t = t0 + k as f64 * h;
            let (s, c) = (0.1 * t).sin_cos();
            let expected = Vector3::new(1.0 + 0.01 * t + 0.3 * c, 0.2 - 0.02 * t + 0.3 * s, -0.1 + 0.05);
            assert!((target.at(k) - expected).norm() < 1e-12, "knot {k}: {} vs {expected}", target.at(k));
        }
        // A fixed target is not timed.
        let fixed = point_cost(PointTarget::Fixed([0.1, 0.2, 0.3])).build(&model, 6, false).unwrap();
        assert!(!fixed.is_timed());
    }

    /// The gradient of a moving-target point cost at a knot equals central differences of its
    /// value along the tangent directions of the state.
    #[test]
    fn a_moving_point_costs_gradient_matches_finite_differences() {
        let model = presets::spatial6();
        let space = StateSpace { n: model.n_dof() };
        let mut cost = point_cost(PointTarget::Moving(spinning([0.3, 0.1, 0.0]))).build(&model, 6, false).unwrap();
        cost.retime(0.0, 0.1, 6).unwrap();
        let costs = [cost];
        let mut work = CostWork::new(&model);
        let mut z = vec![0.0; space.nz()];
        z[..3].copy_from_slice(&[0.05, -0.02, 0.01]);
        z[3..7].copy_from_slice(&[0.1, -0.05, 0.02, (1.0f64 - 0.0129).sqrt()]);
        for (i, q) in model.initial_q().iter().enumerate() {
            z[7 + i] = q + 0.1 * (i as f64 + 1.0).sin();
        }
        let (nd, m) = (space.nd(), 6);
        let (mut lz, mut lc) = (DVector::zeros(nd), DVector::zeros(m));
        let (mut lzz, mut lcc) = (DMatrix::zeros(nd, nd), DMatrix::zeros(m, m));
        let c = vec![0.0; m];
        let k = 4;
        let value = cost_derivatives(&model, &mut work, &costs, k, &z, &c, 1.0, &mut lz, &mut lc, &mut lzz, &mut lcc).unwrap();
        assert!(value > 1e-3, "the target is away from the point");
        assert_eq!(value, cost_value(&model, &mut work, &costs, k, &z, &c, 1.0).unwrap());
        // Another knot's target gives another value.
        assert!((cost_value(&model, &mut work, &costs, 0, &z, &c, 1.0).unwrap() - value).abs() > 1e-6);
        let eps = 1e-6;
        let (mut zp, mut zm, mut dz) = (z.clone(), z.clone(), vec![0.0; nd]);
        for i in 0..nd {
            dz.fill(0.0);
            dz[i] = eps;
            space.integrate(&z, &dz, &mut zp);
            dz[i] = -eps;
            space.integrate(&z, &dz, &mut zm);
            let fd = (cost_value(&model, &mut work, &costs, k, &zp, &c, 1.0).unwrap() - cost_value(&model, &mut work, &costs, k, &zm, &c, 1.0).unwrap()) / (2.0 * eps);
            assert!((fd - lz[i]).abs() < 1e-7 * (1.0 + lz[i].abs()), "entry {i}: fd {fd} vs {}", lz[i]);
        }
    }

    /// In a circular orbit (no J2) a target near the orbit's point follows the Clohessy–Wiltshire
    /// closed form (its LVLH relative state carried to the run's ECI axes) to the linearization's
    /// error, `O(n² ρ²/r t²)`; the torque-free target drifts on a straight line instead.
    #[test]
    fn an_orbiting_target_follows_the_clohessy_wiltshire_motion() {
        use crate::scenario::orbit::{clohessy_wiltshire, EARTH};
        let model = presets::spatial6();
        let orbit = Orbit::circular(EARTH, 500e3, 0.9, 0.3, 0.2, false).unwrap();
        let n = orbit.mean_motion();
        let (ro, vo) = (orbit.r0, orbit.v0);
        // A quarter orbit in 50 knots, from t0 = 10 s.
        let (t0, knots) = (10.0, 51);
        let h = orbit.period() / 4.0 / 50.0;
        let times: Vec<f64> = (0..knots).map(|k| t0 + k as f64 * h).collect();
        let track = orbit.propagate(&times, 1e-12).unwrap();
        // The largest distance to the CW motion of the target at `scale` times a relative state
        // 5 m radially out, 10 m behind, 2 m out of plane, drifting; and to a straight drift.
        let run = |scale: f64| -> (f64, f64) {
            let rel0 = [5.0, -10.0, 2.0, 0.01, -0.02, 0.005].map(|v| v * scale);
            let (r, v) = Orbit::relative_to_eci(&ro, &vo, &rel0);
            let (rho, rho_dot) = (r - ro, v - vo);
            let state = vec![rho.x, rho.y, rho.z, 0.0, 0.0, 0.0, 1.0, rho_dot.x, rho_dot.y, rho_dot.z, 0.0, 0.0, 0.0];
            let target = |orbit: Option<Orbit>| {
                MovingPoint::FreeBody(FreeBodyTarget { body: FreeBodySpec { inertia: InertiaSpec::Principal([3.0, 4.0, 5.0]), state: state.clone(), offset: [0.0; 3], step: 0.05 }, orbit })
            };
            let mut cost = point_cost(PointTarget::Moving(target(Some(orbit)))).build(&model, 6, false).unwrap();
            let mut free = point_cost(PointTarget::Moving(target(None))).build(&model, 6, false).unwrap();
            assert!(cost.is_timed());
            cost.retime(t0, h, knots).unwrap();
            free.retime(t0, h, knots).unwrap();
            let (Cost::Point { target: orbiting, .. }, Cost::Point { target: drifting, .. }) = (&cost, &free) else { unreachable!() };
            let (mut worst, mut apart): (f64, f64) = (0.0, 0.0);
            for (k, (t, (rt, vt))) in times.iter().zip(&track).enumerate() {
                let (p, _) = Orbit::relative_to_eci(rt, vt, &clohessy_wiltshire(n, &rel0, *t));
                worst = worst.max((orbiting.at(k) - (p - rt)).norm());
                apart = apart.max((drifting.at(k) - (p - rt)).norm());
            }
            (worst, apart)
        };
        let (full, apart) = run(1.0);
        let (half, _) = run(0.5);
        // ρ ≈ 11 m, r ≈ 6.9e6 m: the neglected terms, O(n² ρ²/r) in acceleration, reach ~1e-4 m
        // over a quarter orbit, and they are quadratic in ρ: half the offset, a quarter of it.
        assert!(full < 3e-4, "orbiting target vs CW: {full:e} m");
        assert!((3.0..5.0).contains(&(full / half)), "the difference to CW is not the quadratic remainder: {full:e} vs {half:e} m at half the offset");
        assert!(apart > 1.0, "the tidal motion is visible against a straight-line drift: {apart} m");
    }

    #[test]
    fn bad_targets_are_refused_with_their_field() {
        let read = |s: &str| toml::from_str::<CostSpec>(s).map_err(|e| e.to_string());
        let ok = read("kind = 'point'\nbody = 6\nweight = 1.0\ntarget = {kind = 'free_body', inertia = [1.0, 2.0, 3.0], state = [0,0,0, 0,0,0,1, 0,0,0, 0,0,0.1]}");
        assert!(ok.is_ok(), "{ok:?}");
        // The body's fields and `orbit` stand side by side; written back the same way.
        let spec = ok.unwrap();
        assert_eq!(read(&toml::to_string(&spec).unwrap()).unwrap(), spec);
        let e = read("kind = 'point'\nbody = 6\nweight = 1.0\ntarget = {kind = 'free_body', inertia = [1.0, 2.0, 3.0], state = [0.0], spin = 1}").unwrap_err();
        assert!(e.contains("unknown field `spin`"), "{e}");
        let e = read("kind = 'point'\nbody = 6\nweight = 1.0\ntarget = {kind = 'free_body', inertia = [1.0, 2.0, 3.0], state = [0.0], orbits = {}}").unwrap_err();
        assert!(e.contains("unknown field `orbits`"), "{e}");
        let e = read("kind = 'point'\nbody = 6\nweight = 1.0\ntarget = {kind = 'free_body', inertia = [1.0, 2.0, 3.0]}").unwrap_err();
        assert!(e.contains("missing field `state`"), "{e}");
        let e = read("kind = 'point'\nbody = 6\nweight = 1.0\ntarget = [1.0, 2.0]").unwrap_err();
        assert!(e.contains("three numbers"), "{e}");
        let model = presets::spatial6();
        let short = MovingPoint::FreeBody(FreeBodyTarget { body: FreeBodySpec { inertia: InertiaSpec::Principal([1.0, 1.0, 1.0]), state: vec![0.0; 12], offset: [0.0; 3], step: 1e-3 }, orbit: None });
        let e = point_cost(PointTarget::Moving(short)).build(&model, 6, false).unwrap_err().to_string();
        assert!(e.contains("13"), "{e}");
    }
}
