//! Singular positions: the Schur complement solve where `S = Cq M^-1 Cq^T` loses rank,
//! against a dense pseudo-inverse, by both factorisations; a parallelogram chain run
//! through its first singular position at a tight tolerance (it stopped there before);
//! the assembly's choice of independent rows at a singular position; and the sparse
//! factor of a long chain near its singular position, against the envelope factor.

use jointgap_core::dynamics::schur::{Factorisation, RowJacobian, Schur};
use jointgap_core::dynamics::{accelerations, Workspace};
use jointgap_core::mechanics::layout::Layout;
use jointgap_core::mechanics::planar_body::PLANAR_BODY;
use jointgap_core::{Model, SimOptions, Status};
use nalgebra::{DMatrix, DVector};
use serde_json::json;

/// Rows over three bodies, with rows 3 and 5 combinations of the others, so `S` has
/// rank 4 of 6; `M^-1` and the entries from a fixed sequence.
fn rank_deficient_rows() -> (Vec<RowJacobian>, Vec<f64>, DMatrix<f64>) {
    let mut seed = 2024u64;
    let mut next = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let pairs = [
        [Some(0), Some(1)],
        [Some(1), Some(2)],
        [Some(0), Some(1)],
        [Some(0), Some(1)],
        [None, Some(2)],
        [Some(1), Some(2)],
    ];
    let layout = Layout::new([PLANAR_BODY; 3]);
    let mut jac: Vec<RowJacobian> = pairs
        .iter()
        .map(|&bodies| RowJacobian {
            entries: [[next(), next(), next()], [next(), next(), next()]],
            ..RowJacobian::new(bodies, &layout)
        })
        .collect();
    // Row 3 = 2 row 0 - row 2 and row 5 = -3 row 1, each over the same bodies.
    for side in 0..2 {
        for d in 0..3 {
            jac[3].entries[side][d] = 2.0 * jac[0].entries[side][d] - jac[2].entries[side][d];
            jac[5].entries[side][d] = -3.0 * jac[1].entries[side][d];
        }
    }
    let m_inv: Vec<f64> = (0..9).map(|i| 0.5 + (i % 4) as f64).collect();
    let mut cq = DMatrix::zeros(jac.len(), 9);
    for (a, row) in jac.iter().enumerate() {
        for (k, entries) in row.blocks() {
            for d in 0..3 {
                cq[(a, 3 * k + d)] += entries[d];
            }
        }
    }
    (jac, m_inv, cq)
}

/// `S x = b` with `S` of rank 4 of 6, by both factorisations, each of which sees the rank
/// loss in its pivots: for a consistent `b` (in the range of `S`) the solve returns the
/// minimum-norm solution `S^+ b` of the dense pseudo-inverse (to 1e-4) and its
/// constraint force `Cq^T S^+ b` (to 1e-12); for an inconsistent `b` it still returns,
/// and the constraint force
/// `Cq^T x` it gives is the least-squares one, `Cq^T S^+ b`, that the accelerations use.
#[test]
fn rank_deficient_schur_complement_solves_as_the_pseudo_inverse() {
    let (jac, m_inv, cq) = rank_deficient_rows();
    let bodies: Vec<_> = jac.iter().map(|r| r.bodies).collect();
    let s = &cq * DMatrix::from_diagonal(&DVector::from_vec(m_inv.clone())) * cq.transpose();
    let svd = s.clone().svd(true, true);
    let tol = 1e-12 * svd.singular_values.max();
    assert_eq!(svd.rank(tol), 4);
    let pinv = svd.pseudo_inverse(tol).unwrap();
    let consistent = &s * DVector::from_vec(vec![0.3, -1.2, 0.7, 2.0, -0.4, 1.1]);
    let inconsistent = DVector::from_vec(vec![1.0, -2.0, 0.5, 0.25, 3.0, -1.5]);
    for factorisation in [Factorisation::Dense, Factorisation::Sparse] {
        let mut schur = Schur::new(&bodies, factorisation);
        schur.update(&jac, &m_inv);
        let mut x = consistent.as_slice().to_vec();
        schur.solve(&mut x).unwrap();
        // Both factors' pivots show the rank loss.
        assert!(schur.rank_deficient(), "{factorisation:?}");
        // Rounding along the lost rank is divided by the shift (1e-9): the multipliers
        // are the minimum-norm ones to about 1e-7, the force they give to rounding.
        let expected = &pinv * &consistent;
        let x = DVector::from_vec(x);
        let err = (&x - &expected).amax();
        assert!(err <= 1e-4 * expected.amax(), "{factorisation:?}: {err:e} of {:e}", expected.amax());
        let force = cq.transpose() * &x;
        let expected = cq.transpose() * &expected;
        let err = (&force - &expected).amax();
        assert!(err <= 1e-12 * expected.amax(), "{factorisation:?}: force {err:e} of {:e}", expected.amax());

        let mut x = inconsistent.as_slice().to_vec();
        schur.solve(&mut x).unwrap();
        assert!(schur.rank_deficient() && x.iter().all(|x| x.is_finite()));
        let force = cq.transpose() * DVector::from_vec(x);
        let expected = cq.transpose() * (&pinv * &inconsistent);
        let err = (&force - &expected).amax();
        assert!(err <= 1e-6 * expected.amax(), "{factorisation:?}: force {err:e} of {:e}", expected.amax());
    }
}

/// A full-rank, well-conditioned `S` keeps the plain factor: not ill-conditioned, not
/// rank deficient, the exact solution.
#[test]
fn full_rank_schur_complement_is_not_flagged() {
    let (mut jac, m_inv, _) = rank_deficient_rows();
    jac.truncate(3);
    let bodies: Vec<_> = jac.iter().map(|r| r.bodies).collect();
    let mut schur = Schur::new(&bodies, Factorisation::Dense);
    schur.update(&jac, &m_inv);
    let mut x = vec![1.0, 2.0, 3.0];
    schur.solve(&mut x).unwrap();
    assert!(!schur.rank_deficient());
}

fn bar(name: &str, pos: [f64; 2], angle: f64, vel: [f64; 2], omega: f64) -> serde_json::Value {
    json!({"name": name, "mass": 1.0, "inertia": 1.0 / 12.0, "position": pos, "angle": angle,
           "velocity": vel, "omega": omega, "points": {"A": [-0.5, 0.0], "B": [0.5, 0.0]}})
}

/// The chain of `n` parallelogram loops of benchmark A02 (1 m, 1 kg bars, rockers
/// upright, the top of the first moving at 1 m/s), as `benchmarks/benchmark_models.py`.
fn four_bar_chain(n: usize) -> Model {
    Model::from_json(&chain_at(n, std::f64::consts::FRAC_PI_2, None).to_string()).unwrap()
}

/// The chain of [`four_bar_chain`] with its rockers at `phi` turning at -1 rad/s (the
/// couplers translating), and with `driver` its first pivot driven at -1 rad/s.
fn chain_at(n: usize, phi: f64, driver: Option<&str>) -> serde_json::Value {
    let (c, s) = (phi.cos(), phi.sin());
    let mut bodies = vec![];
    let mut joints = vec![];
    let mut ground = serde_json::Map::new();
    for i in 0..=n {
        ground.insert(format!("A{i}"), json!([i as f64, 0.0]));
        bodies.push(bar(
            &format!("rocker_{i}"),
            [i as f64 + 0.5 * c, 0.5 * s],
            phi,
            [0.5 * s, -0.5 * c],
            -1.0,
        ));
        joints.push(json!({"name": format!("pivot_{i}"), "type": "revolute", "body_i": "ground",
                           "point_i": format!("A{i}"), "body_j": format!("rocker_{i}"), "point_j": "A"}));
    }
    for i in 1..=n {
        bodies.push(bar(&format!("coupler_{i}"), [i as f64 - 0.5 + c, s], 0.0, [s, -c], 0.0));
        joints.push(
            json!({"name": format!("left_{i}"), "type": "revolute", "body_i": format!("rocker_{}", i - 1),
                           "point_i": "B", "body_j": format!("coupler_{i}"), "point_j": "A"}),
        );
        joints
            .push(json!({"name": format!("right_{i}"), "type": "revolute", "body_i": format!("coupler_{i}"),
                           "point_i": "B", "body_j": format!("rocker_{i}"), "point_j": "B"}));
    }
    let drivers: Vec<_> = driver
        .map(|name| json!({"name": name, "joint": "pivot_0", "profile": {"type": "constant_speed", "speed": -1.0}}))
        .into_iter()
        .collect();
    json!({"name": "four_bar_chain", "gravity": [0.0, -9.81], "ground_points": ground,
           "bodies": bodies, "joints": joints, "drivers": drivers})
}

/// The two-loop chain stopped at t = 0.714 s (all bars horizontal) at rtol 1e-12 with
/// every method; it now runs through that position and the next ones, its rockers
/// parallel. (tests/test_singular_positions.py checks the motion against its
/// one-degree-of-freedom equation.)
#[test]
fn two_loop_chain_passes_its_singular_positions_at_tight_tolerance() {
    for method in ["dopri5", "radau5"] {
        let mut opts = SimOptions::new(2.0);
        opts.rate = Some(100.0);
        opts.rtol = 1e-12;
        opts.atol = 1e-14;
        opts.method = serde_json::from_value(json!(method)).unwrap();
        let r = jointgap_core::simulate(&four_bar_chain(2), &opts).unwrap();
        assert_eq!(r.status, Status::Finished, "{method}");
        let a0 = r.channel("rocker_0.angle").unwrap();
        let a2 = r.channel("rocker_2.angle").unwrap();
        // Past the horizontal at least twice.
        assert!(a0.iter().fold(f64::INFINITY, |m, &a| m.min(a)) < -std::f64::consts::PI, "{method}");
        let spread = a0.iter().zip(a2).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(spread < 1e-10, "{method}: rockers {spread:e} rad apart");
    }
}

/// The rows the assembly keeps and the warnings it gives for a model file.
fn assembled_rows(model: &serde_json::Value) -> (usize, usize, Vec<String>) {
    let prepared = jointgap_core::simulate::prepare(&Model::from_json(&model.to_string()).unwrap()).unwrap();
    let redundant = prepared.system.warnings.iter().filter(|w| w.contains("redundant")).cloned().collect();
    (prepared.initial.active.len(), prepared.system.rows.len(), redundant)
}

/// Placed exactly at its singular position (all bars horizontal: the two-loop chain's
/// Jacobian has rank 12 of 14 there), the chain keeps all its rows, as when placed a
/// little before it: the rows' independence is decided at a configuration nearby. A
/// truly redundant model keeps its redundant rows dropped, at the singular position as
/// away from it: a third rocker pinned to the middle of each coupler (one row too many
/// per loop) and a pin given twice (two rows).
#[test]
fn assembly_at_a_singular_position_keeps_the_rows_that_are_independent_nearby() {
    for driver in [None, Some("motor")] {
        for phi in [0.0, 1e-3] {
            let (active, rows, redundant) = assembled_rows(&chain_at(2, phi, driver));
            assert_eq!((active, redundant.len()), (rows, 0), "phi = {phi}, driver {driver:?}: {redundant:?}");
        }
    }
    for phi in [0.0, 1e-3, 0.4] {
        let mut model = chain_at(2, phi, None);
        let (c, s) = (phi.cos(), phi.sin());
        for i in 1..=2 {
            let x = i as f64 - 0.5;
            model["ground_points"][format!("M{i}")] = json!([x, 0.0]);
            model["bodies"].as_array_mut().unwrap().push(bar(
                &format!("middle_{i}"),
                [x + 0.5 * c, 0.5 * s],
                phi,
                [0.5 * s, -0.5 * c],
                -1.0,
            ));
            let joints = model["joints"].as_array_mut().unwrap();
            joints.push(json!({"name": format!("middle_pivot_{i}"), "type": "revolute", "body_i": "ground",
                               "point_i": format!("M{i}"), "body_j": format!("middle_{i}"), "point_j": "A"}));
            joints.push(json!({"name": format!("middle_top_{i}"), "type": "revolute", "body_i": format!("coupler_{i}"),
                               "point_i": [0.0, 0.0], "body_j": format!("middle_{i}"), "point_j": "B"}));
        }
        let (active, rows, redundant) = assembled_rows(&model);
        assert_eq!((rows - active, redundant.len()), (2, 2), "phi = {phi}: {redundant:?}");
        let mut model = chain_at(2, phi, None);
        let twice = model["joints"][0].clone();
        model["joints"].as_array_mut().unwrap().push(json!({"name": "pivot_0_again", "type": "revolute",
            "body_i": "ground", "point_i": "A0", "body_j": "rocker_0", "point_j": "A"}));
        assert_eq!(twice["name"], "pivot_0");
        let (active, rows, redundant) = assembled_rows(&model);
        assert_eq!((rows - active, redundant.len()), (2, 2), "phi = {phi}: {redundant:?}");
        assert!(redundant.iter().all(|w| w.contains("pivot_0_again")), "{redundant:?}");
    }
}

/// The 40-loop chain gets faer's sparse factor, and it treats the singular position as
/// the envelope factor does: at the position, a little off it (inside the stretch where
/// the lost rank is released) and away from it, both see the same rank loss and give
/// the same accelerations and constraint forces, to 1e-9 of their size. (Before, the
/// sparse factor took the larger shift only where its refinement failed.)
#[test]
fn sparse_and_envelope_factors_agree_at_a_singular_position() {
    let n = 40;
    for (phi, rank_deficient) in [(0.0, true), (1e-5, true), (0.3, false)] {
        let model = Model::from_json(&chain_at(n, phi, Some("motor")).to_string()).unwrap();
        let prepared = jointgap_core::simulate::prepare(&model).unwrap();
        let (sys, initial) = (&prepared.system, &prepared.initial);
        assert_eq!(initial.active.len(), sys.rows.len());
        assert_eq!(Workspace::new(sys, initial.active.clone()).schur.factorisation(), Factorisation::Sparse);
        let mut results = Vec::new();
        for factorisation in [Factorisation::Dense, Factorisation::Sparse] {
            let mut ws = Workspace::with_factorisation(sys, initial.active.clone(), factorisation);
            accelerations(sys, 0.0, &initial.q, &initial.v, &mut ws).unwrap();
            assert_eq!(ws.schur.rank_deficient(), rank_deficient, "phi = {phi}, {factorisation:?}");
            results.push(ws.qdd.clone());
        }
        let scale = results[0].iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let worst = results[0].iter().zip(&results[1]).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(worst <= 1e-9 * scale, "phi = {phi}: qdd differ by {worst:e} of {scale:e}");
    }
}
