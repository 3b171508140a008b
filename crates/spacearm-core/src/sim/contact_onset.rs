//! Event-located contact onset for the RK4 steps (docs/contact.md, "Steps and onset"): a step
//! in which a pair of collision shapes starts to touch is re-taken in two, the first ending just
//! before the onset and the second starting there with the new pairs acting as touching, so no
//! step integrates across the jump of a Kelvin–Voigt dashpot's force (`d δ̇` at first touch).
//!
//! The onset is the first root in the step of the smallest signed distance of the new pairs,
//! `g(τ) = min d(y(τ))` with `y(τ)` the RK4 step from the step's start to `τ` (the RK4 dense
//! solution the gap events use, [`crate::sim::events`]), located by [`locate_root`] to a few ulps.

use crate::error::Result;
use crate::math::integrate::Rk4;
use crate::sim::events::locate_root;
use crate::sim::plant::Plant;

/// The pairs of `plant`'s contact touching at `y` (its state `[x; u]`).
fn touching(plant: &mut Plant<'_>, y: &[f64]) -> Result<Vec<(usize, usize)>> {
    let nx = plant.nx;
    match &plant.contact {
        Some(c) => c.touching(&plant.model, &mut plant.data, &y[..nx]),
        None => Ok(Vec::new()),
    }
}

/// The smallest distance of `pairs` at `y`.
fn distance(plant: &mut Plant<'_>, y: &[f64], pairs: &[(usize, usize)]) -> Result<f64> {
    let nx = plant.nx;
    let c = plant.contact.as_ref().expect("a plant with contact");
    c.distance(&plant.model, &mut plant.data, &y[..nx], pairs)
}

/// After an RK4 step from `(t, y_start)` to `(t_next, y)`: if a pair touches at `y` that did not
/// at `y_start`, re-take the step in two at the located onset (module docs), `y` its new end;
/// returns the onset time. `rk` is a workspace; `y_try` one of `y`'s length.
pub(crate) fn retake_at_onset(plant: &mut Plant<'_>, rk: &mut Rk4, t: f64, y_start: &[f64], t_next: f64, y: &mut [f64], y_try: &mut [f64]) -> Result<Option<f64>> {
    if plant.contact.is_none() {
        return Ok(None);
    }
    let before = touching(plant, y_start)?;
    let new: Vec<(usize, usize)> = touching(plant, y)?.into_iter().filter(|p| !before.contains(p)).collect();
    if new.is_empty() {
        return Ok(None);
    }
    let g_start = distance(plant, y_start, &new)?;
    let g_end = distance(plant, y, &new)?;
    if !(g_start > 0.0 && g_end <= 0.0) {
        return Ok(None);
    }
    let mut g_at = |tau: f64| -> Result<f64> {
        rk.step_from(&mut *plant, t, y_start, tau, y_try)?;
        distance(plant, y_try, &new)
    };
    let (t_b, _) = locate_root(&mut g_at, (t, g_start), (t_next, g_end))?;
    // The last time before the onset where the pairs are still apart: a few ulps before t_b.
    let mut back = 4.0 * f64::EPSILON * t_b.abs().max(f64::MIN_POSITIVE);
    let mut t_a = t_b - back;
    while t_a > t && g_at(t_a)? <= 0.0 {
        back *= 2.0;
        t_a = t_b - back;
    }
    if t_a <= t {
        // Touching within ulps of the step's start: the whole step starts at the onset.
        t_a = t;
        y.copy_from_slice(y_start);
    } else {
        rk.step_from(&mut *plant, t, y_start, t_a, y)?;
    }
    if let Some(c) = &mut plant.contact {
        c.forced.clone_from(&new);
    }
    let second = rk.step(&mut *plant, t_a, t_next - t_a, y, false);
    if let Some(c) = &mut plant.contact {
        c.forced.clear();
    }
    second?;
    Ok(Some(t_a))
}
