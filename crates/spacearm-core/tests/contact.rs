//! Compliant contact through the run description (sim/contact.rs, collision/compliant.rs): a
//! `[contact]` table of the options TOML that the C stepper and an FMU read, run by the core's
//! loop, against the closed form of the linear spring–dashpot impact without pull
//! (docs/contact.md): restitution `e = exp(−ζ (π − 2 asin ζ)/√(1 − ζ²))`.

mod common;

use common::balls;
use spacearm_core::control::ZeroTorque;
use spacearm_core::sim::options::RunSpec;
use spacearm_core::sim::simulate::simulate;

#[test]
fn a_contact_table_runs_the_closed_form_impact_in_both_integrators() {
    let model = balls();
    let (k, v0, m_r, zeta): (f64, f64, f64, f64) = (1e4, 0.5, 100.0 / 101.0, 0.2);
    let d = 2.0 * zeta * (k * m_r).sqrt();
    let e = (-zeta * (std::f64::consts::PI - 2.0 * f64::asin(zeta)) / (1.0 - zeta * zeta).sqrt()).exp();
    for integrator in ["rk4", "dopri5"] {
        let text = format!(
            "integrator = \"{integrator}\"\ndt = 2e-5\nrtol = 1e-11\natol = 1e-13\n[contact]\npairs = [[\"base\", \"slider\"]]\nstiffness = {k}\ndamping = {d}\n"
        );
        let spec: RunSpec = toml::from_str(&text).unwrap();
        let opts = spec.options(0.06).unwrap();
        let x0 = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.507013]; // onset at t = 0.014026 s, within a step
        let u0 = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -v0];
        let r = simulate(&model, &x0, &u0, &opts, &mut ZeroTorque, &mut |_| Ok(())).unwrap();
        let last = r.records.u.len() - 1;
        let e_run = r.records.u[last] / v0;
        assert!((e_run / e - 1.0).abs() < 1e-6, "{integrator}: e = {e_run}, closed form {e}");
        // The work of the contact forces is the relative motion's lost energy, ½ m_r v0² (1 − e²).
        let w = *r.records.contact_work.as_ref().unwrap().last().unwrap();
        assert!((w / (-0.5 * m_r * v0 * v0 * (1.0 - e * e)) - 1.0).abs() < 1e-6, "{integrator}: W = {w}");
        assert!(r.records.contact_normal_force.as_ref().unwrap().iter().any(|&f| f > 10.0));
    }
}

#[test]
fn contact_names_are_resolved_on_the_model_with_the_cores_message() {
    let model = balls();
    let spec: RunSpec = toml::from_str("[contact]\npairs = [[\"base\", \"hand\"]]\nstiffness = 1e4\n").unwrap();
    let opts = spec.options(0.01).unwrap();
    let x0 = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0];
    let err = simulate(&model, &x0, &[0.0; 7], &opts, &mut ZeroTorque, &mut |_| Ok(())).unwrap_err().to_string();
    assert!(err.contains("no body or collision geometry named 'hand'"), "{err}");
    let spec: RunSpec = toml::from_str("[contact]\nstiffness = -1.0\n").unwrap();
    assert!(spec.options(0.01).unwrap_err().to_string().contains("contact stiffness"));
}
