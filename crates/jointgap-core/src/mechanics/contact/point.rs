//! A contact point: where a clearance joint's two parts touch or, apart, come nearest,
//! as a contact geometry finds it ([`super::geometry`]) and the force laws read it
//! (docs/physics.md section 2). The geometry says where and how fast; the laws say how
//! hard.

use std::ops::Deref;

use nalgebra::SVector;
use smallvec::SmallVec;

use crate::math::{perp, Vec2};
use crate::scalar::Real;

/// Tangent directions at a contact point: one in the plane, `t = perp(n)`; a spatial
/// build has two.
pub const TANGENTS: usize = 1;

/// A tangential vector at a contact point (the slip [m/s], a friction force [N]) by its
/// components along the point's tangents ([`tangents`]).
pub type Tangential<T = f64> = SVector<T, TANGENTS>;

/// The tangents of a contact point with unit normal `n`, in order: in the plane the one
/// `t = perp(n)`, so that `(n, t)` turns as the global axes do.
#[inline]
pub fn tangents<T: Real>(n: Vec2<T>) -> [Vec2<T>; TANGENTS] {
    [perp(n)]
}

/// `a . b` of two tangential vectors, summed from the first component on (no `0 +`
/// ahead of it, so that one component gives exactly its product, signed zero included).
#[inline]
pub fn dot(a: &Tangential, b: &Tangential) -> f64 {
    a.iter().zip(b.iter()).map(|(a, b)| a * b).reduce(|x, y| x + y).unwrap_or(0.0)
}

/// A point of a body, in global axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaterialPoint<T: Real = f64> {
    /// The body it belongs to (`None`: the ground).
    pub body: Option<usize>,
    /// Where it is, global [m].
    pub at: Vec2<T>,
}

/// One contact point of a clearance joint at one state. The joint's parts are those of
/// its model entry: the part on body i (the bearing of a revolute clearance) and the part
/// on body j (the journal). The normal points the way body j's point moves to press
/// deeper into body i's part, so the normal force on body j acts along `-n`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPoint<T: Real = f64> {
    /// Which of its geometry's points this is (0 to the geometry's count - 1): each keeps
    /// its own contact state and impact list.
    pub index: usize,
    /// Unit normal `n`, global.
    pub normal: Vec2<T>,
    /// Penetration `delta` [m]: positive in contact, minus the gap apart.
    pub penetration: T,
    /// Penetration rate `delta_dot = v . n` [m/s], `v` the velocity of body j's point
    /// relative to body i's.
    pub penetration_rate: T,
    /// Slip: `v`'s tangential part, along the [`tangents`] of `normal` [m/s].
    pub slip: Tangential<T>,
    /// The part of its law's force the point takes: 1, but for a gear mesh, whose
    /// stiffness varies along the mesh cycle (the stiffness there over the law's), and
    /// for a worn joint's rims, which share their law where their contacts merge.
    pub share: T,
    /// The point of body i's part (the bearing wall).
    pub on_i: MaterialPoint<T>,
    /// The point of body j's part (the journal's surface).
    pub on_j: MaterialPoint<T>,
}

impl<T: Real> ContactPoint<T> {
    /// A journal's point in its bearing, whose parts' material points are `on_i` and
    /// `on_j`: along `normal`, at `penetration`, with the journal's point moving at `v`
    /// relative to the bearing's; its rate and slip are `v`'s parts along the normal and
    /// the tangents.
    #[inline]
    pub fn in_bearing(
        normal: Vec2<T>,
        penetration: T,
        v: Vec2<T>,
        share: T,
        (on_i, on_j): (MaterialPoint<T>, MaterialPoint<T>),
    ) -> Self {
        let t = tangents(normal);
        ContactPoint {
            index: 0,
            normal,
            penetration,
            penetration_rate: v.dot(&normal),
            slip: Tangential::from_fn(|k, _| v.dot(&t[k])),
            share,
            on_i,
            on_j,
        }
    }

    /// The contact force on body j at [`ContactPoint::on_j`], global [N], from a normal
    /// force `f_n` (compressive positive) and a friction force `f_t` along the tangents:
    /// `-F_N n + sum_k F_T,k t_k`. Body i takes its opposite at [`ContactPoint::on_i`].
    #[inline]
    pub fn force_on_j(&self, f_n: T, f_t: &Tangential<T>) -> Vec2<T> {
        let mut f = -self.normal * f_n;
        for (t, c) in tangents(self.normal).iter().zip(f_t.iter()) {
            f += t * *c;
        }
        f
    }
}

/// The most contact points any geometry has: a block in its guide has four corners.
pub const MAX_POINTS: usize = 4;

/// The contact points a geometry returns for one joint at one state: a list kept on the
/// stack up to [`MAX_POINTS`] (smallvec: its free slots are left unwritten, so a joint of
/// one point pays for one), so that an evaluation allocates nothing.
#[derive(Debug, Clone, Default)]
pub struct ContactPoints<T: Real = f64>(SmallVec<[ContactPoint<T>; MAX_POINTS]>);

impl<T: Real> ContactPoints<T> {
    /// No points.
    #[inline]
    pub fn new() -> Self {
        ContactPoints(SmallVec::new())
    }

    /// Adds a point; a geometry adds at most the points it declares, at most
    /// [`MAX_POINTS`].
    #[inline]
    pub fn push(&mut self, point: ContactPoint<T>) {
        self.0.push(point);
    }
}

impl<T: Real> Deref for ContactPoints<T> {
    type Target = [ContactPoint<T>];

    #[inline]
    fn deref(&self) -> &[ContactPoint<T>] {
        &self.0
    }
}
