//! Fixed-step RK4 integration of a [`Plant`] one step at a time, with optional recording.
//!
//! This is the loop of [`crate::sim::simulate::simulate`]'s RK4 path, and of the step-by-step
//! simulator of the Python package (`spacearm.Simulator`): one code path, so that stepping a
//! plant to a time and simulating it to that time give the same records bit for bit.

use crate::error::{Result, SpacearmError};
use crate::math::integrate::{IntegratorKind, OdeSystem, Rk4};
use crate::sim::record::{onsets, Recorder};
use crate::sim::contact_onset::retake_at_onset;
use crate::sim::plant::Plant;
use crate::sim::record::{admit_records, finish_result};
use crate::sim::result::{SaturationEvent, SimResult};

/// A plant, its state `y = [x; u]` at time `t`, an RK4 workspace and the records so far.
pub struct Rk4Stepper<'a> {
    plant: Plant<'a>,
    rk: Rk4,
    y: Vec<f64>,
    dy: Vec<f64>,
    t: f64,
    n_steps: usize,
    /// `(records, record_every)`; `None`: nothing is recorded (the saturation onsets still are).
    recording: Option<(Recorder, usize)>,
    events: Vec<SaturationEvent>,
    prev_flags: Vec<u8>,
    /// Set by a failed step: the state is then that of an unfinished step.
    failed: bool,
    /// With contact: the state at the step's start and a workspace, for the onset's location
    /// ([`crate::sim::contact_onset`]); empty without.
    y_start: Vec<f64>,
    y_try: Vec<f64>,
}

impl<'a> Rk4Stepper<'a> {
    /// Start at `t = 0` from `(x0, u0)` (checked by the caller, see
    /// [`crate::sim::simulate::check_initial_state`]; the quaternion is normalized exactly).
    /// `recording = Some((capacity, record_every))` records every `record_every`-th step into
    /// buffers reserved for `capacity` samples.
    pub fn new(plant: Plant<'a>, x0: &[f64], u0: &[f64], recording: Option<(usize, usize)>) -> Result<Self> {
        if let Some((_, 0)) = recording {
            return Err(SpacearmError::argument("record_every must be >= 1".to_string()));
        }
        // With contact the state has one more entry, the contact work (0 at the start).
        let mut y: Vec<f64> = plant.initial_state(x0, u0);
        plant.project(&mut y);
        let dim = y.len();
        let n = plant.model().n_dof();
        if let Some((capacity, _)) = recording {
            let values = capacity as f64 * Recorder::values_per_sample_of(&plant) as f64;
            admit_records(IntegratorKind::Rk4, capacity as f64, values)?;
        }
        let recording = recording.map(|(capacity, every)| (Recorder::for_plant(&plant, capacity), every));
        Ok(Rk4Stepper {
            rk: Rk4::new(dim),
            dy: vec![0.0; dim],
            y,
            t: 0.0,
            n_steps: 0,
            recording,
            events: Vec::new(),
            prev_flags: vec![0; n + 6],
            failed: false,
            y_start: if plant.contact.is_some() { vec![0.0; dim] } else { Vec::new() },
            y_try: if plant.contact.is_some() { vec![0.0; dim] } else { Vec::new() },
            plant,
        })
    }

    /// Admission of the records that `n` more steps would hold ([`admit_records`]: all the
    /// samples so far and to come), before any is taken; nothing to admit when not recording.
    pub fn admit_steps(&self, n: usize) -> Result<()> {
        if let Some((_, every)) = &self.recording {
            let samples = self.n_steps.saturating_add(n).div_ceil(*every) as f64 + 1.0;
            admit_records(IntegratorKind::Rk4, samples, samples * Recorder::values_per_sample_of(&self.plant) as f64)?;
        }
        Ok(())
    }

    /// Advance one step from the current time to `t_next` (> the current time), recording the
    /// state at the start of the step if it is a recorded step.
    pub fn step_to(&mut self, t_next: f64) -> Result<()> {
        if self.failed {
            return Err(SpacearmError::Simulation("a step failed earlier; reset the simulation before stepping again".into()));
        }
        let t = self.t;
        self.plant.flags_step.fill(0);
        let record_now = matches!(&self.recording, Some((_, every)) if self.n_steps % every == 0);
        let result = (|| {
            self.plant.sample(t, &self.y)?;
            let rigid = self.plant.is_rigid();
            if record_now || rigid {
                self.plant.rhs(t, &self.y, self.rk.k1_mut())?;
            }
            if record_now {
                if let Some((rec, _)) = &mut self.recording {
                    rec.record(&self.plant, t, &self.y, self.rk.k1());
                }
            }
            // Rigid contact: the step's impulses change u at its start (sim/rigid_contact.rs);
            // the RK4 stage at the start is then evaluated again.
            let jumped = rigid && self.plant.rigid_jump(t, t_next - t, &mut self.y, self.rk.k1())?;
            let contact = !self.y_start.is_empty() && !rigid;
            if contact {
                self.y_start.copy_from_slice(&self.y);
            }
            self.rk.step(&mut self.plant, t, t_next - t, &mut self.y, (record_now || rigid) && !jumped)?;
            if contact {
                retake_at_onset(&mut self.plant, &mut self.rk, t, &self.y_start, t_next, &mut self.y, &mut self.y_try)?;
            }
            Ok(())
        })();
        if result.is_err() {
            self.failed = true;
            return result;
        }
        self.n_steps += 1;
        self.t = t_next;
        onsets(t, &mut self.prev_flags, &self.plant.flags_step, &mut self.events);
        Ok(())
    }

    /// Put the stepper at `(t, y)` within its last step (an event located there,
    /// [`crate::sim::events`]): the run's final sample is then taken there.
    pub(crate) fn land(&mut self, t: f64, y: &[f64]) {
        self.t = t;
        self.y.copy_from_slice(y);
    }

    /// Land at an event located at `t_s` in the last step, which went from `(t_prev, y_prev)` to
    /// `t_next`: the state there is the step re-taken from its start to `t_s` with `rk`
    /// ([`Rk4::step_from`]), or at `t_s = t_next` the step's own end. `y_try` is a workspace.
    pub(crate) fn land_retaken(&mut self, rk: &mut Rk4, (t_prev, y_prev): (f64, &[f64]), t_s: f64, t_next: f64, y_try: &mut [f64]) -> Result<()> {
        if t_s < t_next {
            rk.step_from(&mut self.plant, t_prev, y_prev, t_s, y_try)?;
        } else {
            y_try.copy_from_slice(&self.y);
        }
        self.land(t_s, y_try);
        Ok(())
    }

    /// The current time, s.
    pub fn time(&self) -> f64 {
        self.t
    }

    /// The current state `[x; u]`.
    pub fn state(&self) -> &[f64] {
        let n = self.plant.nx + self.plant.model().nu();
        &self.y[..n]
    }

    /// The free target's 13-state `[r, quat xyzw, v, ω]`, if the plant has one in the loop of
    /// contact ([`crate::sim::free_target`]).
    pub fn target_state(&self) -> Option<&[f64]> {
        self.plant.target_state(&self.y)
    }

    /// The integrator's whole state: `[x; u]`, with contact followed by the contact work.
    pub(crate) fn full_state(&self) -> &[f64] {
        &self.y
    }

    /// The plant's model.
    pub fn model(&self) -> &crate::model::Model {
        self.plant.model()
    }

    /// Joints of the plant.
    pub fn n_dof(&self) -> usize {
        self.plant.model().n_dof()
    }

    /// Accepted steps so far.
    pub fn n_steps(&self) -> usize {
        self.n_steps
    }

    /// The plant (to change its held input between steps).
    pub fn plant_mut(&mut self) -> &mut Plant<'a> {
        &mut self.plant
    }

    /// Whether a step failed (then only a new stepper can go on).
    pub fn failed(&self) -> bool {
        self.failed
    }

    /// Record the final sample (the current state) and return the run's result.
    pub fn finish(mut self) -> Result<SimResult> {
        let rec = match self.recording.take() {
            Some((rec, _)) => rec,
            None => Recorder::for_plant(&self.plant, 1),
        };
        self.result_with(rec)
    }

    /// The result so far, as [`Rk4Stepper::finish`] would return it now, leaving the stepper
    /// able to go on: the records are copied, and the evaluation at the current state (for its
    /// sample) is not counted.
    pub fn snapshot(&mut self) -> Result<SimResult> {
        let rec = match &self.recording {
            Some((rec, _)) => rec.clone(),
            None => Recorder::for_plant(&self.plant, 1),
        };
        let counters = (self.plant.n_evals, self.plant.dropped_max, self.plant.dropped_count);
        let result = self.result_with(rec);
        (self.plant.n_evals, self.plant.dropped_max, self.plant.dropped_count) = counters;
        result
    }

    fn result_with(&mut self, mut rec: Recorder) -> Result<SimResult> {
        if self.failed {
            return Err(SpacearmError::Simulation("a step failed; the simulation has no result".into()));
        }
        self.plant.rhs(self.t, &self.y, &mut self.dy)?;
        rec.record(&self.plant, self.t, &self.y, &self.dy);
        Ok(finish_result(&self.plant, rec, self.events.clone(), self.n_steps, 0))
    }
}
