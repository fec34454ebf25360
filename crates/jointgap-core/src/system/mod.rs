//! Model -> System: checks every element (errors name it), resolves points, and lays
//! out coordinates (each moving body's where its kind says: [`Layout`]) and scalar
//! constraint rows.

pub(crate) mod magnitudes;
pub mod resolved;
mod spatial;

use std::collections::HashMap;

use crate::error::{ElementError, Error, Named};
use crate::math::Vec2;
use crate::mechanics::contact::gear::GearPair;
use crate::mechanics::contact::lubricated::LubricatedRevolute;
use crate::mechanics::contact::planar_clearance::PlanarClearance;
use crate::mechanics::contact::play::{JointPlay, PlayCoordinate};
use crate::mechanics::contact::translational::ClearanceTranslational;
use crate::mechanics::contact::{ClearanceJoint, ClearanceRevolute};
use crate::mechanics::drivers::MotionProfile;
use crate::mechanics::forces::ForceElement;
use crate::mechanics::kind::{BodyKind, ForceLaw};
use crate::mechanics::layout::Layout;
use crate::mechanics::planar::{Planar, RowKind};
use crate::mechanics::planar_body::{self, BodyState, PLANAR_BODY};
use crate::mechanics::resolve::Resolver;
use crate::model::{JointKind, Model, GROUND};

/// A moving body's inertia; its coordinates sit where [`System::layout`] says.
#[derive(Debug, Clone)]
pub struct BodyInfo<K: BodyKind = Planar> {
    /// Name.
    pub name: String,
    /// Mass [kg].
    pub mass: f64,
    /// Centroidal moment of inertia [kg m^2]. For a point mass (inertia 0 in the model)
    /// whose joints hold its rotation fixed, a stand-in (see [`point_mass_inertia`]): its
    /// angular acceleration is then zero, so the motion and the reactions do not depend
    /// on it, and the mass matrix stays invertible. A spatial body's: its principal
    /// moments, its frame the principal frame.
    pub inertia: K::Inertia,
}

/// A joint coordinate given at t = 0 (a joint's `initial` and `initial_rate`): a row that
/// assembly alone solves, with the joints and drivers, and that the run then drops.
#[derive(Debug, Clone)]
pub struct InitialCondition<K: BodyKind = Planar> {
    /// The joint's index.
    pub joint: usize,
    /// Body i of the joint (`None`: ground).
    pub body_i: Option<usize>,
    /// Body j of the joint.
    pub body_j: Option<usize>,
    /// The joint coordinate as a row: `Angle` (revolute) or `Along` the axis (prismatic),
    /// its offset the given coordinate.
    pub kind: K::RowKind,
    /// True when the coordinate is given (else only its rate).
    pub placed: bool,
    /// The given rate [rad/s or m/s].
    pub rate: Option<f64>,
    /// For messages, e.g. `joint 'ground_crank' (initial angle)`.
    pub label: String,
}

/// Which element a constraint row belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Owner {
    /// Joint index.
    Joint(usize),
    /// Driver index.
    Driver(usize),
}

/// One scalar constraint equation.
#[derive(Debug, Clone)]
pub struct Row<K: BodyKind = Planar> {
    /// Body i (`None`: ground).
    pub body_i: Option<usize>,
    /// Body j (`None`: ground).
    pub body_j: Option<usize>,
    /// The equation.
    pub kind: K::RowKind,
    /// Owning joint or driver.
    pub owner: Owner,
    /// Driver whose motion enters this row.
    pub driver: Option<usize>,
    /// False when assembly found the row redundant (dependent on earlier rows).
    pub active: bool,
    /// For messages, e.g. `joint 'crank_rod' (x)`.
    pub label: String,
}

/// A checked marker: a point whose motion the run reports (`measures::marker_motion`).
#[derive(Debug, Clone)]
pub struct MarkerInfo<K: BodyKind = Planar> {
    /// Name.
    pub name: String,
    /// Body carrying the point (`None`: ground).
    pub body: Option<usize>,
    /// The point in the body's frame [m].
    pub s: K::Vector,
    /// Body whose frame the motion is measured in (`None`: ground).
    pub frame: Option<usize>,
}

impl MarkerInfo {
    /// Checks a marker; errors name it.
    fn new(m: &crate::model::Marker, res: &Resolver) -> Result<Self, Error> {
        let who = Named::marker(&m.name);
        let body = res.body(who, "body", &m.body)?;
        let frame = match &m.frame {
            Some(name) => res.body(who, "frame", name)?,
            None => None,
        };
        Ok(MarkerInfo { name: m.name.clone(), body, s: res.point(who, "point", body, &m.point)?, frame })
    }
}

/// A joint after checking.
#[derive(Debug, Clone)]
pub struct JointInfo<K: BodyKind = Planar> {
    /// Name.
    pub name: String,
    /// Kind.
    pub kind: K::JointKind,
    /// Body j, on which reactions are reported (`None`: ground).
    pub body_j: Option<usize>,
    /// Body i.
    pub body_i: Option<usize>,
    /// Joint point on body j, body frame [m].
    pub s_j: K::Vector,
    /// Joint point on body i, body frame [m].
    pub s_i: K::Vector,
    /// Sliding direction of a prismatic joint (a spatial joint's axis), unit vector in
    /// the frame of body i.
    pub axis: Option<K::Vector>,
    /// A spatial joint's axis in the frame of body j (planar joints: none).
    pub axis_j: Option<K::Vector>,
    /// Its rows in `System::rows` (none for a clearance joint).
    pub rows: std::ops::Range<usize>,
    /// Index in `System::clearances` of a clearance joint.
    pub clearance: Option<usize>,
}

/// A driver after checking.
#[derive(Debug, Clone)]
pub struct DriverInfo {
    /// Name.
    pub name: String,
    /// Driven joint index.
    pub joint: usize,
    /// True for a rotation (revolute), false for a translation (prismatic).
    pub rotation: bool,
    /// Motion profile.
    pub profile: MotionProfile,
    /// Its row in `System::rows`.
    pub row: usize,
}

/// The compiled, immutable mechanism: everything the solver needs, nothing it changes.
#[derive(Debug, Clone)]
pub struct System<K: BodyKind = Planar> {
    /// Moving bodies, in model order.
    pub bodies: Vec<BodyInfo<K>>,
    /// Where each body's coordinates sit in `q` and `v`.
    pub layout: Layout,
    /// Joints in model order.
    pub joints: Vec<JointInfo<K>>,
    /// Drivers in model order.
    pub drivers: Vec<DriverInfo>,
    /// Constraint rows: joints in model order, then drivers.
    pub rows: Vec<Row<K>>,
    /// Force elements in model order.
    pub forces: Vec<K::Force>,
    /// Clearance joints, in model order.
    pub clearances: Vec<K::Clearance>,
    /// Markers, in model order.
    pub markers: Vec<MarkerInfo<K>>,
    /// Gravity [m/s^2].
    pub gravity: K::Vector,
    /// Approximate initial coordinates (user placement).
    pub q_guess: Vec<f64>,
    /// Approximate initial velocities.
    pub v_guess: Vec<f64>,
    /// Times where a prescribed input has a corner; steps stop there.
    pub corners: Vec<f64>,
    /// Joint coordinates and rates given at t = 0, for assembly.
    pub initial_conditions: Vec<InitialCondition<K>>,
    /// Notes for the user, filled by `simulate::prepare`: implausible magnitudes
    /// (`magnitudes`), redundant constraints removed by assembly, ...
    pub warnings: Vec<String>,
}

/// Global position, angle and velocity of a body at its user placement.
fn placement(model: &Model, body: Option<usize>) -> BodyState {
    match body {
        None => BodyState::default(),
        Some(k) => {
            let b = &model.bodies[k];
            BodyState::new(
                Vec2::new(b.position[0], b.position[1]),
                b.angle,
                Vec2::new(b.velocity[0], b.velocity[1]),
                b.omega,
            )
        }
    }
}

pub(crate) fn check_finite(who: Named, what: &str, values: &[f64]) -> Result<(), Error> {
    match values.iter().find(|v| !v.is_finite()) {
        Some(v) => Err(who.error(what, format!("{what} = {v} is not finite"))),
        None => Ok(()),
    }
}

/// The row of joint `k`'s coordinate (relative angle of a revolute joint, travel of a
/// prismatic one along its axis) with its value at t = 0: `initial`, else the value at the
/// placement; and whether it is a rotation. `None` for fixed and clearance joints.
fn coordinate_row(
    model: &Model,
    joints: &[JointInfo],
    k: usize,
    initial: Option<f64>,
) -> Option<(RowKind, bool)> {
    let joint = &joints[k];
    let (pi, pj) = (placement(model, joint.body_i), placement(model, joint.body_j));
    match joint.kind.equations()? {
        JointKind::Revolute => {
            Some((RowKind::Angle { offset: initial.unwrap_or(pj.phi() - pi.phi()) }, true))
        }
        JointKind::Prismatic => {
            let axis = model.joints[k].axis.expect("checked with the joint");
            let u = Vec2::new(axis[0], axis[1]).normalize();
            let here = pj.r + pj.rotate(joint.s_j) - pi.r - pi.rotate(joint.s_i);
            let placed = pi.rotate(u).dot(&here);
            Some((
                RowKind::Along { s_i: joint.s_i, w: u, s_j: joint.s_j, offset: initial.unwrap_or(placed) },
                false,
            ))
        }
        _ => None,
    }
}

/// Gives each point mass (a body of zero inertia) a stand-in inertia where its joints
/// fix its rotation, or an error naming the free rotation.
///
/// A body's rotation is fixed when the angle rows of prismatic and fixed joints tie it to
/// the ground, directly or through bodies so tied. Its angular acceleration is then zero
/// at all times, so its inertia multiplies zero in every equation: any value gives the
/// same motion and reactions, and a positive one keeps `M` invertible for the Schur
/// complement. The stand-in is the body's mass times the square of the largest distance
/// of a joint point from its centre of mass in the model (1 m when all sit at centres of
/// mass), which keeps the Schur complement's rows of one scale. A rotation held by a
/// driver is not fixed in this sense: the motor's torque would carry the stand-in.
fn point_mass_inertia(
    model: &Model,
    rows: &[Row],
    joints: &[JointInfo],
    bodies: &mut [BodyInfo],
) -> Result<(), Error> {
    if bodies.iter().all(|b| b.inertia > 0.0) {
        return Ok(());
    }
    let mut fixed = vec![false; bodies.len()];
    let held = |b: Option<usize>, fixed: &[bool]| b.is_none_or(|k| fixed[k]);
    loop {
        let mut grew = false;
        for row in rows.iter().filter(|r| matches!(r.kind, RowKind::Angle { .. }) && r.driver.is_none()) {
            for (a, b) in [(row.body_i, row.body_j), (row.body_j, row.body_i)] {
                if let Some(k) = b {
                    if !fixed[k] && held(a, &fixed) {
                        fixed[k] = true;
                        grew = true;
                    }
                }
            }
        }
        if !grew {
            break;
        }
    }
    let reach = joints
        .iter()
        .flat_map(|j| [j.s_i.norm(), j.s_j.norm()])
        .chain(model.bodies.iter().flat_map(|b| b.points.values().map(|p| p[0].hypot(p[1]))))
        .fold(0.0, f64::max);
    let length = if reach > 0.0 { reach } else { 1.0 };
    for (k, b) in bodies.iter_mut().enumerate() {
        if b.inertia > 0.0 {
            continue;
        }
        if !fixed[k] {
            let mine: Vec<String> = joints
                .iter()
                .filter(|j| j.body_i == Some(k) || j.body_j == Some(k))
                .map(|j| {
                    let kind = j.kind.type_name();
                    format!("'{}' {kind}", j.name)
                })
                .collect();
            return Err(Named::body(&b.name).error(
                "inertia",
                format!(
                    "inertia = 0 (a point mass) needs its rotation fixed by its joints, but its \
                     rotation is free: no prismatic or fixed joint ties it to the ground or to a body \
                     that cannot turn (its joints: {}); give its moment of inertia",
                    if mine.is_empty() { "none".to_string() } else { mine.join(", ") }
                ),
            ));
        }
        b.inertia = b.mass * length * length;
    }
    Ok(())
}

/// The names of the model's elements seen so far: every body, joint, driver, force and
/// marker needs a name of its own, since outputs and messages address elements by name.
#[derive(Default)]
pub(crate) struct Names<'m> {
    /// Name -> kind of the element that took it.
    seen: HashMap<&'m str, &'static str>,
}

impl<'m> Names<'m> {
    /// Takes `name` for an element of `kind`, or an error naming it when it is empty,
    /// reserved, or taken.
    pub(crate) fn claim(&mut self, kind: &'static str, name: &'m str) -> Result<(), Error> {
        if name.is_empty() {
            return Err(Error::Model(format!("a {kind} has an empty name")));
        }
        if name == GROUND || name == "system" {
            return Err(ElementError::model(
                kind,
                name,
                Some("name"),
                format!("the name '{name}' is reserved"),
            ));
        }
        if let Some(other) = self.seen.insert(name, kind) {
            return Err(ElementError::model(
                kind,
                name,
                Some("name"),
                format!("the name is already used by a {other}"),
            ));
        }
        Ok(())
    }
}

/// Checks each body's mass, inertia and placement; returns the bodies and their index
/// by name.
fn check_bodies<'m>(
    model: &'m Model,
    names: &mut Names<'m>,
) -> Result<(Vec<BodyInfo>, HashMap<&'m str, usize>), Error> {
    let mut bodies = Vec::new();
    let mut index = HashMap::new();
    for (k, b) in model.bodies.iter().enumerate() {
        names.claim("body", &b.name)?;
        let who = Named::body(&b.name);
        if !(b.mass.is_finite() && b.mass > 0.0) {
            return Err(who.error("mass", format!("mass = {} kg must be positive", b.mass)));
        }
        if !(b.inertia.is_finite() && b.inertia >= 0.0) {
            return Err(who.error("inertia", format!("inertia = {} kg m^2 must not be negative", b.inertia)));
        }
        check_finite(who, "position", &b.position)?;
        check_finite(who, "angle", &[b.angle])?;
        check_finite(who, "velocity", &b.velocity)?;
        check_finite(who, "omega", &[b.omega])?;
        index.insert(b.name.as_str(), k);
        bodies.push(BodyInfo { name: b.name.clone(), mass: b.mass, inertia: b.inertia });
    }
    Ok((bodies, index))
}

/// The joints compiled: each ideal joint's constraint rows (appended to `rows`), each
/// clearance joint's contact element, and every joint's points and axis.
fn compile_joints<'m>(
    model: &'m Model,
    res: &Resolver,
    names: &mut Names<'m>,
    rows: &mut Vec<Row>,
    warnings: &mut Vec<String>,
) -> Result<(Vec<JointInfo>, Vec<PlanarClearance>), Error> {
    let mut joints = Vec::new();
    let mut clearances = Vec::new();
    for (k, j) in model.joints.iter().enumerate() {
        names.claim("joint", &j.name)?;
        let who = Named::joint(&j.name);
        let bi = res.body(who, "body_i", &j.body_i)?;
        let bj = res.body(who, "body_j", &j.body_j)?;
        if bi == bj {
            // `body_j`, where the body named twice is named the second time.
            return Err(who.error("body_j", format!("connects body '{}' to itself", j.body_i)));
        }
        let s_i = res.point(who, "point_i", bi, &j.point_i)?;
        let s_j = res.point(who, "point_j", bj, &j.point_j)?;
        let (pi, pj) = (placement(model, bi), placement(model, bj));
        let rel_angle = pj.phi() - pi.phi();
        let first = rows.len();
        let mut push = |kind: RowKind, tag: &str| {
            rows.push(Row {
                body_i: bi,
                body_j: bj,
                kind,
                owner: Owner::Joint(k),
                driver: None,
                active: true,
                label: format!("{who} ({tag})"),
            })
        };
        let kind = j.kind;
        let sliding = match (kind.has_axis(), j.axis) {
            (true, Some(axis)) => {
                let u = Vec2::new(axis[0], axis[1]);
                if !(u.x.is_finite() && u.y.is_finite()) || u.norm() < 1e-12 {
                    return Err(who.error("axis", format!("axis {axis:?} must be a non-zero vector")));
                }
                Some(u.normalize())
            }
            (true, None) => {
                return Err(who.error("type", format!("a {} joint needs an 'axis'", kind.type_name())));
            }
            (false, Some(_)) => {
                return Err(who.error(
                    "axis",
                    "'axis' applies to prismatic, prismatic_with_play and clearance_translational joints only"
                        .into(),
                ));
            }
            (false, None) => None,
        };
        let needed = |table: &str, given: bool| -> Result<(), Error> {
            match given {
                true => Ok(()),
                false => {
                    Err(who.error("type", format!("a {} joint needs its '{table}' table", kind.type_name())))
                }
            }
        };
        let uses = |table: &str| match table {
            "clearance" => matches!(
                kind,
                JointKind::ClearanceRevolute
                    | JointKind::LubricatedRevolute
                    | JointKind::ClearanceTranslational
            ),
            "lubrication" => kind == JointKind::LubricatedRevolute,
            "play" => matches!(kind, JointKind::RevoluteWithPlay | JointKind::PrismaticWithPlay),
            _ => kind == JointKind::GearPair,
        };
        for (table, given) in [
            ("clearance", j.clearance.is_some()),
            ("lubrication", j.lubrication.is_some()),
            ("play", j.play.is_some()),
            ("gear", j.gear.is_some()),
        ] {
            if uses(table) {
                needed(table, given)?;
            } else if given {
                warnings.push(format!(
                    "{who}: a {} joint does not use its '{table}' table (kept for switching its type)",
                    kind.type_name()
                ));
            }
        }
        match kind.equations() {
            Some(JointKind::Revolute) => {
                push(RowKind::Coincide { axis: 0, s_i, s_j }, "x");
                push(RowKind::Coincide { axis: 1, s_i, s_j }, "y");
            }
            Some(JointKind::Fixed) => {
                push(RowKind::Coincide { axis: 0, s_i, s_j }, "x");
                push(RowKind::Coincide { axis: 1, s_i, s_j }, "y");
                push(RowKind::Angle { offset: rel_angle }, "angle");
            }
            Some(_) => {
                let u = sliding.expect("checked with the axis");
                push(RowKind::Angle { offset: rel_angle }, "angle");
                push(RowKind::Along { s_i, w: crate::math::perp(u), s_j, offset: 0.0 }, "normal");
            }
            None => {}
        }
        let contact = match kind {
            JointKind::ClearanceRevolute => Some(PlanarClearance::Revolute(ClearanceRevolute::new(
                j,
                j.clearance.as_ref().expect("checked above"),
                bi,
                bj,
                res,
            )?)),
            JointKind::LubricatedRevolute => Some(PlanarClearance::Lubricated(LubricatedRevolute::new(
                j,
                j.clearance.as_ref().expect("checked above"),
                j.lubrication.as_ref().expect("checked above"),
                bi,
                bj,
                res,
            )?)),
            JointKind::ClearanceTranslational => {
                Some(PlanarClearance::Translational(ClearanceTranslational::new(
                    j,
                    j.clearance.as_ref().expect("checked above"),
                    (bi, s_i, sliding.expect("checked with the axis")),
                    (bj, s_j),
                    rel_angle,
                )?))
            }
            JointKind::RevoluteWithPlay | JointKind::PrismaticWithPlay => {
                let (coordinate, placed) = match sliding {
                    None => (PlayCoordinate::Angle, rel_angle),
                    Some(axis) => {
                        let here = pj.r + pj.rotate(s_j) - pi.r - pi.rotate(s_i);
                        (PlayCoordinate::Travel { s_i, s_j, axis }, pi.rotate(axis).dot(&here))
                    }
                };
                let play = j.play.as_ref().expect("checked above");
                Some(PlanarClearance::Play(JointPlay::new(j, play, [bi, bj], coordinate, placed)?))
            }
            JointKind::GearPair => Some(PlanarClearance::Gear(GearPair::new(
                j,
                j.gear.as_ref().expect("checked above"),
                (bi, s_i),
                (bj, s_j),
                (&pi, &pj),
            )?)),
            JointKind::Revolute | JointKind::Prismatic | JointKind::Fixed => None,
        };
        let clearance = contact.map(|c| {
            clearances.push(c);
            clearances.len() - 1
        });
        joints.push(JointInfo {
            name: j.name.clone(),
            kind: j.kind,
            body_i: bi,
            body_j: bj,
            s_i,
            s_j,
            axis: sliding,
            axis_j: None,
            rows: first..rows.len(),
            clearance,
        });
    }
    Ok((joints, clearances))
}

/// The drivers compiled: each one's motion row on its joint's coordinate (appended to
/// `rows`) and profile, whose corners go to `corners`. `model_joints` gives each model
/// joint's name and whether it has an `initial` (or else an `initial_rate`) of its own;
/// `coordinate_row(k, initial)` the row of joint `k`'s coordinate and whether it is a
/// rotation, or why the joint cannot be driven.
pub(crate) fn compile_drivers<'m, K: BodyKind>(
    model_drivers: &'m [crate::model::Driver],
    model_joints: &[(&str, Option<&'static str>)],
    names: &mut Names<'m>,
    joints: &[JointInfo<K>],
    rows: &mut Vec<Row<K>>,
    corners: &mut Vec<f64>,
    coordinate_row: impl Fn(usize, Option<f64>) -> Result<(K::RowKind, bool), String>,
) -> Result<Vec<DriverInfo>, Error> {
    let mut drivers = Vec::new();
    for (k, d) in model_drivers.iter().enumerate() {
        names.claim("driver", &d.name)?;
        let who = Named::driver(&d.name);
        let jk = model_joints.iter().position(|(name, _)| *name == d.joint).ok_or_else(|| {
            let names: Vec<&str> = model_joints.iter().map(|(name, _)| *name).collect();
            who.error(
                "joint",
                format!("joint '{}' is not a joint of the model (joints: {})", d.joint, names.join(", ")),
            )
        })?;
        if let Some(other) = drivers.iter().find(|o: &&DriverInfo| o.joint == jk) {
            return Err(who.error(
                "joint",
                format!("joint '{}' is already driven by driver '{}'", d.joint, other.name),
            ));
        }
        let joint = &joints[jk];
        let profile = MotionProfile::new(&d.profile, &d.name)?;
        if let Some(v) = d.initial {
            check_finite(who, "initial", &[v])?;
        }
        if let Some(key) = model_joints[jk].1 {
            return Err(Named::joint(&d.joint).error(
                key,
                format!(
                    "initial and initial_rate cannot be given for a driven joint \
                     (driver '{}' sets its motion): give its coordinate at t = 0 as the \
                     driver's initial",
                    d.name
                ),
            ));
        }
        let (kind, rotation) = coordinate_row(jk, d.initial).map_err(|why| who.error("joint", why))?;
        corners.extend(profile.corners());
        rows.push(Row {
            body_i: joint.body_i,
            body_j: joint.body_j,
            kind,
            owner: Owner::Driver(k),
            driver: Some(k),
            active: true,
            label: format!("{who} (motion)"),
        });
        drivers.push(DriverInfo { name: d.name.clone(), joint: jk, rotation, profile, row: rows.len() - 1 });
    }
    Ok(drivers)
}

/// The key of a joint's own coordinate at t = 0, when it gives one: `initial`, else
/// `initial_rate`.
pub(crate) fn own_initial(initial: Option<f64>, rate: Option<f64>) -> Option<&'static str> {
    if initial.is_some() {
        Some("initial")
    } else {
        rate.map(|_| "initial_rate")
    }
}

/// The joint coordinates and rates given at t = 0 (`initial`, `initial_rate`), as rows
/// for assembly: `model_joints` gives each model joint's name, `initial` and
/// `initial_rate`; `coordinate_row(k, initial)` the row of joint `k`'s coordinate and
/// whether it is a rotation, or why the joint has none.
pub(crate) fn initial_conditions<K: BodyKind>(
    model_joints: &[(&str, Option<f64>, Option<f64>)],
    joints: &[JointInfo<K>],
    coordinate_row: impl Fn(usize, Option<f64>) -> Result<(K::RowKind, bool), String>,
) -> Result<Vec<InitialCondition<K>>, Error> {
    let mut initial_conditions = Vec::new();
    for (k, &(name, initial, initial_rate)) in model_joints.iter().enumerate() {
        let Some(key) = own_initial(initial, initial_rate) else { continue };
        let who = Named::joint(name);
        check_finite(who, "initial", &initial.into_iter().collect::<Vec<_>>())?;
        check_finite(who, "initial_rate", &initial_rate.into_iter().collect::<Vec<_>>())?;
        let (kind, rotation) = coordinate_row(k, initial).map_err(|why| who.error(key, why))?;
        let what = match (initial.is_some(), rotation) {
            (true, true) => "initial angle",
            (true, false) => "initial travel",
            (false, _) => "initial rate",
        };
        initial_conditions.push(InitialCondition {
            joint: k,
            body_i: joints[k].body_i,
            body_j: joints[k].body_j,
            kind,
            placed: initial.is_some(),
            rate: initial_rate,
            label: format!("{who} ({what})"),
        });
    }
    Ok(initial_conditions)
}

/// The force elements compiled, their profiles' corners added to `corners`.
fn compile_forces<'m>(
    model: &'m Model,
    res: &Resolver,
    names: &mut Names<'m>,
    corners: &mut Vec<f64>,
) -> Result<Vec<ForceElement>, Error> {
    let mut forces = Vec::new();
    for f in &model.forces {
        names.claim("force", f.name())?;
        let element = ForceElement::new(f, res)?;
        corners.extend(element.corners());
        forces.push(element);
    }
    Ok(forces)
}

/// The markers checked.
fn compile_markers<'m>(
    model: &'m Model,
    res: &Resolver,
    names: &mut Names<'m>,
) -> Result<Vec<MarkerInfo>, Error> {
    let mut markers = Vec::new();
    for m in &model.markers {
        names.claim("marker", &m.name)?;
        markers.push(MarkerInfo::new(m, res)?);
    }
    Ok(markers)
}

/// The times inside the run where an input has a corner, in order, each once: the
/// steps stop there.
pub(crate) fn step_corners(mut corners: Vec<f64>) -> Vec<f64> {
    corners.retain(|t| *t > 0.0);
    corners.sort_by(|a, b| a.partial_cmp(b).unwrap());
    corners.dedup();
    corners
}

/// The bodies' coordinates and velocities at their user placement, laid out by
/// `layout`: the starting guess of assembly.
fn placement_guess(model: &Model, layout: &Layout) -> (Vec<f64>, Vec<f64>) {
    let (mut q_guess, mut v_guess) = (vec![0.0; layout.nq()], vec![0.0; layout.nv()]);
    for (b, slot) in model.bodies.iter().zip(layout.slots()) {
        let (q, v) = planar_body::placement_coordinates(b);
        q_guess[slot.q()].copy_from_slice(&q);
        v_guess[slot.v()].copy_from_slice(&v);
    }
    (q_guess, v_guess)
}

/// Models this process has compiled ([`System::new`]), for [`compilations`].
pub(crate) static COMPILATIONS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

/// How many models this process has compiled: a front end's test reads it to see that
/// loading a model and running it, alone or in a batch, compiles the model once.
pub fn compilations() -> usize {
    COMPILATIONS.load(std::sync::atomic::Ordering::Relaxed)
}

impl System<Planar> {
    /// Checks and compiles a model: bodies, joints, drivers, the joint coordinates
    /// given at t = 0, force elements and markers, in this order (so that an error
    /// names the first offending element in the model's order), then the point
    /// masses' stand-in inertia.
    pub fn new(model: &Model) -> Result<System, Error> {
        COMPILATIONS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        if model.bodies.is_empty() {
            return Err(Error::Model(
                "the model has no bodies: a mechanism needs at least one [[body]] (is the file empty?)"
                    .into(),
            ));
        }
        if let Some(v) = model.gravity.iter().find(|v| !v.is_finite()) {
            return Err(Error::Model(format!("model: gravity = {v} is not finite")));
        }
        let mut names = Names::default();
        let (mut bodies, index) = check_bodies(model, &mut names)?;
        let res = Resolver::new(model, index);
        let mut rows = Vec::new();
        let mut warnings = Vec::new();
        let (joints, clearances) = compile_joints(model, &res, &mut names, &mut rows, &mut warnings)?;
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
            |jk, initial| {
                coordinate_row(model, &joints, jk, initial).ok_or_else(|| {
                    format!(
                        "joint '{}' is a {} joint; only revolute and prismatic joints can be driven",
                        joints[jk].name,
                        joints[jk].kind.type_name()
                    )
                })
            },
        )?;
        let given: Vec<_> =
            model.joints.iter().map(|j| (j.name.as_str(), j.initial, j.initial_rate)).collect();
        let initial_conditions = initial_conditions(&given, &joints, |k, initial| {
            coordinate_row(model, &joints, k, initial).ok_or_else(|| {
                "'initial' and 'initial_rate' apply to revolute and prismatic joints only".into()
            })
        })?;
        let forces = compile_forces(model, &res, &mut names, &mut corners)?;
        let markers = compile_markers(model, &res, &mut names)?;
        let corners = step_corners(corners);
        let layout = Layout::new(bodies.iter().map(|_| PLANAR_BODY));
        let (q_guess, v_guess) = placement_guess(model, &layout);
        point_mass_inertia(model, &rows, &joints, &mut bodies)?;
        Ok(System {
            bodies,
            layout,
            joints,
            drivers,
            rows,
            forces,
            clearances,
            markers,
            gravity: Vec2::new(model.gravity[0], model.gravity[1]),
            q_guess,
            v_guess,
            corners,
            initial_conditions,
            warnings,
        })
    }
}

impl<K: BodyKind> System<K> {
    /// Every contact point of clearance joint `k` at state `(q, v)`, apart or touching.
    pub fn contact_points(&self, k: usize, q: &[f64], v: &[f64]) -> <K::Clearance as ClearanceJoint>::Points {
        let c = &self.clearances[k];
        let [i, j] = c.parts().map(|b| self.body_state(b, q, v));
        c.contacts(&i, &j, f64::INFINITY)
    }

    /// Moves the positions `q` by `dv`, a displacement in velocity coordinates, body
    /// by body by its kind's rule.
    pub fn displace(&self, q: &mut [f64], dv: &[f64]) {
        for slot in self.layout.slots() {
            K::displace(&mut q[slot.q()], &dv[slot.v()]);
        }
    }

    /// Whether each velocity coordinate is a rotation (in `v`'s order): what sets a
    /// step's size in radians rather than in metres.
    pub fn rotations(&self) -> Vec<bool> {
        self.layout.slots().iter().flat_map(|s| (0..s.shape.nv).map(K::is_rotation)).collect()
    }

    /// State of body `b` (ground: zero) from coordinate and velocity vectors.
    #[inline]
    pub fn body_state(&self, b: Option<usize>, q: &[f64], v: &[f64]) -> K::State {
        match b {
            None => K::ground(),
            Some(k) => K::read_slot(q, v, &self.layout.slot(k)),
        }
    }
}
