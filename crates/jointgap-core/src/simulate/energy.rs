//! Energy accounts: the work done on the mechanism by its drivers and applied loads, and
//! the energy that dampers, contact damping and friction dissipate, as time integrals of
//! their powers over the integration steps ([outputs](../../../../docs/outputs.md),
//! energy accounts).
//!
//! With them the energy balance `T + V - W_in + D` is a conserved quantity of every run,
//! which a plot of `system.energy_balance` checks. Each integral is summed step by step
//! by 3-point Gauss-Legendre quadrature along the step's dense output (the same
//! interpolant that gives the output samples), so it does not depend on the output rate,
//! and a sample inside a step adds the part of the step up to its time.
//! The powers need the multipliers (a driver's power is `lambda ct` of its row), so
//! every node is a full evaluation of the equations of motion: the accounts cost about
//! three evaluations per step and per sample, and are computed only when a run asks
//! for them. The evaluations use their own workspace, so that a run with accounts
//! steps exactly as one without.

use super::equations::state_shape;
use crate::dynamics::{accelerations, Singular, Workspace};
use crate::integrators::ode::{DenseStep, StateShape};
use crate::mechanics::contact::{self, ClearanceJoint, ContactState};
use crate::mechanics::kind::ForceLaw;
use crate::mechanics::planar::Planar;
use crate::system::System;

use super::Kind;

/// The accounts, in channel order (`system.<name>`) [J].
pub const ACCOUNTS: [&str; 5] =
    ["driver_work", "load_work", "damper_dissipation", "contact_dissipation", "friction_dissipation"];

/// One value per account.
pub type Amounts = [f64; ACCOUNTS.len()];

/// Gauss-Legendre nodes on [0, 1] and their weights: exact for polynomials of degree 5.
const NODES: [f64; 3] = [0.5 - 0.387_298_334_620_741_7, 0.5, 0.5 + 0.387_298_334_620_741_7];
const WEIGHTS: [f64; 3] = [5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0];

/// The running integrals of a run and the step in progress.
pub struct Accounts<K: Kind = Planar> {
    /// Scratch of the evaluations at the quadrature nodes, apart from the integrator's.
    ws: Workspace<K>,
    /// Active index of each driver's row (`None`: a redundant row, which does no work).
    driver_rows: Vec<Option<usize>>,
    /// Integrals at the start and at the end of the step in progress.
    start: Amounts,
    end: Amounts,
    /// The step in progress: from `t0` to `t1` along the dense output of a step `h`
    /// long from `t0` (`y0, f0, y1, f1`, concatenated).
    t0: f64,
    t1: f64,
    h: f64,
    shape: StateShape,
    ends: Vec<f64>,
    /// The state at a node.
    y: Vec<f64>,
}

impl<K: Kind> Accounts<K> {
    /// Zero accounts at t = 0 for a run whose workspace is `ws`.
    pub fn new(sys: &System<K>, ws: &Workspace<K>) -> Self {
        let mut own = ws.clone();
        own.profile = None;
        let driver_rows = sys.drivers.iter().map(|d| ws.active.iter().position(|&r| r == d.row)).collect();
        let shape = state_shape(sys);
        let n = shape.state_len();
        Accounts {
            ws: own,
            driver_rows,
            start: [0.0; ACCOUNTS.len()],
            end: [0.0; ACCOUNTS.len()],
            t0: 0.0,
            t1: 0.0,
            h: 0.0,
            shape,
            ends: vec![0.0; 4 * n],
            y: vec![0.0; n],
        }
    }

    /// Takes the accepted step `step` from `t0`, ended at `t1` (earlier than its full
    /// length when a contact event cut it), with the clearance joints in `contacts`
    /// throughout: adds its integrals.
    pub fn begin_step(
        &mut self,
        sys: &System<K>,
        contacts: &[ContactState],
        step: &DenseStep,
        t0: f64,
        t1: f64,
    ) -> Result<(), Singular> {
        let n = self.y.len();
        for (k, part) in [step.y0, step.f0, step.y1, step.f1].iter().enumerate() {
            self.ends[k * n..(k + 1) * n].copy_from_slice(part);
        }
        (self.t0, self.t1, self.h, self.shape) = (t0, t1, step.h, step.shape);
        self.ws.contacts.copy_from_slice(contacts);
        self.ws.t_piece = 0.5 * (t0 + t1);
        self.start = self.end;
        let step = self.integral(sys, t1)?;
        self.end = std::array::from_fn(|k| self.start[k] + step[k]);
        Ok(())
    }

    /// The integrals from t = 0 to `t`, a time of the step in progress (or its start).
    pub fn at(&mut self, sys: &System<K>, t: f64) -> Result<Amounts, Singular> {
        if t >= self.t1 {
            return Ok(self.end);
        }
        if t <= self.t0 {
            return Ok(self.start);
        }
        let part = self.integral(sys, t)?;
        Ok(std::array::from_fn(|k| self.start[k] + part[k]))
    }

    /// The integrals over `[t0, t]` of the step in progress.
    fn integral(&mut self, sys: &System<K>, t: f64) -> Result<Amounts, Singular> {
        let mut sum = [0.0; ACCOUNTS.len()];
        let span = t - self.t0;
        if span <= 0.0 {
            return Ok(sum);
        }
        let n = self.y.len();
        let (nq, mut y) = (self.shape.nq, std::mem::take(&mut self.y));
        for (x, w) in NODES.iter().zip(WEIGHTS) {
            let [y0, f0, y1, f1] = [0, 1, 2, 3].map(|k| &self.ends[k * n..(k + 1) * n]);
            DenseStep { shape: self.shape, h: self.h, y0, f0, y1, f1, qdd: None }
                .at(x * span / self.h, &mut y);
            let power = self.powers(sys, self.t0 + x * span, &y[..nq], &y[nq..]);
            match power {
                Ok(p) => sum.iter_mut().zip(p).for_each(|(s, p)| *s += w * span * p),
                Err(e) => {
                    self.y = y;
                    return Err(e);
                }
            }
        }
        self.y = y;
        Ok(sum)
    }

    /// The powers [W] at `(t, q, v)`, in [`ACCOUNTS`] order: the drivers' `lambda ct`
    /// summed over their rows (the power of a constraint force `-Cq^T lambda` is
    /// `-lambda Cq v = lambda ct`), the applied loads' and the dampers' from the force
    /// elements, the contacts' from the clearance joints.
    fn powers(&mut self, sys: &System<K>, t: f64, q: &[f64], v: &[f64]) -> Result<Amounts, Singular> {
        let mut p = [0.0; ACCOUNTS.len()];
        if !sys.drivers.is_empty() {
            accelerations(sys, t, q, v, &mut self.ws)?;
            p[0] = self.driver_rows.iter().flatten().map(|&a| self.ws.lambda[a] * self.ws.ct[a]).sum();
        }
        for f in &sys.forces {
            let (load, loss) = f.power(t, |b| sys.body_state(b, q, v));
            p[1] += load;
            p[2] += loss;
        }
        for (_, c, points) in contact::slots(&sys.clearances) {
            let [i, j] = c.parts().map(|b| sys.body_state(b, q, v));
            let (normal, friction) = c.losses(&i, &j, &self.ws.contacts[points]);
            p[3] += normal;
            p[4] += friction;
        }
        Ok(p)
    }
}
