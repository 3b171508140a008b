//! The model handle: a validated core `Model` with its workspaces, built from TOML text, a TOML
//! file or a preset (docs/c-api.md, "Models").

use std::ffi::c_char;
use std::sync::Mutex;

use spacearm_core::derivatives::DerivativeData;
use spacearm_core::model::presets;
use spacearm_core::{Data, Model};

use crate::status::{free_handle, give, guard, guard_value, handle, input, optional_input, output, put, text, write_text, Failure, Outcome, SpacearmStatus};

/// An opaque, immutable model with its own workspaces. Safe to share between threads (the
/// workspaces are behind locks); free it with `spacearm_model_free`.
pub struct SpacearmModel {
    pub(crate) model: Model,
    data: Mutex<Data>,
    derivatives: Mutex<Option<DerivativeData>>,
}

impl SpacearmModel {
    pub(crate) fn new(model: Model) -> Self {
        let data = Mutex::new(Data::new(&model));
        SpacearmModel { model, data, derivatives: Mutex::new(None) }
    }

    /// Run `f` with the model and its workspace.
    pub(crate) fn with_data<R>(&self, f: impl FnOnce(&Model, &mut Data) -> R) -> R {
        // A poisoned lock only means a panic inside an earlier call (reported then); the
        // workspace is overwritten by every algorithm, so it is safe to go on with it.
        let mut d = self.data.lock().unwrap_or_else(|p| p.into_inner());
        f(&self.model, &mut d)
    }

    /// Run `f` with the model and its derivative workspace (made on first use).
    pub(crate) fn with_derivatives<R>(&self, f: impl FnOnce(&Model, &mut DerivativeData) -> R) -> R {
        let mut d = self.derivatives.lock().unwrap_or_else(|p| p.into_inner());
        let work = d.get_or_insert_with(|| DerivativeData::new(&self.model));
        f(&self.model, work)
    }
}

/// The model behind a handle, or a NullPointer failure.
///
/// # Safety
/// `m` must be NULL or a handle from this library not yet freed.
pub(crate) unsafe fn model_ref<'a>(m: *const SpacearmModel) -> Outcome<&'a SpacearmModel> {
    // SAFETY: the caller's contract.
    unsafe { handle(m, "model", "a handle from spacearm_model_from_*") }
}

/// A number of the model behind a possibly NULL handle, for the entry points that return one
/// (`fallback`, with the message kept, for NULL).
///
/// # Safety
/// `m` NULL or a live handle.
unsafe fn model_value<T>(m: *const SpacearmModel, fallback: T, value: fn(&Model) -> T) -> T {
    // SAFETY: the caller's contract.
    guard_value(fallback, || Ok(value(&unsafe { model_ref(m) }?.model)))
}

/// A model from TOML text (docs/model-format.md), with the status of its failure: text that is
/// not TOML (a syntax error) is [`SpacearmStatus::Parse`]; TOML that is not a valid model (an
/// unknown key, a value of the wrong type, a missing field, a negative mass, an unknown
/// parent...) is [`SpacearmStatus::InvalidModel`]. The message is the core's either way: the
/// source, line and column and what was expected. (The core reports both as one kind, for the
/// Python class `ModelFileError`, which is a `ModelError`; C has no class hierarchy, so the
/// door tells them apart by whether the text is TOML at all.)
pub(crate) fn model_from_toml(text: &str, source: &str) -> Outcome<Model> {
    spacearm_core::io::toml::model_from_toml_str(text, source).map_err(|e| {
        let syntax = matches!(e, spacearm_core::SpacearmError::Parse(_)) && text.parse::<toml::Table>().is_err();
        let mut failure = Failure::from(e);
        if failure.status == SpacearmStatus::Parse && !syntax {
            failure.status = SpacearmStatus::InvalidModel;
        }
        failure
    })
}

/// The entry points that make a model handle: `make` (which reads the arguments) runs under
/// [`guard`], then `*out` receives the new handle.
///
/// # Safety
/// `out` NULL or writable; `make` reads its pointers under the caller's contract.
unsafe fn new_model(out: *mut *mut SpacearmModel, make: impl FnOnce() -> Outcome<Model>) -> SpacearmStatus {
    guard(|| {
        let model = make()?;
        // SAFETY: the caller's contract.
        unsafe { give(SpacearmModel::new(model), out, "SpacearmModel") }
    })
}

/// The entry points that edit a model (the core's model/edit.rs): `edit` makes the new model
/// from the handle's (unchanged); `*out` receives it as a new handle.
///
/// # Safety
/// `model` NULL or a live handle; `out` NULL or writable; `edit` reads its pointers under the
/// caller's contract.
unsafe fn edited(model: *const SpacearmModel, out: *mut *mut SpacearmModel, edit: impl FnOnce(&Model) -> Outcome<Model>) -> SpacearmStatus {
    // SAFETY: the caller's contract.
    unsafe { new_model(out, || edit(&model_ref(model)?.model)) }
}

/// A model from TOML text (docs/model-format.md). `*out` receives a new handle.
///
/// # Safety
/// `toml` a NUL-terminated string; `out` writable.
#[no_mangle]
pub unsafe extern "C" fn spacearm_model_from_toml(toml: *const c_char, out: *mut *mut SpacearmModel) -> SpacearmStatus {
    // SAFETY (this block and below): the caller's contract, documented above.
    unsafe { new_model(out, || model_from_toml(text(toml, "toml")?, "<TOML text given to spacearm_model_from_toml>")) }
}

/// A model from a TOML file (docs/model-format.md). `*out` receives a new handle.
///
/// # Safety
/// `path` a NUL-terminated string; `out` writable.
#[no_mangle]
pub unsafe extern "C" fn spacearm_model_from_toml_file(path: *const c_char, out: *mut *mut SpacearmModel) -> SpacearmStatus {
    // SAFETY (this block and below): the caller's contract, documented above.
    unsafe {
        new_model(out, || {
            let p = text(path, "path")?;
            let body = std::fs::read_to_string(p).map_err(|e| Failure::new(SpacearmStatus::Io, format!("cannot read the model file '{p}': {e}")))?;
            model_from_toml(&body, p)
        })
    }
}

/// A preset model by name: `"planar4"`, `"spatial6"`, `"spatial7"`, `"dual_arm"`, `"ets7"`.
///
/// # Safety
/// `name` a NUL-terminated string; `out` writable.
#[no_mangle]
pub unsafe extern "C" fn spacearm_model_preset(name: *const c_char, out: *mut *mut SpacearmModel) -> SpacearmStatus {
    // SAFETY (this block and below): the caller's contract, documented above.
    unsafe {
        new_model(out, || {
            let n = text(name, "name")?;
            presets::by_name(n).ok_or_else(|| Failure::new(SpacearmStatus::NotFound, format!("unknown preset '{n}'; expected one of planar4, spatial6, spatial7, dual_arm, ets7")))
        })
    }
}

/// Free a model handle (NULL is ignored). Steppers made from it keep their own copy.
///
/// # Safety
/// `model` NULL or a handle not yet freed; it must not be used afterwards.
#[no_mangle]
pub unsafe extern "C" fn spacearm_model_free(model: *mut SpacearmModel) {
    // SAFETY: a handle from `spacearm_model_from_*`, freed once (caller's contract).
    unsafe { free_handle(model) }
}

/// Number of joint degrees of freedom `N` (0 for a NULL handle).
///
/// # Safety
/// `model` NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn spacearm_model_n_dof(model: *const SpacearmModel) -> usize {
    // SAFETY: the caller's contract.
    unsafe { model_value(model, 0, Model::n_dof) }
}

/// Length of a configuration `x = [r0, quat0 (x, y, z, w), q]`: `7 + N` (0 for NULL).
///
/// # Safety
/// `model` NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn spacearm_model_nx(model: *const SpacearmModel) -> usize {
    // SAFETY: the caller's contract.
    unsafe { model_value(model, 0, Model::nx) }
}

/// Length of a generalized velocity `u = [v0, ω0, q̇]`: `6 + N` (0 for NULL).
///
/// # Safety
/// `model` NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn spacearm_model_nu(model: *const SpacearmModel) -> usize {
    // SAFETY: the caller's contract.
    unsafe { model_value(model, 0, Model::nu) }
}

/// Number of bodies, the base (body 0) included (0 for NULL).
///
/// # Safety
/// `model` NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn spacearm_model_n_bodies(model: *const SpacearmModel) -> usize {
    // SAFETY: the caller's contract.
    unsafe { model_value(model, 0, Model::n_bodies) }
}

/// Total mass, kg (0 for NULL).
///
/// # Safety
/// `model` NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn spacearm_model_total_mass(model: *const SpacearmModel) -> f64 {
    // SAFETY: the caller's contract.
    unsafe { model_value(model, 0.0, Model::total_mass) }
}

/// The initial configuration `x` (7 + N): base at the origin aligned with 𝒥, the model's
/// initial joint angles.
///
/// # Safety
/// `model` a live handle; `x_out` 7 + N writable doubles.
#[no_mangle]
pub unsafe extern "C" fn spacearm_model_initial_configuration(model: *const SpacearmModel, x_out: *mut f64) -> SpacearmStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let m = unsafe { model_ref(model) }?;
        // SAFETY: the caller's contract.
        let out = unsafe { output(x_out, m.model.nx(), "x_out") }?;
        put("the initial configuration", &presets::initial_configuration(&m.model), out)
    })
}

/// A named point: its body index and its offset in that body's frame from the body's CM.
/// `name = NULL` asks for the end effector.
///
/// # Safety
/// `model` a live handle; `name` NULL or a NUL-terminated string; `body` writable; `offset_out`
/// 3 writable doubles.
#[no_mangle]
pub unsafe extern "C" fn spacearm_model_point(model: *const SpacearmModel, name: *const c_char, body: *mut usize, offset_out: *mut f64) -> SpacearmStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let m = unsafe { model_ref(model) }?;
        let index = if name.is_null() {
            m.model.end_effector().ok_or_else(|| Failure::new(SpacearmStatus::NotFound, format!("model '{}' has no end effector", m.model.name())))?
        } else {
            // SAFETY: the caller's contract.
            m.model.point_index(unsafe { text(name, "name") }?)?
        };
        let p = &m.model.points()[index];
        if body.is_null() {
            return Err(Failure::new(SpacearmStatus::NullPointer, "body is NULL; expected the address of a size_t"));
        }
        // SAFETY: the caller's contract.
        let out = unsafe { output(offset_out, 3, "offset_out") }?;
        put("the point's offset", p.offset.as_slice(), out)?;
        // SAFETY: checked not NULL; writable by the caller's contract.
        unsafe { *body = p.body };
        Ok(())
    })
}

/// The model as TOML text (NUL-terminated) in the caller's buffer `buf` of `len` bytes;
/// `*needed` (if not NULL) receives the size needed. Call with `len = 0` to learn it.
///
/// # Safety
/// `model` a live handle; `buf` NULL or `len` writable bytes; `needed` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn spacearm_model_to_toml(model: *const SpacearmModel, buf: *mut c_char, len: usize, needed: *mut usize) -> SpacearmStatus {
    guard(|| {
        // SAFETY: the caller's contract.
        let m = unsafe { model_ref(model) }?;
        let s = spacearm_core::io::toml::model_to_toml(&m.model);
        // SAFETY: the caller's contract.
        unsafe { write_text(&s, buf, len, needed) }
    })
}

// ---- editing (the core's model/edit.rs): each edit is a new handle; the input is unchanged ----

/// A mount for an edit from C arrays: `origin` 3 doubles, `rotation` 4 doubles `[x, y, z, w]`
/// (NULL: the identity).
///
/// # Safety
/// `parent` a NUL-terminated string; `origin` 3 readable doubles; `rotation` NULL or 4.
unsafe fn mount(parent: *const c_char, origin: *const f64, rotation: *const f64) -> Outcome<spacearm_core::Mount> {
    // SAFETY: the caller's contract.
    let parent = unsafe { text(parent, "parent") }?;
    // SAFETY: the caller's contract.
    let origin = unsafe { input(origin, 3, "origin") }?;
    // SAFETY: the caller's contract.
    let rotation = unsafe { optional_input(rotation, 4, "rotation") }?.unwrap_or(&[0.0, 0.0, 0.0, 1.0]);
    Ok(spacearm_core::Mount::new(parent, [origin[0], origin[1], origin[2]], [rotation[0], rotation[1], rotation[2], rotation[3]]))
}

/// A new model: `model` with a rigid payload `name` attached to the body `parent` on a fixed
/// joint: its CM at `origin` (3, `parent`'s frame, from its CM, m), its axes at `rotation`
/// (4, quaternion `[x, y, z, w]` in `parent`'s frame; NULL: aligned), mass `mass` (kg) and
/// `inertia` (9, row-major, about its CM in its own axes, kg·m²; NULL: a point mass). The
/// model's rules judge it (status `SPACEARM_STATUS_INVALID_MODEL` and the message otherwise);
/// every other quantity of `model` is kept bit for bit. `*out` receives a new handle.
///
/// # Safety
/// `model` a live handle; `name`, `parent` NUL-terminated strings; `origin` 3 readable doubles;
/// `rotation` NULL or 4; `inertia` NULL or 9; `out` writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn spacearm_model_attach_body(
    model: *const SpacearmModel,
    name: *const c_char,
    parent: *const c_char,
    origin: *const f64,
    rotation: *const f64,
    mass: f64,
    inertia: *const f64,
    out: *mut *mut SpacearmModel,
) -> SpacearmStatus {
    // SAFETY (this block and below): the caller's contract, documented above.
    unsafe {
        edited(model, out, |m| {
            let name = text(name, "name")?;
            let at = mount(parent, origin, rotation)?;
            let i = optional_input(inertia, 9, "inertia")?.unwrap_or(&[0.0; 9]);
            let inertia = [[i[0], i[1], i[2]], [i[3], i[4], i[5]], [i[6], i[7], i[8]]];
            Ok(m.attach_body(spacearm_core::LinkSpec::payload(name, &at, mass, inertia), None).map_err(spacearm_core::SpacearmError::from)?)
        })
    }
}

/// A new model: `model` with the whole model `other` attached to the body `parent`: `other`'s
/// base becomes the link `base_link` (NULL: `<prefix><its base name>`) on a fixed joint, its CM
/// at `origin` (3) and its axes at `rotation` (4, `[x, y, z, w]`; NULL: aligned) in `parent`'s
/// frame; its links (joints, limits, passive dynamics, initial `q`, appended to `model`'s),
/// points and geometry follow, every name prefixed with `prefix` (may be ""). A name clash or
/// any broken rule is `SPACEARM_STATUS_INVALID_MODEL` with the message. `*out` receives a new
/// handle; `model` and `other` are unchanged.
///
/// # Safety
/// `model`, `other` live handles; `parent`, `prefix` NUL-terminated strings; `base_link` NULL or
/// one; `origin` 3 readable doubles; `rotation` NULL or 4; `out` writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn spacearm_model_attach_model(
    model: *const SpacearmModel,
    other: *const SpacearmModel,
    parent: *const c_char,
    origin: *const f64,
    rotation: *const f64,
    prefix: *const c_char,
    base_link: *const c_char,
    out: *mut *mut SpacearmModel,
) -> SpacearmStatus {
    // SAFETY (this block and below): the caller's contract, documented above.
    unsafe {
        edited(model, out, |m| {
            let o = handle(other, "other", "a model handle to attach")?;
            let at = mount(parent, origin, rotation)?;
            let prefix = text(prefix, "prefix")?;
            let base_link = if base_link.is_null() { None } else { Some(text(base_link, "base_link")?) };
            Ok(m.attach_model(&o.model, &at, prefix, base_link).map_err(spacearm_core::SpacearmError::from)?)
        })
    }
}

/// A new model: `model` without the link `body`, every link below it, and the points and
/// geometry on them (the end effector too when it is one of them). The base cannot be removed
/// (`SPACEARM_STATUS_INVALID_MODEL`, as for a name that is not a link). `*out` receives a new
/// handle.
///
/// # Safety
/// `model` a live handle; `body` a NUL-terminated string; `out` writable.
#[no_mangle]
pub unsafe extern "C" fn spacearm_model_remove_subtree(model: *const SpacearmModel, body: *const c_char, out: *mut *mut SpacearmModel) -> SpacearmStatus {
    // SAFETY (this block and below): the caller's contract, documented above.
    unsafe { edited(model, out, |m| Ok(m.remove_subtree(text(body, "body")?).map_err(spacearm_core::SpacearmError::from)?)) }
}
