//! A planar body: its coordinates `(x, y, phi)` and velocities `(vx, vy, omega)`, its
//! state as the joints, forces and contacts read it, its diagonal mass, and how a force
//! on it enters the generalised loads. The leaf that the planar joints, forces and
//! contact geometries build on (the body kind itself, [`super::planar::Planar`], gathers
//! them).

use crate::math::{cross, perp, Vec2};
use crate::mechanics::layout::{self, BodyShape};
use crate::model::Body;
use crate::scalar::Real;

/// The planar body kind: positions `(x, y, phi)`, velocities `(vx, vy, omega)`, and a
/// diagonal mass `(m, m, J)`.
pub const PLANAR_BODY: BodyShape = BodyShape { nq: NV, nv: NV };

/// A planar body's channels: its positions, velocities and accelerations, in the order
/// of its coordinates.
pub const CHANNELS: [&str; 3 * NV] = ["x", "y", "angle", "vx", "vy", "omega", "ax", "ay", "alpha"];

/// Velocity coordinates of a planar body: as many as its position coordinates, and as
/// many rows of its own as fix it (a prescribed body, `dynamics::prescribed`).
pub const NV: usize = 3;

/// A constraint row's Jacobian block over one planar body's velocities
/// `dC/d(x, y, phi)`: the dynamics' row storage, the Schur update and the prescribed
/// bodies' blocks are sized by it.
pub type BodyRow = [f64; NV];

/// One planar body's block of a vector over all coordinates, from its address `at`.
#[inline]
pub fn block(x: &[f64], at: usize) -> &BodyRow {
    layout::block(x, at)
}

/// [`block`], to write.
#[inline]
pub fn block_mut(x: &mut [f64], at: usize) -> &mut BodyRow {
    layout::block_mut(x, at)
}

/// A planar body's mass matrix, diagonal: `(m, m, J)`.
#[inline]
pub fn mass_diagonal(mass: f64, inertia: f64) -> BodyRow {
    [mass, mass, inertia]
}

/// The inverse of [`mass_diagonal`], entry by entry.
#[inline]
pub fn inverse_mass(mass: f64, inertia: f64) -> BodyRow {
    [1.0 / mass, 1.0 / mass, 1.0 / inertia]
}

/// Kinetic energy [J] of a planar body with velocities `v = (vx, vy, omega)`.
#[inline]
pub fn kinetic_energy(mass: f64, inertia: f64, v: &[f64]) -> f64 {
    let (vx, vy, w) = (v[0], v[1], v[2]);
    0.5 * mass * (vx * vx + vy * vy) + 0.5 * inertia * w * w
}

/// Work [J] gravity has done on a planar body of mass `mass` at positions `q` since it
/// was at the origin: `m g . r`, the negative of its potential energy.
#[inline]
pub fn gravity_work(mass: f64, gravity: Vec2, q: &[f64]) -> f64 {
    mass * (gravity.x * q[0] + gravity.y * q[1])
}

/// The acceleration of a planar body's centre of mass and its angular acceleration
/// from its accelerations `a = (ax, ay, alpha)`.
#[inline]
pub fn read_acceleration(a: &[f64]) -> (Vec2, f64) {
    (Vec2::new(a[0], a[1]), a[2])
}

/// Adds the weight `m g` of a body of mass `mass` [kg] to its generalized forces (at
/// its centre of mass: no moment).
#[inline]
pub fn add_weight<T: Real>(qe: &mut [T], mass: f64, gravity: Vec2) {
    qe[0] += T::constant(mass * gravity.x);
    qe[1] += T::constant(mass * gravity.y);
}

/// How far the rounding of a planar body's angle moves the point of a row whose block
/// on the body is `entries`, and how much it changes the point's velocity, given the
/// body's positions `q` and velocities `v`: `|s| |phi|` and `|s| |phi| |omega|`, with
/// `|s|` the point's distance from the body's frame read off the row as its angle
/// entry. `None` for a row that holds no position of the body (an angle row).
#[inline]
pub fn rotation_reach(entries: &BodyRow, q: &[f64], v: &[f64]) -> Option<(f64, f64)> {
    (entries[0] != 0.0 || entries[1] != 0.0).then(|| {
        let reach = entries[2].abs() * q[2].abs();
        (reach, reach * v[2].abs())
    })
}

/// Position and velocity of one body (the ground: all zero), with the sine and cosine
/// of its angle computed once: every joint row and force on the body rotates by them.
#[derive(Debug, Clone, Copy)]
pub struct BodyState<T: Real = f64> {
    /// Centre of mass [m].
    pub r: Vec2<T>,
    /// Angle [rad]; read by [`BodyState::phi`], set only with its sine and cosine.
    phi: T,
    /// Velocity of the centre of mass [m/s].
    pub v: Vec2<T>,
    /// Angular velocity [rad/s].
    pub omega: T,
    sin: T,
    cos: T,
}

impl BodyState {
    /// The ground: at rest at the origin, angle zero.
    pub const GROUND: BodyState = BodyState {
        r: Vec2::new(0.0, 0.0),
        phi: 0.0,
        v: Vec2::new(0.0, 0.0),
        omega: 0.0,
        sin: 0.0,
        cos: 1.0,
    };
}

impl<T: Real> BodyState<T> {
    /// The ground, in numbers of `T`.
    pub fn ground() -> Self {
        let zero = T::constant(0.0);
        BodyState {
            r: Vec2::new(zero, zero),
            phi: zero,
            v: Vec2::new(zero, zero),
            omega: zero,
            sin: zero,
            cos: T::constant(1.0),
        }
    }

    /// The state at centre `r`, angle `phi`, velocity `v`, angular velocity `omega`.
    pub fn new(r: Vec2<T>, phi: T, v: Vec2<T>, omega: T) -> Self {
        let (sin, cos) = phi.sin_cos();
        BodyState { r, phi, v, omega, sin, cos }
    }

    /// The state of a planar body from its positions `q = (x, y, phi)` and velocities
    /// `v = (vx, vy, omega)`.
    #[inline]
    pub fn read(q: &[T; NV], v: &[T; NV]) -> Self {
        BodyState::new(Vec2::new(q[0], q[1]), q[2], Vec2::new(v[0], v[1]), v[2])
    }

    /// Angle [rad].
    #[inline]
    pub fn phi(&self) -> T {
        self.phi
    }

    /// `A(phi) s`: a body-frame vector in global axes.
    #[inline]
    pub fn rotate(&self, s: Vec2) -> Vec2<T> {
        Vec2::new(self.cos * s.x - self.sin * s.y, self.sin * s.x + self.cos * s.y)
    }

    /// Velocity of the body's point at global `p`: `v + omega x (p - r)`.
    #[inline]
    pub fn velocity_at(&self, p: Vec2<T>) -> Vec2<T> {
        self.v + perp(p - self.r) * self.omega
    }
}

/// A planar body's positions and velocities at its placement in the model: the
/// starting guess of assembly.
pub fn placement_coordinates(b: &Body) -> ([f64; 3], [f64; 3]) {
    ([b.position[0], b.position[1], b.angle], [b.velocity[0], b.velocity[1], b.omega])
}

/// Moves a planar body's positions `q` by `dv`, a displacement in its velocity
/// coordinates: they are the same coordinates, so it adds.
#[inline]
pub fn displace(q: &mut [f64], dv: &[f64]) {
    q.iter_mut().zip(dv).for_each(|(q, d)| *q += d);
}

/// Whether velocity coordinate `d` of a planar body is its rotation (`omega`).
#[inline]
pub fn is_rotation(d: usize) -> bool {
    d == 2
}

/// Adds force `f` [N], whose arm from the centre of mass is `arm` (global axes), to a
/// planar body's generalized forces `qe = (Fx, Fy, M)`.
#[inline]
pub fn add_force<T: Real>(qe: &mut [T], arm: Vec2<T>, f: Vec2<T>) {
    qe[0] += f.x;
    qe[1] += f.y;
    qe[2] += cross(arm, f);
}

/// Adds torque `tau` [N m] to a planar body's generalized forces.
#[inline]
pub fn add_torque<T: Real>(qe: &mut [T], tau: T) {
    qe[2] += tau;
}

impl Default for BodyState {
    /// The ground: at rest at the origin, angle zero.
    fn default() -> Self {
        BodyState::GROUND
    }
}
