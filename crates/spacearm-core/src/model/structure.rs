//! The rules that need the whole model ([`check_structure`]), applied when a [`Model`](crate::model::Model)
//! is built; the rules on each item's own fields are [`crate::model::validate`]'s.

use crate::error::{ModelError, ModelField, ModelItem};
use crate::model::body::MassProperties;
use crate::model::joint::JointType;
use crate::model::link::{Link, Point};
use crate::model::validate::MAX_LENGTH;

/// The rules that need the whole model: links come parents first (`links[k].parent <= k`, a
/// tree) and points name existing bodies (both guaranteed by the builder, which resolves
/// names in order, and checked here for any other assembly); every moving joint carries some
/// mass or inertia; the end effector names a point; `initial_q` has one finite entry per
/// moving joint. Names are unique by construction (checked as each item is added).
pub fn check_structure(
    base: &MassProperties,
    links: &[Link],
    points: &[Point],
    end_effector: Option<usize>,
    initial_q: &[f64],
) -> Result<(), ModelError> {
    for (k, link) in links.iter().enumerate() {
        let item = ModelItem::Link(k);
        if link.parent > k {
            return Err(ModelError::new(
                item,
                ModelField::Parent,
                format!("link '{}': parent index {} must name the base (0) or a link listed before it (1..={k})", link.name, link.parent),
            ));
        }
    }
    // A moving joint must carry something: with no mass and no inertia anywhere downstream
    // its acceleration is undetermined and H is singular for every configuration.
    let mut subtree_mass: Vec<f64> = std::iter::once(base.mass).chain(links.iter().map(|l| l.mass.mass)).collect();
    let mut subtree_inertia: Vec<f64> =
        std::iter::once(base.inertia.trace()).chain(links.iter().map(|l| l.mass.inertia.trace())).collect();
    for (k, link) in links.iter().enumerate().rev() {
        let body = k + 1;
        if link.joint.kind != JointType::Fixed && subtree_mass[body] == 0.0 && subtree_inertia[body] == 0.0 {
            return Err(ModelError::new(
                ModelItem::Link(k),
                ModelField::Mass,
                format!(
                    "joint '{}' moves link '{}', but that link and everything attached to it have zero mass and inertia: \
                     the joint's acceleration would be undetermined",
                    link.joint.name, link.name
                ),
            ));
        }
        subtree_mass[link.parent] += subtree_mass[body];
        subtree_inertia[link.parent] += subtree_inertia[body];
    }
    for (i, p) in points.iter().enumerate() {
        if p.body > links.len() {
            return Err(ModelError::new(
                ModelItem::Point(i),
                ModelField::Body,
                format!("point '{}': body index {} does not exist (the model has bodies 0..={})", p.name, p.body, links.len()),
            ));
        }
    }
    if let Some(e) = end_effector {
        if e >= points.len() {
            return Err(ModelError::new(ModelItem::Model, ModelField::EndEffector, format!("end effector index {e} does not name a point")));
        }
    }
    let n_dof = links.iter().filter(|l| l.joint.kind != JointType::Fixed).count();
    if initial_q.len() != n_dof {
        return Err(ModelError::new(
            ModelItem::Model,
            ModelField::InitialQ,
            format!("initial_q must have N = {n_dof} entries (one per moving joint), got {}", initial_q.len()),
        ));
    }
    if let Some(x) = initial_q.iter().find(|x| !x.is_finite()) {
        return Err(ModelError::new(ModelItem::Model, ModelField::InitialQ, format!("initial_q must be finite, got {x}")));
    }
    if let Some(x) = initial_q.iter().find(|x| x.abs() > MAX_LENGTH) {
        return Err(ModelError::new(
            ModelItem::Model,
            ModelField::InitialQ,
            format!("initial_q entry {x:e} exceeds {MAX_LENGTH:e} (m or rad) in magnitude"),
        ));
    }
    Ok(())
}
