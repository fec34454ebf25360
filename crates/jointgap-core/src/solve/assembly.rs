//! Initial conditions: Newton solve of the position constraints from the user's
//! approximate placement, detection of redundant rows, then the velocity constraints.

use nalgebra::{DMatrix, DVector};

use super::dynamics::{constraints, Workspace};
use crate::system::{Owner, System};
use crate::Error;

/// Residual that counts as assembled [m or rad].
const ASSEMBLY_TOL: f64 = 1e-12;
/// A row whose part independent of the earlier rows is smaller than this fraction of its
/// norm is redundant.
const REDUNDANT_TOL: f64 = 1e-8;

/// Consistent initial state of a system.
#[derive(Debug, Clone)]
pub struct Assembled {
    /// Coordinates satisfying `C(q, 0) = 0`.
    pub q: Vec<f64>,
    /// Velocities satisfying `Cq v + Ct = 0`.
    pub v: Vec<f64>,
    /// Indices of the independent rows.
    pub active: Vec<usize>,
    /// Redundant rows removed, one note each.
    pub warnings: Vec<String>,
}

/// Minimum-norm solution of `A x = b` (least squares when inconsistent).
fn min_norm_solve(a: &DMatrix<f64>, b: &DVector<f64>) -> DVector<f64> {
    let svd = a.clone().svd(true, true);
    let tol = 1e-10 * svd.singular_values.max().max(1e-300);
    svd.solve(b, tol).unwrap_or_else(|_| DVector::zeros(a.ncols()))
}

/// Assembles the mechanism at t = 0.
pub fn assemble(sys: &System) -> Result<Assembled, Error> {
    let all: Vec<usize> = (0..sys.rows.len()).collect();
    let mut ws = Workspace::in_order(sys, all.clone());
    let mut q = sys.q_guess.clone();
    let v0 = sys.v_guess.clone();
    let t = 0.0;
    if !all.is_empty() {
        let mut converged = false;
        for _ in 0..100 {
            constraints(sys, t, &q, &v0, &mut ws);
            let r0 = ws.c.amax();
            if r0 <= ASSEMBLY_TOL {
                converged = true;
                break;
            }
            let dq = min_norm_solve(&ws.dense_jacobian(), &ws.c);
            // Damped Newton: halve the step while the residual grows.
            let mut step = 1.0;
            let mut trial = q.clone();
            for _ in 0..30 {
                for j in 0..q.len() {
                    trial[j] = q[j] - step * dq[j];
                }
                constraints(sys, t, &trial, &v0, &mut ws);
                if ws.c.amax() < r0 {
                    break;
                }
                step *= 0.5;
            }
            if ws.c.amax() >= r0 {
                break; // stalled: the constraints cannot all be met from here
            }
            q.clone_from(&trial);
        }
        if !converged {
            constraints(sys, t, &q, &v0, &mut ws);
            let mut off: Vec<(usize, f64)> =
                ws.c.iter().enumerate().filter(|(_, c)| c.abs() > 1e-6).map(|(r, c)| (r, c.abs())).collect();
            off.sort_by(|a, b| b.1.partial_cmp(&a.1).unwrap());
            let mut names: Vec<String> = Vec::new();
            for (r, c) in off {
                let who = element_name(sys, sys.rows[r].owner);
                if !names.iter().any(|n| n.starts_with(&who)) {
                    names.push(format!("{who} (off by {c:.3e})"));
                }
            }
            if names.is_empty() {
                names.push("the constraints as a whole".into());
            }
            return Err(Error::Assembly(format!(
                "cannot assemble the mechanism from the given placement: {} cannot be satisfied; \
                 check the joint points, the body positions and angles, and the driver's initial value",
                names.join(", ")
            )));
        }
    }
    let (active, warnings) = independent_rows(sys, &ws.dense_jacobian())?;
    // Velocities: the smallest change of the user's values that satisfies Cq v = -Ct.
    let mut ws = Workspace::in_order(sys, active.clone());
    constraints(sys, t, &q, &v0, &mut ws);
    let mut v = v0.clone();
    if !active.is_empty() {
        let cq = ws.dense_jacobian();
        let resid = &cq * DVector::from_column_slice(&v0) + &ws.ct;
        let dv = min_norm_solve(&cq, &resid);
        for j in 0..v.len() {
            v[j] -= dv[j];
        }
    }
    Ok(Assembled { q, v, active, warnings })
}

/// `joint 'name'` or `driver 'name'`.
pub fn element_name(sys: &System, owner: Owner) -> String {
    match owner {
        Owner::Joint(k) => format!("joint '{}'", sys.joints[k].name),
        Owner::Driver(k) => format!("driver '{}'", sys.drivers[k].name),
    }
}

/// Gram-Schmidt over the Jacobian rows in model order: a row that depends on earlier
/// ones is redundant and dropped (a warning names it); a redundant driver is an error,
/// since it would fight the joints.
fn independent_rows(sys: &System, cq: &DMatrix<f64>) -> Result<(Vec<usize>, Vec<String>), Error> {
    let mut basis: Vec<DVector<f64>> = Vec::new();
    let mut active = Vec::new();
    let mut warnings = Vec::new();
    for r in 0..cq.nrows() {
        let row: DVector<f64> = cq.row(r).transpose();
        let norm = row.norm();
        let mut rest = row.clone();
        for b in &basis {
            let p = b.dot(&rest);
            rest.axpy(-p, b, 1.0);
        }
        if rest.norm() > REDUNDANT_TOL * norm.max(1e-300) {
            basis.push(rest.normalize());
            active.push(r);
            continue;
        }
        let row_info = &sys.rows[r];
        if let Owner::Driver(_) = row_info.owner {
            return Err(Error::Assembly(format!(
                "{}: the driven joint cannot move, the other constraints already fix it",
                element_name(sys, row_info.owner)
            )));
        }
        warnings.push(format!(
            "{}: redundant constraint equation removed (it repeats the others); the joint reactions \
             of a redundant mechanism are not unique, this one's share is reported as zero",
            row_info.label
        ));
    }
    Ok((active, warnings))
}
