//! A round journal (pin on body j) in a round bearing (hole on body i): one contact
//! point, on the line through the two centres (docs/physics.md section 2).

use crate::math::Vec2;
use crate::mechanics::contact::point::{ContactPoint, ContactPoints, MaterialPoint};
use crate::mechanics::planar_body::BodyState;
use crate::scalar::{norm, Real};

/// Where a journal and its bearing are, and their sizes.
#[derive(Debug, Clone, PartialEq)]
pub struct JournalBearing {
    /// Bearing body (`None`: ground).
    pub bearing: Option<usize>,
    /// Bearing centre in the bearing body frame [m].
    pub s_bearing: Vec2,
    /// Journal body.
    pub journal: Option<usize>,
    /// Journal centre in the journal body frame [m].
    pub s_journal: Vec2,
    /// Bearing radius [m].
    pub r_bearing: f64,
    /// Journal radius [m].
    pub r_journal: f64,
    /// Radial clearance [m].
    pub clearance: f64,
}

impl JournalBearing {
    /// Contact points a journal in its bearing has: one.
    pub const POINTS: usize = 1;

    /// The bearing's and the journal's centres, global [m].
    #[inline]
    pub fn centres<T: Real>(&self, bearing: &BodyState<T>, journal: &BodyState<T>) -> (Vec2<T>, Vec2<T>) {
        (bearing.r + bearing.rotate(self.s_bearing), journal.r + journal.rotate(self.s_journal))
    }

    /// Eccentricity `r_J - r_B`: the journal centre from the bearing centre, global [m].
    pub fn eccentricity(&self, bearing: &BodyState, journal: &BodyState) -> Vec2 {
        let (centre_b, centre_j) = self.centres(bearing, journal);
        centre_j - centre_b
    }
}

/// The contact point of journal and bearing, pushed onto `out` unless the gap is `reach`
/// [m] or more. With eccentricity `e = r_J - r_B`: normal `n = e / |e|` (from the
/// bearing centre towards the journal), penetration `|e| - c`, the material points
/// `r_J + R_J n` on the journal and `r_B + R_B n` on the bearing, and the relative
/// velocity `v` of the journal's point to the bearing's split along `n` and the tangent.
#[inline]
pub fn contact_journal_bearing<T: Real>(
    g: &JournalBearing,
    bearing: &BodyState<T>,
    journal: &BodyState<T>,
    reach: f64,
    out: &mut ContactPoints<T>,
) {
    let (centre_b, centre_j) = g.centres(bearing, journal);
    let e = centre_j - centre_b;
    let ecc = norm(&e);
    let penetration = ecc - g.clearance;
    if penetration <= -reach {
        return;
    }
    // Concentric: any normal will do; the force is zero there.
    let n = if ecc > 1e-15 { e / ecc } else { Vec2::new(T::constant(1.0), T::constant(0.0)) };
    let point_journal = centre_j + n * T::constant(g.r_journal);
    let point_bearing = centre_b + n * T::constant(g.r_bearing);
    let v = journal.velocity_at(point_journal) - bearing.velocity_at(point_bearing);
    out.push(ContactPoint::in_bearing(
        n,
        penetration,
        v,
        T::constant(1.0),
        (
            MaterialPoint { body: g.bearing, at: point_bearing },
            MaterialPoint { body: g.journal, at: point_journal },
        ),
    ));
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::math::{perp, rotate};

    /// A bearing of radius 10 mm with 0.5 mm clearance, its centre at (20, -5) mm on a body
    /// at (0.1, 0.2) m turned by 0.3 rad; the journal's centre at (-30, 0) mm on its own.
    pub(crate) fn joint() -> JournalBearing {
        JournalBearing {
            bearing: Some(0),
            s_bearing: Vec2::new(0.02, -0.005),
            journal: Some(1),
            s_journal: Vec2::new(-0.03, 0.0),
            r_bearing: 0.01,
            r_journal: 0.0095,
            clearance: 0.0005,
        }
    }

    /// The journal body placed so that its centre is at eccentricity `e` from the bearing
    /// centre, turned by `phi`, with centre velocity `v_centre` and spin `omega`.
    pub(crate) fn journal_at(
        g: &JournalBearing,
        bearing: &BodyState,
        e: Vec2,
        phi: f64,
        v_centre: Vec2,
        omega: f64,
    ) -> BodyState {
        let centre = bearing.r + rotate(bearing.phi(), g.s_bearing) + e;
        let arm = rotate(phi, g.s_journal);
        // v_body = v_centre - omega x arm
        BodyState::new(centre - arm, phi, v_centre - perp(arm) * omega, omega)
    }

    fn all(g: &JournalBearing, b: &BodyState, j: &BodyState) -> ContactPoints {
        let mut out = ContactPoints::new();
        contact_journal_bearing(g, b, j, f64::INFINITY, &mut out);
        out
    }

    /// Against the closed form at several placements: normal along the eccentricity,
    /// penetration `|e| - c`, the material points on the line of centres at each radius,
    /// and the relative velocity of a journal that moves and spins in a bearing that
    /// spins: `delta_dot = v_c . n`, slip `v_c . t + omega_J R_J - omega_B R_B`
    /// (each surface's speed along t at the contact).
    #[test]
    fn point_against_closed_form() {
        let g = joint();
        let omega_b = 2.5;
        // The bearing body spins about the bearing centre: its centre stays put.
        let arm_b = rotate(0.3, g.s_bearing);
        let bearing = BodyState::new(Vec2::new(0.1, 0.2), 0.3, -perp(arm_b) * omega_b, omega_b);
        let centre_b = bearing.r + arm_b;
        for (ecc, angle) in [(0.0003, 0.4), (0.0005, 2.0), (0.00062, -2.5), (0.0008, 3.1)] {
            let n = Vec2::new(f64::cos(angle), f64::sin(angle));
            let t = perp(n);
            let v_centre = Vec2::new(0.7, -0.4);
            let omega_j = -30.0;
            let journal = journal_at(&g, &bearing, n * ecc, 1.1, v_centre, omega_j);
            let points = all(&g, &bearing, &journal);
            assert_eq!(points.len(), 1);
            let p = points[0];
            assert_eq!(p.index, 0);
            assert!((p.normal - n).norm() < 1e-9, "{ecc} {angle}: normal {:?}", p.normal);
            assert!((p.penetration - (ecc - g.clearance)).abs() < 1e-15, "{ecc}: {}", p.penetration);
            assert!((p.on_j.at - (centre_b + n * (ecc + g.r_journal))).norm() < 1e-15);
            assert!((p.on_i.at - (centre_b + n * g.r_bearing)).norm() < 1e-15);
            assert_eq!((p.on_i.body, p.on_j.body), (Some(0), Some(1)));
            assert!(
                (p.penetration_rate - v_centre.dot(&n)).abs() < 1e-12,
                "{ecc}: rate {}",
                p.penetration_rate
            );
            let slip = v_centre.dot(&t) + omega_j * g.r_journal - omega_b * g.r_bearing;
            assert!((p.slip[0] - slip).abs() < 1e-12, "{ecc}: slip {} vs {slip}", p.slip[0]);
        }
    }

    /// The penetration rate is the time derivative of the penetration, by central
    /// differences of the placements along the bodies' velocities.
    #[test]
    fn rate_is_the_derivative_of_the_penetration() {
        let g = joint();
        let bearing = BodyState::new(Vec2::new(0.1, 0.2), 0.3, Vec2::new(0.2, 0.1), 4.0);
        let journal = journal_at(&g, &bearing, Vec2::new(0.0004, 0.0003), 1.1, Vec2::new(-0.5, 0.9), 12.0);
        let moved =
            |b: &BodyState, dt: f64| BodyState::new(b.r + b.v * dt, b.phi() + b.omega * dt, b.v, b.omega);
        let h = 1e-7;
        let depth = |dt: f64| all(&g, &moved(&bearing, dt), &moved(&journal, dt))[0].penetration;
        let fd = (depth(h) - depth(-h)) / (2.0 * h);
        let rate = all(&g, &bearing, &journal)[0].penetration_rate;
        assert!((rate - fd).abs() < 1e-6 * rate.abs().max(1.0), "{rate} vs {fd}");
    }

    /// Concentric: the gap is the clearance and the normal the x axis.
    #[test]
    fn concentric_journal() {
        let g = joint();
        let bearing = BodyState::new(Vec2::new(0.1, 0.2), 0.3, Vec2::zeros(), 0.0);
        let journal = journal_at(&g, &bearing, Vec2::zeros(), 0.0, Vec2::zeros(), 0.0);
        let p = all(&g, &bearing, &journal)[0];
        assert!((p.penetration + g.clearance).abs() < 1e-15);
        assert_eq!(p.normal, Vec2::new(1.0, 0.0));
    }

    /// Within the laws' reach only: a contact law (reach 0) gets no point in free flight
    /// and the point in contact; a law that acts apart (reach infinite) gets it always.
    #[test]
    fn reach_selects_the_points() {
        let g = joint();
        let bearing = BodyState::new(Vec2::zeros(), 0.0, Vec2::zeros(), 0.0);
        for (ecc, touching) in [(0.0001, false), (0.00049, false), (0.0006, true)] {
            let journal = journal_at(&g, &bearing, Vec2::new(ecc, 0.0), 0.0, Vec2::zeros(), 0.0);
            let mut out = ContactPoints::new();
            contact_journal_bearing(&g, &bearing, &journal, 0.0, &mut out);
            assert_eq!(out.len(), usize::from(touching), "eccentricity {ecc}");
            assert_eq!(all(&g, &bearing, &journal).len(), 1);
        }
    }
}
