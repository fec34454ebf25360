//! Clearance revolute joints: the journal (pin on body j) moves freely inside the
//! bearing (hole on body i) and a contact force acts when it reaches the wall
//! (docs/physics.md section 2).

pub mod friction;
pub mod materials;
pub mod normal;
mod state;

pub use state::{ContactState, Mode};

use crate::error::{Error, Named};
use crate::math::{perp, Vec2};
use crate::mechanics::layout::Loads;
use crate::mechanics::planar::{self, BodyState};
use crate::mechanics::resolve::Resolver;
use crate::model::{Clearance, FrictionSpec, Joint};
use crate::output::ClearanceData;
use normal::NormalForce;

/// A checked clearance joint.
#[derive(Debug, Clone)]
pub struct ClearanceRevolute {
    /// Joint name.
    pub name: String,
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
    /// Normal law with its stiffness.
    pub normal: NormalForce,
    /// Friction law (checked).
    pub friction: FrictionSpec,
}

/// Where the journal is in its bearing, and how fast it moves.
#[derive(Debug, Clone, Copy)]
pub struct ContactKinematics {
    /// Eccentricity `r_J - r_B`, global axes [m].
    pub e: Vec2,
    /// Penetration `|e| - c` [m]; negative in free flight.
    pub penetration: f64,
    /// Penetration rate `v . n` [m/s].
    pub penetration_rate: f64,
    /// Tangential slip `v . t` [m/s].
    pub slip: f64,
    /// Unit normal `e / |e|`, from bearing centre towards the journal.
    pub n: Vec2,
    /// Contact point on the journal, global [m].
    pub point_journal: Vec2,
    /// Contact point on the bearing, global [m].
    pub point_bearing: Vec2,
}

/// The largest normal force [N] an initial penetration may stand for: a journal that
/// starts deeper in its bearing than its own normal law presses under 1 MN (100 t) is a
/// modelling error, not a preloaded contact.
pub const MAX_INITIAL_CONTACT_FORCE: f64 = 1e6;

/// Velocity of a global point `p` of a body.
fn point_velocity(b: &BodyState, p: Vec2) -> Vec2 {
    b.v + perp(p - b.r) * b.omega
}

impl ClearanceRevolute {
    /// The resolved contact data reported with a run's result.
    pub fn data(&self) -> ClearanceData {
        ClearanceData {
            joint: self.name.clone(),
            bearing_radius: self.r_bearing,
            journal_radius: self.r_journal,
            clearance: self.clearance,
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
        Ok(ClearanceRevolute {
            name: j.name.clone(),
            bearing,
            s_bearing: res.point(who, "point_i", bearing, &j.point_i)?,
            journal,
            s_journal: res.point(who, "point_j", journal, &j.point_j)?,
            r_bearing,
            r_journal,
            clearance: r_bearing - r_journal,
            normal: NormalForce::new(&j.name, &c.normal_law, stiffness, d_max_default)?,
            friction: {
                friction::check(&j.name, &c.friction)?;
                c.friction.clone()
            },
        })
    }

    /// Penetration [m] at which the elastic part of the normal law, `K delta^n`, reaches
    /// [`MAX_INITIAL_CONTACT_FORCE`]: the deepest initial penetration an elastic contact
    /// can have.
    pub fn max_initial_penetration(&self) -> f64 {
        (MAX_INITIAL_CONTACT_FORCE / self.normal.stiffness).powf(1.0 / self.normal.exponent)
    }

    /// Rejects an initial state (`k`, the kinematics after assembly) whose penetration no
    /// elastic contact can have ([`Self::max_initial_penetration`]); the error names the
    /// joint, the penetration and the likely causes.
    pub fn check_initial_penetration(&self, k: &ContactKinematics) -> Result<(), Error> {
        let limit = self.max_initial_penetration();
        if k.penetration <= limit {
            return Ok(());
        }
        let mm = 1e3;
        Err(Named::joint(&self.name).error_of_element(format!(
            "the journal starts {:.4} mm deep in the bearing (its centre {:.4} mm from the \
             bearing centre, radial clearance {:.4} mm), deeper than any elastic contact: this joint's \
             normal law (K = {:.4e} N/m^{}) presses {:.4} mm deep only under {:.0e} N; likely a wrong \
             point (point_i or point_j of this joint, or a point of a joint that places its bodies), \
             a wrong bearing or journal radius, or a length in the wrong unit",
            mm * k.penetration,
            mm * k.e.norm(),
            mm * self.clearance,
            self.normal.stiffness,
            self.normal.exponent,
            mm * limit,
            MAX_INITIAL_CONTACT_FORCE,
        )))
    }

    /// Journal-in-bearing geometry and relative motion (`contact_journal_bearing`).
    pub fn kinematics(&self, bearing: &BodyState, journal: &BodyState) -> ContactKinematics {
        let centre_b = bearing.r + bearing.rotate(self.s_bearing);
        let centre_j = journal.r + journal.rotate(self.s_journal);
        let e = centre_j - centre_b;
        let ecc = e.norm();
        // Concentric: any normal will do; the force is zero there.
        let n = if ecc > 1e-15 { e / ecc } else { Vec2::new(1.0, 0.0) };
        let point_journal = centre_j + n * self.r_journal;
        let point_bearing = centre_b + n * self.r_bearing;
        let v = point_velocity(journal, point_journal) - point_velocity(bearing, point_bearing);
        ContactKinematics {
            e,
            penetration: ecc - self.clearance,
            penetration_rate: v.dot(&n),
            slip: v.dot(&perp(n)),
            n,
            point_journal,
            point_bearing,
        }
    }

    /// Normal and tangential force [N] for given kinematics and impact onset speed.
    pub fn contact_force(&self, k: &ContactKinematics, onset_speed: f64) -> (f64, f64) {
        let f_n = self.normal.force(k.penetration, k.penetration_rate, onset_speed);
        let f_t = if f_n > 0.0 { self.friction.force(k.slip, f_n) } else { 0.0 };
        (f_n, f_t)
    }

    /// Power [W] the contact dissipates, as `(normal, friction)`. The contact force does
    /// work at the rate `-F_N delta_dot + F_T v_t` on the two bodies (the journal force
    /// at the journal's contact point, its opposite at the bearing's, and `delta_dot`,
    /// `v_t` the relative velocity of those points along `n` and `t`); of it,
    /// `-K delta^n delta_dot` is the rate of the elastic energy counted as potential
    /// energy. The rest is lost: `(F_N - K delta^n) delta_dot` by the normal law's
    /// damping (and by clipping, which drops the elastic force a pulling force would
    /// return), `-F_T v_t >= 0` by friction.
    pub fn losses(&self, k: &ContactKinematics, state: &ContactState) -> (f64, f64) {
        let (f_n, f_t) = self.contact_force(k, state.onset_for(k.penetration_rate));
        ((f_n - self.normal.elastic_force(k.penetration)) * k.penetration_rate, -f_t * k.slip)
    }

    /// Force on the journal, global axes: `-F_N n + F_T t` [N].
    pub fn journal_force(k: &ContactKinematics, f_n: f64, f_t: f64) -> Vec2 {
        -k.n * f_n + perp(k.n) * f_t
    }

    /// Adds the contact forces to the loads: the journal force at the journal's contact
    /// point, the opposite on the bearing at its own.
    pub fn add_to(&self, bearing: &BodyState, journal: &BodyState, state: &ContactState, qe: &mut Loads) {
        let k = self.kinematics(bearing, journal);
        let (f_n, f_t) = self.contact_force(&k, state.onset_for(k.penetration_rate));
        if f_n != 0.0 || f_t != 0.0 {
            let f = Self::journal_force(&k, f_n, f_t);
            add_force_at(qe, self.journal, journal, k.point_journal, f);
            add_force_at(qe, self.bearing, bearing, k.point_bearing, -f);
        }
    }
}

/// Adds a force at a global point of a body.
fn add_force_at(loads: &mut Loads, b: Option<usize>, state: &BodyState, p: Vec2, f: Vec2) {
    if let Some(qe) = loads.body(b) {
        planar::add_force(qe, p - state.r, f);
    }
}
