//! The outcome of a grasp on contact (docs/contact.md, "The grasp's outcome"): from the records
//! of a run with a free target in the loop ([`crate::sim::free_target`]; `t`, `x`, `u` and the
//! target's 13-state `s = [r, quat xyzw, v, ω]` per sample), whether a gripper
//! ([`crate::model::gripper`]) **held** the target's handle, let it **slip**, or **missed** it.
//!
//! At every sample the gripper frame is the palm's body frame with its origin at the grasp
//! centre `c` (the point `<gripper>_center`), the handle frame the handle geometry's frame on the
//! target (origin `h = r + R o_h`, `o_h` its origin in the target's body frame). Their relative
//! twist and offset (docs/conventions.md: twists in 𝒥; the point velocities of
//! docs/equations.md eqs. 104–108):
//!
//! `ω_rel = ω_target − ω_palm`, `v_rel = (v + ω × (h − r)) − v_c`, `d = h − c`,
//!
//! and the fingers touching the handle: finger `i`'s collision capsules within `touch_margin` of
//! the handle's shape (parry's distance; 0 in interpenetration). Over the **final window**
//! (the samples with `t ≥ t_end − window`) the outcome is
//!
//! - **missed** when no finger touched the handle at any sample of the run;
//! - **held** when, at every sample of the window, every finger touches the handle and
//!   `‖ω_rel‖ ≤ max_relative_spin`, `‖v_rel‖ ≤ max_relative_speed`, `‖d‖ ≤ max_offset`
//!   (bounds included);
//! - **slipped** otherwise (a finger touched the handle, and the grasp did not settle: the
//!   handle turns or slides in the fingers, wanders from the grasp centre, or was knocked out).
//!
//! The outcome carries the numbers that decided it (the window's largest `‖ω_rel‖`, `‖v_rel‖`,
//! `‖d‖`, its fewest fingers touching, the first touch) and the thresholds used.

use nalgebra::{Isometry3, Vector3};
use serde::{Deserialize, Serialize};

use crate::algorithms::kinematics::{forward_kinematics, point_position};
use crate::algorithms::rnea::velocity_pass;
use crate::collision::compliant::point_velocity;
use crate::collision::CollisionShapes;
use crate::error::{Result, SpacearmError};
use crate::model::data::Data;
use crate::model::geometry::GeometryRole;
use crate::model::gripper::detect_grippers;
use crate::model::Model;
use crate::sim::free_target::FreeTarget;

/// The thresholds of [`grasp_outcome`] (module docs), with their defaults.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GraspThresholds {
    /// The final window's length, s (> 0, shorter than the run; default 0.5).
    #[serde(default = "default_window")]
    pub window: f64,
    /// The largest relative angular speed of handle and palm in a held grasp, rad/s (default 0.005).
    #[serde(default = "default_spin")]
    pub max_relative_spin: f64,
    /// The largest speed of the handle's origin relative to the grasp centre, m/s (default 0.005).
    #[serde(default = "default_speed")]
    pub max_relative_speed: f64,
    /// The largest distance of the handle's origin from the grasp centre, m (default 0.005).
    #[serde(default = "default_offset")]
    pub max_offset: f64,
    /// A finger within this distance of the handle touches it, m (≥ 0; default 0.001).
    #[serde(default = "default_margin")]
    pub touch_margin: f64,
}

fn default_window() -> f64 {
    0.5
}
fn default_spin() -> f64 {
    0.005
}
fn default_speed() -> f64 {
    0.005
}
fn default_offset() -> f64 {
    0.005
}
fn default_margin() -> f64 {
    0.001
}

impl Default for GraspThresholds {
    fn default() -> Self {
        GraspThresholds {
            window: default_window(),
            max_relative_spin: default_spin(),
            max_relative_speed: default_speed(),
            max_offset: default_offset(),
            touch_margin: default_margin(),
        }
    }
}

impl GraspThresholds {
    /// Every threshold finite and > 0 (`touch_margin` ≥ 0), named when not.
    pub fn validate(&self) -> Result<()> {
        for (what, v, unit) in [
            ("window", self.window, "s"),
            ("max_relative_spin", self.max_relative_spin, "rad/s"),
            ("max_relative_speed", self.max_relative_speed, "m/s"),
            ("max_offset", self.max_offset, "m"),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(SpacearmError::argument(format!("grasp threshold {what} must be finite and > 0 {unit}, got {v}")));
            }
        }
        if !(self.touch_margin.is_finite() && self.touch_margin >= 0.0) {
            return Err(SpacearmError::argument(format!("grasp threshold touch_margin must be finite and >= 0 m, got {}", self.touch_margin)));
        }
        Ok(())
    }
}

/// The three outcomes (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum GraspVerdict {
    /// Every finger on the handle, handle and palm moving as one at the grasp centre.
    Held,
    /// A finger touched the handle but the grasp did not settle.
    Slipped,
    /// No finger touched the handle.
    Missed,
}

impl GraspVerdict {
    /// `"held"`, `"slipped"` or `"missed"`.
    pub fn name(self) -> &'static str {
        match self {
            GraspVerdict::Held => "held",
            GraspVerdict::Slipped => "slipped",
            GraspVerdict::Missed => "missed",
        }
    }
}

/// What [`grasp_outcome`] found: the verdict and the numbers that decided it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GraspOutcome {
    /// Held, slipped or missed.
    pub verdict: GraspVerdict,
    /// Why, in words (the criteria that failed, or those that held).
    pub reason: String,
    /// The window's largest `‖ω_target − ω_palm‖`, rad/s.
    pub relative_spin: f64,
    /// The window's largest `‖v_rel‖` (handle origin vs grasp centre), m/s.
    pub relative_speed: f64,
    /// The window's largest `‖h − c‖`, m.
    pub offset: f64,
    /// The fewest fingers touching the handle at a sample of the window.
    pub fingers_touching: usize,
    /// The gripper's finger count.
    pub fingers: usize,
    /// The first sample's time at which a finger touched the handle (`None`: never).
    pub first_touch: Option<f64>,
    /// The samples of the run at which a finger touched the handle.
    pub touching_samples: usize,
    /// The window's first sample time, s.
    pub window_start: f64,
    /// The window's sample count.
    pub window_samples: usize,
    /// The thresholds used.
    pub thresholds: GraspThresholds,
}

/// The outcome of the grasp of `target`'s collision geometry `handle` by `robot`'s gripper
/// `gripper` over the records `t` (n, increasing), `x` (n × nx), `u` (n × nu) and
/// `target_state` (n × 13), flattened by rows (module docs).
#[allow(clippy::too_many_arguments)]
pub fn grasp_outcome(
    robot: &Model,
    target: &Model,
    gripper: &str,
    handle: &str,
    t: &[f64],
    x: &[f64],
    u: &[f64],
    target_state: &[f64],
    thresholds: &GraspThresholds,
) -> Result<GraspOutcome> {
    thresholds.validate()?;
    let grippers = detect_grippers(robot);
    let Some(g) = grippers.iter().find(|g| g.name == gripper) else {
        let names: Vec<&str> = grippers.iter().map(|g| g.name.as_str()).collect();
        return Err(SpacearmError::NotFound(format!("robot '{}' has no gripper '{gripper}'; its grippers are {names:?}", robot.name())));
    };
    if !target.links().is_empty() {
        return Err(SpacearmError::argument(format!("target '{}' has {} link(s): a grasp's target is one rigid body (a model without links)", target.name(), target.links().len())));
    }
    let collision: Vec<&str> = target.geometries().iter().filter(|h| h.role == GeometryRole::Collision).map(|h| h.name.as_str()).collect();
    let Some(h_index) = target.geometries().iter().position(|h| h.name == handle && h.role == GeometryRole::Collision) else {
        return Err(SpacearmError::NotFound(format!("target '{}' has no collision geometry '{handle}'; its collision geometries are {collision:?}", target.name())));
    };
    let n = t.len();
    let (nx, nu) = (robot.nx(), robot.nu());
    for (what, v, width) in [("x", x, nx), ("u", u, nu), ("target_state", target_state, 13)] {
        if v.len() != n * width {
            return Err(SpacearmError::Dimension { what: what.into(), expected: format!("{n} samples × {width} = {}", n * width), got: v.len() });
        }
    }
    if n < 2 {
        return Err(SpacearmError::argument(format!("a grasp's outcome needs at least 2 samples, got {n}")));
    }
    if t.iter().any(|v| !v.is_finite()) || t.windows(2).any(|w| w[1] <= w[0]) {
        return Err(SpacearmError::argument("the sample times t must be finite and increasing"));
    }
    let t_end = t[n - 1];
    if thresholds.window >= t_end - t[0] {
        return Err(SpacearmError::argument(format!(
            "grasp threshold window {} s must be shorter than the run ({} s from the first sample to the last)",
            thresholds.window,
            t_end - t[0]
        )));
    }
    let center = &robot.points()[robot.point_index(&format!("{gripper}_center"))?];
    let fingers: Vec<usize> = (0..g.finger_dofs.len()).map(|i| robot.body_index(&format!("{gripper}_finger{i}"))).collect::<Result<_>>()?;
    let robot_shapes = CollisionShapes::from_model(robot)?;
    let target_shapes = CollisionShapes::from_model(target)?;
    let handle_shape = target_shapes.shapes.iter().find(|s| s.geometry == h_index).expect("a collision geometry has its shape");
    let handle_origin = target.geometries()[h_index].origin;

    let mut data = Data::new(robot);
    let window_start = t.iter().copied().find(|&ti| ti >= t_end - thresholds.window).unwrap_or(t_end);
    let (mut spin, mut speed, mut offset, mut fewest, mut window_samples) = (0.0_f64, 0.0_f64, 0.0_f64, usize::MAX, 0);
    let (mut first_touch, mut touching_samples) = (None, 0);
    for k in 0..n {
        let (xk, uk, s) = (&x[k * nx..(k + 1) * nx], &u[k * nu..(k + 1) * nu], &target_state[13 * k..13 * k + 13]);
        if s.iter().any(|v| !v.is_finite()) {
            return Err(SpacearmError::argument(format!("target_state at sample {k} is not finite")));
        }
        forward_kinematics(robot, &mut data, xk)?;
        crate::algorithms::kinematics::check_velocity(robot, "u", uk)?;
        velocity_pass(robot, &mut data, uk);
        let pose = FreeTarget::pose(s);
        let handle_pose: Isometry3<f64> = pose * handle_shape.in_body;
        let touching = fingers
            .iter()
            .filter(|&&f| {
                robot_shapes.shapes.iter().filter(|rs| rs.body == f).any(|rs| {
                    let finger_pose = body_pose(&data, f) * rs.in_body;
                    parry3d_f64::query::distance(&finger_pose, rs.shape.as_ref(), &handle_pose, handle_shape.shape.as_ref()).is_ok_and(|d| d <= thresholds.touch_margin)
                })
            })
            .count();
        if touching > 0 {
            touching_samples += 1;
            first_touch.get_or_insert(t[k]);
        }
        if t[k] < window_start {
            continue;
        }
        window_samples += 1;
        let c = point_position(&data, center.body, &center.offset);
        let v_c = point_velocity(&data, center.body, &c);
        let w_palm = data.body_velocity[g.palm].fixed_rows::<3>(3).into_owned();
        let h = pose * nalgebra::Point3::from(handle_origin);
        let v_h = FreeTarget::point_velocity(s, &h.coords);
        spin = spin.max((Vector3::new(s[10], s[11], s[12]) - w_palm).norm());
        speed = speed.max((v_h - v_c).norm());
        offset = offset.max((h.coords - c).norm());
        fewest = fewest.min(touching);
    }
    let th = thresholds;
    let (verdict, reason) = if touching_samples == 0 {
        (GraspVerdict::Missed, format!("no finger came within {} m of the handle '{handle}' in the run", th.touch_margin))
    } else {
        let mut failed = Vec::new();
        if fewest < fingers.len() {
            failed.push(format!("{fewest} of {} fingers on the handle at a sample of the window", fingers.len()));
        }
        if spin > th.max_relative_spin {
            failed.push(format!("relative spin {spin:.3e} rad/s > {} rad/s", th.max_relative_spin));
        }
        if speed > th.max_relative_speed {
            failed.push(format!("relative speed {speed:.3e} m/s > {} m/s", th.max_relative_speed));
        }
        if offset > th.max_offset {
            failed.push(format!("handle {offset:.3e} m from the grasp centre > {} m", th.max_offset));
        }
        if failed.is_empty() {
            (
                GraspVerdict::Held,
                format!(
                    "every finger on the handle over the last {} s: relative spin {spin:.3e} rad/s, relative speed {speed:.3e} m/s, handle {offset:.3e} m from the grasp centre",
                    th.window
                ),
            )
        } else {
            (GraspVerdict::Slipped, format!("over the last {} s: {}", th.window, failed.join("; ")))
        }
    };
    Ok(GraspOutcome {
        verdict,
        reason,
        relative_spin: spin,
        relative_speed: speed,
        offset,
        fingers_touching: fewest,
        fingers: fingers.len(),
        first_touch,
        touching_samples,
        window_start,
        window_samples,
        thresholds: *th,
    })
}

/// The CM frame of `body` in 𝒥 from the kinematics in `data`.
fn body_pose(data: &Data, body: usize) -> Isometry3<f64> {
    let rot = nalgebra::Rotation3::from_matrix_unchecked(data.body_to_world[body]);
    Isometry3::from_parts(nalgebra::Translation3::from(data.com_in_world[body]), nalgebra::UnitQuaternion::from_rotation_matrix(&rot))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::builder::ModelBuilder;
    use crate::model::geometry::{GeometrySpec, Shape};
    use crate::model::gripper;

    /// A 10 kg base with a parallel gripper on its `+z` face (fingers along `+z`, opening
    /// 0.1 m, ℓ 0.12 m, r 0.01 m): the grasp centre at `(0, 0, 0.56)`.
    fn robot() -> Model {
        gripper::tests::model(&gripper::tests::spec(2))
    }

    /// A box with a handle (a sphere of radius 0.02 m at `(−0.3, 0, 0)` from its CM).
    fn target() -> Model {
        let mut t = ModelBuilder::new("box", "box", 5.0, [[0.1, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 0.1]]).unwrap();
        let geom = |name: &str, shape: Shape, origin: [f64; 3]| GeometrySpec { name: Some(name.into()), body: "box".into(), role: GeometryRole::Collision, shape, origin, rotation: [0.0, 0.0, 0.0, 1.0], rgba: None };
        t.add_geometry(geom("body", Shape::Box { size: [0.2, 0.2, 0.2] }, [0.0; 3])).unwrap();
        t.add_geometry(geom("handle", Shape::Sphere { radius: 0.02 }, [-0.3, 0.0, 0.0])).unwrap();
        t.build().unwrap()
    }

    /// `n` samples over 1 s of the robot at rest with the fingers at `q` and the target's 13-state
    /// from `state(t)`.
    fn records(robot: &Model, n: usize, q: f64, state: impl Fn(f64) -> [f64; 13]) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
        let t: Vec<f64> = (0..n).map(|k| k as f64 / (n - 1) as f64).collect();
        let mut x0 = vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];
        x0.extend(std::iter::repeat(q).take(robot.n_dof()));
        let x = t.iter().flat_map(|_| x0.clone()).collect();
        let u = vec![0.0; n * robot.nu()];
        let s = t.iter().flat_map(|&ti| state(ti)).collect();
        (t, x, u, s)
    }

    /// The target with its handle's centre at `h` (its CM at `h + (0.3, 0, 0)`), moving at `v`
    /// and spinning at `w` about its CM.
    fn at(h: [f64; 3], v: [f64; 3], w: [f64; 3]) -> [f64; 13] {
        [h[0] + 0.3, h[1], h[2], 0.0, 0.0, 0.0, 1.0, v[0], v[1], v[2], w[0], w[1], w[2]]
    }

    #[test]
    fn a_handle_squeezed_at_the_centre_is_held_and_one_away_is_missed() {
        let (r, b) = (robot(), target());
        // Fingers shut on the 0.04 m ball: axes 0.1 − 2q apart, surfaces touch the ball at q = 0.02.
        let (t, x, u, s) = records(&r, 21, 0.02, |_| at([0.0, 0.0, 0.56], [0.0; 3], [0.0; 3]));
        let o = grasp_outcome(&r, &b, "hand", "handle", &t, &x, &u, &s, &GraspThresholds::default()).unwrap();
        assert_eq!(o.verdict, GraspVerdict::Held, "{}", o.reason);
        assert_eq!((o.fingers_touching, o.fingers, o.touching_samples), (2, 2, 21));
        assert!(o.offset < 1e-12 && o.relative_spin == 0.0 && o.relative_speed == 0.0);
        assert_eq!(o.window_samples, 11); // t ≥ 0.5 of 0, 0.05, ..., 1
        // The fingers open (q = 0): 0.02 m gaps on both sides of the ball, beyond the margin.
        let (t, x, u, s) = records(&r, 21, 0.0, |_| at([0.0, 0.0, 0.56], [0.0; 3], [0.0; 3]));
        let o = grasp_outcome(&r, &b, "hand", "handle", &t, &x, &u, &s, &GraspThresholds::default()).unwrap();
        assert_eq!((o.verdict, o.first_touch), (GraspVerdict::Missed, None), "{}", o.reason);
        // A margin just over the gap (0.05 − 0.01 − 0.02 = 0.02 m from each finger) touches again.
        let th = GraspThresholds { touch_margin: 0.0201, ..GraspThresholds::default() };
        let o = grasp_outcome(&r, &b, "hand", "handle", &t, &x, &u, &s, &th).unwrap();
        assert_eq!((o.verdict, o.fingers_touching), (GraspVerdict::Held, 2), "{}", o.reason);
        let th = GraspThresholds { touch_margin: 0.0199, ..GraspThresholds::default() };
        assert_eq!(grasp_outcome(&r, &b, "hand", "handle", &t, &x, &u, &s, &th).unwrap().verdict, GraspVerdict::Missed);
    }

    #[test]
    fn each_threshold_decides_at_its_bound() {
        let (r, b) = (robot(), target());
        let ok = |th: &GraspThresholds, state: &dyn Fn(f64) -> [f64; 13]| {
            let (t, x, u, s) = records(&r, 21, 0.02, state);
            grasp_outcome(&r, &b, "hand", "handle", &t, &x, &u, &s, th).unwrap()
        };
        // Spinning at w about the CM: the relative spin is w; the handle's speed 0.3 w (ω × (−0.3, 0, 0)).
        let w = 0.004;
        let spin = |_: f64| at([0.0, 0.0, 0.56], [0.0; 3], [0.0, 0.0, w]);
        let o = ok(&GraspThresholds::default(), &spin);
        assert_eq!(o.verdict, GraspVerdict::Held, "{}", o.reason);
        assert!((o.relative_spin - w).abs() < 1e-18 && (o.relative_speed - 0.3 * w).abs() < 1e-15, "{} {}", o.relative_spin, o.relative_speed);
        let o = ok(&GraspThresholds { max_relative_spin: 0.0039, ..GraspThresholds::default() }, &spin);
        assert_eq!(o.verdict, GraspVerdict::Slipped);
        assert!(o.reason.contains("relative spin"), "{}", o.reason);
        let o = ok(&GraspThresholds { max_relative_speed: 0.3 * w * 0.99, ..GraspThresholds::default() }, &spin);
        assert!(o.verdict == GraspVerdict::Slipped && o.reason.contains("relative speed"), "{}", o.reason);
        // Offset along the fingers (z, between them: both still touch the ball) by 3 mm.
        let off = |_: f64| at([0.0, 0.0, 0.563], [0.0; 3], [0.0; 3]);
        let o = ok(&GraspThresholds::default(), &off);
        assert!(o.verdict == GraspVerdict::Held && (o.offset - 0.003).abs() < 1e-12, "{} {}", o.reason, o.offset);
        let o = ok(&GraspThresholds { max_offset: 0.0029, ..GraspThresholds::default() }, &off);
        assert!(o.verdict == GraspVerdict::Slipped && o.reason.contains("grasp centre"), "{}", o.reason);
        // Only the window counts: a handle drifting away before t = 0.5 and back at rest after.
        let late = |t: f64| at([0.0, 0.0, 0.56 + if t < 0.45 { 0.01 } else { 0.0 }], [0.0; 3], [0.0; 3]);
        assert_eq!(ok(&GraspThresholds::default(), &late).verdict, GraspVerdict::Held);
        assert_eq!(ok(&GraspThresholds { window: 0.6, ..GraspThresholds::default() }, &late).verdict, GraspVerdict::Slipped);
    }

    #[test]
    fn a_handle_out_of_one_finger_slips() {
        let (r, b) = (robot(), target());
        // Sideways by 10 mm along x: one finger 10 mm from the ball, the other pressing into it.
        let (t, x, u, s) = records(&r, 21, 0.02, |_| at([0.01, 0.0, 0.56], [0.0; 3], [0.0; 3]));
        let o = grasp_outcome(&r, &b, "hand", "handle", &t, &x, &u, &s, &GraspThresholds { max_offset: 0.02, ..GraspThresholds::default() }).unwrap();
        assert_eq!((o.verdict, o.fingers_touching), (GraspVerdict::Slipped, 1), "{}", o.reason);
    }

    #[test]
    fn bad_inputs_are_named() {
        let (r, b) = (robot(), target());
        let (t, x, u, s) = records(&r, 5, 0.0, |_| at([0.0, 0.0, 0.56], [0.0; 3], [0.0; 3]));
        let e = |g: &str, h: &str, th: GraspThresholds, s: &[f64]| grasp_outcome(&r, &b, g, h, &t, &x, &u, s, &th).unwrap_err().to_string();
        assert!(e("claw", "handle", GraspThresholds::default(), &s).contains("no gripper 'claw'"));
        assert!(e("hand", "knob", GraspThresholds::default(), &s).contains("'knob'"));
        assert!(e("hand", "handle", GraspThresholds { window: 1.0, ..GraspThresholds::default() }, &s).contains("shorter than the run"));
        assert!(e("hand", "handle", GraspThresholds { max_offset: -1.0, ..GraspThresholds::default() }, &s).contains("max_offset"));
        assert!(e("hand", "handle", GraspThresholds::default(), &s[..13]).contains("target_state"));
    }
}
