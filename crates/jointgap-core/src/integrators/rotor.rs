//! Every method on a model problem whose positions and velocities differ in size and
//! whose positions move as `q' = G(q) v`: a rotor whose orientation is the unit complex
//! number `q = (cos th, sin th)` (nq = 2) and whose velocity is its angular velocity
//! `v = omega` (nv = 1), so `q' = perp(q) omega`. A torque `C (OMEGA - omega) + A cos(W t)`
//! (a damper towards a steady speed and a harmonic excitation) gives the closed form
//!
//! ```text
//! omega = OMEGA + (omega0 - OMEGA) e + K (C cos Wt + W sin Wt - C e)
//! th    = th0 + OMEGA t + (omega0 - OMEGA) (1 - e) / C + K (C sin(Wt) / W + 1 - cos Wt - (1 - e))
//! ```
//!
//! with `e = exp(-C t)`, `K = A / (C^2 + W^2)`. The update hook renormalises `q`.

use nalgebra::{DMatrix, DMatrixViewMut};

use super::dopri5::Dopri5;
use super::ode::{DenseStep, JacobianKind, PositionRate, Rhs, Singular, StateShape, Tolerances};
use super::radau5::Radau5;
use super::sdirk4::Sdirk4;
use super::stepper::{StepFailure, Stepper};
use crate::profile::Profile;

/// Damping rate [1/s], steady speed [rad/s], excitation [rad/s^2] and its frequency
/// [rad/s], initial angle [rad] and speed [rad/s].
const C: f64 = 20.0;
const OMEGA: f64 = 5.0;
const A: f64 = 40.0;
const W: f64 = 7.0;
const TH0: f64 = 0.3;
const OMEGA0: f64 = -2.0;

/// `(th, omega)` at `t`.
fn exact(t: f64) -> (f64, f64) {
    let (e, k) = ((-C * t).exp(), A / (C * C + W * W));
    let (s, c) = (W * t).sin_cos();
    let omega = OMEGA + (OMEGA0 - OMEGA) * e + k * (C * c + W * s - C * e);
    let th = TH0 + OMEGA * t + (OMEGA0 - OMEGA) * (1.0 - e) / C + k * (C * s / W + 1.0 - c - (1.0 - e));
    (th, omega)
}

/// The rotor; `forces`: it gives its acceleration rows of `df/dy` (else the methods
/// take forward differences).
struct Rotor {
    forces: bool,
    profile: Option<Profile>,
}

impl Rhs for Rotor {
    fn shape(&self) -> StateShape {
        StateShape { nq: 2, nv: 1, rate: PositionRate::Mapped }
    }

    fn eval(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Singular> {
        self.position_rate(&y[..2], &y[2..], &mut dy[..2]);
        dy[2] = C * (OMEGA - y[2]) + A * (W * t).cos();
        Ok(())
    }

    fn position_rate(&self, q: &[f64], v: &[f64], qdot: &mut [f64]) {
        qdot[0] = -q[1] * v[0];
        qdot[1] = q[0] * v[0];
    }

    fn rate_jacobian(&self, q: &[f64], mut g: DMatrixViewMut<'_, f64>) {
        g[(0, 0)] = -q[1];
        g[(1, 0)] = q[0];
    }

    fn update_positions(&mut self, q: &mut [f64]) -> bool {
        let r = q[0].hypot(q[1]);
        q.iter_mut().for_each(|x| *x /= r);
        true
    }

    fn profile(&mut self) -> &mut Option<Profile> {
        &mut self.profile
    }

    fn acceleration_jacobian(
        &mut self,
        _t: f64,
        _y: &[f64],
        jac: &mut DMatrix<f64>,
    ) -> Option<Result<JacobianKind, Singular>> {
        self.forces.then(|| {
            jac.copy_from_slice(&[0.0, 0.0, -C]);
            Ok(JacobianKind::Forces)
        })
    }
}

/// The largest difference of a state `y = (q, omega)` from the closed form at `t`.
fn error_at(t: f64, y: &[f64]) -> f64 {
    let (th, omega) = exact(t);
    [y[0] - th.cos(), y[1] - th.sin(), y[2] - omega].iter().fold(0.0, |m, e| m.max(e.abs()))
}

/// Integrates to `t_end` at `tol` with the loop's step-size rules; returns the largest
/// error at the step ends, the largest inside the steps (the dense output at a quarter,
/// half and three quarters of each), and the accepted steps. Asserts `|q| = 1` to
/// rounding at every step end.
fn run(
    stepper: &mut dyn Stepper<Rotor>,
    rotor: &mut Rotor,
    t_end: f64,
    tol: Tolerances,
) -> (f64, f64, usize) {
    let shape = rotor.shape();
    let mut y = vec![TH0.cos(), TH0.sin(), OMEGA0];
    let mut f = vec![0.0; 3];
    let (mut y1, mut f1, mut out) = (vec![0.0; 3], vec![0.0; 3], vec![0.0; 3]);
    rotor.eval(0.0, &y, &mut f).unwrap();
    let (mut t, mut h) = (0.0_f64, 1e-4_f64);
    let (mut at_ends, mut inside, mut accepted) = (0.0_f64, 0.0_f64, 0);
    while t < t_end {
        h = h.min(t_end - t);
        match stepper.attempt(rotor, tol, t, &y, &f, h, &mut y1, &mut f1) {
            Ok(a) if a.error <= 1.0 => {
                let step = DenseStep { shape, h, y0: &y, f0: &f, y1: &y1, f1: &f1, qdd: None };
                for theta in [0.25, 0.5, 0.75] {
                    step.at(theta, &mut out);
                    inside = inside.max(error_at(t + theta * h, &out));
                }
                t += h;
                std::mem::swap(&mut y, &mut y1);
                std::mem::swap(&mut f, &mut f1);
                let norm = y[0].hypot(y[1]);
                assert!(
                    (norm - 1.0).abs() <= 2.0 * f64::EPSILON,
                    "{}: |q| = 1 + {:e}",
                    stepper.name(),
                    norm - 1.0
                );
                at_ends = at_ends.max(error_at(t, &y));
                accepted += 1;
                let own = 0.9 * a.error.max(1e-10).powf(-stepper.error_exponent());
                h *= stepper.step_factor().unwrap_or(own).clamp(0.2, 5.0);
            }
            Ok(a) => {
                stepper.rejected();
                let own = 0.9 * a.error.powf(-stepper.error_exponent());
                h *= stepper.step_factor().unwrap_or(own).clamp(0.1, 0.9);
            }
            Err(StepFailure::Convergence) => {
                stepper.rejected();
                h *= stepper.step_factor().unwrap_or(0.5).clamp(0.1, 0.9);
            }
            Err(StepFailure::Singular) => panic!("{}: the rotor has no singular state", stepper.name()),
        }
    }
    (at_ends, inside, accepted)
}

/// Each method, the implicit ones with the rotor's force Jacobian and with forward
/// differences, follows the closed form over 2 s (the transient of `C` and four periods
/// of the excitation, 1.6 turns) at the step ends and inside the steps, and keeps `q` on
/// the unit circle. A wrong `G` (a sign, a factor 2) turns the rotor at the wrong rate
/// and misses by radians; a dense output off by a factor in its rates misses by the
/// order of `h omega` (1e-2 and more); the methods' global errors at rtol 1e-9 are below
/// 1e-7 at the step ends, and the cubic dense output's below 1e-6 inside them.
#[test]
fn every_method_follows_a_rotor_on_the_unit_circle() {
    let tol = Tolerances { rtol: 1e-9, atol: 1e-9 };
    let cases: [(Box<dyn Stepper<Rotor>>, bool); 5] = [
        (Box::new(Dopri5::new(2, 1)), true),
        (Box::new(Sdirk4::new(2, 1)), true),
        (Box::new(Sdirk4::new(2, 1)), false),
        (Box::new(Radau5::new(2, 1)), true),
        (Box::new(Radau5::new(2, 1)), false),
    ];
    for (mut stepper, forces) in cases {
        let mut rotor = Rotor { forces, profile: None };
        let (at_ends, inside, steps) = run(&mut *stepper, &mut rotor, 2.0, tol);
        let name = format!("{} (force Jacobian: {forces})", stepper.name());
        println!("{name}: {steps} steps, error {at_ends:.2e} at their ends, {inside:.2e} inside");
        assert!(steps >= 20, "{name}: {steps} steps");
        assert!(at_ends < 1e-7, "{name}: error {at_ends:e} at the step ends");
        assert!(inside < 1e-6, "{name}: error {inside:e} inside the steps");
    }
}
