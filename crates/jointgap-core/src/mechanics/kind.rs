//! The body kind as a type: everything the system, the dynamics and the run need to know
//! about what a body's coordinates mean, so that they are written once and compiled for
//! planar and for spatial models (docs/architecture.md, "Bodies and their coordinates").
//! A model is planar or spatial as a whole; each kind's engine is the same code
//! instantiated for it, so the planar one keeps its three-entry blocks and its speed.

use std::fmt::Debug;

use crate::mechanics::contact::ClearanceJoint;
use crate::mechanics::drivers::Motion;
use crate::mechanics::layout::{BodyShape, BodySlot, Loads};

/// A constraint row's Jacobian block over one body's velocities: `[f64; NV]`.
pub trait Block:
    Copy + Default + Debug + PartialEq + Send + Sync + 'static + AsRef<[f64]> + AsMut<[f64]>
{
    /// The block of a vector over all velocities at address `at`.
    fn of(x: &[f64], at: usize) -> &Self;
    /// [`Block::of`], to write.
    fn of_mut(x: &mut [f64], at: usize) -> &mut Self;
    /// The entries times `w`'s, entry by entry.
    fn scaled(&self, w: &Self) -> Self;
}

impl<const N: usize> Block for [f64; N]
where
    [f64; N]: Default,
{
    #[inline(always)]
    fn of(x: &[f64], at: usize) -> &Self {
        x[at..at + N].try_into().expect("a block of a body's velocities")
    }

    #[inline(always)]
    fn of_mut(x: &mut [f64], at: usize) -> &mut Self {
        (&mut x[at..at + N]).try_into().expect("a block of a body's velocities")
    }

    #[inline(always)]
    fn scaled(&self, w: &Self) -> Self {
        std::array::from_fn(|d| self[d] * w[d])
    }
}

/// A row evaluated at one state: residual, Jacobian blocks and right-hand sides.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RowEval<R, T = f64> {
    /// Residual `C`.
    pub c: T,
    /// `dC/dv_i` over body i's velocity coordinates.
    pub jac_i: R,
    /// `dC/dv_j` over body j's.
    pub jac_j: R,
    /// `dC/dt`.
    pub ct: T,
    /// Acceleration right-hand side: `Cq qdd = gamma`.
    pub gamma: T,
}

/// A force element of a body kind: adds its loads to the bodies, and says the power it
/// feeds in and dissipates, and the energy it stores.
pub trait ForceLaw<S> {
    /// Times where its input has a corner.
    fn corners(&self) -> Vec<f64>;
    /// Adds its loads at time `t`, the bodies' states given by `state`.
    fn add_to(&self, t: f64, state: impl Fn(Option<usize>) -> S, qe: &mut Loads);
    /// `(power fed in, power dissipated)` [W].
    fn power(&self, t: f64, state: impl Fn(Option<usize>) -> S) -> (f64, f64);
    /// Energy stored [J].
    fn potential_energy(&self, state: impl Fn(Option<usize>) -> S) -> f64;
}

/// A body kind: the meaning of one body's coordinates and the vocabulary of the
/// elements written in them.
pub trait BodyKind: Copy + Debug + Default + Send + Sync + 'static {
    /// Position and velocity coordinates per body.
    const SHAPE: BodyShape;
    /// Whether positions move as their velocities (`q' = v`); else `q' = G(q) v`.
    const IDENTITY_RATE: bool;
    /// A body's output channels: its positions, velocities and accelerations, in the
    /// order of its coordinates.
    const CHANNELS: &'static [&'static str];
    /// A row's block over one body's velocities.
    type Row: Block;
    /// One body's state, its rotation computed once.
    type State: Copy + Debug + Send + Sync;
    /// A vector of the kind's space (a point, a force, gravity).
    type Vector: Copy + Debug + PartialEq + Send + Sync;
    /// A body's rotational inertia about its centre of mass.
    type Inertia: Copy + Debug + PartialEq + Send + Sync;
    /// The kinds of joint of a model of this kind.
    type JointKind: Copy + Debug + PartialEq + Send + Sync;
    /// One scalar constraint equation between two bodies.
    type RowKind: Copy + Debug + PartialEq + Send + Sync;
    /// A force element.
    type Force: ForceLaw<Self::State> + Debug + Clone + Send + Sync;
    /// A clearance joint.
    type Clearance: ClearanceJoint<State = Self::State> + Debug + Clone + Send + Sync;

    /// The ground's state.
    fn ground() -> Self::State;
    /// A body's state from its positions and velocities.
    fn read(q: &[f64], v: &[f64]) -> Self::State;
    /// The state of the body in `slot` from the positions and velocities of all bodies.
    #[inline]
    fn read_slot(q: &[f64], v: &[f64], slot: &BodySlot) -> Self::State {
        Self::read(&q[slot.q()], &v[slot.v()])
    }
    /// Evaluates a constraint row.
    fn eval(row: &Self::RowKind, bi: &Self::State, bj: &Self::State, motion: Motion) -> RowEval<Self::Row>;
    /// The body's mass matrix, diagonal.
    fn mass_diagonal(mass: f64, inertia: &Self::Inertia) -> Self::Row;
    /// Its inverse, entry by entry.
    fn inverse_mass(mass: f64, inertia: &Self::Inertia) -> Self::Row {
        let mut m = Self::mass_diagonal(mass, inertia);
        m.as_mut().iter_mut().for_each(|x| *x = 1.0 / *x);
        m
    }
    /// Adds the weight `m g` to a body's generalized forces.
    fn add_weight(qe: &mut [f64], mass: f64, gravity: &Self::Vector);
    /// Adds the inertial loads that a body's own motion makes in its coordinates (the
    /// gyroscopic moment of a spatial body; none for a planar one).
    #[inline]
    fn add_inertial(_qe: &mut [f64], _inertia: &Self::Inertia, _state: &Self::State) {}
    /// Moves a body's positions by `dv`, a displacement in its velocity coordinates.
    fn displace(q: &mut [f64], dv: &[f64]);
    /// Whether velocity coordinate `d` of a body is a rotation.
    fn is_rotation(d: usize) -> bool;
    /// How far the rounding of a body's orientation moves the point of a row whose block
    /// on the body is `entries`, and its velocity (see `planar_body::rotation_reach`).
    fn rotation_reach(entries: &Self::Row, q: &[f64], v: &[f64]) -> Option<(f64, f64)>;
    /// `q' = G(q) v` for one body.
    fn position_rate(q: &[f64], v: &[f64], out: &mut [f64]);
    /// `q'' = G(q) a + (dG/dt) v` of one body at positions `q`, velocities `v` and
    /// accelerations `a` (the dense output's positions; `a` itself where `G = I`).
    #[inline]
    fn position_acceleration(_q: &[f64], _v: &[f64], a: &[f64], out: &mut [f64]) {
        out.copy_from_slice(a)
    }
    /// `G(q)` of one body (`nq` rows, `nv` columns), each entry that is not zero given
    /// to `put(row, column, value)`.
    fn rate_block(q: &[f64], put: impl FnMut(usize, usize, f64));
    /// Brings a body's positions back to their manifold (a unit quaternion); whether it
    /// changed them.
    #[inline]
    fn normalise(_q: &mut [f64]) -> bool {
        false
    }
    /// The length of a vector.
    fn norm(v: &Self::Vector) -> f64;
    /// Kinetic energy [J] of a body with velocities `v`.
    fn kinetic_energy(mass: f64, inertia: &Self::Inertia, v: &[f64]) -> f64;
    /// Work [J] gravity has done on a body at positions `q` since it was at the origin.
    fn gravity_work(mass: f64, gravity: &Self::Vector, q: &[f64]) -> f64;
}
