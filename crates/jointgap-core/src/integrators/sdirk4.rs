//! L-stable SDIRK of order 4 with an embedded order-3 estimate, gamma = 1/4 (Hairer and
//! Wanner, Solving ODEs II, Table IV.6.5). Stages are solved by simplified Newton with a
//! Jacobian reused across steps while Newton converges fast: `[0 G; acceleration rows]`,
//! with `G = d(q')/d(v)` from [`Rhs::rate_jacobian`] and the acceleration rows from
//! [`Rhs::acceleration_jacobian`], or forward differences of the whole right-hand side
//! (every row, `d(q')/d(q)` included) where it has no such rows, or after Newton fails
//! with fresh rows of the applied forces alone, until Newton converges again.

use nalgebra::{DMatrix, DVector};

use super::jacobian;
use super::ode::{JacobianKind, Rhs, Singular, Tolerances};
use super::stepper::{Attempt, StepFailure, Stepper};
use crate::profile;

const GAMMA: f64 = 0.25;
const C: [f64; 5] = [0.25, 0.75, 11.0 / 20.0, 0.5, 1.0];
const A: [[f64; 5]; 5] = [
    [0.25, 0.0, 0.0, 0.0, 0.0],
    [0.5, 0.25, 0.0, 0.0, 0.0],
    [17.0 / 50.0, -1.0 / 25.0, 0.25, 0.0, 0.0],
    [371.0 / 1360.0, -137.0 / 2720.0, 15.0 / 544.0, 0.25, 0.0],
    [25.0 / 24.0, -49.0 / 48.0, 125.0 / 16.0, -85.0 / 12.0, 0.25],
];
/// Embedded 3rd-order weights.
const B_HAT: [f64; 5] = [59.0 / 48.0, -17.0 / 96.0, 225.0 / 32.0, -85.0 / 12.0, 0.0];

/// Newton state of the implicit method.
pub struct Sdirk4 {
    /// Position coordinates of the state.
    nq: usize,
    jac: DMatrix<f64>,
    jac_fresh: bool,
    jac_valid: bool,
    /// The current Jacobian's acceleration rows are the applied forces' part alone.
    jac_from_forces: bool,
    /// Newton failed with fresh rows of the applied forces: forward differences until it
    /// converges.
    full_jacobian: bool,
    /// The acceleration rows `[dv'/dq dv'/dv]`; (nv x n).
    lower: DMatrix<f64>,
    jac_evals: usize,
    newton_iterations: usize,
    lu: Option<nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>>,
    lu_h: f64,
    slow: bool,
    k: Vec<Vec<f64>>,
    base: Vec<f64>,
    stage: Vec<f64>,
    work: Vec<f64>,
}

impl Sdirk4 {
    /// Allocates for a state of `nq` positions and `nv` velocities.
    pub fn new(nq: usize, nv: usize) -> Self {
        let n = nq + nv;
        Sdirk4 {
            nq,
            jac: DMatrix::zeros(n, n),
            jac_fresh: false,
            jac_valid: false,
            jac_from_forces: false,
            full_jacobian: false,
            lower: DMatrix::zeros(nv, n),
            jac_evals: 0,
            newton_iterations: 0,
            lu: None,
            lu_h: 0.0,
            slow: false,
            k: vec![vec![0.0; n]; 5],
            base: vec![0.0; n],
            stage: vec![0.0; n],
            work: vec![0.0; n],
        }
    }

    /// Jacobian of f at (t, y): `[0 G; acceleration rows]`, or forward differences.
    fn jacobian<R: Rhs + ?Sized>(
        &mut self,
        ode: &mut R,
        t: f64,
        y: &[f64],
        f0: &[f64],
    ) -> Result<(), Singular> {
        let cheap = if self.full_jacobian { None } else { ode.acceleration_jacobian(t, y, &mut self.lower) };
        self.jac_from_forces = matches!(cheap, Some(Ok(JacobianKind::Forces)));
        match cheap {
            Some(done) => {
                done?;
                let (nq, nv) = (self.nq, self.lower.nrows());
                self.jac.fill(0.0);
                ode.rate_jacobian(&y[..nq], self.jac.view_mut((0, nq), (nq, nv)));
                self.jac.rows_mut(nq, nv).copy_from(&self.lower);
            }
            None => jacobian::forward_difference(ode, t, y, f0, 0, &mut self.jac, &mut self.work)?,
        }
        self.jac_evals += 1;
        self.jac_fresh = true;
        self.jac_valid = true;
        self.lu = None;
        Ok(())
    }

    fn factor(&mut self, h: f64) -> Result<(), StepFailure> {
        if self.lu.is_some() && self.lu_h == h {
            return Ok(());
        }
        let n = self.jac.nrows();
        let m = DMatrix::identity(n, n) - &self.jac * (h * GAMMA);
        let lu = m.lu();
        if !lu.is_invertible() {
            return Err(StepFailure::Convergence);
        }
        self.lu = Some(lu);
        self.lu_h = h;
        Ok(())
    }

    /// Solves stage `s`: `Y = base + h gamma f(Y)`; leaves `Y` in `stage`, `f(Y)` in `k[s]`.
    fn solve_stage<R: Rhs + ?Sized>(
        &mut self,
        ode: &mut R,
        tol: Tolerances,
        t: f64,
        h: f64,
        s: usize,
        y: &[f64],
    ) -> Result<(), StepFailure> {
        let n = y.len();
        let lu = self.lu.as_ref().expect("factored before the stages");
        // Predictor: the previous stage's slope.
        let guess = if s == 0 { 0 } else { s - 1 };
        for i in 0..n {
            self.stage[i] = self.base[i] + h * GAMMA * self.k[guess][i];
        }
        let mut prev_norm = f64::INFINITY;
        for iter in 0..10 {
            self.newton_iterations += 1;
            ode.eval(t + C[s] * h, &self.stage, &mut self.work).map_err(|Singular| StepFailure::Singular)?;
            let mut r = DVector::from_fn(n, |i, _| self.base[i] + h * GAMMA * self.work[i] - self.stage[i]);
            lu.solve_mut(&mut r);
            let norm = tol.error_norm(r.as_slice(), y, &self.stage);
            for i in 0..n {
                self.stage[i] += r[i];
            }
            if !norm.is_finite() {
                return Err(StepFailure::Convergence);
            }
            let rate = norm / prev_norm;
            if iter > 0 && rate > 0.9 {
                return Err(StepFailure::Convergence);
            }
            if iter > 0 && rate > 0.3 {
                self.slow = true;
            }
            let eta = if iter == 0 { 1.0 } else { rate / (1.0 - rate) };
            if norm < 1e-10 || eta * norm < 0.01 {
                // k from the stage relation, consistent with the converged Y.
                for i in 0..n {
                    self.k[s][i] = (self.stage[i] - self.base[i]) / (h * GAMMA);
                }
                return Ok(());
            }
            prev_norm = norm;
        }
        Err(StepFailure::Convergence)
    }
}

impl<R: Rhs + ?Sized> Stepper<R> for Sdirk4 {
    fn name(&self) -> &'static str {
        "sdirk4"
    }

    fn error_exponent(&self) -> f64 {
        1.0 / 4.0
    }

    fn jacobian_evaluations(&self) -> usize {
        self.jac_evals
    }

    fn newton_iterations(&self) -> usize {
        self.newton_iterations
    }

    fn rejected(&mut self) {
        self.slow = true;
    }

    fn spectral_radius(&mut self, ode: &mut R, t: f64, y: &[f64], f: &[f64]) -> Option<f64> {
        let lap = profile::start(ode.profile());
        self.jacobian(ode, t, y, f).ok()?;
        let radius = self.jac.complex_eigenvalues().iter().map(|z| z.norm()).fold(0.0, f64::max);
        profile::stop(ode.profile(), lap, |p| &mut p.jacobians);
        radius.is_finite().then_some(radius)
    }

    fn attempt(
        &mut self,
        ode: &mut R,
        tol: Tolerances,
        t: f64,
        y: &[f64],
        f0: &[f64],
        h: f64,
        y_new: &mut [f64],
        f_new: &mut [f64],
    ) -> Result<Attempt, StepFailure> {
        let n = y.len();
        if !self.jac_valid || (self.slow && !self.jac_fresh) {
            let lap = profile::start(ode.profile());
            self.jacobian(ode, t, y, f0).map_err(|Singular| StepFailure::Singular)?;
            profile::stop(ode.profile(), lap, |p| &mut p.jacobians);
            self.slow = false;
        }
        let lap = profile::start(ode.profile());
        let factored = self.factor(h);
        profile::stop(ode.profile(), lap, |p| &mut p.jacobians);
        factored?;
        for s in 0..5 {
            for i in 0..n {
                let mut acc = 0.0;
                for j in 0..s {
                    acc += A[s][j] * self.k[j][i];
                }
                self.base[i] = y[i] + h * acc;
            }
            if let Err(e) = self.solve_stage(ode, tol, t, h, s, y) {
                if e == StepFailure::Convergence {
                    self.slow = true;
                    self.full_jacobian |= self.jac_fresh && self.jac_from_forces;
                }
                return Err(e);
            }
        }
        self.jac_fresh = false;
        self.full_jacobian = false;
        // Stiffly accurate: the last stage is the solution.
        y_new.copy_from_slice(&self.stage);
        ode.update_positions(&mut y_new[..self.nq]);
        ode.eval(t + h, y_new, f_new).map_err(|Singular| StepFailure::Singular)?;
        let mut err = DVector::from_fn(n, |i, _| {
            let mut e = 0.0;
            for j in 0..5 {
                e += (A[4][j] - B_HAT[j]) * self.k[j][i];
            }
            h * e
        });
        // Filter through (I - h gamma J)^-1 so stiff components do not inflate the
        // estimate (Shampine's device, as in RADAU5).
        self.lu.as_ref().expect("factored").solve_mut(&mut err);
        Ok(Attempt { error: tol.error_norm(err.as_slice(), y, y_new), stiffness: None })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Order conditions up to 4 for the solution and 3 for the embedded weights.
    #[test]
    fn tableau_meets_order_conditions() {
        let b = A[4];
        for s in 0..5 {
            assert!((A[s].iter().sum::<f64>() - C[s]).abs() < 1e-14, "row {s}");
            assert_eq!(A[s][s], GAMMA);
        }
        let dot = |w: &[f64; 5], f: &dyn Fn(usize) -> f64| (0..5).map(|i| w[i] * f(i)).sum::<f64>();
        let ac = |i: usize| (0..5).map(|j| A[i][j] * C[j]).sum::<f64>();
        let ac2 = |i: usize| (0..5).map(|j| A[i][j] * C[j] * C[j]).sum::<f64>();
        let aac = |i: usize| (0..5).map(|j| A[i][j] * ac(j)).sum::<f64>();
        for (w, order) in [(&b, 4), (&B_HAT, 3)] {
            assert!((dot(w, &|_| 1.0) - 1.0).abs() < 1e-13);
            assert!((dot(w, &|i| C[i]) - 0.5).abs() < 1e-13);
            assert!((dot(w, &|i| C[i] * C[i]) - 1.0 / 3.0).abs() < 1e-13);
            assert!((dot(w, &ac) - 1.0 / 6.0).abs() < 1e-13);
            if order == 4 {
                assert!((dot(w, &|i| C[i].powi(3)) - 0.25).abs() < 1e-13);
                assert!((dot(w, &|i| C[i] * ac(i)) - 0.125).abs() < 1e-13);
                assert!((dot(w, &ac2) - 1.0 / 12.0).abs() < 1e-13);
                assert!((dot(w, &aac) - 1.0 / 24.0).abs() < 1e-13);
            }
        }
    }
}
