//! Constraint equations of planar joints and drivers, one scalar row at a time, with
//! analytic Jacobians and acceleration right-hand sides (gamma).
//!
//! Every row is written `C(q, t) = 0`; its time derivatives give `Cq qd + Ct = 0` and
//! `Cq qdd = gamma`, with `gamma = -(Cq qd)_q qd - 2 Cqt qd - Ctt` (Nikravesh 1988).

use crate::math::{perp, Vec2};
use crate::mechanics::contact::planar_clearance::PlanarClearance;
use crate::mechanics::drivers::Motion;
use crate::mechanics::forces::ForceElement;
use crate::mechanics::kind::{self, BodyKind};
use crate::mechanics::layout::{BodyShape, BodySlot};
use crate::mechanics::planar_body::{
    add_weight, block, displace, gravity_work, inverse_mass, is_rotation, kinetic_energy, mass_diagonal,
    rotation_reach, BodyRow, BodyState, CHANNELS, NV, PLANAR_BODY,
};
use crate::scalar::Real;

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
pub type RowEval<T = f64> = kind::RowEval<[T; NV], T>;

impl RowKind {
    /// Evaluates the row; `motion` is the driver's prescribed motion (zero if none).
    pub fn eval<T: Real>(&self, bi: &BodyState<T>, bj: &BodyState<T>, motion: Motion<T>) -> RowEval<T> {
        let (zero, one) = (T::constant(0.0), T::constant(1.0));
        match *self {
            RowKind::Coincide { axis, s_i, s_j } => {
                let a_i = bi.rotate(s_i);
                let a_j = bj.rotate(s_j);
                let c = bi.r + a_i - bj.r - a_j;
                let (pi, pj) = (perp(a_i), perp(a_j));
                let g = a_i * (bi.omega * bi.omega) - a_j * (bj.omega * bj.omega);
                let mut jac_i = [zero; 3];
                let mut jac_j = [zero; 3];
                jac_i[axis] = one;
                jac_j[axis] = -one;
                jac_i[2] = pi[axis];
                jac_j[2] = -pj[axis];
                RowEval { c: c[axis], jac_i, jac_j, ct: zero, gamma: g[axis] }
            }
            RowKind::Angle { offset } => RowEval {
                c: bj.phi() - bi.phi() - offset - motion.position,
                jac_i: [zero, zero, -one],
                jac_j: [zero, zero, one],
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
                let gamma = motion.acceleration + wi * wi * wg.dot(&d) - wi * 2.0 * perp(wg).dot(&d_dot)
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
        BodyState::new(b.r + b.v * e, b.phi() + b.omega * e, b.v, b.omega)
    }

    /// Checks jac against finite differences of C, ct against dC/dt, and gamma against
    /// `-(d/dt (Cq qd))` at fixed qd, the definition of docs/physics.md section 1.
    fn check(kind: RowKind, bi: BodyState, bj: BodyState, motion: Motion) {
        let ev = kind.eval(&bi, &bj, motion);
        let e = 1e-6;
        for k in 0..3 {
            let perturb = |b: &BodyState, s: f64| {
                let (mut r, mut phi) = (b.r, b.phi());
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
