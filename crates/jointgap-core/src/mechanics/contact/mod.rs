//! Clearance revolute joints: the journal (pin on body j) moves freely inside the
//! bearing (hole on body i) and a contact force acts when it reaches the wall
//! (docs/physics.md section 2). A clearance joint is a contact geometry
//! ([`geometry`]: where its parts touch, as contact points) and the laws ([`normal`],
//! [`friction`]) that turn one contact point into forces.

pub mod film;
pub mod friction;
pub mod gear;
pub mod geometry;
pub mod lubricated;
pub mod lubricated_cylinder;
pub mod materials;
pub mod normal;
pub mod planar_clearance;
pub mod play;
pub mod point;
pub mod point3;
pub mod spatial;
mod state;
pub mod translational;
pub mod wear_coefficients;

pub use point::{ContactPoint, ContactPoints, Tangential, MAX_POINTS};
pub use state::{onset_for, ContactState, Mode};

use std::ops::{Deref, Range};

use crate::error::{Error, Named};
use crate::math::Vec2;
use crate::mechanics::layout::Loads;
use crate::mechanics::planar_body::{self, BodyState};
use crate::mechanics::resolve::Resolver;
use crate::model::{Clearance, FrictionSpec, Joint, JointKind};
use crate::output::ClearanceData;
use crate::scalar::Real;
use geometry::{
    contact_journal_bearing, contact_worn, contact_worn_from, search_worn, Found, JournalBearing, Worn,
};
use normal::NormalForce;

/// What the run reads of any contact point, planar or spatial: which of its joint's
/// points it is, its penetration and the penetration's rate.
pub trait ContactMeasure: Copy + std::fmt::Debug {
    /// Which of its geometry's points this is.
    fn index(&self) -> usize;
    /// Penetration [m]: positive in contact, minus the gap apart.
    fn penetration(&self) -> f64;
    /// Penetration rate [m/s].
    fn penetration_rate(&self) -> f64;
}

impl ContactMeasure for ContactPoint {
    #[inline]
    fn index(&self) -> usize {
        self.index
    }
    #[inline]
    fn penetration(&self) -> f64 {
        self.penetration
    }
    #[inline]
    fn penetration_rate(&self) -> f64 {
        self.penetration_rate
    }
}

/// A clearance joint of some body kind, as the dynamics and the run see it: its parts,
/// its contact points at a state, and the forces and losses of each point.
pub trait ClearanceJoint {
    /// The state of a body of its kind.
    type State;
    /// One contact point of its kind.
    type Point: ContactMeasure;
    /// Its contact points at one state.
    type Points: Deref<Target = [Self::Point]>;
    /// A friction force at a contact point (along its tangents, or a vector).
    type Friction: Copy;
    /// Joint name.
    fn name(&self) -> &str;
    /// Its part on body i (the bearing, the socket) and on body j (the journal, the ball).
    fn parts(&self) -> [Option<usize>; 2];
    /// The resolved contact data reported with a run's result.
    fn data(&self) -> ClearanceData;
    /// Rejects an initial state with a contact point deeper than any elastic contact can
    /// be; the error names the joint, the penetration and the likely causes.
    fn check_initial_penetration(&self, i: &Self::State, j: &Self::State) -> Result<(), Error>;
    /// Contact points the joint's geometry can have (each keeps its own contact state).
    fn points(&self) -> usize;
    /// The gap [m] within which the laws act.
    fn reach(&self) -> f64;
    /// The contact points whose gap is below `reach` [m] (`f64::INFINITY`: all of them,
    /// in the order of their index).
    fn contacts(&self, i: &Self::State, j: &Self::State, reach: f64) -> Self::Points;
    /// Normal force [N] and friction force [N] at contact point `p` for the impact
    /// onset speed `onset_speed` [m/s].
    fn force(&self, p: &Self::Point, onset_speed: f64) -> (f64, Self::Friction);
    /// Power [W] the joint dissipates at the bodies' states `(i, j)`, as `(normal,
    /// friction)`, each point with its own state in `states` (the joint's, by point
    /// index); a fluid film's losses count as normal.
    fn losses(&self, i: &Self::State, j: &Self::State, states: &[ContactState]) -> (f64, f64);
    /// Elastic energy [J] stored at contact point `p`.
    fn elastic_energy(&self, p: &Self::Point) -> f64;
    /// Adds the contact forces to the loads, each point's with its own state in `states`.
    fn add_to(&self, i: &Self::State, j: &Self::State, states: &[ContactState], qe: &mut Loads);
}

/// A clearance joint's checked contact data, whatever its geometry: the radii of its
/// hole (bearing, socket) and its pin (journal, ball), its normal law with the stiffness
/// given or from the materials (`K = 4/3 E* sqrt(R*)`, [`materials`]), and its friction.
#[derive(Debug, Clone)]
pub struct Laws {
    /// Radius of the hole [m].
    pub r_bearing: f64,
    /// Radius of the pin [m].
    pub r_journal: f64,
    /// Normal law with its stiffness.
    pub normal: NormalForce,
    /// Friction law (checked).
    pub friction: FrictionSpec,
    /// The materials' contact modulus `E*` [Pa] ([`materials::contact_modulus`]), when
    /// both are given.
    pub contact_modulus: Option<f64>,
}

impl Laws {
    /// Checks joint `name`'s contact data `c`, which has no wear data (the keys of a
    /// planar `clearance_revolute` alone, [`ClearanceRevolute::new`]); errors name the
    /// joint.
    pub fn new(name: &str, c: &Clearance) -> Result<Self, Error> {
        Self::without_tables(name, c)?;
        Self::without_length(name, c)
    }

    /// [`Laws::new`] for a spatial cylindrical clearance joint, which takes wear tables
    /// (its length is its own, not the clearance's).
    pub fn with_tables(name: &str, c: &Clearance) -> Result<Self, Error> {
        Self::without_length(name, c)
    }

    /// [`Laws::checked`], rejecting a clearance `length`.
    fn without_length(name: &str, c: &Clearance) -> Result<Self, Error> {
        if c.length.is_some() {
            return Err(Named::joint(name).error(
                "length",
                "'length' (wear data) belongs to a planar clearance_revolute joint only".into(),
            ));
        }
        Self::checked(name, c)
    }

    /// Rejects wear tables.
    fn without_tables(name: &str, c: &Clearance) -> Result<(), Error> {
        for (key, given) in
            [("bearing_wear", c.bearing_wear.is_some()), ("journal_wear", c.journal_wear.is_some())]
        {
            if given {
                return Err(Named::joint(name).error(
                    key,
                    format!(
                        "'{key}' (wear data) belongs to a planar clearance_revolute joint and a dry \
                         spatial clearance_cylindrical joint only"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// [`Laws::new`] without the check that `c` has no wear data.
    fn checked(name: &str, c: &Clearance) -> Result<Self, Error> {
        let who = Named::joint(name);
        let positive = |what: &str, v: Option<f64>| -> Result<Option<f64>, Error> {
            match v {
                Some(x) if !(x.is_finite() && x > 0.0) => {
                    Err(who.error(what, format!("{what} = {x} m must be positive")))
                }
                _ => Ok(v),
            }
        };
        let (rb, rj, cl) = (
            positive("bearing_radius", c.bearing_radius)?,
            positive("journal_radius", c.journal_radius)?,
            positive("clearance", c.clearance)?,
        );
        let (r_bearing, r_journal) = match (rb, rj, cl) {
            (Some(b), Some(j), None) => (b, j),
            (Some(b), None, Some(c)) => (b, b - c),
            (None, Some(j), Some(c)) => (j + c, j),
            (Some(b), Some(j), Some(c)) => {
                if ((b - j) - c).abs() > 1e-9 * b {
                    return Err(who.error(
                        "clearance",
                        format!(
                            "bearing_radius - journal_radius = {} m contradicts clearance = {c} m",
                            b - j
                        ),
                    ));
                }
                (b, j)
            }
            _ => {
                return Err(
                    who.error_of_element("give two of bearing_radius, journal_radius and clearance".into())
                );
            }
        };
        // Said in the keys the user gave: a clearance that leaves no journal, or a
        // journal that does not fit its bearing.
        if r_journal <= 0.0 {
            return Err(who.error(
                "clearance",
                format!(
                    "clearance = {} m is not smaller than bearing_radius = {r_bearing} m: \
                     the clearance is the radial gap between bearing and journal, a small fraction \
                     of the bearing radius (check the units)",
                    c.clearance.unwrap_or(r_bearing - r_journal)
                ),
            ));
        }
        if r_journal >= r_bearing {
            return Err(who.error(
                "journal_radius",
                format!("journal_radius = {r_journal} m must be smaller than bearing_radius = {r_bearing} m"),
            ));
        }
        let (stiffness, d_max_default) = match (c.stiffness, &c.bearing_material, &c.journal_material) {
            (Some(k), _, _) => {
                if !(k.is_finite() && k > 0.0) {
                    return Err(who.error("stiffness", format!("stiffness = {k} must be positive")));
                }
                let d_max = match &c.bearing_material {
                    Some(m) => materials::resolve(who, "bearing_material", m)?.1,
                    None => None,
                };
                (k, d_max)
            }
            (None, Some(mb), Some(mj)) => {
                let (bearing_mat, d_max) = materials::resolve(who, "bearing_material", mb)?;
                let (journal_mat, _) = materials::resolve(who, "journal_material", mj)?;
                (
                    materials::journal_bearing_stiffness(&journal_mat, &bearing_mat, r_journal, r_bearing),
                    d_max,
                )
            }
            _ => {
                return Err(who.error_of_element(
                    "give a stiffness or both bearing_material and journal_material".into(),
                ));
            }
        };
        let contact_modulus = match (&c.bearing_material, &c.journal_material) {
            (Some(mb), Some(mj)) => Some(materials::contact_modulus(
                &materials::resolve(who, "bearing_material", mb)?.0,
                &materials::resolve(who, "journal_material", mj)?.0,
            )),
            _ => None,
        };
        Ok(Laws {
            r_bearing,
            r_journal,
            normal: NormalForce::new(name, &c.normal_law, stiffness, d_max_default)?,
            friction: {
                friction::check(name, &c.friction)?;
                c.friction.clone()
            },
            contact_modulus,
        })
    }
}

/// A checked clearance joint: its contact geometry and its laws.
#[derive(Debug, Clone)]
pub struct ClearanceRevolute {
    /// Joint name.
    pub name: String,
    /// Where its parts are and their shape: a journal in its bearing.
    pub geometry: JournalBearing,
    /// Normal law with its stiffness.
    pub normal: NormalForce,
    /// Friction law (checked).
    pub friction: FrictionSpec,
    /// The parts' wear profiles (docs/wear.md); `None`: both round, and the contact is
    /// [`contact_journal_bearing`]'s.
    pub worn: Option<Box<Worn>>,
    /// What a run that accumulates wear needs of the joint: the bearing's length and
    /// the contact modulus; `Err` says what is missing, for that run's error.
    pub wear_contact: Result<WearContact, String>,
}

/// A revolute clearance joint's line contact, for the contact pressure that wears its
/// parts (docs/wear.md).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WearContact {
    /// Bearing length along the axis [m].
    pub length: f64,
    /// Contact modulus `E*` [Pa].
    pub contact_modulus: f64,
    /// Effective radius of the internal contact `R* = R_J R_B / (R_B - R_J)` [m].
    pub effective_radius: f64,
}

impl WearContact {
    /// Half width [m] of the Hertz line contact of two cylinders under normal force
    /// `f_n` [N]: `b = sqrt(4 F R* / (pi L E*))` (Johnson 1985, section 5.3, eq. 5.39;
    /// the bearing's curvature counts negative, so `R*` is that of internal contact).
    #[inline]
    pub fn half_width(&self, f_n: f64) -> f64 {
        (4.0 * f_n * self.effective_radius / (std::f64::consts::PI * self.length * self.contact_modulus))
            .sqrt()
    }
}

/// The largest normal force [N] an initial penetration may stand for: a journal that
/// starts deeper in its bearing than its own normal law presses under 1 MN (100 t) is a
/// modelling error, not a preloaded contact.
pub const MAX_INITIAL_CONTACT_FORCE: f64 = 1e6;

impl ClearanceRevolute {
    /// The resolved contact data reported with a run's result.
    pub fn data(&self) -> ClearanceData {
        ClearanceData {
            joint: self.name.clone(),
            bearing_radius: self.geometry.r_bearing,
            journal_radius: self.geometry.r_journal,
            clearance: self.geometry.clearance,
            stiffness: self.normal.stiffness,
            exponent: self.normal.exponent,
        }
    }

    /// Checks the joint's contact data; errors name the joint.
    pub(crate) fn new(
        j: &Joint,
        c: &Clearance,
        bearing: Option<usize>,
        journal: Option<usize>,
        res: &Resolver,
    ) -> Result<Self, Error> {
        let who = Named::joint(&j.name);
        // Only the dry joint takes wear data; a lubricated one's keys are checked as any
        // other joint's.
        let laws = match j.kind {
            JointKind::ClearanceRevolute => Laws::checked(&j.name, c)?,
            _ => Laws::new(&j.name, c)?,
        };
        let worn = Worn::new(who, (c.bearing_wear.as_deref(), c.journal_wear.as_deref()), laws.r_journal)?
            .map(Box::new);
        let wear_contact = wear_contact(who, c, &laws)?;
        Ok(ClearanceRevolute {
            name: j.name.clone(),
            geometry: JournalBearing {
                bearing,
                s_bearing: res.point(who, "point_i", bearing, &j.point_i)?,
                journal,
                s_journal: res.point(who, "point_j", journal, &j.point_j)?,
                r_bearing: laws.r_bearing,
                r_journal: laws.r_journal,
                clearance: laws.r_bearing - laws.r_journal,
            },
            normal: laws.normal,
            friction: laws.friction,
            worn,
            wear_contact,
        })
    }

    /// Penetration [m] at which the elastic part of the normal law, `K delta^n`, reaches
    /// [`MAX_INITIAL_CONTACT_FORCE`]: the deepest initial penetration an elastic contact
    /// can have.
    pub fn max_initial_penetration(&self) -> f64 {
        (MAX_INITIAL_CONTACT_FORCE / self.normal.stiffness).powf(1.0 / self.normal.exponent)
    }
}

impl ClearanceJoint for ClearanceRevolute {
    type State = BodyState;
    type Point = ContactPoint;
    type Points = ContactPoints;
    type Friction = Tangential;

    fn name(&self) -> &str {
        &self.name
    }

    fn parts(&self) -> [Option<usize>; 2] {
        [self.geometry.bearing, self.geometry.journal]
    }

    fn data(&self) -> ClearanceData {
        self.data()
    }

    fn elastic_energy(&self, p: &ContactPoint) -> f64 {
        p.share * self.normal.elastic_energy(p.penetration)
    }

    /// Rejects an initial state (`bearing`, `journal`: the body states after assembly)
    /// with a contact point deeper than any elastic contact can be
    /// ([`Self::max_initial_penetration`]); the error names the joint, the penetration and
    /// the likely causes.
    fn check_initial_penetration(&self, bearing: &BodyState, journal: &BodyState) -> Result<(), Error> {
        let limit = self.max_initial_penetration();
        let e = self.geometry.eccentricity(bearing, journal);
        for k in self.contacts(bearing, journal, f64::INFINITY).iter() {
            if k.penetration <= limit {
                continue;
            }
            let mm = 1e3;
            return Err(Named::joint(&self.name).error_of_element(format!(
                "the journal starts {:.4} mm deep in the bearing (its centre {:.4} mm from the \
             bearing centre, radial clearance {:.4} mm), deeper than any elastic contact: this joint's \
             normal law (K = {:.4e} N/m^{}) presses {:.4} mm deep only under {:.0e} N; likely a wrong \
             point (point_i or point_j of this joint, or a point of a joint that places its bodies), \
             a wrong bearing or journal radius, or a length in the wrong unit",
                mm * k.penetration,
                mm * e.norm(),
                mm * self.geometry.clearance,
                self.normal.stiffness,
                self.normal.exponent,
                mm * limit,
                MAX_INITIAL_CONTACT_FORCE,
            )));
        }
        Ok(())
    }

    /// Contact points the joint's geometry can have (each keeps its own contact state).
    fn points(&self) -> usize {
        JournalBearing::POINTS
    }

    /// The gap [m] within which the laws act: a contact point farther apart takes no
    /// force, so the geometry need not return it to [`Self::add_to`].
    fn reach(&self) -> f64 {
        self.normal.reach()
    }

    /// The contact points of the joint's geometry whose gap is below `reach` [m]
    /// (`f64::INFINITY`: all of them, in the order of their index).
    #[inline]
    fn contacts(&self, bearing: &BodyState, journal: &BodyState, reach: f64) -> ContactPoints {
        if let Some(worn) = &self.worn {
            return worn_contacts(&self.geometry, worn, bearing, journal, reach);
        }
        let mut out = ContactPoints::new();
        contact_journal_bearing(&self.geometry, bearing, journal, reach, &mut out);
        out
    }

    /// Normal force [N] and friction force along the tangents [N] at contact point `p`
    /// for the impact onset speed `onset_speed` [m/s]: friction opposes the slip, and
    /// acts only under a pressing normal force.
    #[inline]
    fn force(&self, p: &ContactPoint, onset_speed: f64) -> (f64, Tangential) {
        dry_force(&self.normal, &self.friction, p, onset_speed)
    }

    /// Power [W] the joint dissipates, as `(normal, friction)`. At each contact point
    /// `p` the contact force does work at the rate `-F_N delta_dot + F_T . v_t` on the two bodies (body j's force
    /// at its point, its opposite at body i's, and `delta_dot`, `v_t` the relative
    /// velocity of those points along `n` and the tangents); of it, `-K delta^n
    /// delta_dot` is the rate of the elastic energy counted as potential energy. The rest
    /// is lost: `(F_N - K delta^n) delta_dot` by the normal law's damping (and by
    /// clipping, which drops the elastic force a pulling force would return),
    /// `-F_T . v_t >= 0` by friction.
    fn losses(&self, bearing: &BodyState, journal: &BodyState, states: &[ContactState]) -> (f64, f64) {
        dry_losses(self, &self.normal, bearing, journal, states)
    }

    #[inline]
    fn add_to(&self, bearing: &BodyState, journal: &BodyState, states: &[ContactState], qe: &mut Loads) {
        let onset = |k: usize, rate| states[k].onset_for(rate);
        match &self.worn {
            Some(worn) => {
                let found = search_worn(&self.geometry, worn, bearing, journal, self.reach());
                self.add_worn_loads(worn, &found, bearing, journal, onset, qe);
            }
            None => self.add_round_loads(bearing, journal, onset, qe),
        }
    }
}

impl ClearanceRevolute {
    /// Adds the contact loads of the joint's round parts ([`contact_journal_bearing`] and
    /// the dry laws), in any number type: `onset(k, rate)` is the impact onset speed of
    /// point `k` at penetration rate `rate` ([`ContactState::onset_for`]).
    #[inline]
    pub fn add_round_loads<T: Real>(
        &self,
        bearing: &BodyState<T>,
        journal: &BodyState<T>,
        onset: impl Fn(usize, T) -> T,
        qe: &mut Loads<T>,
    ) {
        let mut points = ContactPoints::new();
        contact_journal_bearing(&self.geometry, bearing, journal, self.reach(), &mut points);
        self.apply_dry_forces(&points, bearing, journal, onset, qe);
    }

    /// Adds the contact loads of the joint's worn parts `worn` ([`contact_worn_from`] and
    /// the dry laws) in any number type, from where the search found the rims (`found`,
    /// [`search_worn`] at the law's reach); `onset` as for [`Self::add_round_loads`].
    #[inline]
    pub fn add_worn_loads<T: Real>(
        &self,
        worn: &Worn,
        found: &Found<T>,
        bearing: &BodyState<T>,
        journal: &BodyState<T>,
        onset: impl Fn(usize, T) -> T,
        qe: &mut Loads<T>,
    ) {
        let mut points = ContactPoints::new();
        contact_worn_from(&self.geometry, worn, found, bearing, journal, self.reach(), &mut points);
        self.apply_dry_forces(&points, bearing, journal, onset, qe);
    }

    /// Adds the dry laws' forces at `points`, in line as [`apply_point_forces`].
    #[inline(always)]
    fn apply_dry_forces<T: Real>(
        &self,
        points: &[ContactPoint<T>],
        bearing: &BodyState<T>,
        journal: &BodyState<T>,
        onset: impl Fn(usize, T) -> T,
        qe: &mut Loads<T>,
    ) {
        let force = |p: &ContactPoint<T>| {
            dry_force(&self.normal, &self.friction, p, onset(p.index, p.penetration_rate))
        };
        apply_point_forces(points, force, bearing, journal, qe);
    }
}

/// The contact points of a worn journal in its worn bearing ([`contact_worn`]), as a
/// list of its own: never inlined, so that the round joint's list, which shares
/// [`ClearanceRevolute::contacts`], is still built in the caller's place (a list filled
/// through a call that is not inlined is copied out, 8 % more instructions per run).
#[inline(never)]
fn worn_contacts(
    g: &JournalBearing,
    worn: &Worn,
    bearing: &BodyState,
    journal: &BodyState,
    reach: f64,
) -> ContactPoints {
    let mut out = ContactPoints::new();
    contact_worn(g, worn, bearing, journal, reach, &mut out);
    out
}

/// The line contact of joint `who` (`c` its data, `laws` its checked laws) for a run
/// that accumulates wear: its `length`, checked, and [`line_contact`]. `Ok(Err(why))`
/// where the joint lacks them (only a run with wear needs them).
fn wear_contact(who: Named, c: &Clearance, laws: &Laws) -> Result<Result<WearContact, String>, Error> {
    match c.length {
        Some(l) if !(l.is_finite() && l > 0.0) => {
            Err(who.error("length", format!("length = {l} m must be positive")))
        }
        Some(l) => Ok(line_contact(who, l, laws)),
        None => Ok(Err(format!(
            "{who}: wear needs the bearing's length along its axis (clearance.length), the \
             length of the line contact that carries the load"
        ))),
    }
}

/// The line contact of length `length` [m] of joint `who` (`laws` its checked laws) for
/// a run that accumulates wear: the contact modulus from the materials or, with a
/// stiffness alone of exponent 1.5, the `E* = 3 K / (4 sqrt(R*))` whose journal-bearing
/// stiffness ([`materials::journal_bearing_stiffness`]) is `K`. `Err(why)` where the
/// joint lacks them.
pub(crate) fn line_contact(who: Named, length: f64, laws: &Laws) -> Result<WearContact, String> {
    let effective_radius = laws.r_journal * laws.r_bearing / (laws.r_bearing - laws.r_journal);
    let contact_modulus = match laws.contact_modulus {
        Some(e) => e,
        None if laws.normal.exponent == 1.5 => 0.75 * laws.normal.stiffness / effective_radius.sqrt(),
        None => {
            return Err(format!(
                "{who}: wear needs the contact's width, from bearing_material and journal_material \
                 (a stiffness alone gives it for a Hertz exponent of 1.5 only)"
            ));
        }
    };
    Ok(WearContact { length, contact_modulus, effective_radius })
}

/// Normal force [N] and friction force along the tangents [N] of the dry laws `normal`
/// and `friction` at contact point `p` for the impact onset speed `onset_speed` [m/s]:
/// friction opposes the slip, and acts only under a pressing normal force.
#[inline]
pub(crate) fn dry_force<T: Real>(
    normal: &NormalForce,
    friction: &FrictionSpec,
    p: &ContactPoint<T>,
    onset_speed: T,
) -> (T, Tangential<T>) {
    let f_n = normal.force(p.penetration, p.penetration_rate, onset_speed) * p.share;
    let f_t = if f_n > 0.0 { friction.force_on_slip(&p.slip, f_n) } else { Tangential::zeros() };
    (f_n, f_t)
}

/// The losses of a planar joint `c` whose points take the dry laws (normal law
/// `normal`): `(F_N - K delta^n) delta_dot` by the law's damping and clipping,
/// `-F_T . v_t` by friction, summed over its points.
pub(crate) fn dry_losses<C>(
    c: &C,
    normal: &NormalForce,
    i: &BodyState,
    j: &BodyState,
    states: &[ContactState],
) -> (f64, f64)
where
    C: ClearanceJoint<State = BodyState, Point = ContactPoint, Points = ContactPoints, Friction = Tangential>,
{
    sum_losses(c.contacts(i, j, c.reach()).iter(), |p| {
        let (f_n, f_t) = c.force(p, states[p.index].onset_for(p.penetration_rate));
        (
            (f_n - p.share * normal.elastic_force(p.penetration)) * p.penetration_rate,
            -point::dot(&f_t, &p.slip),
        )
    })
}

/// The sum over `points` of each one's `(normal, friction)` losses.
pub(crate) fn sum_losses<'a, P: 'a>(
    points: impl Iterator<Item = &'a P>,
    each: impl Fn(&P) -> (f64, f64),
) -> (f64, f64) {
    points.map(each).fold((0.0, 0.0), |(n, f), (dn, df)| (n + dn, f + df))
}

/// Adds a planar clearance joint's contact forces to the loads, each contact point's
/// with its own state in `states` (the joint's, by point index): body j's force at its
/// material point, the opposite on body i at its own.
#[inline]
pub(crate) fn add_point_forces<C>(
    c: &C,
    i: &BodyState,
    j: &BodyState,
    states: &[ContactState],
    qe: &mut Loads,
) where
    C: ClearanceJoint<State = BodyState, Point = ContactPoint, Points = ContactPoints, Friction = Tangential>,
{
    let force = |p: &ContactPoint| c.force(p, states[p.index].onset_for(p.penetration_rate));
    apply_point_forces(&c.contacts(i, j, c.reach()), force, i, j, qe);
}

/// Adds the force of each of `points` (`force` gives its normal and friction forces):
/// body j's at its material point, the opposite on body i at its own. In line in each
/// caller: called, it cost the founding case 0.8 % more instructions.
#[inline(always)]
pub(crate) fn apply_point_forces<T: Real>(
    points: &[ContactPoint<T>],
    force: impl Fn(&ContactPoint<T>) -> (T, Tangential<T>),
    i: &BodyState<T>,
    j: &BodyState<T>,
    qe: &mut Loads<T>,
) {
    for p in points {
        let (f_n, f_t) = force(p);
        if f_n != 0.0 || f_t.iter().any(|&f| f != 0.0) {
            let f = p.force_on_j(f_n, &f_t);
            add_force_at(qe, p.on_j.body, j, p.on_j.at, f);
            add_force_at(qe, p.on_i.body, i, p.on_i.at, -f);
        }
    }
}

/// Adds a force at a global point of a body.
#[inline]
pub(crate) fn add_force_at<T: Real>(
    loads: &mut Loads<T>,
    b: Option<usize>,
    state: &BodyState<T>,
    p: Vec2<T>,
    f: Vec2<T>,
) {
    if let Some(qe) = loads.body(b) {
        planar_body::add_force(qe, p - state.r, f);
    }
}

/// Each clearance joint of `clearances` with the range of its contact points among all
/// of them, in order: joint `k`'s points are laid out one after the other, as the
/// contact states and impact lists of a run keep them.
pub fn slots<C: ClearanceJoint>(clearances: &[C]) -> impl Iterator<Item = (usize, &C, Range<usize>)> {
    let ranges = point_ranges(clearances.iter().map(C::points));
    clearances.iter().zip(ranges).enumerate().map(|(k, (c, range))| (k, c, range))
}

/// The ranges of groups of `counts` points laid out one after the other.
pub fn point_ranges(counts: impl IntoIterator<Item = usize>) -> impl Iterator<Item = Range<usize>> {
    counts.into_iter().scan(0, |first, count| {
        let range = *first..*first + count;
        *first = range.end;
        Some(range)
    })
}

/// Contact points of all of `clearances` together.
pub fn point_count<C: ClearanceJoint>(clearances: &[C]) -> usize {
    clearances.iter().map(C::points).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A force on body j's point along `-n F_N + t F_T` of the point's own tangent.
    #[test]
    fn point_force_splits_along_normal_and_tangent() {
        let n = Vec2::new(0.6, 0.8);
        let none = point::MaterialPoint { body: None, at: Vec2::zeros() };
        let p = ContactPoint {
            index: 0,
            normal: n,
            penetration: 1e-5,
            penetration_rate: 0.0,
            slip: Tangential::zeros(),
            share: 1.0,
            on_i: none,
            on_j: none,
        };
        let f = p.force_on_j(100.0, &Tangential::repeat(-7.0));
        assert!((f - (-n * 100.0 + crate::math::perp(n) * -7.0)).norm() < 1e-12, "{f:?}");
        assert!((f.dot(&n) + 100.0).abs() < 1e-12);
    }

    /// Joints of 1, 3 and 2 points: their points follow each other.
    #[test]
    fn points_are_laid_out_joint_after_joint() {
        let ranges: Vec<_> = point_ranges([1, 3, 2]).collect();
        assert_eq!(ranges, vec![0..1, 1..4, 4..6]);
    }
}
