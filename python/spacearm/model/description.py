"""The typed description of a model: what [`Robot.description`][spacearm.Robot.description] returns.

A [`ModelDescription`][spacearm.ModelDescription] states a model's parameters as the Rust core holds them (its visual and collision shapes too,
[`GeometryDescription`][spacearm.GeometryDescription], docs/geometry.md), with each
field's frame and unit (``docs/conventions.md``, "A model's frames, concretely"): every body
frame has its origin at the body's centre of mass (CM); a joint's ``origin`` and ``rotation``
are in the parent's frame; its ``axis`` is in the link frame; a link's ``com`` is measured from
its joint in the link frame; inertias are about the CM in the body's axes. SI units throughout.

The classes are the extension's own (``crates/spacearm-py/src/description_py.rs``), re-exported
here: frozen, built once per model, their arrays read-only. [`ModelDescription.to_dict`][spacearm.ModelDescription.to_dict]
gives the plain-data form that [`Robot.describe`][spacearm.Robot.describe] returns; [`ModelDescription.link`][spacearm.ModelDescription.link] and
[`ModelDescription.point`][spacearm.ModelDescription.point] look items up by name.
"""

from __future__ import annotations

from .._core import BaseDescription, GeometryDescription, JointLimits, LinkDescription, ModelDescription, PointDescription

__all__ = ["ModelDescription", "BaseDescription", "LinkDescription", "PointDescription", "GeometryDescription", "JointLimits"]
