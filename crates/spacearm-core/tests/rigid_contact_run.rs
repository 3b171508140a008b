//! Rigid frictional contact in a run (sim/rigid_contact.rs) through the run description: a
//! `[contact]` table with `kind = "rigid"` of the options TOML that the C stepper and an FMU read,
//! against the closed form of the central impact of two free bodies with Newton's restitution:
//! `v_rel⁺ = −e v_rel⁻`, normal impulse `(1 + e) m_r v_rel⁻` — or, found interpenetrating by `δ`,
//! at least the stabilization's push-out `β δ / h`.

mod common;

use common::balls;
use spacearm_core::control::ZeroTorque;
use spacearm_core::sim::options::RunSpec;
use spacearm_core::sim::simulate::simulate;

#[test]
fn a_rigid_contact_table_rebounds_at_the_closed_form_speed() {
    let model = balls();
    let (v0, m_r) = (0.5, 100.0 / 101.0);
    for (e, margin) in [(1.0, 1e-3), (0.5, 1e-3), (0.0, 1e-3), (1.0, 0.0), (0.1, 0.0), (0.0, 0.0)] {
        let text = format!("dt = 1e-4\n[contact]\nkind = \"rigid\"\npairs = [[\"base\", \"slider\"]]\nrestitution = {e}\nmargin = {margin}\n");
        let spec: RunSpec = toml::from_str(&text).unwrap();
        let opts = spec.options(0.03).unwrap();
        let x0 = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.50623]; // touching at t = 0.01246 s
        let u0 = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -v0];
        let r = simulate(&model, &x0, &u0, &opts, &mut ZeroTorque, &mut |_| Ok(())).unwrap();
        let rec = &r.records;
        let last = rec.n_samples - 1;
        let qd = rec.u[7 * last + 6];
        // Found apart (margin > v0 dt), the balls turn before they touch; found interpenetrating
        // by δ (margin 0: δ = 2e-5 m, the step's start 0.49998), they leave at least at the
        // stabilization's β δ / h (β = 0.2: 0.04 m/s), which e = 0 shows.
        let q_min = (0..rec.n_samples).map(|k| rec.x[8 * k + 7]).fold(f64::INFINITY, f64::min);
        let depth = (0.5 - q_min).max(0.0);
        assert!(if margin > 0.0 { depth < 1e-12 } else { (depth - 2e-5).abs() < 1e-12 }, "q_min {q_min}");
        let after = (e * v0).max(0.2 * depth / 1e-4);
        assert!((qd - after).abs() < 1e-9, "e = {e}, margin {margin}: q̇ after {qd}, closed form {after}");
        let imp = &rec.contact_impulse.as_ref().unwrap()[3 * last..3 * last + 3];
        assert!((imp[0] - m_r * (v0 + after)).abs() < 1e-9 && imp[1].abs() < 1e-15 && imp[2].abs() < 1e-15, "impulse {imp:?}");
        // The work of the impulses: the relative motion's kinetic energy change ½ m_r (v⁺² − v0²);
        // the system's momentum is kept.
        let w = *rec.contact_work.as_ref().unwrap().last().unwrap();
        assert!((w - 0.5 * m_r * (after * after - v0 * v0)).abs() < 1e-9, "W = {w}");
        assert!(r.drift.iter().all(|(_, d)| *d < 1e-14), "{:?}", r.drift);
    }
}
