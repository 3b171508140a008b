//! The FMI 2.0 co-simulation entry points (the signatures of the standard's `fmi2Functions.h`,
//! FMI 2.0.4 §2.1 and §4.2), each a thin call into [`super::Instance`]. Functions the unit does
//! not support (FMU state, directional derivatives, input derivatives, asynchronous steps)
//! answer `fmi2Error` with a logged message, as the standard allows for capabilities the model
//! description declares absent.
#![allow(non_snake_case)]

use std::ffi::{c_char, c_int, c_uint, c_void, CStr, CString};
use std::path::PathBuf;

use super::variables::FmiVersion;
use super::{check_start_time, free_handle, instantiate, slice, slice_mut, with, Instance};

type Fmi2Status = c_int;
const OK: Fmi2Status = super::FMI_OK;
const DISCARD: Fmi2Status = 2;
const ERROR: Fmi2Status = super::FMI_ERROR;
type Fmi2Component = *mut c_void;
type Fmi2Boolean = c_int;
type Fmi2ValueReference = c_uint;

/// `fmi2CallbackLogger`: variadic (a printf format and its arguments).
type Logger = unsafe extern "C" fn(*mut c_void, *const c_char, Fmi2Status, *const c_char, *const c_char, ...);

/// `fmi2CallbackFunctions`.
#[repr(C)]
pub struct Fmi2CallbackFunctions {
    logger: Option<Logger>,
    allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    step_finished: Option<unsafe extern "C" fn(*mut c_void, Fmi2Status)>,
    component_environment: *mut c_void,
}

/// A path from the `file:` URI of `fmuResourceLocation` (RFC 8089, percent-decoded).
fn path_of_uri(uri: &str) -> Result<PathBuf, String> {
    let rest = uri.strip_prefix("file://localhost/").map(|r| format!("/{r}")).or_else(|| uri.strip_prefix("file:///").map(|r| format!("/{r}"))).or_else(|| uri.strip_prefix("file:/").map(|r| format!("/{r}")));
    let rest = rest.ok_or_else(|| format!("fmuResourceLocation must be a file: URI, got '{uri}'"))?;
    let bytes = rest.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            let hex = std::str::from_utf8(&bytes[i + 1..i + 3]).ok().and_then(|h| u8::from_str_radix(h, 16).ok());
            if let Some(b) = hex {
                out.push(b);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8(out).map(PathBuf::from).map_err(|_| format!("fmuResourceLocation '{uri}' is not UTF-8 once decoded"))
}

fn logger_of(functions: *const Fmi2CallbackFunctions, name: &str) -> super::Logger {
    // SAFETY: the importer passes a valid callbacks struct that outlives the instance (FMI 2 §2.1.5).
    let (log, env) = match unsafe { functions.as_ref() } {
        Some(f) => (f.logger, f.component_environment),
        None => (None, std::ptr::null_mut()),
    };
    let name = CString::new(name.replace('\0', "")).unwrap_or_default();
    Box::new(move |is_error, msg| {
        if let Some(log) = log {
            let m = CString::new(msg.replace('\0', "")).unwrap_or_default();
            let (status, category) = if is_error { (ERROR, c"logStatusError") } else { (OK, c"logAll") };
            // SAFETY: the importer's logger, called with a "%s" format and one string.
            unsafe { log(env, name.as_ptr(), status, category.as_ptr(), c"%s".as_ptr(), m.as_ptr()) };
        }
    })
}

#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

/// # Safety
/// FMI 2 contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(c: Fmi2Component, logging_on: Fmi2Boolean, _n: usize, _categories: *const *const c_char) -> Fmi2Status {
    // SAFETY: FMI 2 contract.
    unsafe { with(c, |i| i.set_logging(logging_on != 0)) }
}

/// # Safety
/// FMI 2 contract: NUL-terminated strings, a callbacks struct that outlives the instance.
#[no_mangle]
pub unsafe extern "C" fn fmi2Instantiate(
    instance_name_ptr: *const c_char,
    fmu_type: c_int,
    guid: *const c_char,
    resource_location: *const c_char,
    functions: *const Fmi2CallbackFunctions,
    _visible: Fmi2Boolean,
    logging_on: Fmi2Boolean,
) -> Fmi2Component {
    // SAFETY: FMI 2 contract: NUL-terminated strings or NULL.
    unsafe {
        instantiate(FmiVersion::Fmi2, instance_name_ptr, guid, logging_on != 0, |name| logger_of(functions, name), || {
            if fmu_type != 1 {
                return Err("this FMU supports co-simulation only (fmi2CoSimulation); model exchange is not implemented".into());
            }
            if resource_location.is_null() {
                return Err("fmuResourceLocation is NULL; the FMU needs its resources/ folder".into());
            }
            path_of_uri(&CStr::from_ptr(resource_location).to_string_lossy())
        })
    }
}

/// # Safety
/// FMI 2 contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: Fmi2Component) {
    // SAFETY: an instance from `fmi2Instantiate`, freed once.
    unsafe { free_handle(c) }
}

/// # Safety
/// FMI 2 contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(c: Fmi2Component, _tol_defined: Fmi2Boolean, _tol: f64, start_time: f64, _stop_defined: Fmi2Boolean, _stop: f64) -> Fmi2Status {
    // SAFETY: FMI 2 contract.
    unsafe { with(c, |_| check_start_time(start_time)) }
}

super::instance_entry_points! {
    Fmi2Component, Fmi2Status;
    fmi2EnterInitializationMode => Instance::enter_initialization,
    fmi2ExitInitializationMode => Instance::exit_initialization,
    fmi2Terminate => Instance::terminate,
    fmi2Reset => Instance::reset,
}

/// # Safety
/// FMI 2 contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(c: Fmi2Component, vr: *const Fmi2ValueReference, nvr: usize, value: *mut f64) -> Fmi2Status {
    // SAFETY: FMI 2 contract: `nvr` references and values.
    unsafe { with(c, |i| i.get(slice(vr, nvr)?, slice_mut(value, nvr)?)) }
}

/// # Safety
/// FMI 2 contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetReal(c: Fmi2Component, vr: *const Fmi2ValueReference, nvr: usize, value: *const f64) -> Fmi2Status {
    // SAFETY: FMI 2 contract: `nvr` references and values.
    unsafe { with(c, |i| i.set(slice(vr, nvr)?, slice(value, nvr)?)) }
}

/// The unit has Real variables only: Integer, Boolean and String calls succeed for zero
/// references and fail otherwise.
unsafe fn none_of_type(c: Fmi2Component, nvr: usize, kind: &str) -> Fmi2Status {
    // SAFETY: FMI 2 contract.
    unsafe { with(c, |_| if nvr == 0 { Ok(()) } else { Err(format!("this FMU has no {kind} variables")) }) }
}

macro_rules! no_variables_of_type {
    ($($name:ident($t:ty, $kind:literal)),* $(,)?) => {$(
        /// # Safety
        /// FMI 2 contract.
        #[no_mangle]
        pub unsafe extern "C" fn $name(c: Fmi2Component, _vr: *const Fmi2ValueReference, nvr: usize, _value: $t) -> Fmi2Status {
            // SAFETY: FMI 2 contract.
            unsafe { none_of_type(c, nvr, $kind) }
        }
    )*};
}

no_variables_of_type!(
    fmi2GetInteger(*mut c_int, "Integer"),
    fmi2GetBoolean(*mut Fmi2Boolean, "Boolean"),
    fmi2GetString(*mut *const c_char, "String"),
    fmi2SetInteger(*const c_int, "Integer"),
    fmi2SetBoolean(*const Fmi2Boolean, "Boolean"),
    fmi2SetString(*const *const c_char, "String"),
);

/// # Safety
/// FMI 2 contract.
unsafe fn unsupported(c: Fmi2Component, what: &str) -> Fmi2Status {
    // SAFETY: FMI 2 contract.
    unsafe { with(c, |_| Err(format!("{what} is not supported by this FMU (its model description says so)"))) }
}

macro_rules! unsupported {
    ($($name:ident($($arg:ident: $t:ty),*) $what:literal),* $(,)?) => {$(
        /// # Safety
        /// FMI 2 contract.
        #[no_mangle]
        pub unsafe extern "C" fn $name(c: Fmi2Component, $($arg: $t),*) -> Fmi2Status {
            $(let _ = $arg;)*
            // SAFETY: FMI 2 contract.
            unsafe { unsupported(c, $what) }
        }
    )*};
}

unsupported!(
    fmi2GetFMUstate(s: *mut *mut c_void) "getting the FMU state",
    fmi2SetFMUstate(s: *mut c_void) "setting the FMU state",
    fmi2FreeFMUstate(s: *mut *mut c_void) "freeing an FMU state",
    fmi2SerializedFMUstateSize(s: *mut c_void, size: *mut usize) "serializing the FMU state",
    fmi2SerializeFMUstate(s: *mut c_void, data: *mut c_char, size: usize) "serializing the FMU state",
    fmi2DeSerializeFMUstate(data: *const c_char, size: usize, s: *mut *mut c_void) "deserializing an FMU state",
    fmi2GetDirectionalDerivative(vu: *const Fmi2ValueReference, nu: usize, vk: *const Fmi2ValueReference, nk: usize, dvk: *const f64, dvu: *mut f64) "fmi2GetDirectionalDerivative",
    fmi2SetRealInputDerivatives(vr: *const Fmi2ValueReference, nvr: usize, order: *const c_int, value: *const f64) "fmi2SetRealInputDerivatives",
    fmi2GetRealOutputDerivatives(vr: *const Fmi2ValueReference, nvr: usize, order: *const c_int, value: *mut f64) "fmi2GetRealOutputDerivatives",
    fmi2CancelStep() "fmi2CancelStep (steps are never asynchronous)",
    fmi2GetStatus(kind: c_int, value: *mut c_int) "fmi2GetStatus (steps are never asynchronous)",
    fmi2GetIntegerStatus(kind: c_int, value: *mut c_int) "fmi2GetIntegerStatus",
    fmi2GetStringStatus(kind: c_int, value: *mut *const c_char) "fmi2GetStringStatus",
);

/// # Safety
/// FMI 2 contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(c: Fmi2Component, t: f64, h: f64, _no_set_prior: Fmi2Boolean) -> Fmi2Status {
    // SAFETY: FMI 2 contract.
    unsafe { with(c, |i| i.do_step(t, h)) }
}

/// `fmi2LastSuccessfulTime` (kind 2): the FMU's time.
///
/// # Safety
/// FMI 2 contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(c: Fmi2Component, kind: c_int, value: *mut f64) -> Fmi2Status {
    // SAFETY: FMI 2 contract.
    let status = unsafe {
        with(c, |i| {
            if kind != 2 || value.is_null() {
                return Err("fmi2GetRealStatus answers fmi2LastSuccessfulTime only".into());
            }
            let mut t = [0.0];
            i.get(&[0], &mut t)?;
            // Checked not NULL; writable by the FMI contract.
            *value = t[0];
            Ok(())
        })
    };
    if status == OK { OK } else { DISCARD }
}

/// `fmi2Terminated` (kind 3): never (the unit does not end a simulation itself).
///
/// # Safety
/// FMI 2 contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(c: Fmi2Component, kind: c_int, value: *mut Fmi2Boolean) -> Fmi2Status {
    // SAFETY: FMI 2 contract.
    unsafe {
        with(c, |_| {
            if kind != 3 || value.is_null() {
                return Err("fmi2GetBooleanStatus answers fmi2Terminated only".into());
            }
            // Checked not NULL; writable by the FMI contract.
            *value = 0;
            Ok(())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::path_of_uri;

    #[test]
    fn resource_uris_become_paths() {
        assert_eq!(path_of_uri("file:///tmp/a%20b/resources").unwrap().to_str().unwrap(), "/tmp/a b/resources");
        assert_eq!(path_of_uri("file:/tmp/x").unwrap().to_str().unwrap(), "/tmp/x");
        assert_eq!(path_of_uri("file://localhost/tmp/x").unwrap().to_str().unwrap(), "/tmp/x");
        assert!(path_of_uri("http://example.com/x").is_err());
    }
}
