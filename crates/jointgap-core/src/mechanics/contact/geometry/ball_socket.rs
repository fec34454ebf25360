//! A ball (on body j) in a spherical socket (on body i): a spherical joint with
//! clearance. One contact point, on the line through the two centres
//! (docs/spatial-clearance.md, "Ball in socket"; Flores, Ambrosio, Claro, Lankarani
//! 2006-2008 on spherical clearance joints).

use nalgebra::Vector3;

use crate::mechanics::contact::point3::{split, ContactPoints3, MaterialPoint3};
use crate::mechanics::spatial::body::{constant, BodyState, Vec3};
use crate::scalar::{norm, Real};

/// Where a ball and its socket are, and their sizes.
#[derive(Debug, Clone, PartialEq)]
pub struct BallSocket {
    /// Socket body (`None`: ground).
    pub socket: Option<usize>,
    /// Socket centre in the socket body's frame [m].
    pub s_socket: Vec3,
    /// Ball body.
    pub ball: Option<usize>,
    /// Ball centre in the ball body's frame [m].
    pub s_ball: Vec3,
    /// Socket radius `R_S` [m].
    pub r_socket: f64,
    /// Ball radius `R_B` [m].
    pub r_ball: f64,
    /// Radial clearance `c = R_S - R_B` [m].
    pub clearance: f64,
}

impl BallSocket {
    /// Contact points a ball in its socket has: one.
    pub const POINTS: usize = 1;

    /// The socket's and the ball's centres, global [m].
    #[inline]
    fn centres<T: Real>(&self, socket: &BodyState<T>, ball: &BodyState<T>) -> (Vector3<T>, Vector3<T>) {
        (socket.r + socket.rotate(&constant(&self.s_socket)), ball.r + ball.rotate(&constant(&self.s_ball)))
    }

    /// Eccentricity `e = r_B - r_S`: the ball centre from the socket centre, global [m].
    pub fn eccentricity(&self, socket: &BodyState, ball: &BodyState) -> Vec3 {
        let (centre_s, centre_b) = self.centres(socket, ball);
        centre_b - centre_s
    }
}

/// The contact point of ball and socket, pushed onto `out` unless the gap is `reach` [m]
/// or more. With eccentricity `e = r_B - r_S`: normal `n = e / |e|` (from the socket
/// centre towards the ball's), penetration `|e| - c`, the material points `r_B + R_B n`
/// on the ball and `r_S + R_S n` on the socket, and the relative velocity of the ball's
/// point to the socket's split into the rate along `n` and the slip across it. Both
/// points lie on the line of centres, so the normal force has no moment about either
/// centre: only the friction force turns the ball in its socket. A centred ball (`|e|`
/// below 1e-15 m) takes the global x axis as its normal, as the planar journal does: its
/// gap is the whole clearance and no force acts, so any unit normal gives the same (zero)
/// loads, and a fixed one keeps every output finite.
#[inline]
pub fn contact_ball_socket<T: Real>(
    g: &BallSocket,
    socket: &BodyState<T>,
    ball: &BodyState<T>,
    reach: f64,
    out: &mut ContactPoints3<T>,
) {
    let (centre_s, centre_b) = g.centres(socket, ball);
    let e = centre_b - centre_s;
    let ecc = norm(&e);
    let penetration = ecc - g.clearance;
    if penetration <= -reach {
        return;
    }
    let n = if ecc > 1e-15 { e / ecc } else { Vector3::x() };
    out.push(split(
        0,
        n,
        penetration,
        T::constant(1.0),
        (MaterialPoint3::of(g.socket, socket, centre_s + n * T::constant(g.r_socket)), socket),
        (MaterialPoint3::of(g.ball, ball, centre_b + n * T::constant(g.r_ball)), ball),
    ));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanics::contact::geometry::spatial_checks::{
        check_arms_by_virtual_work, check_rate_and_slip_by_motion,
    };
    use crate::mechanics::spatial::body::Orientation;

    /// A socket of radius 12 mm with 0.2 mm clearance, its centre at (20, -5, 10) mm on a
    /// body at (0.1, 0.2, 0.3) m, turned; the ball's centre at (-30, 0, 15) mm on its own.
    fn joint() -> BallSocket {
        BallSocket {
            socket: Some(0),
            s_socket: Vec3::new(0.02, -0.005, 0.01),
            ball: Some(1),
            s_ball: Vec3::new(-0.03, 0.0, 0.015),
            r_socket: 0.012,
            r_ball: 0.0118,
            clearance: 0.0002,
        }
    }

    fn socket_body() -> BodyState {
        let e = Orientation::from_scaled_axis(Vec3::new(0.3, -0.2, 0.9));
        BodyState::new(Vec3::new(0.1, 0.2, 0.3), e, Vec3::new(0.4, -0.1, 0.2), Vec3::new(3.0, -2.0, 5.0))
    }

    /// The ball body placed so that its centre lies at `e` from the socket centre, turned
    /// by `turn` (a rotation vector), with velocity `v` and body-frame spin `omega`.
    fn ball_at(g: &BallSocket, socket: &BodyState, e: Vec3, turn: Vec3, v: Vec3, omega: Vec3) -> BodyState {
        let orientation = Orientation::from_scaled_axis(turn);
        let centre = socket.r + socket.rotate(&g.s_socket) + e;
        BodyState::new(centre - orientation * g.s_ball, orientation, v, omega)
    }

    fn all(g: &BallSocket, s: &BodyState, b: &BodyState) -> ContactPoints3 {
        let mut out = ContactPoints3::new();
        contact_ball_socket(g, s, b, f64::INFINITY, &mut out);
        out
    }

    /// The ball's centre placed at a known offset `ecc` along a known direction `d` (in
    /// spherical angles): the normal is `d`, the penetration `ecc - c`, the points on
    /// the line of centres at each radius from the socket centre.
    #[test]
    fn point_against_placement() {
        let g = joint();
        let socket = socket_body();
        let centre_s = Vec3::new(0.1, 0.2, 0.3) + socket.orientation() * Vec3::new(0.02, -0.005, 0.01);
        for (ecc, polar, azimuth) in
            [(0.0001, 0.4, 1.0), (0.0002, 2.0, -2.0), (0.00025, 3.0, 0.3), (0.0004, 1.2, 3.1)]
        {
            let (sp, cp) = f64::sin_cos(polar);
            let (sa, ca) = f64::sin_cos(azimuth);
            let d = Vec3::new(sp * ca, sp * sa, cp);
            let ball = ball_at(&g, &socket, d * ecc, Vec3::new(-0.5, 0.2, 1.4), Vec3::zeros(), Vec3::zeros());
            let points = all(&g, &socket, &ball);
            assert_eq!(points.len(), 1);
            let p = points[0];
            assert_eq!((p.index, p.share), (0, 1.0));
            assert!((p.normal - d).norm() < 1e-10, "{ecc}: normal {:?} vs {d:?}", p.normal);
            assert!((p.penetration - (ecc - 0.0002)).abs() < 1e-15, "{ecc}: {}", p.penetration);
            assert!((p.on_j.at - (centre_s + d * (ecc + 0.0118))).norm() < 1e-14);
            assert!((p.on_i.at - (centre_s + d * 0.012)).norm() < 1e-14);
            assert_eq!((p.on_i.body, p.on_j.body), (Some(0), Some(1)));
            assert!((p.on_j.arm - (p.on_j.at - ball.r)).norm() < 1e-15);
            assert!((p.on_i.arm - (p.on_i.at - socket.r)).norm() < 1e-15);
        }
    }

    /// The rate is the time derivative of the penetration, and the slip the relative
    /// velocity of the two material points less its normal part, both by differences of
    /// placements as the bodies move (`r + v t`, `e exp(w' t)`).
    #[test]
    fn rate_and_slip_by_motion() {
        let g = joint();
        let socket = socket_body();
        let ball = ball_at(
            &g,
            &socket,
            Vec3::new(0.00015, -0.0001, 0.00012),
            Vec3::new(-0.5, 0.2, 1.4),
            Vec3::new(-0.5, 0.9, 0.3),
            Vec3::new(12.0, -7.0, 20.0),
        );
        let contact = |s: &BodyState, b: &BodyState| all(&g, s, b);
        check_rate_and_slip_by_motion(&socket, &ball, &contact, 1);
        // The ground as the socket body too.
        let ground = BodyState::ground();
        let g0 = BallSocket { socket: None, ..joint() };
        let ball = ball_at(
            &g0,
            &ground,
            Vec3::new(0.0002, 0.0001, -0.0001),
            Vec3::zeros(),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 30.0, 0.0),
        );
        check_rate_and_slip_by_motion(&ground, &ball, &|s, b| all(&g0, s, b), 1);
    }

    /// The arms: the normal force at each body's material point has the moment a small
    /// rotation of that body does virtual work against (the penetration's gradient).
    #[test]
    fn arms_by_virtual_work() {
        let g = joint();
        let socket = socket_body();
        let ball = ball_at(
            &g,
            &socket,
            Vec3::new(0.00021, 0.00005, -0.0001),
            Vec3::new(0.4, 0.1, -0.3),
            Vec3::zeros(),
            Vec3::zeros(),
        );
        check_arms_by_virtual_work(&socket, &ball, &|s, b| all(&g, s, b), 1);
    }

    /// In planar motion (centres in the xy plane, the bodies turning about z) the ball
    /// in its socket is the planar journal in its bearing: the planar kernel's
    /// penetration, normal, rate, slip (along `t = perp(n)`) and points.
    #[test]
    fn planar_motion_is_the_planar_journal() {
        use crate::math::{perp, rotate, Vec2};
        use crate::mechanics::contact::geometry::{contact_journal_bearing, JournalBearing};
        use crate::mechanics::contact::ContactPoints;
        use crate::mechanics::planar_body;
        let g = BallSocket {
            s_socket: Vec3::new(0.02, -0.005, 0.0),
            s_ball: Vec3::new(-0.03, 0.0, 0.0),
            ..joint()
        };
        let flat = JournalBearing {
            bearing: Some(0),
            s_bearing: Vec2::new(0.02, -0.005),
            journal: Some(1),
            s_journal: Vec2::new(-0.03, 0.0),
            r_bearing: g.r_socket,
            r_journal: g.r_ball,
            clearance: g.clearance,
        };
        let lift = |b: &planar_body::BodyState| {
            BodyState::new(
                Vec3::new(b.r.x, b.r.y, 0.0),
                Orientation::from_scaled_axis(Vec3::z() * b.phi()),
                Vec3::new(b.v.x, b.v.y, 0.0),
                Vec3::z() * b.omega,
            )
        };
        let socket = planar_body::BodyState::new(Vec2::new(0.1, 0.2), 0.3, Vec2::new(0.2, -0.1), 2.5);
        let centre_s = socket.r + rotate(socket.phi(), flat.s_bearing);
        for (e, phi) in [(Vec2::new(0.00015, -0.0001), 1.1), (Vec2::new(-0.0002, 0.00007), -2.0)] {
            let centre = centre_s + e - rotate(phi, flat.s_journal);
            let ball = planar_body::BodyState::new(centre, phi, Vec2::new(0.7, -0.4), -30.0);
            let mut planar_points = ContactPoints::new();
            contact_journal_bearing(&flat, &socket, &ball, f64::INFINITY, &mut planar_points);
            let q = planar_points[0];
            let t = perp(q.normal);
            let p = all(&g, &lift(&socket), &lift(&ball))[0];
            assert!((p.penetration - q.penetration).abs() < 1e-15);
            assert!((p.normal - Vec3::new(q.normal.x, q.normal.y, 0.0)).norm() < 1e-12);
            assert!((p.penetration_rate - q.penetration_rate).abs() < 1e-12);
            assert!((p.slip - Vec3::new(t.x, t.y, 0.0) * q.slip[0]).norm() < 1e-12);
            assert!((Vec2::new(p.on_j.at.x, p.on_j.at.y) - q.on_j.at).norm() < 1e-14);
            assert!((Vec2::new(p.on_i.at.x, p.on_i.at.y) - q.on_i.at).norm() < 1e-14);
        }
    }

    /// A centred ball: finite everything, the gap the whole clearance, the x axis as the
    /// normal, the slip the relative velocity's part across it.
    #[test]
    fn centred_ball_is_finite() {
        let g = joint();
        let socket = socket_body();
        let ball = ball_at(
            &g,
            &socket,
            Vec3::zeros(),
            Vec3::zeros(),
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(0.0, 0.0, 10.0),
        );
        let p = all(&g, &socket, &ball)[0];
        assert!((p.penetration + g.clearance).abs() < 1e-15);
        assert_eq!(p.normal, Vec3::x());
        for x in [p.penetration_rate, p.slip.x, p.slip.y, p.slip.z, p.on_i.at.norm(), p.on_j.at.norm()] {
            assert!(x.is_finite());
        }
        assert_eq!(p.slip.x, 0.0);
    }

    /// Within the laws' reach only: a contact law (reach 0) gets no point apart and the
    /// point in contact; an infinite reach gets it always.
    #[test]
    fn reach_selects_the_point() {
        let g = joint();
        let socket = BodyState::ground();
        for (ecc, touching) in [(0.0001, false), (0.000199, false), (0.00021, true)] {
            let ball =
                ball_at(&g, &socket, Vec3::new(0.0, 0.0, -ecc), Vec3::zeros(), Vec3::zeros(), Vec3::zeros());
            let mut out = ContactPoints3::new();
            contact_ball_socket(&g, &socket, &ball, 0.0, &mut out);
            assert_eq!(out.len(), usize::from(touching), "eccentricity {ecc}");
            assert_eq!(all(&g, &socket, &ball).len(), 1);
        }
    }
}
