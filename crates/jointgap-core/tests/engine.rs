//! End-to-end checks of the engine: closed-form kinematics, corners, redundant
//! constraints, assembly errors and failure reporting.

use crate::common::*;
use jointgap_core::{simulate, Method, Model, SimOptions, Status};
use serde_json::json;
use std::f64::consts::FRAC_PI_2;

fn opts(t_end: f64, rate: f64, rtol: f64, method: Method) -> SimOptions {
    SimOptions { rate: Some(rate), rtol, atol: rtol * 1e-2, method, ..SimOptions::new(t_end) }
}

#[test]
fn slider_crank_matches_closed_form_with_every_method() {
    for method in [Method::Dopri5, Method::Sdirk4, Method::Radau5] {
        let res = simulate(&slider_crank(9.81), &opts(0.5, 2000.0, 1e-10, method)).unwrap();
        assert_eq!(res.status, Status::Finished, "{method:?}");
        assert_eq!(res.stats.method, method.name());
        assert_eq!(res.stats.jacobian_evaluations > 0, method != Method::Dopri5, "{:?}", res.stats);
        let (x, vx, ax) = (
            res.channel("slider.x").unwrap(),
            res.channel("slider.vx").unwrap(),
            res.channel("slider.ax").unwrap(),
        );
        let peak = (0..res.time.len()).map(|i| slider_closed_form(res.time[i]).2.abs()).fold(0.0, f64::max);
        // r w^2 (1 + r/L) = 98.7 m/s^2 at 300 rpm.
        assert!(peak > 95.0, "peak acceleration {peak}");
        for (i, &t) in res.time.iter().enumerate() {
            let (xe, ve, ae) = slider_closed_form(t);
            assert!((x[i] - xe).abs() < 1e-9, "{method:?} x at t={t}: {} vs {xe}", x[i]);
            assert!((vx[i] - ve).abs() < 1e-7, "{method:?} vx at t={t}: {} vs {ve}", vx[i]);
            assert!((ax[i] - ae).abs() < 1e-6 * peak, "{method:?} ax at t={t}: {} vs {ae}", ax[i]);
        }
        assert!(res.channel("system.constraint_error").unwrap().iter().all(|e| *e < 1e-10));
    }
}

/// Steps stop exactly at the end of the ramp, where the crank acceleration jumps.
#[test]
fn ramp_corner_is_a_step_boundary() {
    for method in [Method::Dopri5, Method::Sdirk4, Method::Radau5] {
        let o = SimOptions { rate: None, ..opts(0.3, 1.0, 1e-6, method) };
        let res = simulate(&slider_crank(0.0), &o).unwrap();
        assert!(res.time.contains(&T_RAMP), "{method:?}: no step ends at {T_RAMP}");
    }
}

/// A parallelogram linkage with a third parallel crank has one redundant equation: it
/// is removed with a warning naming it, and the motion is the exact parallelogram
/// (the coupler translates without rotating).
#[test]
fn parallelogram_redundancy_is_removed_and_named() {
    let model = Model::from_json(
        &json!({
            "gravity": [0.0, -9.81],
            "bodies": [
                {"name": "left", "mass": 1.0, "inertia": 0.01, "position": [0.0, 0.1], "angle": FRAC_PI_2,
                 "points": {"bottom": [-0.1, 0.0], "top": [0.1, 0.0]}},
                {"name": "right", "mass": 1.0, "inertia": 0.01, "position": [0.5, 0.1], "angle": FRAC_PI_2,
                 "points": {"bottom": [-0.1, 0.0], "top": [0.1, 0.0]}},
                {"name": "middle", "mass": 1.0, "inertia": 0.01, "position": [0.25, 0.1], "angle": FRAC_PI_2,
                 "points": {"bottom": [-0.1, 0.0], "top": [0.1, 0.0]}},
                {"name": "coupler", "mass": 2.0, "inertia": 0.05, "position": [0.25, 0.2],
                 "points": {"l": [-0.25, 0.0], "r": [0.25, 0.0]}}
            ],
            "joints": [
                {"name": "pin_left", "type": "revolute", "body_i": "ground", "point_i": [0.0, 0.0], "body_j": "left", "point_j": "bottom"},
                {"name": "pin_right", "type": "revolute", "body_i": "ground", "point_i": [0.5, 0.0], "body_j": "right", "point_j": "bottom"},
                {"name": "top_left", "type": "revolute", "body_i": "left", "point_i": "top", "body_j": "coupler", "point_j": "l"},
                {"name": "top_right", "type": "revolute", "body_i": "right", "point_i": "top", "body_j": "coupler", "point_j": "r"},
                {"name": "pin_middle", "type": "revolute", "body_i": "ground", "point_i": [0.25, 0.0], "body_j": "middle", "point_j": "bottom"},
                {"name": "top_middle", "type": "revolute", "body_i": "middle", "point_i": "top", "body_j": "coupler", "point_j": [0.0, 0.0]}
            ],
            "drivers": [{"name": "motor", "joint": "pin_left", "profile": {"type": "constant_speed", "speed": 2.0}}]
        })
        .to_string(),
    )
    .unwrap();
    let res = simulate(&model, &opts(2.0, 100.0, 1e-9, Method::Dopri5)).unwrap();
    assert_eq!(res.status, Status::Finished);
    assert_eq!(res.warnings.len(), 1, "{:?}", res.warnings);
    assert!(
        res.warnings[0].contains("joint 'top_middle'") && res.warnings[0].contains("redundant"),
        "{}",
        res.warnings[0]
    );
    let angle = res.channel("coupler.angle").unwrap();
    let left = res.channel("left.angle").unwrap();
    for (i, &t) in res.time.iter().enumerate() {
        assert!(angle[i].abs() < 1e-9, "coupler angle {}", angle[i]);
        assert!((left[i] - (FRAC_PI_2 + 2.0 * t)).abs() < 1e-9);
    }
}

#[test]
fn unassemblable_model_names_the_joints() {
    // The rod is too short to reach the slider line at 0.5 m height.
    let mut model = slider_crank(9.81);
    model.joints[3].point_i = jointgap_core::model::PointRef::Local([0.0, 0.5]);
    let err = simulate(&model, &SimOptions::new(0.1)).unwrap_err().to_string();
    assert!(err.contains("cannot assemble"), "{err}");
    assert!(err.contains("joint '"), "{err}");
}

#[test]
fn driver_on_a_locked_joint_is_an_error() {
    let mut model = slider_crank(9.81);
    model.joints.push(jointgap_core::model::Joint {
        name: "lock".into(),
        kind: jointgap_core::model::JointKind::Fixed,
        body_i: "ground".into(),
        point_i: jointgap_core::model::PointRef::Local([0.0, 0.0]),
        body_j: "crank".into(),
        point_j: jointgap_core::model::PointRef::Named("O".into()),
        axis: None,
        clearance: None,
        lubrication: None,
        play: None,
        gear: None,
        initial: None,
        initial_rate: None,
    });
    let err = simulate(&model, &SimOptions::new(0.1)).unwrap_err().to_string();
    assert!(err.contains("driver 'motor'") && err.contains("cannot move"), "{err}");
}

/// A run that cannot go on returns what it computed up to the failure, with time and reason.
#[test]
fn failing_run_keeps_its_samples() {
    let o = SimOptions { max_steps: Some(50), ..opts(0.5, 10000.0, 1e-8, Method::Dopri5) };
    let res = simulate(&slider_crank(9.81), &o).unwrap();
    match &res.status {
        Status::Failed { time, reason } => {
            assert!(*time > 0.0 && *time < 0.5);
            assert!(reason.contains("max_steps"));
            let last = *res.time.last().unwrap();
            assert!(last <= *time && last > 0.0);
        }
        s => panic!("expected a failure, got {s:?}"),
    }
}

#[test]
fn bad_elements_are_named() {
    let cases = [
        (
            json!({"bodies": [{"name": "b", "mass": 0.0, "inertia": 1.0}]}),
            "body 'b': mass = 0 kg must be positive",
        ),
        (
            json!({"bodies": [{"name": "b", "mass": 1.0, "inertia": -1.0}]}),
            "body 'b': inertia = -1 kg m^2 must not be negative",
        ),
        (
            json!({"bodies": [{"name": "b", "mass": 1.0, "inertia": 1.0}],
                   "joints": [{"name": "j", "type": "revolute", "body_i": "ground", "point_i": [0.0, 0.0], "body_j": "bb", "point_j": [0.0, 0.0]}]}),
            "joint 'j': body_j 'bb' is not a body of the model",
        ),
        (
            json!({"bodies": [{"name": "b", "mass": 1.0, "inertia": 1.0}],
                   "joints": [{"name": "j", "type": "revolute", "body_i": "b", "point_i": [0.0, 0.0], "body_j": "b", "point_j": [0.0, 0.0]}]}),
            "joint 'j': connects body 'b' to itself",
        ),
        (
            json!({"bodies": [{"name": "b", "mass": 1.0, "inertia": 1.0}, {"name": "b", "mass": 1.0, "inertia": 1.0}]}),
            "body 'b': the name is already used by a body",
        ),
        (
            json!({"bodies": [{"name": "b", "mass": 1.0, "inertia": 1.0}],
                   "joints": [{"name": "j", "type": "prismatic", "body_i": "ground", "point_i": [0.0, 0.0], "body_j": "b", "point_j": [0.0, 0.0]}]}),
            "joint 'j': a prismatic joint needs an 'axis'",
        ),
        (
            json!({"bodies": [{"name": "b", "mass": 1.0, "inertia": 1.0}],
                   "joints": [{"name": "j", "type": "revolute", "body_i": "ground", "point_i": [0.0, 0.0], "body_j": "b", "point_j": "P"}]}),
            "joint 'j': point_j 'P' is not a point of body 'b'",
        ),
    ];
    for (model, expected) in cases {
        let model = Model::from_json(&model.to_string()).unwrap();
        let err = simulate(&model, &SimOptions::new(0.1)).unwrap_err().to_string();
        assert!(err.contains(expected), "{err}\n expected: {expected}");
    }
    let err = Model::from_json(r#"{"bodies": [{"name": "b", "mass": 1, "inertia": 1, "colour": 3}]}"#)
        .unwrap_err()
        .to_string();
    assert!(err.contains("colour"), "{err}");
}

/// A monitor that asks to stop at its third progress report (as Ctrl-C does): the run
/// ends there with status interrupted, and every sample up to that time is kept and
/// equals the uninterrupted run's.
#[test]
fn interrupted_run_keeps_what_it_computed() {
    struct StopAtThird(usize, f64);
    impl jointgap_core::Monitor for StopAtThird {
        fn progress_interval(&self) -> Option<f64> {
            Some(0.0) // every check: the stop comes after a known number of steps
        }
        fn progress(&mut self, p: &jointgap_core::Progress) -> Result<(), jointgap_core::Stop> {
            self.0 += 1;
            self.1 = p.time;
            if self.0 == 3 {
                Err(jointgap_core::Stop::Interrupted)
            } else {
                Ok(())
            }
        }
    }
    let o = opts(0.5, 2000.0, 1e-8, Method::Dopri5);
    let mut monitor = StopAtThird(0, 0.0);
    let res = jointgap_core::simulate_with(&slider_crank(9.81), &o, &mut monitor).unwrap();
    assert_eq!(res.status, Status::Interrupted { time: monitor.1 });
    assert!(monitor.1 > 0.0 && monitor.1 < 0.5, "stopped at {}", monitor.1);
    let full = simulate(&slider_crank(9.81), &o).unwrap();
    let n = res.time.len();
    assert!(n > 1 && n < full.time.len() && res.time[n - 1] <= monitor.1);
    assert_eq!(res.time[..], full.time[..n]);
    assert_eq!(res.channel("slider.x").unwrap()[..], full.channel("slider.x").unwrap()[..n]);
}

/// A batch is the serial runs done on threads; once its control is stopped, no model
/// starts (a run going then ends as interrupted: tests/test_batch_interrupt.py).
#[test]
fn a_batch_gives_the_serial_results_and_starts_nothing_once_stopped() {
    let models = [slider_crank(9.81), slider_crank_clearance()];
    let options = opts(0.05, 1000.0, 1e-8, Method::Dopri5);
    let control = jointgap_core::BatchControl::default();
    let batch = jointgap_core::simulate_batch(&models, &options, Some(2), &control);
    for (model, run) in models.iter().zip(batch) {
        let (alone, run) = (simulate(model, &options).unwrap(), run.unwrap().unwrap());
        assert_eq!((run.time, run.data, run.status), (alone.time, alone.data, Status::Finished));
    }
    assert_eq!((control.running(), control.ended()), (0, 2));
    control.stop();
    let batch = jointgap_core::simulate_batch(&models, &options, Some(2), &control);
    assert!(batch.iter().all(Option::is_none));
    assert_eq!(control.ended(), 2);
}

/// A model prepared once (what a front end checks before it runs) runs any number of
/// times without being compiled again, and each run is bit for bit the one that compiles
/// the model itself: the same samples, impacts, statistics and warnings.
#[test]
fn a_prepared_model_runs_as_the_model_does() {
    use jointgap_core::simulate::{check_prepared, prepare, simulate_prepared, Silent};
    let model = slider_crank_clearance();
    let opts = SimOptions { rate: Some(2000.0), ..SimOptions::new(0.05) };
    let prepared = prepare(&model).unwrap();
    assert_eq!(check_prepared(&prepared).unwrap(), jointgap_core::simulate::check(&model).unwrap());
    let direct = simulate(&model, &opts).unwrap();
    for _ in 0..2 {
        let again = simulate_prepared(&prepared, &opts, &mut Silent).unwrap();
        assert_eq!(again.status, Status::Finished);
        assert_eq!((&again.time, &again.names, &again.data), (&direct.time, &direct.names, &direct.data));
        assert_eq!(
            (&again.impacts, &again.clearances, &again.warnings),
            (&direct.impacts, &direct.clearances, &direct.warnings)
        );
        let without_wall_time =
            |s: &jointgap_core::RunStats| jointgap_core::RunStats { wall_time: 0.0, ..s.clone() };
        assert_eq!(without_wall_time(&again.stats), without_wall_time(&direct.stats));
    }
}
