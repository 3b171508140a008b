//! # spacearm-c
//!
//! A stable C ABI of `spacearm-core` (docs/c-api.md): opaque handles, status codes with a
//! thread-local message, caller-owned row-major buffers, no panic across the boundary. The same
//! library is the binary of the FMI 2 and FMI 3 co-simulation units that `spacearm fmu` writes
//! (docs/fmi.md): it exports the `fmi2*` and `fmi3*` functions too.
//!
//! * [`status`] — status codes, the last-error message, the guard around every entry point;
//! * [`model`] — the model handle (TOML text, TOML file, preset);
//! * [`dynamics`] — `H`, `H0`, `H0m`, `H_m`, `H*`, `J*`, `c`, `c*`, forward and inverse
//!   dynamics, momenta, the momentum map, point poses, the derivatives of forward dynamics;
//! * [`stepper`] — the core's RK4 loop with a native controller;
//! * `fmu` — the FMI instance, its variables and model description, the `fmi2*`/`fmi3*` entry
//!   points (not in `spacearm.h`: the FMI headers declare them).

#![deny(unsafe_op_in_unsafe_fn)]

pub mod dynamics;
/// cbindgen:ignore
pub mod fmu;
pub mod model;
pub mod status;
pub mod stepper;

/// The version of this C ABI: raised on every incompatible change of a signature, a layout or
/// a status code's meaning. Compare it with `SPACEARM_ABI_VERSION` of the header you compiled
/// against.
pub const SPACEARM_ABI_VERSION: u32 = 1;

/// The ABI version of the loaded library (see `SPACEARM_ABI_VERSION`).
#[no_mangle]
pub extern "C" fn spacearm_abi_version() -> u32 {
    SPACEARM_ABI_VERSION
}

/// The version of spacearm the library was built from (a static NUL-terminated string).
#[no_mangle]
pub extern "C" fn spacearm_version() -> *const std::ffi::c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr().cast()
}
