//! The compliant contact law (docs/contact.md, "Contact dynamics"): from a [`Contact`] of
//! detect.rs and the bodies' velocities, the normal force of a spring–dashpot in the depth
//! (Kelvin–Voigt `f_n = k δ^p + d δ̇`, or Hunt–Crossley `f_n = k δ^p (1 + c δ̇)`), clamped at zero
//! (contact pushes, never pulls), and the regularized Coulomb friction
//! `f_t = −μ f_n v_t / √(|v_t|² + ε²)`; applied as equal and opposite forces at one point (the
//! midpoint of the two surface points) on the two bodies, so that the pair exerts no net force
//! and no net moment on the system: the momenta of a floating system are kept (docs/equations.md,
//! the generalized force of an external wrench `Jᵀ w` of docs/conventions.md).

use nalgebra::Vector3;

use crate::algorithms::wrench::ExternalWrench;
use crate::collision::detect::Contact;
use crate::model::data::Data;

/// The normal force law.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NormalLaw {
    /// `f_n = k δ^p + d δ̇` (`d` in N·s/m): with `p = 1` the linear spring–dashpot.
    KelvinVoigt,
    /// `f_n = k δ^p (1 + c δ̇)` (`c` in s/m): no force jump at onset (Hunt & Crossley 1975).
    HuntCrossley,
}

/// The parameters of the compliant law (checked by the run's description, sim/contact.rs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactLaw {
    /// The normal law.
    pub law: NormalLaw,
    /// `k`, N/m^p.
    pub stiffness: f64,
    /// `p` (1: linear; 1.5: Hertz's ball).
    pub exponent: f64,
    /// `d` (Kelvin–Voigt, N·s/m) or `c` (Hunt–Crossley, s/m).
    pub damping: f64,
    /// Coulomb's `μ`.
    pub friction: f64,
    /// The regularization velocity `ε` of the friction, m/s (> 0).
    pub slip_velocity: f64,
}

/// The force of one contact at one state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactForce {
    /// The first and second body.
    pub body: [usize; 2],
    /// The point where the forces act, in 𝒥 (the midpoint of the two surface points), m.
    pub point: Vector3<f64>,
    /// The unit normal from the first body towards the second.
    pub normal: Vector3<f64>,
    /// Depth `δ = −distance`, m (> 0).
    pub depth: f64,
    /// Depth rate `δ̇ = −n · (v₂ − v₁)`, m/s.
    pub depth_rate: f64,
    /// The normal force `f_n ≥ 0`, N.
    pub normal_force: f64,
    /// The total force on the second body (normal plus friction), in 𝒥, N; the first body
    /// feels its opposite.
    pub force: Vector3<f64>,
    /// The power of the pair on the system, `force · (v₂ − v₁)`, W.
    pub power: f64,
}

impl ContactLaw {
    /// The normal force at depth `δ > 0` and depth rate `δ̇`, clamped at zero.
    pub fn normal_force(&self, depth: f64, depth_rate: f64) -> f64 {
        let spring = self.stiffness * depth.powf(self.exponent);
        let f = match self.law {
            NormalLaw::KelvinVoigt => spring + self.damping * depth_rate,
            NormalLaw::HuntCrossley => spring * (1.0 + self.damping * depth_rate),
        };
        f.max(0.0)
    }

    /// The friction force on the second body for the normal force `f_n` and the tangential
    /// velocity `v_t` of the second body relative to the first: `−μ f_n v_t / √(|v_t|² + ε²)`.
    pub fn friction_force(&self, normal_force: f64, tangential_velocity: &Vector3<f64>) -> Vector3<f64> {
        let s = (tangential_velocity.norm_squared() + self.slip_velocity * self.slip_velocity).sqrt();
        tangential_velocity * (-self.friction * normal_force / s)
    }

    /// The force of `contact` (kinematics and body velocities current in `data`: after
    /// [`crate::algorithms::rnea::velocity_pass`]); `None` when the shapes are apart. Touching
    /// (`δ = 0`) the force is the law's there: a Kelvin–Voigt dashpot's `d δ̇` when they approach.
    pub fn force(&self, contact: &Contact, data: &Data) -> Option<ContactForce> {
        self.force_with(contact, |body, point| point_velocity(data, body, point))
    }

    /// [`ContactLaw::force`] with the velocity in 𝒥 of a body's material point given by
    /// `velocity(body, point)`: a body outside the model (a free target,
    /// [`crate::sim::free_target`]) moves by its own state.
    pub fn force_with(&self, contact: &Contact, velocity: impl Fn(usize, &Vector3<f64>) -> Vector3<f64>) -> Option<ContactForce> {
        let depth = -contact.distance;
        if depth < 0.0 {
            return None;
        }
        let point = 0.5 * (contact.point[0] + contact.point[1]);
        let n = contact.normal;
        let v_rel = velocity(contact.body[1], &point) - velocity(contact.body[0], &point);
        let vn = n.dot(&v_rel);
        let normal_force = self.normal_force(depth, -vn);
        let v_t = v_rel - n * vn;
        let force = n * normal_force + self.friction_force(normal_force, &v_t);
        Some(ContactForce { body: contact.body, point, normal: n, depth, depth_rate: -vn, normal_force, force, power: force.dot(&v_rel) })
    }
}

/// The velocity in 𝒥 of the point of body `body` at `point` (𝒥): `v + ω × (point − r0)` with
/// `[v; ω]` the body's spatial velocity at the base CM (docs/conventions.md).
pub fn point_velocity(data: &Data, body: usize, point: &Vector3<f64>) -> Vector3<f64> {
    let v = &data.body_velocity[body];
    let (lin, ang) = (Vector3::new(v[0], v[1], v[2]), Vector3::new(v[3], v[4], v[5]));
    lin + ang.cross(&(point - data.base_position))
}

impl ContactForce {
    /// The pair's two wrenches: `−force` on the first body and `force` on the second, both at
    /// [`ContactForce::point`] (offsets in each body's frame from its CM).
    pub fn wrenches(&self, data: &Data) -> [ExternalWrench; 2] {
        let on = |body: usize, force: Vector3<f64>| ExternalWrench {
            body,
            offset: data.body_to_world[body].transpose() * (self.point - data.com_in_world[body]),
            force,
            torque: Vector3::zeros(),
        };
        [on(self.body[0], -self.force), on(self.body[1], self.force)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law(law: NormalLaw) -> ContactLaw {
        ContactLaw { law, stiffness: 1e4, exponent: 1.5, damping: 0.3, friction: 0.4, slip_velocity: 0.01 }
    }

    #[test]
    fn the_normal_laws_are_their_closed_forms_and_never_pull() {
        let kv = law(NormalLaw::KelvinVoigt);
        assert!((kv.normal_force(0.01, 0.2) - (1e4 * 0.01f64.powf(1.5) + 0.3 * 0.2)).abs() < 1e-12);
        let hc = law(NormalLaw::HuntCrossley);
        assert!((hc.normal_force(0.01, 0.2) - 1e4 * 0.01f64.powf(1.5) * (1.0 + 0.3 * 0.2)).abs() < 1e-12);
        // Separating fast: the dashpot would pull; the law gives zero.
        assert_eq!(kv.normal_force(0.01, -100.0), 0.0);
        assert_eq!(hc.normal_force(0.01, -100.0), 0.0);
    }

    #[test]
    fn friction_opposes_the_slip_and_saturates_at_mu_fn() {
        let l = law(NormalLaw::KelvinVoigt);
        let v = Vector3::new(0.3, -0.4, 0.0);
        let f = l.friction_force(10.0, &v);
        // Opposite to v, magnitude μ f_n |v| / √(|v|² + ε²).
        assert!((f.normalize() + v.normalize()).norm() < 1e-15);
        assert!((f.norm() - 0.4 * 10.0 * 0.5 / (0.25f64 + 1e-4).sqrt()).abs() < 1e-12);
        // At rest: none; slow: viscous with the slope μ f_n / ε.
        assert_eq!(l.friction_force(10.0, &Vector3::zeros()), Vector3::zeros());
        let slow = l.friction_force(10.0, &Vector3::new(1e-9, 0.0, 0.0));
        assert!((slow.x / 1e-9 + 0.4 * 10.0 / 0.01).abs() < 1e-6);
    }
}
