//! The equations of motion as the first-order ODE the integrators step: `y = (q, v)`,
//! `f = (q', qdd)` with `q' = G(q) v` (`v` itself for planar bodies) and `qdd` from the
//! augmented solve of [`crate::dynamics`]. This is where the mechanics meets the generic
//! methods, through their [`Rhs`] trait: the methods never see a body or a constraint,
//! and the dynamics never sees a method.

use nalgebra::DMatrix;

use crate::dynamics::{self, accelerations_for_integration, force_jacobian, Workspace};
use crate::integrators::ode::{PositionRate, Rhs, Singular, StateShape, Tolerances};
use crate::profile::Profile;
use crate::system::System;

/// How the state of `sys` divides: the layout's sizes. Every body kind today is planar,
/// whose positions (x, y, phi) move as `q' = v`.
pub fn state_shape(sys: &System) -> StateShape {
    StateShape { nq: sys.layout.nq(), nv: sys.layout.nv(), rate: PositionRate::Identity }
}

/// One run's ODE: system, scratch and counters.
pub struct Ode<'a> {
    /// The mechanism.
    pub sys: &'a System,
    /// Scratch of the augmented solve.
    pub ws: Workspace,
    /// Number of `f` evaluations.
    pub evaluations: usize,
    /// The run's tolerances, which the methods' error estimates are weighed against.
    pub tolerances: Tolerances,
}

impl<'a> Ode<'a> {
    /// The ODE of `sys` with the active rows `active`, at tolerances `rtol`, `atol`.
    pub fn new(sys: &'a System, active: Vec<usize>, rtol: f64, atol: f64) -> Self {
        Ode { sys, ws: Workspace::new(sys, active), evaluations: 0, tolerances: Tolerances { rtol, atol } }
    }

    /// Writes `f(t, y)` into `dy`.
    pub fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), dynamics::Singular> {
        self.evaluations += 1;
        let n = self.sys.layout.nq();
        let (q, v) = y.split_at(n);
        accelerations_for_integration(self.sys, t, q, v, &mut self.ws)?;
        self.position_rate(q, v, &mut dy[..n]);
        dy[n..].copy_from_slice(&self.ws.qdd);
        Ok(())
    }
}

impl Rhs for Ode<'_> {
    /// [`state_shape`]: `G`, its Jacobian and the position update are the trait's
    /// defaults (the identity and nothing).
    fn shape(&self) -> StateShape {
        state_shape(self.sys)
    }

    fn eval(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Singular> {
        self.rhs(t, y, dy).map_err(|dynamics::Singular| Singular)
    }

    fn profile(&mut self) -> &mut Option<Profile> {
        &mut self.ws.profile
    }

    fn force_jacobian(&mut self, t: f64, y: &[f64], jac: &mut DMatrix<f64>) -> Option<Result<(), Singular>> {
        let (q, v) = y.split_at(self.sys.layout.nq());
        Some(force_jacobian(self.sys, t, q, v, &mut self.ws, jac).map_err(|dynamics::Singular| Singular))
    }
}
