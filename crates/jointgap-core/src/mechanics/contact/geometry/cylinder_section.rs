//! The section of a journal in a cylindrical bearing normal to the bearing's axis: the
//! angles about each part's axis, which its wear table and its wear grid count from, and
//! the contact of a journal end where both parts are worn uniformly along their length
//! (docs/wear.md, "The spatial journal"). In the section of an aligned journal the
//! worn parts are the planar joint's worn profiles, so each end touches at the rims of
//! [`Worn::rims_from`]; a tilted journal's end is taken in the same section, its own turn
//! about its axis projected onto it.

use super::worn::{Found, Worn};
use crate::math::Vec2;
use crate::mechanics::contact::point3::{split, ContactPoints3, MaterialPoint3};
use crate::mechanics::spatial::body::{constant, BodyState, Vec3};
use crate::scalar::Real;
use nalgebra::Vector3;

/// Two unit vectors normal to the unit axis `a`, `[e1, e2]` with `e1 x e2 = a`: the angle
/// about `a` counts from `e1` towards `e2`. `e1` is the body's x axis made normal to `a`,
/// or its y axis where `a` lies within 26 degrees of x; for `a` along z they are x and
/// y, the planar joint's axes.
pub fn section_basis(a: Vec3) -> [Vec3; 2] {
    let from = if a.x.abs() < 0.9 { Vec3::x() } else { Vec3::y() };
    let e1 = (from - a * a.dot(&from)).normalize();
    [e1, a.cross(&e1)]
}

/// The section of a journal and its bearing at one state.
#[derive(Debug, Clone, Copy)]
pub struct Section<T: Real = f64> {
    /// The bearing's section axes ([`section_basis`]), global.
    pub axes: [Vector3<T>; 2],
    /// The journal's turn from the bearing about the bearing's axis [rad]: the angle of
    /// the journal's first section axis, projected onto the section.
    pub journal_turn: T,
}

impl<T: Real> Section<T> {
    /// The section's components of a global vector.
    #[inline]
    pub fn of(&self, v: &Vector3<T>) -> Vec2<T> {
        Vec2::new(v.dot(&self.axes[0]), v.dot(&self.axes[1]))
    }

    /// The global vector of section components `v`.
    #[inline]
    pub fn global(&self, v: Vec2<T>) -> Vector3<T> {
        self.axes[0] * v.x + self.axes[1] * v.y
    }

    /// The angle [rad] of a global vector's projection in the section.
    #[inline]
    pub fn angle(&self, v: &Vector3<T>) -> T {
        v.dot(&self.axes[1]).atan2(v.dot(&self.axes[0]))
    }

    /// The section of a bearing along `u_bearing` (its body's frame) and a journal along
    /// `u_journal` (its own) at the bodies' states `(bearing, journal)`.
    pub fn at(u_bearing: Vec3, u_journal: Vec3, bearing: &BodyState<T>, journal: &BodyState<T>) -> Self {
        let axes = section_basis(u_bearing).map(|e| bearing.rotate(&constant(&e)));
        let mut section = Section { axes, journal_turn: T::constant(0.0) };
        section.journal_turn = section.angle(&journal.rotate(&constant(&section_basis(u_journal)[0])));
        section
    }
}

/// The contact points of the journal end `index` (at `station` along the bearing axis
/// `axis` from the bearing centre `centre_b`, its radial offset `d` from the axis) of a
/// journal of radius `r_journal` on body `bodies[1]` in a bearing of radius `r_bearing`
/// on body `bodies[0]`, radial clearance `clearance`, both worn as `worn`, in any number
/// type: each rim of the section ([`Worn::rims_from`] at the end's eccentricity, where
/// the search found them, `found`) whose overlap is above `-reach` [m], carrying
/// `share` of the rim's part of the law. Each rim's points are the planar joint's
/// ([`super::worn::Rim::points`]) in the section through the end, so that `on_j - on_i
/// = delta n`, and the penetration's rate is the relative velocity of the two points
/// along `n` (`delta' = 0` at a rim).
#[allow(clippy::too_many_arguments)]
pub(super) fn worn_end<T: Real>(
    (worn, section, found): (&Worn, &Section<T>, &Found<T>),
    (bodies, (r_bearing, r_journal), clearance): ([Option<usize>; 2], (f64, f64), f64),
    (bearing, journal): (&BodyState<T>, &BodyState<T>),
    (index, share): (usize, f64),
    (centre_b, axis, station): (Vector3<T>, Vector3<T>, T),
    d: Vector3<T>,
    reach: f64,
    out: &mut ContactPoints3<T>,
) {
    let e = section.of(&d);
    let zero = T::constant(0.0);
    for rim in worn.rims_from(e, (zero, section.journal_turn), clearance, reach, found) {
        let (on_bearing, on_journal) = rim.points((Vec2::new(zero, zero), r_bearing), (e, r_journal));
        let wall = centre_b + axis * station;
        out.push(split(
            index,
            section.global(rim.normal),
            rim.penetration,
            rim.share * share,
            (MaterialPoint3::of(bodies[0], bearing, wall + section.global(on_bearing)), bearing),
            (MaterialPoint3::of(bodies[1], journal, wall + section.global(on_journal)), journal),
        ));
    }
}
