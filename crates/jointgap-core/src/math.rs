//! Planar vectors and rotations, kept in one place so a spatial build can swap them.
//! Written over any [`Real`], so that a compiled model runs the same operations.

use crate::scalar::Real;

/// A 2-vector [m, m/s, N, ...].
pub type Vec2<T = f64> = nalgebra::Vector2<T>;

/// `A(phi) s`: rotates a body-frame vector into global axes.
#[inline]
pub fn rotate(phi: f64, s: Vec2) -> Vec2 {
    let (sn, cs) = phi.sin_cos();
    Vec2::new(cs * s.x - sn * s.y, sn * s.x + cs * s.y)
}

/// The vector turned by +90 degrees; `d/dphi A(phi) s = perp(A(phi) s)`.
#[inline]
pub fn perp<T: Real>(v: Vec2<T>) -> Vec2<T> {
    Vec2::new(-v.y, v.x)
}

/// z-component of the planar cross product `a x b`.
#[inline]
pub fn cross<T: Real>(a: Vec2<T>, b: Vec2<T>) -> T {
    a.x * b.y - a.y * b.x
}

/// A constant vector of the model as a vector of `T`.
#[inline]
pub fn lift<T: Real>(v: Vec2) -> Vec2<T> {
    Vec2::new(T::constant(v.x), T::constant(v.y))
}
