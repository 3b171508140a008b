//! The one entry of a run (docs/architecture.md, "A run is data"): the run's description
//! ([`SimOptions`], from [`crate::sim::options::RunSpec`]), its controller, and optionally a free
//! target and topology events — the core decides which loop runs, so that no door chooses:
//!
//! - neither: the simulation loop ([`simulate`]);
//! - a free target without events: the loop with the target integrated in it under the run's
//!   contact ([`simulate_with_target`], docs/contact.md, "Contact with a free target"; contact
//!   required);
//! - events (with or without a target, with or without contact): the run of segments between
//!   the events ([`simulate_with_events`], docs/events.md).

use crate::error::{Result, SpacearmError};
use crate::model::Model;
use crate::sim::options::SimOptions;
use crate::sim::result::SimResult;
use crate::sim::simulate::{simulate, simulate_with_target, Progress};
use crate::sim::topology::{simulate_with_events, ControllerFactory, TopologyEvent, TopologyRun};

/// What a run gives back: the records of a plain run, or those of a run with a second system
/// (its rows, the ledger, the events that happened).
#[derive(Debug, Clone)]
#[allow(clippy::large_enum_variant)]
pub enum RunOutput {
    /// A run of the robot alone.
    Plain(SimResult),
    /// A run with a free target or topology events.
    WithTarget(TopologyRun),
}

/// What a run is given: the robot and its initial state, the run's options, and optionally a
/// free target at its 13-state and topology events (module docs).
#[derive(Clone, Copy)]
pub struct RunInput<'a> {
    /// The robot.
    pub robot: &'a Model,
    /// Its initial configuration (7+N).
    pub x0: &'a [f64],
    /// Its initial velocity (6+N).
    pub u0: &'a [f64],
    /// The run's options (a run of `opts.duration`).
    pub opts: &'a SimOptions,
    /// The free target's model and 13-state, if any.
    pub target: Option<(&'a Model, &'a [f64])>,
    /// The topology events, in order (empty: none).
    pub events: &'a [TopologyEvent],
}

/// Run `input` with the controller `controller` builds (on the model of each segment; the
/// robot's alone: once), reporting to `progress` (module docs).
pub fn run(input: RunInput<'_>, controller: ControllerFactory<'_>, progress: Progress<'_>) -> Result<RunOutput> {
    let RunInput { robot, x0, u0, opts, target, events } = input;
    match (target, events.is_empty()) {
        (None, true) => {
            let mut c = controller(robot)?;
            Ok(RunOutput::Plain(simulate(robot, x0, u0, opts, c.as_mut(), progress)?))
        }
        (Some((model, state)), true) => {
            if opts.contact.is_none() {
                return Err(SpacearmError::argument(
                    "a free target without topology events takes part in a run by contact: give contact=ContactModel(...) too (or events=[...] to attach it)",
                ));
            }
            let mut c = controller(robot)?;
            let mut result = simulate_with_target(robot, x0, u0, opts, c.as_mut(), model, state, progress)?;
            let r = &mut result.records;
            let n = r.n_samples;
            let take = |v: &mut Option<Vec<f64>>| v.take().ok_or_else(|| SpacearmError::Simulation("a run with a free target records its rows".into()));
            let (target, ledger_momentum, ledger_energy) = (take(&mut r.target_state)?, take(&mut r.ledger_momentum)?, take(&mut r.ledger_energy)?);
            Ok(RunOutput::WithTarget(TopologyRun {
                result,
                target,
                attached: vec![false; n],
                phase: vec![0; n],
                ledger_momentum,
                ledger_energy,
                events: Vec::new(),
                final_model: robot.clone(),
            }))
        }
        _ => Ok(RunOutput::WithTarget(simulate_with_events(robot, x0, u0, opts, controller, target, events, progress)?)),
    }
}
