//! A run never reports a non-finite number as finished, and a model whose initial state
//! no mechanism can have is an error before the run: numbers that overflow at t = 0 or
//! during the run, and a clearance joint's journal deep in its bearing wall.

use crate::common;

use jointgap_core::simulate::{check, prepare};
use jointgap_core::{simulate, Model, SimOptions, Status};
use serde_json::{json, Value};

/// The founding clearance slider-crank with one field of one element replaced.
fn founding_with(kind: &str, name: &str, key: &str, value: Value) -> Model {
    let mut raw = serde_json::to_value(common::slider_crank_clearance()).unwrap();
    let element = raw[kind].as_array_mut().unwrap().iter_mut().find(|e| e["name"] == name).unwrap();
    element[key] = value;
    serde_json::from_value(raw).unwrap()
}

fn error_of(model: &Model, opts: &SimOptions) -> String {
    match simulate(model, opts) {
        Ok(r) => panic!("expected an error, got a run with status {:?}", r.status),
        Err(e) => e.to_string(),
    }
}

/// A crank of inertia 5e305 kg m^2 turns at omega = W t / T_RAMP during the ramp, so its
/// kinetic energy J omega^2 / 2 passes the largest double at t* = T_RAMP / W
/// sqrt(2 f64::MAX / J) = 0.171 s, while every other channel stays finite (the motor torque
/// J alpha = 7.9e307 N m). The run stops at the first sample after t*, names the channel,
/// and keeps the samples before it, all finite.
#[test]
fn an_overflow_during_the_run_stops_it_naming_the_channel() {
    let inertia = 5e305;
    let model = founding_with("bodies", "crank", "inertia", json!(inertia));
    let rate = 1000.0;
    let res = simulate(&model, &SimOptions { rate: Some(rate), ..SimOptions::new(0.3) }).unwrap();
    let t_star = common::T_RAMP / common::W * (f64::MAX / inertia).sqrt() * 2f64.sqrt();
    let Status::Failed { time, reason } = &res.status else { panic!("finished: {:?}", res.status) };
    assert!(*time >= t_star && *time <= t_star + 1.0 / rate + 1e-9, "failed at {time}, t* = {t_star}");
    assert!(reason.contains("system.kinetic_energy = inf"), "{reason}");
    assert!(reason.contains("check the magnitudes and units"), "{reason}");
    let last = *res.time.last().unwrap();
    assert!(last < t_star && last > t_star - 1.0 / rate - 1e-9, "last sample {last}");
    assert_eq!(res.time.len(), (last * rate).round() as usize + 1);
    assert!(res.data.iter().flatten().all(|x| x.is_finite()));
}

/// The same with every step recorded: the step's own sample stops it.
#[test]
fn an_overflow_stops_an_every_step_run_too() {
    let model = founding_with("bodies", "crank", "inertia", json!(5e305));
    let res = simulate(&model, &SimOptions::new(0.3)).unwrap();
    let Status::Failed { reason, .. } = &res.status else { panic!("finished: {:?}", res.status) };
    assert!(reason.contains("system.kinetic_energy = inf"), "{reason}");
    assert!(res.data.iter().flatten().all(|x| x.is_finite()));
}

/// A channel that is not recorded is not computed, so it cannot stop the run: with the
/// kinetic energy left out the same run finishes.
#[test]
fn only_recorded_channels_are_checked() {
    let model = founding_with("bodies", "crank", "inertia", json!(5e305));
    let opts =
        SimOptions { rate: Some(1000.0), channels: Some(vec!["slider.*".into()]), ..SimOptions::new(0.3) };
    let res = simulate(&model, &opts).unwrap();
    assert_eq!(res.status, Status::Finished);
}

/// A mass whose weight overflows is an error naming the body; so is an inertia whose
/// torque overflows at t = 0 (the motor accelerates the crank from the start), naming
/// the first non-finite channel's element (the crank's pivot carries the inertia's
/// reaction). Neither runs.
#[test]
fn numbers_that_overflow_at_the_start_are_model_errors() {
    let opts = SimOptions { rate: Some(1000.0), ..SimOptions::new(0.1) };
    let heavy = founding_with("bodies", "crank", "mass", json!(1e308));
    let err = error_of(&heavy, &opts);
    assert!(err.starts_with("body 'crank': mass = 1e308 kg: its weight m |g| = inf N overflows"), "{err}");
    assert!(prepare(&heavy).is_err());

    let stiff = founding_with("bodies", "crank", "inertia", json!(1e308));
    let err = error_of(&stiff, &opts);
    assert!(err.starts_with("joint 'ground_crank': fx = NaN at the initial state (t = 0)"), "{err}");
    // `check` (what `jointgap check` runs) goes as far as the run: the same error.
    assert!(prepare(&stiff).is_ok());
    assert_eq!(check(&stiff).map(|_| ()).unwrap_err().to_string(), err);
    assert!(check(&common::slider_crank_clearance()).is_ok());
}

const K: f64 = 3.136e10;
const CLEARANCE: f64 = 0.5e-3;

/// A journal (body `pin`) placed `e` [m] right of the centre of a ground bearing.
fn journal_at(e: f64) -> Model {
    Model::from_json(
        &json!({
            "gravity": [0.0, 0.0],
            "bodies": [{"name": "pin", "mass": 0.72, "inertia": 1e-5, "position": [e, 0.0]}],
            "joints": [{
                "name": "gap", "type": "clearance_revolute", "body_i": "ground", "point_i": [0.0, 0.0],
                "body_j": "pin", "point_j": [0.0, 0.0],
                "clearance": {"bearing_radius": 7.5e-3, "clearance": CLEARANCE, "stiffness": K,
                              "normal_law": {"type": "hertz", "exponent": 1.5},
                              "friction": {"type": "none"}}
            }]
        })
        .to_string(),
    )
    .unwrap()
}

/// The rule: an initial penetration is accepted while the elastic force K delta^n it
/// stands for is at most 1 MN. Hertz with n = 3/2 reaches 1 MN at delta = (1e6 / K)^(2/3)
/// = 1.0 mm here: 1 % less starts (and presses below 1 MN), 1 % more is an error that
/// names the joint and the penetration.
#[test]
fn initial_penetration_deeper_than_one_meganewton_is_an_error() {
    let limit = ((1e6 / K) * (1e6 / K)).cbrt();
    let below = 0.99 * limit;
    assert!(K * below.powf(1.5) < 1e6);
    assert!(prepare(&journal_at(CLEARANCE + below)).is_ok());
    let above = 1.01 * limit;
    assert!(K * above.powf(1.5) > 1e6);
    let err = prepare(&journal_at(CLEARANCE + above)).err().expect("an error").to_string();
    let expected = format!("joint 'gap': the journal starts {:.4} mm deep in the bearing", 1e3 * above);
    assert!(err.starts_with(&expected), "{err}");
    assert!(err.contains(&format!("presses {:.4} mm deep only under 1e6 N", 1e3 * limit)), "{err}");
    assert!(err.contains("wrong point"), "{err}");
}

/// The founding case with the crank pin given at the crank's centre instead of its end
/// (point [0, 0] of the crank): assembly moves the rod 40 mm towards the crank, and the
/// journal at its small end starts 39.5 mm outside the 0.5 mm clearance of `rod_slider`.
#[test]
fn a_wrong_point_that_puts_the_journal_in_the_wall_is_named() {
    let model = founding_with("joints", "crank_rod", "point_i", json!([0.0, 0.0]));
    let err = prepare(&model).err().expect("an error").to_string();
    assert!(err.starts_with("joint 'rod_slider': the journal starts 39.5000 mm deep"), "{err}");
    assert!(err.contains("40.0000 mm from the bearing centre, radial clearance 0.5000 mm"), "{err}");
    assert!(simulate(&model, &SimOptions::new(0.01)).is_err());
    // The example as given starts with its journal centred.
    assert!(prepare(&common::slider_crank_clearance()).is_ok());
}
