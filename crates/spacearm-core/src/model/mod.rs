//! The constant description of a spacecraft-manipulator system and its per-configuration
//! workspace: mass properties ([`body`]), joints ([`joint`]), the validated [`Model`]
//! ([`system`]), the one way to build one ([`builder`], checked by [`validate`]), the
//! workspace [`Data`] ([`data`]), the edits of a built model — attach a body or a model, remove
//! a subtree ([`edit`]) —, the bodies' visual and collision shapes ([`geometry`]), the
//! paper's case-study models ([`presets`]) and the slosh models built from passive joints ([`slosh`]) and the panels, beams and compliant
//! joints built from them ([`appendage`]).
//!
//! Imports: [`crate::math`], [`crate::error`] and [`crate::admission`] only (the presets use the
//! builder of this folder).

pub mod appendage;
pub mod body;
pub mod builder;
pub mod cmg;
pub mod data;
pub mod edit;
pub mod geometry;
pub mod docking;
pub mod gripper;
pub mod joint;
pub mod link;
pub mod presets;
pub mod slosh;
pub mod slosh_sphere;
pub mod slosh_tank;
pub mod structure;
pub mod system;
pub mod validate;

pub use body::TriangleInequality;
pub use builder::ModelBuilder;
pub use data::{Data, DataT};
pub use edit::Mount;
pub use geometry::{Geometry, GeometryRole, GeometrySpec, Shape};
pub use link::{Link, LinkSpec, Point};
pub use system::Model;
