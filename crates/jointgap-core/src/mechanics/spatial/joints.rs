//! Constraint rows of spatial ideal joints and drivers, one scalar row at a time, with
//! analytic Jacobians and acceleration right-hand sides, and the set of rows each joint
//! kind adds (Nikravesh 1988, chapter 11; Haug 1989; docs/spatial-joints.md).
//!
//! Every row is written `C(q, t) = 0`; its time derivatives give `Cq v + Ct = 0` and
//! `Cq vdot = gamma`, with `gamma = -(d/dt Cq) v - 2 Cqt v - Ctt`. A row's Jacobian block
//! over one body is `[dC/dr, dC/dpi']`: `dr` a displacement of the centre of mass in
//! global axes and `dpi'` a small rotation in the body's own frame, the pair that the
//! body's velocities `(v, w')` multiply. Each body-frame vector `s` turns as
//! `d(A s) = A (dpi' x s)`, so a term `b . d(A s)` gives the block `s x (A^T b)`.

use std::f64::consts::{PI, TAU};

use nalgebra::Vector3;

use crate::mechanics::drivers::Motion;
use crate::mechanics::kind::RowEval;
use crate::mechanics::spatial::body::{constant, BodyState, Vec3, NV};
use crate::scalar::{c, Real};

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
    /// driver or a joint's initial angle. Its Jacobian is the exact gradient of the
    /// `atan2`, which is `axis . (dpi_j - dpi_i)` (both in global axes) wherever body
    /// j's reference lies across body i's axis, as the joint's other rows make it; it is
    /// singular only where that reference lies along the axis.
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

/// A spatial row evaluated at one state: residual, Jacobian blocks over `(v, w')` of
/// each body, and right-hand sides.
pub type SpatialRowEval<T = f64> = RowEval<[T; NV], T>;

/// A Jacobian block from its translation part `t` (global) and its rotation part `b`
/// (body frame).
#[inline]
fn block<T: Real>(t: Vector3<T>, b: Vector3<T>) -> [T; NV] {
    [t.x, t.y, t.z, b.x, b.y, b.z]
}

/// An angle wrapped to (-pi, pi].
#[inline]
fn wrap<T: Real>(angle: T) -> T {
    c::<T>(PI) - (c::<T>(PI) - angle).rem_euclid(c(TAU))
}

impl SpatialRowKind {
    /// Evaluates the row, in any number type; `motion` is the driver's prescribed motion
    /// (zero if none; the point and perpendicularity rows take none).
    pub fn eval<T: Real>(
        &self,
        bi: &BodyState<T>,
        bj: &BodyState<T>,
        motion: Motion<T>,
    ) -> SpatialRowEval<T> {
        // Global angular velocities: constant along a motion at fixed (v, w'), since
        // d/dt (A w') = A (w' x w') = 0.
        let (wi, wj) = (bi.omega_global(), bj.omega_global());
        let zero = T::constant(0.0);
        match *self {
            SpatialRowKind::Coincide { axis, s_i, s_j } => {
                let (si, sj) = (bi.rotate(&constant(&s_i)), bj.rotate(&constant(&s_j)));
                let e = Vector3::ith(axis, T::constant(1.0));
                let c = bi.r + si - bj.r - sj;
                // Centripetal accelerations of the two points at fixed angular velocity.
                let g = wj.cross(&wj.cross(&sj)) - wi.cross(&wi.cross(&si));
                SpatialRowEval {
                    c: c[axis],
                    jac_i: block(e, bi.a.tr_mul(&si.cross(&e))),
                    jac_j: block(-e, -bj.a.tr_mul(&sj.cross(&e))),
                    ct: zero,
                    gamma: g[axis],
                }
            }
            SpatialRowKind::Perpendicular { a_i, a_j } => {
                let (a_i, a_j) = (constant(&a_i), constant(&a_j));
                let (gi, gj) = (bi.rotate(&a_i), bj.rotate(&a_j));
                let (gi_dot, gj_dot) = (wi.cross(&gi), wj.cross(&gj));
                let quad =
                    gj.dot(&wi.cross(&gi_dot)) + gi_dot.dot(&gj_dot) * 2.0 + gi.dot(&wj.cross(&gj_dot));
                SpatialRowEval {
                    c: gi.dot(&gj),
                    jac_i: block(Vector3::zeros(), a_i.cross(&bi.a.tr_mul(&gj))),
                    jac_j: block(Vector3::zeros(), a_j.cross(&bj.a.tr_mul(&gi))),
                    ct: zero,
                    gamma: -quad,
                }
            }
            SpatialRowKind::Along { a_i, s_i, s_j, offset } => {
                let (a_i, s_j) = (constant(&a_i), constant(&s_j));
                let gi = bi.rotate(&a_i);
                let (si, sj) = (bi.rotate(&constant(&s_i)), bj.rotate(&s_j));
                let pj = bj.r + sj;
                let d = pj - bi.r - si;
                let gi_dot = wi.cross(&gi);
                let d_dot = bj.v + wj.cross(&sj) - bi.v - wi.cross(&si);
                let d_ddot = wj.cross(&wj.cross(&sj)) - wi.cross(&wi.cross(&si));
                let quad = wi.cross(&gi_dot).dot(&d) + gi_dot.dot(&d_dot) * 2.0 + gi.dot(&d_ddot);
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
                let u = bi.rotate(&constant(&axis));
                let e = bi.rotate(&constant(&ref_i));
                let f = u.cross(&e);
                let g = bj.rotate(&constant(&ref_j));
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
                let rho_dot = z * -2.0 * z_dot;
                let h_dot = u_dot - p * (z_dot / rho) - p_dot * (z / rho) + p * (z * rho_dot / (rho * rho));
                SpatialRowEval {
                    c: wrap(y.atan2(x) - offset - motion.position),
                    jac_i: block(Vector3::zeros(), -bi.a.tr_mul(&h)),
                    jac_j: block(Vector3::zeros(), bj.a.tr_mul(&h)),
                    ct: -motion.speed,
                    gamma: motion.acceleration - h_dot.dot(&rel),
                }
            }
        }
    }
}

/// The ideal spatial joints (Nikravesh 1988, chapter 11; Haug 1989).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpatialJointKind {
    /// Ball and socket: the points coincide. 3 rows; the three rotations are free.
    Spherical,
    /// Hinge: the points coincide and the axes stay parallel. 5 rows; the rotation about
    /// the axis is free.
    Revolute,
    /// The point of body j stays on body i's axis line and the axes stay parallel.
    /// 4 rows; the rotation about the axis and the travel along it are free.
    Cylindrical,
    /// Slider: a cylindrical joint whose rotation about the axis keeps its value at the
    /// placement. 5 rows; the travel along the axis is free.
    Prismatic,
    /// Hooke's joint: the points coincide and the cross axes, one on each body, stay
    /// perpendicular. 4 rows; the rotations about the two cross axes are free.
    Universal,
    /// Weld: the points coincide and the relative orientation keeps its value at the
    /// placement. 6 rows; nothing is free.
    Fixed,
    /// The normals, one on each body, stay parallel and the point of body j stays in
    /// body i's plane. 3 rows; the two translations in the plane and the rotation about
    /// the normal are free.
    Planar,
}

/// A joint's frame on one of its bodies, in that body's frame (for the ground: global).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointFrame {
    /// The joint's point [m].
    pub point: Vec3,
    /// The joint's axis, of any length but zero: the hinge or sliding axis, the
    /// universal joint's cross axis on this body, the planar joint's normal. Spherical
    /// and fixed joints do not read it.
    pub axis: Vec3,
}

/// A joint's row with the tag that names it in messages ("x", "axis-1", "rotation", ...).
pub type TaggedRow = (SpatialRowKind, &'static str);

/// A joint coordinate that a driver or an initial condition prescribes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointCoordinate {
    /// The angle [rad] body j has turned about the axis (revolute, cylindrical).
    Angle,
    /// The travel [m] of body j's point along the axis from body i's point (prismatic,
    /// cylindrical).
    Travel,
}

/// How far from perpendicular (the cosine of their angle) a universal joint's cross
/// axes may be at the placement: loose enough for orientations typed with a few
/// decimals, which assembly then corrects, tight enough to refuse axes meant otherwise.
pub const CROSS_AXES_SQUARENESS: f64 = 1e-3;

const POSITION_TAGS: [&str; 3] = ["x", "y", "z"];

/// A vector as the model file writes it.
fn show(v: &Vec3) -> String {
    format!("({}, {}, {})", v.x, v.y, v.z)
}

/// The frame's axis made unit, or an error naming it (`side`: "body i" or "body j").
fn unit_axis(frame: &JointFrame, side: &str) -> Result<Vec3, String> {
    let n = frame.axis.norm();
    if n > 0.0 && n.is_finite() {
        Ok(frame.axis / n)
    } else {
        Err(format!("the axis on {side} is {}: an axis needs a finite, nonzero length", show(&frame.axis)))
    }
}

/// Two unit vectors `(e, f)` that complete the unit `axis` to a right-handed triad
/// `(e, f, axis)`, picked once and the same way every time: `e` is the coordinate axis
/// after the one the axis leans on most (z -> x, x -> y, y -> z), made perpendicular to
/// it, and `f = axis x e`. Two bodies that share an axis along z thus measure the angle
/// between them as planar bodies do, `phi_j - phi_i`.
pub fn perpendiculars(axis: &Vec3) -> (Vec3, Vec3) {
    let next = Vec3::ith((axis.iamax() + 1) % 3, 1.0);
    let e = (next - axis * axis.dot(&next)).normalize();
    (e, axis.cross(&e))
}

/// The rows of a joint between body i and body j, from its frame on each body and the
/// bodies' placement (read by the prismatic and fixed joints, which keep a relative
/// rotation at its placed value, and by the universal joint's check), or an error naming
/// the offending value: an axis of zero length, a universal joint's cross axes that are
/// not perpendicular at the placement.
pub fn joint_rows(
    kind: SpatialJointKind,
    frame_i: &JointFrame,
    frame_j: &JointFrame,
    bi: &BodyState,
    bj: &BodyState,
) -> Result<Vec<TaggedRow>, String> {
    use SpatialJointKind::*;
    let (s_i, s_j) = (frame_i.point, frame_j.point);
    let mut rows: Vec<TaggedRow> = Vec::with_capacity(6);
    if matches!(kind, Spherical | Revolute | Universal | Fixed) {
        rows.extend(
            POSITION_TAGS
                .iter()
                .enumerate()
                .map(|(axis, &tag)| (SpatialRowKind::Coincide { axis, s_i, s_j }, tag)),
        );
    }
    match kind {
        Spherical => {}
        Fixed => {
            // Body i's frame as body j saw it at the placement: each pair of body i's
            // coordinate axes stays as perpendicular as it was then.
            let placed = bj.a.tr_mul(&bi.a);
            let tags = ["rotation-x", "rotation-y", "rotation-z"];
            rows.extend(tags.iter().enumerate().map(|(k, &tag)| {
                let a_i = Vec3::ith((k + 1) % 3, 1.0);
                (SpatialRowKind::Perpendicular { a_i, a_j: placed * Vec3::ith((k + 2) % 3, 1.0) }, tag)
            }));
        }
        Universal => {
            let (a_i, a_j) = (unit_axis(frame_i, "body i")?, unit_axis(frame_j, "body j")?);
            let cos = bi.rotate(&a_i).dot(&bj.rotate(&a_j));
            if cos.abs() > CROSS_AXES_SQUARENESS {
                return Err(format!(
                    "the cross axes {} on body i and {} on body j are {:.4} degrees apart at the \
                     placement; a universal joint needs them perpendicular",
                    show(&frame_i.axis),
                    show(&frame_j.axis),
                    cos.clamp(-1.0, 1.0).acos().to_degrees()
                ));
            }
            rows.push((SpatialRowKind::Perpendicular { a_i, a_j }, "cross"));
        }
        Revolute | Cylindrical | Prismatic | Planar => {
            let (u, h_j) = (unit_axis(frame_i, "body i")?, unit_axis(frame_j, "body j")?);
            let (e, f) = perpendiculars(&u);
            rows.push((SpatialRowKind::Perpendicular { a_i: e, a_j: h_j }, "axis-1"));
            rows.push((SpatialRowKind::Perpendicular { a_i: f, a_j: h_j }, "axis-2"));
            if kind == Planar {
                rows.push((SpatialRowKind::Along { a_i: u, s_i, s_j, offset: 0.0 }, "plane"));
            }
            if matches!(kind, Cylindrical | Prismatic) {
                rows.push((SpatialRowKind::Along { a_i: e, s_i, s_j, offset: 0.0 }, "line-1"));
                rows.push((SpatialRowKind::Along { a_i: f, s_i, s_j, offset: 0.0 }, "line-2"));
            }
            if kind == Prismatic {
                // Body i's e as body j saw it at the placement stays across body i's f.
                let a_j = bj.a.tr_mul(&bi.rotate(&e));
                rows.push((SpatialRowKind::Perpendicular { a_i: f, a_j }, "rotation"));
            }
        }
    }
    Ok(rows)
}

/// The rate of an evaluated row's value, `Cq v` over the two bodies (velocities and
/// body-frame angular velocities).
#[inline]
pub fn row_rate<T: Real>(ev: &SpatialRowEval<T>, bi: &BodyState<T>, bj: &BodyState<T>) -> T {
    // As `Iterator::sum` of f64, from -0.
    let part = |jac: &[T; NV], b: &BodyState<T>| {
        (0..3).fold(T::constant(-0.0), |s, k| s + (jac[k] * b.v[k] + jac[k + 3] * b.omega[k]))
    };
    part(&ev.jac_i, bi) + part(&ev.jac_j, bj)
}

/// The row that holds a joint coordinate at `initial` (the value at the placement when
/// `None`), for a driver (which adds its motion to it) or an initial condition, with the
/// coordinate's value at the placement; `None` where the joint has no such coordinate.
/// The angle is measured from the perpendiculars of each body's axis
/// ([`perpendiculars`]); the travel is that of body j's point from body i's point along
/// body i's unit axis.
pub fn coordinate_row(
    kind: SpatialJointKind,
    coordinate: JointCoordinate,
    frame_i: &JointFrame,
    frame_j: &JointFrame,
    bi: &BodyState,
    bj: &BodyState,
    initial: Option<f64>,
) -> Result<Option<(SpatialRowKind, f64)>, String> {
    use SpatialJointKind::*;
    let held = match coordinate {
        JointCoordinate::Angle => matches!(kind, Revolute | Cylindrical),
        JointCoordinate::Travel => matches!(kind, Prismatic | Cylindrical),
    };
    if !held {
        return Ok(None);
    }
    let axis = unit_axis(frame_i, "body i")?;
    let ref_j = perpendiculars(&unit_axis(frame_j, "body j")?).0;
    let row = |offset| match coordinate {
        JointCoordinate::Angle => {
            SpatialRowKind::Rotation { axis, ref_i: perpendiculars(&axis).0, ref_j, offset }
        }
        JointCoordinate::Travel => {
            SpatialRowKind::Along { a_i: axis, s_i: frame_i.point, s_j: frame_j.point, offset }
        }
    };
    let placed = row(0.0).eval(bi, bj, Motion { position: 0.0, speed: 0.0, acceleration: 0.0 }).c;
    Ok(Some((row(initial.unwrap_or(placed)), placed)))
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
            b.orientation() * Orientation::from_scaled_axis(b.omega * e),
            b.v,
            b.omega,
        )
    }

    /// The body displaced along velocity coordinate `k` by `s`: `dr` for k < 3, a small
    /// rotation `dpi'` in its own frame for k >= 3.
    fn displaced(b: &BodyState, k: usize, s: f64) -> BodyState {
        let (mut r, mut orientation) = (b.r, b.orientation());
        if k < 3 {
            r[k] += s;
        } else {
            orientation *= Orientation::from_scaled_axis(Vec3::ith(k - 3, s));
        }
        BodyState::new(r, orientation, b.v, b.omega)
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
        let velocity = row_rate(&ev, &bi, &bj) + ev.ct;
        assert!((dcdt - velocity).abs() < 1e-7, "{kind:?} velocity equation {dcdt} vs {velocity}");
        let plus = kind.eval(&moved(&bi, e), &moved(&bj, e), motion);
        let minus = kind.eval(&moved(&bi, -e), &moved(&bj, -e), motion);
        let quad = (row_rate(&plus, &bi, &bj) - row_rate(&minus, &bi, &bj)) / (2.0 * e);
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

    use SpatialJointKind::*;

    const KINDS: [SpatialJointKind; 7] =
        [Spherical, Revolute, Cylindrical, Prismatic, Universal, Fixed, Planar];

    /// The joint's frames: points off the centres of mass, axes of no special direction
    /// and not of unit length.
    fn frames() -> (JointFrame, JointFrame) {
        (
            JointFrame { point: Vec3::new(0.1, -0.2, 0.05), axis: Vec3::new(1.0, 2.0, -2.0) },
            JointFrame { point: Vec3::new(-0.15, 0.04, 0.2), axis: Vec3::new(0.0, -3.0, 4.0) },
        )
    }

    /// Body i's axis and its perpendiculars, global: `(u, e, f)`.
    fn triad(bi: &BodyState, fi: &JointFrame) -> (Vec3, Vec3, Vec3) {
        let u = fi.axis.normalize();
        let (e, f) = perpendiculars(&u);
        (bi.rotate(&u), bi.rotate(&e), bi.rotate(&f))
    }

    /// Body j moved rigidly: turned by the global rotation vector `turn` about the point
    /// `pivot`, then shifted by `shift`.
    fn carried(bj: &BodyState, pivot: Vec3, turn: Vec3, shift: Vec3) -> BodyState {
        let rot = Orientation::from_scaled_axis(turn);
        BodyState::new(pivot + rot * (bj.r - pivot) + shift, rot * bj.orientation(), bj.v, bj.omega)
    }

    /// A placement of body j that satisfies the joint: its axis along body i's (across
    /// it for a universal joint), turned 0.4 rad about it, its point on body i's (0.3 m
    /// along the axis for a cylindrical or prismatic joint, off in the plane for a
    /// planar joint).
    fn placement(kind: SpatialJointKind, bi: &BodyState, fi: &JointFrame, fj: &JointFrame) -> BodyState {
        let (u, e, f) = triad(bi, fi);
        let target = if kind == Universal { e } else { u };
        let turn = Orientation::from_scaled_axis(target * 0.4);
        let orientation = turn * Orientation::rotation_between(&fj.axis, &target).expect("not opposite");
        let shift = match kind {
            Cylindrical | Prismatic => u * 0.3,
            Planar => e * 0.2 - f * 0.1,
            _ => Vec3::zeros(),
        };
        let p_i = bi.r + bi.rotate(&fi.point);
        let bj = state([0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3]);
        BodyState::new(p_i + shift - orientation * fj.point, orientation, bj.v, bj.omega)
    }

    /// The relative motions each joint allows and some it forbids, as (turn, shift) of
    /// body j about its joint point, in global axes.
    fn motions(
        kind: SpatialJointKind,
        u: Vec3,
        e: Vec3,
        f: Vec3,
        c_j: Vec3,
    ) -> (Vec<[Vec3; 2]>, Vec<[Vec3; 2]>) {
        let z = Vec3::zeros();
        let shifts = vec![[z, u * 0.1], [z, e * 0.1], [z, f * 0.1]];
        let tilts = vec![[e * 0.1, z], [f * 0.1, z]];
        let cat = |a: Vec<[Vec3; 2]>, b: Vec<[Vec3; 2]>| a.into_iter().chain(b).collect::<Vec<_>>();
        match kind {
            Spherical => (vec![[u * 0.7, z], [e * 0.5 + f * 0.3, z], [Vec3::new(0.4, -0.9, 0.2), z]], shifts),
            Revolute => (vec![[u * 0.9, z], [u * -2.5, z]], cat(shifts, tilts)),
            Cylindrical => (
                vec![[u * 0.9, u * 0.2], [z, u * -1.0]],
                vec![[z, e * 0.1], [z, f * 0.1], [e * 0.1, z], [f * 0.1, z]],
            ),
            Prismatic => (
                vec![[z, u * 0.25], [z, u * -1.0]],
                cat(vec![[u * 0.1, z], [z, e * 0.1], [z, f * 0.1]], tilts),
            ),
            Universal => (vec![[u * 0.6, z], [c_j * -0.5, z]], cat(shifts, vec![[u.cross(&c_j) * 0.1, z]])),
            Fixed => (vec![[z, z]], cat(shifts, cat(tilts, vec![[u * 0.1, z]]))),
            Planar => (
                vec![[u * 0.8, z], [z, e * 0.3 - f * 0.2], [u * -1.5, e * 0.1 + f * 0.4]],
                vec![[z, u * 0.1], [e * 0.1, z], [f * 0.1, z]],
            ),
        }
    }

    fn residuals(rows: &[TaggedRow], bi: &BodyState, bj: &BodyState) -> Vec<f64> {
        rows.iter().map(|(row, _)| row.eval(bi, bj, NO_MOTION).c).collect()
    }

    #[test]
    fn each_joint_has_its_rows_and_names_them_once() {
        let (fi, fj) = frames();
        let counts = [3, 5, 4, 5, 4, 6, 3];
        for (kind, n) in KINDS.into_iter().zip(counts) {
            let (bi, _) = bodies()[0];
            let bj = placement(kind, &bi, &fi, &fj);
            let rows = joint_rows(kind, &fi, &fj, &bi, &bj).unwrap();
            assert_eq!(rows.len(), n, "{kind:?}");
            let mut tags: Vec<_> = rows.iter().map(|r| r.1).collect();
            tags.sort();
            tags.dedup();
            assert_eq!(tags.len(), n, "{kind:?} tags {tags:?}");
        }
    }

    /// At a placement that satisfies the joint every residual is zero; the rows are
    /// independent; the motions the joint allows keep every residual at zero, at the
    /// velocity level span the Jacobian's null space, and each forbidden motion moves
    /// a residual. With a moving body i and with the ground as body i.
    #[test]
    fn each_joint_holds_what_it_should_and_frees_the_rest() {
        let (fi, fj) = frames();
        for (bi, _) in bodies() {
            for kind in KINDS {
                let bj = placement(kind, &bi, &fi, &fj);
                let rows = joint_rows(kind, &fi, &fj, &bi, &bj).unwrap();
                let at_rest = residuals(&rows, &bi, &bj);
                assert!(at_rest.iter().all(|c| c.abs() < 1e-14), "{kind:?} placed {at_rest:?}");
                // Rank over body j's block alone (body i held): rows independent.
                let jac = nalgebra::DMatrix::from_fn(rows.len(), 6, |r, k| {
                    rows[r].0.eval(&bi, &bj, NO_MOTION).jac_j[k]
                });
                let sv = jac.clone().svd(false, false).singular_values;
                assert!(sv.min() > 0.1, "{kind:?} singular values {sv}");
                let (u, e, f) = triad(&bi, &fi);
                let c_j = bj.rotate(&fj.axis.normalize());
                let p_j = bj.r + bj.rotate(&fj.point);
                let (allowed, forbidden) = motions(kind, u, e, f, c_j);
                for [turn, shift] in &allowed {
                    let moved = carried(&bj, p_j, *turn, *shift);
                    let c = residuals(&rows, &bi, &moved);
                    assert!(c.iter().all(|c| c.abs() < 1e-14), "{kind:?} allowed {turn} {shift}: {c:?}");
                }
                for [turn, shift] in &forbidden {
                    let moved = carried(&bj, p_j, *turn, *shift);
                    let c = residuals(&rows, &bi, &moved);
                    let worst = c.iter().fold(0.0f64, |m, c| m.max(c.abs()));
                    assert!(worst > 0.05, "{kind:?} forbidden {turn} {shift}: {c:?}");
                }
                // The allowed twists of body j (body i at rest), as (v, w'), make
                // Cq v = 0; there are 6 - rows of them and they are independent, so
                // they span the Jacobian's null space.
                let twists: Vec<[f64; 6]> = allowed
                    .iter()
                    .filter(|m| m[0].norm() + m[1].norm() > 0.0)
                    .map(|[turn, shift]| {
                        let v = turn.cross(&(bj.r - p_j)) + shift;
                        let w = bj.a.tr_mul(turn);
                        [v.x, v.y, v.z, w.x, w.y, w.z]
                    })
                    .collect();
                let free = nalgebra::DMatrix::from_fn(6, twists.len(), |k, t| twists[t][k]);
                if !twists.is_empty() {
                    let rates = &jac * &free;
                    assert!(rates.amax() < 1e-14, "{kind:?} Cq v of allowed twists {rates}");
                    assert_eq!(free.rank(1e-9), 6 - rows.len(), "{kind:?} allowed twists");
                } else {
                    assert_eq!(rows.len(), 6, "{kind:?}");
                }
            }
        }
    }

    /// A fixed joint's rotation rows are named after body i's axis each one resists.
    #[test]
    fn a_fixed_joints_rotation_rows_name_body_is_axes() {
        let (fi, fj) = frames();
        let (bi, _) = bodies()[0];
        let bj = placement(Fixed, &bi, &fi, &fj);
        let rows = joint_rows(Fixed, &fi, &fj, &bi, &bj).unwrap();
        for (k, tag) in ["rotation-x", "rotation-y", "rotation-z"].into_iter().enumerate() {
            let turned = carried(&bj, bj.r, bi.rotate(&Vec3::ith(k, 0.1)), Vec3::zeros());
            for (row, name) in &rows[3..] {
                let c = row.eval(&bi, &turned, NO_MOTION).c;
                let expected = if *name == tag { -0.1f64.sin() } else { 0.0 };
                assert!((c - expected).abs() < 1e-14, "turned about body i's axis {k}: {name} {c}");
            }
        }
    }

    #[test]
    fn joint_coordinates_measure_the_turn_and_the_travel() {
        let (fi, fj) = frames();
        for (bi, _) in bodies() {
            let (u, _, _) = triad(&bi, &fi);
            let bj = placement(Cylindrical, &bi, &fi, &fj);
            let p_j = bj.r + bj.rotate(&fj.point);
            let angle =
                coordinate_row(Cylindrical, JointCoordinate::Angle, &fi, &fj, &bi, &bj, None).unwrap();
            let travel =
                coordinate_row(Cylindrical, JointCoordinate::Travel, &fi, &fj, &bi, &bj, None).unwrap();
            let ((angle, _), (travel, placed_travel)) = (angle.unwrap(), travel.unwrap());
            assert!((placed_travel - 0.3).abs() < 1e-14, "travel at the placement {placed_travel}");
            for (turn, shift) in [(0.7, 0.25), (3.0, -0.1), (-2.0, 1.5), (-3.0, 0.0)] {
                let moved = carried(&bj, p_j, u * turn, u * shift);
                let c = angle.eval(&bi, &moved, NO_MOTION).c;
                assert!((c - turn).abs() < 1e-13, "turned {turn}, angle row {c}");
                let c = travel.eval(&bi, &moved, NO_MOTION).c;
                assert!((c - shift).abs() < 1e-13, "moved {shift}, travel row {c}");
            }
            // A turn past a half turn reads as the short way round.
            let c = angle.eval(&bi, &carried(&bj, p_j, u * 4.0, Vec3::zeros()), NO_MOTION).c;
            assert!((c - (4.0 - TAU)).abs() < 1e-13, "{c}");
            // A driver's motion is subtracted; an initial value replaces the placed one.
            let motion = Motion { position: 0.5, speed: 0.0, acceleration: 0.0 };
            let c = angle.eval(&bi, &carried(&bj, p_j, u * 0.5, Vec3::zeros()), motion).c;
            assert!(c.abs() < 1e-13, "{c}");
            let (held, placed) =
                coordinate_row(Prismatic, JointCoordinate::Travel, &fi, &fj, &bi, &bj, Some(0.1))
                    .unwrap()
                    .unwrap();
            assert!((held.eval(&bi, &bj, NO_MOTION).c - (placed - 0.1)).abs() < 1e-14);
        }
        // Only revolute and cylindrical joints turn, only prismatic and cylindrical slide.
        let (bi, bj) = bodies()[0];
        for kind in KINDS {
            for (coordinate, has) in [
                (JointCoordinate::Angle, matches!(kind, Revolute | Cylindrical)),
                (JointCoordinate::Travel, matches!(kind, Prismatic | Cylindrical)),
            ] {
                let row = coordinate_row(kind, coordinate, &fi, &fj, &bi, &bj, None).unwrap();
                assert_eq!(row.is_some(), has, "{kind:?} {coordinate:?}");
            }
        }
    }

    #[test]
    fn perpendiculars_complete_a_right_handed_triad() {
        assert_eq!(perpendiculars(&Vec3::z()), (Vec3::x(), Vec3::y()));
        assert_eq!(perpendiculars(&Vec3::x()), (Vec3::y(), Vec3::z()));
        assert_eq!(perpendiculars(&Vec3::y()), (Vec3::z(), Vec3::x()));
        assert_eq!(perpendiculars(&-Vec3::z()), (Vec3::x(), -Vec3::y()));
        let u = Vec3::new(1.0, 2.0, -2.0) / 3.0;
        let (e, f) = perpendiculars(&u);
        for (a, b) in [(e, e), (f, f), (e, f), (e, u), (f, u)] {
            let expected = if a == b { 1.0 } else { 0.0 };
            assert!((a.dot(&b) - expected).abs() < 1e-15, "{a} . {b}");
        }
        assert!((e.cross(&f) - u).norm() < 1e-15);
    }

    /// Bodies that share the z axis measure their relative angle as planar bodies do.
    #[test]
    fn about_z_the_angle_is_the_planar_one() {
        let z = JointFrame { point: Vec3::zeros(), axis: Vec3::z() };
        for (phi_i, phi_j) in [(0.3, 2.1), (1.0, -2.9), (-0.5, -0.5)] {
            let bi = state([0.2, 0.1, 0.0], [0.0, 0.0, phi_i], [0.0; 3], [0.0; 3]);
            let bj = state([0.2, 0.1, 0.0], [0.0, 0.0, phi_j], [0.0; 3], [0.0; 3]);
            let (_, placed) =
                coordinate_row(Revolute, JointCoordinate::Angle, &z, &z, &bi, &bj, None).unwrap().unwrap();
            assert!((placed - wrap(phi_j - phi_i)).abs() < 1e-14, "{phi_i} {phi_j}: {placed}");
        }
    }

    #[test]
    fn a_zero_axis_or_crooked_cross_axes_are_refused_by_value() {
        let (fi, fj) = frames();
        let (bi, bj) = bodies()[0];
        let zero = JointFrame { axis: Vec3::zeros(), ..fi };
        for kind in [Revolute, Cylindrical, Prismatic, Universal, Planar] {
            let err = joint_rows(kind, &zero, &fj, &bi, &bj).unwrap_err();
            assert!(err.contains("body i is (0, 0, 0)"), "{kind:?}: {err}");
            let err = joint_rows(kind, &fi, &zero, &bi, &bj).unwrap_err();
            assert!(err.contains("body j is (0, 0, 0)"), "{kind:?}: {err}");
        }
        let nan = JointFrame { axis: Vec3::new(f64::NAN, 0.0, 1.0), ..fi };
        assert!(joint_rows(Revolute, &nan, &fj, &bi, &bj).unwrap_err().contains("(NaN, 0, 1)"));
        let err = coordinate_row(Revolute, JointCoordinate::Angle, &fi, &zero, &bi, &bj, None).unwrap_err();
        assert!(err.contains("body j is (0, 0, 0)"), "{err}");
        // Spherical and fixed joints read no axis.
        assert!(joint_rows(Spherical, &zero, &zero, &bi, &bj).is_ok());
        assert!(joint_rows(Fixed, &zero, &zero, &bi, &bj).is_ok());
        // Cross axes along each other: 0 degrees apart.
        let bj = placement(Revolute, &bi, &fi, &fj);
        let err = joint_rows(Universal, &fi, &fj, &bi, &bj).unwrap_err();
        assert!(err.contains("(1, 2, -2) on body i and (0, -3, 4) on body j are 0.0000 degrees"), "{err}");
    }
}
