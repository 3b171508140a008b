//! Random spacecraft-manipulator trees, tangent steps and a scripted controller for the
//! core's tests (each test crate uses a part of it).
#![allow(dead_code)]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use spacearm_core::model::body::MassProperties;
use spacearm_core::control::{Command, ControlContext, Controller};
use spacearm_core::{Data, GeometryRole, GeometrySpec, JointLimits, JointType, LinkSpec, Model, ModelBuilder, Shape};

pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

fn unit_quaternion(r: &mut ChaCha8Rng) -> [f64; 4] {
    let v: [f64; 4] = [r.random_range(-1.0..1.0), r.random_range(-1.0..1.0), r.random_range(-1.0..1.0), r.random_range(-1.0..1.0)];
    let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    [v[0] / n, v[1] / n, v[2] / n, v[3] / n]
}

/// A random physical inertia: random principal moments satisfying the triangle inequality,
/// rotated by a random rotation.
fn inertia(r: &mut ChaCha8Rng, mass: f64) -> [[f64; 3]; 3] {
    let (a, b, c): (f64, f64, f64) = (r.random_range(0.05..1.0), r.random_range(0.05..1.0), r.random_range(0.05..1.0));
    let d = MassProperties::solid_box(mass, a, b, c);
    let q = unit_quaternion(r);
    let rot = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[3], q[0], q[1], q[2])).to_rotation_matrix();
    let m = rot.matrix() * d * rot.matrix().transpose();
    let m = (m + m.transpose()) * 0.5;
    [[m[(0, 0)], m[(0, 1)], m[(0, 2)]], [m[(1, 0)], m[(1, 1)], m[(1, 2)]], [m[(2, 0)], m[(2, 1)], m[(2, 2)]]]
}

/// A random tree with `n_links` links, branches at the base and mid-chain, mixed joint types.
pub fn random_model(r: &mut ChaCha8Rng, n_links: usize) -> Model {
    random_builder(r, n_links).build().unwrap()
}

/// The builder of [`random_model`] before it is built (links `link1..`, a point `tip` as end
/// effector), for tests that add to it.
pub fn random_builder(r: &mut ChaCha8Rng, n_links: usize) -> ModelBuilder {
    let base_mass = r.random_range(50.0..500.0);
    let mut b = ModelBuilder::new("random", "base", base_mass, inertia(r, base_mass)).unwrap();
    let mut names = vec!["base".to_string()];
    for k in 0..n_links {
        let parent = if k == 0 { 0 } else if r.random_bool(0.6) { k } else { r.random_range(0..=k) };
        let kind = match r.random_range(0..10) {
            0 => JointType::Fixed,
            1 | 2 => JointType::Prismatic,
            _ => JointType::Revolute,
        };
        let mass = r.random_range(0.5..20.0);
        let name = format!("link{}", k + 1);
        b.add_link(LinkSpec {
            name: name.clone(),
            parent: names[parent].clone(),
            joint_name: None,
            kind,
            origin_in_parent: [r.random_range(-1.0..1.0), r.random_range(-1.0..1.0), r.random_range(-1.0..1.0)],
            rotation_in_parent: unit_quaternion(r),
            axis: [r.random_range(-1.0..1.0), r.random_range(-1.0..1.0), r.random_range(-1.0..1.0)],
            com_from_joint: [r.random_range(-0.6..0.6), r.random_range(-0.6..0.6), r.random_range(-0.6..0.6)],
            mass,
            inertia: inertia(r, mass),
            limits: JointLimits::unlimited(),
        })
        .unwrap();
        names.push(name);
    }
    b.add_point("tip", names.last().unwrap(), [0.1, -0.2, 0.3]).unwrap();
    b.set_end_effector("tip");
    b
}

pub fn random_state(r: &mut ChaCha8Rng, model: &Model) -> (Vec<f64>, Vec<f64>) {
    let mut x: Vec<f64> = (0..3).map(|_| r.random_range(-5.0..5.0)).collect();
    x.extend(unit_quaternion(r));
    x.extend((0..model.n_dof()).map(|_| r.random_range(-2.0..2.0)));
    let u = (0..model.nu()).map(|_| r.random_range(-1.0..1.0)).collect();
    (x, u)
}

pub fn random_vector(r: &mut ChaCha8Rng, n: usize, scale: f64) -> Vec<f64> {
    (0..n).map(|_| r.random_range(-scale..scale)).collect()
}

/// Runs `check(trial, rng, model, data, x, u)` on `trials` random trees, trial `k`'s made by
/// `model_for(rng, k)`, each at a random state drawn after its model from the same generator.
pub fn on_random_states(
    seed: u64,
    trials: usize,
    mut model_for: impl FnMut(&mut ChaCha8Rng, usize) -> Model,
    mut check: impl FnMut(usize, &mut ChaCha8Rng, &Model, &mut Data, &[f64], &[f64]),
) {
    let mut r = rng(seed);
    for trial in 0..trials {
        let model = model_for(&mut r, trial);
        let mut data = Data::new(&model);
        let (x, u) = random_state(&mut r, &model);
        check(trial, &mut r, &model, &mut data, &x, &u);
    }
}

/// `x` moved for time `s` at velocity `u` (tangent coordinates; `R0 ← exp(s ω0^) R0`).
pub fn advance(x: &[f64], u: &[f64], s: f64) -> Vec<f64> {
    let mut y = x.to_vec();
    for i in 0..3 {
        y[i] += s * u[i];
    }
    let q0 = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(x[6], x[3], x[4], x[5]));
    let q1 = nalgebra::UnitQuaternion::from_scaled_axis(nalgebra::Vector3::new(u[3], u[4], u[5]) * s) * q0;
    y[3] = q1.i;
    y[4] = q1.j;
    y[5] = q1.k;
    y[6] = q1.w;
    for j in 0..u.len() - 6 {
        y[7 + j] += s * u[6 + j];
    }
    y
}

/// `x ⊕ h e_k` in tangent coordinates `[δr0, δθ (world, left), δq]`: `R0 ← exp(h ẽ) R0`.
pub fn perturb(x: &[f64], k: usize, h: f64) -> Vec<f64> {
    let mut e = vec![0.0; x.len() - 1];
    e[k] = 1.0;
    advance(x, &e, h)
}

/// A controller that writes `command(t, out)`: the tests' fixed and scripted commands, one
/// `Controller` impl for all of them.
pub struct Scripted<F> {
    pub name: &'static str,
    pub command: F,
}

impl<F: FnMut(f64, &mut Command) + Send> Controller for Scripted<F> {
    fn name(&self) -> &str {
        self.name
    }
    fn setup(&mut self, _ctx: &ControlContext<'_>) -> spacearm_core::Result<()> {
        Ok(())
    }
    fn command(&mut self, t: f64, _x: &[f64], _u: &[f64], out: &mut Command) -> spacearm_core::Result<()> {
        (self.command)(t, out);
        Ok(())
    }
}

/// Central difference of a vector function of a plain vector `v` along its coordinate `k`.
pub fn central_flat(mut f: impl FnMut(&[f64]) -> nalgebra::DVector<f64>, v: &[f64], k: usize, h: f64) -> nalgebra::DVector<f64> {
    let (mut plus, mut minus) = (v.to_vec(), v.to_vec());
    plus[k] += h;
    minus[k] -= h;
    (f(&plus) - f(&minus)) / (2.0 * h)
}

/// A floating base (100 kg) with a ball of 0.3 m at its CM and a slider along x (1 kg) with a
/// ball of 0.2 m: they touch at q = 0.5 (the contact runs' two-body impact, compliant and rigid).
pub fn balls() -> Model {
    let mut b = ModelBuilder::new("balls", "base", 100.0, [[10.0, 0.0, 0.0], [0.0, 10.0, 0.0], [0.0, 0.0, 10.0]]).unwrap();
    b.add_link(LinkSpec::new("slider", "base", JointType::Prismatic, [0.0; 3], [1.0, 0.0, 0.0], [0.0; 3], 1.0, [0.1; 3])).unwrap();
    let ball = |body: &str, radius: f64| GeometrySpec::new(body, GeometryRole::Collision, Shape::Sphere { radius });
    b.add_geometry(ball("base", 0.3)).unwrap();
    b.add_geometry(ball("slider", 0.2)).unwrap();
    b.build().unwrap()
}
