//! Applied forces on spatial bodies: point-to-point spring-dampers and prescribed force
//! and torque vectors (constant or tabulated, in global axes or turning with the body),
//! as generalized forces on `(v, w')`, and their power and stored energy. Gravity is the
//! system's and the gyroscopic moment the body kind's.

use nalgebra::Vector3;

use super::body::{self, constant, BodyState, Vec3};
use crate::error::{Error, Named};
use crate::mechanics::forces::{non_negative, TimeTable};
use crate::mechanics::kind::ForceLaw;
use crate::mechanics::layout::Loads;
use crate::mechanics::resolve::Resolver;
use crate::model::spatial::{Force, LoadFrame, PointRef};
use crate::scalar::{norm, Real};

/// A checked spatial force element; bodies are `None` for the ground.
#[derive(Debug, Clone)]
pub enum SpatialForce {
    /// Tension `k (l - l0) + c dl/dt` along the line from point i to point j.
    SpringDamper {
        /// Name.
        name: String,
        /// Body i.
        body_i: Option<usize>,
        /// Point on body i, body frame [m].
        s_i: Vec3,
        /// Body j.
        body_j: Option<usize>,
        /// Point on body j, body frame [m].
        s_j: Vec3,
        /// Stiffness [N/m].
        stiffness: f64,
        /// Damping [N s/m].
        damping: f64,
        /// Free length [m].
        free_length: f64,
    },
    /// A force at a point of a body.
    AppliedForce {
        /// Name.
        name: String,
        /// Loaded body.
        body: Option<usize>,
        /// Point of application, body frame [m].
        s: Vec3,
        /// The force [N] against time.
        force: TimeTable<3>,
        /// Axes the force is given in.
        frame: LoadFrame,
    },
    /// A torque on a body.
    AppliedTorque {
        /// Name.
        name: String,
        /// Loaded body.
        body: Option<usize>,
        /// The torque [N m] against time.
        torque: TimeTable<3>,
        /// Axes the torque is given in.
        frame: LoadFrame,
    },
}

/// A spatial point of the model, resolved on `body`.
pub(crate) fn point(
    res: &Resolver<'_, 3>,
    who: Named,
    field: &str,
    body: Option<usize>,
    p: &PointRef,
) -> Result<Vec3, Error> {
    let v = match p {
        PointRef::Local(v) => res.coordinates(who, field, *v)?,
        PointRef::Named(n) => res.named(who, field, body, n)?,
    };
    Ok(Vec3::from(v))
}

/// Unit vector, the line and its length and rate between point i and point j; `None`
/// when they coincide (no direction).
fn line<T: Real>(bi: &BodyState<T>, s_i: &Vec3, bj: &BodyState<T>, s_j: &Vec3) -> Option<(Vector3<T>, T, T)> {
    let (s_i, s_j) = (constant(s_i), constant(s_j));
    let d = bj.r + bj.rotate(&s_j) - bi.r - bi.rotate(&s_i);
    let length = norm(&d);
    if length < 1e-12 {
        return None;
    }
    let u = d / length;
    Some((u, length, u.dot(&(bj.point_velocity(&s_j) - bi.point_velocity(&s_i)))))
}

/// A vector given in `frame`, in global axes.
fn global<T: Real>(state: &BodyState<T>, frame: LoadFrame, x: [T; 3]) -> Vector3<T> {
    match frame {
        LoadFrame::Ground => Vector3::from(x),
        LoadFrame::Body => state.rotate(&Vector3::from(x)),
    }
}

/// Adds force `f` (global) at body-frame point `s` of body `b`.
fn add_point_force<T: Real>(
    loads: &mut Loads<T>,
    b: Option<usize>,
    state: &BodyState<T>,
    s: &Vec3,
    f: &Vector3<T>,
) {
    if let Some(qe) = loads.body(b) {
        body::add_force(qe, state, &state.rotate(&constant(s)), f);
    }
}

impl SpatialForce {
    pub(crate) fn new(f: &Force, res: &Resolver<'_, 3>) -> Result<Self, Error> {
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
                SpatialForce::SpringDamper {
                    name: name.clone(),
                    body_i: bi,
                    s_i: point(res, who, "point_i", bi, point_i)?,
                    body_j: bj,
                    s_j: point(res, who, "point_j", bj, point_j)?,
                    stiffness: non_negative(who, "stiffness", "N/m", *stiffness)?,
                    damping: non_negative(who, "damping", "N s/m", *damping)?,
                    free_length: non_negative(who, "free_length", "m", *free_length)?,
                }
            }
            Force::AppliedForce { name, body, point: p, force, frame } => {
                let b = res.body(who, "body", body)?;
                SpatialForce::AppliedForce {
                    name: name.clone(),
                    body: b,
                    s: point(res, who, "point", b, p)?,
                    force: TimeTable::from_signal(who, "force", force)?,
                    frame: *frame,
                }
            }
            Force::AppliedTorque { name, body, torque, frame } => SpatialForce::AppliedTorque {
                name: name.clone(),
                body: res.body(who, "body", body)?,
                torque: TimeTable::from_signal(who, "torque", torque)?,
                frame: *frame,
            },
        })
    }
}

impl SpatialForce {
    /// The table value of an applied force or torque at time `t` (zero for a
    /// spring-damper).
    pub fn applied_at(&self, t: f64) -> [f64; 3] {
        match self {
            SpatialForce::AppliedForce { force, .. } => force.at(t),
            SpatialForce::AppliedTorque { torque, .. } => torque.at(t),
            SpatialForce::SpringDamper { .. } => [0.0; 3],
        }
    }

    /// Adds this element's generalised forces to the loads, in any number type, the
    /// bodies' states given by `state` and an applied load's table value by `applied`
    /// ([`Self::applied_at`]).
    pub fn add_loads<T: Real>(
        &self,
        applied: [T; 3],
        state: impl Fn(Option<usize>) -> BodyState<T>,
        qe: &mut Loads<T>,
    ) {
        match self {
            SpatialForce::SpringDamper {
                body_i, s_i, body_j, s_j, stiffness, damping, free_length, ..
            } => {
                let (bi, bj) = (state(*body_i), state(*body_j));
                let Some((u, length, rate)) = line(&bi, s_i, &bj, s_j) else {
                    return;
                };
                let tension = (length - *free_length) * *stiffness + rate * *damping;
                add_point_force(qe, *body_i, &bi, s_i, &(u * tension));
                add_point_force(qe, *body_j, &bj, s_j, &(-u * tension));
            }
            SpatialForce::AppliedForce { body, s, frame, .. } => {
                let b = state(*body);
                add_point_force(qe, *body, &b, s, &global(&b, *frame, applied));
            }
            SpatialForce::AppliedTorque { body, frame, .. } => {
                let b = state(*body);
                if let Some(qe) = qe.body(*body) {
                    body::add_torque(qe, &b, &global(&b, *frame, applied));
                }
            }
        }
    }
}

impl ForceLaw<BodyState> for SpatialForce {
    fn corners(&self) -> Vec<f64> {
        match self {
            SpatialForce::AppliedForce { force, .. } => force.times().to_vec(),
            SpatialForce::AppliedTorque { torque, .. } => torque.times().to_vec(),
            SpatialForce::SpringDamper { .. } => vec![],
        }
    }

    fn add_to(&self, t: f64, state: impl Fn(Option<usize>) -> BodyState, qe: &mut Loads) {
        self.add_loads(self.applied_at(t), state, qe);
    }

    fn power(&self, t: f64, state: impl Fn(Option<usize>) -> BodyState) -> (f64, f64) {
        match self {
            SpatialForce::SpringDamper { body_i, s_i, body_j, s_j, damping, .. } => {
                match line(&state(*body_i), s_i, &state(*body_j), s_j) {
                    Some((_, _, rate)) => (0.0, damping * rate * rate),
                    None => (0.0, 0.0),
                }
            }
            SpatialForce::AppliedForce { body, s, force, frame, .. } => {
                let b = state(*body);
                (global(&b, *frame, force.at(t)).dot(&b.point_velocity(s)), 0.0)
            }
            SpatialForce::AppliedTorque { body, torque, frame, .. } => {
                let b = state(*body);
                (global(&b, *frame, torque.at(t)).dot(&b.omega_global()), 0.0)
            }
        }
    }

    fn potential_energy(&self, state: impl Fn(Option<usize>) -> BodyState) -> f64 {
        match self {
            SpatialForce::SpringDamper { body_i, s_i, body_j, s_j, stiffness, free_length, .. } => {
                let (bi, bj) = (state(*body_i), state(*body_j));
                let d = bj.r + bj.rotate(s_j) - bi.r - bi.rotate(s_i);
                0.5 * stiffness * (d.norm() - free_length).powi(2)
            }
            _ => 0.0,
        }
    }
}
