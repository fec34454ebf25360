//! Planar vectors and rotations, kept in one place so a spatial build can swap them.

/// A 2-vector [m, m/s, N, ...].
pub type Vec2 = nalgebra::Vector2<f64>;

/// `A(phi) s`: rotates a body-frame vector into global axes.
#[inline]
pub fn rotate(phi: f64, s: Vec2) -> Vec2 {
    let (sn, cs) = phi.sin_cos();
    Vec2::new(cs * s.x - sn * s.y, sn * s.x + cs * s.y)
}

/// The vector turned by +90 degrees; `d/dphi A(phi) s = perp(A(phi) s)`.
#[inline]
pub fn perp(v: Vec2) -> Vec2 {
    Vec2::new(-v.y, v.x)
}

/// z-component of the planar cross product `a x b`.
#[inline]
pub fn cross(a: Vec2, b: Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}
