//! Many [`Rk4Stepper`]s advanced one step each in one call, on native threads: the batch
//! behind the vectorized learning environments of the Python package (`spacearm.gym`).
//!
//! Each copy is an independent stepper with its own plant (a shared model or one perturbed
//! model per copy), state, workspace and held input; copies share nothing mutable. A copy's
//! step is therefore the very step [`Rk4Stepper::step_to`] takes alone (the same `t_next =
//! (n_steps + 1)·dt` grid): a batch gives, bit for bit, what stepping each copy by itself
//! gives, whatever the number of threads and whichever thread runs it.

use nalgebra::Vector6;
use rayon::prelude::*;

use crate::error::{Result, SpacearmError};
use crate::sim::rollout::MAX_THREADS;
use crate::sim::stepper::Rk4Stepper;

/// The memory one copy of a batch holds beyond its bodies, bytes: its stepper, RK4 stages and
/// held input (measured: about 4 kB for the presets, whatever their size).
pub const BATCH_COPY_BYTES: f64 = 4096.0;

/// The memory each body adds to one copy, bytes: the copy's own model and its kinematic and
/// dynamic workspace (measured: about 2.0 kB per body for planar4, spatial6 and dual_arm;
/// 2.3 kB here, a margin).
pub const BATCH_BODY_BYTES: f64 = 2304.0;

/// Admit a batch of `copies` copies of `model` ([`BATCH_COPY_BYTES`] + [`BATCH_BODY_BYTES`] per
/// body each, and their states), or refuse it with a `ResourceLimit` error before anything is
/// allocated ([`crate::admission`]): a batch of a million copies would otherwise allocate
/// gigabytes and abort.
pub fn admit_batch(model: &crate::Model, copies: usize) -> Result<()> {
    if copies == 0 {
        return Err(SpacearmError::argument("a batch needs at least one copy".to_string()));
    }
    let state = crate::admission::bytes_of::<f64>((model.nx() + model.nu()) as f64);
    let per_copy = BATCH_COPY_BYTES + BATCH_BODY_BYTES * model.n_bodies() as f64 + 2.0 * state;
    crate::admission::admit(
        format_args!("a batch of {copies} copies of '{}' ({} bodies)", model.name(), model.n_bodies()),
        copies as f64 * per_copy,
        "use fewer copies (num_envs), or several batches",
    )
}

/// `N` steppers of plants with the same joints, stepped together with steps of `dt`.
pub struct BatchStepper {
    copies: Vec<Rk4Stepper<'static>>,
    dt: f64,
    n_dof: usize,
    dim: usize,
    /// Its own pool of `threads` threads, or `None`: rayon's global pool.
    pool: Option<rayon::ThreadPool>,
}

impl BatchStepper {
    /// The batch of `copies` (at least one, all of the same joint count), each stepped by `dt`
    /// (> 0, finite) per call, on `threads` threads (`None`: rayon's global pool, one per core).
    pub fn new(copies: Vec<Rk4Stepper<'static>>, dt: f64, threads: Option<usize>) -> Result<Self> {
        let first = copies.first().ok_or_else(|| SpacearmError::argument("a batch needs at least one copy".to_string()))?;
        if !(dt.is_finite() && dt > 0.0) {
            return Err(SpacearmError::argument(format!("dt must be a finite number > 0, got {dt}")));
        }
        let (n_dof, dim) = (first.n_dof(), first.state().len());
        if let Some((i, c)) = copies.iter().enumerate().find(|(_, c)| c.n_dof() != n_dof) {
            return Err(SpacearmError::argument(format!("copy {i} has {} joints, copy 0 has {n_dof}; every copy needs the same joints", c.n_dof())));
        }
        let pool = match threads {
            None => None,
            Some(n) if n == 0 || n > MAX_THREADS => {
                return Err(SpacearmError::argument(format!("threads must be between 1 and {MAX_THREADS}, got {n}")));
            }
            Some(n) => Some(
                rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .build()
                    .map_err(|e| SpacearmError::Simulation(format!("could not start {n} threads: {e}")))?,
            ),
        };
        Ok(BatchStepper { copies, dt, n_dof, dim, pool })
    }

    /// The number of copies.
    pub fn len(&self) -> usize {
        self.copies.len()
    }

    /// Whether the batch has no copy (never: [`BatchStepper::new`] needs one).
    pub fn is_empty(&self) -> bool {
        self.copies.is_empty()
    }

    /// Joints per copy.
    pub fn n_dof(&self) -> usize {
        self.n_dof
    }

    /// The length of one copy's state `[x; u]`.
    pub fn state_dim(&self) -> usize {
        self.dim
    }

    /// Copy `i` (to read its time, state, steps).
    pub fn copy(&self, i: usize) -> &Rk4Stepper<'static> {
        &self.copies[i]
    }

    /// Put `stepper` in place of copy `i` (a reset of that copy: a new stepper from its initial
    /// state, of a plant with the same joints).
    pub fn replace(&mut self, i: usize, stepper: Rk4Stepper<'static>) -> Result<()> {
        if i >= self.copies.len() {
            return Err(SpacearmError::argument(format!("copy index {i} out of range for a batch of {}", self.copies.len())));
        }
        if stepper.n_dof() != self.n_dof {
            return Err(SpacearmError::argument(format!("the new copy {i} has {} joints, the batch {}", stepper.n_dof(), self.n_dof)));
        }
        self.copies[i] = stepper;
        Ok(())
    }

    /// `steps` (>= 1) steps of every copy, copy `i` holding the joint torque
    /// `tau[i·N..(i+1)·N]` and, when given, the base wrench `wrench[6i..6i+6]` over them (added
    /// to its controller's command). Each copy's new state is written to `out[i·dim..(i+1)·dim]`. Returns each
    /// copy's outcome: a copy that fails leaves its stepper failed (it needs a
    /// [`BatchStepper::replace`]) and the others go on.
    pub fn step(&mut self, tau: &[f64], wrench: Option<&[f64]>, steps: usize, out: &mut [f64]) -> Result<Vec<Result<()>>> {
        let (b, n, dim, dt) = (self.copies.len(), self.n_dof, self.dim, self.dt);
        if tau.len() != b * n {
            return Err(SpacearmError::Dimension { what: "tau".into(), expected: format!("{b}·{n} values ({b} copies of {n} joints)"), got: tau.len() });
        }
        if let Some(w) = wrench {
            if w.len() != b * 6 {
                return Err(SpacearmError::Dimension { what: "base_wrench".into(), expected: format!("{b}·6 values"), got: w.len() });
            }
        }
        if out.len() != b * dim {
            return Err(SpacearmError::Dimension { what: "out".into(), expected: format!("{b}·{dim} values"), got: out.len() });
        }
        if steps == 0 {
            return Err(SpacearmError::argument("steps must be >= 1".to_string()));
        }
        let copies = &mut self.copies;
        Ok(match &self.pool {
            Some(pool) => pool.install(|| step_all(copies, tau, wrench, out, (n, dim, steps), dt)),
            None => step_all(copies, tau, wrench, out, (n, dim, steps), dt),
        })
    }
}

/// One step of every copy (see [`BatchStepper::step`]), on the current rayon pool.
fn step_all(copies: &mut [Rk4Stepper<'static>], tau: &[f64], wrench: Option<&[f64]>, out: &mut [f64], sizes: (usize, usize, usize), dt: f64) -> Vec<Result<()>> {
    let (n, dim, steps) = sizes;
    copies
        .par_iter_mut()
        .zip(out.par_chunks_mut(dim))
        .enumerate()
        .map(|(i, (copy, row))| {
            let w = wrench.map_or_else(Vector6::zeros, |w| Vector6::from_column_slice(&w[6 * i..6 * i + 6]));
            copy.plant_mut().set_held_input(Some((&tau[i * n..(i + 1) * n], w)));
            let result = (0..steps).try_for_each(|_| {
                let t_next = (copy.n_steps() + 1) as f64 * dt;
                copy.step_to(t_next)
            });
            row.copy_from_slice(copy.state());
            result
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::ZeroTorque;
    use crate::model::presets::spatial6;
    use crate::sim::simulate::{Plant, SimOptions};

    fn stepper(model: &crate::Model, opts: &SimOptions, q: f64) -> Rk4Stepper<'static> {
        let n = model.n_dof();
        let mut x0 = vec![0.0; 7 + n];
        x0[6] = 1.0;
        x0[7] = q;
        let mut u0 = vec![0.0; 6 + n];
        u0[5] = 0.01;
        let plant = Plant::owned(model.clone(), opts, Box::new(ZeroTorque)).unwrap();
        Rk4Stepper::new(plant, &x0, &u0, None).unwrap()
    }

    #[test]
    fn a_batch_too_large_for_memory_is_refused_before_it_is_built() {
        let model = spatial6();
        assert!(admit_batch(&model, 1000).is_ok());
        let err = admit_batch(&model, 1_000_000).unwrap_err();
        assert!(matches!(err, SpacearmError::ResourceLimit(_)), "{err}");
        assert!(err.to_string().contains("a batch of 1000000 copies of"), "{err}");
        assert!(admit_batch(&model, 0).is_err());
    }

    #[test]
    fn a_batch_step_is_each_copy_stepped_alone() {
        let model = spatial6();
        let opts = SimOptions { dt: 1e-3, ..SimOptions::default() };
        let n = model.n_dof();
        for threads in [Some(1), Some(3), None] {
            let copies: Vec<_> = (0..5).map(|i| stepper(&model, &opts, 0.1 * i as f64)).collect();
            let mut alone: Vec<_> = (0..5).map(|i| stepper(&model, &opts, 0.1 * i as f64)).collect();
            let mut batch = BatchStepper::new(copies, opts.dt, threads).unwrap();
            let dim = batch.state_dim();
            let mut out = vec![0.0; 5 * dim];
            for k in 0..20 {
                let tau: Vec<f64> = (0..5 * n).map(|j| 0.01 * ((j + k) as f64).sin()).collect();
                let outcomes = batch.step(&tau, None, 2, &mut out).unwrap();
                assert!(outcomes.iter().all(|r| r.is_ok()));
                for (i, s) in alone.iter_mut().enumerate() {
                    s.plant_mut().set_held_input(Some((&tau[i * n..(i + 1) * n], Vector6::zeros())));
                    s.step_to((2 * k + 1) as f64 * opts.dt).unwrap();
                    s.step_to((2 * k + 2) as f64 * opts.dt).unwrap();
                    assert_eq!(&out[i * dim..(i + 1) * dim], s.state(), "copy {i} step {k}");
                }
            }
        }
    }

    #[test]
    fn wrong_sizes_and_threads_are_errors() {
        let model = spatial6();
        let opts = SimOptions { dt: 1e-3, ..SimOptions::default() };
        assert!(BatchStepper::new(vec![], 1e-3, None).is_err());
        assert!(BatchStepper::new(vec![stepper(&model, &opts, 0.0)], 1e-3, Some(0)).is_err());
        assert!(BatchStepper::new(vec![stepper(&model, &opts, 0.0)], f64::NAN, None).is_err());
        let mut b = BatchStepper::new(vec![stepper(&model, &opts, 0.0)], 1e-3, Some(1)).unwrap();
        let mut out = vec![0.0; b.state_dim()];
        assert!(b.step(&[0.0], None, 1, &mut out).is_err());
        assert!(b.step(&[0.0; 6], None, 0, &mut out).is_err());
        assert!(b.step(&[0.0; 6], Some(&[0.0; 5]), 1, &mut out).is_err());
    }
}
