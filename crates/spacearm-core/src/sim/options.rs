//! The options of a run: as data, [`RunSpec`] (serde: what every door reads — the Python
//! `RunOptions`, the C stepper's and an FMU's options TOML), and built and checked,
//! [`SimOptions`] (mode, integrator, duration, steps, records, actuators, orbit;
//! [`SimOptions::validate`]); the loop is [`crate::sim::simulate`]. docs/architecture.md, "A run
//! is data".

use serde::{Deserialize, Serialize};

use crate::control::spec::{ControllerSpec, ThrusterLimitsSpec};
use crate::error::{Result, SpacearmError};
use crate::math::integrate::IntegratorKind;
use crate::model::Model;
use crate::scenario::actuators::ThrusterLimits;
use crate::scenario::modes::Mode;
use crate::scenario::orbit::Orbit;
use crate::sim::contact::ContactSpec;
use crate::sim::stop::StopCondition;

/// The options that a run's description ([`RunSpec`], data) and its checked options
/// ([`SimOptions`]) share, the same as data and checked: declared once, in the invocation below,
/// with their doc, type and default. The macro writes both structs (each with its own fields
/// after the shared ones), their `Default`s, and `RunSpec::shared_options`, which carries the
/// shared fields over; a run option of this kind is added there and nowhere else (its check
/// goes to [`SimOptions::validate`]).
macro_rules! run_options {
    ($( $(#[doc = $doc:expr])* $field:ident : $ty:ty = $default:expr, )+) => {
        /// Options of a simulation.
        #[derive(Debug, Clone, PartialEq)]
        pub struct SimOptions {
            $( $(#[doc = $doc])* pub $field: $ty, )+
            /// Simulated time, s (> 0).
            pub duration: f64,
            /// Thruster limits (flying modes); `None`: unlimited.
            pub thrusters: Option<ThrusterLimits>,
            /// The orbit of the run ([`OrbitOptions`]); `None`: empty, inertial space.
            pub orbit: Option<OrbitOptions>,
        }

        impl Default for SimOptions {
            fn default() -> Self {
                SimOptions { $( $field: $default, )+ duration: 1.0, thrusters: None, orbit: None }
            }
        }

        /// A run's description as data: every option of [`SimOptions`] but the duration (an
        /// argument of each entry point), with the controller. Every field may be left out (the
        /// defaults are [`SimOptions::default`]'s); an unknown one is refused. The names are
        /// those of the Python `spacearm.simulate` keywords and of the C stepper's options TOML
        /// (docs/c-api.md):
        ///
        /// ```toml
        /// mode = "flying"          # Mode::NAMES
        /// integrator = "rk4"       # IntegratorKind::NAMES
        /// dt = 1e-3
        /// thrusters = { max_force = 10.0, max_torque = [1.0, 1.0, 2.0] }
        /// [controller]             # a ControllerSpec (control/spec.rs)
        /// kind = "joint_pd"
        /// kp = 40.0
        /// kd = 12.0
        /// reference = [0.0, 0.5]
        /// ```
        ///
        /// [`RunSpec::options`] builds and checks the [`SimOptions`] of a run of a given
        /// duration (one validation: [`SimOptions::validate`]); the controller is built on the
        /// plant by the entry point ([`ControllerSpec::build`]).
        #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
        #[serde(default, deny_unknown_fields)]
        pub struct RunSpec {
            $( $(#[doc = $doc])* pub $field: $ty, )+
            /// Thruster limits (flying modes) as data; absent: unlimited.
            pub thrusters: Option<ThrusterLimitsSpec>,
            /// The orbit of the run's origin and whether its tidal wrenches act (the keys `orbit`
            /// and `gravity_gradient`).
            #[serde(flatten)]
            pub in_orbit: RunOrbit,
            /// The control law; absent: zero torques.
            pub controller: Option<ControllerSpec>,
            /// A free target in the loop of contact (docs/contact.md, "Contact with a free
            /// target"): the path of its model's TOML file (docs/model-format.md; relative: to the
            /// folder of the options file, [`RunSpec::free_target`]). Read by the C stepper and
            /// FMUs; the Python door takes the model itself (`simulate(target=...)`), so
            /// [`RunSpec::options`] refuses a target left in the description.
            #[serde(skip_serializing_if = "Option::is_none")]
            pub target: Option<String>,
            /// The target's 13-state `[r, quat xyzw, v, ω]` in 𝒥 (with `target`).
            #[serde(skip_serializing_if = "Option::is_none")]
            pub target_state: Option<Vec<f64>>,
        }

        impl Default for RunSpec {
            fn default() -> Self {
                RunSpec { $( $field: $default, )+ thrusters: None, in_orbit: RunOrbit::default(), controller: None, target: None, target_state: None }
            }
        }

        impl RunSpec {
            /// The [`SimOptions`] of this description's shared fields with `duration`, the built
            /// `thrusters` and `orbit` (unchecked: [`RunSpec::options`] checks).
            fn shared_options(&self, duration: f64, thrusters: Option<ThrusterLimits>, orbit: Option<OrbitOptions>) -> SimOptions {
                SimOptions { $( $field: self.$field.clone(), )+ duration, thrusters, orbit }
            }
        }
    };
}

run_options! {
    /// Maneuvering mode ([`Mode::NAMES`]).
    mode: Mode = Mode::Floating,
    /// Integrator ([`IntegratorKind::NAMES`]).
    integrator: IntegratorKind = IntegratorKind::Rk4,
    /// RK4: the step; DOPRI5: the output (recording) interval. s, > 0.
    dt: f64 = 1e-3,
    /// DOPRI5 relative tolerance (> 0).
    rtol: f64 = 1e-9,
    /// DOPRI5 absolute tolerance (≥ 0).
    atol: f64 = 1e-12,
    /// RK4: keep every k-th step (≥ 1); the final state is always kept.
    record_every: usize = 1,
    /// Wheel degrees of freedom; `None`: those the model's structure shows
    /// ([`detect_reaction_wheels`](crate::scenario::actuators::detect_reaction_wheels)).
    wheels: Option<Vec<usize>> = None,
    /// Whether the joints' effort and velocity limits apply (they always do to nothing else).
    joint_limits: bool = true,
    /// DOPRI5: the largest number of attempted steps (accepted and rejected) before giving up.
    max_steps: usize = DEFAULT_MAX_STEPS,
    /// Conditions that stop the run before its duration, the first to hold wins
    /// ([`crate::sim::stop`], [`crate::sim::events`]; [`SimResult::stop`](crate::sim::result::SimResult::stop)
    /// says which and when); empty: none. Honoured by [`simulate`](crate::sim::simulate::simulate)
    /// (both integrators); the entry points that stack equal-length runs or step a plant refuse
    /// them ([`SimOptions::refuse_stop`]).
    stop: Vec<StopCondition> = Vec::new(),
    /// Compliant contact between the system's bodies ([`crate::sim::contact`], [`ContactSpec`]);
    /// `None`: none.
    contact: Option<ContactSpec> = None,
}

/// A run in orbit (docs/orbit.md): the origin of 𝒥 is the orbit's point `O`, propagated on its
/// own (point mass, two-body + J2, [`OrbitTrack`](crate::scenario::orbit::OrbitTrack)), with 𝒥's axes those of ECI; the states stay
/// relative to `O`. With `gravity_gradient`, every body feels the tidal force `mᵢ G ρᵢ` at its CM
/// (`ρᵢ` its CM from `O`) and the torque `axial(Iᵢ G − G Iᵢ)` about it, `G` the gradient at `O`
/// ([`crate::scenario::orbit`]); the uniform part of gravity moves `O` and with it everything. The
/// conserved quantities of the mode are then monitored as balances: the change of each equals
/// the integral of the tidal wrenches (trapezoid over the samples), the energy is dropped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitOptions {
    /// The orbit of `O` (at `t = 0`).
    pub orbit: Orbit,
    /// Whether the tidal wrenches act on the bodies.
    pub gravity_gradient: bool,
}

/// The default step budget of a DOPRI5 run ([`SimOptions::max_steps`], accepted and rejected
/// steps): spent, the run stops with a `SimulationError` naming the time reached and the
/// budget. About two minutes of spatial6 (a run of 10⁶ s at rtol 1e-12 reaches t = 1.2·10⁴ s).
pub const DEFAULT_MAX_STEPS: usize = 10_000_000;

impl SimOptions {
    /// Check every value (positive duration and step, tolerances, counts).
    pub fn validate(&self) -> Result<()> {
        let arg = |msg: String| Err(SpacearmError::argument(msg));
        if !(self.duration.is_finite() && self.duration > 0.0) {
            return arg(format!("duration must be finite and > 0 s, got {}", self.duration));
        }
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return arg(format!("dt must be finite and > 0 s, got {}", self.dt));
        }
        if self.duration / self.dt > 1e9 {
            return arg(format!("duration / dt = {:e} steps or samples is more than the 1e9 allowed", self.duration / self.dt));
        }
        if !(self.rtol.is_finite() && self.rtol > 0.0) {
            return arg(format!("rtol must be finite and > 0, got {}", self.rtol));
        }
        if !(self.atol.is_finite() && self.atol >= 0.0) {
            return arg(format!("atol must be finite and >= 0, got {}", self.atol));
        }
        if self.record_every == 0 {
            return arg(format!("record_every must be an integer >= 1, got {}", self.record_every));
        }
        if self.max_steps == 0 {
            return arg(format!("max_steps must be an integer >= 1, got {}", self.max_steps));
        }
        crate::sim::stop::validate(&self.stop)?;
        if let Some(c) = &self.contact {
            c.validate()?;
            if c.kind == crate::sim::contact::ContactKind::Rigid {
                if self.integrator != IntegratorKind::Rk4 {
                    return arg(format!(
                        "rigid contact (kind=\"rigid\") is a time-stepping scheme of fixed steps dt: it runs with integrator=\"rk4\", not \"{}\" \
                         (an adaptive step cannot take the velocity jumps of the impacts)",
                        self.integrator.name()
                    ));
                }
                if self.stop.iter().any(|s| !matches!(s, StopCondition::Time { .. })) {
                    return arg(
                        "rigid contact (kind=\"rigid\") takes time stop conditions only: a gap or record condition is located inside a step, which \
                         the velocity jumps of the rigid contact's steps do not allow yet"
                            .to_string(),
                    );
                }
            }
        }
        Ok(())
    }

    /// Refuse contact where `entry` (a run whose state is not one plant's) cannot honour it.
    pub fn refuse_contact(&self, entry: &str) -> Result<()> {
        if self.contact.is_none() {
            return Ok(());
        }
        Err(SpacearmError::argument(format!("{entry} does not take contact yet (docs/contact.md, \"What is not handled\"): use simulate for a run with contact=")))
    }

    /// Refuse stop conditions where `entry` (a run that is not [`simulate`](crate::sim::simulate::simulate)'s) cannot honour them.
    pub fn refuse_stop(&self, entry: &str) -> Result<()> {
        if self.stop.is_empty() {
            return Ok(());
        }
        Err(SpacearmError::argument(format!(
            "{entry} does not take stop conditions (a run that stops early has its own length): use simulate for a run with stop="
        )))
    }
}

/// The orbit of a run as data (docs/orbit.md), the part of a run's description that
/// [`RunSpec`] and a capture's ([`crate::sim::capture_spec::CaptureSpec`]) share (flattened into
/// each: the keys `orbit` and `gravity_gradient`), with its one check ([`RunOrbit::options`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct RunOrbit {
    /// The orbit of the run's origin (the states are relative to its point at time 0, ECI
    /// axes); absent: empty space.
    pub orbit: Option<Orbit>,
    /// In orbit: whether the tidal wrenches act (absent: yes); `true` without an orbit is refused.
    pub gravity_gradient: Option<bool>,
}

impl RunOrbit {
    /// The checked orbit options (`None`: empty space). Data from a file is checked as
    /// `Orbit::from_state` checks a made orbit (a bound state).
    pub fn options(&self) -> Result<Option<OrbitOptions>> {
        match (self.orbit, self.gravity_gradient) {
            (Some(o), gg) => Ok(Some(OrbitOptions { orbit: Orbit::from_state(o.body, o.r0, o.v0, o.j2)?, gravity_gradient: gg.unwrap_or(true) })),
            (None, Some(true)) => Err(SpacearmError::argument("gravity_gradient = true needs an orbit (orbit=spacearm.Orbit...)")),
            (None, _) => Ok(None),
        }
    }

    /// Whether the tidal wrenches act: in orbit, unless `gravity_gradient` is false.
    pub fn tidal(&self) -> bool {
        self.orbit.is_some() && self.gravity_gradient != Some(false)
    }
}

impl RunSpec {
    /// Take the free target out of this description (docs/contact.md, "Contact with a free
    /// target"): its model read from the TOML file `target` (a relative path joined to `base`, the
    /// folder of the options file, when given) and its 13-state; `None` without one. Both keys
    /// or neither; a URDF file is refused (the core reads model TOML; Python's `spacearm.io`
    /// converts URDF).
    pub fn free_target(&mut self, base: Option<&std::path::Path>) -> Result<Option<(Model, Vec<f64>)>> {
        let (path, state) = match (self.target.take(), self.target_state.take()) {
            (None, None) => return Ok(None),
            (Some(p), Some(s)) => (p, s),
            _ => return Err(SpacearmError::argument("target and target_state go together: give both (a model TOML file and its 13-state) or neither")),
        };
        crate::error::check_vector("target_state", &state, 13)
            .map_err(|e| SpacearmError::argument(format!("target_state: the target's 13-state [r, quat xyzw, v, w] ({e})")))?;
        let file = std::path::Path::new(&path);
        if file.extension().is_some_and(|e| e.eq_ignore_ascii_case("urdf")) {
            return Err(SpacearmError::argument(format!(
                "target = \"{path}\": a URDF target is not read here; write it as a model TOML (spacearm.io.save_toml of spacearm.io.load_urdf) and name that file"
            )));
        }
        let full = match base {
            Some(b) if file.is_relative() => b.join(file),
            _ => file.to_path_buf(),
        };
        let model = crate::io::toml::model_from_toml_file(&full)?;
        Ok(Some((model, state)))
    }

    /// The checked options of a run of `duration` seconds ([`SimOptions::validate`], the thruster
    /// limits', the controller spec's own checks that need no plant).
    pub fn options(&self, duration: f64) -> Result<SimOptions> {
        if self.target.is_some() || self.target_state.is_some() {
            return Err(SpacearmError::argument(
                "a free target (target, target_state) in the run's options is read by the C stepper and FMUs from an options TOML; \
                 in Python give the model itself: simulate(..., contact=, target=, target_state=) (docs/contact.md)",
            ));
        }
        let orbit = self.in_orbit.options()?;
        let thrusters = self.thrusters.as_ref().map(ThrusterLimitsSpec::build).transpose()?;
        let options = self.shared_options(duration, thrusters, orbit);
        options.validate()?;
        if let Some(c) = &self.controller {
            c.validate()?;
        }
        Ok(options)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_empty_description_is_the_default_run_and_every_field_has_a_name() {
        let spec: RunSpec = toml::from_str("").unwrap();
        assert_eq!(spec, RunSpec::default());
        assert_eq!(spec.options(2.0).unwrap(), SimOptions { duration: 2.0, ..SimOptions::default() });
        let text = "mode = \"flying\"\nintegrator = \"dopri5\"\ndt = 0.002\nrtol = 1e-10\natol = 0.0\nrecord_every = 3\n\
                    wheels = [6]\njoint_limits = false\nmax_steps = 7\nthrusters = { max_force = 2.0 }\n\
                    stop = [{ kind = \"time\", t = 0.5 }]\n[controller]\nkind = \"none\"\n";
        let spec: RunSpec = toml::from_str(text).unwrap();
        let o = spec.options(1.0).unwrap();
        assert_eq!((o.mode, o.integrator, o.dt, o.rtol, o.atol, o.record_every), (Mode::Flying, IntegratorKind::Dopri5, 0.002, 1e-10, 0.0, 3));
        assert_eq!((o.wheels, o.joint_limits, o.max_steps, o.stop.len()), (Some(vec![6]), false, 7, 1));
        assert_eq!(o.thrusters.unwrap().max_force.x, 2.0);
        assert!(o.thrusters.unwrap().max_torque.z.is_infinite());
        // Written and read back, the description is the same.
        let back: RunSpec = toml::from_str(&toml::to_string(&spec).unwrap()).unwrap();
        assert_eq!(back, spec);
    }

    /// The orbit keys are top-level keys of a run's and of a capture's description (one
    /// [`RunOrbit`] flattened into each), checked by the one rule.
    #[test]
    fn the_orbit_keys_are_flat_and_checked_once_for_runs_and_captures() {
        use crate::scenario::orbit::EARTH;
        use crate::sim::capture_spec::CaptureSpec;
        let orbit = Orbit::circular(EARTH, 500e3, 0.3, 0.0, 0.0, false).unwrap();
        let spec = RunSpec { in_orbit: RunOrbit { orbit: Some(orbit), gravity_gradient: Some(false) }, ..RunSpec::default() };
        let text = toml::to_string(&spec).unwrap();
        assert!(text.contains("gravity_gradient = false") && text.contains("[orbit]"), "{text}");
        assert_eq!(toml::from_str::<RunSpec>(&text).unwrap(), spec);
        let o = spec.options(1.0).unwrap().orbit.unwrap();
        assert_eq!((o.orbit, o.gravity_gradient), (orbit, false));
        assert!(!spec.in_orbit.tidal() && RunOrbit { orbit: Some(orbit), gravity_gradient: None }.tidal());
        let target = "target_state = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.2]\n";
        let capture: CaptureSpec = toml::from_str(&format!("{target}{}", toml::to_string(&spec.in_orbit).unwrap())).unwrap();
        assert_eq!(capture.in_orbit, spec.in_orbit);
        let capture: CaptureSpec = toml::from_str(&format!("{target}gravity_gradient = true")).unwrap();
        assert!(capture.validate().unwrap_err().to_string().contains("gravity_gradient = true needs an orbit"));
        let err = toml::from_str::<CaptureSpec>(&format!("{target}orbitt = 1.0")).unwrap_err().to_string();
        assert!(err.contains("unknown field `orbitt`"), "{err}");
    }

    #[test]
    fn names_values_and_keys_are_checked_with_the_cores_messages() {
        let err = |text: &str| toml::from_str::<RunSpec>(text).unwrap_err().to_string();
        assert!(err("mode = \"drifting\"").contains("mode"), "{}", err("mode = \"drifting\""));
        assert!(err("integrator = \"euler\"").contains("integrator"));
        assert!(err("dtt = 1.0").contains("unknown field `dtt`"));
        let spec: RunSpec = toml::from_str("dt = -1.0").unwrap();
        assert!(spec.options(1.0).unwrap_err().to_string().contains("dt must be finite and > 0"));
        let spec: RunSpec = toml::from_str("target_state = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]").unwrap();
        assert!(spec.options(1.0).unwrap_err().to_string().contains("in Python give the model itself"));
        assert!(spec.clone().free_target(None).unwrap_err().to_string().contains("target and target_state go together"));
        let mut spec: RunSpec = toml::from_str("target = \"rock.urdf\"\ntarget_state = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]").unwrap();
        assert!(spec.free_target(None).unwrap_err().to_string().contains("a URDF target is not read here"));
        let mut spec: RunSpec = toml::from_str("target = \"rock.toml\"\ntarget_state = [0.0, 1.0]").unwrap();
        assert!(spec.free_target(None).unwrap_err().to_string().contains("13-state"));
        // a relative path is read from the options file's folder
        let dir = std::env::temp_dir().join(format!("spacearm_target_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let rock = crate::model::ModelBuilder::new("rock", "rock", 2.0, [[0.1, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 0.1]]).unwrap().build().unwrap();
        std::fs::write(dir.join("rock.toml"), crate::io::toml::model_to_toml(&rock)).unwrap();
        let mut spec: RunSpec = toml::from_str("target = \"rock.toml\"\ntarget_state = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]").unwrap();
        let (m, s) = spec.free_target(Some(&dir)).unwrap().unwrap();
        assert_eq!((m.name(), m.total_mass(), s.len()), ("rock", 2.0, 13));
        assert!(spec.target.is_none() && spec.options(1.0).is_ok());
        assert!(toml::from_str::<RunSpec>("target = \"rock.toml\"\ntarget_state = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]").unwrap().free_target(None).is_err());
        std::fs::remove_dir_all(&dir).ok();
        let spec: RunSpec = toml::from_str("gravity_gradient = true").unwrap();
        assert!(spec.options(1.0).unwrap_err().to_string().contains("needs an orbit"));
        let spec: RunSpec = toml::from_str("thrusters = { max_force = 0.0 }").unwrap();
        assert!(spec.options(1.0).is_err());
        let spec: RunSpec = toml::from_str("[controller]\nkind = \"joint_pd\"\nkp = -1.0\nkd = 1.0\nreference = [0.0]").unwrap();
        assert!(spec.options(1.0).is_err());
    }
}
