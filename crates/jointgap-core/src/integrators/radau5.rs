//! Radau IIA of order 5: the 3-stage collocation method at the Radau points, stiffly
//! accurate and L-stable, with an embedded order-3 error estimate (Hairer and Wanner,
//! Solving Ordinary Differential Equations II, 2nd ed., Springer 1996, section IV.8: the
//! method of their code RADAU5).
//!
//! The stage increments `z_i = Y_i - y0` solve `Z = h (A x I) F(Z)`. Simplified Newton
//! iterations on `W = (T^-1 x I) Z`, with `T^-1 A^-1 T = diag(gamma, [alpha -beta; beta
//! alpha])`, decouple into one real and one complex linear system of size n:
//!
//! ```text
//! (gamma/h I - J) dW1 = -gamma/h W1 + G1
//! ((alpha + i beta)/h I - J) (dW2 + i dW3) = -(alpha + i beta)/h (W2 + i W3) + G2 + i G3
//! ```
//!
//! with `G = (T^-1 x I) F((T x I) W)` and `J` a Jacobian at the step's start: the
//! right-hand side's acceleration rows where it has them ([`Rhs::acceleration_jacobian`]:
//! exact, or the stiff part through the applied forces at a fraction of the cost),
//! forward differences of the whole right-hand side after Newton fails with fresh rows
//! of the applied forces alone, until a step is accepted. The iteration starts from the previous step's
//! collocation polynomial; its contraction rate `theta` decides whether `J` and the LU
//! factors are kept for the next step. The error estimate is
//! `(I - h gamma0 J)^-1 (gamma0 h f0 + gamma0 sum dd_i z_i)` (`gamma0 = 1/gamma`),
//! filtered a second time on a first or repeated step. The method picks its next step
//! itself, see [`Stepper::step_factor`]: the error with a safety factor that shrinks
//! with Newton's iteration count, Gustafsson's predictive controller, and `h` kept
//! unchanged when it would change little and Newton converged fast, so that the factors
//! are reused.
//!
//! Departures from RADAU5, chosen by measurement on the founding clearance case
//! (docs/integrators.md): the user's rtol and atol are used as they are (RADAU5 maps
//! them to `0.1 rtol^(2/3)` for its order-3 estimate; the work-precision curve is the
//! same, and without the mapping rtol 1e-9 reaches NRMSE 1e-8); Newton stops at
//! `kappa = 0.03` (RADAU5: `min(0.03, rtol'^(1/2))`); `J` is kept for
//! `theta <= 0.1` (RADAU5: 0.001, which it recommends raising when Jacobians are costly;
//! with the force Jacobian 0.01 and 0.001 were not faster at equal accuracy) and also
//! after an error rejection when Newton converged that fast. Retrying a Newton failure
//! at the same step with a renewed force Jacobian, before halving it, was measured and
//! dropped: the failures come from the contact's nonlinearity, not from a stale `J`.

use nalgebra::{Complex, DMatrix, DVector, Dyn, LU};

use super::jacobian;
use super::ode::{JacobianKind, PositionRate, Rhs, Singular, Tolerances};
use super::stepper::{Attempt, StepFailure, Stepper};
use crate::profile;

/// Nodes: `c1 = (4 - sqrt 6)/10`, `c2 = (4 + sqrt 6)/10`, `c3 = 1`.
const C: [f64; 3] = [0.1550510257216822, 0.6449489742783178, 1.0];
/// The real eigenvalue of `A^-1`: `1 / gamma = (6 + 81^(1/3) - 9^(1/3)) / 30`.
const GAMMA: f64 = 3.637834252744496;
/// The complex pair `alpha +- i beta` of `A^-1`, the inverses of `A`'s eigenvalues
/// `((12 - 81^(1/3) + 9^(1/3)) +- i sqrt 3 (81^(1/3) + 9^(1/3))) / 60`.
const ALPHA: f64 = 2.681082873627752;
const BETA: f64 = 3.0504301992474105;
/// Columns: the eigenvector of `A^-1` for `gamma`, the real part and minus the imaginary
/// part of that for `alpha + i beta`; scaled as in RADAU5 (last row `(T31, 1, 0)`).
const T: [[f64; 3]; 3] = [
    [0.09123239487089295, -0.1412552950209542, -0.030029194105147424],
    [0.241717932707107, 0.20412935229379994, 0.3829421127572619],
    [0.966048182615093, 1.0, 0.0],
];
/// `T^-1`.
const TI: [[f64; 3]; 3] = [
    [4.325579890063155, 0.33919925181580984, 0.5417705399358749],
    [-4.178718591551904, -0.32768282076106237, 0.47662355450055044],
    [-0.5028726349457869, 2.571926949855605, -0.5960392048282249],
];
/// Error weights over `gamma0`: `-(13 + 7 sqrt 6)/3`, `(-13 + 7 sqrt 6)/3`, `-1/3`.
const DD: [f64; 3] = [-10.048809399827414, 1.382142733160749, -1.0 / 3.0];

/// Newton stops when `theta / (1 - theta) ||dW|| <= NEWTON_TOL` in the error norm
/// (`kappa` of HW II, IV.8).
const NEWTON_TOL: f64 = 0.03;
/// Most simplified-Newton iterations per step (RADAU5's NIT).
const MAX_NEWTON: usize = 7;
/// Newton contraction rate at or below which `J` is kept for the next step (THET).
const KEEP_JACOBIAN: f64 = 0.1;
/// A proposed `h_new / h` in this band keeps `h`, and with it the LU factors, when
/// Newton converged fast (RADAU5's QUOT1, QUOT2).
const KEEP_STEP: (f64, f64) = (1.0, 1.2);
/// Safety factor of the step-size rule.
const SAFE: f64 = 0.9;
/// Bounds of `h_new / h` (RADAU5's 1/FACL, 1/FACR).
const RATIO: (f64, f64) = (0.2, 8.0);

/// LU factors of the iteration matrices `s I - J` for one step size, `s = gamma/h` and
/// `s = (alpha + i beta)/h`. With `J = [0 G; Jq Jv]` (the state is `(q, v)`,
/// `q' = G(q) v`, `G = I` for `q' = v`) the system `(s I - J) x = b` reduces to its
/// lower half, `(s I - Jv - Jq G / s) x2 = b2 + Jq b1 / s` and `x1 = (b1 + G x2) / s`
/// (the structure RADAU5 exploits for second-order systems, its option M1), so only
/// `nv x nv` matrices are factored. The block `d(q')/d(q) = d(G(q) v)/d(q)` is taken as
/// zero: it is zero for `q' = v`, and where `G` varies it is of the order of the speeds,
/// small against `s` at the steps of an accurate run; keeping it would cost a factor of
/// `s I - d(q')/d(q)` besides, and the iteration matrix steers Newton's iterations only,
/// not the stages they converge to.
struct Factors {
    real: LU<f64, Dyn, Dyn>,
    complex: LU<Complex<f64>, Dyn, Dyn>,
    s: f64,
    sigma: Complex<f64>,
    h: f64,
}

impl Factors {
    /// Factors both matrices for step `h`; `jac` is `[Jq Jv]` (nv x (nq + nv)), `g` is `G`
    /// (nq x nv; `None`: the identity). `None` when singular.
    fn new(jac: &DMatrix<f64>, g: Option<&DMatrix<f64>>, h: f64) -> Option<Self> {
        let (m, nq) = (jac.nrows(), jac.ncols() - jac.nrows());
        // `Jq G`: `Jq` itself for `G = I`.
        let product: DMatrix<f64>;
        let coupling = match g {
            Some(g) => {
                product = jac.columns(0, nq) * g;
                product.columns(0, m)
            }
            None => jac.columns(0, m),
        };
        let s = GAMMA / h;
        let real = DMatrix::from_fn(m, m, |i, j| {
            let d = if i == j { s } else { 0.0 };
            d - jac[(i, nq + j)] - coupling[(i, j)] / s
        });
        let sigma = Complex::new(ALPHA / h, BETA / h);
        let inv = sigma.inv();
        let complex = DMatrix::from_fn(m, m, |i, j| {
            let d = if i == j { sigma } else { Complex::new(0.0, 0.0) };
            d - inv * coupling[(i, j)] - jac[(i, nq + j)]
        });
        let (real, complex) = (real.lu(), complex.lu());
        (real.is_invertible() && complex.is_invertible()).then_some(Factors { real, complex, s, sigma, h })
    }

    /// Solves `(s I - J) x = b` in place for the real shift; `g` as in [`Factors::new`],
    /// `tmp` is scratch of nv.
    fn solve_real(
        &self,
        jac: &DMatrix<f64>,
        g: Option<&DMatrix<f64>>,
        b: &mut [f64],
        tmp: &mut DVector<f64>,
    ) {
        let (m, nq) = (tmp.len(), jac.ncols() - tmp.len());
        for i in 0..m {
            let mut acc = 0.0;
            for j in 0..nq {
                acc += jac[(i, j)] * b[j];
            }
            tmp[i] = b[nq + i] + acc / self.s;
        }
        self.real.solve_mut(tmp);
        match g {
            None => {
                for j in 0..nq {
                    b[j] = (b[j] + tmp[j]) / self.s;
                }
            }
            Some(g) => {
                for j in 0..nq {
                    let gx: f64 = (0..m).map(|k| g[(j, k)] * tmp[k]).sum();
                    b[j] = (b[j] + gx) / self.s;
                }
            }
        }
        b[nq..].copy_from_slice(tmp.as_slice());
    }

    /// As [`Factors::solve_real`] for the complex shift.
    fn solve_complex(
        &self,
        jac: &DMatrix<f64>,
        g: Option<&DMatrix<f64>>,
        b: &mut [Complex<f64>],
        tmp: &mut DVector<Complex<f64>>,
    ) {
        let (m, nq) = (tmp.len(), jac.ncols() - tmp.len());
        for i in 0..m {
            let mut acc = Complex::new(0.0, 0.0);
            for j in 0..nq {
                acc += b[j] * jac[(i, j)];
            }
            tmp[i] = b[nq + i] + acc / self.sigma;
        }
        self.complex.solve_mut(tmp);
        match g {
            None => {
                for j in 0..nq {
                    b[j] = (b[j] + tmp[j]) / self.sigma;
                }
            }
            Some(g) => {
                for j in 0..nq {
                    let gx: Complex<f64> = (0..m).map(|k| tmp[k] * g[(j, k)]).sum();
                    b[j] = (b[j] + gx) / self.sigma;
                }
            }
        }
        b[nq..].copy_from_slice(tmp.as_slice());
    }
}

/// The last accepted step's collocation polynomial `u`, as `u(s) - y1` with
/// `s = (t - t1) / h` in Newton form on the nodes `0, c2 - 1, c1 - 1, -1`.
struct Polynomial {
    d: [Vec<f64>; 3],
    t1: f64,
    h: f64,
}

impl Polynomial {
    /// `u(s) - y1`, component `i`.
    fn at(&self, i: usize, s: f64) -> f64 {
        let d = &self.d;
        s * (d[0][i] + (s - C[1] + 1.0) * (d[1][i] + (s - C[0] + 1.0) * d[2][i]))
    }
}

/// Newton state, Jacobian and step history of the Radau IIA method.
pub struct Radau5 {
    /// Position coordinates of the state.
    nq: usize,
    /// Rows `nq..n` of the Jacobian, `[Jq Jv]`; (nv x n).
    jac: DMatrix<f64>,
    /// `G = d(q')/d(v)` (nq x nv) with `J`, where `q' = G(q) v`; `None` for `q' = v`.
    rate: Option<DMatrix<f64>>,
    jac_evals: usize,
    newton_iterations: usize,
    /// `J` was evaluated at the start of the step being attempted (RADAU5's CALJAC).
    jac_current: bool,
    /// Evaluate `J` afresh at the start of the next attempt.
    need_jac: bool,
    /// `J`'s acceleration rows are the applied forces' part alone
    /// ([`Rhs::acceleration_jacobian`]).
    jac_from_forces: bool,
    /// Newton failed with fresh rows of the applied forces: forward differences until a
    /// step is accepted.
    full_jacobian: bool,
    factors: Option<Factors>,
    /// Newton's `theta / (1 - theta)` of the last attempt, for the first iteration's test.
    faccon: f64,
    /// Newton contraction rate of the last attempt.
    theta: f64,
    /// No step accepted yet.
    first: bool,
    last_rejected: bool,
    poly: Option<Polynomial>,
    /// Gustafsson's controller: accepted steps, and the last one's size and error.
    accepted: usize,
    h_acc: f64,
    err_acc: f64,
    factor: Option<f64>,
    /// Most Newton iterations: MAX_NEWTON (tests at a fixed step allow more).
    max_newton: usize,
    z: [Vec<f64>; 3],
    w: [Vec<f64>; 3],
    fz: [Vec<f64>; 3],
    stage: Vec<f64>,
    scal: Vec<f64>,
    work: Vec<f64>,
    rr: Vec<f64>,
    rc: Vec<Complex<f64>>,
    tmp_r: DVector<f64>,
    tmp_c: DVector<Complex<f64>>,
    /// Tests: accept every step whatever its error, and iterate Newton to convergence,
    /// for runs at a fixed step.
    #[cfg(test)]
    fixed: bool,
}

/// The estimate as the loop reads it: at least 1e-10, infinite when not a number.
fn error_of(e: f64) -> f64 {
    if e.is_nan() {
        f64::INFINITY
    } else {
        e.max(1e-10)
    }
}

/// RMS of `x_i / scal_i`.
fn wrms(x: &[f64], scal: &[f64]) -> f64 {
    let sum: f64 = x.iter().zip(scal).map(|(x, s)| (x / s).powi(2)).sum();
    (sum / scal.len().max(1) as f64).sqrt()
}

impl Radau5 {
    /// Allocates for a state `(q, v)` of `nq` positions and `nv` velocities.
    pub fn new(nq: usize, nv: usize) -> Self {
        let n = nq + nv;
        let v = || vec![0.0; n];
        Radau5 {
            nq,
            jac: DMatrix::zeros(nv, n),
            rate: None,
            jac_evals: 0,
            newton_iterations: 0,
            jac_current: false,
            need_jac: true,
            jac_from_forces: false,
            full_jacobian: false,
            factors: None,
            faccon: 1.0,
            theta: KEEP_JACOBIAN,
            first: true,
            last_rejected: false,
            poly: None,
            accepted: 0,
            h_acc: 0.0,
            err_acc: 1e-2,
            factor: None,
            max_newton: MAX_NEWTON,
            z: [v(), v(), v()],
            w: [v(), v(), v()],
            fz: [v(), v(), v()],
            stage: v(),
            scal: v(),
            work: v(),
            rr: v(),
            rc: vec![Complex::new(0.0, 0.0); n],
            tmp_r: DVector::zeros(nv),
            tmp_c: DVector::zeros(nv),
            #[cfg(test)]
            fixed: false,
        }
    }

    /// Newton's starting point: the last step's collocation polynomial extrapolated to
    /// this step's nodes (from `t`, at the end of that step or inside it when an event
    /// cut it short), else zero.
    fn start(&mut self, t: f64, h: f64) {
        let Some(p) = self.poly.as_ref() else {
            for k in 0..3 {
                self.z[k].fill(0.0);
                self.w[k].fill(0.0);
            }
            return;
        };
        let (r, s0) = (h / p.h, (t - p.t1) / p.h);
        for i in 0..self.stage.len() {
            let base = p.at(i, s0);
            let z = [p.at(i, s0 + C[0] * r) - base, p.at(i, s0 + C[1] * r) - base, p.at(i, s0 + r) - base];
            for k in 0..3 {
                self.z[k][i] = z[k];
                self.w[k][i] = TI[k][0] * z[0] + TI[k][1] * z[1] + TI[k][2] * z[2];
            }
        }
    }

    /// Keeps the accepted step's collocation polynomial through `y0` (`s = -1`) and the
    /// stages, as divided differences.
    fn keep_polynomial(&mut self, t1: f64, h: f64) {
        let n = self.stage.len();
        let mut d = self.poly.take().map_or_else(|| [vec![0.0; n], vec![0.0; n], vec![0.0; n]], |p| p.d);
        let (c1m1, c2m1) = (C[0] - 1.0, C[1] - 1.0);
        for i in 0..n {
            let (z1, z2, z3) = (self.z[0][i], self.z[1][i], self.z[2][i]);
            let d01 = (z2 - z3) / c2m1; // [0, c2-1]
            let d12 = (z1 - z2) / (C[0] - C[1]); // [c2-1, c1-1]
            let d012 = (d12 - d01) / c1m1; // [0, c2-1, c1-1]
            let d123 = (d12 - z1 / C[0]) / C[1]; // [c2-1, c1-1, -1]
            d[0][i] = d01;
            d[1][i] = d012;
            d[2][i] = d012 - d123; // [0, c2-1, c1-1, -1]
        }
        self.poly = Some(Polynomial { d, t1, h });
    }

    /// A failed attempt: retry with `h factor`, with a new Jacobian unless this one is
    /// current and complete (a current force Jacobian gives way to forward differences).
    fn fail(&mut self, factor: f64) -> StepFailure {
        self.factor = Some(factor);
        self.full_jacobian |= self.jac_current && self.jac_from_forces;
        self.need_jac = !self.jac_current || self.jac_from_forces;
        self.last_rejected = true;
        StepFailure::Convergence
    }

    /// The Jacobian when due, and the factors for `h`.
    fn prepare<R: Rhs + ?Sized>(
        &mut self,
        rhs: &mut R,
        t: f64,
        y: &[f64],
        f0: &[f64],
        h: f64,
    ) -> Result<(), StepFailure> {
        let lap = profile::start(rhs.profile());
        let mut result = Ok(());
        if self.need_jac {
            let nq = self.nq;
            let cheap =
                if self.full_jacobian { None } else { rhs.acceleration_jacobian(t, y, &mut self.jac) };
            self.jac_from_forces = matches!(cheap, Some(Ok(JacobianKind::Forces)));
            let done = cheap.map(|done| done.map(drop)).unwrap_or_else(|| {
                jacobian::forward_difference(rhs, t, y, f0, nq, &mut self.jac, &mut self.work)
            });
            self.rate = match rhs.shape().rate {
                PositionRate::Identity => None,
                PositionRate::Mapped => {
                    let nv = self.jac.nrows();
                    let mut g = self.rate.take().unwrap_or_else(|| DMatrix::zeros(nq, nv));
                    rhs.rate_jacobian(&y[..nq], g.view_mut((0, 0), (nq, nv)));
                    Some(g)
                }
            };
            if done.is_err() {
                result = Err(StepFailure::Singular);
            } else {
                self.jac_evals += 1;
                self.jac_current = true;
                self.need_jac = false;
                self.factors = None;
            }
        }
        if result.is_ok() && self.factors.as_ref().is_none_or(|f| f.h != h) {
            self.factors = Factors::new(&self.jac, self.rate.as_ref(), h);
            if self.factors.is_none() {
                result = Err(self.fail(0.5));
            }
        }
        profile::stop(rhs.profile(), lap, |p| &mut p.jacobians);
        result
    }

    /// Simplified Newton iterations on the stages; returns their number.
    fn newton<R: Rhs + ?Sized>(
        &mut self,
        rhs: &mut R,
        t: f64,
        y: &[f64],
        h: f64,
    ) -> Result<usize, StepFailure> {
        let n = y.len();
        self.faccon = self.faccon.max(f64::EPSILON).powf(0.8);
        self.theta = KEEP_JACOBIAN;
        let (mut dyno_old, mut thq_old) = (1.0, 1.0);
        let (g, a, b) = (GAMMA / h, ALPHA / h, BETA / h);
        for newt in 1..=self.max_newton {
            self.newton_iterations += 1;
            for k in 0..3 {
                for i in 0..n {
                    self.stage[i] = y[i] + self.z[k][i];
                }
                rhs.eval(t + C[k] * h, &self.stage, &mut self.fz[k])
                    .map_err(|Singular| StepFailure::Singular)?;
            }
            for i in 0..n {
                let f = [self.fz[0][i], self.fz[1][i], self.fz[2][i]];
                let tf = |k: usize| TI[k][0] * f[0] + TI[k][1] * f[1] + TI[k][2] * f[2];
                let (w1, w2, w3) = (self.w[0][i], self.w[1][i], self.w[2][i]);
                self.rr[i] = tf(0) - g * w1;
                self.rc[i] = Complex::new(tf(1) - a * w2 + b * w3, tf(2) - a * w3 - b * w2);
            }
            let factors = self.factors.as_ref().expect("factored before Newton");
            factors.solve_real(&self.jac, self.rate.as_ref(), &mut self.rr, &mut self.tmp_r);
            factors.solve_complex(&self.jac, self.rate.as_ref(), &mut self.rc, &mut self.tmp_c);
            let mut sum = 0.0;
            for i in 0..n {
                let s = self.scal[i];
                sum += (self.rr[i] / s).powi(2) + (self.rc[i].re / s).powi(2) + (self.rc[i].im / s).powi(2);
            }
            let dyno = (sum / (3 * n).max(1) as f64).sqrt();
            if !dyno.is_finite() {
                return Err(self.fail(0.5));
            }
            if newt > 1 && newt < self.max_newton {
                let thq = dyno / dyno_old;
                self.theta = if newt == 2 { thq } else { (thq * thq_old).sqrt() };
                thq_old = thq;
                if self.theta >= 0.99 {
                    return Err(self.fail(0.5));
                }
                self.faccon = self.theta / (1.0 - self.theta);
                // The error predicted after the iterations left: too large, retry smaller.
                let left = self.max_newton - 1 - newt;
                let dyth = self.faccon * dyno * self.theta.powi(left as i32) / NEWTON_TOL;
                #[cfg(test)]
                let dyth = if self.fixed { 0.0 } else { dyth };
                if dyth >= 1.0 {
                    let qnewt = dyth.clamp(1e-4, 20.0);
                    return Err(self.fail(0.8 * qnewt.powf(-1.0 / (4.0 + left as f64))));
                }
            }
            dyno_old = dyno.max(f64::EPSILON);
            for i in 0..n {
                let w =
                    [self.w[0][i] + self.rr[i], self.w[1][i] + self.rc[i].re, self.w[2][i] + self.rc[i].im];
                for k in 0..3 {
                    self.w[k][i] = w[k];
                    self.z[k][i] = T[k][0] * w[0] + T[k][1] * w[1] + T[k][2] * w[2];
                }
            }
            if self.faccon * dyno <= NEWTON_TOL {
                return Ok(newt);
            }
        }
        Err(self.fail(0.5))
    }

    /// The error estimate filtered through `(gamma/h I - J)^-1`, and a second time at
    /// `y0 + err` on a first or repeated step that fails the test (RADAU5's ESTRAD).
    fn estimate<R: Rhs + ?Sized>(
        &mut self,
        rhs: &mut R,
        t: f64,
        y: &[f64],
        f0: &[f64],
        h: f64,
    ) -> Result<f64, StepFailure> {
        let n = y.len();
        for i in 0..n {
            self.work[i] = (DD[0] * self.z[0][i] + DD[1] * self.z[1][i] + DD[2] * self.z[2][i]) / h;
            self.rr[i] = f0[i] + self.work[i];
        }
        let factors = self.factors.as_ref().expect("factored before the estimate");
        factors.solve_real(&self.jac, self.rate.as_ref(), &mut self.rr, &mut self.tmp_r);
        let err = error_of(wrms(&self.rr, &self.scal));
        if err < 1.0 || !(self.first || self.last_rejected) {
            return Ok(err);
        }
        for i in 0..n {
            self.stage[i] = y[i] + self.rr[i];
        }
        rhs.eval(t, &self.stage, &mut self.fz[0]).map_err(|Singular| StepFailure::Singular)?;
        for i in 0..n {
            self.rr[i] = self.fz[0][i] + self.work[i];
        }
        factors.solve_real(&self.jac, self.rate.as_ref(), &mut self.rr, &mut self.tmp_r);
        Ok(error_of(wrms(&self.rr, &self.scal)))
    }

    /// One step of size `h` from `(t, y)` of `rhs` (`f0 = f(t, y)`, tolerances `tol`):
    /// [`Stepper::attempt`] for any right-hand side of the form `y = (q, v)`,
    /// `f = (G(q) v, a(t, q, v))`.
    #[allow(clippy::too_many_arguments)]
    pub fn step<R: Rhs + ?Sized>(
        &mut self,
        rhs: &mut R,
        Tolerances { rtol, atol }: Tolerances,
        t: f64,
        y: &[f64],
        f0: &[f64],
        h: f64,
        y_new: &mut [f64],
        f_new: &mut [f64],
    ) -> Result<Attempt, StepFailure> {
        self.factor = None;
        for (s, yi) in self.scal.iter_mut().zip(y) {
            *s = atol + rtol * yi.abs();
        }
        self.prepare(rhs, t, y, f0, h)?;
        self.start(t, h);
        let newt = self.newton(rhs, t, y, h)?;
        let err = self.estimate(rhs, t, y, f0, h)?;
        #[cfg(test)]
        let err = if self.fixed { err.min(1.0) } else { err };

        // Next step: from the error, with less safety the more Newton iterations.
        let fac = SAFE.min(SAFE * (1 + 2 * MAX_NEWTON) as f64 / (newt + 2 * MAX_NEWTON) as f64);
        let bounds = (1.0 / RATIO.1, 1.0 / RATIO.0);
        let mut quot = (err.powf(0.25) / fac).clamp(bounds.0, bounds.1);
        if err > 1.0 {
            self.factor = Some(if self.first || err.is_infinite() { 0.1 } else { 1.0 / quot });
            // An error rejection after fast convergence keeps J (RADAU5 renews it).
            self.need_jac = !self.jac_current && self.theta > KEEP_JACOBIAN;
            self.last_rejected = true;
            return Ok(Attempt { error: err, stiffness: None });
        }
        for i in 0..y.len() {
            y_new[i] = y[i] + self.z[2][i];
        }
        rhs.update_positions(&mut y_new[..self.nq]);
        rhs.eval(t + h, y_new, f_new).map_err(|Singular| StepFailure::Singular)?;
        self.accepted += 1;
        if self.accepted > 1 {
            // Gustafsson's predictive controller (HW II, IV.8, (8.21)).
            let gus = (self.h_acc / h) * (err * err / self.err_acc).powf(0.25) / SAFE;
            quot = quot.max(gus.clamp(bounds.0, bounds.1));
        }
        self.h_acc = h;
        self.err_acc = err.max(1e-2);
        let mut ratio = 1.0 / quot;
        if self.last_rejected {
            ratio = ratio.min(1.0);
        }
        if self.theta <= KEEP_JACOBIAN && (KEEP_STEP.0..=KEEP_STEP.1).contains(&ratio) {
            ratio = 1.0;
        }
        self.factor = Some(ratio);
        self.need_jac = self.theta > KEEP_JACOBIAN;
        self.jac_current = false;
        self.full_jacobian = false;
        self.first = false;
        self.last_rejected = false;
        self.keep_polynomial(t + h, h);
        Ok(Attempt { error: err, stiffness: None })
    }
}

impl<R: Rhs + ?Sized> Stepper<R> for Radau5 {
    fn name(&self) -> &'static str {
        "radau5"
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

    fn step_factor(&self) -> Option<f64> {
        self.factor
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
        self.step(ode, tol, t, y, f0, h, y_new, f_new)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::ode::StateShape;
    use crate::profile::Profile;

    /// A model problem `y = (q, v)`, `y' = (v, a(t, q, v))`, `n` positions.
    struct Problem<F: FnMut(f64, &[f64], &[f64], &mut [f64])> {
        n: usize,
        accel: F,
        evaluations: usize,
        profile: Option<Profile>,
    }

    impl<F: FnMut(f64, &[f64], &[f64], &mut [f64])> Rhs for Problem<F> {
        fn shape(&self) -> StateShape {
            StateShape { nq: self.n, nv: self.n, rate: PositionRate::Identity }
        }

        fn eval(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Singular> {
            self.evaluations += 1;
            let (q, v) = y.split_at(self.n);
            self.position_rate(q, v, &mut dy[..self.n]);
            (self.accel)(t, q, v, &mut dy[self.n..]);
            Ok(())
        }

        fn profile(&mut self) -> &mut Option<Profile> {
            &mut self.profile
        }
    }

    fn problem<F: FnMut(f64, &[f64], &[f64], &mut [f64])>(n: usize, accel: F) -> Problem<F> {
        Problem { n, accel, evaluations: 0, profile: None }
    }

    /// `steps` steps of size `t_end / steps` from `y0` at t = 0; Newton to `tol`.
    fn fixed_steps<R: Rhs>(rhs: &mut R, y0: &[f64], t_end: f64, steps: usize, tol: f64) -> Vec<f64> {
        let StateShape { nq, nv, .. } = rhs.shape();
        let n = nq + nv;
        let mut radau = Radau5::new(nq, nv);
        radau.fixed = true;
        radau.max_newton = 40;
        let (mut y, mut f) = (y0.to_vec(), vec![0.0; n]);
        let (mut y1, mut f1) = (vec![0.0; n], vec![0.0; n]);
        rhs.eval(0.0, &y, &mut f).unwrap();
        let h = t_end / steps as f64;
        for k in 0..steps {
            let t = k as f64 * h;
            radau
                .step(rhs, Tolerances { rtol: tol, atol: tol }, t, &y, &f, h, &mut y1, &mut f1)
                .expect("Newton converges");
            std::mem::swap(&mut y, &mut y1);
            std::mem::swap(&mut f, &mut f1);
        }
        y
    }

    /// The tableau from its closed form: nodes, collocation conditions C(3) and order 5,
    /// the eigen-decomposition `T^-1 A^-1 T`, and the embedded order-3 weights behind DD.
    #[test]
    fn tableau_matches_the_closed_form() {
        let s6 = 6f64.sqrt();
        let a = [
            [(88.0 - 7.0 * s6) / 360.0, (296.0 - 169.0 * s6) / 1800.0, (-2.0 + 3.0 * s6) / 225.0],
            [(296.0 + 169.0 * s6) / 1800.0, (88.0 + 7.0 * s6) / 360.0, (-2.0 - 3.0 * s6) / 225.0],
            [(16.0 - s6) / 36.0, (16.0 + s6) / 36.0, 1.0 / 9.0],
        ];
        let c = [(4.0 - s6) / 10.0, (4.0 + s6) / 10.0, 1.0];
        for i in 0..3 {
            assert!((C[i] - c[i]).abs() < 1e-16, "c{i}");
            // Collocation: sum_j a_ij c_j^(k-1) = c_i^k / k, k = 1, 2, 3.
            for k in 1..=3 {
                let lhs: f64 = (0..3).map(|j| a[i][j] * c[j].powi(k - 1)).sum();
                assert!((lhs - c[i].powi(k) / k as f64).abs() < 1e-15, "C({k}) row {i}");
            }
        }
        // Weights b = last row: quadrature of order 5 (sum b_j c_j^(k-1) = 1/k, k <= 5).
        for k in 1..=5 {
            let lhs: f64 = (0..3).map(|j| a[2][j] * c[j].powi(k - 1)).sum();
            assert!((lhs - 1.0 / k as f64).abs() < 1e-15, "B({k})");
        }
        let k6: f64 = (0..3).map(|j| a[2][j] * c[j].powi(5)).sum();
        assert!((k6 - 1.0 / 6.0).abs() > 1e-4, "order exactly 5");
        let am = DMatrix::from_fn(3, 3, |i, j| a[i][j]);
        let ai = am.clone().try_inverse().unwrap();
        let t = DMatrix::from_fn(3, 3, |i, j| T[i][j]);
        let ti = DMatrix::from_fn(3, 3, |i, j| TI[i][j]);
        assert!((&t * &ti - DMatrix::identity(3, 3)).amax() < 1e-15);
        let lambda = DMatrix::from_row_slice(3, 3, &[GAMMA, 0.0, 0.0, 0.0, ALPHA, -BETA, 0.0, BETA, ALPHA]);
        assert!((&ti * &ai * &t - lambda).amax() < 1e-13);
        // Eigenvalues from the cube roots.
        let (r81, r9) = (81f64.cbrt(), 9f64.cbrt());
        assert!((GAMMA - 30.0 / (6.0 + r81 - r9)).abs() < 1e-14);
        let (re, im) = ((12.0 - r81 + r9) / 60.0, (r81 + r9) * 3f64.sqrt() / 60.0);
        let norm = re * re + im * im;
        assert!((ALPHA - re / norm).abs() < 1e-14 && (BETA - im / norm).abs() < 1e-14);
        // Embedded order 3 with b0 = gamma0 at c0 = 0: sum bh_j c_j^(k-1) = 1/k - gamma0 [k = 1];
        // the estimate gamma0 h f0 + sum e_j z_j with e = (bh - b) A^-1 is gamma0 (h f0 + DD.z).
        let g0 = 1.0 / GAMMA;
        let v = DMatrix::from_fn(3, 3, |k, j| c[j].powi(k as i32));
        let bh = v.lu().solve(&DVector::from_row_slice(&[1.0 - g0, 0.5, 1.0 / 3.0])).unwrap();
        for j in 0..3 {
            let e: f64 = (0..3).map(|i| (bh[i] - a[2][i]) * ai[(i, j)]).sum();
            assert!((e / g0 - DD[j]).abs() < 1e-12, "dd{j}: {} against {}", e / g0, DD[j]);
        }
        assert!(
            (DD[0] + (13.0 + 7.0 * s6) / 3.0).abs() < 1e-14
                && (DD[1] - (-13.0 + 7.0 * s6) / 3.0).abs() < 1e-14
        );
    }

    /// Global error of order 5 at a fixed step on a nonlinear problem with a known
    /// solution: the Kepler orbit of eccentricity 0.6, `q'' = -q / |q|^3`, over one
    /// period 2 pi, against `q = (cos E - e, sqrt(1 - e^2) sin E)`, `E - e sin E = t`.
    /// Halving h divides the error by about 2^5 = 32 (order 4: 16, order 6: 64).
    #[test]
    fn converges_with_order_five() {
        let e: f64 = 0.6;
        let kepler = |_t: f64, q: &[f64], _v: &[f64], a: &mut [f64]| {
            let r3 = (q[0] * q[0] + q[1] * q[1]).powf(1.5);
            a[0] = -q[0] / r3;
            a[1] = -q[1] / r3;
        };
        let orbit = |t: f64| {
            let mut ea = t;
            for _ in 0..50 {
                ea -= (ea - e * ea.sin() - t) / (1.0 - e * ea.cos());
            }
            let (s, c, b) = (ea.sin(), ea.cos(), (1.0 - e * e).sqrt());
            let d = 1.0 - e * c;
            [c - e, b * s, -s / d, b * c / d]
        };
        let t_end = 2.0 * std::f64::consts::PI;
        let exact = orbit(t_end);
        let errors: Vec<f64> = [80, 160, 320, 640]
            .iter()
            .map(|&steps| {
                let y = fixed_steps(&mut problem(2, kepler), &orbit(0.0), t_end, steps, 1e-13);
                y.iter().zip(&exact).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max)
            })
            .collect();
        for w in errors.windows(2) {
            let order = (w[0] / w[1]).log2();
            assert!((4.85..5.15).contains(&order), "observed order {order:.3}, errors {errors:?}");
        }
    }

    /// L-stable on a stiff linear problem far beyond any explicit method's step: the
    /// overdamped `u'' + (1e6 + 1) u' + 1e6 u = 0` (eigenvalues -1 and -1e6), u(0) = 1,
    /// at h = 0.05 and 0.025 (h lambda = -5e4), against
    /// `u = (1e6 e^-t - e^-1e6t) / (1e6 - 1)`: the fast mode is damped out in the first
    /// step and the slow one keeps order 5 (measured errors 1.6e-11 and 5.0e-13 at t = 1).
    #[test]
    fn stiff_decay_is_stable_at_large_steps() {
        let (k, c) = (1e6, 1e6 + 1.0);
        let mut p = problem(1, |_t: f64, q: &[f64], v: &[f64], a: &mut [f64]| a[0] = -k * q[0] - c * v[0]);
        for (steps, bound) in [(20, 1e-10), (40, 5e-12)] {
            let y = fixed_steps(&mut p, &[1.0, 0.0], 1.0, steps, 1e-12);
            let u = (1e6 * (-1f64).exp()) / (1e6 - 1.0);
            let du = -u;
            assert!(
                (y[0] - u).abs() < bound && (y[1] - du).abs() < bound,
                "{steps} steps: {y:?} against {u}, {du}"
            );
        }
    }

    /// The reduced solve of the second-order structure equals a dense solve of
    /// `(s I - J) x = b` with the full Jacobian `[0 G; Jq Jv]`, for both shifts: with
    /// `G = I` (nq = nv = 3) and with a `G` of 4 positions and 3 velocities.
    #[test]
    fn reduced_solve_matches_the_full_system() {
        let mapped = DMatrix::from_fn(4, 3, |i, j| ((2 * i + 3 * j) % 5) as f64 * 0.4 - 0.6);
        for (nq, g) in [(3, None), (4, Some(&mapped))] {
            let (m, n) = (3, nq + 3);
            let jac = DMatrix::from_fn(m, n, |i, j| {
                ((3 * i + 5 * j) % 7) as f64 - 3.0 + if j == nq + i { -40.0 } else { 0.0 }
            });
            let upper = g.cloned().unwrap_or_else(|| DMatrix::identity(m, m));
            let full = DMatrix::from_fn(n, n, |i, j| match (i < nq, j < nq) {
                (true, true) => 0.0,
                (true, false) => upper[(i, j - nq)],
                (false, _) => jac[(i - nq, j)],
            });
            let h = 0.01;
            let f = Factors::new(&jac, g, h).unwrap();
            let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
            let mut x = b.clone();
            f.solve_real(&jac, g, &mut x, &mut DVector::zeros(m));
            let dense = (DMatrix::identity(n, n) * (GAMMA / h) - &full)
                .lu()
                .solve(&DVector::from_row_slice(&b))
                .unwrap();
            assert!((DVector::from_row_slice(&x) - dense).amax() < 1e-12, "nq = {nq}");
            let bc: Vec<Complex<f64>> =
                b.iter().enumerate().map(|(i, &r)| Complex::new(r, 0.3 * i as f64)).collect();
            let mut xc = bc.clone();
            f.solve_complex(&jac, g, &mut xc, &mut DVector::zeros(m));
            let shift = Complex::new(ALPHA / h, BETA / h);
            let fullc = DMatrix::from_fn(n, n, |i, j| {
                let d = if i == j { shift } else { Complex::new(0.0, 0.0) };
                d - Complex::new(full[(i, j)], 0.0)
            });
            let densec = fullc.lu().solve(&DVector::from_row_slice(&bc)).unwrap();
            assert!((DVector::from_row_slice(&xc) - densec).camax() < 1e-12, "nq = {nq}");
        }
    }
}
