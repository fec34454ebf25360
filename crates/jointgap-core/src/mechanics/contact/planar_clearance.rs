//! The planar kind's joints with contact: every joint whose parts touch rather than
//! stay together (a journal in its bearing, dry or lubricated; a block in its guide; a
//! joint's play; a gear mesh), as one type the run keeps in a list.

use super::gear::GearPair;
use super::geometry::JournalBearing;
use super::lubricated::LubricatedRevolute;
use super::normal::NormalForce;
use super::play::JointPlay;
use super::point::{ContactPoint, ContactPoints, Tangential};
use super::translational::ClearanceTranslational;
use super::{ClearanceJoint, ClearanceRevolute, ContactState};
use crate::error::Error;
use crate::mechanics::layout::Loads;
use crate::mechanics::planar_body::BodyState;
use crate::model::FrictionSpec;
use crate::output::ClearanceData;

/// A planar joint with contact.
#[derive(Debug, Clone)]
pub enum PlanarClearance {
    /// A journal in its bearing, dry.
    Revolute(ClearanceRevolute),
    /// A journal in its bearing on an oil film.
    Lubricated(LubricatedRevolute),
    /// A block in its guide.
    Translational(ClearanceTranslational),
    /// A revolute or prismatic joint's play.
    Play(JointPlay),
    /// A gear pair's mesh.
    Gear(GearPair),
}

/// Calls the same method on whichever joint `$self` holds.
macro_rules! each {
    ($self:expr, $c:ident => $call:expr) => {
        match $self {
            PlanarClearance::Revolute($c) => $call,
            PlanarClearance::Lubricated($c) => $call,
            PlanarClearance::Translational($c) => $call,
            PlanarClearance::Play($c) => $call,
            PlanarClearance::Gear($c) => $call,
        }
    };
}

impl PlanarClearance {
    /// The journal in its bearing of a revolute clearance joint, dry or lubricated.
    pub fn journal_bearing(&self) -> Option<&JournalBearing> {
        match self {
            PlanarClearance::Revolute(c) => Some(&c.geometry),
            PlanarClearance::Lubricated(c) => Some(&c.dry.geometry),
            _ => None,
        }
    }

    /// The normal law with its stiffness.
    pub fn normal(&self) -> &NormalForce {
        match self {
            PlanarClearance::Revolute(c) => &c.normal,
            PlanarClearance::Lubricated(c) => &c.dry.normal,
            PlanarClearance::Translational(c) => &c.normal,
            PlanarClearance::Play(c) => &c.normal,
            PlanarClearance::Gear(c) => &c.normal,
        }
    }

    /// The friction law at its contact points (none for a play or a gear mesh).
    pub fn friction(&self) -> &FrictionSpec {
        const NONE: FrictionSpec = FrictionSpec::None;
        match self {
            PlanarClearance::Revolute(c) => &c.friction,
            PlanarClearance::Lubricated(c) => &c.dry.friction,
            PlanarClearance::Translational(c) => &c.friction,
            PlanarClearance::Play(_) | PlanarClearance::Gear(_) => &NONE,
        }
    }
}

impl ClearanceJoint for PlanarClearance {
    type State = BodyState;
    type Point = ContactPoint;
    type Points = ContactPoints;
    type Friction = Tangential;

    fn name(&self) -> &str {
        each!(self, c => c.name())
    }

    #[inline]
    fn parts(&self) -> [Option<usize>; 2] {
        each!(self, c => c.parts())
    }

    fn data(&self) -> ClearanceData {
        each!(self, c => c.data())
    }

    fn check_initial_penetration(&self, i: &BodyState, j: &BodyState) -> Result<(), Error> {
        each!(self, c => c.check_initial_penetration(i, j))
    }

    #[inline]
    fn points(&self) -> usize {
        each!(self, c => c.points())
    }

    #[inline]
    fn reach(&self) -> f64 {
        each!(self, c => c.reach())
    }

    #[inline]
    fn contacts(&self, i: &BodyState, j: &BodyState, reach: f64) -> ContactPoints {
        each!(self, c => c.contacts(i, j, reach))
    }

    #[inline]
    fn force(&self, p: &ContactPoint, onset_speed: f64) -> (f64, Tangential) {
        each!(self, c => c.force(p, onset_speed))
    }

    fn losses(&self, i: &BodyState, j: &BodyState, states: &[ContactState]) -> (f64, f64) {
        each!(self, c => c.losses(i, j, states))
    }

    fn elastic_energy(&self, p: &ContactPoint) -> f64 {
        each!(self, c => c.elastic_energy(p))
    }

    #[inline]
    fn add_to(&self, i: &BodyState, j: &BodyState, states: &[ContactState], qe: &mut Loads) {
        each!(self, c => c.add_to(i, j, states, qe))
    }
}
