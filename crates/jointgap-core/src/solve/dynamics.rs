//! Equations of motion: constraints, applied forces and the augmented solve
//! `[M Cq^T; Cq 0][qdd; lambda] = [Qe; gamma]`, done through the Schur complement
//! `(Cq M^-1 Cq^T) lambda = Cq M^-1 Qe - gamma` because M is diagonal.

use nalgebra::{DMatrix, DVector};

use super::contacts::ContactState;
use crate::drivers::Motion;
use crate::system::System;

const NO_MOTION: Motion = Motion { position: 0.0, speed: 0.0, acceleration: 0.0 };

/// The augmented system is singular: the mechanism locks up or passes a singular
/// configuration (e.g. a four-bar at a change point).
#[derive(Debug, Clone, Copy)]
pub struct Singular;

/// Scratch space of one run, filled by the functions of this module.
#[derive(Debug, Clone)]
pub struct Workspace {
    /// Indices of the active rows in `System::rows`.
    pub active: Vec<usize>,
    /// Inverse of the diagonal mass matrix; (n_coords).
    pub m_inv: Vec<f64>,
    /// Filled by [`constraints`]: residuals; (n_active).
    pub c: DVector<f64>,
    /// Filled by [`constraints`]: Jacobian; (n_active x n_coords).
    pub cq: DMatrix<f64>,
    /// Filled by [`constraints`]: `dC/dt`; (n_active).
    pub ct: DVector<f64>,
    /// Filled by [`constraints`]: acceleration right-hand side; (n_active).
    pub gamma: DVector<f64>,
    /// Filled by [`applied_forces`]: generalised applied forces; (n_coords).
    pub qe: Vec<f64>,
    /// Filled by [`accelerations`]: `Cq M^-1`; (n_active x n_coords).
    pub cq_minv: DMatrix<f64>,
    /// Filled by [`accelerations`]: Schur complement `Cq M^-1 Cq^T`; (n_active^2).
    pub schur: DMatrix<f64>,
    /// Filled by [`accelerations`]: multipliers, one per active row; (n_active).
    pub lambda: DVector<f64>,
    /// Filled by [`accelerations`]: accelerations; (n_coords).
    pub qdd: Vec<f64>,
    /// Time inside the current step, selecting the driver profiles' pieces.
    pub t_piece: f64,
    /// Discrete state of each clearance joint; forces filled by [`applied_forces`].
    pub contacts: Vec<ContactState>,
}

impl Workspace {
    /// Allocates for a system whose active rows are `active`.
    pub fn new(sys: &System, active: Vec<usize>) -> Self {
        let n = sys.n_coords();
        let m = active.len();
        let mut m_inv = Vec::with_capacity(n);
        for b in &sys.bodies {
            m_inv.extend([1.0 / b.mass, 1.0 / b.mass, 1.0 / b.inertia]);
        }
        Workspace {
            active,
            m_inv,
            c: DVector::zeros(m),
            cq: DMatrix::zeros(m, n),
            ct: DVector::zeros(m),
            gamma: DVector::zeros(m),
            qe: vec![0.0; n],
            cq_minv: DMatrix::zeros(m, n),
            schur: DMatrix::zeros(m, m),
            lambda: DVector::zeros(m),
            qdd: vec![0.0; n],
            t_piece: 0.0,
            contacts: vec![ContactState::default(); sys.clearances.len()],
        }
    }
}

/// Evaluates the active constraint rows at `(t, q, v)`: fills `c`, `cq`, `ct`, `gamma`.
pub fn constraints(sys: &System, t: f64, q: &[f64], v: &[f64], ws: &mut Workspace) {
    ws.cq.fill(0.0);
    for (a, &r) in ws.active.iter().enumerate() {
        let row = &sys.rows[r];
        let motion = match row.driver {
            Some(d) => sys.drivers[d].profile.motion_on(t, ws.t_piece),
            None => NO_MOTION,
        };
        let ev = row.kind.eval(&sys.body_state(row.body_i, q, v), &sys.body_state(row.body_j, q, v), motion);
        ws.c[a] = ev.c;
        ws.ct[a] = ev.ct;
        ws.gamma[a] = ev.gamma;
        if let Some(k) = row.body_i {
            for (d, x) in ev.jac_i.iter().enumerate() {
                ws.cq[(a, 3 * k + d)] += x;
            }
        }
        if let Some(k) = row.body_j {
            for (d, x) in ev.jac_j.iter().enumerate() {
                ws.cq[(a, 3 * k + d)] += x;
            }
        }
    }
}

/// Fills `qe` with gravity and every force element at `(t, q, v)`.
pub fn applied_forces(sys: &System, t: f64, q: &[f64], v: &[f64], ws: &mut Workspace) {
    ws.qe.fill(0.0);
    for (k, b) in sys.bodies.iter().enumerate() {
        ws.qe[3 * k] += b.mass * sys.gravity.x;
        ws.qe[3 * k + 1] += b.mass * sys.gravity.y;
    }
    for f in &sys.forces {
        f.add_to(t, |b| sys.body_state(b, q, v), &mut ws.qe);
    }
    for (c, state) in sys.clearances.iter().zip(&ws.contacts) {
        let (bearing, journal) = (sys.body_state(c.bearing, q, v), sys.body_state(c.journal, q, v));
        c.add_to(&bearing, &journal, state, &mut ws.qe);
    }
}

/// Solves `S mu = rhs` in place with `S = Cq M^-1 Cq^T` (fills `cq_minv`, `schur`).
fn schur_solve(ws: &mut Workspace, rhs: &mut DVector<f64>) -> Result<(), Singular> {
    ws.cq_minv.copy_from(&ws.cq);
    for (j, mut col) in ws.cq_minv.column_iter_mut().enumerate() {
        col *= ws.m_inv[j];
    }
    // S = (Cq M^-1) Cq^T, entry by entry: S is small and symmetric.
    let m = ws.cq.nrows();
    for a in 0..m {
        for b in 0..=a {
            let s = ws.cq_minv.row(a).dot(&ws.cq.row(b));
            ws.schur[(a, b)] = s;
            ws.schur[(b, a)] = s;
        }
    }
    // S + eps I with iterative refinement: the solution of S x = rhs where S is well
    // conditioned; near a change point (a parallelogram with all bars collinear), where
    // S loses rank but the equations stay consistent, the regularisation keeps the
    // multipliers bounded and the accelerations, which do not depend on the null-space
    // part of lambda, accurate. This is the dual form of the augmented Lagrangian
    // method (Bayo and Ledesma 1996).
    let m = ws.schur.nrows();
    let scale = (0..m).map(|a| ws.schur[(a, a)]).fold(0.0, f64::max);
    let mut reg = ws.schur.clone();
    for a in 0..m {
        reg[(a, a)] += REGULARISATION * scale;
    }
    let chol = nalgebra::Cholesky::new(reg).ok_or(Singular)?;
    let target = rhs.clone();
    chol.solve_mut(rhs);
    for _ in 0..REFINEMENTS {
        let mut r = &target - &ws.schur * &*rhs;
        if r.amax() <= 1e-15 * target.amax() {
            break;
        }
        chol.solve_mut(&mut r);
        *rhs += r;
    }
    let residual = (&ws.schur * &*rhs - &target).amax();
    if residual > 1e-6 * target.amax().max(1e-300) && residual > 1e-12 {
        return Err(Singular);
    }
    if rhs.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(Singular)
    }
}

/// Accelerations and multipliers at `(t, q, v)`: fills everything in the workspace.
pub fn accelerations(sys: &System, t: f64, q: &[f64], v: &[f64], ws: &mut Workspace) -> Result<(), Singular> {
    constraints(sys, t, q, v, ws);
    applied_forces(sys, t, q, v, ws);
    let n = sys.n_coords();
    if ws.active.is_empty() {
        for i in 0..n {
            ws.qdd[i] = ws.m_inv[i] * ws.qe[i];
        }
        return Ok(());
    }
    // rhs = Cq M^-1 Qe - gamma
    let mut rhs = -ws.gamma.clone();
    for a in 0..ws.active.len() {
        let mut s = 0.0;
        for j in 0..n {
            s += ws.cq[(a, j)] * ws.m_inv[j] * ws.qe[j];
        }
        rhs[a] += s;
    }
    schur_solve(ws, &mut rhs)?;
    ws.lambda.copy_from(&rhs);
    for j in 0..n {
        let mut s = ws.qe[j];
        for a in 0..ws.active.len() {
            s -= ws.cq[(a, j)] * ws.lambda[a];
        }
        ws.qdd[j] = ws.m_inv[j] * s;
    }
    Ok(())
}

/// Mass-weighted projection of `q` onto `C(q, t) = 0` (a few Newton steps) and of `v`
/// onto `Cq v + Ct = 0`; `Singular` when the constraints cannot be met.
pub fn project(
    sys: &System,
    t: f64,
    q: &mut [f64],
    v: &mut [f64],
    ws: &mut Workspace,
) -> Result<(), Singular> {
    if ws.active.is_empty() {
        return Ok(());
    }
    let n = sys.n_coords();
    for _ in 0..4 {
        constraints(sys, t, q, v, ws);
        if ws.c.amax() <= POSITION_TOL {
            break;
        }
        let mut mu = ws.c.clone();
        schur_solve(ws, &mut mu)?;
        for j in 0..n {
            let mut s = 0.0;
            for a in 0..ws.active.len() {
                s += ws.cq[(a, j)] * mu[a];
            }
            q[j] -= ws.m_inv[j] * s;
        }
    }
    constraints(sys, t, q, v, ws);
    if ws.c.amax() > 1e3 * POSITION_TOL {
        return Err(Singular);
    }
    let mut mu = &ws.cq * DVector::from_column_slice(v) + &ws.ct;
    schur_solve(ws, &mut mu)?;
    for j in 0..n {
        let mut s = 0.0;
        for a in 0..ws.active.len() {
            s += ws.cq[(a, j)] * mu[a];
        }
        v[j] -= ws.m_inv[j] * s;
    }
    Ok(())
}

/// Relative diagonal shift of the Schur complement (see `schur_solve`).
const REGULARISATION: f64 = 1e-12;
/// Iterative-refinement sweeps of the regularised solve.
const REFINEMENTS: usize = 3;

/// Position residual below which projection stops [m or rad].
pub const POSITION_TOL: f64 = 1e-13;

/// Largest position residual and velocity residual of the active rows at `(t, q, v)`.
pub fn violation(sys: &System, t: f64, q: &[f64], v: &[f64], ws: &mut Workspace) -> (f64, f64) {
    if ws.active.is_empty() {
        return (0.0, 0.0);
    }
    constraints(sys, t, q, v, ws);
    let vel = &ws.cq * DVector::from_column_slice(v) + &ws.ct;
    (ws.c.amax(), vel.amax())
}
