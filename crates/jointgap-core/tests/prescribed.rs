//! Bodies that their own joints and drivers fix leave the Schur complement
//! (`dynamics::prescribed`): their accelerations come from their rows and their rows'
//! multipliers from their Newton-Euler equations. Checked against the whole augmented
//! system `[M Cq^T; Cq 0][qdd; lambda] = [Qe; gamma]` assembled densely and solved by LU,
//! at states that need not satisfy the constraints (the equations hold at any state).

use crate::common;

use jointgap_core::dynamics::{
    accelerations, applied_forces, constraints, project, violation, Workspace, POSITION_TOL,
};
use jointgap_core::simulate::prepare;
use jointgap_core::{simulate, Model, SimOptions, Status};
use nalgebra::{DMatrix, DVector};
use serde_json::json;

/// `(qdd, lambda by row of System::rows)` from the dense augmented system.
fn dense_solution(model: &Model, t: f64, q: &[f64], v: &[f64]) -> (Vec<f64>, Vec<Option<f64>>) {
    let prepared = prepare(model).unwrap();
    let sys = &prepared.system;
    let mut ws = Workspace::in_order(sys, prepared.initial.active.clone());
    constraints(sys, t, q, v, &mut ws);
    applied_forces(sys, t, q, v, &mut ws);
    let (n, m) = (sys.layout.nv(), ws.active.len());
    let mut a = DMatrix::zeros(n + m, n + m);
    for (k, b) in sys.bodies.iter().enumerate() {
        a[(3 * k, 3 * k)] = b.mass;
        a[(3 * k + 1, 3 * k + 1)] = b.mass;
        a[(3 * k + 2, 3 * k + 2)] = b.inertia;
    }
    let cq = ws.dense_jacobian();
    a.view_mut((n, 0), (m, n)).copy_from(&cq);
    a.view_mut((0, n), (n, m)).copy_from(&cq.transpose());
    let mut rhs = DVector::zeros(n + m);
    rhs.rows_mut(0, n).copy_from_slice(&ws.qe);
    rhs.rows_mut(n, m).copy_from(&ws.gamma);
    let x = a.lu().solve(&rhs).expect("augmented system is regular");
    let mut lambda = vec![None; sys.rows.len()];
    for (a, &r) in ws.active.iter().enumerate() {
        lambda[r] = Some(x[n + a]);
    }
    (x.rows(0, n).iter().copied().collect(), lambda)
}

/// Checks the split solve against the dense one at the assembled state with velocities
/// `v_scale` times the assembled ones plus a twist, and a slightly moved position;
/// returns the number of prescribed bodies.
fn check(model: &Model, t: f64) -> usize {
    let prepared = prepare(model).unwrap();
    let sys = &prepared.system;
    let n = sys.layout.nv();
    let q: Vec<f64> =
        prepared.initial.q.iter().enumerate().map(|(i, x)| x + 1e-3 * ((i * 7 % 5) as f64 - 2.0)).collect();
    let v: Vec<f64> = prepared
        .initial
        .v
        .iter()
        .enumerate()
        .map(|(i, x)| 1.3 * x + 0.4 * ((i * 3 % 4) as f64 - 1.5))
        .collect();
    let mut ws = Workspace::new(sys, prepared.initial.active.clone());
    accelerations(sys, t, &q, &v, &mut ws).unwrap();
    let (qdd, lambda) = dense_solution(model, t, &q, &v);
    let scale = qdd.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    assert_eq!(qdd.len(), n);
    for (j, (split, dense)) in ws.qdd.iter().zip(&qdd).enumerate() {
        assert!((split - dense).abs() < 1e-10 * scale, "qdd[{j}]: split {split} dense {dense}");
    }
    let l_scale = lambda.iter().flatten().fold(1.0f64, |m, x| m.max(x.abs()));
    for (a, &r) in ws.active.iter().enumerate() {
        let dense = lambda[r].expect("same active rows");
        assert!(
            (ws.lambda[a] - dense).abs() < 1e-10 * l_scale,
            "{}: split {} dense {dense}",
            sys.rows[r].label,
            ws.lambda[a]
        );
    }
    ws.prescribed_bodies().count()
}

/// The founding slider-crank, ideal and with its clearance joint: the driven crank is
/// prescribed, and the crank-rod revolute's rows act on it from the Schur complement.
#[test]
fn driven_crank_matches_the_dense_augmented_solve() {
    assert_eq!(check(&common::slider_crank(9.81), 0.13), 1);
    assert_eq!(check(&common::slider_crank_clearance(), 0.31), 1);
}

/// A two-link arm whose joints are both driven, the second on the first: both links are
/// prescribed, the second after the first, and no row is left for the Schur complement.
/// A third, free link hangs from the second.
#[test]
fn driven_arm_on_a_driven_arm_matches_the_dense_augmented_solve() {
    let link = |name: &str, x: f64| {
        json!({"name": name, "mass": 1.5, "inertia": 0.02, "position": [x, 0.0],
               "points": {"a": [-0.2, 0.0], "b": [0.2, 0.0]}})
    };
    let mut raw = json!({
        "gravity": [0.0, -9.81],
        "bodies": [link("upper", 0.2), link("lower", 0.6)],
        "joints": [
            {"name": "shoulder", "type": "revolute", "body_i": "ground", "point_i": [0.0, 0.0], "body_j": "upper", "point_j": "a"},
            {"name": "elbow", "type": "revolute", "body_i": "upper", "point_i": "b", "body_j": "lower", "point_j": "a"}
        ],
        "drivers": [
            {"name": "m1", "joint": "shoulder", "profile": {"type": "linear_ramp", "speed": 3.0, "ramp_time": 0.5}},
            {"name": "m2", "joint": "elbow", "profile": {"type": "constant_speed", "speed": -2.0}}
        ]
    });
    assert_eq!(check(&Model::from_json(&raw.to_string()).unwrap(), 0.2), 2);
    raw["bodies"].as_array_mut().unwrap().push(link("hand", 1.0));
    raw["joints"].as_array_mut().unwrap().push(
        json!({"name": "wrist", "type": "revolute", "body_i": "lower", "point_i": "b", "body_j": "hand", "point_j": "a"}),
    );
    assert_eq!(check(&Model::from_json(&raw.to_string()).unwrap(), 0.2), 2);
}

/// A slider driven along an inclined guide carries a pendulum: the slider is prescribed
/// by its prismatic joint's two rows and the translation driver.
#[test]
fn driven_slider_matches_the_dense_augmented_solve() {
    let model = Model::from_json(
        &json!({
            "gravity": [0.0, -9.81],
            "bodies": [
                {"name": "carriage", "mass": 3.0, "inertia": 0.05, "position": [0.0, 0.0], "angle": 0.4},
                {"name": "bob", "mass": 0.8, "inertia": 0.004, "position": [0.0, -0.3],
                 "points": {"top": [0.0, 0.3]}}
            ],
            "joints": [
                {"name": "guide", "type": "prismatic", "body_i": "ground", "point_i": [0.0, 0.0], "body_j": "carriage", "point_j": [0.0, 0.0], "axis": [0.92, 0.39]},
                {"name": "hinge", "type": "revolute", "body_i": "carriage", "point_i": [0.0, 0.0], "body_j": "bob", "point_j": "top"}
            ],
            "drivers": [
                {"name": "screw", "joint": "guide", "profile": {"type": "linear_ramp", "speed": 0.8, "ramp_time": 0.3}}
            ]
        })
        .to_string(),
    )
    .unwrap();
    assert_eq!(check(&model, 0.1), 1);
}

/// Projection with a prescribed body meets every row, its own included.
#[test]
fn projection_meets_the_prescribed_rows_and_the_others() {
    let model = common::slider_crank(9.81);
    let prepared = prepare(&model).unwrap();
    let sys = &prepared.system;
    let mut q: Vec<f64> =
        prepared.initial.q.iter().enumerate().map(|(i, x)| x + 2e-4 * ((i % 3) as f64 - 1.0)).collect();
    let mut v: Vec<f64> = prepared.initial.v.iter().map(|x| x + 0.05).collect();
    let mut ws = Workspace::new(sys, prepared.initial.active.clone());
    let t = 0.05;
    assert!(violation(sys, t, &q, &v, &mut ws).0 > 1e-5);
    project(sys, t, &mut q, &mut v, &mut ws, POSITION_TOL).unwrap();
    let (position, velocity) = violation(sys, t, &q, &v, &mut ws);
    assert!(position < 1e-12, "position residual {position}");
    assert!(velocity < 1e-10, "velocity residual {velocity}");
}

/// A two-link arm driven at constant speed at both joints, under gravity: every body is
/// prescribed and the Schur complement is empty. The motor torques of the run equal the
/// closed-form inverse dynamics of a planar two-link arm (uniform links, relative elbow
/// angle; e.g. Spong, Hutchinson and Vidyasagar, Robot Modeling and Control, 7.4):
/// `tau1 = -m2 L1 lc2 sin q2 (2 w1 w2 + w2^2) + G1`, `tau2 = m2 L1 lc2 sin q2 w1^2 + G2`.
#[test]
fn driven_arm_torques_equal_the_closed_form_inverse_dynamics() {
    let (m, inertia, l, g) = (1.5, 0.02, 0.4, 9.81);
    let (w1, w2) = (3.0, -2.0);
    let link = |name: &str, x: f64| {
        json!({"name": name, "mass": m, "inertia": inertia, "position": [x, 0.0],
               "points": {"a": [-l / 2.0, 0.0], "b": [l / 2.0, 0.0]}})
    };
    let model = Model::from_json(
        &json!({
            "gravity": [0.0, -g],
            "bodies": [link("upper", l / 2.0), link("lower", 1.5 * l)],
            "joints": [
                {"name": "shoulder", "type": "revolute", "body_i": "ground", "point_i": [0.0, 0.0], "body_j": "upper", "point_j": "a"},
                {"name": "elbow", "type": "revolute", "body_i": "upper", "point_i": "b", "body_j": "lower", "point_j": "a"}
            ],
            "drivers": [
                {"name": "m1", "joint": "shoulder", "profile": {"type": "constant_speed", "speed": w1}},
                {"name": "m2", "joint": "elbow", "profile": {"type": "constant_speed", "speed": w2}}
            ]
        })
        .to_string(),
    )
    .unwrap();
    let res = simulate(&model, &SimOptions { rate: Some(100.0), ..SimOptions::new(1.0) }).unwrap();
    assert_eq!(res.status, Status::Finished);
    let (tau1, tau2) = (res.channel("m1.torque").unwrap(), res.channel("m2.torque").unwrap());
    let lc = l / 2.0;
    let mut largest = 0.0f64;
    for (i, &t) in res.time.iter().enumerate() {
        let (q1, q2) = (w1 * t, w2 * t);
        let h = m * l * lc * q2.sin();
        let g2 = m * lc * g * (q1 + q2).cos();
        let g1 = (m * lc + m * l) * g * q1.cos() + g2;
        let expected = [-h * (2.0 * w1 * w2 + w2 * w2) + g1, h * w1 * w1 + g2];
        for (got, want) in [tau1[i], tau2[i]].iter().zip(expected) {
            assert!((got - want).abs() < 1e-8, "t = {t}: torque {got} against {want}");
            largest = largest.max(want.abs());
        }
    }
    assert!(largest > 5.0, "the check must see torques of some size ({largest} N m)");
}
