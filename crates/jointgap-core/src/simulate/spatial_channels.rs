//! The spatial kind's output channels: a joint's reaction on body j as a force and a
//! moment about the joint point (global axes), a clearance joint's resultant contact
//! force and eccentricity (in the bearing body's frame) with each contact point's forces,
//! penetration, slip and mode, the joint coordinates, the drivers' efforts and the
//! markers' motion (docs/outputs.md).

use super::kind::{clearance_channels, Integrand, Kind, Wearing};
use super::record::Cursor;
use crate::dynamics::Workspace;
use crate::error::Error;
use crate::mechanics::contact::geometry::CylinderBearing;
use crate::mechanics::contact::point3::ContactPoint3;
use crate::mechanics::contact::spatial::{SpatialClearance, SpatialGeometry};
use crate::mechanics::contact::{self, ClearanceJoint, ContactState, Mode};
use crate::mechanics::drivers::Motion;
use crate::mechanics::kind::{BodyKind, RowEval};
use crate::mechanics::spatial::body::{self, BodyRow, BodyState, Vec3};
use crate::mechanics::spatial::joints::{perpendiculars, row_rate, SpatialRowKind};
use crate::mechanics::spatial::kind::Spatial;
use crate::mechanics::spatial::orientation::EulerConvention;
use crate::model::spatial::{JointKind, SpatialModel};
use crate::system::{BodyInfo, JointInfo, MarkerInfo, System};

/// An ideal joint's channels: the reaction force on body j and its moment about the
/// joint point, global axes.
const REACTION_QUANTITIES: [&str; 6] = ["fx", "fy", "fz", "mx", "my", "mz"];

/// A clearance joint's channels: the joint's own (`fx fy fz`: the resultant contact
/// force on body j; `ex ey ez`: the eccentricity of the pin's centre in the frame of
/// body i) and each contact point's (`true`), named as the planar joint's are.
const CLEARANCE_QUANTITIES: [(&str, bool); 18] = [
    ("fx", false),
    ("fy", false),
    ("fz", false),
    ("fn", true),
    ("ft", true),
    ("penetration", true),
    ("penetration_rate", true),
    ("ex", false),
    ("ey", false),
    ("ez", false),
    ("slip", true),
    ("mode", true),
    ("fnx", true),
    ("fny", true),
    ("fnz", true),
    ("ftx", true),
    ("fty", true),
    ("ftz", true),
];

/// A block in its channel's channels: the resultant contact force on the block, each
/// point's contact quantities (point `2k - 1` is corner `k` against its height wall,
/// `2k` against its depth wall), the block's travel and speed along the channel, its
/// centre's offset across the height and the depth, and its tilt (rotation vector in
/// the channel's axes).
const BLOCK_QUANTITIES: [(&str, bool); 16] = [
    ("fx", false),
    ("fy", false),
    ("fz", false),
    ("fn", true),
    ("ft", true),
    ("penetration", true),
    ("penetration_rate", true),
    ("slip", true),
    ("mode", true),
    ("travel", false),
    ("speed", false),
    ("offset_height", false),
    ("offset_depth", false),
    ("tilt_along", false),
    ("tilt_height", false),
    ("tilt_depth", false),
];

/// A lubricated joint's film channels, after the dry joint's: the film's resultant force
/// on the journal (global), and for each half (1 on the side of journal end 1, 2 on the
/// other) its eccentricity ratio, smallest thickness, force, peak pressure (the whole
/// film's at that eccentricity), mode and
/// torque on the journal about the bearing axis.
const FILM_QUANTITIES: [(&str, bool); 9] = [
    ("film_fx", false),
    ("film_fy", false),
    ("film_fz", false),
    ("eccentricity_ratio", true),
    ("film_thickness", true),
    ("film_force", true),
    ("peak_pressure", true),
    ("film_mode", true),
    ("friction_torque", true),
];

/// The film's halves.
const HALVES: usize = 2;

/// A joint's play, after its reaction: the coordinate from the middle of the play, the
/// stop's torque about (or force along) the axis on body j, its contact quantities.
const ANGLE_PLAY_QUANTITIES: [&str; 5] = ["play_angle", "torque", "penetration", "penetration_rate", "mode"];
const TRAVEL_PLAY_QUANTITIES: [&str; 5] = ["play_travel", "force", "penetration", "penetration_rate", "mode"];

/// The play channels of a joint with play.
fn play_quantities(kind: JointKind) -> &'static [&'static str] {
    match kind {
        JointKind::RevoluteWithPlay => &ANGLE_PLAY_QUANTITIES,
        _ => &TRAVEL_PLAY_QUANTITIES,
    }
}

/// A joint's play channels at one state.
fn put_play(
    out: &mut Cursor,
    sys: &System<Spatial>,
    ws: &Workspace<Spatial>,
    k: usize,
    (q, v): (&[f64], &[f64]),
) {
    let c = &sys.clearances[k];
    let SpatialGeometry::Play(g) = &c.geometry else { unreachable!("a joint with play") };
    let [bi, bj] = c.parts().map(|b| sys.body_state(b, q, v));
    let first = contact::slots(&sys.clearances).nth(k).expect("joint k's points").2.start;
    let state = &ws.contacts[first];
    let p = c.contacts(&bi, &bj, f64::INFINITY)[0];
    let (f_n, _) = c.force(&p, state.onset_for(p.penetration_rate));
    let (x, ..) = g.measure(&bi, &bj);
    let mode = if state.in_contact { state.mode } else { Mode::FreeFlight };
    for value in [x, -p.normal.x * f_n, p.penetration, p.penetration_rate, mode as u8 as f64] {
        out.put(value);
    }
}

/// A marker's channels: position, velocity, acceleration, global axes.
const MARKER_QUANTITIES: [&str; 9] = ["x", "y", "z", "vx", "vy", "vz", "ax", "ay", "az"];

/// The Euler angles' convention of the outputs.
const ZYX: EulerConvention = EulerConvention::ZYX;

const NO_MOTION: Motion = Motion { position: 0.0, speed: 0.0, acceleration: 0.0 };

/// The rows of a joint's coordinates: its angle about the axis and its travel along it.
fn coordinate_rows(j: &JointInfo<Spatial>) -> Vec<SpatialRowKind> {
    let (Some(a_i), Some(a_j)) = (j.axis, j.axis_j) else { return Vec::new() };
    let angle = SpatialRowKind::Rotation {
        axis: a_i,
        ref_i: perpendiculars(&a_i).0,
        ref_j: perpendiculars(&a_j).0,
        offset: 0.0,
    };
    let travel = SpatialRowKind::Along { a_i, s_i: j.s_i, s_j: j.s_j, offset: 0.0 };
    match j.kind {
        JointKind::Revolute | JointKind::RevoluteWithPlay => vec![angle],
        JointKind::Prismatic | JointKind::PrismaticWithPlay => vec![travel],
        JointKind::Cylindrical => vec![angle, travel],
        _ => Vec::new(),
    }
}

/// A clearance joint's channels at one state.
fn put_clearance(
    out: &mut Cursor,
    sys: &System<Spatial>,
    ws: &Workspace<Spatial>,
    k: usize,
    (q, v): (&[f64], &[f64]),
) {
    let c = &sys.clearances[k];
    let [bi, bj] = c.parts().map(|b| sys.body_state(b, q, v));
    let points = c.contacts(&bi, &bj, f64::INFINITY);
    let first = contact::slots(&sys.clearances).nth(k).expect("joint k's points").2.start;
    let states = &ws.contacts[first..first + c.points()];
    // Each point's normal force, friction force and normal force vector on body j.
    let mut forces: Vec<(f64, Vec3, Vec3)> = points
        .iter()
        .map(|p| {
            let (f_n, f_t) = c.force(p, states[p.index].onset_for(p.penetration_rate));
            (f_n, f_t, -p.normal * f_n)
        })
        .collect();
    // A worn journal end's other rims share the end's deepest point and its channels:
    // their forces count in the end's and the joint's.
    if let SpatialGeometry::Cylinder(CylinderBearing { worn: Some(_), .. }) = &c.geometry {
        let mut seen = [false; 2];
        for p in c.contacts(&bi, &bj, c.reach()).iter().filter(|p| p.index < 2) {
            if std::mem::replace(&mut seen[p.index], true) {
                let (f_n, f_t) = c.force(p, states[p.index].onset_for(p.penetration_rate));
                let end = &mut forces[p.index];
                end.0 += f_n;
                end.1 += f_t;
                end.2 -= p.normal * f_n;
            }
        }
    }
    let f = forces.iter().fold(Vec3::zeros(), |sum, (_, f_t, n)| sum + (n + f_t));
    let e = match &c.geometry {
        SpatialGeometry::BallSocket(g) => g.eccentricity(&bi, &bj),
        SpatialGeometry::Cylinder(g) => g.eccentricity(&bi, &bj),
        SpatialGeometry::Lubricated(g) => g.dry.eccentricity(&bi, &bj),
        SpatialGeometry::Block(_) | SpatialGeometry::Play(_) => Vec3::zeros(),
    };
    let e_local = bi.a.tr_mul(&e);
    let block = match &c.geometry {
        SpatialGeometry::Block(g) => Some(g),
        _ => None,
    };
    let mode = |p: &ContactPoint3| {
        let state = &states[p.index];
        if state.in_contact {
            state.mode
        } else {
            Mode::FreeFlight
        }
    };
    f.iter().for_each(|&x| out.put(x));
    forces.iter().for_each(|(f_n, _, _)| out.put(*f_n));
    forces.iter().for_each(|(_, f_t, _)| out.put(f_t.norm()));
    points.iter().for_each(|p| out.put(p.penetration));
    points.iter().for_each(|p| out.put(p.penetration_rate));
    if block.is_none() {
        e_local.iter().for_each(|&x| out.put(x));
    }
    points.iter().for_each(|p| out.put(p.slip.norm()));
    points.iter().for_each(|p| out.put(mode(p) as u8 as f64));
    if let Some(g) = block {
        let pose = g.pose(&bi, &bj);
        let [h, d] = pose.offset;
        [pose.travel, g.speed(&bi, &bj), h, d].iter().chain(pose.tilt.iter()).for_each(|&x| out.put(x));
        return;
    }
    for d in 0..3 {
        forces.iter().for_each(|(_, _, n)| out.put(n[d]));
    }
    for d in 0..3 {
        forces.iter().for_each(|(_, f_t, _)| out.put(f_t[d]));
    }
    if let SpatialGeometry::Lubricated(g) = &c.geometry {
        let halves = g.halves(&bi, &bj);
        halves.iter().fold(Vec3::zeros(), |sum, h| sum + h.force).iter().for_each(|&x| out.put(x));
        halves.iter().for_each(|h| out.put(h.eccentricity.norm() / g.film.clearance));
        halves.iter().for_each(|h| out.put(h.thickness));
        halves.iter().for_each(|h| out.put(h.force.norm()));
        halves.iter().for_each(|h| out.put(h.film.peak_pressure));
        halves.iter().for_each(|h| out.put(h.mode as u8 as f64));
        halves.iter().for_each(|h| out.put(h.torque));
    }
}

/// The contact channels of clearance joint `c`, as `(quantity, point)`.
fn contact_channels(c: &SpatialClearance) -> Vec<(&'static str, Option<usize>)> {
    match &c.geometry {
        SpatialGeometry::Block(_) => clearance_channels(&BLOCK_QUANTITIES, c.points()),
        SpatialGeometry::Lubricated(_) => {
            let mut out = clearance_channels(&CLEARANCE_QUANTITIES, c.points());
            out.extend(clearance_channels(&FILM_QUANTITIES, HALVES));
            out
        }
        _ => clearance_channels(&CLEARANCE_QUANTITIES, c.points()),
    }
}

impl Kind for Spatial {
    type Model = SpatialModel;

    fn wears(c: &SpatialClearance) -> Option<Wearing<'_>> {
        match &c.geometry {
            SpatialGeometry::Cylinder(g) => Some(Wearing {
                name: &c.name,
                radii: (g.r_bearing, g.r_journal),
                clearance: g.clearance,
                worn: g.worn.as_deref(),
                contact: &c.wear_contact,
                points: 2,
                share: CylinderBearing::END_SHARE,
            }),
            _ => None,
        }
    }

    fn wear_integrands(
        sys: &System<Spatial>,
        k: usize,
        states: &[ContactState],
        q: &[f64],
        v: &[f64],
        out: &mut [Option<Integrand>],
    ) {
        let c = &sys.clearances[k];
        let SpatialGeometry::Cylinder(g) = &c.geometry else { return out.fill(None) };
        let [bearing, journal] = c.parts().map(|b| sys.body_state(b, q, v));
        super::wear::cylinder_integrands(c, g, (&bearing, &journal), states, out);
    }

    fn compile(model: &SpatialModel) -> Result<System<Spatial>, Error> {
        System::spatial(model)
    }

    fn magnitude_warnings(_model: &SpatialModel, _sys: &System<Spatial>) -> Vec<String> {
        Vec::new()
    }

    fn joint_force_channels(
        sys: &System<Spatial>,
        j: &JointInfo<Spatial>,
    ) -> Vec<(&'static str, Option<usize>)> {
        match j.clearance {
            Some(_) if !j.rows.is_empty() => {
                REACTION_QUANTITIES.iter().chain(play_quantities(j.kind)).map(|&q| (q, None)).collect()
            }
            Some(k) => contact_channels(&sys.clearances[k]),
            None => REACTION_QUANTITIES.iter().map(|&q| (q, None)).collect(),
        }
    }

    fn joint_force_channel_count(sys: &System<Spatial>, j: &JointInfo<Spatial>) -> usize {
        match j.clearance {
            Some(_) if !j.rows.is_empty() => REACTION_QUANTITIES.len() + play_quantities(j.kind).len(),
            Some(k) => contact_channels(&sys.clearances[k]).len(),
            None => REACTION_QUANTITIES.len(),
        }
    }

    fn put_joint_forces(
        out: &mut Cursor,
        sys: &System<Spatial>,
        ws: &Workspace<Spatial>,
        j: &JointInfo<Spatial>,
        (bi, bj): (&BodyState, &BodyState),
        state: (&[f64], &[f64]),
        lambda_of: &dyn Fn(usize) -> f64,
    ) {
        match j.clearance {
            Some(k) if j.rows.is_empty() => {
                put_clearance(out, sys, ws, k, state);
                return;
            }
            _ => {}
        }
        // The generalized reaction on body j, -Cq_j^T lambda: a force (global) and a
        // moment about the centre of mass (body frame).
        let mut g = [0.0; 6];
        for r in j.rows.clone() {
            let ev = Spatial::eval(&sys.rows[r].kind, bi, bj, NO_MOTION);
            let l = lambda_of(r);
            g.iter_mut().zip(&ev.jac_j).for_each(|(g, e)| *g -= e * l);
        }
        let f = Vec3::new(g[0], g[1], g[2]);
        let m = bj.rotate(&Vec3::new(g[3], g[4], g[5])) - bj.rotate(&j.s_j).cross(&f);
        f.iter().chain(m.iter()).for_each(|&x| out.put(x));
        if let Some(k) = j.clearance {
            put_play(out, sys, ws, k, state);
        }
    }

    fn coordinate_quantities(kind: JointKind) -> &'static [&'static str] {
        match kind {
            JointKind::Revolute | JointKind::RevoluteWithPlay => &["angle", "omega"],
            JointKind::Prismatic | JointKind::PrismaticWithPlay => &["travel", "speed"],
            JointKind::Cylindrical => &["angle", "omega", "travel", "speed"],
            _ => &[],
        }
    }

    fn put_joint_coordinates(out: &mut Cursor, j: &JointInfo<Spatial>, bi: &BodyState, bj: &BodyState) {
        for row in coordinate_rows(j) {
            let ev = row.eval(bi, bj, NO_MOTION);
            out.put(ev.c);
            out.put(row_rate(&ev, bi, bj));
        }
    }

    /// The effort along the driven coordinate: the row's Jacobian over the driven body
    /// is the unit axis (its rotation part for an angle), so the effort is the
    /// multiplier's negative on body j and the multiplier itself on body i.
    fn driver_effort(_ev: &RowEval<BodyRow>, _rotation: bool, on_j: bool, l: f64) -> f64 {
        if on_j {
            -l
        } else {
            l
        }
    }

    /// The Euler angles of the body frame the model gave (ZYX: yaw about z, pitch about
    /// the turned y, roll about the twice-turned x), and the angular velocity and
    /// acceleration in global axes.
    const BODY_EXTRA: &'static [&'static str] =
        &["yaw", "pitch", "roll", "wgx", "wgy", "wgz", "alphagx", "alphagy", "alphagz"];

    fn put_body_extra(out: &mut Cursor, b: &BodyInfo<Spatial>, q: &[f64], v: &[f64], a: &[f64]) {
        let state = BodyState::read(q, v);
        let given = state.orientation() * b.inertia.frame.inverse();
        let [yaw, pitch, roll] = ZYX.angles(&given);
        let (_, _, alpha) = body::read_acceleration(a, &state);
        [yaw, pitch, roll]
            .iter()
            .chain(state.omega_global().iter())
            .chain(alpha.iter())
            .for_each(|&x| out.put(x));
    }

    const MARKER_QUANTITIES: &'static [&'static str] = &MARKER_QUANTITIES;

    fn put_marker(
        out: &mut Cursor,
        sys: &System<Spatial>,
        ws: &Workspace<Spatial>,
        m: &MarkerInfo<Spatial>,
        q: &[f64],
        v: &[f64],
    ) {
        let b = sys.body_state(m.body, q, v);
        let (a_cm, alpha) = match m.body {
            None => (Vec3::zeros(), Vec3::zeros()),
            Some(k) => {
                let (a, alpha, _) = body::read_acceleration(&ws.qdd[sys.layout.slot(k).v()], &b);
                (a, alpha)
            }
        };
        let w = b.omega;
        let p = b.r + b.rotate(&m.s);
        let pv = b.point_velocity(&m.s);
        let pa = a_cm + b.rotate(&(alpha.cross(&m.s) + w.cross(&w.cross(&m.s))));
        p.iter().chain(pv.iter()).chain(pa.iter()).for_each(|&x| out.put(x));
    }
}
