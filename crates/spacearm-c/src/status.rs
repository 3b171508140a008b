//! Status codes, the thread-local last-error message, and the guard every entry point runs its
//! body in (docs/c-api.md, "Errors").
//!
//! Every function of the C ABI returns a [`SpacearmStatus`]. On anything but
//! [`SpacearmStatus::Ok`] the message that names what was wrong and what was expected is kept
//! per thread and read with [`spacearm_last_error`]. A Rust panic never crosses the boundary:
//! [`guard`] catches it (`std::panic::catch_unwind`) and turns it into
//! [`SpacearmStatus::Internal`].

use std::cell::RefCell;
use std::ffi::{c_char, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

use nalgebra::{Dim, Matrix, RawStorage};
use spacearm_core::{ErrorKind, SpacearmError};

/// What a call of the C ABI returned. `0` is success; every other value names the kind of
/// failure (the same kinds as the Python exceptions of `spacearm.errors`), and
/// `spacearm_last_error()` gives the message.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpacearmStatus {
    /// Success.
    Ok = 0,
    /// The model description breaks a physical or structural rule.
    InvalidModel = 1,
    /// An array has the wrong length.
    Dimension = 2,
    /// An input holds NaN or an infinity, or a result computed from finite inputs would (the
    /// output is then not written).
    NonFinite = 3,
    /// A quaternion is not of unit length.
    NotUnitQuaternion = 4,
    /// A name or index refers to nothing in the model.
    NotFound = 5,
    /// A matrix that must be invertible is singular at this state.
    Singular = 6,
    /// A model or options text could not be parsed (the message has line and column).
    Parse = 7,
    /// An option or argument has an invalid value.
    InvalidArgument = 8,
    /// A simulation could not go on.
    Simulation = 9,
    /// A request would allocate more than the core allows.
    ResourceLimit = 10,
    /// A pointer argument that must not be NULL was NULL.
    NullPointer = 11,
    /// A caller-owned buffer is too small (the message and the `needed` argument say how large).
    BufferTooSmall = 12,
    /// A file could not be read.
    Io = 13,
    /// A defect inside spacearm (a Rust panic, caught at the boundary). Please report it.
    Internal = 14,
}

impl SpacearmStatus {
    /// Every status in code order, with its short name (`spacearm_status_name`).
    const NAMES: [(SpacearmStatus, &'static CStr); 15] = [
        (SpacearmStatus::Ok, c"ok"),
        (SpacearmStatus::InvalidModel, c"invalid model"),
        (SpacearmStatus::Dimension, c"dimension"),
        (SpacearmStatus::NonFinite, c"non-finite"),
        (SpacearmStatus::NotUnitQuaternion, c"not a unit quaternion"),
        (SpacearmStatus::NotFound, c"not found"),
        (SpacearmStatus::Singular, c"singular"),
        (SpacearmStatus::Parse, c"parse"),
        (SpacearmStatus::InvalidArgument, c"invalid argument"),
        (SpacearmStatus::Simulation, c"simulation"),
        (SpacearmStatus::ResourceLimit, c"resource limit"),
        (SpacearmStatus::NullPointer, c"null pointer"),
        (SpacearmStatus::BufferTooSmall, c"buffer too small"),
        (SpacearmStatus::Io, c"io"),
        (SpacearmStatus::Internal, c"internal"),
    ];

    /// The status of the code `code` with its name (`None`: not a status code). The argument is
    /// a plain int, not the enum: a C caller may pass any value, and a Rust enum holding a value
    /// outside its variants would be undefined behaviour.
    fn of_code(code: i32) -> Option<(SpacearmStatus, &'static CStr)> {
        SpacearmStatus::NAMES.into_iter().find(|(s, _)| *s as i32 == code)
    }
}

/// A failure inside an entry point: its status and message.
#[derive(Debug)]
pub(crate) struct Failure {
    pub status: SpacearmStatus,
    pub message: String,
}

impl Failure {
    pub(crate) fn new(status: SpacearmStatus, message: impl Into<String>) -> Self {
        Failure { status, message: message.into() }
    }
    pub(crate) fn argument(message: impl Into<String>) -> Self {
        Failure::new(SpacearmStatus::InvalidArgument, message)
    }
}

impl From<SpacearmError> for Failure {
    fn from(e: SpacearmError) -> Self {
        Failure::new(SpacearmStatus::of_kind(e.kind()), e.to_string())
    }
}

impl SpacearmStatus {
    /// The status of an error kind of the core: the one whose code the core's table gives
    /// ([`ErrorKind::status_code`]).
    pub(crate) fn of_kind(kind: ErrorKind) -> SpacearmStatus {
        SpacearmStatus::of_code(kind.status_code()).map_or(SpacearmStatus::Internal, |(s, _)| s)
    }
}

pub(crate) type Outcome<T = ()> = Result<T, Failure>;

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

pub(crate) fn set_last_error(message: &str) {
    // An interior NUL cannot be represented in a C string: cut the message there.
    let cut = message.split('\0').next().unwrap_or("");
    let text = CString::new(cut).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = text);
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "a panic without a message".to_string()
    }
}

/// The one place a body runs under `catch_unwind` (every entry point of the C ABI and of the
/// FMUs, through [`guard`], [`guard_value`], [`free_handle`] and the FMI wrappers of
/// `fmu/mod.rs`): a panic becomes a [`SpacearmStatus::Internal`] failure whose message says so
/// and carries the panic's own.
pub(crate) fn caught<T>(body: impl FnOnce() -> Outcome<T>) -> Outcome<T> {
    catch_unwind(AssertUnwindSafe(body)).unwrap_or_else(|payload| {
        Err(Failure::new(
            SpacearmStatus::Internal,
            format!("internal error in spacearm (a Rust panic, caught at the C boundary): {}", panic_message(payload.as_ref())),
        ))
    })
}

/// [`caught`], the outcome kept for [`spacearm_last_error`]: a failure's message, or `""` on
/// success.
fn recorded<T>(body: impl FnOnce() -> Outcome<T>) -> Result<T, SpacearmStatus> {
    let outcome = caught(body);
    set_last_error(outcome.as_ref().err().map_or("", |f| f.message.as_str()));
    outcome.map_err(|f| f.status)
}

/// Run the body of an entry point: its failure becomes a status code with the message kept for
/// [`spacearm_last_error`]; a panic is caught and becomes [`SpacearmStatus::Internal`]. Success
/// clears the message.
pub(crate) fn guard(body: impl FnOnce() -> Outcome) -> SpacearmStatus {
    recorded(body).err().unwrap_or(SpacearmStatus::Ok)
}

/// Like [`guard`] for the entry points that return a value rather than a status (sizes):
/// `fallback` on failure or panic, with the message kept. Success clears the message, as
/// [`guard`] does.
pub(crate) fn guard_value<T>(fallback: T, body: impl FnOnce() -> Outcome<T>) -> T {
    recorded(body).unwrap_or(fallback)
}

/// The handle `p` of an entry point (a model, a stepper), or a NullPointer failure naming
/// `what` and where such a handle comes from (`expected`).
///
/// # Safety
/// `p` NULL or a live handle of this library.
pub(crate) unsafe fn handle<'a, T>(p: *const T, what: &str, expected: &str) -> Outcome<&'a T> {
    // SAFETY: the caller's contract.
    unsafe { p.as_ref() }.ok_or_else(|| Failure::new(SpacearmStatus::NullPointer, format!("{what} is NULL; expected {expected}")))
}

/// Store a new handle holding `value` in `*out` (`type_name` the C type, for the message when
/// `out` is NULL); the caller frees it with [`free_handle`].
///
/// # Safety
/// `out` NULL or writable.
pub(crate) unsafe fn give<T>(value: T, out: *mut *mut T, type_name: &str) -> Outcome {
    if out.is_null() {
        return Err(Failure::new(SpacearmStatus::NullPointer, format!("out is NULL; expected the address of a {type_name}*")));
    }
    // SAFETY: `out` is writable (caller's contract).
    unsafe { *out = Box::into_raw(Box::new(value)) };
    Ok(())
}

/// Free a handle made by [`give`] (or any `Box::into_raw`); NULL is ignored, a panic while
/// dropping is caught (a free has no status to report it with).
///
/// # Safety
/// `p` NULL or a handle not yet freed; it must not be used afterwards.
pub(crate) unsafe fn free_handle<T>(p: *mut T) {
    if !p.is_null() {
        // SAFETY: a handle from `Box::into_raw`, freed once (caller's contract).
        let _ = caught(|| {
            drop(unsafe { Box::from_raw(p) });
            Ok(())
        });
    }
}

/// The message of the last failed call on this thread (empty after a successful call). The
/// text is owned by the library and stays valid until the next spacearm call on this thread;
/// copy it to keep it. Never NULL.
#[no_mangle]
pub extern "C" fn spacearm_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

/// A short name of a status code (`"dimension"` for `SPACEARM_STATUS_DIMENSION`); a static
/// string, never NULL. Any value that is not a status code (negative, or above
/// `SPACEARM_STATUS_INTERNAL`) gives `"unknown status"`.
#[no_mangle]
pub extern "C" fn spacearm_status_name(status: i32) -> *const c_char {
    SpacearmStatus::of_code(status).map_or(c"unknown status", |(_, name)| name).as_ptr()
}

// ---- argument helpers (caller-owned memory) ----

/// A caller's input array of `len` values; NULL is refused (unless `len == 0`), and so is any
/// value that is not finite (NaN or an infinity: a [`SpacearmStatus::NonFinite`] naming `what`
/// and the entry), as the Python binding refuses it.
///
/// # Safety
/// `p` must point at `len` readable `f64` (or be NULL).
pub(crate) unsafe fn input<'a>(p: *const f64, len: usize, what: &str) -> Outcome<&'a [f64]> {
    if len == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(Failure::new(SpacearmStatus::NullPointer, format!("{what} is NULL; expected a pointer to {len} doubles")));
    }
    // SAFETY: the caller's contract (documented on every entry point): `len` readable doubles.
    let v = unsafe { std::slice::from_raw_parts(p, len) };
    finite(what, v)?;
    Ok(v)
}

/// An optional caller's input array: `None` for NULL; otherwise as [`input`] (finite values).
///
/// # Safety
/// `p` must point at `len` readable `f64` or be NULL.
pub(crate) unsafe fn optional_input<'a>(p: *const f64, len: usize, what: &str) -> Outcome<Option<&'a [f64]>> {
    // SAFETY: as for `input`.
    if p.is_null() { Ok(None) } else { unsafe { input(p, len, what) }.map(Some) }
}

/// A caller's output buffer of `len` values; NULL is refused (unless `len == 0`).
///
/// # Safety
/// `p` must point at `len` writable `f64` (or be NULL) not aliased by any input.
pub(crate) unsafe fn output<'a>(p: *mut f64, len: usize, what: &str) -> Outcome<&'a mut [f64]> {
    if len == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err(Failure::new(SpacearmStatus::NullPointer, format!("{what} is NULL; expected a buffer of {len} doubles")));
    }
    // SAFETY: the caller's contract: `len` writable doubles.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, len) })
}

/// A NUL-terminated UTF-8 string argument.
///
/// # Safety
/// `p` must be NULL or point at a NUL-terminated string.
pub(crate) unsafe fn text<'a>(p: *const c_char, what: &str) -> Outcome<&'a str> {
    if p.is_null() {
        return Err(Failure::new(SpacearmStatus::NullPointer, format!("{what} is NULL; expected a NUL-terminated UTF-8 string")));
    }
    // SAFETY: the caller's contract: a NUL-terminated string.
    let s = unsafe { CStr::from_ptr(p) };
    s.to_str().map_err(|e| Failure::argument(format!("{what} is not valid UTF-8: {e}")))
}

/// Write `s` NUL-terminated into the caller's buffer `buf` of `len` bytes; `needed` (if not
/// NULL) receives the size the text needs, NUL included. A NULL or short `buf` gives
/// [`SpacearmStatus::BufferTooSmall`] (call once with `len = 0` to learn the size).
///
/// # Safety
/// `buf` must be NULL or point at `len` writable bytes; `needed` NULL or writable.
pub(crate) unsafe fn write_text(s: &str, buf: *mut c_char, len: usize, needed: *mut usize) -> Outcome {
    let size = s.len() + 1;
    if !needed.is_null() {
        // SAFETY: the caller's contract: `needed` is writable.
        unsafe { *needed = size };
    }
    if buf.is_null() || len < size {
        return Err(Failure::new(SpacearmStatus::BufferTooSmall, format!("the text needs a buffer of {size} bytes (NUL included), got {len}")));
    }
    // SAFETY: `buf` has `len >= size` writable bytes.
    unsafe {
        std::ptr::copy_nonoverlapping(s.as_ptr(), buf.cast::<u8>(), s.len());
        *buf.add(s.len()) = 0;
    }
    Ok(())
}

/// Every value of `v` finite, or a NonFinite failure naming the first that is not.
pub(crate) fn finite(what: &str, v: &[f64]) -> Outcome {
    match v.iter().position(|x| !x.is_finite()) {
        None => Ok(()),
        Some(index) => Err(SpacearmError::NonFinite { what: what.into(), index, value: v[index] }.into()),
    }
}

// ---- results: the one check of every value the C ABI writes ----

/// The check of every result before it is written to a caller's buffer (as the Python binding
/// checks each result, crates/spacearm-py/src/batch.rs): a value that is not finite, computed
/// from finite inputs (which [`input`] has checked), is a [`SpacearmStatus::NonFinite`] failure
/// naming the output, the entry and its value, and nothing is written to that output.
fn finite_result(what: &str, values: impl Iterator<Item = f64>) -> Outcome {
    for (index, value) in values.enumerate() {
        if !value.is_finite() {
            return Err(Failure::new(
                SpacearmStatus::NonFinite,
                format!(
                    "{what} would be non-finite (entry {index} is {value}) from finite inputs: the state is beyond what double \
                     precision can represent (e.g. velocities of 1e200 overflow the velocity products); reduce the magnitudes \
                     of the inputs"
                ),
            ));
        }
    }
    Ok(())
}

/// Write the result `values` to the caller's buffer `out` (of the same length) after
/// [`finite_result`].
pub(crate) fn put(what: &str, values: &[f64], out: &mut [f64]) -> Outcome {
    finite_result(what, values.iter().copied())?;
    out.copy_from_slice(values);
    Ok(())
}

/// Write the result matrix `m` **row-major** (element `(i, j)` at `out[i * ncols + j]`) to the
/// caller's buffer `out` (of its size) after [`finite_result`].
pub(crate) fn put_row_major<R: Dim, C: Dim, S: RawStorage<f64, R, C>>(what: &str, m: &Matrix<f64, R, C, S>, out: &mut [f64]) -> Outcome {
    finite_result(what, m.iter().copied())?;
    let cols = m.ncols();
    for ((i, j), v) in (0..m.nrows()).flat_map(|i| (0..cols).map(move |j| (i, j))).zip(out.iter_mut()) {
        *v = m[(i, j)];
    }
    Ok(())
}

/// [`put_row_major`] into an optional output buffer `p` of the matrix's size (`rows × cols`
/// doubles; a vector's entries in order): NULL is not written.
///
/// # Safety
/// `p` NULL or `m.len()` writable doubles not aliased by any input.
pub(crate) unsafe fn put_optional<R: Dim, C: Dim, S: RawStorage<f64, R, C>>(what: &str, m: &Matrix<f64, R, C, S>, p: *mut f64) -> Outcome {
    if p.is_null() {
        return Ok(());
    }
    // SAFETY: the caller's contract: `m.len()` writable doubles.
    put_row_major(what, m, unsafe { std::slice::from_raw_parts_mut(p, m.len()) })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn last() -> String {
        // SAFETY: the pointer of this thread's message, valid until the next call here.
        unsafe { CStr::from_ptr(spacearm_last_error()) }.to_str().unwrap().to_string()
    }

    #[test]
    fn a_panic_becomes_the_internal_status_with_its_message() {
        let status = guard(|| panic!("index 7 out of range"));
        assert_eq!(status, SpacearmStatus::Internal);
        assert!(last().contains("index 7 out of range"), "{}", last());
        assert_eq!(guard_value(-1, || -> Outcome<i32> { panic!("boom") }), -1);
        assert!(last().contains("boom"));
    }

    #[test]
    fn failures_keep_their_kind_and_message_and_success_clears_it() {
        let status = guard(|| Err(SpacearmError::Dimension { what: "x".into(), expected: "13".into(), got: 2 }.into()));
        assert_eq!(status, SpacearmStatus::Dimension);
        assert_eq!(last(), "x must have length 13, got 2");
        assert_eq!(guard(|| Ok(())), SpacearmStatus::Ok);
        assert_eq!(last(), "");
        // A message with an interior NUL is cut there, never dropped.
        assert_eq!(guard(|| Err(Failure::argument("before\0after"))), SpacearmStatus::InvalidArgument);
        assert_eq!(last(), "before");
    }

    #[test]
    fn every_error_kind_of_the_core_is_its_own_status_of_the_same_name() {
        let statuses: Vec<SpacearmStatus> = ErrorKind::ALL.into_iter().map(SpacearmStatus::of_kind).collect();
        for (kind, status) in ErrorKind::ALL.into_iter().zip(&statuses) {
            // The core's code lands on the C enum's variant of the kind's name (not on the
            // statuses only the C ABI has: Ok, NullPointer, BufferTooSmall, Io, Internal).
            assert_eq!(format!("{status:?}"), kind.name());
            assert_eq!(*status as i32, kind.status_code());
        }
        let distinct: std::collections::HashSet<i32> = statuses.iter().map(|s| *s as i32).collect();
        assert_eq!(distinct.len(), ErrorKind::ALL.len());
        // An error of the core arrives as its kind's status.
        let f = Failure::from(SpacearmError::Parse("line 1".into()));
        assert_eq!((f.status, f.message.as_str()), (SpacearmStatus::Parse, "line 1"));
    }

    #[test]
    fn every_int_has_a_status_name() {
        let name = |s: i32| unsafe { CStr::from_ptr(spacearm_status_name(s)) }.to_str().unwrap().to_string();
        for (code, (s, _)) in SpacearmStatus::NAMES.into_iter().enumerate() {
            assert_eq!(s as usize, code, "the table is in code order");
            assert_ne!(name(s as i32), "unknown status");
        }
        assert_eq!(name(SpacearmStatus::NotUnitQuaternion as i32), "not a unit quaternion");
        assert_eq!(name(SpacearmStatus::Internal as i32), "internal");
        for s in [-1, 15, i32::MIN, i32::MAX] {
            assert_eq!(name(s), "unknown status");
        }
    }

    #[test]
    fn a_non_finite_result_is_refused_and_not_written() {
        let mut out = [7.0; 3];
        let f = put("du_out", &[1.0, f64::INFINITY, 2.0], &mut out).unwrap_err();
        assert_eq!(f.status, SpacearmStatus::NonFinite);
        assert!(f.message.contains("du_out") && f.message.contains("entry 1 is inf"), "{}", f.message);
        assert_eq!(out, [7.0; 3]);
        let m = nalgebra::Matrix2::new(1.0, 2.0, f64::NAN, 4.0);
        let mut o = [7.0; 4];
        assert_eq!(put_row_major("H", &m, &mut o).unwrap_err().status, SpacearmStatus::NonFinite);
        assert_eq!(o, [7.0; 4]);
        put_row_major("H", &nalgebra::Matrix2::new(1.0, 2.0, 3.0, 4.0), &mut o).unwrap();
        assert_eq!(o, [1.0, 2.0, 3.0, 4.0]);
        // SAFETY: a 2-element array.
        let e = unsafe { input([0.0, f64::NAN].as_ptr(), 2, "offset") }.unwrap_err();
        assert_eq!((e.status, e.message.as_str()), (SpacearmStatus::NonFinite, "offset must be finite, but entry 1 is NaN"));
    }

    #[test]
    fn the_one_wrapper_catches_panics_of_bodies_and_of_frees() {
        let f = caught(|| -> Outcome<i32> { panic!("at entry 3") }).unwrap_err();
        assert_eq!(f.status, SpacearmStatus::Internal);
        assert!(f.message.contains("a Rust panic") && f.message.contains("at entry 3"), "{}", f.message);
        assert_eq!(caught(|| Ok(5)).unwrap(), 5);
        struct PanicsOnDrop(std::rc::Rc<std::cell::Cell<bool>>);
        impl Drop for PanicsOnDrop {
            fn drop(&mut self) {
                self.0.set(true);
                panic!("drop");
            }
        }
        let dropped = std::rc::Rc::new(std::cell::Cell::new(false));
        // SAFETY: a fresh handle, freed once; NULL is ignored.
        unsafe {
            free_handle(Box::into_raw(Box::new(PanicsOnDrop(dropped.clone()))));
            free_handle(std::ptr::null_mut::<PanicsOnDrop>());
        }
        assert!(dropped.get());
    }

    #[test]
    fn optional_outputs_are_written_row_major_or_not_at_all() {
        let m = nalgebra::Matrix2x3::new(1.0, 2.0, 3.0, 4.0, 5.0, 6.0);
        let mut o = [0.0; 6];
        // SAFETY: NULL, then a 6-element buffer.
        unsafe {
            put_optional("M", &m, std::ptr::null_mut()).unwrap();
            put_optional("M", &m, o.as_mut_ptr()).unwrap();
        }
        assert_eq!(o, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    }

    #[test]
    fn success_clears_the_message_of_value_calls_too() {
        let _ = guard(|| Err(Failure::argument("earlier")));
        assert_eq!(guard_value(0, || Ok(3)), 3);
        assert_eq!(last(), "");
    }

    #[test]
    fn the_message_is_per_thread() {
        let _ = guard(|| Err(Failure::argument("main thread")));
        std::thread::spawn(|| assert_eq!(last(), "")).join().unwrap();
        assert_eq!(last(), "main thread");
    }

    #[test]
    fn short_text_buffers_say_the_size_they_need() {
        let mut needed = 0usize;
        let mut buf = [0 as c_char; 4];
        // SAFETY: a 4-byte buffer and a writable size.
        let r = unsafe { write_text("hello", buf.as_mut_ptr(), buf.len(), &mut needed) };
        assert_eq!(r.unwrap_err().status, SpacearmStatus::BufferTooSmall);
        assert_eq!(needed, 6);
        let mut big = [0 as c_char; 6];
        // SAFETY: a 6-byte buffer.
        unsafe { write_text("hello", big.as_mut_ptr(), big.len(), &mut needed) }.unwrap();
        // SAFETY: NUL-terminated by write_text.
        assert_eq!(unsafe { CStr::from_ptr(big.as_ptr()) }.to_str().unwrap(), "hello");
    }
}
