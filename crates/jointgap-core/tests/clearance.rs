//! Clearance revolute joint: Hertz impact against the closed form, energy conservation
//! across many impacts, and friction acting on both bodies with the right sign.

use jointgap_core::{simulate, Method, Model, SimOptions, SimResult, Status};
use serde_json::{json, Value};

const K: f64 = 3.136e10;
const CLEARANCE: f64 = 0.5e-3;

/// A free journal (body `pin`) in a bearing fixed to the ground at the origin.
fn free_journal(velocity: [f64; 2], omega: f64, gravity: f64, law: Value, friction: Value) -> Model {
    Model::from_json(
        &json!({
            "gravity": [0.0, -gravity],
            "bodies": [{"name": "pin", "mass": 0.72, "inertia": 1e-5, "velocity": velocity, "omega": omega}],
            "joints": [{
                "name": "gap", "type": "clearance_revolute", "body_i": "ground", "point_i": [0.0, 0.0], "body_j": "pin", "point_j": [0.0, 0.0],
                "clearance": {"bearing_radius": 7.5e-3, "clearance": CLEARANCE, "stiffness": K,
                              "normal_law": law, "friction": friction}
            }]
        })
        .to_string(),
    )
    .unwrap()
}

/// Peak penetration `(5 m v0^2 / (4 K))^(2/5)` and duration `2.94 delta_max / v0`
/// (docs/physics.md section 6), within 0.5 %; the rebound is elastic.
#[test]
fn hertz_impact_matches_closed_form() {
    let (m, v0) = (0.72, 0.5);
    let model = free_journal([v0, 0.0], 0.0, 0.0, json!({"type": "hertz"}), json!({"type": "none"}));
    let t_end = 1.5 * CLEARANCE / v0;
    let opts = SimOptions {
        rate: Some(2e7),
        rtol: 1e-9,
        atol: 1e-13,
        method: Method::Dopri5,
        ..SimOptions::new(t_end)
    };
    let res = simulate(&model, &opts).unwrap();
    assert_eq!(res.status, Status::Finished);
    let impacts = &res.impacts[0].impacts;
    assert_eq!(impacts.len(), 1, "{impacts:?}");
    let delta_max = (5.0 * m * v0 * v0 / (4.0 * K)).powf(0.4);
    let pen = res.channel("gap.penetration").unwrap().iter().copied().fold(f64::MIN, f64::max);
    assert!((pen / delta_max - 1.0).abs() < 5e-3, "peak penetration {pen:e} vs {delta_max:e}");
    let imp = &impacts[0];
    assert!((imp.onset_time - CLEARANCE / v0).abs() < 1e-9, "onset at {}", imp.onset_time);
    assert!((imp.onset_speed - v0).abs() < 1e-6 * v0);
    let duration = imp.duration.expect("separated");
    assert!((duration / (2.94 * delta_max / v0) - 1.0).abs() < 5e-3, "duration {duration:e}");
    let peak_force = K * delta_max.powf(1.5);
    assert!(
        (imp.peak_force / peak_force - 1.0).abs() < 5e-3,
        "peak force {} vs {peak_force}",
        imp.peak_force
    );
    let vx = *res.channel("pin.vx").unwrap().last().unwrap();
    assert!((vx + v0).abs() < 1e-6 * v0, "rebound {vx}");
}

/// Elastic contact without friction conserves kinetic plus contact energy over many
/// impacts of an oblique, spinning journal.
#[test]
fn elastic_contact_conserves_energy_over_many_impacts() {
    let model = free_journal([0.3, 0.17], 5.0, 0.0, json!({"type": "hertz"}), json!({"type": "none"}));
    let opts = SimOptions {
        rate: Some(1e5),
        rtol: 1e-10,
        atol: 1e-14,
        method: Method::Dopri5,
        ..SimOptions::new(0.05)
    };
    let res = simulate(&model, &opts).unwrap();
    assert_eq!(res.status, Status::Finished);
    assert!(res.impacts[0].impacts.len() >= 15, "{} impacts", res.impacts[0].impacts.len());
    let ke = res.channel("system.kinetic_energy").unwrap();
    let pe = res.channel("system.potential_energy").unwrap();
    let e0 = ke[0] + pe[0];
    let drift = ke.iter().zip(pe).map(|(k, p)| ((k + p) / e0 - 1.0).abs()).fold(0.0, f64::max);
    assert!(drift < 1e-6, "energy drift {drift:e}");
    // Without friction the journal's spin never changes.
    assert!(res.channel("pin.omega").unwrap().iter().all(|w| (w - 5.0).abs() < 1e-9));
}

/// A heavy spinning journal resting in its bearing: friction opposes the slip, its
/// moment `R_J F_T` is the only torque on the journal, and while sliding fast the
/// ADAMS law gives |F_T| = mu_d F_N.
#[test]
fn coulomb_friction_opposes_slip_and_spins_the_journal_down() {
    let law = json!({"type": "adams_impact", "c_max": 27960.0, "d_max": 1e-5});
    let friction = json!({"type": "coulomb", "mu_s": 0.08, "mu_d": 0.05, "v_s": 1e-4, "v_d": 0.01016});
    let model = free_journal([0.0, 0.0], 40.0, 9.81, law, friction);
    let opts = SimOptions { rate: Some(1e4), rtol: 1e-8, atol: 1e-12, ..SimOptions::new(0.3) };
    let res = simulate(&model, &opts).unwrap();
    assert_eq!(res.status, Status::Finished, "{:?}", res.stats);
    let (fn_, ft, slip) =
        (res.channel("gap.fn").unwrap(), res.channel("gap.ft").unwrap(), res.channel("gap.slip").unwrap());
    let alpha = res.channel("pin.alpha").unwrap();
    let (r_j, inertia) = (7.0e-3, 1e-5);
    let mut sliding = 0;
    for i in 0..res.time.len() {
        assert!(ft[i] * slip[i] <= 0.0, "friction helps the slip at t = {}", res.time[i]);
        assert!(
            (alpha[i] - r_j * ft[i] / inertia).abs() < 1e-6 * (1.0 + alpha[i].abs()),
            "moment at t = {}",
            res.time[i]
        );
        if res.time[i] > 0.05 && slip[i].abs() > 0.02 && fn_[i] > 0.0 {
            sliding += 1;
            assert!((ft[i].abs() / fn_[i] - 0.05).abs() < 1e-9, "mu at t = {}", res.time[i]);
        }
    }
    assert!(sliding > 100, "only {sliding} sliding samples");
}

#[test]
fn bad_clearance_data_is_named() {
    let law = json!({"type": "hertz"});
    let cases = [
        (
            json!({"bearing_radius": 7e-3, "journal_radius": 7.5e-3, "stiffness": K, "normal_law": law}),
            "journal_radius = 0.0075 m must be smaller than bearing_radius = 0.007 m",
        ),
        (
            json!({"bearing_radius": 7.5e-3, "clearance": 1e-2, "stiffness": K, "normal_law": law}),
            "clearance = 0.01 m is not smaller than bearing_radius = 0.0075 m",
        ),
        (
            json!({"bearing_radius": 7.5e-3, "clearance": -1e-4, "stiffness": K, "normal_law": law}),
            "clearance = -0.0001 m must be positive",
        ),
        (
            json!({"bearing_radius": 7.5e-3, "clearance": 5e-4, "normal_law": {"type": "flores", "restitution": 1.2}, "stiffness": K}),
            "restitution = 1.2",
        ),
        (
            json!({"bearing_radius": 7.5e-3, "clearance": 5e-4, "bearing_material": "unobtainium", "journal_material": "steel", "normal_law": law}),
            "'unobtainium' is not in the material library",
        ),
        (
            json!({"bearing_radius": 7.5e-3, "clearance": 5e-4, "stiffness": K, "normal_law": {"type": "adams_impact", "c_max": 1.0, "d_max": 0.0}}),
            "d_max = 0 m must be positive",
        ),
    ];
    for (clearance, expected) in cases {
        let model = json!({
            "bodies": [{"name": "pin", "mass": 1.0, "inertia": 1e-5}],
            "joints": [{"name": "gap", "type": "clearance_revolute", "body_i": "ground", "point_i": [0.0, 0.0], "body_j": "pin", "point_j": [0.0, 0.0], "clearance": clearance}]
        });
        let err = simulate(&Model::from_json(&model.to_string()).unwrap(), &SimOptions::new(0.01))
            .unwrap_err()
            .to_string();
        assert!(err.contains("joint 'gap'") && err.contains(expected), "{err}\n expected {expected}");
    }
    let model = json!({
        "bodies": [{"name": "pin", "mass": 1.0, "inertia": 1e-5}],
        "joints": [{"name": "gap", "type": "clearance_revolute", "body_i": "pin", "point_i": [0.0, 0.0], "body_j": "pin", "point_j": [0.0, 0.0],
                    "clearance": {"bearing_radius": 7.5e-3, "clearance": 5e-4, "stiffness": K, "normal_law": law}}]
    });
    let err = simulate(&Model::from_json(&model.to_string()).unwrap(), &SimOptions::new(0.01))
        .unwrap_err()
        .to_string();
    assert!(err.contains("joint 'gap': connects body 'pin' to itself"), "{err}");
}

/// A run that fails midway still reports what it spent, Jacobians of the implicit
/// method included.
#[test]
fn failed_run_reports_its_counters() {
    let law = json!({"type": "adams_impact", "c_max": 27960.0, "d_max": 1e-5});
    let friction = json!({"type": "coulomb", "mu_s": 0.08, "mu_d": 0.05, "v_s": 1e-4, "v_d": 0.01016});
    let model = free_journal([0.0, 0.0], 40.0, 9.81, law, friction);
    let opts = SimOptions { method: Method::Sdirk4, max_steps: Some(50), ..SimOptions::new(0.3) };
    let res = simulate(&model, &opts).unwrap();
    assert!(matches!(res.status, Status::Failed { .. }), "{:?}", res.status);
    assert_eq!(res.stats.accepted_steps + res.stats.rejected_steps, 50);
    assert!(res.stats.jacobian_evaluations > 0, "{:?}", res.stats);
    assert_eq!(res.stats.method, "sdirk4");
}

/// The friction rate that `auto` reads is the law's damping `|dF_T/dv_t|` times the
/// slip's inverse mass through the constraints. A bar pinned to the ground at A with its
/// journal in a ground bearing can only turn about A, so that inverse mass is
/// `cross(P - A, t)^2 / I_A` (P the contact point, t the tangent, I_A the inertia about A).
#[test]
fn friction_rate_is_damping_over_the_slip_mass_through_the_constraints() {
    use jointgap_core::dynamics::{accelerations, Contacts, Workspace};
    use jointgap_core::mechanics::contact::ClearanceJoint;
    use jointgap_core::mechanics::planar::Planar;
    let (length, mass, inertia) = (0.3, 0.72, 0.0069);
    let (clearance, depth, angle) = (CLEARANCE, 2e-6, 30f64.to_radians());
    let n = [angle.cos(), angle.sin()];
    // Bearing centre placed so that the journal (at the bar's end) sinks `depth` along n.
    let centre = [length - (clearance + depth) * n[0], -(clearance + depth) * n[1]];
    let friction = json!({"type": "coulomb", "mu_s": 0.08, "mu_d": 0.05, "v_s": 1e-4, "v_d": 0.01016});
    let model = Model::from_json(
        &json!({
            "gravity": [0.0, 0.0],
            "ground_points": {"A": [0.0, 0.0], "G": centre},
            "bodies": [{"name": "bar", "mass": mass, "inertia": inertia, "position": [length / 2.0, 0.0],
                        "points": {"A": [-length / 2.0, 0.0], "B": [length / 2.0, 0.0]}}],
            "joints": [
                {"name": "pin", "type": "revolute", "body_i": "ground", "point_i": "A",
                 "body_j": "bar", "point_j": "A"},
                {"name": "gap", "type": "clearance_revolute", "body_i": "ground", "point_i": "G",
                 "body_j": "bar", "point_j": "B",
                 "clearance": {"bearing_radius": 7.5e-3, "clearance": clearance, "stiffness": K,
                               "normal_law": {"type": "hertz"}, "friction": friction}}
            ]
        })
        .to_string(),
    )
    .unwrap();
    let prepared = jointgap_core::simulate::prepare(&model).unwrap();
    let sys = &prepared.system;
    let q = prepared.initial.q.clone();
    let i_a = inertia + mass * (length / 2.0).powi(2);
    let gap = &sys.clearances[0];
    let r_journal = gap.journal_bearing().expect("a journal in its bearing").r_journal;
    // Contact point P = B + r_j n; tangent t = perp(n); slip = omega cross(P - A, t).
    let p = [length + r_journal * n[0], r_journal * n[1]];
    let lever = p[0] * n[0] + p[1] * n[1];
    for slip in [3e-5, -8e-5, 2e-3, 0.5] {
        let omega = slip / lever;
        let v = vec![0.0, omega * length / 2.0, omega];
        let mut ws = Workspace::new(sys, prepared.initial.active.clone());
        accelerations(sys, 0.0, &q, &v, &mut ws).unwrap();
        let [bearing, journal] = gap.parts().map(|b| sys.body_state(b, &q, &v));
        let points = gap.contacts(&bearing, &journal, f64::INFINITY);
        let kin = points[0];
        assert!((kin.penetration - depth).abs() < 1e-12, "penetration {}", kin.penetration);
        assert!((kin.slip[0] - slip).abs() < 1e-9 * slip.abs().max(1e-3), "slip {} vs {slip}", kin.slip[0]);
        let (f_n, _) = gap.force(&kin, kin.penetration_rate);
        let expected = gap.friction().damping(slip, f_n) * lever * lever / i_a;
        let rate = Planar::friction_rate(sys, &q, &v, &points[..], 0.0, &mut ws);
        assert!((rate - expected).abs() <= 1e-9 * expected.max(1e-300), "slip {slip}: {rate} vs {expected}");
        // Where no rate tells the switching rule anything, the bound without the pin.
        let bound = Planar::friction_rate(sys, &q, &v, &points[..], f64::INFINITY, &mut ws);
        if slip.abs() > 0.01016 {
            assert_eq!((rate, bound), (0.0, 0.0), "no damping while sliding");
        } else {
            // Without the pin the inverse mass would be 1/m + cross(P - G, t)^2 / I, 30 % more.
            let free = 1.0 / mass + (lever - length / 2.0 * n[0]).powi(2) / inertia;
            let unpinned = gap.friction().damping(slip, f_n) * free;
            assert!(rate < 0.8 * unpinned, "{rate} vs free {free}");
            assert!((bound - unpinned).abs() <= 1e-9 * unpinned, "bound {bound} vs {unpinned}");
            // A rate that decides is exact: just below it, the pinned rate again.
            let decides = 0.999 * rate;
            assert_eq!(Planar::friction_rate(sys, &q, &v, &points[..], decides, &mut ws), rate);
        }
    }
}

/// Sticking friction hands `auto`'s steps to Radau IIA (switching.rs): on the founding
/// case auto names the sticking phases in its method line, needs far fewer force
/// evaluations than DOPRI5 at the same tolerance (measured at rtol 1e-8: 61.5k against
/// 104k), and is as close to a tight DOPRI5 run as DOPRI5 itself (NRMSE of slider.ax
/// 1.7e-5 and 1.5e-5).
#[test]
fn sticking_friction_hands_auto_to_radau5() {
    let model = common::slider_crank_clearance();
    let run = |method: Method, rtol: f64| {
        let o = SimOptions { rate: Some(10_000.0), rtol, atol: 1e-3 * rtol, method, ..SimOptions::new(0.5) };
        let res = simulate(&model, &o).unwrap();
        assert_eq!(res.status, Status::Finished, "{method:?} {rtol}");
        res
    };
    let reference = run(Method::Dopri5, 1e-11);
    let ax_ref = reference.channel("slider.ax").unwrap();
    let range =
        ax_ref.iter().fold(f64::MIN, |a, &b| a.max(b)) - ax_ref.iter().fold(f64::MAX, |a, &b| a.min(b));
    let nrmse = |res: &SimResult| {
        let ax = res.channel("slider.ax").unwrap();
        let sum: f64 = ax.iter().zip(ax_ref).map(|(a, b)| (a - b).powi(2)).sum();
        (sum / ax.len() as f64).sqrt() / range
    };
    let auto = run(Method::Auto, 1e-8);
    let explicit = run(Method::Dopri5, 1e-8);
    assert!(auto.stats.method.contains("radau5 for sticking friction"), "{}", auto.stats.method);
    let (ea, ed) = (auto.stats.rhs_evaluations, explicit.stats.rhs_evaluations);
    assert!(4 * ea < 3 * ed, "auto {ea} evaluations, dopri5 {ed}");
    assert!(nrmse(&auto) < 1e-4 && nrmse(&explicit) < 1e-4, "{} {}", nrmse(&auto), nrmse(&explicit));
}

use crate::common;

/// A journal thrown up inside its bearing that just reaches the wall at the top of its
/// flight (apex penetration `eps c`): the brief contact at the apex is found at the
/// parabola's crossing time, with the parabola's vertical speed there, however long the
/// free-flight steps around it are.
#[test]
fn grazing_contact_at_the_apex_is_found() {
    let g = 9.81;
    for (eps, method) in [(1e-3, Method::Dopri5), (1e-6, Method::Dopri5), (1e-6, Method::Radau5)] {
        let v0 = (2.0 * g * CLEARANCE * (1.0 + eps)).sqrt();
        let model = free_journal([0.0, v0], 0.0, g, json!({"type": "hertz"}), json!({"type": "none"}));
        let opts = SimOptions { rate: Some(100.0), rtol: 1e-6, atol: 1e-10, method, ..SimOptions::new(0.02) };
        let res = simulate(&model, &opts).unwrap();
        assert_eq!(res.status, Status::Finished);
        let impacts = &res.impacts[0].impacts;
        assert_eq!(impacts.len(), 1, "eps {eps}, {method:?}: {impacts:?}");
        let onset_speed = (v0 * v0 - 2.0 * g * CLEARANCE).sqrt();
        let onset_time = (v0 - onset_speed) / g;
        let imp = &impacts[0];
        assert!((imp.onset_time - onset_time).abs() < 1e-9, "eps {eps}: onset at {}", imp.onset_time);
        assert!(
            (imp.onset_speed / onset_speed - 1.0).abs() < 1e-3,
            "eps {eps}: onset speed {} vs {onset_speed}",
            imp.onset_speed
        );
    }
}
