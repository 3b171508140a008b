//! Many simulations at once on native threads: [`rollout`].
//!
//! Each rollout is an independent call of [`simulate`] with its own plant model, initial state
//! and controller (and so its own workspaces); rollouts share nothing mutable. A rollout's
//! result is therefore bit-identical to `simulate` of the same inputs, whatever the number of
//! threads and whichever thread runs it. A rollout that fails (diverges, meets a singular mass
//! matrix, a controller error) gives its error in its slot of the result; the others run on.

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use crate::control::Controller;
use crate::error::{Result, SpacearmError};
use crate::model::Model;
use crate::sim::record::Recorder;
use crate::sim::simulate::{admit_records, sample_count, simulate, SimOptions, SimResult};

/// The inputs of one rollout.
pub struct RolloutSpec<'a> {
    /// The plant (a shared model, or one perturbed model per rollout).
    pub model: &'a Model,
    /// Initial configuration `[r0, quat0, q]` (7+N).
    pub x0: &'a [f64],
    /// Initial velocity `[v0, ω0, q̇]` (6+N).
    pub u0: &'a [f64],
    /// This rollout's controller (its own instance: controllers keep workspaces).
    pub controller: Box<dyn Controller + 'a>,
}

/// The largest number of threads [`rollout`] accepts.
pub const MAX_THREADS: usize = 1024;

/// Run every rollout of `specs` under `opts` on `threads` threads (`None`: rayon's global pool,
/// one thread per core), in parallel; the results come back in the order of `specs`.
///
/// The options are checked first (an error there is the whole call's); after that each rollout
/// succeeds or fails on its own. Nothing is printed or reported while the rollouts run.
pub fn rollout(specs: Vec<RolloutSpec<'_>>, opts: &SimOptions, threads: Option<usize>) -> Result<Vec<Result<SimResult>>> {
    rollout_cancellable(specs, opts, threads, &AtomicBool::new(false))
}

/// [`rollout`] that stops soon after `cancel` is set: every run checks it at each of its
/// progress reports (~1000 a run) and the runs not yet started do not start; each stopped run
/// gives `SimulationError("interrupted")` in its slot.
pub fn rollout_cancellable(specs: Vec<RolloutSpec<'_>>, opts: &SimOptions, threads: Option<usize>, cancel: &AtomicBool) -> Result<Vec<Result<SimResult>>> {
    opts.validate()?;
    opts.refuse_stop("rollout")?;
    // Admission of every rollout's records together (they are all held at the end), counting
    // each model's own values per sample (the controller's few extra columns aside).
    let values: f64 = specs.iter().map(|s| Recorder::values_per_sample(s.model, 0, 0, false, false) as f64).sum();
    let samples = sample_count(opts) as f64;
    admit_records(opts.integrator, samples * specs.len() as f64, values * samples)?;
    let run = move || -> Vec<Result<SimResult>> {
        specs
            .into_par_iter()
            .with_max_len(1)
            .map(|mut s| {
                let mut stop = |_: f64| if cancel.load(Ordering::Relaxed) { Err(SpacearmError::Simulation("interrupted".into())) } else { Ok(()) };
                stop(0.0)?;
                simulate(s.model, s.x0, s.u0, opts, s.controller.as_mut(), &mut stop)
            })
            .collect()
    };
    match threads {
        None => Ok(run()),
        Some(n) => {
            if n == 0 || n > MAX_THREADS {
                return Err(SpacearmError::argument(format!("threads must be between 1 and {MAX_THREADS}, got {n}")));
            }
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| SpacearmError::Simulation(format!("could not start {n} threads for the rollouts: {e}")))?;
            Ok(pool.install(run))
        }
    }
}
