//! The inner step of an integration method; the simulation loop owns time, error
//! control, corners, projection and output (the template of scipy's `OdeSolver`).

use super::ode::{Rhs, Tolerances};

/// Outcome of one trial step.
#[derive(Debug, Clone, Copy)]
pub struct Attempt {
    /// Weighted RMS local error estimate; the step is accepted when <= 1.
    pub error: f64,
    /// Explicit methods: estimate of `h |lambda|` for stiffness detection.
    pub stiffness: Option<f64>,
}

/// Why a trial step produced no estimate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepFailure {
    /// The implicit stage equations did not converge: retry with a smaller step.
    Convergence,
    /// The augmented system is singular: the run cannot go on.
    Singular,
}

/// One integration method's inner step on any right-hand side `R` (a trait object per
/// `R`, so that the loop can change methods mid-run).
pub trait Stepper<R: Rhs + ?Sized> {
    /// Name in reports.
    fn name(&self) -> &'static str;
    /// `1 / (p + 1)` with p the order of the error estimate.
    fn error_exponent(&self) -> f64;
    /// Tries a step of size `h` from `(t, y)` with `f0 = f(t, y)`, its error weighed
    /// against `tol`; writes the solution and its derivative at `t + h`. An accepted
    /// attempt (error <= 1) evaluates `ode` last at `(t + h, y_new)`: the loop reads the
    /// drift there from the workspace.
    #[allow(clippy::too_many_arguments)]
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
    ) -> Result<Attempt, StepFailure>;
    /// Jacobian evaluations so far (implicit methods).
    fn jacobian_evaluations(&self) -> usize {
        0
    }
    /// Newton iterations so far (implicit methods), converged or not: each one
    /// evaluates the right-hand side at every stage it solves.
    fn newton_iterations(&self) -> usize {
        0
    }
    /// Called after a rejected step.
    fn rejected(&mut self) {}
    /// Methods that choose their own step size: `h_next / h` after the last attempt
    /// (accepted, rejected, or failed to converge), which the loop then bounds as its own
    /// rule's. `None`: the loop's rule from `error` and `error_exponent`.
    fn step_factor(&self) -> Option<f64> {
        None
    }
    /// Implicit methods: the spectral radius of the Jacobian at `(t, y)`, evaluated
    /// afresh, so that `auto` can tell whether an explicit step would be stable.
    fn spectral_radius(&mut self, _ode: &mut R, _t: f64, _y: &[f64], _f: &[f64]) -> Option<f64> {
        None
    }
}
