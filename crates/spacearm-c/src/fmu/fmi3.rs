//! The FMI 3.0 co-simulation entry points (the signatures of the standard's `fmi3Functions.h`,
//! FMI 3.0.2 §2.3 and §4), each a thin call into [`super::Instance`]. The unit has Float64
//! variables only, no event mode, no FMU state, no clocks; the functions for those answer
//! `fmi3Error` with a logged message (model exchange and scheduled execution: a NULL instance).
//! The unsupported functions are defined with their first argument only: under the C calling
//! conventions of the supported platforms the callee may ignore the arguments that follow.
#![allow(non_snake_case)]

use std::ffi::{c_char, c_void, CStr, CString};
use std::path::PathBuf;

use super::variables::FmiVersion;
use super::{check_start_time, free_handle, instantiate, log_caught, slice, slice_mut, with, Instance, Phase};

type Fmi3Status = i32;
const OK: Fmi3Status = super::FMI_OK;
const ERROR: Fmi3Status = super::FMI_ERROR;
type Fmi3Instance = *mut c_void;
type Fmi3ValueReference = u32;
/// `fmi3LogMessageCallback`.
type LogMessage = unsafe extern "C" fn(*mut c_void, Fmi3Status, *const c_char, *const c_char);

fn logger_of(log: Option<LogMessage>, env: *mut c_void) -> super::Logger {
    Box::new(move |is_error, msg| {
        if let Some(log) = log {
            let m = CString::new(msg.replace('\0', "")).unwrap_or_default();
            let (status, category) = if is_error { (ERROR, c"logStatusError") } else { (OK, c"logEvents") };
            // SAFETY: the importer's callback with its own environment (FMI 3 §2.3.1).
            unsafe { log(env, status, category.as_ptr(), m.as_ptr()) };
        }
    })
}

#[no_mangle]
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    c"3.0".as_ptr()
}

/// # Safety
/// FMI 3 contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetDebugLogging(c: Fmi3Instance, logging_on: bool, _n: usize, _categories: *const *const c_char) -> Fmi3Status {
    // SAFETY: FMI 3 contract.
    unsafe { with(c, |i| i.set_logging(logging_on)) }
}

/// # Safety
/// FMI 3 contract: NUL-terminated strings; `resource_path` the FMU's `resources/` folder with
/// a trailing separator.
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    instance_name_ptr: *const c_char,
    token: *const c_char,
    resource_path: *const c_char,
    _visible: bool,
    logging_on: bool,
    event_mode_used: bool,
    _early_return_allowed: bool,
    _required_intermediate: *const Fmi3ValueReference,
    _n_required_intermediate: usize,
    instance_environment: *mut c_void,
    log_message: Option<LogMessage>,
    _intermediate_update: *mut c_void,
) -> Fmi3Instance {
    // SAFETY: FMI 3 contract: NUL-terminated strings or NULL.
    unsafe {
        instantiate(FmiVersion::Fmi3, instance_name_ptr, token, logging_on, |_| logger_of(log_message, instance_environment), || {
            if event_mode_used {
                return Err("this FMU has no event mode (hasEventMode=false); instantiate it with eventModeUsed = false".into());
            }
            if resource_path.is_null() {
                return Err("resourcePath is NULL; the FMU needs its resources/ folder".into());
            }
            Ok(PathBuf::from(CStr::from_ptr(resource_path).to_string_lossy().into_owned()))
        })
    }
}

/// Model exchange is not implemented: always NULL (after logging why).
///
/// # Safety
/// FMI 3 contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateModelExchange(
    _name: *const c_char,
    _token: *const c_char,
    _resource_path: *const c_char,
    _visible: bool,
    _logging_on: bool,
    env: *mut c_void,
    log_message: Option<LogMessage>,
) -> Fmi3Instance {
    log_caught(|| logger_of(log_message, env)(true, "this FMU supports co-simulation only; model exchange is not implemented"));
    std::ptr::null_mut()
}

/// Scheduled execution is not implemented: always NULL.
#[no_mangle]
pub extern "C" fn fmi3InstantiateScheduledExecution() -> Fmi3Instance {
    std::ptr::null_mut()
}

/// # Safety
/// FMI 3 contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3FreeInstance(c: Fmi3Instance) {
    // SAFETY: an instance from `fmi3InstantiateCoSimulation`, freed once.
    unsafe { free_handle(c) }
}

/// # Safety
/// FMI 3 contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3EnterInitializationMode(c: Fmi3Instance, _tol_defined: bool, _tol: f64, start_time: f64, _stop_defined: bool, _stop: f64) -> Fmi3Status {
    // SAFETY: FMI 3 contract.
    unsafe {
        with(c, |i| {
            check_start_time(start_time)?;
            i.enter_initialization()
        })
    }
}

super::instance_entry_points! {
    Fmi3Instance, Fmi3Status;
    fmi3ExitInitializationMode => Instance::exit_initialization,
    fmi3Terminate => Instance::terminate,
    fmi3Reset => Instance::reset,
}

/// The unit has no event mode; step mode is where it always is after initialization.
///
/// # Safety
/// FMI 3 contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3EnterStepMode(c: Fmi3Instance) -> Fmi3Status {
    // SAFETY: FMI 3 contract.
    unsafe { with(c, |i| if i.phase == Phase::Stepping { Ok(()) } else { Err("step mode follows initialization".into()) }) }
}

/// # Safety
/// FMI 3 contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetFloat64(c: Fmi3Instance, vr: *const Fmi3ValueReference, nvr: usize, values: *mut f64, n_values: usize) -> Fmi3Status {
    // SAFETY: FMI 3 contract: `nvr` references, `n_values` values.
    unsafe { with(c, |i| i.get(slice(vr, nvr)?, slice_mut(values, n_values)?)) }
}

/// # Safety
/// FMI 3 contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetFloat64(c: Fmi3Instance, vr: *const Fmi3ValueReference, nvr: usize, values: *const f64, n_values: usize) -> Fmi3Status {
    // SAFETY: FMI 3 contract: `nvr` references, `n_values` values.
    unsafe { with(c, |i| i.set(slice(vr, nvr)?, slice(values, n_values)?)) }
}

/// # Safety
/// FMI 3 contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3DoStep(
    c: Fmi3Instance,
    t: f64,
    h: f64,
    _no_set_prior: bool,
    event_handling_needed: *mut bool,
    terminate_simulation: *mut bool,
    early_return: *mut bool,
    last_successful_time: *mut f64,
) -> Fmi3Status {
    // SAFETY: FMI 3 contract: the four outputs are writable (or NULL, then skipped).
    unsafe {
        with(c, |i| {
            let result = i.do_step(t, h);
            for flag in [event_handling_needed, terminate_simulation, early_return] {
                if !flag.is_null() {
                    *flag = false;
                }
            }
            if !last_successful_time.is_null() {
                let mut now = [0.0];
                i.get(&[0], &mut now)?;
                *last_successful_time = now[0];
            }
            result
        })
    }
}

/// The unit has Float64 variables only: calls for other types succeed for zero references.
macro_rules! no_variables_of_type {
    ($($name:ident $kind:literal),* $(,)?) => {$(
        /// # Safety
        /// FMI 3 contract.
        #[no_mangle]
        pub unsafe extern "C" fn $name(c: Fmi3Instance, _vr: *const Fmi3ValueReference, nvr: usize) -> Fmi3Status {
            // SAFETY: FMI 3 contract.
            unsafe { with(c, |_| if nvr == 0 { Ok(()) } else { Err(format!("this FMU has no {} variables", $kind)) }) }
        }
    )*};
}

no_variables_of_type!(
    fmi3GetFloat32 "Float32", fmi3GetInt8 "Int8", fmi3GetUInt8 "UInt8", fmi3GetInt16 "Int16", fmi3GetUInt16 "UInt16",
    fmi3GetInt32 "Int32", fmi3GetUInt32 "UInt32", fmi3GetInt64 "Int64", fmi3GetUInt64 "UInt64", fmi3GetBoolean "Boolean",
    fmi3GetString "String", fmi3GetBinary "Binary", fmi3GetClock "Clock",
    fmi3SetFloat32 "Float32", fmi3SetInt8 "Int8", fmi3SetUInt8 "UInt8", fmi3SetInt16 "Int16", fmi3SetUInt16 "UInt16",
    fmi3SetInt32 "Int32", fmi3SetUInt32 "UInt32", fmi3SetInt64 "Int64", fmi3SetUInt64 "UInt64", fmi3SetBoolean "Boolean",
    fmi3SetString "String", fmi3SetBinary "Binary", fmi3SetClock "Clock",
);

/// Functions for capabilities the model description declares absent.
macro_rules! unsupported {
    ($($name:ident $what:literal),* $(,)?) => {$(
        /// # Safety
        /// FMI 3 contract.
        #[no_mangle]
        pub unsafe extern "C" fn $name(c: Fmi3Instance) -> Fmi3Status {
            // SAFETY: FMI 3 contract.
            unsafe { with(c, |_| Err(format!("{} is not supported by this FMU (its model description says so)", $what))) }
        }
    )*};
}

unsupported!(
    fmi3EnterEventMode "event mode",
    fmi3GetNumberOfVariableDependencies "fmi3GetNumberOfVariableDependencies",
    fmi3GetVariableDependencies "fmi3GetVariableDependencies",
    fmi3GetFMUState "getting the FMU state",
    fmi3SetFMUState "setting the FMU state",
    fmi3FreeFMUState "freeing an FMU state",
    fmi3SerializedFMUStateSize "serializing the FMU state",
    fmi3SerializeFMUState "serializing the FMU state",
    fmi3DeserializeFMUState "deserializing an FMU state",
    fmi3GetDirectionalDerivative "fmi3GetDirectionalDerivative",
    fmi3GetAdjointDerivative "fmi3GetAdjointDerivative",
    fmi3EnterConfigurationMode "configuration mode",
    fmi3ExitConfigurationMode "configuration mode",
    fmi3GetIntervalDecimal "clocks",
    fmi3GetIntervalFraction "clocks",
    fmi3GetShiftDecimal "clocks",
    fmi3GetShiftFraction "clocks",
    fmi3SetIntervalDecimal "clocks",
    fmi3SetIntervalFraction "clocks",
    fmi3SetShiftDecimal "clocks",
    fmi3SetShiftFraction "clocks",
    fmi3EvaluateDiscreteStates "event mode",
    fmi3UpdateDiscreteStates "event mode",
    fmi3EnterContinuousTimeMode "model exchange",
    fmi3CompletedIntegratorStep "model exchange",
    fmi3SetTime "model exchange",
    fmi3SetContinuousStates "model exchange",
    fmi3GetContinuousStateDerivatives "model exchange",
    fmi3GetEventIndicators "model exchange",
    fmi3GetContinuousStates "model exchange",
    fmi3GetNominalsOfContinuousStates "model exchange",
    fmi3GetNumberOfEventIndicators "model exchange",
    fmi3GetNumberOfContinuousStates "model exchange",
    fmi3GetOutputDerivatives "fmi3GetOutputDerivatives",
    fmi3ActivateModelPartition "scheduled execution",
);
