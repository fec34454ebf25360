//! Energy accounts: the work of drivers and loads and the energy dissipated, against
//! closed forms, and the balance `T + V - W_in + D`, which stays at its initial value.

use crate::common;

use jointgap_core::{simulate, Model, SimOptions, SimResult, Status};
use serde_json::json;

const ACCOUNTS: [&str; 5] = [
    "system.driver_work",
    "system.load_work",
    "system.damper_dissipation",
    "system.contact_dissipation",
    "system.friction_dissipation",
];

fn run(model: &Model, t_end: f64, rtol: f64, energy: bool) -> SimResult {
    let mut opts = SimOptions::new(t_end);
    opts.rate = Some(1e4);
    opts.rtol = rtol;
    opts.atol = 1e-14;
    opts.energy = energy;
    let r = simulate(model, &opts).unwrap();
    assert_eq!(r.status, Status::Finished);
    r
}

fn channel<'a>(r: &'a SimResult, name: &str) -> &'a [f64] {
    r.channel(name).unwrap_or_else(|| panic!("no channel {name}"))
}

/// Largest change of the balance over the run, and the energy scale: the largest
/// kinetic energy, work or dissipation.
fn balance_drift(r: &SimResult) -> (f64, f64) {
    let b = channel(r, "system.energy_balance");
    let drift = b.iter().map(|x| (x - b[0]).abs()).fold(0.0, f64::max);
    let scale = ACCOUNTS
        .iter()
        .chain(&["system.kinetic_energy"])
        .flat_map(|name| channel(r, name).iter())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    (drift, scale)
}

/// The founding case with a clearance, 0.2 s (the ramp, with its impacts): the balance
/// holds to 1e-8 of the energy scale, and the contact loses energy at every step.
#[test]
fn balance_holds_over_a_damped_contact_run() {
    let r = run(&common::slider_crank_clearance(), 0.2, 1e-11, true);
    let (drift, scale) = balance_drift(&r);
    assert!(drift < 1e-8 * scale, "balance moves by {drift:e} J of {scale:e} J");
    assert!(scale > 5.0, "scale {scale}");
    for name in ["system.contact_dissipation", "system.friction_dissipation"] {
        let d = channel(&r, name);
        assert!(d.windows(2).all(|w| w[1] >= w[0] - 1e-15), "{name} decreases");
        // Dissipation large against the balance's error: the test would see it missing.
        assert!(d[d.len() - 1] > 1e4 * drift, "{name} = {:e} J", d[d.len() - 1]);
    }
    // The motor puts in what the mechanism holds and what the contact lost.
    let last = |name: &str| channel(&r, name)[r.time.len() - 1];
    let kept = last("system.kinetic_energy") + last("system.potential_energy")
        - channel(&r, "system.potential_energy")[0];
    let lost = last("system.contact_dissipation") + last("system.friction_dissipation");
    assert!((last("system.driver_work") - kept - lost).abs() < 1e-8 * scale);
    assert_eq!(last("system.load_work"), 0.0);
    assert_eq!(last("system.damper_dissipation"), 0.0);
}

/// The ideal slider-crank: the balance holds, and the drivers' work equals the integral
/// of the recorded torque times the crank speed (Simpson's rule on the samples, a
/// check of its sign and size written apart from the engine's quadrature).
#[test]
fn balance_holds_on_the_ideal_driven_run() {
    let r = run(&common::slider_crank(9.81), 0.5, 1e-11, true);
    let (drift, scale) = balance_drift(&r);
    assert!(drift < 1e-8 * scale, "balance moves by {drift:e} J of {scale:e} J");
    let (tau, omega) = (channel(&r, "motor.torque"), channel(&r, "crank.omega"));
    let h = 1e-4;
    // Simpson's rule from t = 0.2 s (the ramp's corner, where the torque jumps) to 0.45 s
    // (crank half a turn from its start: the gravity potential differs).
    let (a, b) = (2000, 4500);
    let p = |i: usize| tau[i] * omega[i];
    let simpson = h / 3.0
        * (p(a) + p(b) + (a + 1..b).map(|i| if (i - a) % 2 == 1 { 4.0 } else { 2.0 } * p(i)).sum::<f64>());
    let work = channel(&r, "system.driver_work");
    let engine = work[b] - work[a];
    assert!((engine - simpson).abs() < 1e-7 * scale, "{engine} J against {simpson} J");
    assert!(engine.abs() > 0.1, "{engine}");
}

/// Keeping the accounts does not change the motion: every other channel is bit for bit
/// that of a run without them.
#[test]
fn accounts_leave_the_motion_unchanged() {
    let model = common::slider_crank_clearance();
    let with = run(&model, 0.05, 1e-8, true);
    let without = run(&model, 0.05, 1e-8, false);
    assert_eq!(with.time, without.time);
    assert_eq!(with.names.len(), without.names.len() + ACCOUNTS.len() + 1);
    for (k, name) in without.names.iter().enumerate() {
        assert_eq!(channel(&with, name), without.data[k].as_slice(), "{name}");
    }
    assert_eq!(with.stats.accepted_steps, without.stats.accepted_steps);
}

/// A block on a spring-damper along a slide, a rotor on a torsion spring-damper, and a
/// free puck pushed by a constant force and torque, no gravity: the dampers dissipate
/// what the closed-form damped vibrations lose, and the loads do the work
/// `|F|^2 t^2 / (2 m) + tau^2 t^2 / (2 J)` of a body accelerated from rest.
#[test]
fn loads_and_dampers_against_closed_forms() {
    let (m, k, c, u0) = (2.0, 800.0, 6.0, 0.03);
    let (j, kr, cr, a0) = (0.05, 30.0, 0.2, 0.4);
    let (mp, jp, f, tau) = (1.5, 0.02, [3.0, -4.0], 0.7);
    let free_length = 0.2;
    let model = Model::from_json(
        &json!({
            "gravity": [0.0, 0.0],
            "bodies": [
                {"name": "block", "mass": m, "inertia": 0.01, "position": [free_length + u0, 0.0]},
                {"name": "rotor", "mass": 1.0, "inertia": j, "position": [0.0, 1.0], "angle": a0},
                {"name": "puck", "mass": mp, "inertia": jp, "position": [0.0, -1.0],
                 "points": {"edge": [0.1, 0.0]}}
            ],
            "ground_points": {"O": [0.0, 0.0], "P": [0.0, 1.0]},
            "joints": [
                {"name": "slide", "type": "prismatic", "body_i": "ground", "point_i": "O",
                 "body_j": "block", "point_j": [0.0, 0.0], "axis": [1.0, 0.0]},
                {"name": "pivot", "type": "revolute", "body_i": "ground", "point_i": "P",
                 "body_j": "rotor", "point_j": [0.0, 0.0]}
            ],
            "forces": [
                {"name": "spring", "type": "spring_damper", "body_i": "ground", "point_i": "O",
                 "body_j": "block", "point_j": [0.0, 0.0], "stiffness": k, "damping": c,
                 "free_length": free_length},
                {"name": "torsion", "type": "rotational_spring_damper", "body_i": "ground",
                 "body_j": "rotor", "stiffness": kr, "damping": cr},
                {"name": "push", "type": "applied_force", "body": "puck", "point": [0.0, 0.0], "force": f},
                {"name": "twist", "type": "applied_torque", "body": "puck", "torque": tau}
            ]
        })
        .to_string(),
    )
    .unwrap();
    let r = run(&model, 0.5, 1e-11, true);
    // Energy an underdamped oscillator x'' + 2 s x' + w0^2 x = 0 from (x0, 0) has lost.
    let lost = |mass: f64, stiffness: f64, damping: f64, x0: f64, t: f64| {
        let s = damping / (2.0 * mass);
        let w0sq = stiffness / mass;
        let wd = (w0sq - s * s).sqrt();
        let e = (-s * t).exp();
        let x = x0 * e * ((wd * t).cos() + s / wd * (wd * t).sin());
        let v = -x0 * w0sq / wd * e * (wd * t).sin();
        0.5 * stiffness * x0 * x0 - 0.5 * mass * v * v - 0.5 * stiffness * x * x
    };
    let f2 = f[0] * f[0] + f[1] * f[1];
    let (dissipated, work) = (channel(&r, "system.damper_dissipation"), channel(&r, "system.load_work"));
    let e0 = 0.5 * k * u0 * u0 + 0.5 * kr * a0 * a0;
    for (i, &t) in r.time.iter().enumerate() {
        let expected = lost(m, k, c, u0, t) + lost(j, kr, cr, a0, t);
        assert!(
            (dissipated[i] - expected).abs() < 1e-9 * e0,
            "t = {t}: {} J against {expected} J",
            dissipated[i]
        );
        let pushed = f2 * t * t / (2.0 * mp) + tau * tau * t * t / (2.0 * jp);
        assert!(
            (work[i] - pushed).abs() < 1e-9 * pushed.max(1e-3),
            "t = {t}: {} J against {pushed} J",
            work[i]
        );
    }
    assert!(dissipated[r.time.len() - 1] > 0.5 * e0);
    let (drift, scale) = balance_drift(&r);
    assert!(drift < 1e-9 * scale, "balance moves by {drift:e} J of {scale:e} J");
}

/// Without the option the accounts are no channels, and asking for one says how to get it.
#[test]
fn accounts_are_kept_only_when_asked() {
    let model = common::slider_crank(9.81);
    let r = run(&model, 0.01, 1e-8, false);
    assert!(r.channel("system.energy_balance").is_none());
    let mut opts = SimOptions::new(0.01);
    opts.channels = Some(vec!["system.energy_balance".into()]);
    let err = simulate(&model, &opts).unwrap_err().to_string();
    assert!(err.contains("option energy"), "{err}");
    opts.energy = true;
    let r = simulate(&model, &opts).unwrap();
    assert_eq!(r.names, ["system.energy_balance"]);
}
