//! Spatial clearance joints: a ball in its socket (spherical clearance) and a journal
//! in its bearing that may tilt (cylindrical clearance), each a contact geometry of
//! [`geometry`](super::geometry) with the same normal and friction laws as the planar
//! clearance joint (docs/spatial-clearance.md). A contact point's normal force is its
//! share of the law's (a journal end carries half) and its friction acts against the
//! slip vector.

use super::film::FilmMotion;
use super::geometry::{
    contact_ball_socket, contact_block_channel, contact_cylinder_bearing, contact_round_cylinder,
    contact_worn_cylinder, search_cylinder, wall_contact, BallSocket, BlockChannel, CylinderBearing, Found,
    Frames, Worn,
};
use super::lubricated_cylinder::LubricatedCylinder;
use super::normal::NormalForce;
use super::point3::{ContactPoint3, ContactPoints3, MaterialPoint3};
use super::{ClearanceJoint, ContactMeasure, ContactState, WearContact, MAX_INITIAL_CONTACT_FORCE};
use crate::error::{Error, Named};
use crate::mechanics::drivers::Motion;
use crate::mechanics::layout::Loads;
use crate::mechanics::spatial::body::{self, constant, BodyState, Vec3};
use crate::mechanics::spatial::joints::{row_rate, SpatialRowEval, SpatialRowKind};
use crate::model::FrictionSpec;
use crate::output::ClearanceData;
use crate::scalar::Real;
use nalgebra::Vector3;

/// Where a spatial clearance joint's parts are and their shape.
#[derive(Debug, Clone, PartialEq)]
pub enum SpatialGeometry {
    /// A ball (body j) in a spherical socket (body i).
    BallSocket(BallSocket),
    /// A journal (body j) in a cylindrical bearing (body i), free to tilt.
    Cylinder(CylinderBearing),
    /// A revolute or prismatic joint's play about or along its axis.
    Play(SpatialPlay),
    /// A box-shaped block (body j) in a guide channel (body i).
    Block(BlockChannel),
    /// A journal (body j) in a cylindrical bearing (body i) carried by an oil film.
    Lubricated(LubricatedCylinder),
}

/// The play of a spatial revolute or prismatic joint: its coordinate (angle about the
/// axis, travel along it) is free within `+- half_play` of the row's offset.
#[derive(Debug, Clone, PartialEq)]
pub struct SpatialPlay {
    /// Bodies i and j.
    pub bodies: [Option<usize>; 2],
    /// The joint points on each body, their frames [m] (where the impact is drawn).
    pub points: [Vec3; 2],
    /// The row measuring the coordinate from the middle of the play (its offset).
    pub row: SpatialRowKind,
    /// Half the play [rad or m].
    pub half_play: f64,
}

impl SpatialPlay {
    /// The coordinate from the middle of the play, its rate, and the row's Jacobian
    /// blocks (the coordinate's gradient over each body's velocity coordinates), in any
    /// number type.
    #[inline]
    pub fn measure<T: Real>(&self, i: &BodyState<T>, j: &BodyState<T>) -> (T, T, SpatialRowEval<T>) {
        let zero = T::constant(0.0);
        let ev = self.row.eval(i, j, Motion { position: zero, speed: zero, acceleration: zero });
        (ev.c, row_rate(&ev, i, j), ev)
    }

    /// The one point: penetration `|x| - play/2`, its normal's first component the side.
    fn contact<T: Real>(&self, i: &BodyState<T>, j: &BodyState<T>, reach: f64, out: &mut ContactPoints3<T>) {
        let (x, rate, _) = self.measure(i, j);
        let side = T::constant(if x >= 0.0 { 1.0 } else { -1.0 });
        let penetration = side * x - self.half_play;
        if penetration > -reach {
            let zero = T::constant(0.0);
            out.push(ContactPoint3 {
                index: 0,
                normal: Vector3::new(side, zero, zero),
                penetration,
                penetration_rate: side * rate,
                slip: Vector3::zeros(),
                share: T::constant(1.0),
                on_i: MaterialPoint3::of(self.bodies[0], i, i.r + i.rotate(&constant(&self.points[0]))),
                on_j: MaterialPoint3::of(self.bodies[1], j, j.r + j.rotate(&constant(&self.points[1]))),
            });
        }
    }
}

/// A checked spatial clearance joint: its contact geometry and its laws.
#[derive(Debug, Clone)]
pub struct SpatialClearance {
    /// Joint name.
    pub name: String,
    /// Its parts and their shape.
    pub geometry: SpatialGeometry,
    /// Normal law with its stiffness.
    pub normal: NormalForce,
    /// Friction law (checked).
    pub friction: FrictionSpec,
    /// What a run that accumulates wear needs of a dry cylindrical joint, its line
    /// contact ([`super::line_contact`]); `Err` says why the joint cannot wear.
    pub wear_contact: Result<WearContact, String>,
}

/// Why joint `who` takes no part in a run's wear: it is no dry journal in its bearing.
pub fn not_worn(who: Named) -> String {
    format!("{who}: wear is modelled for dry revolute and cylindrical clearance joints")
}

impl ContactMeasure for ContactPoint3 {
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

/// Adds force `f` (global) at the global point `p` of a body.
#[inline]
fn add_force_at<T: Real>(loads: &mut Loads<T>, p: &MaterialPoint3<T>, state: &BodyState<T>, f: &Vector3<T>) {
    if let Some(qe) = loads.body(p.body) {
        body::add_force(qe, state, &p.arm, f);
    }
}

/// Adds the force of each of `points` (`force` gives its normal and friction forces):
/// body j's at its material point, the opposite on body i at its own.
#[inline]
fn apply_point_forces<T: Real>(
    points: &[ContactPoint3<T>],
    force: impl Fn(&ContactPoint3<T>) -> (T, Vector3<T>),
    i: &BodyState<T>,
    j: &BodyState<T>,
    qe: &mut Loads<T>,
) {
    for p in points {
        let (f_n, f_t) = force(p);
        if f_n != 0.0 || f_t.iter().any(|&f| f != 0.0) {
            let f = p.force_on_j(f_n, &f_t);
            add_force_at(qe, &p.on_j, j, &f);
            add_force_at(qe, &p.on_i, i, &-f);
        }
    }
}

impl SpatialClearance {
    /// A contact point's normal force (its share of the normal law's) and friction
    /// force, in any number type, for the impact onset speed `onset_speed` [m/s]:
    /// friction acts against the slip, and only under a pressing normal force.
    #[inline]
    fn point_force<T: Real>(&self, p: &ContactPoint3<T>, onset_speed: T) -> (T, Vector3<T>) {
        let f_n = self.normal.force(p.penetration, p.penetration_rate, onset_speed) * p.share;
        let f_t = if f_n > 0.0 { self.friction.force_on_slip(&p.slip, f_n) } else { Vector3::zeros() };
        (f_n, f_t)
    }

    /// Adds the contact loads of a ball in its socket or a round journal in its bearing,
    /// dry or (its dry laws) lubricated (no wear), in any number type (the interpreted [`ClearanceJoint::add_to`] runs the
    /// same kernels): `onset(k, rate)` is the impact onset speed of point `k` at
    /// penetration rate `rate` ([`ContactState::onset_for`]). `None` for the other
    /// geometries, which add nothing here.
    #[inline]
    pub fn add_dry_loads<T: Real>(
        &self,
        i: &BodyState<T>,
        j: &BodyState<T>,
        onset: impl Fn(usize, T) -> T,
        qe: &mut Loads<T>,
    ) -> Option<()> {
        let mut points = ContactPoints3::new();
        match &self.geometry {
            SpatialGeometry::BallSocket(g) => contact_ball_socket(g, i, j, self.reach(), &mut points),
            SpatialGeometry::Cylinder(g) if g.worn.is_none() => {
                contact_round_cylinder(g, i, j, self.reach(), &mut points)
            }
            SpatialGeometry::Lubricated(g) => contact_round_cylinder(&g.dry, i, j, self.reach(), &mut points),
            _ => return None,
        }
        let force = |p: &ContactPoint3<T>| self.point_force(p, onset(p.index, p.penetration_rate));
        apply_point_forces(&points, force, i, j, qe);
        Some(())
    }

    /// Adds the contact loads of a journal in its bearing `g` whose parts are worn as
    /// `worn`, in any number type, from where the search found the rims at each end
    /// (`found`, [`search_cylinder`]); `onset` as for [`Self::add_dry_loads`].
    #[inline]
    pub fn add_worn_loads<T: Real>(
        &self,
        (g, worn, found): (&CylinderBearing, &Worn, &[Found<T>; 2]),
        i: &BodyState<T>,
        j: &BodyState<T>,
        onset: impl Fn(usize, T) -> T,
        qe: &mut Loads<T>,
    ) {
        let mut points = ContactPoints3::new();
        contact_worn_cylinder(g, worn, found, i, j, self.reach(), &mut points);
        let force = |p: &ContactPoint3<T>| self.point_force(p, onset(p.index, p.penetration_rate));
        apply_point_forces(&points, force, i, j, qe);
    }

    /// The worn parts of a dry journal in its bearing, if it has them (a lubricated
    /// joint has none).
    pub fn worn(&self) -> Option<(&CylinderBearing, &Worn)> {
        match &self.geometry {
            SpatialGeometry::Cylinder(g) => Some((g, g.worn.as_deref()?)),
            _ => None,
        }
    }

    /// Adds the loads of point `index` of a block in its channel `g` in any number type,
    /// as [`ClearanceJoint::add_to`] adds each point's: its corner at `corner`, the
    /// frames being `f`; `onset(k, rate)` as for [`Self::add_dry_loads`].
    #[inline]
    pub fn add_wall_loads<T: Real>(
        &self,
        (g, f, corner): (&BlockChannel, &Frames<T>, Vector3<T>),
        (i, j): (&BodyState<T>, &BodyState<T>),
        index: usize,
        onset: impl Fn(usize, T) -> T,
        qe: &mut Loads<T>,
    ) {
        if let Some(p) = wall_contact(g, f, corner, (i, j), index, self.reach()) {
            apply_point_forces(&[p], |p| self.point_force(p, onset(p.index, p.penetration_rate)), i, j, qe);
        }
    }

    /// Adds the loads of a joint's play `g` at its stops, in any number type: the
    /// generalized force `-side F` along its coordinate's gradient (a torque about the
    /// axis, a force along it), minus the derivative of its energy. `onset(k, rate)` as
    /// for [`Self::add_dry_loads`].
    #[inline]
    pub fn add_play_loads<T: Real>(
        &self,
        g: &SpatialPlay,
        i: &BodyState<T>,
        j: &BodyState<T>,
        onset: impl Fn(usize, T) -> T,
        qe: &mut Loads<T>,
    ) {
        let mut points = ContactPoints3::new();
        g.contact(i, j, self.reach(), &mut points);
        for p in points.iter() {
            let (f_n, _) = self.point_force(p, onset(0, p.penetration_rate));
            if f_n == 0.0 {
                continue;
            }
            let (_, _, ev) = g.measure(i, j);
            for (body, jac) in [(g.bodies[0], &ev.jac_i), (g.bodies[1], &ev.jac_j)] {
                if let Some(q) = qe.body(body) {
                    q.iter_mut().zip(jac.iter()).for_each(|(q, d)| *q -= p.normal.x * f_n * *d);
                }
            }
        }
    }

    /// The radii of the hole and the pin, and the radial clearance.
    fn radii(&self) -> (f64, f64, f64) {
        match &self.geometry {
            SpatialGeometry::BallSocket(g) => (g.r_socket, g.r_ball, g.clearance),
            SpatialGeometry::Cylinder(g) => (g.r_bearing, g.r_journal, g.clearance),
            SpatialGeometry::Play(g) => (0.0, 0.0, g.half_play),
            SpatialGeometry::Block(g) => {
                (g.half_channel[0], g.half_block.y, g.half_channel[0] - g.half_block.y)
            }
            SpatialGeometry::Lubricated(g) => (g.dry.r_bearing, g.dry.r_journal, g.film.clearance),
        }
    }
}

impl ClearanceJoint for SpatialClearance {
    type State = BodyState;
    type Point = ContactPoint3;
    type Points = ContactPoints3;
    type Friction = Vec3;

    fn name(&self) -> &str {
        &self.name
    }

    fn parts(&self) -> [Option<usize>; 2] {
        match &self.geometry {
            SpatialGeometry::BallSocket(g) => [g.socket, g.ball],
            SpatialGeometry::Cylinder(g) => [g.bearing, g.journal],
            SpatialGeometry::Play(g) => g.bodies,
            SpatialGeometry::Block(g) => [g.guide, g.block],
            SpatialGeometry::Lubricated(g) => [g.dry.bearing, g.dry.journal],
        }
    }

    fn data(&self) -> ClearanceData {
        let (r_bearing, r_journal, clearance) = self.radii();
        ClearanceData {
            joint: self.name.clone(),
            bearing_radius: r_bearing,
            journal_radius: r_journal,
            clearance,
            stiffness: self.normal.stiffness,
            exponent: self.normal.exponent,
        }
    }

    fn check_initial_penetration(&self, i: &BodyState, j: &BodyState) -> Result<(), Error> {
        let limit = (MAX_INITIAL_CONTACT_FORCE / self.normal.stiffness).powf(1.0 / self.normal.exponent);
        let (_, _, clearance) = self.radii();
        match self.contacts(i, j, f64::INFINITY).iter().find(|p| p.penetration > limit) {
            None => Ok(()),
            Some(p) => {
                let mm = 1e3;
                Err(Named::joint(&self.name).error_of_element(format!(
                    "contact point {} starts {:.4} mm deep (clearance {:.4} mm), deeper \
                     than any elastic contact: this joint's normal law (K = {:.4e} N/m^{}) presses \
                     {:.4} mm deep only under {:.0e} N; likely a wrong point (point_i or point_j), a \
                     wrong radius, or a length in the wrong unit",
                    p.index + 1,
                    mm * p.penetration,
                    mm * clearance,
                    self.normal.stiffness,
                    self.normal.exponent,
                    mm * limit,
                    MAX_INITIAL_CONTACT_FORCE,
                )))
            }
        }
    }

    fn points(&self) -> usize {
        match &self.geometry {
            SpatialGeometry::BallSocket(_) => BallSocket::POINTS,
            SpatialGeometry::Cylinder(g) => g.points(),
            SpatialGeometry::Play(_) => 1,
            SpatialGeometry::Block(_) => BlockChannel::POINTS,
            SpatialGeometry::Lubricated(g) => g.dry.points(),
        }
    }

    fn reach(&self) -> f64 {
        self.normal.reach()
    }

    #[inline]
    fn contacts(&self, i: &BodyState, j: &BodyState, reach: f64) -> ContactPoints3 {
        let mut out = ContactPoints3::new();
        match &self.geometry {
            SpatialGeometry::BallSocket(g) => contact_ball_socket(g, i, j, reach, &mut out),
            SpatialGeometry::Cylinder(g) => contact_cylinder_bearing(g, i, j, reach, &mut out),
            SpatialGeometry::Play(g) => g.contact(i, j, reach, &mut out),
            SpatialGeometry::Block(g) => contact_block_channel(g, i, j, reach, &mut out),
            SpatialGeometry::Lubricated(g) => contact_cylinder_bearing(&g.dry, i, j, reach, &mut out),
        }
        out
    }

    #[inline]
    fn force(&self, p: &ContactPoint3, onset_speed: f64) -> (f64, Vec3) {
        self.point_force(p, onset_speed)
    }

    /// As the planar joint's ([`super::ClearanceRevolute`]): the law's damping and
    /// clipping lose `(F_N - share K delta^n) delta_dot`, friction `-F_T . v_t`.
    /// A film loses its power on the two bodies as normal losses.
    fn losses(&self, i: &BodyState, j: &BodyState, states: &[ContactState]) -> (f64, f64) {
        let (normal, friction) = super::sum_losses(self.contacts(i, j, self.reach()).iter(), |p| {
            let (f_n, f_t) = self.force(p, states[p.index].onset_for(p.penetration_rate));
            let elastic = p.share * self.normal.elastic_force(p.penetration);
            ((f_n - elastic) * p.penetration_rate, -f_t.dot(&p.slip))
        });
        match &self.geometry {
            SpatialGeometry::Lubricated(g) => (normal - g.film_power(i, j), friction),
            _ => (normal, friction),
        }
    }

    fn elastic_energy(&self, p: &ContactPoint3) -> f64 {
        p.share * self.normal.elastic_energy(p.penetration)
    }

    /// Each point's force on body j at its point and the opposite on body i at its own, and
    /// a film's loads; a play's stop by [`SpatialClearance::add_play_loads`].
    #[inline]
    fn add_to(&self, i: &BodyState, j: &BodyState, states: &[ContactState], qe: &mut Loads) {
        let onset = |k: usize, rate| states[k].onset_for(rate);
        if let SpatialGeometry::Play(g) = &self.geometry {
            return self.add_play_loads(g, i, j, onset, qe);
        }
        if let Some((g, worn)) = self.worn() {
            let found = search_cylinder(g, worn, i, j, self.reach());
            return self.add_worn_loads((g, worn, &found), i, j, onset, qe);
        }
        if self.add_dry_loads(i, j, onset, qe).is_none() {
            let points = self.contacts(i, j, self.reach());
            apply_point_forces(
                &points,
                |p| self.point_force(p, onset(p.index, p.penetration_rate)),
                i,
                j,
                qe,
            );
        }
        if let SpatialGeometry::Lubricated(g) = &self.geometry {
            let film = |m: &FilmMotion| {
                let f = g.film.force(m);
                [f.along, f.across, f.torque_journal]
            };
            g.add_film_loads(i, j, film, qe);
        }
    }
}
