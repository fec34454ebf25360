//! A gear pair with backlash: two external spur gears whose teeth touch along the line
//! of action once the mesh has taken up the backlash (docs/gears.md). The mesh is
//! measured along the line of action from the gears' angles to their line of centres,
//! so the pair may sit on any bodies (a fixed housing, a turning carrier).

use super::normal::NormalForce;
use super::point::{ContactPoint, ContactPoints, MaterialPoint, Tangential};
use super::{add_force_at, ClearanceJoint, ContactState};
use crate::error::{Error, Named};
use crate::math::{cross, lift, perp, Vec2};
use crate::mechanics::layout::Loads;
use crate::mechanics::planar_body::BodyState;
use crate::model::{Gear, Joint, MeshStiffness};
use crate::output::ClearanceData;
use crate::scalar::{c, norm, Real};

/// A gear mesh's stiffness against gear 1's angle to the line of centres, as a factor
/// of the law's stiffness.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshCycle {
    /// Strictly increasing angles [rad]; the cycle is their span.
    pub angle: Vec<f64>,
    /// Stiffness factor at each angle.
    pub factor: Vec<f64>,
}

impl MeshCycle {
    /// The factor at angle `theta`, the table repeated over its span, linear between
    /// points, in any number type.
    pub fn at<T: Real>(&self, theta: T) -> T {
        let (first, span) = (self.angle[0], self.angle[self.angle.len() - 1] - self.angle[0]);
        let x = c::<T>(first) + (theta - first).rem_euclid(c(span));
        let k = self.angle.partition_point(|&a| x >= a).clamp(1, self.angle.len() - 1);
        let (a0, a1) = (self.angle[k - 1], self.angle[k]);
        let s = (x - a0) / (a1 - a0);
        c::<T>(self.factor[k - 1]) + s * (self.factor[k] - self.factor[k - 1])
    }
}

/// A checked gear pair.
#[derive(Debug, Clone)]
pub struct GearPair {
    /// Joint name.
    pub name: String,
    /// Gear 1's body and centre in its frame [m].
    pub gear_1: (Option<usize>, Vec2),
    /// Gear 2's body and centre in its frame [m].
    pub gear_2: (Option<usize>, Vec2),
    /// Pitch radii [m].
    pub radii: [f64; 2],
    /// Cosine and sine of the pressure angle.
    pub pressure: (f64, f64),
    /// Half the backlash along the line of action [m].
    pub half_backlash: f64,
    /// Direction of the line of centres at the placement, global (`psi` is measured from
    /// it, so that it is continuous while the line turns less than half a turn).
    pub u0: Vec2,
    /// Mesh measure at the placement [m]: the middle of the backlash.
    pub s0: f64,
    /// The teeth's law; its stiffness the mean mesh stiffness [N/m^n].
    pub normal: NormalForce,
    /// The stiffness along the mesh cycle, where it varies.
    pub cycle: Option<MeshCycle>,
}

/// The mesh at one state: the centres, the unit line of centres `u`, the pitch point,
/// gear 1's angle to the line, the measure along the line of action and its rate.
pub struct Mesh<T: Real> {
    u: Vec2<T>,
    pitch: Vec2<T>,
    /// Gear 1's angle to the line of centres [rad].
    pub theta_1: T,
    s: T,
    rate: T,
}

impl GearPair {
    /// Checks joint `j`'s gear data `g`, gear 1 on body `gear_1` centred at its point,
    /// gear 2 likewise, with the bodies' placements `placed` (their centres' distance
    /// must match the pitch radii). Errors name the joint and key.
    pub(crate) fn new(
        j: &Joint,
        g: &Gear,
        gear_1: (Option<usize>, Vec2),
        gear_2: (Option<usize>, Vec2),
        placed: (&BodyState, &BodyState),
    ) -> Result<Self, Error> {
        let who = Named::joint(&j.name);
        if !(g.ratio.is_finite() && g.ratio > 0.0) {
            return Err(who.error(
                "gear.ratio",
                format!(
                    "ratio = {} must be positive: it is gear 2's pitch radius over gear 1's \
                     (tooth counts z2/z1) of external gears",
                    g.ratio
                ),
            ));
        }
        if !(g.pitch_radius.is_finite() && g.pitch_radius > 0.0) {
            return Err(who.error(
                "gear.pitch_radius",
                format!("pitch_radius = {} m must be positive", g.pitch_radius),
            ));
        }
        if !(g.backlash.is_finite() && g.backlash >= 0.0) {
            return Err(
                who.error("gear.backlash", format!("backlash = {} m must be zero or positive", g.backlash))
            );
        }
        let max_angle = 45f64.to_radians();
        if !(g.pressure_angle.is_finite() && (0.0..max_angle).contains(&g.pressure_angle)) {
            return Err(who.error(
                "gear.pressure_angle",
                format!("pressure_angle = {} rad must lie in [0, 45 deg)", g.pressure_angle),
            ));
        }
        let (stiffness, cycle) = match &g.mesh_stiffness {
            MeshStiffness::Constant(k) if k.is_finite() && *k > 0.0 => (*k, None),
            MeshStiffness::Constant(k) => {
                return Err(
                    who.error("gear.mesh_stiffness", format!("mesh_stiffness = {k} must be positive"))
                );
            }
            MeshStiffness::Table { angle, value } => {
                let bad = angle.len() < 2
                    || angle.len() != value.len()
                    || angle.windows(2).any(|w| w[1] <= w[0])
                    || angle.iter().any(|a| !a.is_finite());
                if bad {
                    return Err(who.error(
                        "gear.mesh_stiffness",
                        "the table needs at least 2 strictly increasing finite angles and one value per angle".into(),
                    ));
                }
                if let Some(v) = value.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
                    return Err(who.error(
                        "gear.mesh_stiffness",
                        format!("stiffness {v} in the table must be positive"),
                    ));
                }
                let mean = value.iter().sum::<f64>() / value.len() as f64;
                (
                    mean,
                    Some(MeshCycle {
                        angle: angle.clone(),
                        factor: value.iter().map(|v| v / mean).collect(),
                    }),
                )
            }
        };
        let radii = [g.pitch_radius, g.ratio * g.pitch_radius];
        let (b1, b2) = placed;
        let (c1, c2) = (b1.r + b1.rotate(gear_1.1), b2.r + b2.rotate(gear_2.1));
        let distance = (c2 - c1).norm();
        let expected = radii[0] + radii[1];
        if (distance - expected).abs() > 1e-3 * expected || !distance.is_finite() {
            return Err(who.error_of_element(format!(
                "the gears' centres are {distance:.6} m apart at the placement, but their pitch \
                 radii (pitch_radius = {} m, ratio = {}) need {expected:.6} m: place the gears' \
                 centres (point_i, point_j and their bodies) one pitch radius sum apart",
                radii[0], g.ratio
            )));
        }
        let mut pair = GearPair {
            name: j.name.clone(),
            gear_1,
            gear_2,
            radii,
            pressure: (g.pressure_angle.cos(), g.pressure_angle.sin()),
            half_backlash: 0.5 * g.backlash * g.pressure_angle.cos(),
            u0: (c2 - c1) / distance,
            s0: 0.0,
            normal: NormalForce::new(&j.name, &g.normal_law, stiffness, None)?,
            cycle,
        };
        pair.s0 = pair.mesh(b1, b2).s;
        Ok(pair)
    }

    /// The mesh at the gears' states: `s = r_b1 (phi_1 - psi) + r_b2 (phi_2 - psi) - s0`
    /// with `r_b = r cos(alpha)` the base radii and `psi` the line of centres' angle.
    #[inline]
    pub fn mesh<T: Real>(&self, g1: &BodyState<T>, g2: &BodyState<T>) -> Mesh<T> {
        let (c1, c2) = (g1.r + g1.rotate(self.gear_1.1), g2.r + g2.rotate(self.gear_2.1));
        let d = c2 - c1;
        let distance = norm(&d);
        let u = d / distance;
        let u0 = lift(self.u0);
        let psi = cross(u0, u).atan2(u0.dot(&u));
        let (v1, v2) = (g1.v + perp(c1 - g1.r) * g1.omega, g2.v + perp(c2 - g2.r) * g2.omega);
        let psi_rate = cross(u, v2 - v1) / distance;
        let (b1, b2) = (self.radii[0] * self.pressure.0, self.radii[1] * self.pressure.0);
        Mesh {
            u,
            pitch: c1 + u * c::<T>(self.radii[0]),
            theta_1: g1.phi() - psi,
            s: (g1.phi() - psi) * b1 + (g2.phi() - psi) * b2 - self.s0,
            rate: (g1.omega - psi_rate) * b1 + (g2.omega - psi_rate) * b2,
        }
    }

    /// The mesh measure along the line of action [m] (zero at the placement, the middle
    /// of the backlash) and the stiffness there [N/m^n].
    pub fn measure(&self, g1: &BodyState, g2: &BodyState) -> (f64, f64) {
        let m = self.mesh(g1, g2);
        (m.s, self.normal.stiffness * self.share_at(m.theta_1))
    }

    /// The tooth force on gear 2 [N] at the pitch point for a normal force `f_n` on the
    /// flank of side `side` (+1: gear 1 drives gear 2 forwards, -1: the other flank).
    fn tooth_force<T: Real>(&self, u: Vec2<T>, side: f64, f_n: T) -> Vec2<T> {
        (perp(u) * c::<T>(side * self.pressure.0) + u * c::<T>(self.pressure.1)) * f_n
    }

    /// The stiffness factor at gear 1's angle `theta_1` to the line of centres: the mesh
    /// cycle's, 1 without one.
    #[inline]
    pub fn share_at<T: Real>(&self, theta_1: T) -> T {
        self.cycle.as_ref().map_or(c(1.0), |cycle| cycle.at(theta_1))
    }

    /// The one point within `reach` ([`ClearanceJoint::contacts`]) of mesh `m`, in any
    /// number type; `share` its stiffness factor.
    #[inline]
    fn point_of<T: Real>(&self, m: &Mesh<T>, share: T, reach: f64) -> Option<ContactPoint<T>> {
        let side = if m.s >= 0.0 { 1.0 } else { -1.0 };
        let penetration = m.s * side - self.half_backlash;
        (penetration > -reach).then(|| ContactPoint {
            index: 0,
            normal: -self.tooth_force(m.u, side, T::constant(1.0)),
            penetration,
            penetration_rate: m.rate * side,
            slip: Tangential::zeros(),
            share,
            on_i: MaterialPoint { body: self.gear_1.0, at: m.pitch },
            on_j: MaterialPoint { body: self.gear_2.0, at: m.pitch },
        })
    }

    /// The teeth's normal force at point `p` for onset speed `onset_speed`: the law's,
    /// times the mesh stiffness's factor `share`.
    #[inline]
    fn tooth_normal_force<T: Real>(&self, p: &ContactPoint<T>, onset_speed: T) -> T {
        self.normal.force(p.penetration, p.penetration_rate, onset_speed) * p.share
    }

    /// Adds the tooth forces ([`ClearanceJoint::add_to`]) of mesh `m` ([`Self::mesh`])
    /// in any number type, the stiffness factor there being `share` ([`Self::share_at`]):
    /// `onset(k, rate)` is the impact onset speed of point `k` at penetration rate `rate`
    /// ([`ContactState::onset_for`]).
    #[inline]
    pub fn add_gear_loads<T: Real>(
        &self,
        m: &Mesh<T>,
        share: T,
        (g1, g2): (&BodyState<T>, &BodyState<T>),
        onset: impl Fn(usize, T) -> T,
        qe: &mut Loads<T>,
    ) {
        if let Some(p) = self.point_of(m, share, self.reach()) {
            let f_n = self.tooth_normal_force(&p, onset(p.index, p.penetration_rate));
            if f_n != 0.0 {
                let f = -p.normal * f_n;
                add_force_at(qe, self.gear_2.0, g2, p.on_j.at, f);
                add_force_at(qe, self.gear_1.0, g1, p.on_i.at, -f);
            }
        }
    }

    /// The tooth torques on gear 1 and gear 2 about their centres [N m] at the gears'
    /// states and the contact state `state`.
    pub fn torques(&self, g1: &BodyState, g2: &BodyState, state: &ContactState) -> (f64, f64, f64) {
        let Some(p) = self.contacts(g1, g2, f64::INFINITY).first().copied() else { return (0.0, 0.0, 0.0) };
        let (f_n, _) = self.force(&p, state.onset_for(p.penetration_rate));
        let m = self.mesh(g1, g2);
        let f2 = self.tooth_force(m.u, if m.s >= 0.0 { 1.0 } else { -1.0 }, f_n);
        let (c1, c2) = (g1.r + g1.rotate(self.gear_1.1), g2.r + g2.rotate(self.gear_2.1));
        (cross(m.pitch - c1, -f2), cross(m.pitch - c2, f2), f_n)
    }
}

impl ClearanceJoint for GearPair {
    type State = BodyState;
    type Point = ContactPoint;
    type Points = ContactPoints;
    type Friction = Tangential;

    fn name(&self) -> &str {
        &self.name
    }

    fn parts(&self) -> [Option<usize>; 2] {
        [self.gear_1.0, self.gear_2.0]
    }

    /// The pitch radii as the "bearing" and "journal", half the backlash along the line
    /// of action as the clearance.
    fn data(&self) -> ClearanceData {
        ClearanceData {
            joint: self.name.clone(),
            bearing_radius: self.radii[0],
            journal_radius: self.radii[1],
            clearance: self.half_backlash,
            stiffness: self.normal.stiffness,
            exponent: self.normal.exponent,
        }
    }

    /// The mesh starts at the middle of its backlash by construction.
    fn check_initial_penetration(&self, _: &BodyState, _: &BodyState) -> Result<(), Error> {
        Ok(())
    }

    fn points(&self) -> usize {
        1
    }

    fn reach(&self) -> f64 {
        self.normal.reach()
    }

    /// The one point at the pitch point: penetration `|s| - backlash cos(alpha) / 2`, its
    /// normal the line of action of the flank in touch (the force on gear 2 along `-n`
    /// pushes it back), its share the stiffness factor of the mesh cycle.
    #[inline]
    fn contacts(&self, g1: &BodyState, g2: &BodyState, reach: f64) -> ContactPoints {
        let m = self.mesh(g1, g2);
        let mut out = ContactPoints::new();
        if let Some(p) = self.point_of(&m, self.share_at(m.theta_1), reach) {
            out.push(p);
        }
        out
    }

    #[inline]
    fn force(&self, p: &ContactPoint, onset_speed: f64) -> (f64, Tangential) {
        (self.tooth_normal_force(p, onset_speed), Tangential::zeros())
    }

    fn losses(&self, g1: &BodyState, g2: &BodyState, states: &[ContactState]) -> (f64, f64) {
        super::sum_losses(self.contacts(g1, g2, self.reach()).iter(), |p| {
            let (f_n, _) = self.force(p, states[0].onset_for(p.penetration_rate));
            ((f_n - p.share * self.normal.elastic_force(p.penetration)) * p.penetration_rate, 0.0)
        })
    }

    fn elastic_energy(&self, p: &ContactPoint) -> f64 {
        p.share * self.normal.elastic_energy(p.penetration)
    }

    /// The tooth force `F (+-t cos(alpha) + u sin(alpha))` on gear 2 at the pitch point,
    /// its opposite on gear 1 there.
    #[inline]
    fn add_to(&self, g1: &BodyState, g2: &BodyState, states: &[ContactState], qe: &mut Loads) {
        let m = self.mesh(g1, g2);
        self.add_gear_loads(&m, self.share_at(m.theta_1), (g1, g2), |k, rate| states[k].onset_for(rate), qe);
    }
}
