//! Constraint equations of planar joints and drivers, one scalar row at a time, with
//! analytic Jacobians and acceleration right-hand sides (gamma).
//!
//! Every row is written `C(q, t) = 0`; its time derivatives give `Cq qd + Ct = 0` and
//! `Cq qdd = gamma`, with `gamma = -(Cq qd)_q qd - 2 Cqt qd - Ctt` (Nikravesh 1988).

use crate::math::{cross, perp, Vec2};
use crate::mechanics::contact::planar_clearance::PlanarClearance;
use crate::mechanics::drivers::Motion;
use crate::mechanics::forces::ForceElement;
use crate::mechanics::kind::{self, BodyKind};
use crate::mechanics::layout::{BodyShape, BodySlot};
use crate::model::Body;

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
    x[at..at + NV].try_into().expect("a block of NV entries")
}

/// [`block`], to write.
#[inline]
pub fn block_mut(x: &mut [f64], at: usize) -> &mut BodyRow {
    (&mut x[at..at + NV]).try_into().expect("a block of NV entries")
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
pub fn add_weight(qe: &mut [f64], mass: f64, gravity: Vec2) {
    qe[0] += mass * gravity.x;
    qe[1] += mass * gravity.y;
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
pub struct BodyState {
    /// Centre of mass [m].
    pub r: Vec2,
    /// Angle [rad]; read by [`BodyState::phi`], set only with its sine and cosine.
    phi: f64,
    /// Velocity of the centre of mass [m/s].
    pub v: Vec2,
    /// Angular velocity [rad/s].
    pub omega: f64,
    sin: f64,
    cos: f64,
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

    /// The state at centre `r`, angle `phi`, velocity `v`, angular velocity `omega`.
    pub fn new(r: Vec2, phi: f64, v: Vec2, omega: f64) -> Self {
        let (sin, cos) = phi.sin_cos();
        BodyState { r, phi, v, omega, sin, cos }
    }

    /// The state of a planar body from its positions `q = (x, y, phi)` and velocities
    /// `v = (vx, vy, omega)`.
    #[inline]
    pub fn read(q: &BodyRow, v: &BodyRow) -> Self {
        BodyState::new(Vec2::new(q[0], q[1]), q[2], Vec2::new(v[0], v[1]), v[2])
    }

    /// Angle [rad].
    #[inline]
    pub fn phi(&self) -> f64 {
        self.phi
    }

    /// `A(phi) s`: a body-frame vector in global axes.
    #[inline]
    pub fn rotate(&self, s: Vec2) -> Vec2 {
        Vec2::new(self.cos * s.x - self.sin * s.y, self.sin * s.x + self.cos * s.y)
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
pub fn add_force(qe: &mut [f64], arm: Vec2, f: Vec2) {
    qe[0] += f.x;
    qe[1] += f.y;
    qe[2] += cross(arm, f);
}

/// Adds torque `tau` [N m] to a planar body's generalized forces.
#[inline]
pub fn add_torque(qe: &mut [f64], tau: f64) {
    qe[2] += tau;
}

/// The planar body kind ([`BodyKind`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Planar;

impl BodyKind for Planar {
    const SHAPE: BodyShape = PLANAR_BODY;
    const IDENTITY_RATE: bool = true;
    const CHANNELS: &'static [&'static str] = &CHANNELS;
    type Row = BodyRow;
    type State = BodyState;
    type Vector = Vec2;
    type Inertia = f64;
    type JointKind = crate::model::JointKind;
    type RowKind = RowKind;
    type Force = ForceElement;
    type Clearance = PlanarClearance;

    #[inline]
    fn ground() -> BodyState {
        BodyState::GROUND
    }

    #[inline]
    fn read(q: &[f64], v: &[f64]) -> BodyState {
        BodyState::read(block(q, 0), block(v, 0))
    }

    #[inline]
    fn read_slot(q: &[f64], v: &[f64], slot: &BodySlot) -> BodyState {
        BodyState::read(block(q, slot.q_at), block(v, slot.v_at))
    }

    #[inline]
    fn eval(row: &RowKind, bi: &BodyState, bj: &BodyState, motion: Motion) -> RowEval {
        row.eval(bi, bj, motion)
    }

    #[inline]
    fn mass_diagonal(mass: f64, inertia: &f64) -> BodyRow {
        mass_diagonal(mass, *inertia)
    }

    #[inline]
    fn inverse_mass(mass: f64, inertia: &f64) -> BodyRow {
        inverse_mass(mass, *inertia)
    }

    #[inline]
    fn add_weight(qe: &mut [f64], mass: f64, gravity: &Vec2) {
        add_weight(qe, mass, *gravity)
    }

    #[inline]
    fn displace(q: &mut [f64], dv: &[f64]) {
        displace(q, dv)
    }

    #[inline]
    fn is_rotation(d: usize) -> bool {
        is_rotation(d)
    }

    #[inline]
    fn rotation_reach(entries: &BodyRow, q: &[f64], v: &[f64]) -> Option<(f64, f64)> {
        rotation_reach(entries, q, v)
    }

    #[inline]
    fn position_rate(_q: &[f64], v: &[f64], out: &mut [f64]) {
        out.copy_from_slice(v)
    }

    fn rate_block(_q: &[f64], mut put: impl FnMut(usize, usize, f64)) {
        (0..NV).for_each(|d| put(d, d, 1.0))
    }

    fn norm(v: &Vec2) -> f64 {
        v.norm()
    }

    #[inline]
    fn kinetic_energy(mass: f64, inertia: &f64, v: &[f64]) -> f64 {
        kinetic_energy(mass, *inertia, v)
    }

    #[inline]
    fn gravity_work(mass: f64, gravity: &Vec2, q: &[f64]) -> f64 {
        gravity_work(mass, *gravity, q)
    }
}

impl Default for BodyState {
    /// The ground: at rest at the origin, angle zero.
    fn default() -> Self {
        BodyState::GROUND
    }
}

/// One scalar constraint equation between body i and body j.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RowKind {
    /// Component `axis` (0 = x, 1 = y) of `P_i - P_j`: half of a revolute or fixed joint.
    Coincide {
        /// 0 for x, 1 for y.
        axis: usize,
        /// Point on body i, body frame [m].
        s_i: Vec2,
        /// Point on body j, body frame [m].
        s_j: Vec2,
    },
    /// `phi_j - phi_i - offset - theta(t)`: fixed relative angle (prismatic, fixed
    /// joints) or a rotation driver.
    Angle {
        /// Relative angle at t = 0 [rad].
        offset: f64,
    },
    /// `(A_i w) . (P_j - P_i) - offset - theta(t)`: `P_j` stays on a line of body i
    /// (w is the line's normal), or a translation driver (w is the sliding axis).
    Along {
        /// Point on body i, body frame [m].
        s_i: Vec2,
        /// Unit direction in the frame of body i.
        w: Vec2,
        /// Point on body j, body frame [m].
        s_j: Vec2,
        /// Value at t = 0 [m].
        offset: f64,
    },
}

/// A planar row evaluated at one state.
pub type RowEval = kind::RowEval<BodyRow>;

impl RowKind {
    /// Evaluates the row; `motion` is the driver's prescribed motion (zero if none).
    pub fn eval(&self, bi: &BodyState, bj: &BodyState, motion: Motion) -> RowEval {
        match *self {
            RowKind::Coincide { axis, s_i, s_j } => {
                let a_i = bi.rotate(s_i);
                let a_j = bj.rotate(s_j);
                let c = bi.r + a_i - bj.r - a_j;
                let (pi, pj) = (perp(a_i), perp(a_j));
                let g = a_i * bi.omega.powi(2) - a_j * bj.omega.powi(2);
                let mut jac_i = [0.0; 3];
                let mut jac_j = [0.0; 3];
                jac_i[axis] = 1.0;
                jac_j[axis] = -1.0;
                jac_i[2] = pi[axis];
                jac_j[2] = -pj[axis];
                RowEval { c: c[axis], jac_i, jac_j, ct: 0.0, gamma: g[axis] }
            }
            RowKind::Angle { offset } => RowEval {
                c: bj.phi - bi.phi - offset - motion.position,
                jac_i: [0.0, 0.0, -1.0],
                jac_j: [0.0, 0.0, 1.0],
                ct: -motion.speed,
                gamma: motion.acceleration,
            },
            RowKind::Along { s_i, w, s_j, offset } => {
                let wg = bi.rotate(w);
                let a_i = bi.rotate(s_i);
                let a_j = bj.rotate(s_j);
                let d = bj.r + a_j - bi.r - a_i;
                let d_dot = bj.v + perp(a_j) * bj.omega - bi.v - perp(a_i) * bi.omega;
                let (wi, wj) = (bi.omega, bj.omega);
                let gamma = motion.acceleration + wi * wi * wg.dot(&d) - 2.0 * wi * perp(wg).dot(&d_dot)
                    + wj * wj * wg.dot(&a_j)
                    - wi * wi * wg.dot(&a_i);
                RowEval {
                    c: wg.dot(&d) - offset - motion.position,
                    jac_i: [-wg.x, -wg.y, perp(wg).dot(&d) - wg.dot(&perp(a_i))],
                    jac_j: [wg.x, wg.y, wg.dot(&perp(a_j))],
                    ct: -motion.speed,
                    gamma,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(x: f64, y: f64, phi: f64, vx: f64, vy: f64, w: f64) -> BodyState {
        BodyState::new(Vec2::new(x, y), phi, Vec2::new(vx, vy), w)
    }

    /// Advances both bodies along their velocities (and the driver along its speed).
    fn moved(b: &BodyState, e: f64) -> BodyState {
        BodyState::new(b.r + b.v * e, b.phi + b.omega * e, b.v, b.omega)
    }

    /// Checks jac against finite differences of C, ct against dC/dt, and gamma against
    /// `-(d/dt (Cq qd))` at fixed qd, the definition of docs/physics.md section 1.
    fn check(kind: RowKind, bi: BodyState, bj: BodyState, motion: Motion) {
        let ev = kind.eval(&bi, &bj, motion);
        let e = 1e-6;
        for k in 0..3 {
            let perturb = |b: &BodyState, s: f64| {
                let (mut r, mut phi) = (b.r, b.phi);
                match k {
                    0 => r.x += s,
                    1 => r.y += s,
                    _ => phi += s,
                }
                BodyState::new(r, phi, b.v, b.omega)
            };
            let di = (kind.eval(&perturb(&bi, e), &bj, motion).c
                - kind.eval(&perturb(&bi, -e), &bj, motion).c)
                / (2.0 * e);
            let dj = (kind.eval(&bi, &perturb(&bj, e), motion).c
                - kind.eval(&bi, &perturb(&bj, -e), motion).c)
                / (2.0 * e);
            assert!((di - ev.jac_i[k]).abs() < 1e-8, "{kind:?} jac_i[{k}] {di} vs {}", ev.jac_i[k]);
            assert!((dj - ev.jac_j[k]).abs() < 1e-8, "{kind:?} jac_j[{k}] {dj} vs {}", ev.jac_j[k]);
        }
        // Cq qd + Ct is the total time derivative of C along the motion.
        let shifted = |s: f64| Motion { position: motion.position + motion.speed * s, ..motion };
        let dcdt = (kind.eval(&moved(&bi, e), &moved(&bj, e), shifted(e)).c
            - kind.eval(&moved(&bi, -e), &moved(&bj, -e), shifted(-e)).c)
            / (2.0 * e);
        let cq_qd = |ev: &RowEval, bi: &BodyState, bj: &BodyState| {
            ev.jac_i[0] * bi.v.x
                + ev.jac_i[1] * bi.v.y
                + ev.jac_i[2] * bi.omega
                + ev.jac_j[0] * bj.v.x
                + ev.jac_j[1] * bj.v.y
                + ev.jac_j[2] * bj.omega
        };
        assert!((dcdt - (cq_qd(&ev, &bi, &bj) + ev.ct)).abs() < 1e-7, "{kind:?} velocity equation");
        // gamma = -(Cq qd)_q qd + Ctt-part: differentiate Cq qd along qd, then add the
        // driver acceleration that Ctt contributes.
        let plus = kind.eval(&moved(&bi, e), &moved(&bj, e), motion);
        let minus = kind.eval(&moved(&bi, -e), &moved(&bj, -e), motion);
        let quad = (cq_qd(&plus, &bi, &bj) - cq_qd(&minus, &bi, &bj)) / (2.0 * e);
        let expected = -quad + motion.acceleration;
        assert!(
            (ev.gamma - expected).abs() < 1e-6 * (1.0 + expected.abs()),
            "{kind:?} gamma {} vs {expected}",
            ev.gamma
        );
    }

    #[test]
    fn every_row_kind_matches_finite_differences() {
        let bi = state(0.3, -0.2, 0.7, 1.1, -0.4, 2.3);
        let bj = state(-0.1, 0.5, -1.2, -0.6, 0.9, -3.1);
        let motion = Motion { position: 0.4, speed: 1.7, acceleration: -2.9 };
        let s_i = Vec2::new(0.12, -0.05);
        let s_j = Vec2::new(-0.2, 0.07);
        for axis in 0..2 {
            check(
                RowKind::Coincide { axis, s_i, s_j },
                bi,
                bj,
                Motion { position: 0.0, speed: 0.0, acceleration: 0.0 },
            );
        }
        check(RowKind::Angle { offset: 0.3 }, bi, bj, motion);
        let w = Vec2::new(0.6, 0.8);
        check(RowKind::Along { s_i, w, s_j, offset: 0.1 }, bi, bj, motion);
        // With the ground as body i (at rest at the origin).
        check(RowKind::Along { s_i, w, s_j, offset: 0.0 }, BodyState::default(), bj, motion);
    }
}
