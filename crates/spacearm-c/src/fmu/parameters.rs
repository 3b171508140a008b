//! The controller's parameters of an FMU (docs/fmi.md, "Controller parameters"): every finite
//! number of the options' `[controller]` table (the core's `ControllerSpec`, serialized) is a
//! Float64 / Real parameter named by its path in the table, its start value the number
//! exported; at the end of initialization the table with the parameters' values is read back
//! into a `ControllerSpec`, checked and built by the core as the stepper does.
//!
//! The table is written in its per-joint form first, so that each arm joint has its own
//! parameters: a constant joint reference is its list of set points (`reference[k]`, the spec's
//! own short form), and the gains `kp`, `kd` of `joint_pd` and `computed_torque` are given one
//! per arm joint (the core's `broadcast_gains` of the exported ones). Paths: keys joined by
//! `.`, list entries 1-based in brackets: `kp[2]`, `quat_ref[4]`, `reference.p_goal[1]`,
//! `arm.kp[1]` (a `combined` controller's arm law), `controller.kd[3]` (the law a
//! `torque_limit` clamps), `base_pose_ref[2][4]`. Integers (indices, task rows), strings
//! (names, models), booleans and infinities are not parameters: they keep their exported value.

use spacearm_core::control::broadcast_gains;
use spacearm_core::control::spec::{ControllerSpec, Gains};
use toml::Value;

use crate::status::{Failure, Outcome, SpacearmStatus};

/// One step of a path into the table.
#[derive(Debug, Clone, PartialEq)]
enum Step {
    Key(String),
    Index(usize),
}

/// One parameter: its name, its place in the table, its exported value and what it is.
#[derive(Debug, Clone)]
pub(crate) struct Parameter {
    pub name: String,
    path: Vec<Step>,
    pub start: f64,
    pub description: String,
}

/// The controller's table in its per-joint form and its parameters, in table order.
#[derive(Debug, Clone)]
pub(crate) struct ControllerParameters {
    table: Value,
    pub list: Vec<Parameter>,
}

fn internal(e: impl std::fmt::Display) -> Failure {
    Failure::new(SpacearmStatus::Internal, format!("the controller spec as a TOML table: {e}"))
}

/// `spec` with the gains of the joint-space laws one per arm joint (as many as the reference
/// has entries, which the controller's setup checks against the plant's arm joints).
fn per_joint(spec: &ControllerSpec) -> Outcome<ControllerSpec> {
    let widen = |g: &Gains, what: &str, n: usize| -> Outcome<Gains> { Ok(Gains(broadcast_gains(what, &g.0, n)?)) };
    Ok(match spec {
        ControllerSpec::JointPd { kp, kd, reference } => {
            let n = reference.build()?.len();
            ControllerSpec::JointPd { kp: widen(kp, "kp", n)?, kd: widen(kd, "kd", n)?, reference: reference.clone() }
        }
        ControllerSpec::ComputedTorque { kp, kd, reference, model, passive } => {
            let n = reference.build()?.len();
            ControllerSpec::ComputedTorque { kp: widen(kp, "kp", n)?, kd: widen(kd, "kd", n)?, reference: reference.clone(), model: model.clone(), passive: passive.clone() }
        }
        ControllerSpec::Combined { arm, base } => ControllerSpec::Combined { arm: Box::new(per_joint(arm)?), base: Box::new(per_joint(base)?) },
        ControllerSpec::TorqueLimit { controller, limit } => ControllerSpec::TorqueLimit { controller: Box::new(per_joint(controller)?), limit: *limit },
        other => other.clone(),
    })
}

/// Replace every constant joint reference `{kind = "constant", q = [...]}` by its list `[...]`
/// (the form `JointReferenceSpec` reads as a set point).
fn set_points_as_lists(v: &mut Value) {
    match v {
        Value::Table(t) => {
            let constant = t.len() == 2 && t.get("kind").and_then(Value::as_str) == Some("constant") && t.get("q").is_some_and(Value::is_array);
            if constant {
                let q = t.remove("q").unwrap_or(Value::Array(vec![]));
                *v = q;
                return;
            }
            for (_, child) in t.iter_mut() {
                set_points_as_lists(child);
            }
        }
        Value::Array(a) => a.iter_mut().for_each(set_points_as_lists),
        _ => {}
    }
}

fn path_name(path: &[Step]) -> String {
    let mut s = String::new();
    for step in path {
        match step {
            Step::Key(k) if s.is_empty() => s.push_str(k),
            Step::Key(k) => {
                s.push('.');
                s.push_str(k);
            }
            Step::Index(i) => s.push_str(&format!("[{}]", i + 1)),
        }
    }
    s
}

/// Collect the finite floats under `v` at `path`; `kind` is the kind of the innermost tagged
/// table (the law or reference the number belongs to).
fn collect(v: &Value, path: &mut Vec<Step>, kind: &str, out: &mut Vec<Parameter>) {
    match v {
        Value::Float(x) if x.is_finite() => {
            let name = path_name(path);
            let field = path.iter().rev().find_map(|s| match s {
                Step::Key(k) => Some(k.as_str()),
                Step::Index(_) => None,
            });
            out.push(Parameter { description: format!("controller parameter: {kind} '{}'", field.unwrap_or("")), name, path: path.clone(), start: *x });
        }
        Value::Table(t) => {
            let kind = t.get("kind").and_then(Value::as_str).unwrap_or(kind);
            for (k, child) in t {
                path.push(Step::Key(k.clone()));
                collect(child, path, kind, out);
                path.pop();
            }
        }
        Value::Array(a) => {
            for (i, child) in a.iter().enumerate() {
                path.push(Step::Index(i));
                collect(child, path, kind, out);
                path.pop();
            }
        }
        _ => {}
    }
}

fn leaf_mut<'a>(mut v: &'a mut Value, path: &[Step]) -> Option<&'a mut Value> {
    for step in path {
        v = match (step, v) {
            (Step::Key(k), Value::Table(t)) => t.get_mut(k)?,
            (Step::Index(i), Value::Array(a)) => a.get_mut(*i)?,
            _ => return None,
        };
    }
    Some(v)
}

impl ControllerParameters {
    /// The parameters of `spec` (checked already: the stepper options' parse).
    pub(crate) fn new(spec: &ControllerSpec) -> Outcome<Self> {
        let mut table = Value::try_from(per_joint(spec)?).map_err(internal)?;
        set_points_as_lists(&mut table);
        let mut list = Vec::new();
        collect(&table, &mut Vec::new(), spec.kind(), &mut list);
        Ok(ControllerParameters { table, list })
    }

    /// The spec with `values`, one per parameter in order (the values a parameter can hold are
    /// finite: the FMU's setters refuse others); not yet checked.
    pub(crate) fn spec(&self, values: &[f64]) -> Outcome<ControllerSpec> {
        let mut table = self.table.clone();
        for (p, &v) in self.list.iter().zip(values) {
            *leaf_mut(&mut table, &p.path).ok_or_else(|| internal(format!("no entry at '{}'", p.name)))? = Value::Float(v);
        }
        table.try_into().map_err(|e| Failure::new(SpacearmStatus::Parse, format!("the controller's parameters: {e}")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(text: &str) -> ControllerSpec {
        toml::from_str(text).unwrap()
    }

    fn names(p: &ControllerParameters) -> Vec<&str> {
        p.list.iter().map(|p| p.name.as_str()).collect()
    }

    #[test]
    fn a_joint_law_has_its_gains_and_set_point_per_joint() {
        let s = spec("kind = 'joint_pd'\nkp = 3\nkd = [1.0, 2.0]\nreference = [0.1, 0.2]");
        let p = ControllerParameters::new(&s).unwrap();
        let mut n = names(&p);
        n.sort();
        assert_eq!(n, ["kd[1]", "kd[2]", "kp[1]", "kp[2]", "reference[1]", "reference[2]"]);
        let start = |name: &str| p.list.iter().find(|q| q.name == name).unwrap().start;
        let starts: Vec<f64> = ["kp[1]", "kp[2]", "kd[1]", "kd[2]", "reference[1]", "reference[2]"].iter().map(|k| start(k)).collect();
        assert_eq!(starts, [3.0, 3.0, 1.0, 2.0, 0.1, 0.2]);
        // The exported values give back the spec (gains widened); new values land in place.
        let values: Vec<f64> = p.list.iter().map(|q| q.start).collect();
        assert_eq!(p.spec(&values).unwrap(), spec("kind = 'joint_pd'\nkp = [3.0, 3.0]\nkd = [1.0, 2.0]\nreference = [0.1, 0.2]"));
        let moved: Vec<f64> = p.list.iter().map(|q| match q.name.as_str() {
            "kp[2]" => 4.0,
            "reference[1]" => 0.5,
            "reference[2]" => -0.5,
            _ => q.start,
        }).collect();
        assert_eq!(p.spec(&moved).unwrap(), spec("kind = 'joint_pd'\nkp = [3.0, 4.0]\nkd = [1.0, 2.0]\nreference = [0.5, -0.5]"));
    }

    #[test]
    fn nested_laws_and_references_are_named_by_their_path() {
        let s = spec(
            "kind = 'combined'\n[arm]\nkind = 'resolved_motion_rate'\ngain = 1.0\nreference = {kind = 'line', p_start = [1.0, 0.0, 0.0], p_goal = [1.2, 0.1, 0.0], t_start = 0.0, t_end = 1.0}\n\
             [base]\nkind = 'attitude'\nquat_ref = [0.0, 0.0, 0.0, 1.0]\nkp = 5.0\nkd = 2.0\n",
        );
        let p = ControllerParameters::new(&s).unwrap();
        let n = names(&p);
        for want in ["arm.reference.p_goal[2]", "arm.reference.t_end", "arm.gain", "arm.velocity_gain", "base.quat_ref[4]", "base.kp", "base.kd"] {
            assert!(n.contains(&want), "{want} not in {n:?}");
        }
        // max_joint_rate is inf (no cap): not a parameter.
        assert!(!n.iter().any(|k| k.contains("max_joint_rate")), "{n:?}");
        let i = n.iter().position(|k| *k == "base.kp").unwrap();
        assert_eq!(p.list[i].description, "controller parameter: attitude 'kp'");
        let mut v: Vec<f64> = p.list.iter().map(|p| p.start).collect();
        v[i] = 7.5;
        match p.spec(&v).unwrap() {
            ControllerSpec::Combined { base, .. } => assert!(matches!(*base, ControllerSpec::Attitude { kp, .. } if kp == 7.5)),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_law_without_numbers_has_no_parameters() {
        assert!(ControllerParameters::new(&ControllerSpec::None {}).unwrap().list.is_empty());
    }

    #[test]
    fn the_exported_values_give_back_every_kind_of_spec() {
        let specs = [
            "kind = 'none'",
            "kind = 'joint_pd'\nkp = [1.0, 2.0]\nkd = [0.5, 0.5]\nreference = {kind = 'quintic', q_start = [0.0, 0.1], q_goal = [0.2, 0.3], t_start = 0.5, t_end = 1.5}",
            "kind = 'computed_torque'\nkp = [4.0]\nkd = [4.0]\npassive = 'frozen'\nreference = {kind = 'shaped', reference = {kind = 'quintic', q_start = [0.0], q_goal = [1.0], t_start = 0.0, t_end = 1.0}, shaper = {kind = 'zvd', frequency = 3.0, damping = 0.05}}",
            "kind = 'joint_pd'\nkp = [1.0]\nkd = [1.0]\nreference = {kind = 'sampled', t = [0.0, 1.0], q = [[0.0, 0.0], [1.0, 2.0]], qd = [[0.0, 0.0], [0.0, 0.0]], qdd = [[0.0, 0.0], [0.0, 0.0]]}",
            "kind = 'resolved_motion_rate'\ngain = 2.0\npoint = ['link2', [0.1, 0.0, 0.0]]\ntask = [0, 1, 5]\nstrategy = 'reactionless'\nmax_joint_rate = 2.0\nreference = {kind = 'free_body', inertia = [1.0, 2.0, 3.0], state = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.1], offset = [0.1, 0.0, 0.0]}",
            "kind = 'base_thrusters'\ncom_ref = [0.1, 0.2, 0.3]\nkp_attitude = 3.0",
            "kind = 'coordinated_flying'\nbase_pose_ref = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]]\nee_reference = {kind = 'line', p_start = [1.0, 0.0, 0.0], p_goal = [1.1, 0.0, 0.0], t_start = 0.0, t_end = 2.0, point = 'end_effector'}",
            "kind = 'momentum_damping'\ntime_constant = 2.0\nmax_force = 5.0",
            "kind = 'torque_limit'\nlimit = 3.0\ncontroller = {kind = 'joint_pd', kp = 2.0, kd = 1.0, reference = [0.1, 0.2, 0.3]}",
        ];
        for text in specs {
            let s = spec(text);
            let p = ControllerParameters::new(&s).unwrap();
            let values: Vec<f64> = p.list.iter().map(|q| q.start).collect();
            let back = p.spec(&values).unwrap();
            assert_eq!(back, per_joint(&s).unwrap(), "{text}");
            assert!(p.list.iter().all(|q| q.start.is_finite()));
        }
        // The tuple of a base pose and a body point's offset are nested lists.
        let p = ControllerParameters::new(&spec(specs[6])).unwrap();
        assert!(names(&p).contains(&"base_pose_ref[2][4]"), "{:?}", names(&p));
        let p = ControllerParameters::new(&spec(specs[4])).unwrap();
        assert!(names(&p).contains(&"point[2][1]") && names(&p).contains(&"reference.state[13]"), "{:?}", names(&p));
        assert!(!names(&p).iter().any(|n| n.starts_with("task")), "{:?}", names(&p));
    }
}
