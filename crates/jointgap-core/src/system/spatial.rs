//! Spatial model -> `System<Spatial>`: checks every element (errors name it), turns each
//! body's frame into its principal frame at the centre of mass (the frame the spatial
//! body kind's diagonal mass needs), resolves points and axes into it, and lays out the
//! bodies' coordinates and the joints' scalar rows.

use std::collections::HashMap;

use super::{
    check_finite, compile_drivers, initial_conditions, own_initial, step_corners, BodyInfo, JointInfo,
    MarkerInfo, Names, Owner, Row, System, COMPILATIONS,
};
use crate::error::{Error, Named};
use crate::mechanics::contact::geometry::{BallSocket, BlockChannel, CylinderBearing, Worn};
use crate::mechanics::contact::lubricated::checked_film;
use crate::mechanics::contact::lubricated_cylinder::LubricatedCylinder;
use crate::mechanics::contact::play::check_play;
use crate::mechanics::contact::spatial::not_worn;
use crate::mechanics::contact::spatial::{SpatialClearance, SpatialGeometry, SpatialPlay};
use crate::mechanics::contact::translational::BlockData;
use crate::mechanics::contact::{line_contact, Laws};
use crate::mechanics::kind::ForceLaw;
use crate::mechanics::layout::Layout;
use crate::mechanics::resolve::Resolver;
use crate::mechanics::spatial::body::{self, BodyState, Orientation, Vec3, SPATIAL_BODY};
use crate::mechanics::spatial::forces::{point, SpatialForce};
use crate::mechanics::spatial::inertia::PrincipalInertia;
use crate::mechanics::spatial::joints::{self, JointCoordinate, JointFrame, SpatialJointKind};
use crate::mechanics::spatial::kind::Spatial;
use crate::mechanics::spatial::orientation::{self, EulerConvention};
use crate::model::spatial::{self as model, JointKind, SpatialModel};
use crate::model::FrictionSpec;

/// An orientation of the model, checked; errors name `who`'s `key`.
fn orientation_of(who: Named, key: &str, o: &model::Orientation) -> Result<Orientation, Error> {
    match o {
        model::Orientation::Quaternion(e) => orientation::from_quaternion(*e),
        model::Orientation::AxisAngle { axis, angle } => {
            orientation::from_axis_angle(&Vec3::from(*axis), *angle)
        }
        model::Orientation::Euler { convention, angles } => {
            EulerConvention::parse(convention).and_then(|c| c.orientation(*angles))
        }
    }
    .map_err(|problem| who.error(key, problem))
}

/// The ideal joint whose rows a kind adds; `None` for the clearance kinds.
fn ideal(kind: JointKind) -> Option<SpatialJointKind> {
    Some(match kind {
        JointKind::Spherical => SpatialJointKind::Spherical,
        JointKind::Revolute => SpatialJointKind::Revolute,
        JointKind::Cylindrical => SpatialJointKind::Cylindrical,
        JointKind::Prismatic => SpatialJointKind::Prismatic,
        JointKind::Universal => SpatialJointKind::Universal,
        JointKind::Fixed => SpatialJointKind::Fixed,
        JointKind::Planar => SpatialJointKind::Planar,
        JointKind::RevoluteWithPlay => SpatialJointKind::Revolute,
        JointKind::PrismaticWithPlay => SpatialJointKind::Prismatic,
        JointKind::ClearanceSpherical
        | JointKind::ClearanceCylindrical
        | JointKind::ClearanceTranslational
        | JointKind::LubricatedCylindrical => return None,
    })
}

/// Whether a joint kind needs an axis.
fn has_axis(kind: JointKind) -> bool {
    !matches!(kind, JointKind::Spherical | JointKind::Fixed | JointKind::ClearanceSpherical)
}

/// The checked bodies, each body's principal frame in its own frame (points given in
/// the body's frame turn by its inverse), and its placement state.
struct Bodies<'m> {
    info: Vec<BodyInfo<Spatial>>,
    principal: Vec<Orientation>,
    placement: Vec<BodyState>,
    index: HashMap<&'m str, usize>,
}

fn check_bodies<'m>(model: &'m SpatialModel, names: &mut Names<'m>) -> Result<Bodies<'m>, Error> {
    let mut out =
        Bodies { info: Vec::new(), principal: Vec::new(), placement: Vec::new(), index: HashMap::new() };
    for (k, b) in model.bodies.iter().enumerate() {
        names.claim("body", &b.name)?;
        let who = Named::body(&b.name);
        if !(b.mass.is_finite() && b.mass > 0.0) {
            return Err(who.error("mass", format!("mass = {} kg must be positive", b.mass)));
        }
        let inertia = match &b.inertia {
            model::Inertia::Principal { moments, frame } => {
                let frame = match frame {
                    Some(f) => orientation_of(who, "inertia", f)?,
                    None => Orientation::identity(),
                };
                PrincipalInertia::from_principal(Vec3::from(*moments), frame)
            }
            model::Inertia::Tensor(rows) => {
                PrincipalInertia::from_tensor(&body::Mat3::from_fn(|r, c| rows[r][c]))
            }
        }
        .map_err(|problem| who.error("inertia", problem))?;
        check_finite(who, "position", &b.position)?;
        check_finite(who, "velocity", &b.velocity)?;
        check_finite(who, "angular_velocity", &b.angular_velocity)?;
        let placed = match &b.orientation {
            Some(o) => orientation_of(who, "orientation", o)?,
            None => Orientation::identity(),
        };
        let orientation = placed * inertia.frame;
        let omega = orientation.inverse() * Vec3::from(b.angular_velocity);
        out.placement.push(BodyState::new(
            Vec3::from(b.position),
            orientation,
            Vec3::from(b.velocity),
            omega,
        ));
        out.index.insert(b.name.as_str(), k);
        out.principal.push(inertia.frame);
        out.info.push(BodyInfo { name: b.name.clone(), mass: b.mass, inertia });
    }
    Ok(out)
}

impl Bodies<'_> {
    /// A vector given in body `b`'s frame (the ground's: global), in the frame the
    /// engine uses for it (its principal frame).
    fn inward(&self, b: Option<usize>, x: Vec3) -> Vec3 {
        b.map_or(x, |k| self.principal[k].inverse() * x)
    }

    fn placement(&self, b: Option<usize>) -> BodyState {
        b.map_or_else(BodyState::ground, |k| self.placement[k])
    }
}

/// A joint's axis in body i's frame, when it has one; errors name the joint.
fn axis_of(who: Named, key: &str, axis: Option<[f64; 3]>) -> Result<Option<Vec3>, Error> {
    match axis {
        None => Ok(None),
        Some(a) => {
            let v = Vec3::from(a);
            if !v.iter().all(|x| x.is_finite()) || v.norm() < 1e-12 {
                return Err(who.error(key, format!("{key} {a:?} must be a finite, non-zero vector")));
            }
            Ok(Some(v.normalize()))
        }
    }
}

/// A joint kind's name as the model file spells it.
fn kind_name(kind: JointKind) -> String {
    serde_json::to_value(kind).ok().and_then(|v| v.as_str().map(str::to_owned)).unwrap_or_default()
}

/// A cylindrical clearance joint's journal in its bearing (`length` and
/// `axial_clearance` checked), the bearing on body `bi` at `s_i` along `a_i`, the journal
/// on body `bj` at `s_j` along `a_j`.
fn cylinder_bearing(
    who: Named,
    j: &model::Joint,
    laws: &Laws,
    (bi, s_i, a_i): (Option<usize>, Vec3, Vec3),
    (bj, s_j, a_j): (Option<usize>, Vec3, Vec3),
) -> Result<CylinderBearing, Error> {
    let length = match j.length {
        Some(l) if l.is_finite() && l > 0.0 => l,
        Some(l) => return Err(who.error("length", format!("length = {l} m must be positive"))),
        None => {
            return Err(
                who.error("length", "a cylindrical clearance joint needs its journal's 'length'".into())
            )
        }
    };
    let axial_clearance = match j.axial_clearance {
        Some(c) if !(c.is_finite() && c > 0.0) => {
            return Err(who.error("axial_clearance", format!("axial_clearance = {c} m must be positive")))
        }
        c => c,
    };
    Ok(CylinderBearing {
        bearing: bi,
        s_bearing: s_i,
        u_bearing: a_i,
        journal: bj,
        s_journal: s_j,
        u_journal: a_j,
        r_bearing: laws.r_bearing,
        r_journal: laws.r_journal,
        clearance: laws.r_bearing - laws.r_journal,
        length,
        axial_clearance,
        worn: None,
    })
}

/// A block in its guide channel: the channel on body `bi` through `s_i` along `axis`,
/// its height across `height` (both in body i's frame, `height` perpendicular to `axis`
/// within 1e-6 rad); the block on body `bj` centred at `s_j`, its edges along the
/// channel's directions at the placement (`pi`, `pj`).
fn block_channel(
    who: Named,
    data: &crate::model::Clearance,
    (bi, s_i, axis, height): (Option<usize>, Vec3, Vec3, Vec3),
    (bj, s_j): (Option<usize>, Vec3),
    (pi, pj): (&BodyState, &BodyState),
) -> Result<(BlockChannel, BlockData), Error> {
    if axis.dot(&height).abs() > 1e-6 {
        return Err(who.error(
            "height_axis",
            format!(
                "height_axis is not perpendicular to axis (their angle is {:.4} deg)",
                axis.angle(&height).to_degrees()
            ),
        ));
    }
    let laws = BlockData::new(who.name, data, true)?;
    let height = (height - axis * axis.dot(&height)).normalize();
    let axes_guide = [axis, height, axis.cross(&height)];
    let to_block = pj.a.tr_mul(&pi.a);
    let ((h, w), (d, dw)) = (laws.height, laws.depth.expect("a spatial block has a depth"));
    let geometry = BlockChannel {
        guide: bi,
        s_guide: s_i,
        axes_guide,
        block: bj,
        s_block: s_j,
        axes_block: axes_guide.map(|a| to_block * a),
        half_block: Vec3::new(laws.length, h, d) * 0.5,
        half_channel: [0.5 * w, 0.5 * dw],
    };
    Ok((geometry, laws))
}

/// The joints compiled: each ideal joint's rows (appended to `rows`), each clearance
/// joint's contact element, and every joint's frames on its two bodies.
#[allow(clippy::type_complexity)]
fn compile_joints<'m>(
    model: &'m SpatialModel,
    bodies: &Bodies,
    res: &Resolver<'_, 3>,
    names: &mut Names<'m>,
    rows: &mut Vec<Row<Spatial>>,
) -> Result<(Vec<JointInfo<Spatial>>, Vec<(JointFrame, JointFrame)>, Vec<SpatialClearance>), Error> {
    let (mut joints, mut frames, mut clearances) = (Vec::new(), Vec::new(), Vec::new());
    for (k, j) in model.joints.iter().enumerate() {
        names.claim("joint", &j.name)?;
        let who = Named::joint(&j.name);
        let bi = res.body(who, "body_i", &j.body_i)?;
        let bj = res.body(who, "body_j", &j.body_j)?;
        if bi == bj {
            return Err(who.error("body_j", format!("connects body '{}' to itself", j.body_i)));
        }
        let s_i = bodies.inward(bi, point(res, who, "point_i", bi, &j.point_i)?);
        let s_j = bodies.inward(bj, point(res, who, "point_j", bj, &j.point_j)?);
        let clearance_kind = ideal(j.kind).is_none();
        if j.clearance.is_some() != clearance_kind {
            return Err(who.error(
                "type",
                "contact data ('clearance') belongs to the clearance joints, and they need it".into(),
            ));
        }
        let play_kind = matches!(j.kind, JointKind::RevoluteWithPlay | JointKind::PrismaticWithPlay);
        if j.play.is_some() != play_kind {
            return Err(who.error(
                "type",
                "a 'play' table belongs to revolute_with_play and prismatic_with_play joints, and they need it"
                    .into(),
            ));
        }
        for (key, given, kind) in [
            ("height_axis", j.height_axis.is_some(), JointKind::ClearanceTranslational),
            ("lubrication", j.lubrication.is_some(), JointKind::LubricatedCylindrical),
        ] {
            if given != (j.kind == kind) {
                return Err(who
                    .error(key, format!("'{key}' belongs to {} joints, and they need it", kind_name(kind))));
            }
        }
        let (pi, pj) = (bodies.placement(bi), bodies.placement(bj));
        let given_i = axis_of(who, "axis", j.axis)?;
        let given_j = axis_of(who, "axis_j", j.axis_j)?;
        let axes = match (has_axis(j.kind), given_i) {
            (true, None) => return Err(who.error("type", "this kind of joint needs an 'axis'".into())),
            (false, Some(_)) => {
                return Err(who.error("axis", "'axis' does not apply to this kind of joint".into()));
            }
            (false, None) => None,
            (true, Some(a)) => {
                let a_i = bodies.inward(bi, a);
                // Body j's axis: given, or the same line as body i's at the placement.
                let a_j = match given_j {
                    Some(b) => bodies.inward(bj, b),
                    None if j.kind == JointKind::Universal => {
                        return Err(who
                            .error("axis_j", "a universal joint needs body j's cross axis 'axis_j'".into()));
                    }
                    None => pj.a.tr_mul(&(pi.a * a_i)),
                };
                Some((a_i, a_j))
            }
        };
        let (a_i, a_j) = axes.unwrap_or((Vec3::z(), Vec3::z()));
        let (frame_i, frame_j) = (JointFrame { point: s_i, axis: a_i }, JointFrame { point: s_j, axis: a_j });
        let first = rows.len();
        let mut clearance = None;
        match ideal(j.kind) {
            Some(kind) => {
                for (row, tag) in joints::joint_rows(kind, &frame_i, &frame_j, &pi, &pj)
                    .map_err(|problem| who.error(if axes.is_some() { "axis" } else { "type" }, problem))?
                {
                    rows.push(Row {
                        body_i: bi,
                        body_j: bj,
                        kind: row,
                        owner: Owner::Joint(k),
                        driver: None,
                        active: true,
                        label: format!("{who} ({tag})"),
                    });
                }
                if let Some(play) = &j.play {
                    let rotation = j.kind == JointKind::RevoluteWithPlay;
                    let (half_play, normal) = check_play(&j.name, play, rotation)?;
                    let coordinate = if rotation { JointCoordinate::Angle } else { JointCoordinate::Travel };
                    let (row, _) =
                        joints::coordinate_row(kind, coordinate, &frame_i, &frame_j, &pi, &pj, play.centre)
                            .map_err(|problem| who.error("axis", problem))?
                            .expect("a revolute joint's angle, a prismatic joint's travel");
                    clearances.push(SpatialClearance {
                        name: j.name.clone(),
                        geometry: SpatialGeometry::Play(SpatialPlay {
                            bodies: [bi, bj],
                            points: [s_i, s_j],
                            row,
                            half_play,
                        }),
                        normal,
                        friction: FrictionSpec::None,
                        wear_contact: Err(not_worn(who)),
                    });
                    clearance = Some(clearances.len() - 1);
                }
            }
            None => {
                let data = j.clearance.as_ref().expect("checked above");
                let mut wear_contact = Err(not_worn(who));
                let (geometry, normal, friction) = match j.kind {
                    JointKind::ClearanceTranslational => {
                        let height = axis_of(who, "height_axis", j.height_axis)?.expect("checked above");
                        let (geometry, laws) = block_channel(
                            who,
                            data,
                            (bi, s_i, a_i, bodies.inward(bi, height)),
                            (bj, s_j),
                            (&pi, &pj),
                        )?;
                        (SpatialGeometry::Block(geometry), laws.normal, laws.friction)
                    }
                    JointKind::ClearanceSpherical => {
                        let laws = Laws::new(&j.name, data)?;
                        let geometry = SpatialGeometry::BallSocket(BallSocket {
                            socket: bi,
                            s_socket: s_i,
                            ball: bj,
                            s_ball: s_j,
                            r_socket: laws.r_bearing,
                            r_ball: laws.r_journal,
                            clearance: laws.r_bearing - laws.r_journal,
                        });
                        (geometry, laws.normal, laws.friction)
                    }
                    _ => {
                        // Only the dry journal wears (docs/wear.md).
                        let laws = match &j.lubrication {
                            Some(_) => Laws::new(&j.name, data)?,
                            None => Laws::with_tables(&j.name, data)?,
                        };
                        let mut dry = cylinder_bearing(who, j, &laws, (bi, s_i, a_i), (bj, s_j, a_j))?;
                        let geometry = match &j.lubrication {
                            Some(l) => {
                                let (film, threshold) =
                                    checked_film(&j.name, l, dry.r_journal, dry.clearance)?;
                                dry.clearance -= threshold;
                                SpatialGeometry::Lubricated(LubricatedCylinder { dry, film, threshold })
                            }
                            None => {
                                wear_contact = line_contact(who, dry.length, &laws);
                                dry.worn = Worn::new(
                                    who,
                                    (data.bearing_wear.as_deref(), data.journal_wear.as_deref()),
                                    laws.r_journal,
                                )?
                                .map(Box::new);
                                SpatialGeometry::Cylinder(dry)
                            }
                        };
                        (geometry, laws.normal, laws.friction)
                    }
                };
                clearances.push(SpatialClearance {
                    name: j.name.clone(),
                    geometry,
                    normal,
                    friction,
                    wear_contact,
                });
                clearance = Some(clearances.len() - 1);
            }
        }
        if clearance_kind && (j.initial.is_some() || j.initial_rate.is_some()) {
            return Err(who.error(
                own_initial(j.initial, j.initial_rate).expect("given"),
                "'initial' and 'initial_rate' apply to revolute, prismatic and cylindrical joints only"
                    .into(),
            ));
        }
        joints.push(JointInfo {
            name: j.name.clone(),
            kind: j.kind,
            body_i: bi,
            body_j: bj,
            s_i,
            s_j,
            axis: axes.map(|(a, _)| a),
            axis_j: axes.map(|(_, a)| a),
            rows: first..rows.len(),
            clearance,
        });
        frames.push((frame_i, frame_j));
    }
    Ok((joints, frames, clearances))
}

/// The coordinate a driver or an initial condition of joint `k` holds: the angle of a
/// revolute or cylindrical joint, the travel of a prismatic one; its row and whether it
/// is a rotation.
fn coordinate_row(
    joints: &[JointInfo<Spatial>],
    frames: &[(JointFrame, JointFrame)],
    bodies: &Bodies,
    k: usize,
    initial: Option<f64>,
) -> Result<(crate::mechanics::spatial::joints::SpatialRowKind, bool), String> {
    let j = &joints[k];
    let (coordinate, rotation) = match j.kind {
        JointKind::Revolute | JointKind::Cylindrical => (JointCoordinate::Angle, true),
        JointKind::Prismatic => (JointCoordinate::Travel, false),
        _ => return Err(format!("joint '{}' has no coordinate to drive or set: only revolute, prismatic and cylindrical joints have one", j.name)),
    };
    let kind = ideal(j.kind).expect("an ideal joint");
    let (fi, fj) = &frames[k];
    let (pi, pj) = (bodies.placement(j.body_i), bodies.placement(j.body_j));
    match joints::coordinate_row(kind, coordinate, fi, fj, &pi, &pj, initial)? {
        Some((row, _)) => Ok((row, rotation)),
        None => Err(format!("joint '{}' has no such coordinate", j.name)),
    }
}

impl System<Spatial> {
    /// Checks and compiles a spatial model: bodies, joints, drivers, the joint
    /// coordinates given at t = 0, force elements and markers, in this order.
    pub fn spatial(model: &SpatialModel) -> Result<Self, Error> {
        COMPILATIONS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        if model.bodies.is_empty() {
            return Err(Error::Model(
                "the model has no bodies: a mechanism needs at least one [[body]]".into(),
            ));
        }
        if let Some(v) = model.gravity.iter().find(|v| !v.is_finite()) {
            return Err(Error::Model(format!("model: gravity = {v} is not finite")));
        }
        let mut names = Names::default();
        let bodies = check_bodies(model, &mut names)?;
        let res = Resolver::of(
            model.bodies.iter().map(|b| (b.name.as_str(), &b.points)).collect(),
            &model.ground_points,
            bodies.index.clone(),
        );
        let mut rows = Vec::new();
        let (joints, frames, clearances) = compile_joints(model, &bodies, &res, &mut names, &mut rows)?;
        let mut corners = Vec::new();
        let model_joints: Vec<_> =
            model.joints.iter().map(|j| (j.name.as_str(), own_initial(j.initial, j.initial_rate))).collect();
        let drivers = compile_drivers(
            &model.drivers,
            &model_joints,
            &mut names,
            &joints,
            &mut rows,
            &mut corners,
            |k, initial| coordinate_row(&joints, &frames, &bodies, k, initial),
        )?;
        let given: Vec<_> =
            model.joints.iter().map(|j| (j.name.as_str(), j.initial, j.initial_rate)).collect();
        let initial_conditions = initial_conditions(&given, &joints, |k, initial| {
            coordinate_row(&joints, &frames, &bodies, k, initial)
        })?;
        let mut forces = Vec::new();
        for f in &model.forces {
            names.claim("force", f.name())?;
            let element = SpatialForce::new(f, &res)?;
            corners.extend(element.corners());
            forces.push(element);
        }
        let mut markers = Vec::new();
        for m in &model.markers {
            names.claim("marker", &m.name)?;
            let who = Named::marker(&m.name);
            let body = res.body(who, "body", &m.body)?;
            let s = bodies.inward(body, point(&res, who, "point", body, &m.point)?);
            markers.push(MarkerInfo { name: m.name.clone(), body, s, frame: None });
        }
        let layout = Layout::new(bodies.info.iter().map(|_| SPATIAL_BODY));
        let (mut q_guess, mut v_guess) = (vec![0.0; layout.nq()], vec![0.0; layout.nv()]);
        for (p, slot) in bodies.placement.iter().zip(layout.slots()) {
            let (q, v) = body::placement_coordinates(&p.r, &p.orientation(), &p.v, &p.omega_global());
            q_guess[slot.q()].copy_from_slice(&q);
            v_guess[slot.v()].copy_from_slice(&v);
        }
        Ok(System {
            bodies: bodies.info,
            layout,
            joints,
            drivers,
            rows,
            forces,
            clearances,
            markers,
            gravity: Vec3::from(model.gravity),
            q_guess,
            v_guess,
            corners: step_corners(corners),
            initial_conditions,
            warnings: Vec::new(),
        })
    }
}
