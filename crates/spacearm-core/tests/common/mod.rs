//! Random spacecraft-manipulator trees for the core's tests.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use spacearm_core::model::body::MassProperties;
use spacearm_core::{JointLimits, JointType, LinkSpec, Model, ModelBuilder};

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
#[allow(dead_code)]
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
