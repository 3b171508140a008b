//! Admission control: every request that allocates in proportion to its size (a simulation's
//! records, a dense `(6+N)²` workspace, a `(6+N)³` tensor of partials) estimates its bytes
//! first and is refused, before anything is allocated, when the estimate exceeds
//! [`MEMORY_LIMIT_BYTES`]. The refusal ([`SpacearmError::ResourceLimit`]) names the request,
//! its size, the limit and the way out (record fewer samples, a shorter run, a smaller model,
//! an O(N) algorithm). Without it such a request aborts the process ("memory allocation of …
//! bytes failed") or is killed by the kernel, taking the interpreter with it.

use crate::error::{Result, SpacearmError};

/// The largest allocation one request may make: 2 GiB. Large enough for a 10,000-link mass
/// matrix (0.8 GB) or 2·10⁷ recorded samples of a 6-joint arm, small enough to leave room on
/// a laptop. Documented in docs/simulation-core.md ("Memory limits").
pub const MEMORY_LIMIT_BYTES: u64 = 2 << 30;

/// The most arithmetic one request of a deliberately cubic algorithm may do, in multiply-adds:
/// 4·10⁹, about 15 s on one core. Only the paper-form inertia (eqs. 27–36, a sum over links of
/// Jacobian products: Σ depth² per link, N³/3 on a chain) is limited this way: it is the
/// independent check of CRBA, which gives the same `H` in O(N·depth).
pub const WORK_LIMIT: f64 = 4e9;

/// Admit a computation of about `operations` multiply-adds, or refuse it (see [`WORK_LIMIT`]).
/// `what` is formatted only for a refusal (pass `format_args!`: admission is on the path of
/// every call, where building a message that is thrown away would cost more than the check).
pub fn admit_work(what: impl std::fmt::Display, operations: f64, remedy: &str) -> Result<()> {
    if operations.is_finite() && operations <= WORK_LIMIT {
        return Ok(());
    }
    Err(SpacearmError::ResourceLimit(format!(
        "{what} would take about {operations:.2e} multiply-adds (more than the {WORK_LIMIT:.0e} one request may use); {remedy}"
    )))
}

/// Bytes as a short human-readable size (`"104.0 GB"`).
pub fn format_bytes(bytes: f64) -> String {
    const UNITS: [&str; 5] = ["B", "kB", "MB", "GB", "TB"];
    let mut value = bytes;
    let mut unit = 0;
    while value >= 1000.0 && unit + 1 < UNITS.len() {
        value /= 1000.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{value:.0} B")
    } else {
        format!("{value:.1} {}", UNITS[unit])
    }
}

/// Admit a request that will allocate about `bytes` (a float, so that the estimate itself
/// cannot overflow), or refuse it: `what` names the request, `remedy` the way out. `what` is
/// formatted only for a refusal (pass `format_args!`, see [`admit_work`]).
pub fn admit(what: impl std::fmt::Display, bytes: f64, remedy: &str) -> Result<()> {
    if within_memory_limit(bytes) {
        return Ok(());
    }
    Err(SpacearmError::ResourceLimit(format!(
        "{what} would allocate {} (more than the {} one request may use); {remedy}",
        format_bytes(bytes),
        format_bytes(MEMORY_LIMIT_BYTES as f64)
    )))
}

/// Whether a request of about `bytes` is admitted (the test of [`admit`], for callers that
/// choose their message only when it is not).
#[inline]
pub fn within_memory_limit(bytes: f64) -> bool {
    bytes.is_finite() && bytes <= MEMORY_LIMIT_BYTES as f64
}

/// Bytes of `count` values of type `T`, as a float.
pub fn bytes_of<T>(count: f64) -> f64 {
    count * std::mem::size_of::<T>() as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_as_written() {
        assert_eq!(format_bytes(512.0), "512 B");
        assert_eq!(format_bytes(104_000_000_208.0), "104.0 GB");
    }

    #[test]
    fn limit_is_inclusive_and_overflow_refused() {
        assert!(admit("x", MEMORY_LIMIT_BYTES as f64, "").is_ok());
        let e = admit("a simulation's records", 1e11, "record fewer samples").unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("100.0 GB") && msg.contains("2.1 GB") && msg.contains("record fewer samples"), "{msg}");
        assert!(admit("x", f64::INFINITY, "").is_err());
        assert!(admit("x", f64::NAN, "").is_err());
    }
}
