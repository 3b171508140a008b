//! Ctrl-C during a long native call: the work runs on a helper thread while the calling thread
//! (the one Python's signal handlers run on) checks the signals every 0.1 s with the GIL taken
//! back briefly; a `KeyboardInterrupt` sets the work's cancel flag, the work stops at its next
//! check of the flag, and the call raises the interrupt (docs/batch.md, docs/rollouts.md).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use pyo3::prelude::*;

/// How often a long call takes the GIL back to check for Ctrl-C.
pub const SIGNAL_CHECK_INTERVAL: Duration = Duration::from_millis(100);

/// Run `work(cancel)` with the GIL released and the signals checked every
/// [`SIGNAL_CHECK_INTERVAL`]; `work` must return soon after `cancel` is set. The result, or the
/// signal handler's exception (`KeyboardInterrupt`) once the work has stopped.
pub fn run_interruptible<R: Send>(py: Python<'_>, work: impl FnOnce(&AtomicBool) -> R + Send) -> PyResult<R> {
    run_until(py, None, work)
}

/// [`run_interruptible`] that also stops when `stop` (an object with `is_set()`, such as a
/// `threading.Event`: the way to stop a call running on a thread other than the main one,
/// where no signal arrives) is set; the call then raises `SimulationError("stopped ...")`.
pub fn run_until<R: Send>(py: Python<'_>, stop: Option<Py<PyAny>>, work: impl FnOnce(&AtomicBool) -> R + Send) -> PyResult<R> {
    let cancel = AtomicBool::new(false);
    let (result, interrupted) = py.detach(|| {
        std::thread::scope(|s| {
            let (tx, rx) = mpsc::channel();
            let cancel = &cancel;
            s.spawn(move || {
                // The receiver outlives this thread (the scope joins it first): a send cannot fail.
                let _ = tx.send(work(cancel));
            });
            let mut interrupted: Option<PyErr> = None;
            loop {
                match rx.recv_timeout(SIGNAL_CHECK_INTERVAL) {
                    Ok(r) => break (Some(r), interrupted),
                    Err(mpsc::RecvTimeoutError::Timeout) => {
                        if interrupted.is_none() {
                            let checked = Python::attach(|py| {
                                py.check_signals()?;
                                if let Some(stop) = &stop {
                                    if stop.bind(py).call_method0("is_set")?.is_truthy()? {
                                        return Err(crate::errors_py::new_error(
                                            py,
                                            crate::errors_py::ErrorClass::Simulation,
                                            "stopped: the call's stop event was set".into(),
                                        ));
                                    }
                                }
                                Ok(())
                            });
                            if let Err(e) = checked {
                                interrupted = Some(e);
                                cancel.store(true, Ordering::Relaxed);
                            }
                        }
                    }
                    // The worker panicked: the scope re-raises the panic when it joins.
                    Err(mpsc::RecvTimeoutError::Disconnected) => break (None, interrupted),
                }
            }
        })
    });
    if let Some(e) = interrupted {
        return Err(e);
    }
    result.ok_or_else(|| pyo3::exceptions::PySystemError::new_err("a native worker thread stopped without a result"))
}

/// Run `work(progress)` with the GIL released, where `progress` (the core's progress report)
/// takes the GIL back to call `progress_fn` (if any) with the fraction done and to check for
/// Ctrl-C: at every report if there is a callable (at most ~1000 a run), else every
/// [`SIGNAL_CHECK_INTERVAL`] of wall time and at the last report (taking the GIL back waits for
/// the other Python threads, so not more often than that). The callable's exception or a
/// pending signal fails the report with `Simulation("interrupted")`, so that the work stops at
/// once. Returns the work's result and that exception if there was one (the caller chooses
/// which error the call raises: a callback controller's own exception comes first).
pub fn run_reporting<R: Send>(
    py: Python<'_>,
    progress_fn: Option<&Py<PyAny>>,
    work: impl FnOnce(spacearm_core::sim::simulate::Progress<'_>) -> spacearm_core::Result<R> + Send,
) -> (spacearm_core::Result<R>, Option<PyErr>) {
    let mut interrupted: Option<PyErr> = None;
    let result = py.detach(|| {
        let mut last_check = Instant::now();
        let mut progress = |fraction: f64| -> spacearm_core::Result<()> {
            if progress_fn.is_none() && fraction < 1.0 && last_check.elapsed() < SIGNAL_CHECK_INTERVAL {
                return Ok(());
            }
            last_check = Instant::now();
            Python::attach(|py| {
                py.check_signals()?;
                match progress_fn {
                    Some(f) => f.call1(py, (fraction,)).map(|_| ()),
                    None => Ok(()),
                }
            })
            .map_err(|e| {
                interrupted.get_or_insert(e);
                spacearm_core::SpacearmError::Simulation("interrupted".into())
            })
        };
        work(&mut progress)
    });
    (result, interrupted)
}
