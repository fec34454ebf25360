//! A cylindrical journal (on body j) in a cylindrical bearing (on body i): a spatial
//! revolute joint with radial clearance, and, optionally, axial clearance between the
//! journal's end faces and the bearing's thrust faces. The journal may tilt within the
//! clearance, so it is checked at both ends: a tilted journal touches at one end first
//! (docs/spatial-clearance.md, "Journal in a cylindrical bearing"; Flores, Ambrosio,
//! Claro, Lankarani 2006 and Marques, Isaac, Dourado, Flores 2017 on spatial revolute
//! joints with radial and axial clearance).

use super::cylinder_section::{worn_end, Section};
use super::worn::{Found, Worn};
use nalgebra::Vector3;

use crate::mechanics::contact::point3::{split, ContactPoints3, MaterialPoint3};
use crate::mechanics::spatial::body::{constant, BodyState, Vec3};
use crate::scalar::{norm, Real};

/// Where a journal and its bearing are, their sizes, and their axial play.
#[derive(Debug, Clone, PartialEq)]
pub struct CylinderBearing {
    /// Bearing body (`None`: ground).
    pub bearing: Option<usize>,
    /// Bearing centre (mid-length on its axis) in the bearing body's frame [m].
    pub s_bearing: Vec3,
    /// Bearing axis, a unit vector in the bearing body's frame.
    pub u_bearing: Vec3,
    /// Journal body.
    pub journal: Option<usize>,
    /// Journal centre (mid-length on its axis) in the journal body's frame [m].
    pub s_journal: Vec3,
    /// Journal axis, a unit vector in the journal body's frame, pointing the bearing
    /// axis's way (a tilt within a clearance is small).
    pub u_journal: Vec3,
    /// Bearing radius `R_B` [m].
    pub r_bearing: f64,
    /// Journal radius `R_J` [m].
    pub r_journal: f64,
    /// Radial clearance `c = R_B - R_J` [m].
    pub clearance: f64,
    /// Journal length `L` [m]: its two end faces lie `L/2` either side of its centre.
    pub length: f64,
    /// Axial clearance `c_a` [m], when the bearing has thrust faces: the gap at each end
    /// face with the journal centred, so that the faces lie `L/2 + c_a` either side of
    /// the bearing centre (a bearing of length `L + 2 c_a`; the end play is `2 c_a`).
    /// `None`: no thrust faces; the bearing holds the journal radially wherever it slides.
    pub axial_clearance: Option<f64>,
    /// The parts' wear, uniform along their length, against the angle about each part's
    /// axis ([`super::cylinder_section::section_basis`]); `None`: both round.
    pub worn: Option<Box<Worn>>,
}

/// A journal's and its bearing's centres and unit axes, global.
#[derive(Debug, Clone, Copy)]
struct Axes<T: Real = f64> {
    centre_b: Vector3<T>,
    axis_b: Vector3<T>,
    centre_j: Vector3<T>,
    axis_j: Vector3<T>,
}

impl CylinderBearing {
    /// The part of the joint's normal law each journal end carries: a half, so that an
    /// aligned journal, pressing equally at both ends, takes the whole law, as the
    /// planar journal in its bearing does (docs/spatial-clearance.md, "Contact along
    /// the line").
    pub const END_SHARE: f64 = 0.5;

    /// Contact points the joint has: the journal's two ends (indices 0 at `-L/2` and 1 at
    /// `+L/2` along the journal axis), and with thrust faces the faces at `-(L/2 + c_a)`
    /// (index 2) and `+(L/2 + c_a)` (index 3) along the bearing axis.
    pub fn points(&self) -> usize {
        if self.axial_clearance.is_some() {
            4
        } else {
            2
        }
    }

    #[inline]
    fn axes<T: Real>(&self, bearing: &BodyState<T>, journal: &BodyState<T>) -> Axes<T> {
        Axes {
            centre_b: bearing.r + bearing.rotate(&constant(&self.s_bearing)),
            axis_b: bearing.rotate(&constant(&self.u_bearing)),
            centre_j: journal.r + journal.rotate(&constant(&self.s_journal)),
            axis_j: journal.rotate(&constant(&self.u_journal)),
        }
    }

    /// Eccentricity `r_J - r_B`: the journal centre from the bearing centre, global [m].
    pub fn eccentricity(&self, bearing: &BodyState, journal: &BodyState) -> Vec3 {
        let x = self.axes(bearing, journal);
        x.centre_j - x.centre_b
    }

    /// The joint's section at the bodies' states `(bearing, journal)`.
    pub fn section(&self, bearing: &BodyState, journal: &BodyState) -> Section {
        Section::at(self.u_bearing, self.u_journal, bearing, journal)
    }

    /// The radial offsets `d` of the journal's two ends (points 0 and 1) from the bearing
    /// axis, global [m]: each end's eccentricity in the plane normal to the bearing axis
    /// (`A_i^T d` in the bearing body's frame).
    pub fn end_offsets(&self, bearing: &BodyState, journal: &BodyState) -> [Vec3; 2] {
        let x = self.axes(bearing, journal);
        [-1.0, 1.0].map(|side| self.end(&x, side).2)
    }

    /// The journal end at `side` (-1: point 0, +1: point 1): its centre `E`, its station
    /// `a_B . (E - r_B)` along the bearing axis, and its radial offset `d` from that axis.
    #[inline]
    fn end<T: Real>(&self, x: &Axes<T>, side: f64) -> (Vector3<T>, T, Vector3<T>) {
        let end = x.centre_j + x.axis_j * T::constant(side * 0.5 * self.length);
        let w = end - x.centre_b;
        let station = x.axis_b.dot(&w);
        (end, station, w - x.axis_b * station)
    }
}

/// The unit normal of a radial offset `d` (perpendicular to the unit axis `a`) of length
/// `len`; for an end on the bearing axis (`len` below 1e-15 m) a fixed unit vector
/// perpendicular to `a` (nalgebra's first basis vector of the plane normal to `a`): the
/// end's gap is then the whole clearance and no force acts, so any normal in the plane
/// gives the same (zero) loads, and a fixed one keeps every output finite.
///
/// In any number type, the fixed vector is a constant of the recording: where it is
/// taken, the end is a whole clearance off the wall and its loads are zero whatever the
/// normal, so no output depends on it.
#[inline]
pub fn radial_normal<T: Real>(d: Vector3<T>, len: T, a: Vector3<T>) -> Vector3<T> {
    if len > 1e-15 {
        return d / len;
    }
    let mut n = Vec3::x();
    Vec3::orthonormal_subspace_basis(&[a.map(T::value)], |v| {
        n = *v;
        false
    });
    constant(&n)
}

/// The contact points of journal and bearing whose gap is below `reach` [m], pushed onto
/// `out` in the order of their index ([`CylinderBearing::points`]).
///
/// Journal ends (`E = r_J +- (L/2) a_J`, `a_J` the journal axis): `w = E - r_B`, its
/// radial offset from the bearing axis `a_B` is `d = w - (a_B . w) a_B`; normal `n = d /
/// |d|` (in the plane normal to the bearing axis), penetration `|d| - c`, the points
/// `E + R_J n` on the journal and `r_B + (a_B . w) a_B + R_B n` on the bearing wall at
/// the end's station. The journal's radial distance from the bearing axis is convex
/// along its length, so its deepest points are at its ends, and an aligned journal has
/// both ends equally deep. `|d| - c` is the depth of the end's centre circle offset by
/// `R_J`: a tilted end's rim, a circle normal to `a_J`, reaches at most `R_J (1 - cos
/// theta)` less far than that at tilt `theta` (about 5 nm for `R_J` = 10 mm and theta =
/// 1 mrad), a bound this model neglects. Each end carries [`CylinderBearing::END_SHARE`]
/// of the law.
///
/// Thrust faces (planes normal to `a_B` at `+-h`, `h = L/2 + c_a`, from the bearing
/// centre): the journal's end facing the face reaches it first at the rim point `X = E +
/// R_J u` farthest along the face's normal (`u` the unit part of `+-a_B` normal to
/// `a_J`; the end's centre when the journal is aligned, where the whole face meets at
/// once and its resultant acts at the centre); normal `+-a_B`, penetration `+-a_B . (X -
/// r_B) - h`, the points `X` on the journal and `X - delta n` on the face. Each face
/// carries the whole law.
///
/// In every case `on_j - on_i = delta n` and the two points differ from the points
/// whose motion sets the penetration only along `n`, so each point's force has the
/// moment that the penetration's change under a small rotation of its body calls for:
/// the elastic contact force derives from a potential.
#[inline]
pub fn contact_cylinder_bearing(
    g: &CylinderBearing,
    bearing: &BodyState,
    journal: &BodyState,
    reach: f64,
    out: &mut ContactPoints3,
) {
    match g.worn.as_deref() {
        Some(w) => contact_worn_cylinder(
            g,
            w,
            &search_cylinder(g, w, bearing, journal, reach),
            bearing,
            journal,
            reach,
            out,
        ),
        None => contact_round_cylinder(g, bearing, journal, reach, out),
    }
}

/// Where the search over the worn profiles `worn` finds the rims at each of the
/// journal's ends ([`Worn::search`] in the end's section).
pub fn search_cylinder(
    g: &CylinderBearing,
    worn: &Worn,
    bearing: &BodyState,
    journal: &BodyState,
    reach: f64,
) -> [Found; 2] {
    let x = g.axes(bearing, journal);
    let section = g.section(bearing, journal);
    let phis = (0.0, section.journal_turn);
    [-1.0, 1.0].map(|side| worn.search(section.of(&g.end(&x, side).2), phis, g.clearance, reach))
}

/// [`contact_cylinder_bearing`] of worn parts `worn`, in any number type, from where
/// the search found the rims at each end (`found`, [`search_cylinder`]).
#[inline]
pub fn contact_worn_cylinder<T: Real>(
    g: &CylinderBearing,
    worn: &Worn,
    found: &[Found<T>; 2],
    bearing: &BodyState<T>,
    journal: &BodyState<T>,
    reach: f64,
    out: &mut ContactPoints3<T>,
) {
    let x = g.axes(bearing, journal);
    let section = Section::at(g.u_bearing, g.u_journal, bearing, journal);
    for (index, side) in [(0, -1.0), (1, 1.0)] {
        let (_, station, d) = g.end(&x, side);
        let parts = ([g.bearing, g.journal], (g.r_bearing, g.r_journal), g.clearance);
        let ends = (index, CylinderBearing::END_SHARE);
        let at = (x.centre_b, x.axis_b, station);
        worn_end((worn, &section, &found[index]), parts, (bearing, journal), ends, at, d, reach, out);
    }
    thrust_faces(g, &x, bearing, journal, reach, out);
}

/// [`contact_cylinder_bearing`] of round parts (no wear), in any number type.
#[inline]
pub fn contact_round_cylinder<T: Real>(
    g: &CylinderBearing,
    bearing: &BodyState<T>,
    journal: &BodyState<T>,
    reach: f64,
    out: &mut ContactPoints3<T>,
) {
    let x = g.axes(bearing, journal);
    for end in [(0, -1.0), (1, 1.0)] {
        round_end(g, &x, end, bearing, journal, reach, out);
    }
    thrust_faces(g, &x, bearing, journal, reach, out);
}

/// The contact point of the round journal's end `(index, side)` against the round
/// bearing ([`contact_cylinder_bearing`]).
#[inline]
fn round_end<T: Real>(
    g: &CylinderBearing,
    x: &Axes<T>,
    (index, side): (usize, f64),
    bearing: &BodyState<T>,
    journal: &BodyState<T>,
    reach: f64,
    out: &mut ContactPoints3<T>,
) {
    let (end, station, d) = g.end(x, side);
    let len = norm(&d);
    let penetration = len - g.clearance;
    if penetration <= -reach {
        return;
    }
    let n = radial_normal(d, len, x.axis_b);
    let wall = x.centre_b + x.axis_b * station + n * T::constant(g.r_bearing);
    out.push(split(
        index,
        n,
        penetration,
        T::constant(CylinderBearing::END_SHARE),
        (MaterialPoint3::of(g.bearing, bearing, wall), bearing),
        (MaterialPoint3::of(g.journal, journal, end + n * T::constant(g.r_journal)), journal),
    ));
}

/// The contact points of the journal's end faces against the bearing's thrust faces,
/// where it has them ([`contact_cylinder_bearing`]).
#[inline]
fn thrust_faces<T: Real>(
    g: &CylinderBearing,
    x: &Axes<T>,
    bearing: &BodyState<T>,
    journal: &BodyState<T>,
    reach: f64,
    out: &mut ContactPoints3<T>,
) {
    let Some(c_a) = g.axial_clearance else { return };
    let half = 0.5 * g.length;
    let h = half + c_a;
    // The journal end that faces the bearing's + face, and the in-face direction of its
    // rim point farthest along the bearing axis.
    let facing = if x.axis_b.dot(&x.axis_j) >= 0.0 { 1.0 } else { -1.0 };
    let lean = x.axis_b - x.axis_j * x.axis_b.dot(&x.axis_j);
    let lean_len = norm(&lean);
    let rim = if lean_len > 1e-15 { lean * (T::constant(g.r_journal) / lean_len) } else { Vector3::zeros() };
    for (index, side) in [(2, -1.0), (3, 1.0)] {
        let n = x.axis_b * T::constant(side);
        let point_j = x.centre_j + x.axis_j * T::constant(side * facing * half) + rim * T::constant(side);
        let penetration = n.dot(&(point_j - x.centre_b)) - h;
        if penetration <= -reach {
            continue;
        }
        out.push(split(
            index,
            n,
            penetration,
            T::constant(1.0),
            (MaterialPoint3::of(g.bearing, bearing, point_j - n * penetration), bearing),
            (MaterialPoint3::of(g.journal, journal, point_j), journal),
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanics::contact::geometry::spatial_checks::{
        check_arms_by_virtual_work, check_rate_and_slip_by_motion,
    };
    use crate::mechanics::spatial::body::Orientation;

    const C: f64 = 0.0002;
    const C_A: f64 = 0.0005;
    const L: f64 = 0.03;
    const R_J: f64 = 0.0098;
    const R_B: f64 = 0.01;

    /// A bearing of radius 10 mm, 0.2 mm radial and 0.5 mm axial clearance, its centre at
    /// (20, 10, -30) mm on a turned body, its axis a skew unit vector of that body; a
    /// journal 30 mm long, its centre at (-10, 40, 0) mm on its own body, along another.
    fn joint() -> CylinderBearing {
        CylinderBearing {
            bearing: Some(0),
            s_bearing: Vec3::new(0.02, 0.01, -0.03),
            u_bearing: Vec3::new(0.2, -0.3, 0.9).normalize(),
            journal: Some(1),
            s_journal: Vec3::new(-0.01, 0.04, 0.0),
            u_journal: Vec3::new(-0.5, 0.1, 0.3).normalize(),
            r_bearing: R_B,
            r_journal: R_J,
            clearance: C,
            length: L,
            axial_clearance: Some(C_A),
            worn: None,
        }
    }

    fn bearing_body() -> BodyState {
        let e = Orientation::from_scaled_axis(Vec3::new(0.3, -0.2, 0.9));
        BodyState::new(Vec3::new(0.1, 0.2, 0.3), e, Vec3::new(0.4, -0.1, 0.2), Vec3::new(3.0, -2.0, 5.0))
    }

    /// The bearing's centre, its axis `a`, and a unit radial direction `m` normal to it,
    /// global.
    fn frame(g: &CylinderBearing, b: &BodyState) -> (Vec3, Vec3, Vec3) {
        let a = b.orientation() * g.u_bearing;
        (b.r + b.orientation() * g.s_bearing, a, a.cross(&Vec3::new(1.0, 2.0, 3.0)).normalize())
    }

    /// The journal body with its centre at `centre` and its axis along `axis` (both
    /// global), turned by `spin` about its axis, with velocity `v` and body spin `omega`.
    fn journal_at(
        g: &CylinderBearing,
        centre: Vec3,
        axis: Vec3,
        spin: f64,
        v: Vec3,
        omega: Vec3,
    ) -> BodyState {
        let align = Orientation::rotation_between(&g.u_journal, &axis).expect("not opposite");
        let e = align * Orientation::from_scaled_axis(g.u_journal * spin);
        BodyState::new(centre - e * g.s_journal, e, v, omega)
    }

    fn all(g: &CylinderBearing, b: &BodyState, j: &BodyState) -> ContactPoints3 {
        let mut out = ContactPoints3::new();
        contact_cylinder_bearing(g, b, j, f64::INFINITY, &mut out);
        out
    }

    /// The journal centre placed at radial offset `e0` along `m` and axial shift `u`,
    /// its axis tilted by `theta` towards `m` (`a_J = cos(theta) a + sin(theta) m`): by
    /// hand, its ends lie `(L/2) cos(theta)` along `a` and `e0 +- (L/2) sin(theta)` along
    /// `m` from the bearing centre; the end faces' rim points nearest the thrust faces
    /// reach `R_J sin(theta)` farther along `+-a` than the end centres.
    #[test]
    fn tilted_journal_against_hand_geometry() {
        let g = joint();
        let b = bearing_body();
        let (centre_b, a, m) = frame(&g, &b);
        let half = L / 2.0;
        // (e0, theta, u): one end touches; the other end touches; aligned, both ends
        // equally deep and a thrust face touching; the diagonal jam at zero offset.
        let tilt_one = f64::asin((C / 2.0 + 1e-5) / half);
        let tilt_jam = f64::asin((C + 3e-5) / half);
        for (e0, theta, u) in [
            (C / 2.0, tilt_one, 0.0),
            (-C / 2.0, -tilt_one, 1e-4),
            (C + 2e-5, 0.0, C_A + 3e-5),
            (0.0, tilt_jam, -C_A),
        ] {
            let axis = a * theta.cos() + m * theta.sin();
            let journal = journal_at(&g, centre_b + m * e0 + a * u, axis, 0.7, Vec3::zeros(), Vec3::zeros());
            let points = all(&g, &b, &journal);
            assert_eq!(points.len(), 4);
            let offsets = g.end_offsets(&b, &journal);
            for (k, side) in [(0, -1.0), (1, 1.0)] {
                let p = points[k];
                let radial = e0 + side * half * theta.sin(); // signed, along m
                assert!((offsets[k] - m * radial).norm() < 1e-15, "end {k}: offset {:?}", offsets[k]);
                let station = u + side * half * theta.cos(); // along a
                let n = m * radial.signum();
                let case = format!("e0 {e0}, theta {theta}, end {k}");
                assert_eq!((p.index, p.share), (k, 0.5), "{case}");
                assert!((p.penetration - (radial.abs() - C)).abs() < 1e-15, "{case}: {}", p.penetration);
                assert!((p.normal - n).norm() < 1e-10, "{case}: {:?}", p.normal);
                let on_axis = centre_b + a * station;
                // Round-off of positions (1e-17 m) over an offset of 10 um turns the
                // normal by 1e-12 rad, the points at a radius by 1e-14 m.
                assert!((p.on_j.at - (on_axis + n * (radial.abs() + R_J))).norm() < 1e-12, "{case}");
                assert!((p.on_i.at - (on_axis + n * R_B)).norm() < 1e-12, "{case}");
            }
            for (k, side) in [(2, -1.0), (3, 1.0)] {
                let p = points[k];
                let depth = side * u + half * theta.cos() + R_J * theta.sin().abs() - (half + C_A);
                let case = format!("e0 {e0}, theta {theta}, face {k}");
                assert_eq!((p.index, p.share), (k, 1.0), "{case}");
                // Round-off: positions 0.3 m from the origin, a tilt from unit vectors.
                assert!((p.penetration - depth).abs() < 1e-14, "{case}: {} vs {depth}", p.penetration);
                assert!((p.normal - a * side).norm() < 1e-12, "{case}");
                assert!((p.on_j.at - p.on_i.at - p.normal * p.penetration).norm() < 1e-15, "{case}");
                // The face point lies on the face's plane.
                assert!((a.dot(&(p.on_i.at - centre_b)) - side * (half + C_A)).abs() < 1e-14, "{case}");
            }
        }
    }

    /// A tilted journal touches at one end first: with a contact law's reach only one
    /// end is returned, the end that the tilt moves towards the side the centre is
    /// offset to (end 1, at `+L/2`, when offset and tilt lean the same way along `m`).
    #[test]
    fn tilted_journal_touches_at_one_end_first() {
        let g = joint();
        let b = bearing_body();
        let (centre_b, a, m) = frame(&g, &b);
        let theta = f64::asin((C / 2.0 + 1e-5) / (L / 2.0));
        for (offset, tilt, end) in [(1.0, 1.0, 1), (1.0, -1.0, 0), (-1.0, 1.0, 0), (-1.0, -1.0, 1)] {
            let axis = a * theta.cos() + m * (tilt * theta.sin());
            let journal =
                journal_at(&g, centre_b + m * (offset * C / 2.0), axis, 0.0, Vec3::zeros(), Vec3::zeros());
            let mut out = ContactPoints3::new();
            contact_cylinder_bearing(&g, &b, &journal, 0.0, &mut out);
            let touching: Vec<usize> = out.iter().map(|p| p.index).collect();
            assert_eq!(touching, vec![end], "offset {offset}, tilt {tilt}");
            assert!((out[0].penetration - 1e-5).abs() < 1e-15);
            assert!((out[0].normal - m * offset).norm() < 1e-10);
            // The end force's moment about the journal centre: the force times its arm
            // (L/2) cos(theta) (the end's reach normal to n), about the axis a x m, the
            // way that turns the journal back from its tilt (a tilt towards +m of end
            // 1 turns it about +a x m).
            let p = out[0];
            let f = p.force_on_j(250.0, &Vec3::zeros());
            let centre = centre_b + m * (offset * C / 2.0);
            let moment = (p.on_j.at - centre).cross(&f);
            let arm = L / 2.0 * theta.cos();
            let sign = if end == 1 { -1.0 } else { 1.0 } * offset;
            let expected = a.cross(&m) * (sign * 250.0 * arm);
            assert!((moment - expected).norm() < 1e-9 * 250.0 * arm, "{moment:?} vs {expected:?}");
        }
    }

    /// In planar motion (both axes along z, the bodies turning about z) the journal's
    /// two ends are the planar journal in its bearing, each with half its law: the
    /// planar kernel's penetration, normal, rate, slip (along `t = perp(n)`) and
    /// points, against the spatial kernel's; round, and worn (a bearing worn into a
    /// pocket narrower than the journal's path, whose rims both touch, and a journal worn
    /// flat at one side) against the planar worn kernel's rims.
    #[test]
    fn aligned_planar_motion_is_the_planar_journal() {
        use crate::error::Named;
        use crate::math::{rotate, Vec2};
        use crate::mechanics::contact::geometry::{contact_journal_bearing, contact_worn, JournalBearing};
        use crate::mechanics::contact::ContactPoints;
        use crate::mechanics::planar_body;
        let z = Vec3::z();
        let round = CylinderBearing {
            s_bearing: Vec3::new(0.02, -0.005, 0.0),
            u_bearing: z,
            s_journal: Vec3::new(-0.03, 0.0, 0.0),
            u_journal: z,
            axial_clearance: None,
            ..joint()
        };
        let flat = JournalBearing {
            bearing: Some(0),
            s_bearing: Vec2::new(0.02, -0.005),
            journal: Some(1),
            s_journal: Vec2::new(-0.03, 0.0),
            r_bearing: R_B,
            r_journal: R_J,
            clearance: C,
        };
        let lift = |b: &planar_body::BodyState| {
            BodyState::new(
                Vec3::new(b.r.x, b.r.y, 0.0),
                Orientation::from_scaled_axis(z * b.phi()),
                Vec3::new(b.v.x, b.v.y, 0.0),
                z * b.omega,
            )
        };
        let bearing = planar_body::BodyState::new(Vec2::new(0.1, 0.2), 0.3, Vec2::new(0.2, -0.1), 2.5);
        // A pocket 30 um deep, 8 degrees either side of the first eccentricity's direction
        // in the bearing's frame; the journal worn 5 um over a quarter of its round.
        let pocket = (-1.0f64).atan2(1.5) - 0.3;
        let bearing_wear: Vec<f64> = (0..360)
            .map(|k| {
                let d = (k as f64).to_radians() - pocket;
                let d = (d + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
                3e-5 * (1.0 - (d / 8f64.to_radians()).powi(2)).max(0.0)
            })
            .collect();
        let journal_wear: Vec<f64> =
            (0..72).map(|k| 5e-6 * (k as f64 * 5f64.to_radians()).cos().max(0.0).powi(2)).collect();
        let worn = Worn::new(Named::joint("c"), (Some(&bearing_wear), Some(&journal_wear)), R_J).unwrap();
        let centre_b = bearing.r + rotate(bearing.phi(), flat.s_bearing);
        let mut rims = 0;
        for (e, phi) in [(Vec2::new(0.00015, -0.0001), 1.1), (Vec2::new(-0.0002, 0.00007), -2.0)] {
            let centre = centre_b + e - rotate(phi, flat.s_journal);
            let journal = planar_body::BodyState::new(centre, phi, Vec2::new(0.7, -0.4), -30.0);
            for (g, reach) in [
                (round.clone(), f64::INFINITY),
                (CylinderBearing { worn: worn.clone().map(Box::new), ..round.clone() }, 1e-3),
            ] {
                let mut planar = ContactPoints::new();
                match &g.worn {
                    Some(w) => contact_worn(&flat, w, &bearing, &journal, reach, &mut planar),
                    None => contact_journal_bearing(&flat, &bearing, &journal, reach, &mut planar),
                }
                let mut spatial = ContactPoints3::new();
                contact_cylinder_bearing(&g, &lift(&bearing), &lift(&journal), reach, &mut spatial);
                assert_eq!(spatial.len(), 2 * planar.len());
                rims = rims.max(planar.len());
                for k in 0..2 {
                    for (p, q) in spatial.iter().filter(|p| p.index == k).zip(planar.iter()) {
                        let t = crate::math::perp(q.normal);
                        assert!((p.penetration - q.penetration).abs() < 1e-15, "end {k}");
                        assert!(
                            (p.normal - Vec3::new(q.normal.x, q.normal.y, 0.0)).norm() < 1e-12,
                            "end {k}"
                        );
                        assert!((p.penetration_rate - q.penetration_rate).abs() < 1e-12, "end {k}");
                        assert!((p.slip - Vec3::new(t.x, t.y, 0.0) * q.slip[0]).norm() < 1e-12, "end {k}");
                        let on_j = Vec2::new(p.on_j.at.x, p.on_j.at.y);
                        let on_i = Vec2::new(p.on_i.at.x, p.on_i.at.y);
                        assert!(
                            (on_j - q.on_j.at).norm() < 1e-14 && (on_i - q.on_i.at).norm() < 1e-14,
                            "end {k}"
                        );
                        assert!(p.share == 0.5 * q.share, "end {k}");
                        assert!((p.on_j.at.z - (2.0 * k as f64 - 1.0) * L / 2.0).abs() < 1e-15, "end {k}");
                    }
                }
            }
        }
        assert!(rims >= 2, "the pocket's two rims");
    }

    /// A journal whose own axis points against the bearing's: the ends swap indices and
    /// the thrust faces still meet the ends that face them, at the same depths.
    #[test]
    fn reversed_journal_axis_meets_the_same_faces() {
        let g = joint();
        let reversed = CylinderBearing { u_journal: -g.u_journal, ..joint() };
        let b = bearing_body();
        let (centre_b, a, m) = frame(&g, &b);
        let axis = a * 0.01f64.cos() + m * 0.01f64.sin();
        let centre = centre_b + m * 1e-4 + a * 2e-4;
        let p = all(&g, &b, &journal_at(&g, centre, axis, 0.0, Vec3::zeros(), Vec3::zeros()));
        let q = all(&reversed, &b, &journal_at(&reversed, centre, -axis, 0.0, Vec3::zeros(), Vec3::zeros()));
        for (k, k_reversed) in [(0, 1), (1, 0), (2, 2), (3, 3)] {
            assert!((p[k].penetration - q[k_reversed].penetration).abs() < 1e-15, "point {k}");
            assert!((p[k].on_j.at - q[k_reversed].on_j.at).norm() < 1e-14, "point {k}");
        }
    }

    /// The rates are the time derivatives of the penetrations, the slips the relative
    /// velocities of the material points less their normal parts, for all four points of
    /// a tilted, offset, moving and spinning journal in a moving bearing.
    #[test]
    fn rate_and_slip_by_motion() {
        let g = joint();
        let b = bearing_body();
        let (centre_b, a, m) = frame(&g, &b);
        let axis = (a + m * 0.004 + a.cross(&m) * 0.003).normalize();
        let centre = centre_b + m * 5e-5 + a.cross(&m) * 8e-5 + a * 1e-4;
        let journal =
            journal_at(&g, centre, axis, 1.3, Vec3::new(-0.5, 0.9, 0.3), Vec3::new(6.0, -7.0, 20.0));
        check_rate_and_slip_by_motion(&b, &journal, &|i, j| all(&g, i, j), 4);
        // Grounded bearing, no thrust faces.
        let g0 = CylinderBearing { bearing: None, axial_clearance: None, ..joint() };
        let ground = BodyState::ground();
        let (centre_b, a, m) = frame(&g0, &ground);
        let axis = (a - m * 0.005).normalize();
        let journal = journal_at(
            &g0,
            centre_b + m * 1e-4,
            axis,
            0.2,
            Vec3::new(0.3, 0.0, -0.2),
            Vec3::new(0.0, 15.0, 3.0),
        );
        check_rate_and_slip_by_motion(&ground, &journal, &|i, j| all(&g0, i, j), 2);
    }

    /// The arms: each point's normal force has the moments that virtual work along small
    /// rotations of either body calls for (tilted, so that the thrust rim point is
    /// defined).
    #[test]
    fn arms_by_virtual_work() {
        let g = joint();
        let b = bearing_body();
        let (centre_b, a, m) = frame(&g, &b);
        let axis = (a + m * 0.006 - a.cross(&m) * 0.002).normalize();
        let centre = centre_b + m * 6e-5 - a.cross(&m) * 9e-5 - a * 3e-4;
        let journal = journal_at(&g, centre, axis, -0.4, Vec3::zeros(), Vec3::zeros());
        check_arms_by_virtual_work(&b, &journal, &|i, j| all(&g, i, j), 4);
    }

    /// Worn parts (a bearing worn 20 um into an oval, a journal worn at two opposite
    /// sides), the journal aligned (no thrust faces) and on the move about every axis: each end's rate and
    /// slip against the motion, and its arms against virtual work, as the round joint's.
    #[test]
    fn worn_ends_pass_the_rate_slip_and_arm_checks() {
        use crate::error::Named;
        let table = |n: usize, f: &dyn Fn(f64) -> f64| -> Vec<f64> {
            (0..n).map(|k| f(std::f64::consts::TAU * k as f64 / n as f64)).collect()
        };
        let (bearing_wear, journal_wear) =
            (table(72, &|t| 1e-5 * (1.0 + (2.0 * t).cos())), table(36, &|t| 3e-6 * (1.0 + (2.0 * t).cos())));
        let worn = Worn::new(Named::joint("c"), (Some(&bearing_wear), Some(&journal_wear)), R_J).unwrap();
        let g = CylinderBearing { worn: worn.map(Box::new), axial_clearance: None, ..joint() };
        let b = bearing_body();
        let (centre_b, a, m) = frame(&g, &b);
        let centre = centre_b + m * 1.5e-4 + a.cross(&m) * 8e-5 + a * 1e-4;
        let journal = journal_at(&g, centre, a, 1.3, Vec3::new(-0.5, 0.9, 0.3), Vec3::new(6.0, -7.0, 20.0));
        check_rate_and_slip_by_motion(&b, &journal, &|i, j| all(&g, i, j), 2);
        check_arms_by_virtual_work(&b, &journal, &|i, j| all(&g, i, j), 2);
    }

    /// A centred, aligned journal: finite everything; the ends' gaps the radial
    /// clearance with unit normals normal to the bearing axis, the faces' the axial
    /// clearance with the end centres as their points.
    #[test]
    fn centred_journal_is_finite() {
        let g = joint();
        let b = bearing_body();
        let (centre_b, a, _) = frame(&g, &b);
        let journal = journal_at(&g, centre_b, a, 0.0, Vec3::new(0.1, 0.2, 0.3), Vec3::new(0.0, 0.0, 10.0));
        let points = all(&g, &b, &journal);
        for p in points.iter() {
            let finite =
                [p.penetration, p.penetration_rate, p.slip.norm(), p.on_i.at.norm(), p.on_j.at.norm()];
            assert!(finite.iter().all(|x| x.is_finite()), "point {}", p.index);
            assert!((p.normal.norm() - 1.0).abs() < 1e-12, "point {}", p.index);
        }
        for k in [0, 1] {
            assert!((points[k].penetration + C).abs() < 1e-15);
            assert!(points[k].normal.dot(&a).abs() < 1e-12);
        }
        for (k, side) in [(2, -1.0), (3, 1.0)] {
            assert!((points[k].penetration + C_A).abs() < 1e-15);
            assert!((points[k].on_j.at - (centre_b + a * (side * L / 2.0))).norm() < 1e-15);
        }
    }

    /// Without thrust faces the joint has its two ends only.
    #[test]
    fn thrust_faces_only_with_an_axial_clearance() {
        let g = CylinderBearing { axial_clearance: None, ..joint() };
        assert_eq!((g.points(), joint().points()), (2, 4));
        let b = bearing_body();
        let (centre_b, a, _) = frame(&g, &b);
        let journal = journal_at(&g, centre_b + a * 0.01, a, 0.0, Vec3::zeros(), Vec3::zeros());
        assert_eq!(all(&g, &b, &journal).len(), 2);
    }
}
