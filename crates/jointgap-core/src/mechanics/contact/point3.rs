//! A spatial contact point: where a spatial clearance joint's two parts touch or, apart,
//! come nearest, as a spatial contact geometry finds it ([`super::geometry`]: a ball in
//! its socket, a journal in a cylindrical bearing) and the force laws read it
//! (docs/spatial-clearance.md). The spatial counterpart of [`super::point`]: the same
//! quantities, with a 3D normal and the slip as a vector in global axes instead of its
//! components on a tangent basis, since in space the friction law acts along the slip
//! itself.

use std::ops::Deref;

use smallvec::SmallVec;

use nalgebra::Vector3;

use crate::mechanics::spatial::body::BodyState;
use crate::scalar::Real;

/// A point of a spatial body, in global axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaterialPoint3<T: Real = f64> {
    /// The body it belongs to (`None`: the ground).
    pub body: Option<usize>,
    /// Where it is, global [m].
    pub at: Vector3<T>,
    /// `at` from the body's centre of mass, global axes [m]: a force `f` at the point
    /// has the moment `arm x f` about the centre of mass (in the body frame, `A^T (arm x
    /// f)`, the generalized force on the body's virtual rotation `dpi'`).
    pub arm: Vector3<T>,
}

impl<T: Real> MaterialPoint3<T> {
    /// The point `at` (global) of `body`, whose state is `state`.
    #[inline]
    pub fn of(body: Option<usize>, state: &BodyState<T>, at: Vector3<T>) -> Self {
        MaterialPoint3 { body, at, arm: at - state.r }
    }

    /// Velocity [m/s] of the point, moving with its body (state `state`): `v + w x arm`.
    #[inline]
    pub fn velocity(&self, state: &BodyState<T>) -> Vector3<T> {
        state.v + state.omega_global().cross(&self.arm)
    }
}

/// One contact point of a spatial clearance joint at one state. The joint's parts are
/// those of its model entry: the part on body i (the socket, the bearing) and the part on
/// body j (the ball, the journal). The normal points the way body j's point moves to
/// press deeper into body i's part, so the normal force on body j acts along `-n`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPoint3<T: Real = f64> {
    /// Which of its geometry's points this is (0 to the geometry's count - 1): each keeps
    /// its own contact state and impact list.
    pub index: usize,
    /// Unit normal `n`, global.
    pub normal: Vector3<T>,
    /// Penetration `delta` [m]: positive in contact, minus the gap apart.
    pub penetration: T,
    /// Penetration rate `delta_dot = v . n` [m/s], `v` the velocity of body j's point
    /// relative to body i's: the time derivative of `penetration`.
    pub penetration_rate: T,
    /// Slip: `v - (v . n) n`, the tangential part of that relative velocity, global
    /// [m/s].
    pub slip: Vector3<T>,
    /// The part of the joint's normal law this point carries: its normal force is `share`
    /// times the law's force at its penetration and rate (1 for a ball in its socket;
    /// 1/2 at each end of a journal, whose two ends together carry the whole journal's
    /// law when it lies aligned).
    pub share: T,
    /// The point of body i's part (the socket's, the bearing's wall).
    pub on_i: MaterialPoint3<T>,
    /// The point of body j's part (the ball's, the journal's surface).
    pub on_j: MaterialPoint3<T>,
}

impl<T: Real> ContactPoint3<T> {
    /// The contact force on body j at [`ContactPoint3::on_j`], global [N], from a normal
    /// force `f_n` (compressive positive) and a friction force `f_t` (global, tangential):
    /// `-F_N n + F_T`. Body i takes its opposite at [`ContactPoint3::on_i`].
    #[inline]
    pub fn force_on_j(&self, f_n: T, f_t: &Vector3<T>) -> Vector3<T> {
        -self.normal * f_n + f_t
    }
}

/// The contact points a spatial geometry keeps on the stack: a journal in a bearing with
/// thrust faces has four (two journal ends, two thrust faces). A block in its guide has
/// sixteen (eight corners, each against two faces); those beyond four spill to the heap.
pub const INLINE_POINTS3: usize = 4;

/// The contact points a spatial geometry returns for one joint at one state: a list kept
/// on the stack up to [`INLINE_POINTS3`] (smallvec: its free slots are left unwritten,
/// so a joint of one point pays for one).
#[derive(Debug, Clone, Default)]
pub struct ContactPoints3<T: Real = f64>(SmallVec<[ContactPoint3<T>; INLINE_POINTS3]>);

impl<T: Real> ContactPoints3<T> {
    /// No points.
    #[inline]
    pub fn new() -> Self {
        ContactPoints3(SmallVec::new())
    }

    /// Adds a point; a geometry adds at most the points it declares.
    #[inline]
    pub fn push(&mut self, point: ContactPoint3<T>) {
        self.0.push(point);
    }
}

impl<T: Real> Deref for ContactPoints3<T> {
    type Target = [ContactPoint3<T>];

    #[inline]
    fn deref(&self) -> &[ContactPoint3<T>] {
        &self.0
    }
}

/// The contact point between material points `on_i` and `on_j` along unit normal `n`
/// with penetration `penetration` and law share `share`: the relative velocity `v` of
/// `on_j` to `on_i` (each moving with its body) split into the rate `v . n` and the slip
/// `v - (v . n) n`. Every spatial geometry ends with it, so all of them split alike.
#[inline]
pub(crate) fn split<T: Real>(
    index: usize,
    n: Vector3<T>,
    penetration: T,
    share: T,
    (on_i, state_i): (MaterialPoint3<T>, &BodyState<T>),
    (on_j, state_j): (MaterialPoint3<T>, &BodyState<T>),
) -> ContactPoint3<T> {
    let v = on_j.velocity(state_j) - on_i.velocity(state_i);
    let rate = v.dot(&n);
    ContactPoint3 {
        index,
        normal: n,
        penetration,
        penetration_rate: rate,
        slip: v - n * rate,
        share,
        on_i,
        on_j,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanics::spatial::body::{Orientation, Vec3};

    /// A force on body j's point: its normal part is `-F_N`, the rest the friction force.
    #[test]
    fn point_force_splits_along_normal_and_tangent() {
        let n = Vec3::new(2.0, -3.0, 6.0) / 7.0;
        let f_t = Vec3::new(3.0, 2.0, 0.0) * 1.5; // perpendicular to n
        let none = MaterialPoint3 { body: None, at: Vec3::zeros(), arm: Vec3::zeros() };
        let p = ContactPoint3 {
            index: 0,
            normal: n,
            penetration: 1e-5,
            penetration_rate: 0.0,
            slip: Vec3::zeros(),
            share: 1.0,
            on_i: none,
            on_j: none,
        };
        let f = p.force_on_j(100.0, &f_t);
        assert!((f.dot(&n) + 100.0).abs() < 1e-12, "{f:?}");
        assert!((f - f.dot(&n) * n - f_t).norm() < 1e-12, "{f:?}");
    }

    /// The friction laws act on the slip vector as it is (`FrictionSpec::force_on_slip`
    /// over three components): the friction force lies in the tangent plane, against
    /// the slip, and the force on body j keeps `-F_N` along `n`.
    #[test]
    fn friction_acts_on_the_slip_vector() {
        let n = Vec3::new(2.0, -3.0, 6.0) / 7.0;
        let v = Vec3::new(0.3, 0.1, -0.2);
        let slip = v - n * v.dot(&n);
        let none = MaterialPoint3 { body: None, at: Vec3::zeros(), arm: Vec3::zeros() };
        let p = ContactPoint3 {
            index: 0,
            normal: n,
            penetration: 1e-5,
            penetration_rate: v.dot(&n),
            slip,
            share: 1.0,
            on_i: none,
            on_j: none,
        };
        let law = crate::model::FrictionSpec::Coulomb { mu_s: 0.08, mu_d: 0.05, v_s: 1e-4, v_d: 0.01016 };
        let f_t = law.force_on_slip(&p.slip, 100.0);
        assert!(f_t.dot(&n).abs() < 1e-12);
        assert!((f_t + slip.normalize() * 5.0).norm() < 1e-12, "{f_t:?}");
        assert!((p.force_on_j(100.0, &f_t).dot(&n) + 100.0).abs() < 1e-12);
    }

    /// A material point's velocity against the body's own point velocity `v + A (w' x
    /// s)` with `s` the point in the body frame.
    #[test]
    fn material_point_moves_with_its_body() {
        let e = Orientation::from_scaled_axis(Vec3::new(0.3, -1.1, 0.7));
        let b = BodyState::new(
            Vec3::new(0.1, 0.2, -0.3),
            e,
            Vec3::new(1.0, -2.0, 0.5),
            Vec3::new(4.0, 5.0, -6.0),
        );
        let s = Vec3::new(0.02, -0.01, 0.05);
        let p = MaterialPoint3::of(Some(3), &b, b.r + b.rotate(&s));
        assert!((p.velocity(&b) - b.point_velocity(&s)).norm() < 1e-14);
        assert!((p.arm - b.rotate(&s)).norm() < 1e-15);
    }
}
