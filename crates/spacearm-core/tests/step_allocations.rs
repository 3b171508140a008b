//! A simulation step allocates nothing: a counting global allocator around RK4 steps and
//! DOPRI5 attempts of spatial6 under every native controller (after a first, warming step).

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use nalgebra::Vector3;
use spacearm_core::control::{
    AttitudeControl, BaseThrusterControl, Combined, ComputedTorque, Controller, CoordinatedFlying, CoordinatedGains, JointPd,
    ResolvedMotionRate, ZeroTorque,
};
use spacearm_core::analysis::redundancy::Strategy;
use spacearm_core::analysis::Task;
use spacearm_core::sim::integrate::{Dopri5, OdeSystem, Rk4};
use spacearm_core::sim::modes::Mode;
use spacearm_core::sim::reference::{CartesianLine, JointReference};
use spacearm_core::sim::simulate::{Plant, SimOptions};
use spacearm_core::model::presets;
use spacearm_core::{JointLimits, JointType, LinkSpec, Model, ModelBuilder};

struct Counting;

thread_local! {
    // This thread's allocations only: the test harness's own threads (its "running for over 60
    // seconds" notice on a loaded machine) must not count as the step's.
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn allocations() -> usize {
    ALLOCATIONS.with(Cell::get)
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// A builder holding spatial6's base and links (unlimited joints), named `name`, and spatial6.
fn spatial6_builder(name: &str) -> (ModelBuilder, Model) {
    let base = presets::spatial6();
    let mut b = ModelBuilder::new(name, "base", base.base().mass, [[68.33, 0.0, 0.0], [0.0, 86.67, 0.0], [0.0, 0.0, 101.67]]).unwrap();
    for l in base.links() {
        b.add_link(LinkSpec {
            name: l.name.clone(),
            parent: base.body_name(l.parent).to_string(),
            joint_name: Some(l.joint.name.clone()),
            kind: l.joint.kind,
            origin_in_parent: l.joint.origin_in_parent.into(),
            rotation_in_parent: [0.0, 0.0, 0.0, 1.0],
            axis: l.joint.axis.into_inner().into(),
            com_from_joint: l.com_from_joint.into(),
            mass: l.mass.mass,
            inertia: l.mass.inertia.into(),
            limits: JointLimits::unlimited(),
        })
        .unwrap();
    }
    (b, base)
}

/// spatial6 with its fourth joint passive and sprung (on the path to the end effector).
fn with_passive_joint() -> Model {
    let (mut b, base) = spatial6_builder("p");
    let name = base.links()[3].name.clone();
    b.set_joint_dynamics(&name, spacearm_core::model::joint::JointDynamics { actuated: false, stiffness: 5.0, damping: 0.1, rest: 0.0 }).unwrap();
    b.build().unwrap()
}

/// spatial6 plus three reaction wheels.
fn wheeled() -> Model {
    let (mut b, _) = spatial6_builder("w");
    for (i, axis) in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]].into_iter().enumerate() {
        let wheel = LinkSpec::new(&format!("wheel{i}"), "base", JointType::Revolute, [0.0, 0.0, -0.3], axis, [0.0; 3], 1.0, [0.3, 0.3, 0.3]);
        b.add_link(LinkSpec { limits: JointLimits { lower: f64::NEG_INFINITY, upper: f64::INFINITY, velocity: 100.0, effort: 1.0 }, ..wheel }).unwrap();
    }
    b.build().unwrap()
}

fn allocations_per_step(model: &Model, mode: Mode, controller: &mut dyn Controller) -> (usize, usize) {
    let opts = SimOptions { mode, ..SimOptions::default() };
    let setup = allocations();
    let mut plant = Plant::new(model, &opts, controller).unwrap();
    // The counter works: setting up allocates the workspaces.
    assert!(allocations() > setup);
    let mut y = presets::initial_configuration(model);
    y.extend((0..model.nu()).map(|i| 0.05 * (i as f64).sin()));
    let mut rk = Rk4::new(plant.dim());
    let mut dp = Dopri5::new(plant.dim(), 1e-9, 1e-12);
    rk.step(&mut plant, 0.0, 1e-3, &mut y, false).unwrap();
    dp.initial_step(&mut plant, 1e-3, &y, 1.0).unwrap();
    let before = allocations();
    for i in 0..5 {
        rk.step(&mut plant, 1e-3 * (i + 1) as f64, 1e-3, &mut y, false).unwrap();
    }
    let rk_allocs = allocations() - before;
    let before = allocations();
    let mut t = 0.006;
    for _ in 0..5 {
        if dp.try_step(&mut plant, t, 1e-3, &mut y).unwrap().accepted {
            t += 1e-3;
        }
    }
    (rk_allocs, allocations() - before)
}

#[test]
fn steps_allocate_nothing_under_every_native_controller() {
    let arm = presets::spatial6();
    let q0 = arm.initial_q().to_vec();
    let q1: Vec<f64> = q0.iter().map(|q| q + 0.3).collect();
    let quintic = || JointReference::quintic(q0.clone(), q1.clone(), 0.0, 1.0).unwrap();
    let ee = &arm.points()[arm.end_effector().unwrap()];
    let line = CartesianLine::new(Vector3::new(2.6, 0.0, 0.1), Vector3::new(2.7, 0.1, 0.1), 0.0, 1.0).unwrap();
    let gains = CoordinatedGains { kp_ee: 100.0, kd_ee: 20.0, kp_base: 25.0, kd_base: 10.0 };
    let wheels = wheeled();
    let passive = with_passive_joint();
    let cases: Vec<(&str, &Model, Mode, Box<dyn Controller>)> = vec![
        ("zero", &arm, Mode::Floating, Box::new(ZeroTorque)),
        ("pd", &arm, Mode::Floating, Box::new(JointPd::new(vec![1.0], vec![0.5], quintic()))),
        ("computed torque", &arm, Mode::Floating, Box::new(ComputedTorque::new(vec![25.0], vec![10.0], quintic(), None))),
        ("rmrc", &arm, Mode::Floating, Box::new(ResolvedMotionRate::new(line, 5.0, 0.05, 0.1, 50.0, ee.body, ee.offset))),
        (
            "rmrc reactionless, whole twist, capped",
            &arm,
            Mode::Floating,
            Box::new(
                ResolvedMotionRate::new(line, 5.0, 0.05, 0.1, 50.0, ee.body, ee.offset)
                    .with_task(Task::full())
                    .with_strategy(Strategy::Reactionless)
                    .with_max_joint_rate(0.01),
            ),
        ),
        (
            "rmrc minimum disturbance, wheels as drift",
            &wheels,
            Mode::Floating,
            Box::new(ResolvedMotionRate::new(line, 5.0, 0.05, 0.1, 50.0, ee.body, ee.offset).with_strategy(Strategy::MinimumBaseDisturbance)),
        ),
        ("coordinated", &arm, Mode::Flying, Box::new(CoordinatedFlying::new(line, ee.body, ee.offset, None, gains, 0.05, 0.1))),
        (
            "coordinated, a passive joint (partial feedback linearization)",
            &passive,
            Mode::Flying,
            Box::new(CoordinatedFlying::new(line, ee.body, ee.offset, None, gains, 0.05, 0.1)),
        ),
        ("pd, a passive joint", &passive, Mode::Floating, Box::new(JointPd::new(vec![1.0], vec![0.5], JointReference::quintic(q0[..5].to_vec(), q1[..5].to_vec(), 0.0, 1.0).unwrap()))),
        ("thrusters", &arm, Mode::Flying, Box::new(BaseThrusterControl::new(None, None, 1.0, 2.0, 100.0, 50.0))),
        (
            "wheels + computed torque",
            &wheels,
            Mode::RotationFloating,
            Box::new(Combined::new(
                Box::new(ComputedTorque::new(vec![25.0], vec![10.0], quintic(), None)),
                Box::new(AttitudeControl::new([0.0, 0.0, 0.0, 1.0], 100.0, 50.0)),
            )),
        ),
    ];
    for (name, model, mode, mut c) in cases {
        let (rk, dp) = allocations_per_step(model, mode, c.as_mut());
        assert_eq!((rk, dp), (0, 0), "{name}: allocations in 5 RK4 steps, 5 DOPRI5 attempts");
    }
}
