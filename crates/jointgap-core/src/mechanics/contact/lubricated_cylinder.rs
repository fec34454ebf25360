//! The lubricated cylindrical joint: a journal that may tilt in its bearing, carried by
//! an oil film ([`super::film`]), with the dry laws of the cylindrical clearance joint
//! where the film is thinner than its threshold (docs/lubrication.md, "In space").
//!
//! The film is taken in two halves, each at the eccentricity of its mid-plane (a quarter
//! of the film's length from the journal's centre) and carrying half the force of the
//! whole film at that eccentricity. An aligned journal thus gets exactly the planar
//! joint's film; a tilted one gets the difference of its halves as a restoring moment, to
//! first order in the tilt. The pressure field of a misaligned bearing (a Reynolds
//! equation over the whole film) is not modelled.

use super::film::{Film, FilmForce, FilmMotion};
use super::geometry::CylinderBearing;
use super::lubricated::{film_mode, FilmMode};
use super::point3::MaterialPoint3;
use crate::mechanics::layout::Loads;
use crate::mechanics::spatial::body::{self, constant, BodyState, Vec3};
use crate::scalar::{c, norm, Real};
use nalgebra::Vector3;

/// A checked lubricated cylindrical joint's geometry and film.
#[derive(Debug, Clone, PartialEq)]
pub struct LubricatedCylinder {
    /// The journal in its bearing for the dry laws, its radial clearance reduced by the
    /// film threshold, so that its penetration is the threshold less the film's
    /// thickness.
    pub dry: CylinderBearing,
    /// The whole film over the true clearance.
    pub film: Film,
    /// Film threshold [m]: three times the composite roughness.
    pub threshold: f64,
}

/// One half of the film at one state.
#[derive(Debug, Clone, Copy)]
pub struct HalfFilm {
    /// The half's mid-plane point on the journal axis, global [m].
    pub on_journal: Vec3,
    /// Its foot on the bearing axis, global [m].
    pub on_bearing: Vec3,
    /// Eccentricity: `on_journal - on_bearing`, normal to the bearing axis [m].
    pub eccentricity: Vec3,
    /// Smallest film thickness `c - |e|` [m].
    pub thickness: f64,
    /// The half's force on the journal, global [N].
    pub force: Vec3,
    /// The half's torque on the journal about the bearing axis [N m].
    pub torque: f64,
    /// The whole film's force and torque at this eccentricity (the half carries half).
    pub film: FilmForce,
    /// The mode.
    pub mode: FilmMode,
}

/// One half of the film's kinematics at one state, in any number type.
struct Half<T: Real> {
    /// The bearing axis `a`, global.
    axis: Vector3<T>,
    on_journal: Vector3<T>,
    on_bearing: Vector3<T>,
    /// Eccentricity `on_journal - on_bearing` and its length.
    e: Vector3<T>,
    ecc: T,
    /// Its direction `n` and `a x n`.
    n: Vector3<T>,
    across: Vector3<T>,
    motion: FilmMotion<T>,
}

/// The part of the film each half carries.
pub const HALF: f64 = 0.5;

impl LubricatedCylinder {
    /// The two halves of the film (at `-L/4` and `+L/4` along the journal axis from its
    /// centre, `L` the film's length) at the bodies' states: each half's eccentricity in
    /// the plane normal to the bearing axis `a`, its rates from the relative velocity of
    /// the journal's and the bearing's material points there, and the spins about `a`.
    pub fn halves(&self, bearing: &BodyState, journal: &BodyState) -> [HalfFilm; 2] {
        [-1.0, 1.0].map(|side| {
            let h = self.half(bearing, journal, side);
            let film = self.film.force(&h.motion);
            let thickness = self.film.clearance - h.ecc;
            HalfFilm {
                on_journal: h.on_journal,
                on_bearing: h.on_bearing,
                eccentricity: h.e,
                thickness,
                force: (h.n * film.along + h.across * film.across) * HALF,
                torque: HALF * film.torque_journal,
                film,
                mode: film_mode(thickness, self.threshold),
            }
        })
    }

    /// The half of the film on side `side` (-1 or 1) in any number type ([`Self::halves`]).
    #[inline]
    fn half<T: Real>(&self, bearing: &BodyState<T>, journal: &BodyState<T>, side: f64) -> Half<T> {
        let g = &self.dry;
        let centre_b = bearing.r + bearing.rotate(&constant(&g.s_bearing));
        let a = bearing.rotate(&constant(&g.u_bearing));
        let centre_j = journal.r + journal.rotate(&constant(&g.s_journal));
        let axis_j = journal.rotate(&constant(&g.u_journal));
        let (spin_j, spin_b) = (journal.omega_global().dot(&a), bearing.omega_global().dot(&a));
        let on_journal = centre_j + axis_j * c::<T>(side * 0.25 * self.film.length);
        let w = on_journal - centre_b;
        let on_bearing = centre_b + a * a.dot(&w);
        let e = on_journal - on_bearing;
        let ecc = norm(&e);
        let n = if ecc > 0.0 { e / ecc } else { super::geometry::radial_normal(e, ecc, a) };
        let across = a.cross(&n);
        let de = MaterialPoint3::of(g.journal, journal, on_journal).velocity(journal)
            - MaterialPoint3::of(g.bearing, bearing, on_bearing).velocity(bearing);
        let motion = FilmMotion {
            eccentricity: ecc.min(c(self.film.clearance - self.threshold)),
            eccentricity_rate: de.dot(&n),
            attitude_rate: if ecc > 0.0 { de.dot(&across) / ecc } else { c(0.0) },
            omega_journal: spin_j,
            omega_bearing: spin_b,
        };
        Half { axis: a, on_journal, on_bearing, e, ecc, n, across, motion }
    }

    /// The film's loads in any number type, the whole film's force along and across each
    /// half's `n` and its torque being `film`'s at the half's motion: each half's force
    /// on the journal at its point with its torque about the bearing axis `a`; on the
    /// bearing, the opposite force at the foot and the torque `-T a - e x F`, so that the
    /// film carries no moment of its own.
    #[inline]
    pub fn add_film_loads<T: Real>(
        &self,
        bearing: &BodyState<T>,
        journal: &BodyState<T>,
        film: impl Fn(&FilmMotion<T>) -> [T; 3],
        qe: &mut Loads<T>,
    ) {
        let g = &self.dry;
        for side in [-1.0, 1.0] {
            let h = self.half(bearing, journal, side);
            let [along, across, torque] = film(&h.motion);
            let force = (h.n * along + h.across * across) * c::<T>(HALF);
            let torque = torque * HALF;
            if let Some(q) = qe.body(g.journal) {
                body::add_force(q, journal, &(h.on_journal - journal.r), &force);
                body::add_torque(q, journal, &(h.axis * torque));
            }
            if let Some(q) = qe.body(g.bearing) {
                body::add_force(q, bearing, &(h.on_bearing - bearing.r), &-force);
                body::add_torque(q, bearing, &(-h.axis * torque - h.e.cross(&force)));
            }
        }
    }

    /// The film's power on the two bodies [W], the same loads as [`Self::add_film`]:
    /// `F . (v_J - v_B) + T a . (w_J - w_B) - (e x F) . w_B` for each half.
    pub fn film_power(&self, bearing: &BodyState, journal: &BodyState) -> f64 {
        let g = &self.dry;
        let a = bearing.rotate(&g.u_bearing);
        let (w_j, w_b) = (journal.omega_global(), bearing.omega_global());
        self.halves(bearing, journal)
            .iter()
            .map(|h| {
                let de = MaterialPoint3::of(g.journal, journal, h.on_journal).velocity(journal)
                    - MaterialPoint3::of(g.bearing, bearing, h.on_bearing).velocity(bearing);
                h.force.dot(&de) + h.torque * a.dot(&(w_j - w_b)) - h.eccentricity.cross(&h.force).dot(&w_b)
            })
            .sum()
    }
}
