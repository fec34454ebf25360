//! The planar kind's output channels: a joint's reaction on body j (`fx fy`, and the
//! couple of a prismatic or fixed joint), a clearance joint's contact quantities, the
//! joint coordinates, the drivers' efforts and the markers' motion (docs/outputs.md).

use super::kind::{clearance_channel_count, clearance_channels, Kind};
use super::measures::{joint_coordinate, marker_motion, BodyMotion};
use super::record::Cursor;
use crate::dynamics::Workspace;
use crate::error::Error;
use crate::math::{cross, rotate, Vec2};
use crate::mechanics::contact::{self, ClearanceJoint, ContactPoint, Mode, Tangential, MAX_POINTS};
use crate::mechanics::kind::RowEval;
use crate::mechanics::planar::{self, BodyRow, BodyState, Planar};
use crate::model::{JointKind, Model};
use crate::system::{JointInfo, MarkerInfo, System};

/// Channels of each kind of joint: the force on body j (for a clearance joint, the
/// contact force on the journal body), then the kind's own.
const REVOLUTE_QUANTITIES: [&str; 2] = ["fx", "fy"];
const PRISMATIC_QUANTITIES: [&str; 3] = ["fx", "fy", "moment"];
/// A clearance joint's channels: the joint's own (`fx fy`: the resultant contact force
/// on the journal body; `ex ey`: the eccentricity in the bearing body's frame) and each
/// contact point's (`true`). A joint of one point names them all `<joint>.<quantity>`; a
/// joint of several writes each point's quantity for every point in turn, named
/// `<joint>.p<i>.<quantity>` with `i` from 1 (docs/outputs.md).
const CLEARANCE_QUANTITIES: [(&str, bool); 10] = [
    ("fx", false),
    ("fy", false),
    ("fn", true),
    ("ft", true),
    ("penetration", true),
    ("penetration_rate", true),
    ("ex", false),
    ("ey", false),
    ("slip", true),
    ("mode", true),
];

/// The force channels of a joint of kind `kind` other than a clearance joint, in the
/// order a sample writes them.
fn joint_quantities(kind: JointKind) -> &'static [&'static str] {
    match kind {
        JointKind::Revolute => &REVOLUTE_QUANTITIES,
        JointKind::Prismatic | JointKind::Fixed => &PRISMATIC_QUANTITIES,
        JointKind::ClearanceRevolute => unreachable!("a clearance joint's channels depend on its points"),
    }
}

/// The force channels of joint `j` as `(quantity, point)`, in the order a sample writes
/// them: `point` is the contact point's number from 1 in a joint of several points.
fn joint_channels(sys: &System, j: &JointInfo) -> Vec<(&'static str, Option<usize>)> {
    let Some(k) = j.clearance else {
        return joint_quantities(j.kind).iter().map(|&q| (q, None)).collect();
    };
    clearance_channels(&CLEARANCE_QUANTITIES, sys.clearances[k].points())
}

/// How many force channels joint `j` has ([`joint_channels`]).
fn joint_channel_count(sys: &System, j: &JointInfo) -> usize {
    match j.clearance {
        Some(k) => clearance_channel_count(&CLEARANCE_QUANTITIES, sys.clearances[k].points()),
        None => joint_quantities(j.kind).len(),
    }
}

/// The joint coordinate and its rate ([`joint_coordinate`]), after a joint's forces.
fn coordinate_quantities(kind: JointKind) -> &'static [&'static str] {
    match kind {
        JointKind::Revolute | JointKind::ClearanceRevolute => &["angle", "omega"],
        JointKind::Prismatic => &["travel", "speed"],
        JointKind::Fixed => &[],
    }
}

/// A marker's channels: position, velocity, acceleration in its frame.
const MARKER_QUANTITIES: [&str; 6] = ["x", "y", "vx", "vy", "ax", "ay"];

/// A joint's force channels: for a clearance joint the contact force on the journal and
/// its contact quantities, for the others the reaction on body j (and the couple).
fn put_joint_forces(
    out: &mut Cursor,
    sys: &System,
    ws: &Workspace,
    j: &JointInfo,
    (bi, bj): (&BodyState, &BodyState),
    (q, v): (&[f64], &[f64]),
    lambda_of: &dyn Fn(usize) -> f64,
) {
    let mut put = |x: f64| out.put(x);
    if let Some(k) = j.clearance {
        let c = &sys.clearances[k];
        let (bearing, journal) =
            (sys.body_state(c.geometry.bearing, q, v), sys.body_state(c.geometry.journal, q, v));
        let points = c.contacts(&bearing, &journal, f64::INFINITY);
        let first = contact::slots(&sys.clearances).nth(k).expect("joint k's points").2.start;
        let states = &ws.contacts[first..first + c.points()];
        let mut forces = [(0.0, Tangential::zeros()); MAX_POINTS];
        for (p, force) in points.iter().zip(&mut forces) {
            *force = c.force(p, states[p.index].onset_for(p.penetration_rate));
        }
        let forces = &forces[..points.len()];
        let f = points
            .iter()
            .zip(forces)
            .map(|(p, (f_n, f_t))| p.force_on_j(*f_n, f_t))
            .reduce(|a, b| a + b)
            .unwrap_or_else(Vec2::zeros);
        let e_local = rotate(-bearing.phi(), c.geometry.eccentricity(&bearing, &journal));
        // The located state decides, not the sign of the penetration: right after
        // an onset, projection may leave the penetration a hair below zero.
        let mode = |p: &ContactPoint| {
            let state = &states[p.index];
            if state.in_contact {
                state.mode
            } else {
                Mode::FreeFlight
            }
        };
        put(f.x);
        put(f.y);
        forces.iter().for_each(|(f_n, _)| put(*f_n));
        forces.iter().for_each(|(_, f_t)| put(f_t[0]));
        points.iter().for_each(|p| put(p.penetration));
        points.iter().for_each(|p| put(p.penetration_rate));
        put(e_local.x);
        put(e_local.y);
        points.iter().for_each(|p| put(p.slip[0]));
        points.iter().for_each(|p| put(mode(p) as u8 as f64));
        return;
    }
    let (mut f, mut m) = (Vec2::zeros(), 0.0);
    for r in j.rows.clone() {
        let ev = sys.rows[r].kind.eval(
            bi,
            bj,
            crate::mechanics::drivers::Motion { position: 0.0, speed: 0.0, acceleration: 0.0 },
        );
        let l = lambda_of(r);
        f -= Vec2::new(ev.jac_j[0], ev.jac_j[1]) * l;
        m -= ev.jac_j[2] * l;
    }
    put(f.x);
    put(f.y);
    if j.kind != JointKind::Revolute {
        // Couple about the joint point of body j.
        put(m - cross(bj.rotate(j.s_j), f));
    }
}

impl Kind for Planar {
    type Model = Model;

    fn compile(model: &Model) -> Result<System, Error> {
        System::new(model)
    }

    fn magnitude_warnings(model: &Model, sys: &System) -> Vec<String> {
        crate::system::magnitudes::warnings(model, sys)
    }

    fn joint_force_channels(sys: &System, j: &JointInfo) -> Vec<(&'static str, Option<usize>)> {
        joint_channels(sys, j)
    }

    #[inline]
    fn joint_force_channel_count(sys: &System, j: &JointInfo) -> usize {
        joint_channel_count(sys, j)
    }

    fn put_joint_forces(
        out: &mut Cursor,
        sys: &System,
        ws: &Workspace,
        j: &JointInfo,
        bodies: (&BodyState, &BodyState),
        state: (&[f64], &[f64]),
        lambda_of: &dyn Fn(usize) -> f64,
    ) {
        put_joint_forces(out, sys, ws, j, bodies, state, lambda_of)
    }

    fn coordinate_quantities(kind: JointKind) -> &'static [&'static str] {
        coordinate_quantities(kind)
    }

    fn put_joint_coordinates(out: &mut Cursor, j: &JointInfo, bi: &BodyState, bj: &BodyState) {
        let (value, rate) = joint_coordinate(j, bi, bj).expect("a joint with coordinate channels");
        out.put(value);
        out.put(rate);
    }

    fn driver_effort(ev: &RowEval<BodyRow>, rotation: bool, on_j: bool, l: f64) -> f64 {
        match (rotation, on_j) {
            (true, true) => -ev.jac_j[2] * l,
            (true, false) => -ev.jac_i[2] * l,
            (false, true) => -l,
            (false, false) => l,
        }
    }

    const MARKER_QUANTITIES: &'static [&'static str] = &MARKER_QUANTITIES;

    fn put_marker(out: &mut Cursor, sys: &System, ws: &Workspace, m: &MarkerInfo, q: &[f64], v: &[f64]) {
        let motion = |b: Option<usize>| match b {
            None => BodyMotion::default(),
            Some(k) => {
                let (acceleration, alpha) = planar::read_acceleration(&ws.qdd[sys.layout.slot(k).v()]);
                BodyMotion { state: sys.body_state(b, q, v), acceleration, alpha }
            }
        };
        for p in marker_motion(m, &motion(m.body), &motion(m.frame)) {
            out.put(p.x);
            out.put(p.y);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::kind::clearance_channels;
    use super::CLEARANCE_QUANTITIES;

    /// One point: the joint's ten channels as they have always been; two points: each
    /// point quantity once per point, numbered from 1, in the same places.
    #[test]
    fn clearance_channels_by_point() {
        let names = |points| -> Vec<String> {
            clearance_channels(&CLEARANCE_QUANTITIES, points)
                .into_iter()
                .map(|(q, p)| p.map_or(format!("gap.{q}"), |i| format!("gap.p{i}.{q}")))
                .collect()
        };
        let one = ["fx", "fy", "fn", "ft", "penetration", "penetration_rate", "ex", "ey", "slip", "mode"];
        assert_eq!(names(1), one.map(|q| format!("gap.{q}")));
        let two = names(2);
        assert_eq!(two.len(), 16);
        assert_eq!(two[..6], ["gap.fx", "gap.fy", "gap.p1.fn", "gap.p2.fn", "gap.p1.ft", "gap.p2.ft"]);
        assert_eq!(two[10..14], ["gap.ex", "gap.ey", "gap.p1.slip", "gap.p2.slip"]);
        assert_eq!(two[15], "gap.p2.mode");
    }
}
