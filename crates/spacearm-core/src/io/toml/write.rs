//! Writing a [`Model`] as a TOML model file ([`model_to_toml`]): the text the reader reads back
//! to the same model.

use std::fmt::Write as _;

use nalgebra::Matrix3;

use crate::model::joint::{JointDynamics, JointLimits};
use crate::model::{Model, Shape};

use super::schema::FORMAT_VERSION;

/// A float as TOML: Rust's shortest round-trip representation (`1.0`, `0.1`, `1e-7`, `inf`).
fn num(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else {
        format!("{x:?}")
    }
}

pub(super) fn vec_str(v: &[f64]) -> String {
    let items: Vec<String> = v.iter().map(|&x| num(x)).collect();
    format!("[{}]", items.join(", "))
}

/// A TOML basic string.
fn string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            c if (c as u32) < 0x20 || c as u32 == 0x7f => {
                let _ = write!(out, "\\u{:04X}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn inertia_str(m: &Matrix3<f64>) -> String {
    if m[(0, 1)] == 0.0 && m[(0, 2)] == 0.0 && m[(1, 2)] == 0.0 && m[(1, 0)] == 0.0 && m[(2, 0)] == 0.0 && m[(2, 1)] == 0.0 {
        vec_str(&[m[(0, 0)], m[(1, 1)], m[(2, 2)]])
    } else {
        let rows: Vec<String> = (0..3).map(|i| vec_str(&[m[(i, 0)], m[(i, 1)], m[(i, 2)]])).collect();
        format!("[{}]", rows.join(", "))
    }
}

/// Write a model as a TOML model file (format [`FORMAT_VERSION`]). Reading the text back with
/// [`model_from_toml_str`](super::read::model_from_toml_str) gives a model equal to `model` (every number is written in its
/// shortest exact form).
pub fn model_to_toml(model: &Model) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# spacearm model file. Schema: docs/model-format.md");
    let _ = writeln!(s, "# SI units (m, kg, kg·m², rad). Every body frame has its origin at the body's centre of mass;");
    let _ = writeln!(s, "# a joint's origin is given in its parent's frame, com/axis/inertia in the link's own frame.");
    let _ = writeln!(s, "\n[model]");
    let _ = writeln!(s, "name = {}", string(model.name()));
    let _ = writeln!(s, "format_version = {FORMAT_VERSION}");
    if let Some(e) = model.end_effector() {
        let _ = writeln!(s, "end_effector = {}", string(&model.points()[e].name));
    }
    let _ = writeln!(s, "initial_q = {}", vec_str(model.initial_q()));
    let _ = writeln!(s, "\n[base]");
    let _ = writeln!(s, "name = {}", string(model.base_name()));
    let _ = writeln!(s, "mass = {}", num(model.base().mass));
    let _ = writeln!(s, "inertia = {}", inertia_str(&model.base().inertia));
    for l in model.links() {
        let j = &l.joint;
        let _ = writeln!(s, "\n[[link]]");
        let _ = writeln!(s, "name = {}", string(&l.name));
        let _ = writeln!(s, "parent = {}", string(model.body_name(l.parent)));
        let _ = writeln!(s, "com = {}", vec_str(l.com_from_joint.as_slice()));
        let _ = writeln!(s, "mass = {}", num(l.mass.mass));
        let _ = writeln!(s, "inertia = {}", inertia_str(&l.mass.inertia));
        let _ = writeln!(s, "[link.joint]");
        let _ = writeln!(s, "name = {}", string(&j.name));
        let _ = writeln!(s, "type = {}", string(j.kind.as_str()));
        let _ = writeln!(s, "origin = {}", vec_str(j.origin_in_parent.as_slice()));
        let q = j.rotation_in_parent;
        if !(q.i == 0.0 && q.j == 0.0 && q.k == 0.0 && q.w == 1.0) {
            let _ = writeln!(s, "rotation = {}", vec_str(&[q.i, q.j, q.k, q.w]));
        }
        let _ = writeln!(s, "axis = {}", vec_str(j.axis.as_slice()));
        let lim = j.limits;
        let u = JointLimits::unlimited();
        let mut parts = Vec::new();
        for (key, v, d) in [("lower", lim.lower, u.lower), ("upper", lim.upper, u.upper), ("velocity", lim.velocity, u.velocity), ("effort", lim.effort, u.effort)] {
            if v != d {
                parts.push(format!("{key} = {}", num(v)));
            }
        }
        if !parts.is_empty() {
            let _ = writeln!(s, "limits = {{ {} }}", parts.join(", "));
        }
        let (d, none) = (j.dynamics, JointDynamics::default());
        if d.actuated != none.actuated {
            let _ = writeln!(s, "actuated = {}", d.actuated);
        }
        for (key, v, dv) in [("stiffness", d.stiffness, none.stiffness), ("damping", d.damping, none.damping), ("rest", d.rest, none.rest)] {
            if v != dv {
                let _ = writeln!(s, "{key} = {}", num(v));
            }
        }
    }
    for p in model.points() {
        let _ = writeln!(s, "\n[[point]]");
        let _ = writeln!(s, "name = {}", string(&p.name));
        let _ = writeln!(s, "body = {}", string(model.body_name(p.body)));
        let _ = writeln!(s, "offset = {}", vec_str(p.offset.as_slice()));
    }
    for g in model.geometries() {
        let _ = writeln!(s, "\n[[geometry]]");
        let _ = writeln!(s, "name = {}", string(&g.name));
        let _ = writeln!(s, "body = {}", string(model.body_name(g.body)));
        let _ = writeln!(s, "role = {}", string(g.role.as_str()));
        let _ = writeln!(s, "shape = {}", string(g.shape.kind()));
        match &g.shape {
            Shape::Box { size } => {
                let _ = writeln!(s, "size = {}", vec_str(size));
            }
            Shape::Sphere { radius } => {
                let _ = writeln!(s, "radius = {}", num(*radius));
            }
            Shape::Cylinder { radius, length } | Shape::Capsule { radius, length } => {
                let _ = writeln!(s, "radius = {}\nlength = {}", num(*radius), num(*length));
            }
            Shape::Mesh { file, scale } => {
                let _ = writeln!(s, "file = {}\nscale = {}", string(file), vec_str(scale));
            }
        }
        let _ = writeln!(s, "origin = {}", vec_str(g.origin.as_slice()));
        let q = g.rotation;
        if !(q.i == 0.0 && q.j == 0.0 && q.k == 0.0 && q.w == 1.0) {
            let _ = writeln!(s, "rotation = {}", vec_str(&[q.i, q.j, q.k, q.w]));
        }
        let _ = writeln!(s, "rgba = {}", vec_str(&g.rgba));
    }
    s
}
