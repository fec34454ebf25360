//! The sparse factorisation of the Schur complement gives the envelope factor's
//! accelerations and multipliers on a long chain, where the engine picks the envelope
//! factor (a band); a pattern whose rows do not follow the topology gets the sparse one.

use jointgap_core::dynamics::schur::{Factorisation, RowJacobian, Schur, DENSE_LIMIT};
use jointgap_core::dynamics::{accelerations, Workspace};
use jointgap_core::mechanics::layout::Layout;
use jointgap_core::mechanics::planar_body::PLANAR_BODY;
use jointgap_core::{Model, SimOptions};
use nalgebra::{DMatrix, DVector};
use serde_json::json;

/// A planar chain of `n` bars of 1 m and 1 kg hanging from the ground, laid out along x.
fn chain(n: usize) -> Model {
    chain_listed(n, |k| k)
}

/// [`chain`] whose joint `k` in the model's list holds link `link(k)` to the one before.
pub fn chain_listed(n: usize, link: impl Fn(usize) -> usize) -> Model {
    let bodies: Vec<_> = (0..n)
        .map(|k| {
            json!({"name": format!("bar{k}"), "mass": 1.0, "inertia": 1.0 / 12.0,
                   "position": [k as f64 + 0.5, 0.0],
                   "points": {"L": [-0.5, 0.0], "R": [0.5, 0.0]}})
        })
        .collect();
    let joints: Vec<_> = (0..n)
        .map(link)
        .map(|k| {
            let (body_i, point_i) = if k == 0 {
                ("ground".to_string(), json!([0.0, 0.0]))
            } else {
                (format!("bar{}", k - 1), json!("R"))
            };
            json!({"name": format!("j{k}"), "type": "revolute", "body_i": body_i, "point_i": point_i,
                   "body_j": format!("bar{k}"), "point_j": "L"})
        })
        .collect();
    Model::from_json(
        &json!({"name": "chain", "gravity": [0.0, -9.81], "bodies": bodies, "joints": joints}).to_string(),
    )
    .unwrap()
}

#[test]
fn sparse_and_dense_factorisations_agree_on_a_long_chain() {
    let n = 40;
    let prepared = jointgap_core::simulate::prepare(&chain(n)).unwrap();
    let sys = &prepared.system;
    let active = prepared.initial.active.clone();
    assert!(active.len() > DENSE_LIMIT, "the chain must be longer than the dense limit");
    // A state off the rest position: bars turning, so gamma and the multipliers are not trivial.
    let q = prepared.initial.q.clone();
    let v: Vec<f64> = (0..q.len()).map(|i| 0.1 * ((i * 7919) % 13) as f64 - 0.6).collect();
    let mut dense = Workspace::with_factorisation(sys, active.clone(), Factorisation::Dense);
    let mut sparse = Workspace::with_factorisation(sys, active.clone(), Factorisation::Sparse);
    assert_eq!(sparse.schur.factorisation(), Factorisation::Sparse);
    assert_eq!(Workspace::new(sys, active).schur.factorisation(), Factorisation::Dense);
    // A chain's rows touch at most two neighbouring bars: S is banded, O(n) entries.
    assert!(sparse.schur.stored_entries() <= 5 * 2 * n, "{} entries", sparse.schur.stored_entries());
    accelerations(sys, 0.0, &q, &v, &mut dense).unwrap();
    accelerations(sys, 0.0, &q, &v, &mut sparse).unwrap();
    let scale = dense.qdd.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(scale > 1.0);
    for (a, b) in dense.qdd.iter().zip(&sparse.qdd) {
        assert!((a - b).abs() <= 1e-12 * scale, "qdd {a} vs {b}");
    }
    let lambda_scale = dense.lambda.amax();
    for (a, b) in dense.lambda.iter().zip(sparse.lambda.iter()) {
        assert!((a - b).abs() <= 1e-12 * lambda_scale, "lambda {a} vs {b}");
    }
}

#[test]
fn a_long_chain_conserves_energy() {
    let n = 30;
    let mut opts = SimOptions::new(0.5);
    opts.rate = Some(100.0);
    opts.rtol = 1e-9;
    opts.atol = 1e-11;
    let result = jointgap_core::simulate(&chain(n), &opts).unwrap();
    assert_eq!(result.status, jointgap_core::Status::Finished);
    let kinetic = result.channel("system.kinetic_energy").unwrap();
    let potential = result.channel("system.potential_energy").unwrap();
    let total: Vec<f64> = kinetic.iter().zip(potential).map(|(k, p)| k + p).collect();
    let swing = kinetic.iter().fold(0.0f64, |m, &k| m.max(k));
    // The chain falls from the horizontal: kinetic energy of hundreds of joules.
    assert!(swing > 100.0, "kinetic energy reached only {swing} J");
    let drift = total.iter().map(|e| (e - total[0]).abs()).fold(0.0, f64::max);
    assert!(drift < 1e-6 * swing, "energy drift {drift} J of {swing} J");
}

/// Rows of a 100-link chain listed in a scrambled order (link 37 k mod 100 at place k):
/// neighbouring links' rows lie far apart, the envelope fills much of the lower triangle,
/// and the sparse factor with its own ordering is chosen; listed in order, the same rows
/// form a band and get the envelope factor.
#[test]
fn rows_out_of_topological_order_get_the_sparse_factor() {
    let n = 100;
    let link = |k: usize| [if k == 0 { None } else { Some(k - 1) }, Some(k)];
    let in_order: Vec<_> = (0..n).flat_map(|k| [link(k), link(k)]).collect();
    let scrambled: Vec<_> = (0..n).flat_map(|k| [link(37 * k % n), link(37 * k % n)]).collect();
    assert_eq!(Schur::<[f64; 3]>::new(&in_order, Factorisation::Auto).factorisation(), Factorisation::Dense);
    assert_eq!(
        Schur::<[f64; 3]>::new(&scrambled, Factorisation::Auto).factorisation(),
        Factorisation::Sparse
    );
}

/// The envelope factor of a scrambled pattern, whose envelope holds entries that stay
/// zero and entries that fill in, solves `S x = b` as faer's sparse factor and as a
/// dense Cholesky of `S` built entry by entry from `Cq M^-1 Cq^T`.
#[test]
fn envelope_factor_with_fill_solves_as_a_dense_cholesky() {
    let n = 30;
    let link = |k: usize| [if k == 0 { None } else { Some(k - 1) }, Some(k)];
    let bodies: Vec<_> = (0..n).flat_map(|k| [link(7 * k % n), link(7 * k % n)]).collect();
    let m = bodies.len();
    let layout = Layout::new((0..n).map(|_| PLANAR_BODY));
    // Entries of each row from a fixed pseudo-random sequence in (-1, 1).
    let mut seed = 12345u64;
    let mut next = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let jac: Vec<RowJacobian> = bodies
        .iter()
        .map(|&b| RowJacobian {
            entries: [[next(), next(), next()], [next(), next(), next()]],
            ..RowJacobian::new(b, &layout)
        })
        .collect();
    let m_inv: Vec<f64> = (0..3 * n).map(|i| 1.0 + (i % 5) as f64).collect();
    let mut cq = DMatrix::zeros(m, 3 * n);
    for (a, row) in jac.iter().enumerate() {
        for (k, entries) in row.blocks() {
            for d in 0..3 {
                cq[(a, 3 * k + d)] = entries[d];
            }
        }
    }
    let s = &cq * DMatrix::from_diagonal(&DVector::from_vec(m_inv.clone())) * cq.transpose();
    let b: Vec<f64> = (0..m).map(|_| next()).collect();
    let expected = s.clone().cholesky().unwrap().solve(&DVector::from_vec(b.clone()));
    for factorisation in [Factorisation::Dense, Factorisation::Sparse] {
        let mut schur = Schur::new(&bodies, factorisation);
        assert_eq!(schur.factorisation(), factorisation);
        schur.update(&jac, &m_inv);
        let mut x = b.clone();
        schur.solve(&mut x).unwrap();
        let err = x.iter().zip(expected.iter()).map(|(x, e)| (x - e).abs()).fold(0.0, f64::max);
        assert!(err <= 1e-9 * expected.amax(), "{factorisation:?}: {err:e} of {:e}", expected.amax());
    }
}
