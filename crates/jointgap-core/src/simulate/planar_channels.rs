//! The planar kind's output channels: a joint's reaction on body j (`fx fy`, and the
//! couple of a prismatic or fixed joint), a clearance joint's contact quantities, the
//! joint coordinates, the drivers' efforts and the markers' motion (docs/outputs.md).

use super::kind::{clearance_channel_count, clearance_channels, Kind, Wearing};
use super::measures::{joint_coordinate, marker_motion, BodyMotion};
use super::record::Cursor;
use crate::dynamics::Workspace;
use crate::error::Error;
use crate::math::{cross, rotate, Vec2};
use crate::mechanics::contact::planar_clearance::PlanarClearance;
use crate::mechanics::contact::play::PlayCoordinate;
use crate::mechanics::contact::{
    self, ClearanceJoint, ContactPoint, ContactState, Mode, Tangential, MAX_POINTS,
};
use crate::mechanics::kind::RowEval;
use crate::mechanics::planar::Planar;
use crate::mechanics::planar_body::{self, BodyRow, BodyState};
use crate::model::{JointKind, Model};
use crate::system::{JointInfo, MarkerInfo, System};

/// The reaction channels of a joint with equations, by the ideal kind whose equations
/// it keeps: the force on body j, and the couple of a prismatic or fixed joint.
const REVOLUTE_QUANTITIES: [&str; 2] = ["fx", "fy"];
const PRISMATIC_QUANTITIES: [&str; 3] = ["fx", "fy", "moment"];
/// A revolute clearance joint's channels: the joint's own (`fx fy`: the resultant contact
/// force on the journal body; `ex ey`: the eccentricity in the bearing body's frame) and
/// each contact point's (`true`). A joint of one point names them all
/// `<joint>.<quantity>`; a joint of several writes each point's quantity for every point
/// in turn, named `<joint>.p<i>.<quantity>` with `i` from 1 (docs/outputs.md).
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
/// A lubricated revolute joint's, after the clearance joint's (whose `fx fy` are then the
/// film's and the contact's force together): the film's.
const FILM_QUANTITIES: [(&str, bool); 8] = [
    ("eccentricity_ratio", false),
    ("attitude", false),
    ("film_thickness", false),
    ("film_fx", false),
    ("film_fy", false),
    ("peak_pressure", false),
    ("film_mode", false),
    ("friction_torque", false),
];
/// A translational clearance joint's: `fx fy` the resultant on the block, each corner's
/// contact quantities, the block's `tilt` and `offset` in the guide.
const TRANSLATIONAL_QUANTITIES: [(&str, bool); 10] = [
    ("fx", false),
    ("fy", false),
    ("fn", true),
    ("ft", true),
    ("penetration", true),
    ("penetration_rate", true),
    ("tilt", false),
    ("offset", false),
    ("slip", true),
    ("mode", true),
];
/// A revolute joint's play, after its reaction: the angle from the middle of the play,
/// the stop's torque on body j, and its contact quantities.
const ANGLE_PLAY_QUANTITIES: [(&str, bool); 5] = [
    ("play_angle", false),
    ("torque", false),
    ("penetration", true),
    ("penetration_rate", true),
    ("mode", true),
];
/// A prismatic joint's play: the same along the axis.
const TRAVEL_PLAY_QUANTITIES: [(&str, bool); 5] = [
    ("play_travel", false),
    ("force", false),
    ("penetration", true),
    ("penetration_rate", true),
    ("mode", true),
];
/// A gear pair's: the tooth force on gear 2, the mesh along the line of action, the
/// normal tooth force, each gear's tooth torque, the contact quantities and the mesh
/// stiffness there.
const GEAR_QUANTITIES: [(&str, bool); 10] = [
    ("fx", false),
    ("fy", false),
    ("mesh", false),
    ("fn", true),
    ("torque_1", false),
    ("torque_2", false),
    ("penetration", true),
    ("penetration_rate", true),
    ("mode", true),
    ("stiffness", false),
];

/// The reaction channels of a joint of kind `kind` (none for a joint without equations).
fn joint_quantities(kind: JointKind) -> &'static [&'static str] {
    match kind.equations() {
        Some(JointKind::Revolute) => &REVOLUTE_QUANTITIES,
        Some(_) => &PRISMATIC_QUANTITIES,
        None => &[],
    }
}

/// The contact channels of a joint with contact, in two parts written one after the
/// other.
fn contact_quantities(c: &PlanarClearance) -> [&'static [(&'static str, bool)]; 2] {
    match c {
        PlanarClearance::Revolute(_) => [&CLEARANCE_QUANTITIES, &[]],
        PlanarClearance::Lubricated(_) => [&CLEARANCE_QUANTITIES, &FILM_QUANTITIES],
        PlanarClearance::Translational(_) => [&TRANSLATIONAL_QUANTITIES, &[]],
        PlanarClearance::Play(p) if p.coordinate == PlayCoordinate::Angle => [&ANGLE_PLAY_QUANTITIES, &[]],
        PlanarClearance::Play(_) => [&TRAVEL_PLAY_QUANTITIES, &[]],
        PlanarClearance::Gear(_) => [&GEAR_QUANTITIES, &[]],
    }
}

/// The force channels of joint `j` as `(quantity, point)`, in the order a sample writes
/// them: its reaction, then its contact's (`point` the contact point's number from 1 in
/// a joint of several points).
fn joint_channels(sys: &System, j: &JointInfo) -> Vec<(&'static str, Option<usize>)> {
    let mut out: Vec<_> = joint_quantities(j.kind).iter().map(|&q| (q, None)).collect();
    if let Some(k) = j.clearance {
        let c = &sys.clearances[k];
        for part in contact_quantities(c) {
            out.extend(clearance_channels(part, c.points()));
        }
    }
    out
}

/// How many force channels joint `j` has ([`joint_channels`]).
fn joint_channel_count(sys: &System, j: &JointInfo) -> usize {
    joint_quantities(j.kind).len()
        + j.clearance.map_or(0, |k| {
            let c = &sys.clearances[k];
            contact_quantities(c).iter().map(|part| clearance_channel_count(part, c.points())).sum::<usize>()
        })
}

/// The joint coordinate and its rate ([`joint_coordinate`]), after a joint's forces.
fn coordinate_quantities(kind: JointKind) -> &'static [&'static str] {
    match kind.coordinate() {
        Some(true) => &["angle", "omega"],
        Some(false) => &["travel", "speed"],
        None => &[],
    }
}

/// A marker's channels: position, velocity, acceleration in its frame.
const MARKER_QUANTITIES: [&str; 6] = ["x", "y", "vx", "vy", "ax", "ay"];

/// A joint's force channels: the reaction on body j (and the couple) of a joint with
/// equations, then the contact quantities of a joint with contact.
fn put_joint_forces(
    out: &mut Cursor,
    sys: &System,
    ws: &Workspace,
    j: &JointInfo,
    (bi, bj): (&BodyState, &BodyState),
    (q, v): (&[f64], &[f64]),
    lambda_of: &dyn Fn(usize) -> f64,
) {
    if !j.rows.is_empty() {
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
        out.put(f.x);
        out.put(f.y);
        if j.kind.equations() != Some(JointKind::Revolute) {
            // Couple about the joint point of body j.
            out.put(m - cross(bj.rotate(j.s_j), f));
        }
    }
    if let Some(k) = j.clearance {
        put_contact(out, sys, ws, k, (q, v));
    }
}

/// Contact joint `k`'s channels ([`contact_quantities`]) at `(q, v)`.
fn put_contact(out: &mut Cursor, sys: &System, ws: &Workspace, k: usize, (q, v): (&[f64], &[f64])) {
    let c = &sys.clearances[k];
    let [bi, bj] = c.parts().map(|b| sys.body_state(b, q, v));
    let points = c.contacts(&bi, &bj, f64::INFINITY);
    let first = contact::slots(&sys.clearances).nth(k).expect("joint k's points").2.start;
    let states = &ws.contacts[first..first + c.points()];
    let mut forces = [(0.0, Tangential::zeros()); MAX_POINTS];
    for (p, force) in points.iter().zip(&mut forces) {
        *force = c.force(p, states[p.index].onset_for(p.penetration_rate));
    }
    let mut resultant = points
        .iter()
        .zip(&forces)
        .map(|(p, (f_n, f_t))| p.force_on_j(*f_n, f_t))
        .reduce(|a, b| a + b)
        .unwrap_or_else(Vec2::zeros);
    // A worn journal's other rims share the deepest point's slot: their forces count in
    // the slot's and the joint's.
    if let PlanarClearance::Revolute(r) = c {
        if r.worn.is_some() {
            for p in c.contacts(&bi, &bj, c.reach()).iter().skip(1) {
                let (f_n, f_t) = c.force(p, states[p.index].onset_for(p.penetration_rate));
                forces[p.index].0 += f_n;
                forces[p.index].1 += f_t;
                resultant += p.force_on_j(f_n, &f_t);
            }
        }
    }
    let forces = &forces[..points.len()];
    // The located state decides, not the sign of the penetration: right after an onset,
    // projection may leave the penetration a hair below zero.
    let mode = |p: &ContactPoint| {
        let state = &states[p.index];
        (if state.in_contact { state.mode } else { Mode::FreeFlight }) as u8 as f64
    };
    let mut put = |x: f64| out.put(x);
    match c {
        PlanarClearance::Revolute(_) | PlanarClearance::Lubricated(_) => {
            let g = c.journal_bearing().expect("a journal in its bearing");
            let film = match c {
                PlanarClearance::Lubricated(l) => Some((l, l.film_at(&bi, &bj))),
                _ => None,
            };
            // Added only where there is a film, so that a dry joint's zero keeps its sign.
            let f = film.map_or(resultant, |(_, f)| resultant + f.force);
            let e_local = rotate(-bi.phi(), g.eccentricity(&bi, &bj));
            put(f.x);
            put(f.y);
            forces.iter().for_each(|(f_n, _)| put(*f_n));
            forces.iter().for_each(|(_, f_t)| put(f_t[0]));
            points.iter().for_each(|p| put(p.penetration));
            points.iter().for_each(|p| put(p.penetration_rate));
            put(e_local.x);
            put(e_local.y);
            points.iter().for_each(|p| put(p.slip[0]));
            points.iter().for_each(|p| put(mode(p)));
            if let Some((l, f)) = film {
                put(f.eccentricity.norm() / l.film.clearance);
                put(f64::atan2(e_local.y, e_local.x));
                put(f.thickness);
                put(f.force.x);
                put(f.force.y);
                put(f.film.peak_pressure);
                put(f.mode as u8 as f64);
                put(f.film.torque_journal);
            }
        }
        PlanarClearance::Translational(t) => {
            let (tilt, offset) = t.geometry.tilt_and_offset(&bi, &bj);
            put(resultant.x);
            put(resultant.y);
            forces.iter().for_each(|(f_n, _)| put(*f_n));
            forces.iter().for_each(|(_, f_t)| put(f_t[0]));
            points.iter().for_each(|p| put(p.penetration));
            points.iter().for_each(|p| put(p.penetration_rate));
            put(tilt);
            put(offset);
            points.iter().for_each(|p| put(p.slip[0]));
            points.iter().for_each(|p| put(mode(p)));
        }
        PlanarClearance::Play(play) => {
            let (x, ..) = play.coordinate(&bi, &bj);
            let p = &points[0];
            put(x - play.centre);
            put(-p.normal.x * forces[0].0);
            put(p.penetration);
            put(p.penetration_rate);
            put(mode(p));
        }
        PlanarClearance::Gear(gear) => {
            let p = &points[0];
            let (mesh, stiffness) = gear.measure(&bi, &bj);
            let (t1, t2, f_n) = gear.torques(&bi, &bj, &states[0]);
            put(resultant.x);
            put(resultant.y);
            put(mesh);
            put(f_n);
            put(t1);
            put(t2);
            put(p.penetration);
            put(p.penetration_rate);
            put(mode(p));
            put(stiffness);
        }
    }
}

impl Kind for Planar {
    type Model = Model;

    fn wears(c: &PlanarClearance) -> Option<Wearing<'_>> {
        match c {
            PlanarClearance::Revolute(c) => Some(Wearing {
                name: &c.name,
                radii: (c.geometry.r_bearing, c.geometry.r_journal),
                clearance: c.geometry.clearance,
                worn: c.worn.as_deref(),
                contact: &c.wear_contact,
                points: 1,
                share: 1.0,
            }),
            _ => None,
        }
    }

    fn wear_integrands(
        sys: &System,
        k: usize,
        states: &[ContactState],
        q: &[f64],
        v: &[f64],
        out: &mut [Option<super::kind::Integrand>],
    ) {
        let PlanarClearance::Revolute(c) = &sys.clearances[k] else { return out.fill(None) };
        let [bearing, journal] = c.parts().map(|b| sys.body_state(b, q, v));
        out[0] = super::wear::integrand(c, &bearing, &journal, &states[0]);
    }

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
                let (acceleration, alpha) = planar_body::read_acceleration(&ws.qdd[sys.layout.slot(k).v()]);
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
