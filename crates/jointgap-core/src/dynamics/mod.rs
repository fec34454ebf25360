//! Equations of motion: constraints, applied forces and the augmented solve
//! `[M Cq^T; Cq 0][qdd; lambda] = [Qe; gamma]`, done through the Schur complement
//! `(Cq M^-1 Cq^T) lambda = Cq M^-1 Qe - gamma` because M is diagonal. The Jacobian is
//! kept row by row (each row touches at most two bodies), so every product here costs
//! in proportion to the number of rows. Bodies that their own rows fix (a driven crank)
//! are solved ahead of the Schur complement and their multipliers after it
//! ([`prescribed`]).

use nalgebra::{DMatrix, DVector, Vector3};

pub mod assembly;
pub mod compiled;
pub mod kernels;
pub mod prescribed;
pub mod schur;

pub use schur::Singular;

use crate::mechanics::contact::point3::ContactPoint3;
use crate::mechanics::contact::{self, ClearanceJoint, ContactPoint, ContactState};
use crate::mechanics::drivers::Motion;
use crate::mechanics::kind::{BodyKind, ForceLaw};
use crate::mechanics::layout::Layout;
use crate::mechanics::layout::Loads;
use crate::mechanics::planar::Planar;
use crate::mechanics::planar_body;
use crate::mechanics::spatial::{self, kind::Spatial};
use crate::profile::{self, Profile};
use crate::system::System;
use prescribed::PrescribedBody;
use schur::{Factorisation, RowJacobian, Schur};

const NO_MOTION: Motion = Motion { position: 0.0, speed: 0.0, acceleration: 0.0 };

/// Scratch space of one run, filled by the functions of this module.
#[derive(Debug, Clone)]
pub struct Workspace<K: BodyKind = Planar> {
    /// Indices of the active rows in `System::rows`, in solve order: the rows of the
    /// Schur complement, then the prescribed bodies' own ([`prescribed`]).
    pub active: Vec<usize>,
    /// Number of leading active rows in the Schur complement.
    dynamic: usize,
    /// Bodies that their own rows fix, in the order their accelerations are found.
    prescribed: Vec<PrescribedBody>,
    /// Filled by [`accelerations`]: each prescribed body's `B^-1`.
    prescribed_inverse: Vec<prescribed::BodyBlock>,
    /// Where each body's coordinates sit (the system's).
    layout: Layout,
    /// Inverse of the mass matrix, each planar body's diagonal laid out as `v`, zero for
    /// a prescribed body: no force moves it; (nv).
    pub m_inv: Vec<f64>,
    /// Filled by [`constraints`]: residuals; (n_active).
    pub c: DVector<f64>,
    /// Filled by [`constraints`]: the Jacobian `Cq`, one entry per active row.
    pub jac: Vec<RowJacobian<K::Row>>,
    /// Filled by [`constraints`]: `dC/dt`; (n_active).
    pub ct: DVector<f64>,
    /// Filled by [`constraints`]: acceleration right-hand side; (n_active).
    pub gamma: DVector<f64>,
    /// Filled by [`applied_forces`]: generalised applied forces; (nv).
    pub qe: Vec<f64>,
    /// The Schur complement `Cq M^-1 Cq^T` and its solver.
    pub schur: Schur<K::Row>,
    /// Filled by [`accelerations`]: multipliers, one per active row; (n_active).
    pub lambda: DVector<f64>,
    /// Filled by [`accelerations`]: accelerations; (nv).
    pub qdd: Vec<f64>,
    /// Time inside the current step, selecting the driver profiles' pieces.
    pub t_piece: f64,
    /// Discrete state of each contact point of the clearance joints, joint after joint
    /// ([`contact::slots`]); forces filled by [`applied_forces`].
    pub contacts: Vec<ContactState>,
    /// Time per stage, when measured.
    pub profile: Option<Profile>,
    /// Each body's state at the last evaluation, its rotation computed once for all rows
    /// and forces; (n_bodies).
    bodies: Vec<K::State>,
    /// The ground's state, which rows and forces on the ground read.
    ground: K::State,
    /// Scratch of length nv.
    scratch: Vec<f64>,
    /// The rows and forces compiled to native code, when the run compiles them.
    pub compiled: Option<Box<compiled::Stage<K>>>,
}

impl<K: Contacts> Workspace<K> {
    /// Allocates for a system whose active rows are `active` (reordered into solve
    /// order), factoring the Schur complement over its envelope or sparse by its pattern
    /// ([`Factorisation::Auto`]).
    pub fn new(sys: &System<K>, active: Vec<usize>) -> Self {
        Self::with_factorisation(sys, active, Factorisation::Auto)
    }

    /// As [`Workspace::new`] with the factorisation chosen by the caller (tests compare
    /// both on one system).
    pub fn with_factorisation(sys: &System<K>, active: Vec<usize>, factorisation: Factorisation) -> Self {
        let split = prescribed::split(sys, &active);
        Self::build(sys, split.order, split.dynamic, split.bodies, factorisation)
    }

    /// For assembly: the rows `rows` in the order given, all in the Schur complement.
    pub fn in_order(sys: &System<K>, rows: Vec<usize>) -> Self {
        let m = rows.len();
        Self::build(sys, rows, m, Vec::new(), Factorisation::Auto)
    }

    fn build(
        sys: &System<K>,
        active: Vec<usize>,
        dynamic: usize,
        prescribed: Vec<PrescribedBody>,
        factorisation: Factorisation,
    ) -> Self {
        let layout = sys.layout.clone();
        let n = layout.nv();
        let m = active.len();
        let mut m_inv = vec![0.0; n];
        for (b, slot) in sys.bodies.iter().zip(layout.slots()) {
            m_inv[slot.v()].copy_from_slice(K::inverse_mass(b.mass, &b.inertia).as_ref());
        }
        for p in &prescribed {
            m_inv[p.own.clone()].fill(0.0);
        }
        let bodies: Vec<[Option<usize>; 2]> =
            active.iter().map(|&r| [sys.rows[r].body_i, sys.rows[r].body_j]).collect();
        // In the Schur complement a prescribed body is a moving support, like the ground.
        let mut fixed = vec![false; sys.bodies.len()];
        prescribed.iter().for_each(|p| fixed[p.body] = true);
        let moving = |b: Option<usize>| b.filter(|&k| !fixed[k]);
        let schur_bodies: Vec<[Option<usize>; 2]> =
            bodies[..dynamic].iter().map(|&[i, j]| [moving(i), moving(j)]).collect();
        Workspace {
            active,
            dynamic,
            prescribed_inverse: vec![Default::default(); prescribed.len()],
            prescribed,
            c: DVector::zeros(m),
            // Each row's bodies are fixed for the run; `constraints` fills the entries.
            jac: bodies.iter().map(|&bodies| RowJacobian::new(bodies, &layout)).collect(),
            ct: DVector::zeros(m),
            gamma: DVector::zeros(m),
            qe: vec![0.0; n],
            schur: Schur::new(&schur_bodies, factorisation),
            m_inv,
            lambda: DVector::zeros(m),
            qdd: vec![0.0; n],
            t_piece: 0.0,
            contacts: vec![ContactState::default(); K::contact_point_count(sys)],
            profile: None,
            bodies: vec![K::ground(); sys.bodies.len()],
            ground: K::ground(),
            scratch: vec![0.0; n],
            layout,
            compiled: None,
        }
    }

    /// The bodies that their own rows fix, in the order their accelerations are found.
    pub fn prescribed_bodies(&self) -> impl Iterator<Item = usize> + '_ {
        self.prescribed.iter().map(|p| p.body)
    }

    /// The Jacobian as a dense matrix (n_active x nv), for the one-time solves of
    /// assembly.
    pub fn dense_jacobian(&self) -> DMatrix<f64> {
        let mut cq = DMatrix::zeros(self.jac.len(), self.m_inv.len());
        for (a, row) in self.jac.iter().enumerate() {
            for (at, entries) in row.placed_blocks() {
                for (d, e) in entries.as_ref().iter().enumerate() {
                    cq[(a, at + d)] += e;
                }
            }
        }
        cq
    }

    /// The loaded state of body `b` (the ground for `None`).
    #[inline]
    fn body(&self, b: Option<usize>) -> &K::State {
        b.map_or(&self.ground, |k| &self.bodies[k])
    }

    /// Loads every body's state at `(q, v)`.
    fn load_bodies(&mut self, sys: &System<K>, q: &[f64], v: &[f64]) {
        for (k, state) in self.bodies.iter_mut().enumerate() {
            *state = sys.body_state(Some(k), q, v);
        }
    }

    /// [`violation`] at the state of the last evaluation, whose velocities are `v`: its
    /// rows are still in the workspace. An integration step's last evaluation is at its
    /// end, so the drift check after the step needs no evaluation of its own.
    pub fn violation_here(&self, v: &[f64]) -> (f64, f64) {
        if self.active.is_empty() {
            return (0.0, 0.0);
        }
        let velocity = self.velocity_residual(v).fold(0.0f64, |m, r| m.max(r.abs()));
        (self.c.amax(), velocity)
    }

    /// The position and velocity residuals that the rounding of the state `(q, v)` alone
    /// leaves in the active rows of the last evaluation, which no projection can take
    /// away: [`ROUNDING_ULPS`] ulps of the largest coordinate (speed), or of a rotation's
    /// reach, whichever is more. The rounding of a body's angle `phi` moves each of its
    /// points by `|s| eps |phi|` and changes its velocity by `|s| |omega| eps |phi|`,
    /// with `|s|` the point's distance from the body's frame, read off the rows as their
    /// angle entry where the row also holds the body's position (a point row, not an
    /// angle row; the entry is a component of `|s|`, which the margin of ulps covers).
    /// Both grow with the angle of a crank that turns on: after 300 turns (1900 rad) a
    /// point 0.04 m out on a crank at 31.4 rad/s carries velocity residuals of 5e-13 m/s
    /// from its angle's rounding, five times `0.01 atol` at the default tolerance.
    pub fn rounding(&self, q: &[f64], v: &[f64]) -> (f64, f64) {
        let largest = |x: &[f64]| x.iter().fold(0.0f64, |m, a| m.max(a.abs()));
        let (mut position, mut velocity) = (largest(q), largest(v));
        for row in &self.jac {
            for (k, entries) in row.blocks() {
                let slot = self.layout.slot(k);
                if let Some((moved, changed)) = K::rotation_reach(entries, &q[slot.q()], &v[slot.v()]) {
                    position = position.max(moved);
                    velocity = velocity.max(changed);
                }
            }
        }
        let ulps = ROUNDING_ULPS * f64::EPSILON;
        (ulps * position, ulps * velocity)
    }

    /// `Cq v + ct` row by row: the velocity constraint residual.
    fn velocity_residual<'a>(&'a self, v: &'a [f64]) -> impl Iterator<Item = f64> + 'a {
        self.jac.iter().zip(self.ct.iter()).map(move |(row, ct)| row.dot(v) + ct)
    }

    /// The inverse mass that a unit force along `g` (a direction in velocity
    /// coordinates) meets through the constraints of the last evaluation,
    /// `g^T (M^-1 - M^-1 Cq^T S^-1 Cq M^-1) g`, between zero and the free `g^T M^-1 g`;
    /// the free one where that is at most `enough` (no solve with the constraints).
    fn inverse_mass_along(&mut self, g: &[f64], enough: f64) -> f64 {
        let u: Vec<f64> = g.iter().zip(&self.m_inv).map(|(g, m)| g * m).collect();
        let free: f64 = g.iter().zip(&u).map(|(g, u)| g * u).sum();
        let mut inverse_mass = free;
        if self.dynamic > 0 && free > enough {
            let mut mu: Vec<f64> = self.jac[..self.dynamic].iter().map(|row| row.dot(&u)).collect();
            let r = mu.clone();
            if self.schur_solve(&mut mu).is_ok() {
                inverse_mass -= r.iter().zip(&mu).map(|(r, m)| r * m).sum::<f64>();
            }
        }
        inverse_mass.clamp(0.0, free)
    }

    /// `x -= M^-1 Cq^T mu` over the Schur complement's rows (`mu` has one entry each).
    fn subtract_correction(&mut self, mu: &[f64], x: &mut [f64]) {
        self.scratch.fill(0.0);
        for (row, &m) in self.jac.iter().zip(mu) {
            row.add_transposed(m, &mut self.scratch);
        }
        for j in 0..x.len() {
            x[j] -= self.m_inv[j] * self.scratch[j];
        }
    }

    /// Solves `S mu = rhs` in place with the current Jacobian (one entry per row of the
    /// Schur complement).
    fn schur_solve(&mut self, rhs: &mut [f64]) -> Result<(), Singular> {
        if rhs.is_empty() {
            return Ok(());
        }
        let lap = profile::start(&self.profile);
        self.schur.update(&self.jac[..self.dynamic], &self.m_inv);
        let solved = self.schur.solve(rhs);
        profile::stop(&mut self.profile, lap, |p| &mut p.linear_solves);
        solved
    }

    /// The smallest mass-weighted `dx` (velocity coordinates) with `Cq dx = r` (`r` per
    /// active row, e.g. the residuals, for a projection): the prescribed bodies from
    /// their own rows, the others through the Schur complement. Moves `x` by `-dx` with
    /// `add(x, -dx)`, in these two parts: for velocities `add` adds, for positions it
    /// displaces each body by its kind's rule ([`System::displace`]).
    fn subtract_solution(
        &mut self,
        r: &[f64],
        x: &mut [f64],
        add: impl Fn(&mut [f64], &[f64]),
    ) -> Result<(), Singular> {
        let mut dx = std::mem::take(&mut self.scratch);
        dx.fill(0.0);
        for p in &self.prescribed {
            let b_inv = p.inverse(&self.jac)?;
            p.solve_rows(&self.jac, &b_inv, |a| r[a], &mut dx);
        }
        let mut mu: Vec<f64> = (0..self.dynamic).map(|a| r[a] - self.jac[a].dot(&dx)).collect();
        dx.iter_mut().for_each(|d| *d = -*d);
        add(x, &dx);
        self.schur_solve(&mut mu)?;
        dx.fill(0.0);
        for (row, &m) in self.jac.iter().zip(&mu) {
            row.add_transposed(m, &mut dx);
        }
        dx.iter_mut().zip(&self.m_inv).for_each(|(d, m)| *d = -(m * *d));
        add(x, &dx);
        self.scratch = dx;
        Ok(())
    }
}

/// Evaluates the active constraint rows at `(t, q, v)`: fills `c`, `jac`, `ct`, `gamma`.
pub fn constraints<K: Contacts>(sys: &System<K>, t: f64, q: &[f64], v: &[f64], ws: &mut Workspace<K>) {
    ws.load_bodies(sys, q, v);
    constraint_rows(sys, t, ws);
}

/// [`constraints`] at the loaded body states.
fn constraint_rows<K: Contacts>(sys: &System<K>, t: f64, ws: &mut Workspace<K>) {
    for (a, &r) in ws.active.iter().enumerate() {
        let row = &sys.rows[r];
        let motion = match row.driver {
            Some(d) => sys.drivers[d].profile.motion_on(t, ws.t_piece),
            None => NO_MOTION,
        };
        let (bi, bj) = (ws.body(row.body_i), ws.body(row.body_j));
        let ev = K::eval(&row.kind, bi, bj, motion);
        ws.c[a] = ev.c;
        ws.ct[a] = ev.ct;
        ws.gamma[a] = ev.gamma;
        ws.jac[a].entries = [ev.jac_i, ev.jac_j];
    }
}

/// Fills `qe` with gravity and every force element at `(t, q, v)`.
pub fn applied_forces<K: Contacts>(sys: &System<K>, t: f64, q: &[f64], v: &[f64], ws: &mut Workspace<K>) {
    ws.load_bodies(sys, q, v);
    forces_at_bodies(sys, t, ws);
}

/// [`applied_forces`] at the loaded body states.
fn forces_at_bodies<K: Contacts>(sys: &System<K>, t: f64, ws: &mut Workspace<K>) {
    ws.qe.fill(0.0);
    for ((b, slot), state) in sys.bodies.iter().zip(sys.layout.slots()).zip(&ws.bodies) {
        let qe = &mut ws.qe[slot.v()];
        K::add_weight(qe, b.mass, &sys.gravity);
        K::add_inertial(qe, &b.inertia, state);
    }
    let (bodies, ground) = (&ws.bodies, &ws.ground);
    let state = |b: Option<usize>| b.map_or(ground, |k| &bodies[k]);
    let mut loads = Loads::new(&sys.layout, &mut ws.qe);
    for f in &sys.forces {
        f.add_to(t, |b| *state(b), &mut loads);
    }
    K::add_contact_loads(sys, state, &ws.contacts, &mut loads);
}

/// Accelerations and multipliers at `(t, q, v)`: fills everything in the workspace.
pub fn accelerations<K: Contacts>(
    sys: &System<K>,
    t: f64,
    q: &[f64],
    v: &[f64],
    ws: &mut Workspace<K>,
) -> Result<(), Singular> {
    accelerations_for_integration(sys, t, q, v, ws)?;
    prescribed_multipliers(sys, ws);
    Ok(())
}

/// [`accelerations`] without the prescribed rows' multipliers (the driving torques and
/// their pins' reactions): the motion does not depend on them, so the integrator's
/// evaluations leave them out and only recorded samples compute them.
pub fn accelerations_for_integration<K: Contacts>(
    sys: &System<K>,
    t: f64,
    q: &[f64],
    v: &[f64],
    ws: &mut Workspace<K>,
) -> Result<(), Singular> {
    let lap = profile::start(&ws.profile);
    if compiled::accelerations(sys, t, q, v, ws) {
        profile::stop(&mut ws.profile, lap, |p| &mut p.forces);
        return Ok(());
    }
    ws.load_bodies(sys, q, v);
    constraint_rows(sys, t, ws);
    forces_at_bodies(sys, t, ws);
    let n = sys.layout.nv();
    for j in 0..n {
        ws.qdd[j] = ws.m_inv[j] * ws.qe[j];
    }
    if ws.active.is_empty() {
        profile::stop(&mut ws.profile, lap, |p| &mut p.forces);
        return Ok(());
    }
    // The prescribed bodies' accelerations from their own rows; then lambda solves
    // S lambda = Cq M^-1 Qe - gamma over the other rows, the prescribed bodies' terms
    // included through qdd, and qdd = M^-1 (Qe - Cq^T lambda).
    let mut qdd = std::mem::take(&mut ws.qdd);
    let mut lambda = std::mem::take(&mut ws.lambda);
    let mut solved = Ok(());
    for (p, b_inv) in ws.prescribed.iter().zip(ws.prescribed_inverse.iter_mut()) {
        match p.inverse(&ws.jac) {
            Ok(inv) => {
                *b_inv = inv;
                p.solve_rows(&ws.jac, b_inv, |a| ws.gamma[a], &mut qdd);
            }
            Err(e) => solved = Err(e),
        }
    }
    for a in 0..ws.dynamic {
        lambda[a] = ws.jac[a].dot(&qdd) - ws.gamma[a];
    }
    solved = solved.and_then(|()| ws.schur_solve(&mut lambda.as_mut_slice()[..ws.dynamic]));
    if solved.is_ok() {
        ws.subtract_correction(&lambda.as_slice()[..ws.dynamic], &mut qdd);
    }
    ws.qdd = qdd;
    ws.lambda = lambda;
    profile::stop(&mut ws.profile, lap, |p| &mut p.forces);
    solved
}

/// The prescribed rows' multipliers (driving torque, pin reactions) after
/// [`accelerations_for_integration`], outermost body first: its rows act on the bodies
/// it rests on.
fn prescribed_multipliers<K: Contacts>(sys: &System<K>, ws: &mut Workspace<K>) {
    let mut lambda = std::mem::take(&mut ws.lambda);
    for (p, b_inv) in ws.prescribed.iter().zip(&ws.prescribed_inverse).rev() {
        let b = &sys.bodies[p.body];
        let mass = K::mass_diagonal(b.mass, &b.inertia);
        p.multipliers(&ws.jac, b_inv, &mass, &ws.qe, &ws.qdd, lambda.as_mut_slice());
    }
    ws.lambda = lambda;
}

/// The acceleration rows of `df/dy` for the implicit methods, `jac = [dqdd/dq dqdd/dv]`
/// (nv x (nq + nv)), taken through the applied forces alone: column `j` is
/// `P dQe/dy_j` with `P = M^-1 - M^-1 Cq^T S^-1 Cq M^-1`, the constrained inverse mass
/// at `(t, q, v)`, and `dQe/dy_j` a forward difference of the forces only (increment as
/// the methods' own forward-difference Jacobian). What it leaves out is the derivative of
/// `P` and of `gamma`: the geometric stiffness of the constraint forces and the
/// velocity terms, which scale with the mechanism's speeds and loads, not with a
/// contact's or a spring's stiffness, so the Newton iteration keeps the stiff part it
/// needs. It costs a force evaluation per coordinate and one solve with the factor
/// already in hand per column that is not zero, against a full evaluation (forces,
/// constraints, factor and solve) per column for forward differences.
pub fn force_jacobian<K: Contacts>(
    sys: &System<K>,
    t: f64,
    q: &[f64],
    v: &[f64],
    ws: &mut Workspace<K>,
    jac: &mut DMatrix<f64>,
) -> Result<(), Singular> {
    let layout = &sys.layout;
    let n = layout.nv();
    ws.load_bodies(sys, q, v);
    constraint_rows(sys, t, ws);
    forces_at_bodies(sys, t, ws);
    let qe0 = ws.qe.clone();
    // Column j: position j, then velocity j - nq, each with its body.
    let positions = layout.slots().iter().enumerate().flat_map(|(k, s)| s.q().map(move |i| (k, i, false)));
    let velocities = layout.slots().iter().enumerate().flat_map(|(k, s)| s.v().map(move |i| (k, i, true)));
    let (mut q_body, mut v_body) = (q.to_vec(), v.to_vec());
    // Factor S at the base point; the columns below reuse it.
    let mut mu = vec![0.0; ws.dynamic];
    ws.schur_solve(&mut mu)?;
    let mut col = vec![0.0; n];
    for (j, (k, i, velocity)) in positions.chain(velocities).enumerate() {
        let base = ws.bodies[k];
        let bumped = if velocity { &mut v_body } else { &mut q_body };
        let y = bumped[i];
        let dy = f64::EPSILON.sqrt() * y.abs().max(1e-5);
        bumped[i] += dy;
        let slot = layout.slot(k);
        ws.bodies[k] = K::read_slot(&q_body, &v_body, &slot);
        let bumped = if velocity { &mut v_body } else { &mut q_body };
        bumped[i] = y;
        forces_at_bodies(sys, t, ws);
        ws.bodies[k] = base;
        let mut nonzero = false;
        for i in 0..n {
            col[i] = ws.m_inv[i] * (ws.qe[i] - qe0[i]) / dy;
            nonzero |= col[i] != 0.0;
        }
        if nonzero && !mu.is_empty() {
            for (m, row) in mu.iter_mut().zip(&ws.jac) {
                *m = row.dot(&col);
            }
            ws.schur.solve_again(&mut mu)?;
            ws.subtract_correction(&mu, &mut col);
        }
        for i in 0..n {
            jac[(i, j)] = col[i];
        }
    }
    ws.qe = qe0;
    Ok(())
}

/// Mass-weighted projection of `q` onto `C(q, t) = 0` (a few Newton steps) and of `v`
/// onto `Cq v + Ct = 0`; `Singular` when the constraints cannot be met. `limit` is the
/// position residual the run keeps to ([`crate::simulate::integrate::drift_limits`]).
pub fn project<K: Contacts>(
    sys: &System<K>,
    t: f64,
    q: &mut [f64],
    v: &mut [f64],
    ws: &mut Workspace<K>,
    limit: f64,
) -> Result<(), Singular> {
    if ws.active.is_empty() {
        return Ok(());
    }
    for _ in 0..4 {
        constraints(sys, t, q, v, ws);
        // Near a singular position a residual left along the rank that is being lost
        // would make the velocity projection and the accelerations follow its level
        // set, which bends away from the mechanism's branch there: take it to rounding.
        // A run that keeps its residuals well below POSITION_TOL (atol below 3e-12)
        // asks for as much.
        let tol = if ws.schur.ill_conditioned() || limit < TIGHT_RUN_DRIFT {
            NEAR_SINGULAR_POSITION_TOL
        } else {
            settled(ws, q, v)
        };
        if ws.c.amax() <= tol {
            break;
        }
        let residual = ws.c.clone();
        ws.subtract_solution(residual.as_slice(), q, |q, dx| sys.displace(q, dx))?;
    }
    constraints(sys, t, q, v, ws);
    if ws.c.amax() > 1e3 * settled(ws, q, v) {
        return Err(Singular);
    }
    let residual: Vec<f64> = ws.velocity_residual(v).collect();
    ws.subtract_solution(&residual, v, |v, dv| v.iter_mut().zip(dv).for_each(|(v, d)| *v += d))
}

/// The position residual at which [`project`] stops away from singular positions:
/// [`POSITION_TOL`], or what the rounding of `(q, v)` leaves if that is more (a crank
/// angle of 1900 rad rounds at 2.3e-13 rad, and its driver's row with it).
fn settled<K: Contacts>(ws: &Workspace<K>, q: &[f64], v: &[f64]) -> f64 {
    POSITION_TOL.max(ws.rounding(q, v).0)
}

/// Position residual below which projection stops [m or rad], or the rounding of the
/// coordinates if that is more ([`Workspace::rounding`]).
pub const POSITION_TOL: f64 = 1e-13;
/// Drift limit [m or rad] below which a run asks for its positions projected to rounding
/// ([`project`]): a third of [`POSITION_TOL`], an atol below 3e-12 (the spatial founding
/// case at rtol 1e-11 agrees with the planar engine to 2e-8 so, to 1.2e-7 projected to
/// `POSITION_TOL` or to the rounding estimate).
pub const TIGHT_RUN_DRIFT: f64 = POSITION_TOL / 3.0;
/// Ulps of the state's size that its constraint residuals may carry from rounding alone
/// ([`Workspace::rounding`]): a step rounds each coordinate by half an ulp, and the
/// rounding adds up over the steps between projections.
pub const ROUNDING_ULPS: f64 = 16.0;
/// Position residual below which projection stops near a singular position [m or rad]
/// (see [`project`]): below the rounding of coordinates of metres, so up to 4 Newton
/// steps are taken there.
pub const NEAR_SINGULAR_POSITION_TOL: f64 = 1e-16;

/// Largest position residual and velocity residual of the active rows at `(t, q, v)`.
pub fn violation<K: Contacts>(
    sys: &System<K>,
    t: f64,
    q: &[f64],
    v: &[f64],
    ws: &mut Workspace<K>,
) -> (f64, f64) {
    if ws.active.is_empty() {
        return (0.0, 0.0);
    }
    constraints(sys, t, q, v, ws);
    ws.violation_here(v)
}

/// What the dynamics needs of a body kind's clearance joints: their contact points'
/// count, their loads, and the stiffness their friction brings.
pub trait Contacts: BodyKind + compiled::Compile {
    /// Contact points of all the clearance joints ([`contact::slots`]).
    fn contact_point_count(sys: &System<Self>) -> usize;

    /// Adds every clearance joint's contact loads, the bodies' states given by `state`
    /// and the contact points' discrete states by `contacts`.
    fn add_contact_loads<'a>(
        sys: &System<Self>,
        state: impl Fn(Option<usize>) -> &'a Self::State,
        contacts: &[ContactState],
        loads: &mut Loads,
    ) where
        Self::State: 'a;

    /// Largest rate [1/s] at which a clearance joint's friction damps its slip at `(q, v)`,
    /// over its contact points and their tangents: `|dF_T/dv_t|` times the slip's inverse
    /// mass through the constraints, `g^T (M^-1 - M^-1 Cq^T S^-1 Cq M^-1) g` with `g` the
    /// slip's direction in coordinates.
    /// An explicit step is stable only below about 3.3 divided by it, so this is the
    /// stiffness that sticking friction brings. Uses the constraint Jacobian of the last
    /// evaluation, and the contact points at `(q, v)`, all joints' by slot.
    ///
    /// Rates up to `decides` are not told apart: a point's rate is taken without the
    /// constraints, `g^T M^-1 g`, where that bound is at most `decides`. So the rate is
    /// exact where it exceeds `decides`, and at most `decides` where it does not.
    fn friction_rate(
        sys: &System<Self>,
        q: &[f64],
        v: &[f64],
        points: &[<Self::Clearance as ClearanceJoint>::Point],
        decides: f64,
        ws: &mut Workspace<Self>,
    ) -> f64;
}

impl Contacts for Planar {
    fn contact_point_count(sys: &System) -> usize {
        contact::point_count(&sys.clearances)
    }

    #[inline]
    fn add_contact_loads<'a>(
        sys: &System,
        state: impl Fn(Option<usize>) -> &'a planar_body::BodyState,
        contacts: &[ContactState],
        loads: &mut Loads,
    ) {
        for (_, c, points) in contact::slots(&sys.clearances) {
            let [i, j] = c.parts();
            c.add_to(state(i), state(j), &contacts[points], loads);
        }
    }

    /// Largest rate [1/s] at which a clearance joint's friction damps its slip at `(q, v)`,
    /// over its contact points and their tangents: `|dF_T/dv_t|` times the slip's inverse
    /// mass through the constraints, `g^T (M^-1 - M^-1 Cq^T S^-1 Cq M^-1) g` with `g` the
    /// slip's direction in coordinates.
    /// An explicit step is stable only below about 3.3 divided by it, so this is the
    /// stiffness that sticking friction brings. Uses the constraint Jacobian of the last
    /// evaluation, and the contact points at `(q, v)`, all joints' by slot.
    fn friction_rate(
        sys: &System,
        q: &[f64],
        v: &[f64],
        all: &[ContactPoint],
        decides: f64,
        ws: &mut Workspace,
    ) -> f64 {
        let mut rate = 0.0f64;
        for (_, c, points) in contact::slots(&sys.clearances) {
            let [bearing, journal] = c.parts().map(|b| sys.body_state(b, q, v));
            for (kin, (slip, t)) in all[points.clone()].iter().flat_map(|kin| {
                kin.slip.iter().zip(contact::point::tangents(kin.normal)).map(move |tangent| (kin, tangent))
            }) {
                let contact = ws.contacts[points.start + kin.index];
                let (f_n, _) = c.force(kin, contact.onset_for(kin.penetration_rate));
                let damping = if f_n > 0.0 { c.friction().damping(*slip, f_n) } else { 0.0 };
                if damping == 0.0 {
                    continue;
                }
                // Slip = g . qdot: each body's point velocity along the tangent.
                let mut g = vec![0.0; ws.m_inv.len()];
                let mut along = Loads::new(&sys.layout, &mut g);
                for (body, state, point, sign) in [
                    (kin.on_j.body, &journal, kin.on_j.at, 1.0),
                    (kin.on_i.body, &bearing, kin.on_i.at, -1.0),
                ] {
                    if let Some(g) = along.body(body) {
                        planar_body::add_force(g, point - state.r, t * sign);
                    }
                }
                rate = rate.max(damping * ws.inverse_mass_along(&g, decides / damping));
            }
        }
        rate
    }
}

impl Contacts for Spatial {
    fn contact_point_count(sys: &System<Spatial>) -> usize {
        contact::point_count(&sys.clearances)
    }

    #[inline]
    fn add_contact_loads<'a>(
        sys: &System<Spatial>,
        state: impl Fn(Option<usize>) -> &'a spatial::body::BodyState,
        contacts: &[ContactState],
        loads: &mut Loads,
    ) {
        for (_, c, points) in contact::slots(&sys.clearances) {
            let [i, j] = c.parts();
            c.add_to(state(i), state(j), &contacts[points], loads);
        }
    }

    /// As the planar kind's, the slip taken along two tangents at each contact point
    /// (perpendicular to its normal) at the slip's speed.
    fn friction_rate(
        sys: &System<Spatial>,
        q: &[f64],
        v: &[f64],
        all: &[ContactPoint3],
        decides: f64,
        ws: &mut Workspace<Spatial>,
    ) -> f64 {
        let mut rate = 0.0f64;
        for (_, c, points) in contact::slots(&sys.clearances) {
            let [i, j] = c.parts();
            let (si, sj) = (sys.body_state(i, q, v), sys.body_state(j, q, v));
            for p in &all[points.clone()] {
                let contact = ws.contacts[points.start + p.index];
                let (f_n, _) = c.force(p, contact.onset_for(p.penetration_rate));
                let damping = if f_n > 0.0 { c.friction.damping(p.slip.norm(), f_n) } else { 0.0 };
                if damping == 0.0 {
                    continue;
                }
                let t1 = p
                    .normal
                    .cross(&if p.normal.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() })
                    .normalize();
                for t in [t1, p.normal.cross(&t1)] {
                    let mut g = vec![0.0; ws.m_inv.len()];
                    let mut along = Loads::new(&sys.layout, &mut g);
                    for (point, state, sign) in [(&p.on_j, &sj, 1.0), (&p.on_i, &si, -1.0)] {
                        if let Some(g) = along.body(point.body) {
                            spatial::body::add_force(g, state, &point.arm, &(t * sign));
                        }
                    }
                    rate = rate.max(damping * ws.inverse_mass_along(&g, decides / damping));
                }
            }
        }
        rate
    }
}
