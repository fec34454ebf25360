//! Applied forces: gravity, spring-dampers and prescribed loads, as generalised forces
//! `Qe` on the coordinates (x, y, phi) of each body, and their potential energy.

use crate::error::{Error, Named};
use crate::math::{perp, Vec2};
use crate::mechanics::kind::ForceLaw;
use crate::mechanics::layout::Loads;
use crate::mechanics::planar_body::{self, BodyState};
use crate::mechanics::resolve::Resolver;
use crate::model::{Force, Signal};
use crate::scalar::{norm, Real};

/// A value against time: constant, or linear between table points and held outside.
#[derive(Debug, Clone)]
pub struct TimeTable<const N: usize> {
    time: Vec<f64>,
    value: Vec<[f64; N]>,
}

impl<const N: usize> TimeTable<N> {
    /// A table of `who`'s `key` (`force`, `torque`), its errors naming them.
    pub(crate) fn new(who: Named, key: &str, time: Vec<f64>, value: Vec<[f64; N]>) -> Result<Self, Error> {
        if time.is_empty() || time.len() != value.len() {
            return Err(who.error(
                key,
                format!(
                    "a table needs as many values as times (got {} times, {} values)",
                    time.len(),
                    value.len()
                ),
            ));
        }
        if let Some(k) =
            time.windows(2).position(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
        {
            return Err(who.error(
                &format!("{key}.time"),
                format!("table times must increase strictly (time[{k}] = {} then {})", time[k], time[k + 1]),
            ));
        }
        if let Some((part, v)) = time
            .iter()
            .map(|v| ("time", v))
            .chain(value.iter().flatten().map(|v| ("value", v)))
            .find(|(_, v)| !v.is_finite())
        {
            return Err(who.error(&format!("{key}.{part}"), format!("table value {v} is not finite")));
        }
        Ok(TimeTable { time, value })
    }

    fn constant(v: [f64; N]) -> Self {
        TimeTable { time: vec![0.0], value: vec![v] }
    }

    /// `who`'s `key` (`force`, `torque`), constant or a table.
    pub(crate) fn from_signal(who: Named, key: &str, s: &Signal<[f64; N]>) -> Result<Self, Error> {
        match s {
            Signal::Constant(v) => {
                if let Some(x) = v.iter().find(|x| !x.is_finite()) {
                    return Err(who.error(key, format!("value {x} is not finite")));
                }
                Ok(Self::constant(*v))
            }
            Signal::Table { time, value } => Self::new(who, key, time.clone(), value.clone()),
        }
    }

    /// The table's times, where the load's slope jumps.
    pub fn times(&self) -> &[f64] {
        &self.time
    }

    /// Value at time `t`.
    pub fn at(&self, t: f64) -> [f64; N] {
        let n = self.time.len();
        if t <= self.time[0] {
            return self.value[0];
        }
        if t >= self.time[n - 1] {
            return self.value[n - 1];
        }
        let i = self.time.partition_point(|&x| x <= t) - 1;
        let s = (t - self.time[i]) / (self.time[i + 1] - self.time[i]);
        std::array::from_fn(|k| self.value[i][k] + s * (self.value[i + 1][k] - self.value[i][k]))
    }
}

/// A checked force element; bodies are `None` for the ground.
#[derive(Debug, Clone)]
pub enum ForceElement {
    /// Point-to-point spring-damper.
    SpringDamper {
        /// Name.
        name: String,
        /// Body i.
        body_i: Option<usize>,
        /// Point on body i [m].
        s_i: Vec2,
        /// Body j.
        body_j: Option<usize>,
        /// Point on body j [m].
        s_j: Vec2,
        /// Stiffness [N/m].
        stiffness: f64,
        /// Damping [N s/m].
        damping: f64,
        /// Free length [m].
        free_length: f64,
    },
    /// Torsional spring-damper between two bodies.
    RotationalSpringDamper {
        /// Name.
        name: String,
        /// Body i.
        body_i: Option<usize>,
        /// Body j.
        body_j: Option<usize>,
        /// Stiffness [N m/rad].
        stiffness: f64,
        /// Damping [N m s/rad].
        damping: f64,
        /// Unloaded relative angle [rad].
        free_angle: f64,
    },
    /// Force in global axes at a body point.
    AppliedForce {
        /// Name.
        name: String,
        /// Loaded body.
        body: Option<usize>,
        /// Point [m].
        s: Vec2,
        /// Force [N] against time.
        force: TimeTable<2>,
    },
    /// Torque on a body.
    AppliedTorque {
        /// Name.
        name: String,
        /// Loaded body.
        body: Option<usize>,
        /// Torque [N m] against time.
        torque: TimeTable<1>,
    },
}

/// The line of a point-to-point element from point `s_i` of body i to point `s_j` of
/// body j: unit vector, length and the length's rate; `None` where the points coincide
/// and the direction is undefined (such an element carries no force).
fn line<T: Real>(bi: &BodyState<T>, s_i: Vec2, bj: &BodyState<T>, s_j: Vec2) -> Option<(Vec2<T>, T, T)> {
    let (a_i, a_j) = (bi.rotate(s_i), bj.rotate(s_j));
    let d = bj.r + a_j - bi.r - a_i;
    let length = norm(&d);
    if length < 1e-12 {
        return None;
    }
    let u = d / length;
    Some((u, length, u.dot(&(bj.v + perp(a_j) * bj.omega - bi.v - perp(a_i) * bi.omega))))
}

/// Adds force `f` acting at body-frame point `s` of body `b` to the loads.
#[inline]
pub fn add_point_force<T: Real>(
    loads: &mut Loads<T>,
    b: Option<usize>,
    state: &BodyState<T>,
    s: Vec2,
    f: Vec2<T>,
) {
    if let Some(qe) = loads.body(b) {
        planar_body::add_force(qe, state.rotate(s), f);
    }
}

#[inline]
fn add_torque<T: Real>(loads: &mut Loads<T>, b: Option<usize>, tau: T) {
    if let Some(qe) = loads.body(b) {
        planar_body::add_torque(qe, tau);
    }
}

pub(crate) fn non_negative(who: Named, what: &str, unit: &str, v: f64) -> Result<f64, Error> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(who.error(what, format!("{what} = {v} {unit} must be zero or positive")))
    }
}

impl ForceElement {
    /// The value of an applied force's table at time `t` (`[fx, fy]`), of an applied
    /// torque's (`[tau, 0]`); zero for an element whose force comes from the state.
    pub fn applied_at(&self, t: f64) -> [f64; 2] {
        match self {
            ForceElement::AppliedForce { force, .. } => force.at(t),
            ForceElement::AppliedTorque { torque, .. } => [torque.at(t)[0], 0.0],
            _ => [0.0; 2],
        }
    }

    /// Adds this element's generalised force to the loads, the bodies' states given by
    /// `state` and an applied load's table value by `applied` ([`Self::applied_at`]).
    pub fn add_loads<T: Real>(
        &self,
        applied: [T; 2],
        state: impl Fn(Option<usize>) -> BodyState<T>,
        qe: &mut Loads<T>,
    ) {
        match self {
            ForceElement::SpringDamper {
                body_i, s_i, body_j, s_j, stiffness, damping, free_length, ..
            } => {
                let (bi, bj) = (state(*body_i), state(*body_j));
                let Some((u, length, rate)) = line(&bi, *s_i, &bj, *s_j) else {
                    return;
                };
                let tension = (length - *free_length) * *stiffness + rate * *damping;
                add_point_force(qe, *body_i, &bi, *s_i, u * tension);
                add_point_force(qe, *body_j, &bj, *s_j, -u * tension);
            }
            ForceElement::RotationalSpringDamper {
                body_i, body_j, stiffness, damping, free_angle, ..
            } => {
                let (bi, bj) = (state(*body_i), state(*body_j));
                let tau =
                    (bj.phi() - bi.phi() - *free_angle) * -*stiffness - (bj.omega - bi.omega) * *damping;
                add_torque(qe, *body_j, tau);
                add_torque(qe, *body_i, -tau);
            }
            ForceElement::AppliedForce { body, s, .. } => {
                add_point_force(qe, *body, &state(*body), *s, Vec2::new(applied[0], applied[1]));
            }
            ForceElement::AppliedTorque { body, .. } => add_torque(qe, *body, applied[0]),
        }
    }

    pub(crate) fn new(f: &Force, res: &Resolver) -> Result<Self, Error> {
        let who = Named::force(f.name());
        Ok(match f {
            Force::SpringDamper {
                name,
                body_i,
                point_i,
                body_j,
                point_j,
                stiffness,
                damping,
                free_length,
            } => {
                let bi = res.body(who, "body_i", body_i)?;
                let bj = res.body(who, "body_j", body_j)?;
                ForceElement::SpringDamper {
                    name: name.clone(),
                    body_i: bi,
                    s_i: res.point(who, "point_i", bi, point_i)?,
                    body_j: bj,
                    s_j: res.point(who, "point_j", bj, point_j)?,
                    stiffness: non_negative(who, "stiffness", "N/m", *stiffness)?,
                    damping: non_negative(who, "damping", "N s/m", *damping)?,
                    free_length: non_negative(who, "free_length", "m", *free_length)?,
                }
            }
            Force::RotationalSpringDamper { name, body_i, body_j, stiffness, damping, free_angle } => {
                if !free_angle.is_finite() {
                    return Err(who.error("free_angle", format!("free_angle = {free_angle} is not finite")));
                }
                ForceElement::RotationalSpringDamper {
                    name: name.clone(),
                    body_i: res.body(who, "body_i", body_i)?,
                    body_j: res.body(who, "body_j", body_j)?,
                    stiffness: non_negative(who, "stiffness", "N m/rad", *stiffness)?,
                    damping: non_negative(who, "damping", "N m s/rad", *damping)?,
                    free_angle: *free_angle,
                }
            }
            Force::AppliedForce { name, body, point, force } => {
                let b = res.body(who, "body", body)?;
                ForceElement::AppliedForce {
                    name: name.clone(),
                    body: b,
                    s: res.point(who, "point", b, point)?,
                    force: TimeTable::from_signal(who, "force", force)?,
                }
            }
            Force::AppliedTorque { name, body, torque } => {
                let torque = match torque {
                    Signal::Constant(v) => Signal::Constant([*v]),
                    Signal::Table { time, value } => {
                        Signal::Table { time: time.clone(), value: value.iter().map(|v| [*v]).collect() }
                    }
                };
                ForceElement::AppliedTorque {
                    name: name.clone(),
                    body: res.body(who, "body", body)?,
                    torque: TimeTable::from_signal(who, "torque", &torque)?,
                }
            }
        })
    }
}

impl ForceLaw<BodyState> for ForceElement {
    /// Table times, where the load's slope jumps.
    fn corners(&self) -> Vec<f64> {
        match self {
            ForceElement::AppliedForce { force, .. } => force.time.clone(),
            ForceElement::AppliedTorque { torque, .. } => torque.time.clone(),
            _ => vec![],
        }
    }

    /// Adds this element's generalised force at time `t` to the loads.
    fn add_to(&self, t: f64, state: impl Fn(Option<usize>) -> BodyState, qe: &mut Loads) {
        self.add_loads(self.applied_at(t), state, qe);
    }

    /// Power [W] the element delivers to the bodies at time `t`, as `(load, loss)`: the
    /// work rate of an applied force or torque (energy from outside the mechanism), and
    /// the rate at which a damper dissipates, `c rate^2 >= 0` (its force `-c rate` along
    /// the rate). A spring's elastic power is the rate of its potential energy and is in
    /// neither.
    fn power(&self, t: f64, state: impl Fn(Option<usize>) -> BodyState) -> (f64, f64) {
        match self {
            ForceElement::SpringDamper { body_i, s_i, body_j, s_j, damping, .. } => {
                match line(&state(*body_i), *s_i, &state(*body_j), *s_j) {
                    Some((_, _, rate)) => (0.0, damping * rate * rate),
                    None => (0.0, 0.0),
                }
            }
            ForceElement::RotationalSpringDamper { body_i, body_j, damping, .. } => {
                let rate = state(*body_j).omega - state(*body_i).omega;
                (0.0, damping * rate * rate)
            }
            ForceElement::AppliedForce { body, s, force, .. } => {
                let b = state(*body);
                let f = force.at(t);
                (Vec2::new(f[0], f[1]).dot(&(b.v + perp(b.rotate(*s)) * b.omega)), 0.0)
            }
            ForceElement::AppliedTorque { body, torque, .. } => (torque.at(t)[0] * state(*body).omega, 0.0),
        }
    }

    /// Stored elastic energy [J] (springs only; applied loads are non-conservative).
    fn potential_energy(&self, state: impl Fn(Option<usize>) -> BodyState) -> f64 {
        match self {
            ForceElement::SpringDamper { body_i, s_i, body_j, s_j, stiffness, free_length, .. } => {
                let (bi, bj) = (state(*body_i), state(*body_j));
                let d = bj.r + bj.rotate(*s_j) - bi.r - bi.rotate(*s_i);
                0.5 * stiffness * (d.norm() - free_length).powi(2)
            }
            ForceElement::RotationalSpringDamper { body_i, body_j, stiffness, free_angle, .. } => {
                let (bi, bj) = (state(*body_i), state(*body_j));
                0.5 * stiffness * (bj.phi() - bi.phi() - free_angle).powi(2)
            }
            _ => 0.0,
        }
    }
}
