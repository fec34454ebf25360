//! A first-order ODE `y' = f(t, y)` with `y = (q, v)` and `f = (G(q) v, a)` as the
//! methods see it, the tolerance-weighted error norm they share, and the dense output of
//! a step.

use nalgebra::{DMatrix, DMatrixViewMut};

use crate::profile::Profile;

/// `f(t, y)` has no value at a state: the system behind it is singular there (for the
/// equations of motion, the mechanism locks up). No step can pass such a state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Singular;

/// How the positions of a state `y = (q, v)` move with its velocities.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PositionRate {
    /// `q' = v` (`G = I`, `nq = nv`): planar bodies. The methods use the structure of a
    /// second-order system exactly (Radau IIA's reduced solve, the quintic dense output).
    Identity,
    /// `q' = G(q) v` with `G` given by [`Rhs::position_rate`] and [`Rhs::rate_jacobian`]
    /// (a unit quaternion moved by an angular velocity: `nq = 4`, `nv = 3`).
    Mapped,
}

/// How a state `y = (q, v)` divides: `q = y[..nq]`, `v = y[nq..]`, and how `q` moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StateShape {
    /// Position coordinates.
    pub nq: usize,
    /// Velocity coordinates.
    pub nv: usize,
    /// `q' = v` or `q' = G(q) v`.
    pub rate: PositionRate,
}

impl StateShape {
    /// Length of the state `y`, `nq + nv`.
    pub fn state_len(&self) -> usize {
        self.nq + self.nv
    }
}

/// A first-order system `y' = f(t, y)` with `y = (q, v)` and `f = (q', v')`,
/// `q' = G(q) v`, as the methods see it: the equations of motion (the simulation loop's
/// `Ode`), or a model problem in their tests.
pub trait Rhs {
    /// The state's sizes (`y.len() == nq + nv`) and how its positions move.
    fn shape(&self) -> StateShape;
    /// Writes `f(t, y)` into `dy`.
    fn eval(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Singular>;
    /// Writes the position rate `q' = G(q) v` (`nq` long) into `qdot`: what `eval` writes
    /// into `dy[..nq]`. The default is `G = I`, a copy of `v` ([`PositionRate::Identity`]).
    fn position_rate(&self, _q: &[f64], v: &[f64], qdot: &mut [f64]) {
        qdot.copy_from_slice(v);
    }
    /// Writes `d(q')/d(v) = G(q)` (nq x nv) into `g`, the upper right block of the
    /// implicit methods' Jacobian `df/dy`; the default is the identity. The block beside
    /// it, `d(q')/d(q) = d(G(q) v)/d(q)`, is zero for `q' = v`; where `G` varies it is of
    /// the order of the speeds, not of a stiffness, and the methods' Newton matrices leave
    /// it out (it steers the iterations only, not what they converge to), except the
    /// forward-difference Jacobian of all rows that SDIRK4 falls back to
    /// ([`crate::integrators::jacobian`]), which has it.
    fn rate_jacobian(&self, _q: &[f64], mut g: DMatrixViewMut<'_, f64>) {
        g.fill_with_identity();
    }
    /// Writes the positions' second derivatives `q'' = G(q) a + (dG/dt) v` (`nq` long)
    /// at positions `q`, velocities `v` and accelerations `a`, for the dense output where
    /// `q' = G(q) v` ([`DenseStep::qdd`]); `a` itself by default (`G = I`).
    fn position_acceleration(&self, _q: &[f64], _v: &[f64], a: &[f64], qdd: &mut [f64]) {
        qdd.copy_from_slice(a);
    }
    /// Brings the positions of a state a method has just stepped to back onto their
    /// manifold (renormalises a unit quaternion); returns whether it changed them, so that
    /// a method evaluates `f` at the state it hands back. Nothing by default.
    fn update_positions(&mut self, _q: &mut [f64]) -> bool {
        false
    }
    /// Where stage times are booked when the run measures them.
    fn profile(&mut self) -> &mut Option<Profile>;
    /// The acceleration rows of `df/dy` (nv x (nq + nv)) by another route than forward
    /// differences of [`Rhs::eval`], where there is one, and how exact it is; `None`
    /// where there is none.
    fn acceleration_jacobian(
        &mut self,
        _t: f64,
        _y: &[f64],
        _jac: &mut DMatrix<f64>,
    ) -> Option<Result<JacobianKind, Singular>> {
        None
    }
}

/// How [`Rhs::acceleration_jacobian`] took its rows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JacobianKind {
    /// The derivatives of the accelerations themselves: a Newton iteration that fails
    /// with it needs a smaller step, not another Jacobian.
    Exact,
    /// The applied forces' part alone: a Newton iteration that fails with it takes
    /// forward differences of the whole right-hand side next.
    Forces,
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
/// long: what its dense output is built from.
#[derive(Debug, Clone, Copy)]
pub struct DenseStep<'a> {
    /// How the states divide and how their positions move.
    pub shape: StateShape,
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
    /// Where `q' = G(q) v`: the positions' second derivatives `q''` at the start and at
    /// the end, when the caller has them ([`Rhs::position_acceleration`]).
    pub qdd: Option<[&'a [f64]; 2]>,
}

impl DenseStep<'_> {
    /// The state at `theta` (0 at the start, 1 at the end) into `out`: for `q' = v` the
    /// quintic of [`hermite5`]; for `q' = G(q) v`, positions by the quintic of their
    /// values, rates and second derivatives where `qdd` gives them (else the cubic of
    /// [`hermite3`]), velocities by the cubic of their values and accelerations.
    pub fn at(&self, theta: f64, out: &mut [f64]) {
        match self.shape.rate {
            PositionRate::Identity => {
                hermite5(theta, self.h, self.shape.nq, self.y0, self.f0, self.y1, self.f1, out)
            }
            PositionRate::Mapped => {
                hermite3(theta, self.h, self.y0, self.f0, self.y1, self.f1, out);
                if let Some([qdd0, qdd1]) = self.qdd {
                    let nq = self.shape.nq;
                    let (q0, q1) = (&self.y0[..nq], &self.y1[..nq]);
                    positions5(
                        theta,
                        self.h,
                        [q0, &self.f0[..nq], qdd0],
                        [q1, &self.f1[..nq], qdd1],
                        &mut out[..nq],
                    );
                }
            }
        }
    }
}

/// Quintic Hermite interpolation of positions from their values, rates and second
/// derivatives at both ends of a step `h` long (6th order, as [`hermite5`]'s positions).
pub fn positions5(theta: f64, h: f64, [q0, d0, a0]: [&[f64]; 3], [q1, d1, a1]: [&[f64]; 3], out: &mut [f64]) {
    let s = theta;
    let (s2, s3) = (s * s, s * s * s);
    let (s4, s5) = (s3 * s, s3 * s2);
    let h0 = 1.0 - 10.0 * s3 + 15.0 * s4 - 6.0 * s5;
    let h1 = s - 6.0 * s3 + 8.0 * s4 - 3.0 * s5;
    let h2 = 0.5 * (s2 - 3.0 * s3 + 3.0 * s4 - s5);
    let h3 = 10.0 * s3 - 15.0 * s4 + 6.0 * s5;
    let h4 = -4.0 * s3 + 7.0 * s4 - 3.0 * s5;
    let h5 = 0.5 * (s3 - 2.0 * s4 + s5);
    for i in 0..out.len() {
        out[i] = h0 * q0[i]
            + h * h1 * d0[i]
            + h * h * h2 * a0[i]
            + h3 * q1[i]
            + h * h4 * d1[i]
            + h * h * h5 * a1[i];
    }
}

/// Quintic Hermite interpolation of a second-order system `q' = v` over one step, `n`
/// positions and `n` velocities: positions from their values, velocities (their rates)
/// and accelerations at both ends (6th order), velocities as its derivative. `y0`, `f0`
/// at the start, `y1`, `f1` at the end, `h` the step.
#[allow(clippy::too_many_arguments)]
pub fn hermite5(
    theta: f64,
    h: f64,
    n: usize,
    y0: &[f64],
    f0: &[f64],
    y1: &[f64],
    f1: &[f64],
    out: &mut [f64],
) {
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
    // Each half sliced to `n` up front, so that the loop runs without bounds checks.
    let (q0, v0, a0) = (&y0[..n], &y0[n..2 * n], &f0[n..2 * n]);
    let (q1, v1, a1) = (&y1[..n], &y1[n..2 * n], &f1[n..2 * n]);
    let (q, v) = out[..2 * n].split_at_mut(n);
    for i in 0..n {
        let (q0, v0, a0, q1, v1, a1) = (q0[i], v0[i], a0[i], q1[i], v1[i], a1[i]);
        q[i] = h0 * q0 + h * h1 * v0 + h * h * h2 * a0 + h3 * q1 + h * h4 * v1 + h * h * h5 * a1;
        v[i] = (d0 * q0 + d3 * q1) / h + d1 * v0 + h * d2 * a0 + d4 * v1 + h * d5 * a1;
    }
}

/// Cubic Hermite interpolation of every component of `y` over one step from its values
/// and rates at both ends (4th order): the dense output where `q' = G(q) v`. There `q''`
/// is not known (it needs the derivative of `G`), so positions take their values and
/// rates `q' = f[..nq]`, and velocities, to the same order, their values and
/// accelerations. `y0`, `f0` at the start, `y1`, `f1` at the end, `h` the step.
pub fn hermite3(theta: f64, h: f64, y0: &[f64], f0: &[f64], y1: &[f64], f1: &[f64], out: &mut [f64]) {
    let s = theta;
    let (s2, s3) = (s * s, s * s * s);
    let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
    let h10 = s3 - 2.0 * s2 + s;
    let h01 = 3.0 * s2 - 2.0 * s3;
    let h11 = s3 - s2;
    for i in 0..out.len() {
        out[i] = h00 * y0[i] + h * h10 * f0[i] + h01 * y1[i] + h * h11 * f1[i];
    }
}

#[cfg(test)]
mod tests {
    use super::{hermite3, hermite5, positions5};

    /// Exact for quintic positions, from their values, rates and second derivatives.
    #[test]
    fn positions5_reproduces_a_quintic() {
        let q = |t: f64| 2.0 * t.powi(5) - t.powi(4) + 3.0 * t * t - 1.0;
        let d = |t: f64| 10.0 * t.powi(4) - 4.0 * t.powi(3) + 6.0 * t;
        let a = |t: f64| 40.0 * t.powi(3) - 12.0 * t * t + 6.0;
        let (ta, tb) = (0.2, 0.9);
        let mut out = [0.0];
        for k in 0..=10 {
            let th = k as f64 / 10.0;
            let t = ta + th * (tb - ta);
            positions5(th, tb - ta, [&[q(ta)], &[d(ta)], &[a(ta)]], [&[q(tb)], &[d(tb)], &[a(tb)]], &mut out);
            assert!((out[0] - q(t)).abs() < 1e-13, "q at {t}: {} vs {}", out[0], q(t));
        }
    }

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
            hermite5(th, tb - ta, 1, &y0, &f0, &y1, &f1, &mut out);
            assert!((out[0] - q(t)).abs() < 1e-14, "q at {t}");
            assert!((out[1] - v(t)).abs() < 1e-13, "v at {t}");
        }
    }

    /// Exact for cubics in each component, whatever its rate: y = (t^3 - t, 2 t^3 + t^2)
    /// on [0.3, 0.8], with rates (3 t^2 - 1, 6 t^2 + 2 t).
    #[test]
    fn hermite3_reproduces_a_cubic() {
        let y = |t: f64| [t.powi(3) - t, 2.0 * t.powi(3) + t * t];
        let f = |t: f64| [3.0 * t * t - 1.0, 6.0 * t * t + 2.0 * t];
        let (ta, tb) = (0.3, 0.8);
        let mut out = [0.0; 2];
        for k in 0..=10 {
            let th = k as f64 / 10.0;
            let t = ta + th * (tb - ta);
            hermite3(th, tb - ta, &y(ta), &f(ta), &y(tb), &f(tb), &mut out);
            for i in 0..2 {
                assert!((out[i] - y(t)[i]).abs() < 1e-14, "y{i} at {t}");
            }
        }
    }
}
