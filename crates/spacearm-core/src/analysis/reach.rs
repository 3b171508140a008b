//! Whether a free-floating system can bring a point to a target at all: the checks a planner
//! makes before it starts a solve (docs/optimal-control.md, "Checks of the target").
//!
//! **Reach** (Vafa & Dubowsky 1990, the virtual manipulator). With no external force the
//! system CM moves uniformly, `r_g(t) = r_g(0) + P t / M`, and the point `P` of body `e` sits at
//! `r_P − r_g = Σ_i (m_i / M)(r_P − r_i)`. The tree path from the CM `r_i` of body `i` to `P`
//! is a chain of steps, each between two points fixed in one body (a CM, a joint position — on
//! the joint's axis, so fixed in both the parent and the child — or `P` itself). Grouping the
//! steps of every body by the body they lie in gives `r_P − r_g = Σ_b V_b`, each *virtual link*
//! `V_b` a vector fixed in body `b`, of a length no revolute or fixed joint changes. Hence
//! `|r_P − r_g| ≤ R_max = Σ_b |V_b|` in every configuration: a target farther than `R_max` from
//! where the system CM will be is out of reach whatever the joints do (joint position limits
//! only shrink the set). A prismatic joint changes a length: no bound is given then.
//!
//! **Plane.** If every revolute joint axis is parallel to one direction `n`, every prismatic
//! axis perpendicular to it, every CM, joint position and the point lie in one plane normal to
//! `n`, `n` is a principal axis of every body's inertia, and the state moves in that plane (base
//! angular velocity along `n`, every body's CM velocity perpendicular to it), then the plane is
//! invariant: the joint torques and the internal forces all act in it, so the point never
//! leaves it. A target off that plane cannot be reached.

use nalgebra::Vector3;

use crate::algorithms::kinematics::{check_body, forward_kinematics, point_position};
use crate::algorithms::momentum::momentum;
use crate::error::{Result, SpacearmError};
use crate::model::joint::JointType;
use crate::model::{Data, Model};

/// The plane a planar system moves in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionPlane {
    /// Unit normal `n`.
    pub normal: Vector3<f64>,
    /// A point of the plane (the base CM at the given state), m.
    pub point: Vector3<f64>,
}

/// What can be said of the reach of a point from a state, before any motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Reach {
    /// Where the system CM is after the given time, m (uniform motion, zero external force).
    pub center: Vector3<f64>,
    /// `R_max = Σ_b |V_b|`, the largest distance of the point from the system CM in any
    /// configuration, m; `None` for a model with a prismatic joint.
    pub radius: Option<f64>,
    /// The plane the point stays in, when the system and its state are planar.
    pub plane: Option<MotionPlane>,
}

/// Relative tolerance of the parallelism and coplanarity tests of the plane check (on unit
/// vectors and on lengths relative to the model's size).
const PLANAR_TOLERANCE: f64 = 1e-9;

/// The reach of the point of `body` at `offset` (body frame, from its CM) from the state
/// `(x, u)` after `duration` seconds (module docstring).
pub fn reach(model: &Model, data: &mut Data, x: &[f64], u: &[f64], body: usize, offset: &Vector3<f64>, duration: f64) -> Result<Reach> {
    check_body(model, body)?;
    if !(duration.is_finite() && duration >= 0.0) {
        return Err(SpacearmError::InvalidArgument(format!("the duration must be finite and >= 0 s, got {duration}")));
    }
    let mom = momentum(model, data, x, u)?; // checks x and u, and runs the forward kinematics
    forward_kinematics(model, data, x)?;
    let total = model.total_mass();
    let com: Vector3<f64> = (0..model.n_bodies()).map(|b| data.com_in_world[b] * model.mass_properties(b).mass).sum::<Vector3<f64>>() / total;
    let center = com + mom.linear * (duration / total);
    let p = point_position(data, body, offset);
    let radius = if model.links().iter().any(|l| l.joint.kind == JointType::Prismatic) { None } else { Some(virtual_links(model, data, body, &p).iter().map(|v| v.norm()).sum()) };
    let plane = motion_plane(model, data, u, &p);
    Ok(Reach { center, radius, plane })
}

/// The virtual links `V_b` (one per body, in 𝒥 at the current kinematics) of the point `p`
/// fixed to `body`: `Σ_b V_b = p − r_g`.
pub fn virtual_links(model: &Model, data: &Data, body: usize, p: &Vector3<f64>) -> Vec<Vector3<f64>> {
    let n = model.n_bodies();
    // The chain from the base down to `body`, and each body's place on it.
    let mut chain = vec![body];
    while let Some(parent) = model.parent(*chain.last().expect("the chain starts with body")) {
        chain.push(parent);
    }
    chain.reverse();
    let mut on_chain = vec![None; n];
    for (k, &b) in chain.iter().enumerate() {
        on_chain[b] = Some(k);
    }
    let total = model.total_mass();
    let mut links = vec![Vector3::zeros(); n];
    for i in 0..n {
        let w = model.mass_properties(i).mass / total;
        // Up from CM_i to the chain, each step in the body it leaves.
        let (mut cur, mut b) = (data.com_in_world[i], i);
        while on_chain[b].is_none() {
            let joint = data.joint_position_in_world[b];
            links[b] += w * (joint - cur);
            cur = joint;
            b = model.parent(b).expect("the base is on every chain");
        }
        // Down the chain to `body`: from the current point to the next joint, in body `b`.
        for &next in &chain[on_chain[b].expect("on the chain") + 1..] {
            let joint = data.joint_position_in_world[next];
            links[b] += w * (joint - cur);
            cur = joint;
            b = next;
        }
        links[b] += w * (p - cur);
    }
    links
}

/// The plane of a planar system in a planar state (module docstring), or `None`.
fn motion_plane(model: &Model, data: &Data, u: &[f64], p: &Vector3<f64>) -> Option<MotionPlane> {
    let links = model.links();
    let first = links.iter().position(|l| l.joint.kind == JointType::Revolute)?;
    let n = data.joint_axis_in_world[first + 1].normalize();
    let r0 = data.base_position;
    let size = (1..model.n_bodies()).map(|b| (data.com_in_world[b] - r0).norm() + (data.joint_position_in_world[b] - r0).norm()).fold((p - r0).norm(), f64::max).max(1.0);
    let in_plane = |v: &Vector3<f64>| (v - r0).dot(&n).abs() <= PLANAR_TOLERANCE * size;
    for (k, link) in links.iter().enumerate() {
        let axis = data.joint_axis_in_world[k + 1];
        let ok = match link.joint.kind {
            JointType::Revolute => axis.cross(&n).norm() <= PLANAR_TOLERANCE,
            JointType::Prismatic => axis.dot(&n).abs() <= PLANAR_TOLERANCE,
            JointType::Fixed => true,
        };
        if !ok || !in_plane(&data.com_in_world[k + 1]) || !in_plane(&data.joint_position_in_world[k + 1]) {
            return None;
        }
    }
    if !in_plane(p) {
        return None;
    }
    for b in 0..model.n_bodies() {
        let i = data.inertia_in_world[b];
        let scale = i.norm().max(f64::MIN_POSITIVE);
        if (i * n).cross(&n).norm() > PLANAR_TOLERANCE * scale {
            return None;
        }
    }
    // The state: base angular velocity along n, every joint rate moves in the plane already
    // (axes checked above), the base CM velocity in the plane.
    let (v0, w0) = (Vector3::new(u[0], u[1], u[2]), Vector3::new(u[3], u[4], u[5]));
    let speed = u.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if v0.dot(&n).abs() > PLANAR_TOLERANCE * speed.max(f64::MIN_POSITIVE) || w0.cross(&n).norm() > PLANAR_TOLERANCE * speed.max(f64::MIN_POSITIVE) {
        return None;
    }
    Some(MotionPlane { normal: n, point: r0 })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;

    #[test]
    fn the_virtual_links_sum_to_the_point_from_the_system_cm() {
        for model in [presets::planar4(), presets::spatial6()] {
            let mut data = Data::new(&model);
            let mut x = vec![0.0; model.nx()];
            x[6] = 1.0;
            for (k, q) in x[7..].iter_mut().enumerate() {
                *q = 0.3 + 0.2 * k as f64;
            }
            forward_kinematics(&model, &mut data, &x).unwrap();
            let body = model.points()[model.end_effector().unwrap()].body;
            let offset = model.points()[model.end_effector().unwrap()].offset;
            let p = point_position(&data, body, &offset);
            let com: Vector3<f64> = (0..model.n_bodies()).map(|b| data.com_in_world[b] * model.mass_properties(b).mass).sum::<Vector3<f64>>() / model.total_mass();
            let sum: Vector3<f64> = virtual_links(&model, &data, body, &p).iter().sum();
            assert!((sum - (p - com)).norm() < 1e-12, "{}", model.name());
        }
    }
}
