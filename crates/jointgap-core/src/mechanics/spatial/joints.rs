//! Constraint rows of spatial ideal joints and drivers, one scalar row at a time, with
//! analytic Jacobians and acceleration right-hand sides, and the set of rows each joint
//! kind adds (Nikravesh 1988, chapter 11; Haug 1989, chapter 9; docs/spatial-joints.md).
//!
//! Every row is written `C(q, t) = 0`; its time derivatives give `Cq v + Ct = 0` and
//! `Cq vdot = gamma`, with `gamma = -(d/dt Cq) v - 2 Cqt v - Ctt`. A row's Jacobian block
//! over one body is `[dC/dr, dC/dpi']`: `dr` a displacement of the centre of mass in
//! global axes and `dpi'` a small rotation in the body's own frame, the pair that the
//! body's velocities `(v, w')` multiply. Each body-frame vector `s` turns as
//! `d(A s) = A (dpi' x s)`, so a term `b . d(A s)` gives the block `s x (A^T b)`.

use std::f64::consts::{PI, TAU};

use crate::mechanics::drivers::Motion;
use crate::mechanics::spatial::body::{BodyRow, BodyState, Vec3};

/// One scalar constraint equation between body i and body j. Vectors and points are in
/// the frame of the body they belong to (for the ground: global).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SpatialRowKind {
    /// Component `axis` (0 = x, 1 = y, 2 = z, global) of `P_i - P_j`: three of them hold
    /// two points together (a spherical joint).
    Coincide {
        /// 0 for x, 1 for y, 2 for z.
        axis: usize,
        /// Point on body i [m].
        s_i: Vec3,
        /// Point on body j [m].
        s_j: Vec3,
    },
    /// `(A_i a_i) . (A_j a_j)`: a vector of body i stays perpendicular to a vector of
    /// body j (Nikravesh's dot-1 row).
    Perpendicular {
        /// Vector on body i.
        a_i: Vec3,
        /// Vector on body j.
        a_j: Vec3,
    },
    /// `(A_i a_i) . (P_j - P_i) - offset - theta(t)`: the point of body j keeps its
    /// distance `offset` from a plane of body i whose normal is `a_i` (Nikravesh's dot-2
    /// row), or a translation driver along `a_i` (unit, then the distance is in metres).
    Along {
        /// Direction on body i.
        a_i: Vec3,
        /// Point on body i [m].
        s_i: Vec3,
        /// Point on body j [m].
        s_j: Vec3,
        /// Value at t = 0 [m].
        offset: f64,
    },
    /// `wrap(theta - offset - theta(t))`: the angle `theta` body j has turned about
    /// body i's `axis`, from body i's `ref_i` to body j's `ref_j` (each a unit vector
    /// perpendicular to the joint's axis on its body), measured by `atan2` and wrapped to
    /// (-pi, pi] so the residual stays continuous through a whole turn; a rotation
    /// driver or a joint's initial angle.
    Rotation {
        /// Unit axis on body i.
        axis: Vec3,
        /// Unit reference vector on body i, perpendicular to `axis`.
        ref_i: Vec3,
        /// Unit reference vector on body j, perpendicular to the joint's axis on body j.
        ref_j: Vec3,
        /// Value at t = 0 [rad].
        offset: f64,
    },
}

/// A row evaluated at one state: residual, Jacobian blocks and right-hand sides.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SpatialRowEval {
    /// Residual `C`.
    pub c: f64,
    /// `dC/d(r_i, pi'_i)`.
    pub jac_i: BodyRow,
    /// `dC/d(r_j, pi'_j)`.
    pub jac_j: BodyRow,
    /// `dC/dt`.
    pub ct: f64,
    /// Acceleration right-hand side: `Cq vdot = gamma`.
    pub gamma: f64,
}

/// A Jacobian block from its translation part `t` (global) and its rotation part `b`
/// (body frame).
#[inline]
fn block(t: Vec3, b: Vec3) -> BodyRow {
    [t.x, t.y, t.z, b.x, b.y, b.z]
}

/// An angle wrapped to (-pi, pi].
#[inline]
fn wrap(angle: f64) -> f64 {
    PI - (PI - angle).rem_euclid(TAU)
}

impl SpatialRowKind {
    /// Evaluates the row; `motion` is the driver's prescribed motion (zero if none; the
    /// point and perpendicularity rows take none).
    pub fn eval(&self, bi: &BodyState, bj: &BodyState, motion: Motion) -> SpatialRowEval {
        // Global angular velocities: constant along a motion at fixed (v, w'), since
        // d/dt (A w') = A (w' x w') = 0.
        let (wi, wj) = (bi.omega_global(), bj.omega_global());
        match *self {
            SpatialRowKind::Coincide { axis, s_i, s_j } => {
                let (si, sj) = (bi.rotate(&s_i), bj.rotate(&s_j));
                let e = Vec3::ith(axis, 1.0);
                let c = bi.r + si - bj.r - sj;
                // Centripetal accelerations of the two points at fixed angular velocity.
                let g = wj.cross(&wj.cross(&sj)) - wi.cross(&wi.cross(&si));
                SpatialRowEval {
                    c: c[axis],
                    jac_i: block(e, bi.a.tr_mul(&si.cross(&e))),
                    jac_j: block(-e, -bj.a.tr_mul(&sj.cross(&e))),
                    ct: 0.0,
                    gamma: g[axis],
                }
            }
            SpatialRowKind::Perpendicular { a_i, a_j } => {
                let (gi, gj) = (bi.rotate(&a_i), bj.rotate(&a_j));
                let (gi_dot, gj_dot) = (wi.cross(&gi), wj.cross(&gj));
                let quad =
                    gj.dot(&wi.cross(&gi_dot)) + 2.0 * gi_dot.dot(&gj_dot) + gi.dot(&wj.cross(&gj_dot));
                SpatialRowEval {
                    c: gi.dot(&gj),
                    jac_i: block(Vec3::zeros(), a_i.cross(&bi.a.tr_mul(&gj))),
                    jac_j: block(Vec3::zeros(), a_j.cross(&bj.a.tr_mul(&gi))),
                    ct: 0.0,
                    gamma: -quad,
                }
            }
            SpatialRowKind::Along { a_i, s_i, s_j, offset } => {
                let gi = bi.rotate(&a_i);
                let (si, sj) = (bi.rotate(&s_i), bj.rotate(&s_j));
                let pj = bj.r + sj;
                let d = pj - bi.r - si;
                let gi_dot = wi.cross(&gi);
                let d_dot = bj.v + wj.cross(&sj) - bi.v - wi.cross(&si);
                let d_ddot = wj.cross(&wj.cross(&sj)) - wi.cross(&wi.cross(&si));
                let quad = wi.cross(&gi_dot).dot(&d) + 2.0 * gi_dot.dot(&d_dot) + gi.dot(&d_ddot);
                SpatialRowEval {
                    c: gi.dot(&d) - offset - motion.position,
                    jac_i: block(-gi, a_i.cross(&bi.a.tr_mul(&(pj - bi.r)))),
                    jac_j: block(gi, s_j.cross(&bj.a.tr_mul(&gi))),
                    ct: -motion.speed,
                    gamma: motion.acceleration - quad,
                }
            }
            SpatialRowKind::Rotation { axis, ref_i, ref_j, offset } => {
                // Body i's right-handed triad (ref, axis x ref, axis) and body j's
                // reference vector g, in global axes: theta = atan2(g . f, g . e).
                let u = bi.rotate(&axis);
                let e = bi.rotate(&ref_i);
                let f = u.cross(&e);
                let g = bj.rotate(&ref_j);
                let (x, y, z) = (g.dot(&e), g.dot(&f), g.dot(&u));
                // dtheta = h . (dphi_j - dphi_i) (global small rotations), with
                // h = u - z p / rho, p = x e + y f the part of g across the axis and
                // rho = |p|^2: h is the axis itself wherever g is across it, that is
                // wherever the joint's other rows hold.
                let p = g - u * z;
                let rho = x * x + y * y;
                let h = u - p * (z / rho);
                // d/dt h at fixed (v, w'): e, f, u turn with body i, g with body j.
                let rel = wj - wi;
                let z_dot = rel.dot(&g.cross(&u));
                let u_dot = wi.cross(&u);
                let p_dot = wj.cross(&g) - u * z_dot - u_dot * z;
                let rho_dot = -2.0 * z * z_dot;
                let h_dot = u_dot - p * (z_dot / rho) - p_dot * (z / rho) + p * (z * rho_dot / (rho * rho));
                SpatialRowEval {
                    c: wrap(y.atan2(x) - offset - motion.position),
                    jac_i: block(Vec3::zeros(), -bi.a.tr_mul(&h)),
                    jac_j: block(Vec3::zeros(), bj.a.tr_mul(&h)),
                    ct: -motion.speed,
                    gamma: motion.acceleration - h_dot.dot(&rel),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanics::spatial::body::Orientation;

    const NO_MOTION: Motion = Motion { position: 0.0, speed: 0.0, acceleration: 0.0 };

    fn state(r: [f64; 3], turn: [f64; 3], v: [f64; 3], w: [f64; 3]) -> BodyState {
        BodyState::new(
            Vec3::from(r),
            Orientation::from_scaled_axis(Vec3::from(turn)),
            Vec3::from(v),
            Vec3::from(w),
        )
    }

    /// The body after a time `e` along its velocities at fixed `(v, w')`: `r + v e`,
    /// orientation turned by `w' e` in its own frame.
    fn moved(b: &BodyState, e: f64) -> BodyState {
        BodyState::new(
            b.r + b.v * e,
            b.orientation * Orientation::from_scaled_axis(b.omega * e),
            b.v,
            b.omega,
        )
    }

    /// The body displaced along velocity coordinate `k` by `s`: `dr` for k < 3, a small
    /// rotation `dpi'` in its own frame for k >= 3.
    fn displaced(b: &BodyState, k: usize, s: f64) -> BodyState {
        let (mut r, mut orientation) = (b.r, b.orientation);
        if k < 3 {
            r[k] += s;
        } else {
            orientation *= Orientation::from_scaled_axis(Vec3::ith(k - 3, s));
        }
        BodyState::new(r, orientation, b.v, b.omega)
    }

    /// `Cq v` of an evaluated row.
    fn cq_v(ev: &SpatialRowEval, bi: &BodyState, bj: &BodyState) -> f64 {
        let part = |jac: &BodyRow, b: &BodyState| {
            (0..3).map(|k| jac[k] * b.v[k] + jac[k + 3] * b.omega[k]).sum::<f64>()
        };
        part(&ev.jac_i, bi) + part(&ev.jac_j, bj)
    }

    /// Checks the Jacobian blocks against central differences of C, `ct` against dC/dt
    /// along the motion, and gamma against `-(d/dt (Cq v))` at fixed v plus the driver's
    /// acceleration (what `-Ctt` contributes; `Cqt` is zero for every row).
    fn check(kind: SpatialRowKind, bi: BodyState, bj: BodyState, motion: Motion) {
        let ev = kind.eval(&bi, &bj, motion);
        let e = 1e-6;
        for k in 0..6 {
            let di = (kind.eval(&displaced(&bi, k, e), &bj, motion).c
                - kind.eval(&displaced(&bi, k, -e), &bj, motion).c)
                / (2.0 * e);
            let dj = (kind.eval(&bi, &displaced(&bj, k, e), motion).c
                - kind.eval(&bi, &displaced(&bj, k, -e), motion).c)
                / (2.0 * e);
            assert!((di - ev.jac_i[k]).abs() < 1e-8, "{kind:?} jac_i[{k}] {di} vs {}", ev.jac_i[k]);
            assert!((dj - ev.jac_j[k]).abs() < 1e-8, "{kind:?} jac_j[{k}] {dj} vs {}", ev.jac_j[k]);
        }
        let shifted = |s: f64| Motion { position: motion.position + motion.speed * s, ..motion };
        let dcdt = (kind.eval(&moved(&bi, e), &moved(&bj, e), shifted(e)).c
            - kind.eval(&moved(&bi, -e), &moved(&bj, -e), shifted(-e)).c)
            / (2.0 * e);
        let velocity = cq_v(&ev, &bi, &bj) + ev.ct;
        assert!((dcdt - velocity).abs() < 1e-7, "{kind:?} velocity equation {dcdt} vs {velocity}");
        let plus = kind.eval(&moved(&bi, e), &moved(&bj, e), motion);
        let minus = kind.eval(&moved(&bi, -e), &moved(&bj, -e), motion);
        let quad = (cq_v(&plus, &bi, &bj) - cq_v(&minus, &bi, &bj)) / (2.0 * e);
        let expected = -quad + motion.acceleration;
        assert!(
            (ev.gamma - expected).abs() < 1e-6 * (1.0 + expected.abs()),
            "{kind:?} gamma {} vs {expected}",
            ev.gamma
        );
    }

    /// Two moving bodies in general position, and the ground.
    fn bodies() -> [(BodyState, BodyState); 2] {
        let bi = state([0.3, -0.2, 0.5], [0.7, -0.4, 1.1], [1.1, -0.4, 0.6], [2.3, -1.2, 0.8]);
        let bj = state([-0.1, 0.5, 0.2], [-1.2, 0.3, 0.5], [-0.6, 0.9, -0.3], [-3.1, 0.7, 1.9]);
        [(bi, bj), (BodyState::ground(), bj)]
    }

    #[test]
    fn every_row_kind_matches_finite_differences() {
        let motion = Motion { position: 0.4, speed: 1.7, acceleration: -2.9 };
        let s_i = Vec3::new(0.12, -0.05, 0.08);
        let s_j = Vec3::new(-0.2, 0.07, 0.15);
        let a_i = Vec3::new(0.3, -0.8, 0.5);
        let a_j = Vec3::new(-0.6, 0.2, 0.9);
        let axis = Vec3::new(2.0, -1.0, 2.0) / 3.0;
        let ref_i = Vec3::new(1.0, 2.0, 0.0) / 5f64.sqrt();
        let ref_j = Vec3::new(0.0, 0.6, 0.8);
        for (bi, bj) in bodies() {
            for axis in 0..3 {
                check(SpatialRowKind::Coincide { axis, s_i, s_j }, bi, bj, NO_MOTION);
            }
            check(SpatialRowKind::Perpendicular { a_i, a_j }, bi, bj, NO_MOTION);
            check(SpatialRowKind::Along { a_i, s_i, s_j, offset: 0.1 }, bi, bj, motion);
            check(SpatialRowKind::Rotation { axis, ref_i, ref_j, offset: 0.3 }, bi, bj, motion);
        }
    }

    #[test]
    fn the_angle_is_wrapped_into_a_half_open_turn() {
        assert_eq!(wrap(PI), PI);
        assert_eq!(wrap(-PI), PI);
        assert!((wrap(3.0 * PI / 2.0) + PI / 2.0).abs() < 1e-15);
        assert!((wrap(-7.0 * PI / 4.0) - PI / 4.0).abs() < 1e-15);
        assert_eq!(wrap(0.25), 0.25);
    }
}
