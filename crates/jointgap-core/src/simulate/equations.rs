//! The equations of motion as the first-order ODE the integrators step: `y = (q, v)`,
//! `f = (q', qdd)` with `q' = G(q) v` (`v` itself for planar bodies) and `qdd` from the
//! augmented solve of [`crate::dynamics`]. This is where the mechanics meets the generic
//! methods, through their [`Rhs`] trait: the methods never see a body or a constraint,
//! and the dynamics never sees a method.

use nalgebra::{DMatrix, DMatrixViewMut};

use crate::dynamics::{self, accelerations_for_integration, force_jacobian, Workspace};
use crate::integrators::ode::{JacobianKind, PositionRate, Rhs, Singular, StateShape, Tolerances};
use crate::mechanics::planar::Planar;
use crate::profile::Profile;
use crate::system::System;

use super::Kind;

/// How the state of `sys` divides: the layout's sizes, and whether positions move as
/// their velocities (planar bodies) or through the body kind's `G(q)` (a spatial
/// body's quaternion).
pub fn state_shape<K: Kind>(sys: &System<K>) -> StateShape {
    let rate = if K::IDENTITY_RATE { PositionRate::Identity } else { PositionRate::Mapped };
    StateShape { nq: sys.layout.nq(), nv: sys.layout.nv(), rate }
}

/// One run's ODE: system, scratch and counters.
pub struct Ode<'a, K: Kind = Planar> {
    /// The mechanism.
    pub sys: &'a System<K>,
    /// Scratch of the augmented solve.
    pub ws: Workspace<K>,
    /// Number of `f` evaluations.
    pub evaluations: usize,
    /// The run's tolerances, which the methods' error estimates are weighed against.
    pub tolerances: Tolerances,
}

impl<'a, K: Kind> Ode<'a, K> {
    /// The ODE of `sys` with the active rows `active`, at tolerances `rtol`, `atol`.
    pub fn new(sys: &'a System<K>, active: Vec<usize>, rtol: f64, atol: f64) -> Self {
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

impl<K: Kind> Rhs for Ode<'_, K> {
    /// [`state_shape`].
    fn shape(&self) -> StateShape {
        state_shape(self.sys)
    }

    /// `q' = G(q) v`, body by body by its kind's rule.
    fn position_rate(&self, q: &[f64], v: &[f64], out: &mut [f64]) {
        if K::IDENTITY_RATE {
            out.copy_from_slice(v);
            return;
        }
        for slot in self.sys.layout.slots() {
            K::position_rate(&q[slot.q()], &v[slot.v()], &mut out[slot.q()]);
        }
    }

    /// `q''` body by body, for the dense output where `q' = G(q) v`.
    fn position_acceleration(&self, q: &[f64], v: &[f64], a: &[f64], qdd: &mut [f64]) {
        for slot in self.sys.layout.slots() {
            K::position_acceleration(&q[slot.q()], &v[slot.v()], &a[slot.v()], &mut qdd[slot.q()]);
        }
    }

    /// `G(q)` as the block `d(q')/d(v)`, body by body.
    fn rate_jacobian(&self, q: &[f64], mut g: DMatrixViewMut<'_, f64>) {
        g.fill(0.0);
        for slot in self.sys.layout.slots() {
            K::rate_block(&q[slot.q()], |r, c, x| g[(slot.q_at + r, slot.v_at + c)] = x);
        }
    }

    /// Brings each body's positions back to their manifold (a unit quaternion).
    fn update_positions(&mut self, q: &mut [f64]) -> bool {
        let mut changed = false;
        if !K::IDENTITY_RATE {
            for slot in self.sys.layout.slots() {
                changed |= K::normalise(&mut q[slot.q()]);
            }
        }
        changed
    }

    fn eval(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Singular> {
        self.rhs(t, y, dy).map_err(|dynamics::Singular| Singular)
    }

    fn profile(&mut self) -> &mut Option<Profile> {
        &mut self.ws.profile
    }

    /// Exact, from the graph of the recorded evaluation where the run records one
    /// ([`dynamics::compiled::jacobian`]); the applied forces' part otherwise
    /// ([`force_jacobian`]).
    fn acceleration_jacobian(
        &mut self,
        t: f64,
        y: &[f64],
        jac: &mut DMatrix<f64>,
    ) -> Option<Result<JacobianKind, Singular>> {
        let (q, v) = y.split_at(self.sys.layout.nq());
        if dynamics::compiled::jacobian(self.sys, t, q, v, &mut self.ws, jac) {
            return Some(Ok(JacobianKind::Exact));
        }
        let forces = force_jacobian(self.sys, t, q, v, &mut self.ws, jac);
        Some(forces.map(|()| JacobianKind::Forces).map_err(|dynamics::Singular| Singular))
    }
}
