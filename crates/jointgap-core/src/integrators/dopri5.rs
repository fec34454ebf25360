//! Dormand-Prince 5(4): explicit, 7 stages with first-same-as-last (Dormand and Prince
//! 1980; coefficients as in Hairer, Norsett, Wanner, Solving ODEs I, Table II.5.2).

use super::ode::{Rhs, Singular, Tolerances};
use super::stepper::{Attempt, StepFailure, Stepper};

const C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0],
    [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0],
    [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0],
];
/// Difference of the 5th- and 4th-order weights: the local error estimate.
const E: [f64; 7] =
    [71.0 / 57600.0, 0.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0];

/// Stage storage of the explicit method.
pub struct Dopri5 {
    /// Position coordinates of the state.
    nq: usize,
    k: Vec<Vec<f64>>,
    stage: Vec<f64>,
    err: Vec<f64>,
}

impl Dopri5 {
    /// Allocates for a state of `nq` positions and `nv` velocities.
    pub fn new(nq: usize, nv: usize) -> Self {
        let n = nq + nv;
        Dopri5 { nq, k: vec![vec![0.0; n]; 7], stage: vec![0.0; n], err: vec![0.0; n] }
    }
}

impl<R: Rhs + ?Sized> Stepper<R> for Dopri5 {
    fn name(&self) -> &'static str {
        "dopri5"
    }

    fn error_exponent(&self) -> f64 {
        1.0 / 5.0
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
        self.k[0].copy_from_slice(f0);
        for s in 1..7 {
            let (y, stage) = (&y[..n], &mut self.stage[..n]);
            weighted_sum(&A[s][..s], &self.k, n, |i, sum| stage[i] = y[i] + h * sum);
            ode.eval(t + C[s] * h, &self.stage, &mut self.k[s]).map_err(|Singular| StepFailure::Singular)?;
            if s == 5 {
                // Keep stage 6 for the stiffness test; stage 7 is the new solution.
                self.err.copy_from_slice(&self.stage);
            }
        }
        // Stage 7's argument is the 5th-order solution (FSAL).
        y_new.copy_from_slice(&self.stage);
        f_new.copy_from_slice(&self.k[6]);
        // Stiffness indicator h |lambda| ~ h |k7 - k6| / |y7 - y6| (Hairer's DOPRI5 code).
        let (mut num, mut den) = (0.0, 0.0);
        for i in 0..n {
            num += (self.k[6][i] - self.k[5][i]).powi(2);
            den += (y_new[i] - self.err[i]).powi(2);
        }
        let stiffness = if den > 0.0 { Some(h * (num / den).sqrt()) } else { None };
        let err = &mut self.err[..n];
        weighted_sum(&E, &self.k, n, |i, sum| err[i] = h * sum);
        let error = tol.error_norm(&self.err, y, y_new);
        // Positions brought back onto their manifold: f at the state handed back.
        if ode.update_positions(&mut y_new[..self.nq]) {
            ode.eval(t + h, y_new, f_new).map_err(|Singular| StepFailure::Singular)?;
        }
        Ok(Attempt { error, stiffness })
    }
}

/// Hands `put(i, sum_j w_j k_j[i])` for each of the `n` entries, each sum taken from zero
/// in stage order (which fixes its rounding), over the first `w.len()` stages (1 to 7).
#[inline]
fn weighted_sum(w: &[f64], k: &[Vec<f64>], n: usize, put: impl FnMut(usize, f64)) {
    match w.len() {
        1 => sum_of::<1>(w, k, n, put),
        2 => sum_of::<2>(w, k, n, put),
        3 => sum_of::<3>(w, k, n, put),
        4 => sum_of::<4>(w, k, n, put),
        5 => sum_of::<5>(w, k, n, put),
        6 => sum_of::<6>(w, k, n, put),
        _ => sum_of::<7>(w, k, n, put),
    }
}

/// [`weighted_sum`] over `S` stages, a count the compiler knows, so that the loop over
/// the entries is unrolled over the stages and vectorised.
#[inline(always)]
fn sum_of<const S: usize>(w: &[f64], k: &[Vec<f64>], n: usize, mut put: impl FnMut(usize, f64)) {
    let w: [f64; S] = std::array::from_fn(|j| w[j]);
    let k: [&[f64]; S] = std::array::from_fn(|j| &k[j][..n]);
    for i in 0..n {
        let mut sum = 0.0;
        for j in 0..S {
            sum += w[j] * k[j][i];
        }
        put(i, sum);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Row sums equal the nodes, and the 5th-order weights meet the order conditions.
    #[test]
    fn tableau_is_consistent() {
        for s in 0..7 {
            let sum: f64 = A[s].iter().sum();
            assert!((sum - C[s]).abs() < 1e-15, "row {s}");
        }
        let b = A[6];
        let bc: f64 = (0..6).map(|i| b[i] * C[i]).sum();
        let bc4: f64 = (0..6).map(|i| b[i] * C[i].powi(4)).sum();
        assert!((bc - 0.5).abs() < 1e-15 && (bc4 - 0.2).abs() < 1e-15);
        assert!(E.iter().sum::<f64>().abs() < 1e-15);
    }
}
