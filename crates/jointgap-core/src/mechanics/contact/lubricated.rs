//! The lubricated revolute joint: a journal in its bearing carried by an oil film
//! ([`super::film`]), with the dry contact laws taking over where the film is thinner
//! than a threshold (docs/lubrication.md, "Transition to dry contact").

use super::film::{Film, FilmForce, FilmMotion};
use super::point::{ContactPoint, ContactPoints, Tangential};
use super::{add_force_at, add_point_forces, ClearanceJoint, ClearanceRevolute, ContactState};
use crate::error::{Error, Named};
use crate::math::{cross, perp, Vec2};
use crate::mechanics::layout::Loads;
use crate::mechanics::planar_body::BodyState;
use crate::mechanics::resolve::Resolver;
use crate::model::{Clearance, Joint, Lubrication};
use crate::output::ClearanceData;
use crate::scalar::{c, norm, Real};

/// How the film carries the journal, as the `film_mode` channel reports it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FilmMode {
    /// The film is thicker than its threshold and carries the load alone.
    Film = 0,
    /// Thinner than the threshold: the asperities touch and the dry laws act beside the
    /// film.
    Mixed = 1,
    /// The journal presses into the bearing's wall (no film left).
    Dry = 2,
}

/// Roughness multiples of the film threshold: Hamrock's film parameter
/// `Lambda = h_min / sigma` is 3 or more in full film lubrication.
pub const FULL_FILM_LAMBDA: f64 = 3.0;

/// A checked lubricated revolute joint.
#[derive(Debug, Clone)]
pub struct LubricatedRevolute {
    /// The journal in its bearing with the dry laws, its clearance reduced by the film
    /// threshold, so that its penetration is the threshold less the film's thickness.
    pub dry: ClearanceRevolute,
    /// The film over the true clearance.
    pub film: Film,
    /// Film threshold [m]: three times the composite roughness.
    pub threshold: f64,
}

/// The film at one state.
#[derive(Debug, Clone, Copy)]
pub struct FilmState {
    /// Eccentricity `r_J - r_B`, global [m].
    pub eccentricity: Vec2,
    /// Smallest film thickness `c - |e|` [m] (negative: the journal presses in).
    pub thickness: f64,
    /// The film's force on the journal, global [N].
    pub force: Vec2,
    /// Its force along and across the eccentricity, torque and peak pressure, at the
    /// eccentricity capped at the threshold.
    pub film: FilmForce,
    /// The mode.
    pub mode: FilmMode,
}

/// Checks joint `name`'s film `l` for a journal of radius `radius` in a radial
/// clearance `clearance`: the film and its threshold (three times the roughness), which
/// must be small against the clearance. Errors name the joint and key.
pub(crate) fn checked_film(
    name: &str,
    l: &Lubrication,
    radius: f64,
    clearance: f64,
) -> Result<(Film, f64), Error> {
    let who = Named::joint(name);
    for (key, v, unit) in [
        ("lubrication.length", l.length, "m"),
        ("lubrication.viscosity", l.viscosity, "Pa s"),
        ("lubrication.roughness", l.roughness, "m"),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(who.error(key, format!("{} = {v} {unit} must be positive", &key[12..])));
        }
    }
    let threshold = FULL_FILM_LAMBDA * l.roughness;
    if threshold >= 0.5 * clearance {
        return Err(who.error(
            "lubrication.roughness",
            format!(
                "roughness = {} m gives a film threshold of {threshold} m (3 x roughness), not \
                 small against the radial clearance {clearance} m: the film would never carry \
                 the journal (check the units: roughness is a few micrometres)",
                l.roughness
            ),
        ));
    }
    let film = Film { radius, clearance, length: l.length, viscosity: l.viscosity, model: l.film };
    Ok((film, threshold))
}

/// The mode of a film of smallest thickness `thickness` and threshold `threshold`.
pub(crate) fn film_mode(thickness: f64, threshold: f64) -> FilmMode {
    if thickness > threshold {
        FilmMode::Film
    } else if thickness > 0.0 {
        FilmMode::Mixed
    } else {
        FilmMode::Dry
    }
}

impl LubricatedRevolute {
    /// Checks joint `j`'s contact data `c` and film `l`; errors name the joint and key.
    pub(crate) fn new(
        j: &Joint,
        c: &Clearance,
        l: &Lubrication,
        bearing: Option<usize>,
        journal: Option<usize>,
        res: &Resolver,
    ) -> Result<Self, Error> {
        let mut dry = ClearanceRevolute::new(j, c, bearing, journal, res)?;
        let (film, threshold) = checked_film(&j.name, l, dry.geometry.r_journal, dry.geometry.clearance)?;
        dry.geometry.clearance -= threshold;
        Ok(LubricatedRevolute { film, dry, threshold })
    }

    /// The film at the bodies' states: its kinematics from the centres' relative motion
    /// and the two spins, its eccentricity capped where the film is thinner than the
    /// threshold (the asperities carry the rest).
    pub fn film_at(&self, bearing: &BodyState, journal: &BodyState) -> FilmState {
        let (e, ecc, n, motion) = self.film_motion(bearing, journal);
        let thickness = self.film.clearance - ecc;
        let film = self.film.force(&motion);
        let mode = film_mode(thickness, self.threshold);
        FilmState { eccentricity: e, thickness, force: n * film.along + perp(n) * film.across, film, mode }
    }

    /// The eccentricity `r_J - r_B`, its length, its direction `n` and the film's
    /// motion ([`Self::film_at`]), in any number type.
    #[inline]
    fn film_motion<T: Real>(
        &self,
        bearing: &BodyState<T>,
        journal: &BodyState<T>,
    ) -> (Vec2<T>, T, Vec2<T>, FilmMotion<T>) {
        let g = &self.dry.geometry;
        let (arm_b, arm_j) = (bearing.rotate(g.s_bearing), journal.rotate(g.s_journal));
        let e = journal.r + arm_j - bearing.r - arm_b;
        let ecc = norm(&e);
        let n = if ecc > 0.0 { e / ecc } else { Vec2::new(c(1.0), c(0.0)) };
        let de = journal.v + perp(arm_j) * journal.omega - bearing.v - perp(arm_b) * bearing.omega;
        let motion = FilmMotion {
            eccentricity: ecc.min(c(self.film.clearance - self.threshold)),
            eccentricity_rate: de.dot(&n),
            attitude_rate: if ecc > 0.0 { de.dot(&perp(n)) / ecc } else { c(0.0) },
            omega_journal: journal.omega,
            omega_bearing: bearing.omega,
        };
        (e, ecc, n, motion)
    }

    /// Adds the film's loads in any number type, its force along and across `n` and its
    /// torque on the journal being `film`'s at the film's motion: the force on the journal
    /// at its centre with the torque, their opposites on the bearing at its centre
    /// ([`ClearanceJoint::add_to`] adds the dry laws' before).
    #[inline]
    pub fn add_film_loads<T: Real>(
        &self,
        bearing: &BodyState<T>,
        journal: &BodyState<T>,
        film: impl Fn(&FilmMotion<T>) -> [T; 3],
        qe: &mut Loads<T>,
    ) {
        let (e, _, n, motion) = self.film_motion(bearing, journal);
        let [along, across, torque] = film(&motion);
        let force = n * along + perp(n) * across;
        let g = &self.dry.geometry;
        let (centre_b, centre_j) = g.centres(bearing, journal);
        add_force_at(qe, g.journal, journal, centre_j, force);
        add_force_at(qe, g.bearing, bearing, centre_b, -force);
        if let Some(q) = qe.body(g.journal) {
            q[2] += torque;
        }
        if let Some(q) = qe.body(g.bearing) {
            q[2] += -torque - cross(e, force);
        }
    }

    /// The film's torque on the bearing [N m]: the film carries no moment of its own, so
    /// it is minus the journal's torque and the moment of the journal's force about the
    /// bearing centre.
    fn bearing_torque(f: &FilmState) -> f64 {
        -f.film.torque_journal - cross(f.eccentricity, f.force)
    }
}

impl ClearanceJoint for LubricatedRevolute {
    type State = BodyState;
    type Point = ContactPoint;
    type Points = ContactPoints;
    type Friction = Tangential;

    fn name(&self) -> &str {
        &self.dry.name
    }

    fn parts(&self) -> [Option<usize>; 2] {
        self.dry.parts()
    }

    /// The true radial clearance (the dry laws' starts at the threshold).
    fn data(&self) -> ClearanceData {
        ClearanceData { clearance: self.film.clearance, ..self.dry.data() }
    }

    fn check_initial_penetration(&self, bearing: &BodyState, journal: &BodyState) -> Result<(), Error> {
        self.dry.check_initial_penetration(bearing, journal)
    }

    fn points(&self) -> usize {
        1
    }

    fn reach(&self) -> f64 {
        self.dry.reach()
    }

    /// The dry laws' point: its penetration is the threshold less the film's thickness.
    #[inline]
    fn contacts(&self, bearing: &BodyState, journal: &BodyState, reach: f64) -> ContactPoints {
        self.dry.contacts(bearing, journal, reach)
    }

    #[inline]
    fn force(&self, p: &ContactPoint, onset_speed: f64) -> (f64, Tangential) {
        self.dry.force(p, onset_speed)
    }

    /// The dry laws' losses, and the film's as normal: minus the power of its forces on
    /// the two bodies, `-(F . de/dt + T_J omega_J + T_B omega_B)`.
    fn losses(&self, bearing: &BodyState, journal: &BodyState, states: &[ContactState]) -> (f64, f64) {
        let (normal, friction) = self.dry.losses(bearing, journal, states);
        let f = self.film_at(bearing, journal);
        let g = &self.dry.geometry;
        let (arm_b, arm_j) = (bearing.rotate(g.s_bearing), journal.rotate(g.s_journal));
        let de = journal.v + perp(arm_j) * journal.omega - bearing.v - perp(arm_b) * bearing.omega;
        let power = f.force.dot(&de)
            + f.film.torque_journal * journal.omega
            + Self::bearing_torque(&f) * bearing.omega;
        (normal - power, friction)
    }

    fn elastic_energy(&self, p: &ContactPoint) -> f64 {
        self.dry.elastic_energy(p)
    }

    /// The dry laws' forces, and the film's: its force on the journal at the journal's
    /// centre with its torque, their opposites on the bearing at the bearing's centre.
    #[inline]
    fn add_to(&self, bearing: &BodyState, journal: &BodyState, states: &[ContactState], qe: &mut Loads) {
        add_point_forces(&self.dry, bearing, journal, states, qe);
        let film = |m: &FilmMotion| {
            let f = self.film.force(m);
            [f.along, f.across, f.torque_journal]
        };
        self.add_film_loads(bearing, journal, film, qe);
    }
}
