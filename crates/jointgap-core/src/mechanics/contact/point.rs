//! A contact point: where a clearance joint's two parts touch or, apart, come nearest,
//! as a contact geometry finds it ([`super::geometry`]) and the force laws read it
//! (docs/physics.md section 2). The geometry says where and how fast; the laws say how
//! hard.

use std::ops::Deref;

use nalgebra::SVector;
use smallvec::SmallVec;

use crate::math::{perp, Vec2};

/// Tangent directions at a contact point: one in the plane, `t = perp(n)`; a spatial
/// build has two.
pub const TANGENTS: usize = 1;

/// A tangential vector at a contact point (the slip [m/s], a friction force [N]) by its
/// components along the point's tangents ([`tangents`]).
pub type Tangential = SVector<f64, TANGENTS>;

/// The tangents of a contact point with unit normal `n`, in order: in the plane the one
/// `t = perp(n)`, so that `(n, t)` turns as the global axes do.
#[inline]
pub fn tangents(n: Vec2) -> [Vec2; TANGENTS] {
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
pub struct MaterialPoint {
    /// The body it belongs to (`None`: the ground).
    pub body: Option<usize>,
    /// Where it is, global [m].
    pub at: Vec2,
}

/// One contact point of a clearance joint at one state. The joint's parts are those of
/// its model entry: the part on body i (the bearing of a revolute clearance) and the part
/// on body j (the journal). The normal points the way body j's point moves to press
/// deeper into body i's part, so the normal force on body j acts along `-n`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPoint {
    /// Which of its geometry's points this is (0 to the geometry's count - 1): each keeps
    /// its own contact state and impact list.
    pub index: usize,
    /// Unit normal `n`, global.
    pub normal: Vec2,
    /// Penetration `delta` [m]: positive in contact, minus the gap apart.
    pub penetration: f64,
    /// Penetration rate `delta_dot = v . n` [m/s], `v` the velocity of body j's point
    /// relative to body i's.
    pub penetration_rate: f64,
    /// Slip: `v`'s tangential part, along the [`tangents`] of `normal` [m/s].
    pub slip: Tangential,
    /// The part of its law's force the point takes: 1, but for a gear mesh, whose
    /// stiffness varies along the mesh cycle (the stiffness there over the law's).
    pub share: f64,
    /// The point of body i's part (the bearing wall).
    pub on_i: MaterialPoint,
    /// The point of body j's part (the journal's surface).
    pub on_j: MaterialPoint,
}

impl ContactPoint {
    /// A journal's point in its bearing, whose parts' material points are `on_i` and
    /// `on_j`: along `normal`, at `penetration`, with the journal's point moving at `v`
    /// relative to the bearing's; its rate and slip are `v`'s parts along the normal and
    /// the tangents.
    #[inline]
    pub fn in_bearing(
        normal: Vec2,
        penetration: f64,
        v: Vec2,
        share: f64,
        (on_i, on_j): (MaterialPoint, MaterialPoint),
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
    pub fn force_on_j(&self, f_n: f64, f_t: &Tangential) -> Vec2 {
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
pub struct ContactPoints(SmallVec<[ContactPoint; MAX_POINTS]>);

impl ContactPoints {
    /// No points.
    #[inline]
    pub fn new() -> Self {
        ContactPoints(SmallVec::new())
    }

    /// Adds a point; a geometry adds at most the points it declares, at most
    /// [`MAX_POINTS`].
    #[inline]
    pub fn push(&mut self, point: ContactPoint) {
        self.0.push(point);
    }
}

impl Deref for ContactPoints {
    type Target = [ContactPoint];

    #[inline]
    fn deref(&self) -> &[ContactPoint] {
        &self.0
    }
}
