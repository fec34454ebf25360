//! Joint play (backlash): a revolute or prismatic joint whose own coordinate (relative
//! angle, travel) is free within a play and stopped by a contact law beyond it
//! (docs/backlash.md). One contact point: the coordinate's excess over the play, on
//! whichever side it is.

use super::normal::NormalForce;
use super::point::{ContactPoint, ContactPoints, MaterialPoint, Tangential};
use super::{add_force_at, ClearanceJoint, ContactState, MAX_INITIAL_CONTACT_FORCE};
use crate::error::{Error, Named};
use crate::math::{perp, Vec2};
use crate::mechanics::layout::Loads;
use crate::mechanics::planar_body::BodyState;
use crate::model::{Joint, Play};
use crate::output::ClearanceData;
use crate::scalar::Real;

/// What the play acts on.
#[derive(Debug, Clone, PartialEq)]
pub enum PlayCoordinate {
    /// The relative angle `phi_j - phi_i` of a revolute joint [rad].
    Angle,
    /// The travel of point j from point i along the axis (unit, body i's frame) [m].
    Travel {
        /// Joint point on body i, its frame [m].
        s_i: Vec2,
        /// Joint point on body j, its frame [m].
        s_j: Vec2,
        /// Sliding direction, unit, body i's frame.
        axis: Vec2,
    },
}

/// A checked joint play: the coordinate, the middle of its free range, half its width,
/// and the stop's law.
#[derive(Debug, Clone)]
pub struct JointPlay {
    /// Joint name.
    pub name: String,
    /// Bodies i and j.
    pub bodies: [Option<usize>; 2],
    /// The coordinate the play acts on.
    pub coordinate: PlayCoordinate,
    /// Coordinate at the middle of the play [rad or m].
    pub centre: f64,
    /// Half the play [rad or m].
    pub half_play: f64,
    /// The stop's law; its stiffness in N m/rad^n or N/m^n.
    pub normal: NormalForce,
}

/// Checks joint `joint`'s play `p` (of an angle when `rotation`, else of a travel):
/// half the play and the stop's law. Errors name the joint and key.
pub(crate) fn check_play(joint: &str, p: &Play, rotation: bool) -> Result<(f64, NormalForce), Error> {
    let who = Named::joint(joint);
    let unit = if rotation { "rad" } else { "m" };
    if !(p.play.is_finite() && p.play >= 0.0) {
        return Err(who.error(
            "play.play",
            format!("play = {} {unit} must be zero or positive (it is the total free range)", p.play),
        ));
    }
    if let Some(c) = p.centre.filter(|c| !c.is_finite()) {
        return Err(who.error("play.centre", format!("centre = {c} {unit} is not finite")));
    }
    if !(p.stiffness.is_finite() && p.stiffness > 0.0) {
        return Err(who.error("play.stiffness", format!("stiffness = {} must be positive", p.stiffness)));
    }
    Ok((0.5 * p.play, NormalForce::new(joint, &p.normal_law, p.stiffness, None)?))
}

impl JointPlay {
    /// Checks joint `j`'s play `p`; `placed` is the coordinate at the model's placement,
    /// the middle of the play unless `centre` is given. Errors name the joint and key.
    pub(crate) fn new(
        j: &Joint,
        p: &Play,
        bodies: [Option<usize>; 2],
        coordinate: PlayCoordinate,
        placed: f64,
    ) -> Result<Self, Error> {
        let (half_play, normal) = check_play(&j.name, p, coordinate == PlayCoordinate::Angle)?;
        Ok(JointPlay {
            name: j.name.clone(),
            bodies,
            coordinate,
            centre: p.centre.unwrap_or(placed),
            half_play,
            normal,
        })
    }

    /// The coordinate and its rate at the bodies' states, with the global point and
    /// direction along which a travel's stop acts (the angle's: body j's origin, none),
    /// in any number type.
    #[inline]
    pub fn coordinate<T: Real>(&self, i: &BodyState<T>, j: &BodyState<T>) -> (T, T, Vec2<T>, Vec2<T>) {
        match &self.coordinate {
            PlayCoordinate::Angle => (j.phi() - i.phi(), j.omega - i.omega, j.r, Vec2::zeros()),
            PlayCoordinate::Travel { s_i, s_j, axis } => {
                let a_j = j.rotate(*s_j);
                let p_j = j.r + a_j;
                let u = i.rotate(*axis);
                // The travel's rate is the velocity of point j relative to body i's
                // material point where it is, along u (u turns with body i).
                let v_j = j.v + perp(a_j) * j.omega;
                let v_i = i.v + perp(p_j - i.r) * i.omega;
                ((p_j - i.r - i.rotate(*s_i)).dot(&u), (v_j - v_i).dot(&u), p_j, u)
            }
        }
    }

    /// The one point within `reach` ([`ClearanceJoint::contacts`]), in any number type.
    #[inline]
    pub fn points_at<T: Real>(&self, i: &BodyState<T>, j: &BodyState<T>, reach: f64) -> ContactPoints<T> {
        let mut out = ContactPoints::new();
        let (x, rate, at, _) = self.coordinate(i, j);
        let side = if x >= self.centre { 1.0 } else { -1.0 };
        let penetration = (x - self.centre) * side - self.half_play;
        if penetration > -reach {
            out.push(ContactPoint {
                index: 0,
                normal: Vec2::new(T::constant(side), T::constant(0.0)),
                penetration,
                penetration_rate: rate * side,
                slip: Tangential::zeros(),
                share: T::constant(1.0),
                on_i: MaterialPoint { body: self.bodies[0], at },
                on_j: MaterialPoint { body: self.bodies[1], at },
            });
        }
        out
    }

    /// Adds the stop's loads ([`ClearanceJoint::add_to`]) in any number type: `onset(k,
    /// rate)` is the impact onset speed of point `k` at penetration rate `rate`
    /// ([`ContactState::onset_for`]).
    #[inline]
    pub fn add_play_loads<T: Real>(
        &self,
        i: &BodyState<T>,
        j: &BodyState<T>,
        onset: impl Fn(usize, T) -> T,
        qe: &mut Loads<T>,
    ) {
        for p in self.points_at(i, j, self.reach()).iter() {
            let f_n =
                self.normal.force(p.penetration, p.penetration_rate, onset(p.index, p.penetration_rate));
            if f_n == 0.0 {
                continue;
            }
            let push = -p.normal.x * f_n;
            match &self.coordinate {
                PlayCoordinate::Angle => {
                    for (body, sign) in [(self.bodies[1], 1.0), (self.bodies[0], -1.0)] {
                        if let Some(q) = qe.body(body) {
                            q[2] += push * sign;
                        }
                    }
                }
                PlayCoordinate::Travel { .. } => {
                    let (.., at, u) = self.coordinate(i, j);
                    add_force_at(qe, self.bodies[1], j, at, u * push);
                    add_force_at(qe, self.bodies[0], i, at, -u * push);
                }
            }
        }
    }
}

impl ClearanceJoint for JointPlay {
    type State = BodyState;
    type Point = ContactPoint;
    type Points = ContactPoints;
    type Friction = Tangential;

    fn name(&self) -> &str {
        &self.name
    }

    fn parts(&self) -> [Option<usize>; 2] {
        self.bodies
    }

    /// Half the play as the clearance (radii are those of no round part: zero).
    fn data(&self) -> ClearanceData {
        ClearanceData {
            joint: self.name.clone(),
            bearing_radius: 0.0,
            journal_radius: 0.0,
            clearance: self.half_play,
            stiffness: self.normal.stiffness,
            exponent: self.normal.exponent,
        }
    }

    fn check_initial_penetration(&self, i: &BodyState, j: &BodyState) -> Result<(), Error> {
        let limit = (MAX_INITIAL_CONTACT_FORCE / self.normal.stiffness).powf(1.0 / self.normal.exponent);
        let p = self.contacts(i, j, f64::INFINITY)[0];
        if p.penetration <= limit {
            return Ok(());
        }
        let (x, ..) = self.coordinate(i, j);
        Err(Named::joint(&self.name).error_of_element(format!(
            "the joint starts at {x:.6} ({} from the middle of its play {:.6}), beyond the \
             play of +-{:.6} by {:.6}, more than its stop's law gives under {MAX_INITIAL_CONTACT_FORCE:.0e}: \
             check play.centre, the bodies' angles and the units (radians, metres)",
            x - self.centre,
            self.centre,
            self.half_play,
            p.penetration,
        )))
    }

    fn points(&self) -> usize {
        1
    }

    fn reach(&self) -> f64 {
        self.normal.reach()
    }

    /// The one point: penetration `|x - centre| - play/2`, its normal's first component
    /// the side (+1 beyond the upper end, -1 below the lower), the rate that of the
    /// penetration.
    #[inline]
    fn contacts(&self, i: &BodyState, j: &BodyState, reach: f64) -> ContactPoints {
        self.points_at(i, j, reach)
    }

    #[inline]
    fn force(&self, p: &ContactPoint, onset_speed: f64) -> (f64, Tangential) {
        (self.normal.force(p.penetration, p.penetration_rate, onset_speed), Tangential::zeros())
    }

    fn losses(&self, i: &BodyState, j: &BodyState, states: &[ContactState]) -> (f64, f64) {
        super::sum_losses(self.contacts(i, j, self.reach()).iter(), |p| {
            let (f_n, _) = self.force(p, states[0].onset_for(p.penetration_rate));
            ((f_n - self.normal.elastic_force(p.penetration)) * p.penetration_rate, 0.0)
        })
    }

    fn elastic_energy(&self, p: &ContactPoint) -> f64 {
        self.normal.elastic_energy(p.penetration)
    }

    /// The stop's torque on body j (the opposite on body i), or its force along the axis
    /// at point j on body j and the opposite on body i's material point there (no couple
    /// between them), against the side the coordinate left the play on.
    #[inline]
    fn add_to(&self, i: &BodyState, j: &BodyState, states: &[ContactState], qe: &mut Loads) {
        self.add_play_loads(i, j, |k, rate| states[k].onset_for(rate), qe);
    }
}
