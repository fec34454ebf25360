//! What a run needs of a body kind beyond the dynamics: how its models compile, and the
//! output channels of its joints, drivers and markers. Each kind's channels are its own
//! module ([`planar_channels`](super::planar_channels)); the run is written once.

use super::record::Cursor;
use crate::dynamics::{Contacts, Workspace};
use crate::error::Error;
use crate::mechanics::contact::geometry::Worn;
use crate::mechanics::contact::{ContactState, WearContact};
use crate::mechanics::kind::RowEval;
use crate::system::{BodyInfo, JointInfo, MarkerInfo, System};

/// A body kind a model can be made of.
pub trait Kind: Contacts {
    /// The plain data of a model of this kind.
    type Model;

    /// Checks and compiles a model of this kind.
    fn compile(model: &Self::Model) -> Result<System<Self>, Error>;

    /// Notes on implausible magnitudes in the model (a mass in grams given as kg, ...).
    fn magnitude_warnings(model: &Self::Model, sys: &System<Self>) -> Vec<String>;

    /// The force channels of joint `j` as `(quantity, point)`, in the order a sample
    /// writes them: `point` is the contact point's number from 1 in a joint of several.
    fn joint_force_channels(sys: &System<Self>, j: &JointInfo<Self>) -> Vec<(&'static str, Option<usize>)>;

    /// How many force channels joint `j` has ([`Kind::joint_force_channels`]), without
    /// naming them: a sample asks for every joint.
    fn joint_force_channel_count(sys: &System<Self>, j: &JointInfo<Self>) -> usize;

    /// Writes joint `j`'s force channels: the reaction on body j (for a clearance joint,
    /// its contact quantities), the bodies' states `(bi, bj)`, each row's multiplier by
    /// `lambda_of`.
    #[allow(clippy::too_many_arguments)]
    fn put_joint_forces(
        out: &mut Cursor,
        sys: &System<Self>,
        ws: &Workspace<Self>,
        j: &JointInfo<Self>,
        bodies: (&Self::State, &Self::State),
        state: (&[f64], &[f64]),
        lambda_of: &dyn Fn(usize) -> f64,
    );

    /// The channels of a joint's coordinate and its rate, after its forces.
    fn coordinate_quantities(kind: Self::JointKind) -> &'static [&'static str];

    /// Writes a joint's coordinates and their rates (those a driver prescribes), as
    /// [`Kind::coordinate_quantities`] names them.
    fn put_joint_coordinates(out: &mut Cursor, j: &JointInfo<Self>, bi: &Self::State, bj: &Self::State);

    /// A driver's effort (torque or force) on the driven body from its row `ev` and
    /// multiplier `lambda`: on body j, or on body i where j is the ground (`on_j` false).
    fn driver_effort(ev: &RowEval<Self::Row>, rotation: bool, on_j: bool, lambda: f64) -> f64;

    /// A body's channels after its coordinates' (none for a planar body).
    const BODY_EXTRA: &'static [&'static str] = &[];

    /// Writes body `b`'s [`Kind::BODY_EXTRA`] channels from its positions `q`, velocities
    /// `v` and accelerations `a`.
    fn put_body_extra(_out: &mut Cursor, _b: &BodyInfo<Self>, _q: &[f64], _v: &[f64], _a: &[f64]) {}

    /// A marker's channels.
    const MARKER_QUANTITIES: &'static [&'static str];

    /// The clearance joint `c` as a joint that wears, a dry journal in its bearing
    /// (docs/wear.md); a kind without wear has none.
    fn wears(_c: &Self::Clearance) -> Option<Wearing<'_>> {
        None
    }

    /// The wear integrands of clearance joint `k`'s wearing points at `(q, v)`, in their
    /// contact states `states`, into `out` ([`super::wear`]): `None` for a point that
    /// does not wear or carries no load.
    fn wear_integrands(
        _sys: &System<Self>,
        _k: usize,
        _states: &[ContactState],
        _q: &[f64],
        _v: &[f64],
        out: &mut [Option<Integrand>],
    ) {
        out.fill(None);
    }

    /// Writes marker `m`'s channels at `(q, v)`, the accelerations in `ws`.
    fn put_marker(
        out: &mut Cursor,
        sys: &System<Self>,
        ws: &Workspace<Self>,
        m: &MarkerInfo<Self>,
        q: &[f64],
        v: &[f64],
    );
}

/// The channels of a clearance joint of `points` contact points as `(quantity, point)`:
/// each of `quantities` that is the joint's own (`false`) once, each contact point's
/// (`true`) once for a joint of one point, else once per point numbered from 1
/// (`<joint>.p<i>.<quantity>`, docs/outputs.md).
pub(super) fn clearance_channels(
    quantities: &[(&'static str, bool)],
    points: usize,
) -> Vec<(&'static str, Option<usize>)> {
    let mut out = Vec::new();
    for &(quantity, of_point) in quantities {
        match (of_point, points) {
            (true, 1) | (false, _) => out.push((quantity, None)),
            (true, _) => out.extend((1..=points).map(|i| (quantity, Some(i)))),
        }
    }
    out
}

/// How many channels [`clearance_channels`] names, without naming them.
pub(super) fn clearance_channel_count(quantities: &[(&'static str, bool)], points: usize) -> usize {
    quantities.iter().map(|&(_, p)| if p { points } else { 1 }).sum()
}

/// A clearance joint that wears, as a run's wear sees it: a journal in its bearing.
#[derive(Debug, Clone, Copy)]
pub struct Wearing<'a> {
    /// Its name.
    pub name: &'a str,
    /// Bearing and journal radii [m].
    pub radii: (f64, f64),
    /// Radial clearance [m].
    pub clearance: f64,
    /// The parts' profiles (`None`: round).
    pub worn: Option<&'a Worn>,
    /// Its line contact, or why it has none.
    pub contact: &'a Result<WearContact, String>,
    /// Its contact points that wear, the first of its points: each a section of the
    /// journal that stands for `share` of its length (one for a planar journal, a
    /// spatial journal's two ends a half each).
    pub points: usize,
    /// The part of the length each point stands for.
    pub share: f64,
}

/// The wear integrand of a journal in its bearing at one state: where its parts touch
/// and how hard and fast they slide there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Integrand {
    /// Normal force [N] of the whole length: a section's force over its share of the
    /// length ([`Wearing::share`]).
    pub f_n: f64,
    /// Sliding speed `|v_t|` of the contact [m/s].
    pub speed: f64,
    /// The contact normal's angle in the bearing body's frame [rad].
    pub bearing_angle: f64,
    /// The contact normal's angle in the journal body's frame [rad].
    pub journal_angle: f64,
    /// The bearing body's and the journal body's angular velocities [rad/s]: each
    /// part turns under the contact backwards at its own rate.
    pub spins: (f64, f64),
    /// The eccentricity `|e|` [m].
    pub eccentricity: f64,
    /// The eccentricity's angle less the contact normal's [rad] (zero for round parts).
    pub lead: f64,
}
