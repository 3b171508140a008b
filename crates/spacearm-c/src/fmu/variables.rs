//! The variables of a spacearm FMU and its model description (docs/fmi.md, "Variables"): the one
//! table that both the `modelDescription.xml` that `spacearm.fmi.export` writes and the FMU's
//! binary read, so the two cannot disagree.
//!
//! Every variable is a Float64 (FMI 3) / Real (FMI 2) scalar; its value reference is its index
//! in the table. In order: `time`; the outputs `r0[1..3]`, `quat0[1..4]` (x, y, z, w), `q[1..N]`,
//! `v0[1..3]`, `w0[1..3]`, `qd[1..N]` (the state `x`, `u` of docs/conventions.md), `P[1..3]`
//! (linear momentum), `L[1..3]` (angular momentum about the origin of 𝒥), and, if the model has
//! an end effector, `ee_position[1..3]` and `ee_quat[1..4]`; the inputs `tau[1..N]` and, in the
//! flying modes, `base_wrench[1..6]` (`[F0, N0]` in 𝒥 at the base CM); the parameters
//! `x0[1..7+N]`, `u0[1..6+N]` and the controller's numbers ([`super::parameters`]: e.g. `kp[k]`,
//! `kd[k]`, `reference[k]` of a joint PD, `quat_ref[1..4]`, `kp`, `kd` of an attitude law).

use std::fmt::Write;
use std::ops::Range;

use spacearm_core::model::joint::JointType;
use spacearm_core::Model;

use super::parameters::ControllerParameters;
use crate::status::Outcome;
use crate::stepper::StepperOptions;

/// What a variable is to the importer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Causality {
    Independent,
    Output,
    Input,
    Parameter,
}

#[derive(Debug, Clone)]
pub(crate) struct Variable {
    pub name: String,
    pub causality: Causality,
    pub description: String,
    pub start: f64,
    /// The unit, a name of [`UNITS`] (`None`: dimensionless or not known, as the controller's
    /// parameters).
    pub unit: Option<&'static str>,
}

/// The units the variables use, with their SI base-unit exponents as FMI writes them
/// (`<BaseUnit kg="1" m="2" s="-2"/>`).
pub(crate) const UNITS: &[(&str, &str)] = &[
    ("s", r#"s="1""#),
    ("m", r#"m="1""#),
    ("rad", r#"rad="1""#),
    ("m/s", r#"m="1" s="-1""#),
    ("rad/s", r#"s="-1" rad="1""#),
    ("N", r#"kg="1" m="1" s="-2""#),
    ("N.m", r#"kg="1" m="2" s="-2""#),
    ("N.s", r#"kg="1" m="1" s="-1""#),
    ("N.m.s", r#"kg="1" m="2" s="-1""#),
];

/// The unit of a joint coordinate, rate and effort for each dof: rad, rad/s, N·m for a revolute
/// joint; m, m/s, N for a prismatic one.
fn joint_units(model: &Model) -> Vec<[&'static str; 3]> {
    (0..model.n_dof())
        .map(|d| match model.links()[model.body_of_dof(d) - 1].joint.kind {
            JointType::Prismatic => ["m", "m/s", "N"],
            _ => ["rad", "rad/s", "N.m"],
        })
        .collect()
}

/// The table, with the value-reference range of each group.
#[derive(Debug, Clone)]
pub(crate) struct Layout {
    pub vars: Vec<Variable>,
    pub x: Range<usize>,
    pub u: Range<usize>,
    pub momentum: Range<usize>,
    pub ee_position: Option<Range<usize>>,
    pub ee_quat: Option<Range<usize>>,
    pub tau: Range<usize>,
    pub base_wrench: Option<Range<usize>>,
    pub x0: Range<usize>,
    pub u0: Range<usize>,
    /// The controller's parameters, in the order of [`ControllerParameters::list`].
    pub controller: Range<usize>,
    pub parameters: ControllerParameters,
}

struct Table(Vec<Variable>);

impl Table {
    /// Add `starts.len()` variables `group[k]` (1-based) with the units `units` in order (`""`
    /// or none left: no unit), returning their range.
    fn group(&mut self, group: &str, causality: Causality, what: &str, starts: &[f64], units: &[&'static str]) -> Range<usize> {
        let first = self.0.len();
        for (k, &start) in starts.iter().enumerate() {
            let unit = units.get(k).copied().filter(|u| !u.is_empty());
            self.0.push(Variable { name: format!("{group}[{}]", k + 1), causality, description: format!("{what}, entry {}", k + 1), start, unit });
        }
        first..self.0.len()
    }
}

impl Layout {
    pub(crate) fn new(model: &Model, options: &StepperOptions) -> Outcome<Layout> {
        let n = model.n_dof();
        let mut t = Table(vec![Variable { name: "time".into(), causality: Causality::Independent, description: "simulation time, s".into(), start: 0.0, unit: Some("s") }]);
        let joints = joint_units(model);
        let q_units: Vec<&str> = joints.iter().map(|j| j[0]).collect();
        let qd_units: Vec<&str> = joints.iter().map(|j| j[1]).collect();
        let tau_units: Vec<&str> = joints.iter().map(|j| j[2]).collect();
        let x_units: Vec<&str> = ["m", "m", "m", "", "", "", ""].into_iter().chain(q_units.iter().copied()).collect();
        let u_units: Vec<&str> = ["m/s", "m/s", "m/s", "rad/s", "rad/s", "rad/s"].into_iter().chain(qd_units.iter().copied()).collect();
        let out = Causality::Output;
        let zeros = |k: usize| vec![0.0; k];
        let r0 = t.group("r0", out, "base CM position in the inertial frame, m", &zeros(3), &x_units[..3]);
        let _quat0 = t.group("quat0", out, "base attitude quaternion [x, y, z, w] (base to inertial)", &zeros(4), &x_units[3..7]);
        let _q = t.group("q", out, "joint coordinate, rad or m", &zeros(n), &x_units[7..]);
        let x = r0.start.._q.end;
        let v0 = t.group("v0", out, "base CM velocity in the inertial frame, m/s", &zeros(3), &u_units[..3]);
        let _w0 = t.group("w0", out, "base angular velocity in the inertial frame, rad/s", &zeros(3), &u_units[3..6]);
        let qd = t.group("qd", out, "joint rate, rad/s or m/s", &zeros(n), &u_units[6..]);
        let u = v0.start..qd.end;
        let p = t.group("P", out, "linear momentum in the inertial frame, N s", &zeros(3), &["N.s"; 3]);
        let l = t.group("L", out, "angular momentum about the inertial origin, N m s", &zeros(3), &["N.m.s"; 3]);
        let momentum = p.start..l.end;
        let (ee_position, ee_quat) = match model.end_effector() {
            Some(_) => (
                Some(t.group("ee_position", out, "end-effector position in the inertial frame, m", &zeros(3), &["m"; 3])),
                Some(t.group("ee_quat", out, "end-effector body attitude [x, y, z, w], sign kept continuous", &zeros(4), &[])),
            ),
            None => (None, None),
        };
        let tau = t.group("tau", Causality::Input, "joint torque (force) added to the controller's, N m or N", &zeros(n), &tau_units);
        let mode = options.sim.mode;
        let base_wrench = (mode.allows_force() || mode.allows_torque()).then(|| {
            let what = "base wrench [F0, N0] in the inertial frame at the base CM (as the mode allows), N and N m";
            t.group("base_wrench", Causality::Input, what, &zeros(6), &["N", "N", "N", "N.m", "N.m", "N.m"])
        });
        let x0_start = spacearm_core::model::presets::initial_configuration(model);
        let x0 = t.group("x0", Causality::Parameter, "initial configuration [r0, quat0 (x, y, z, w), q]", &x0_start, &x_units);
        let u0 = t.group("u0", Causality::Parameter, "initial velocity [v0, w0, qd]", &zeros(6 + n), &u_units);
        let parameters = ControllerParameters::new(&options.controller)?;
        let first = t.0.len();
        for p in &parameters.list {
            t.0.push(Variable { name: p.name.clone(), causality: Causality::Parameter, description: p.description.clone(), start: p.start, unit: None });
        }
        let controller = first..t.0.len();
        let mut seen = std::collections::HashSet::new();
        if let Some(v) = t.0.iter().find(|v| !seen.insert(v.name.as_str())) {
            return Err(crate::status::Failure::new(crate::status::SpacearmStatus::Internal, format!("two FMU variables are named '{}'", v.name)));
        }
        Ok(Layout { vars: t.0, x, u, momentum, ee_position, ee_quat, tau, base_wrench, x0, u0, controller, parameters })
    }
}

/// Which FMI version a description is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum FmiVersion {
    Fmi2,
    Fmi3,
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// A number as XML text: the shortest form that reads back to the same double.
fn num(v: f64) -> String {
    format!("{v:?}")
}

/// The `<UnitDefinitions>` of the units `layout` uses (FMI 3 and FMI 2 write them alike).
fn unit_definitions(s: &mut String, layout: &Layout) {
    let used: Vec<&(&str, &str)> = UNITS.iter().filter(|(name, _)| layout.vars.iter().any(|v| v.unit == Some(*name))).collect();
    if used.is_empty() {
        return;
    }
    let _ = writeln!(s, "  <UnitDefinitions>");
    for (name, base) in used {
        let _ = writeln!(s, r#"    <Unit name="{name}"><BaseUnit {base}/></Unit>"#);
    }
    let _ = writeln!(s, "  </UnitDefinitions>");
}

/// The `modelDescription.xml` of a co-simulation FMU of `model` with `options`.
pub(crate) fn model_description(model: &Model, options: &StepperOptions, version: FmiVersion, identifier: &str, token: &str, stop_time: f64) -> Outcome<String> {
    let layout = Layout::new(model, options)?;
    let mut s = String::new();
    let name = escape(model.name());
    let token = escape(token);
    let tool = format!("spacearm {}", env!("CARGO_PKG_VERSION"));
    let dt = num(options.sim.dt);
    let descr = escape(&format!(
        "spacearm model '{}' ({} joints), mode {}, controller {}, RK4 at {} s",
        model.name(),
        model.n_dof(),
        options.sim.mode.name(),
        options.controller.kind(),
        options.sim.dt
    ));
    let id = escape(identifier);
    let outputs: Vec<usize> = (0..layout.vars.len()).filter(|&i| layout.vars[i].causality == Causality::Output).collect();
    let _ = writeln!(s, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    match version {
        FmiVersion::Fmi3 => {
            let _ = writeln!(
                s,
                r#"<fmiModelDescription fmiVersion="3.0" modelName="{name}" description="{descr}" instantiationToken="{token}" generationTool="{tool}" variableNamingConvention="flat">"#
            );
            let _ = writeln!(s, r#"  <CoSimulation modelIdentifier="{id}" canHandleVariableCommunicationStepSize="true" fixedInternalStepSize="{dt}" canGetAndSetFMUState="false" canSerializeFMUState="false" providesIntermediateUpdate="false" hasEventMode="false"/>"#);
        }
        FmiVersion::Fmi2 => {
            let _ = writeln!(
                s,
                r#"<fmiModelDescription fmiVersion="2.0" modelName="{name}" description="{descr}" guid="{token}" generationTool="{tool}" variableNamingConvention="flat" numberOfEventIndicators="0">"#
            );
            let _ = writeln!(s, r#"  <CoSimulation modelIdentifier="{id}" canHandleVariableCommunicationStepSize="true" canGetAndSetFMUstate="false" canSerializeFMUstate="false" canNotUseMemoryManagementFunctions="true"/>"#);
        }
    }
    unit_definitions(&mut s, &layout);
    let _ = writeln!(s, r#"  <DefaultExperiment startTime="0.0" stopTime="{}" stepSize="{dt}"/>"#, num(stop_time));
    let _ = writeln!(s, "  <ModelVariables>");
    for (vr, v) in layout.vars.iter().enumerate() {
        let (n, d) = (escape(&v.name), escape(&v.description));
        let unit = v.unit.map(|u| format!(r#" unit="{u}""#)).unwrap_or_default();
        match version {
            FmiVersion::Fmi3 => {
                let attrs = match v.causality {
                    Causality::Independent => r#"causality="independent" variability="continuous""#.to_string(),
                    Causality::Output => r#"causality="output" variability="continuous""#.to_string(),
                    Causality::Input => format!(r#"causality="input" variability="continuous" start="{}""#, num(v.start)),
                    Causality::Parameter => format!(r#"causality="parameter" variability="fixed" start="{}""#, num(v.start)),
                };
                let _ = writeln!(s, r#"    <Float64 name="{n}" valueReference="{vr}" description="{d}" {attrs}{unit}/>"#);
            }
            FmiVersion::Fmi2 => {
                let (attrs, real) = match v.causality {
                    Causality::Independent => (r#"causality="independent" variability="continuous""#.to_string(), format!("<Real{unit}/>")),
                    Causality::Output => (r#"causality="output" variability="continuous" initial="calculated""#.to_string(), format!("<Real{unit}/>")),
                    Causality::Input => (r#"causality="input" variability="continuous""#.to_string(), format!(r#"<Real{unit} start="{}"/>"#, num(v.start))),
                    Causality::Parameter => (r#"causality="parameter" variability="fixed" initial="exact""#.to_string(), format!(r#"<Real{unit} start="{}"/>"#, num(v.start))),
                };
                let _ = writeln!(s, r#"    <ScalarVariable name="{n}" valueReference="{vr}" description="{d}" {attrs}>{real}</ScalarVariable>"#);
            }
        }
    }
    let _ = writeln!(s, "  </ModelVariables>");
    let _ = writeln!(s, "  <ModelStructure>");
    match version {
        FmiVersion::Fmi3 => {
            for tag in ["Output", "InitialUnknown"] {
                for &i in &outputs {
                    let _ = writeln!(s, r#"    <{tag} valueReference="{i}"/>"#);
                }
            }
        }
        FmiVersion::Fmi2 => {
            for tag in ["Outputs", "InitialUnknowns"] {
                let _ = writeln!(s, "    <{tag}>");
                for &i in &outputs {
                    let _ = writeln!(s, r#"      <Unknown index="{}"/>"#, i + 1);
                }
                let _ = writeln!(s, "    </{tag}>");
            }
        }
    }
    let _ = writeln!(s, "  </ModelStructure>");
    let _ = writeln!(s, "</fmiModelDescription>");
    Ok(s)
}
