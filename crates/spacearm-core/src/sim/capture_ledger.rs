//! The momentum ledger of a capture (docs/capture.md, "Momentum ledger"): `P` and `L` about the
//! origin of 𝒥 of robot + target at every recorded sample, and their drift by the one definition
//! of drift ([`conserved_drift`], docs/simulation-core.md) against the largest sum of the bodies'
//! own momentum magnitudes, robot and target ([`momentum_scales`]).
//!
//! While the target is free its momentum is added to the robot's; once it is a link of the
//! captured system (`combined`), the captured model's momentum already holds its share.

use crate::algorithms::momentum::{conserved_drift, momentum, momentum_scales};
use crate::error::Result;
use crate::model::{Data, Model};

/// `P`, `L` (row-major, 3 per sample) and their drifts.
#[derive(Debug, Clone, PartialEq)]
pub struct Ledger {
    /// Linear momentum of robot + target, N·s.
    pub p: Vec<f64>,
    /// Angular momentum of robot + target about the origin of 𝒥, N·m·s.
    pub l: Vec<f64>,
    /// Drift of `P` (relative).
    pub drift_p: f64,
    /// Drift of `L` (relative).
    pub drift_l: f64,
    /// The scale of `P`'s drift (the largest `Σ |pᵢ|` over the samples), N·s.
    pub scale_p: f64,
    /// The scale of `L`'s drift, N·m·s.
    pub scale_l: f64,
}

/// The ledger of the samples `(x, u)` of the robot (rows of `robot.nx()`, `robot.nu()`) and `s`
/// of a rigid target (rows of 13): at a sample with `combined[k]` the state is `captured`'s (the
/// robot with the target attached), else the robot's and the free target's.
pub fn ledger(robot: &Model, captured: &Model, target: &Model, x: &[f64], u: &[f64], s: &[f64], combined: &[bool]) -> Result<Ledger> {
    let (nx, nu) = (robot.nx(), robot.nu());
    let (tx, tu) = (target.nx(), target.nu());
    let (mut dr, mut dc, mut dt) = (Data::new(robot), Data::new(captured), Data::new(target));
    let n = combined.len();
    let (mut p, mut l) = (Vec::with_capacity(3 * n), Vec::with_capacity(3 * n));
    let (mut scale_p, mut scale_l) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    for (k, &comb) in combined.iter().enumerate() {
        let (xk, uk) = (&x[k * nx..(k + 1) * nx], &u[k * nu..(k + 1) * nu]);
        let (owner, d) = if comb { (captured, &mut dc) } else { (robot, &mut dr) };
        let h = momentum(owner, d, xk, uk)?;
        let sc = momentum_scales(owner, d, xk, uk)?;
        let (mut pk, mut lk, mut sp, mut sl) = (h.linear, h.angular_about_origin, sc.linear, sc.angular_about_origin);
        if !comb {
            let sk = &s[k * (tx + tu)..(k + 1) * (tx + tu)];
            let ht = momentum(target, &mut dt, &sk[..tx], &sk[tx..])?;
            let st = momentum_scales(target, &mut dt, &sk[..tx], &sk[tx..])?;
            pk += ht.linear;
            lk += ht.angular_about_origin;
            sp += st.linear;
            sl += st.angular_about_origin;
        }
        p.extend_from_slice(pk.as_slice());
        l.extend_from_slice(lk.as_slice());
        scale_p = scale_p.max(sp);
        scale_l = scale_l.max(sl);
    }
    Ok(Ledger { drift_p: conserved_drift(&p, 3, scale_p), drift_l: conserved_drift(&l, 3, scale_l), p, l, scale_p, scale_l })
}
