//! A first-order ODE `y' = f(t, y)` with `y = (q, v)` and `f = (v, a)` as the methods
//! see it, the tolerance-weighted error norm they share, and the dense output of a step.

use nalgebra::DMatrix;

use crate::profile::Profile;

/// `f(t, y)` has no value at a state: the system behind it is singular there (for the
/// equations of motion, the mechanism locks up). No step can pass such a state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Singular;

/// A first-order system `y' = f(t, y)` as the methods see it: the equations of motion
/// (the simulation loop's `Ode`), or a model problem in their tests.
pub trait Rhs {
    /// Writes `f(t, y)` into `dy`.
    fn eval(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Singular>;
    /// Where stage times are booked when the run measures them.
    fn profile(&mut self) -> &mut Option<Profile>;
    /// The acceleration rows of `df/dy` ((n/2) x n) by a cheaper route than forward
    /// differences of [`Rhs::eval`], where there is one; `None` where not.
    fn force_jacobian(
        &mut self,
        _t: f64,
        _y: &[f64],
        _jac: &mut DMatrix<f64>,
    ) -> Option<Result<(), Singular>> {
        None
    }
}

/// Tolerances of a run: a method accepts a step whose local error, weighted by them,
/// is at most 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
}

impl Tolerances {
    /// RMS of `err_i / (atol + rtol max(|y0_i|, |y1_i|))` (Hairer, Norsett, Wanner I, II.4).
    pub fn error_norm(&self, err: &[f64], y0: &[f64], y1: &[f64]) -> f64 {
        let mut sum = 0.0;
        for i in 0..err.len() {
            let sc = self.atol + self.rtol * y0[i].abs().max(y1[i].abs());
            sum += (err[i] / sc).powi(2);
        }
        (sum / err.len().max(1) as f64).sqrt()
    }
}

/// One accepted step's ends, `(y0, f0)` at its start and `(y1, f1)` at its end, `h`
/// long: what its dense output ([`hermite5`]) is built from.
#[derive(Debug, Clone, Copy)]
pub struct DenseStep<'a> {
    /// Step size.
    pub h: f64,
    /// State at the start.
    pub y0: &'a [f64],
    /// Derivative at the start.
    pub f0: &'a [f64],
    /// State at the end.
    pub y1: &'a [f64],
    /// Derivative at the end.
    pub f1: &'a [f64],
}

impl DenseStep<'_> {
    /// The state at `theta` (0 at the start, 1 at the end) into `out`.
    pub fn at(&self, theta: f64, out: &mut [f64]) {
        hermite5(theta, self.h, self.y0, self.f0, self.y1, self.f1, out);
    }
}

/// Quintic Hermite interpolation of a second-order system over one step: positions from
/// their values, velocities and accelerations at both ends (6th order), velocities as
/// its derivative. `y0`, `f0` at the start, `y1`, `f1` at the end, `h` the step.
pub fn hermite5(theta: f64, h: f64, y0: &[f64], f0: &[f64], y1: &[f64], f1: &[f64], out: &mut [f64]) {
    let n = y0.len() / 2;
    let s = theta;
    let (s2, s3) = (s * s, s * s * s);
    let (s4, s5) = (s3 * s, s3 * s2);
    let h0 = 1.0 - 10.0 * s3 + 15.0 * s4 - 6.0 * s5;
    let h1 = s - 6.0 * s3 + 8.0 * s4 - 3.0 * s5;
    let h2 = 0.5 * (s2 - 3.0 * s3 + 3.0 * s4 - s5);
    let h3 = 10.0 * s3 - 15.0 * s4 + 6.0 * s5;
    let h4 = -4.0 * s3 + 7.0 * s4 - 3.0 * s5;
    let h5 = 0.5 * (s3 - 2.0 * s4 + s5);
    // d/dtheta of the basis
    let d0 = -30.0 * s2 + 60.0 * s3 - 30.0 * s4;
    let d1 = 1.0 - 18.0 * s2 + 32.0 * s3 - 15.0 * s4;
    let d2 = 0.5 * (2.0 * s - 9.0 * s2 + 12.0 * s3 - 5.0 * s4);
    let d3 = -d0;
    let d4 = -12.0 * s2 + 28.0 * s3 - 15.0 * s4;
    let d5 = 0.5 * (3.0 * s2 - 8.0 * s3 + 5.0 * s4);
    for i in 0..n {
        let (q0, v0, a0) = (y0[i], y0[n + i], f0[n + i]);
        let (q1, v1, a1) = (y1[i], y1[n + i], f1[n + i]);
        out[i] = h0 * q0 + h * h1 * v0 + h * h * h2 * a0 + h3 * q1 + h * h4 * v1 + h * h * h5 * a1;
        out[n + i] = (d0 * q0 + d3 * q1) / h + d1 * v0 + h * d2 * a0 + d4 * v1 + h * d5 * a1;
    }
}

#[cfg(test)]
mod tests {
    use super::hermite5;

    /// Exact for quintic positions: q = t^5 - 2 t^3 + t on [0.3, 0.8].
    #[test]
    fn hermite5_reproduces_a_quintic() {
        let q = |t: f64| t.powi(5) - 2.0 * t.powi(3) + t;
        let v = |t: f64| 5.0 * t.powi(4) - 6.0 * t * t + 1.0;
        let a = |t: f64| 20.0 * t.powi(3) - 12.0 * t;
        let (ta, tb) = (0.3, 0.8);
        let y0 = [q(ta), v(ta)];
        let f0 = [v(ta), a(ta)];
        let y1 = [q(tb), v(tb)];
        let f1 = [v(tb), a(tb)];
        let mut out = [0.0; 2];
        for k in 0..=10 {
            let th = k as f64 / 10.0;
            let t = ta + th * (tb - ta);
            hermite5(th, tb - ta, &y0, &f0, &y1, &f1, &mut out);
            assert!((out[0] - q(t)).abs() < 1e-14, "q at {t}");
            assert!((out[1] - v(t)).abs() < 1e-13, "v at {t}");
        }
    }
}
