//! The model as plain data: what the user describes, in SI units and radians.
//!
//! This is the contract between the file/Python front end and the engine. It is
//! deserialised with unknown keys rejected, then checked by [`crate::system`], which
//! names the offending element in every error.

use serde::{Deserialize, Serialize};

/// The name by which joints, forces and drivers refer to the fixed frame.
pub const GROUND: &str = "ground";

/// A planar mechanism.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Model {
    /// Model name, for reports.
    #[serde(default)]
    pub name: String,
    /// Uniform gravity in the plane [m/s^2]; `[0, 0]` for a horizontal-plane mechanism.
    #[serde(default)]
    pub gravity: [f64; 2],
    /// Moving rigid bodies. The ground is implicit and named `ground`.
    #[serde(default)]
    pub bodies: Vec<Body>,
    /// Ideal joints.
    #[serde(default)]
    pub joints: Vec<Joint>,
    /// Prescribed motions of joints.
    #[serde(default)]
    pub drivers: Vec<Driver>,
    /// Force elements and applied loads.
    #[serde(default)]
    pub forces: Vec<Force>,
    /// Named points fixed in the ground frame (global coordinates) [m].
    #[serde(default)]
    pub ground_points: std::collections::BTreeMap<String, [f64; 2]>,
}

/// A rigid body in the plane; coordinates are those of its centre of mass.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Body {
    /// Unique name.
    pub name: String,
    /// Mass [kg], > 0.
    pub mass: f64,
    /// Moment of inertia about the centre of mass [kg m^2], > 0.
    pub inertia: f64,
    /// Approximate initial position of the centre of mass [m]; assembly corrects it.
    #[serde(default)]
    pub position: [f64; 2],
    /// Approximate initial angle [rad].
    #[serde(default)]
    pub angle: f64,
    /// Initial velocity of the centre of mass [m/s]; assembly makes it consistent.
    #[serde(default)]
    pub velocity: [f64; 2],
    /// Initial angular velocity [rad/s].
    #[serde(default)]
    pub omega: f64,
    /// Named points in the body frame (relative to the centre of mass) [m].
    #[serde(default)]
    pub points: std::collections::BTreeMap<String, [f64; 2]>,
    /// Optional drawing shape; the engine ignores it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape: Option<serde_json::Value>,
}

/// A point on a body: a named point of that body or a vector in its frame [m].
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum PointRef {
    /// A name from the body's `points` (or the model's `ground_points`).
    Named(String),
    /// Coordinates in the body frame (global coordinates for the ground).
    Local([f64; 2]),
}

impl Default for PointRef {
    fn default() -> Self {
        PointRef::Local([0.0, 0.0])
    }
}

/// An ideal joint between body `body_i` and body `body_j` (either may be `ground`).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Joint {
    /// Unique name.
    pub name: String,
    /// Joint kind.
    #[serde(rename = "type")]
    pub kind: JointKind,
    /// First body (reactions are reported as forces on the second body).
    pub body_i: String,
    /// Joint point on the first body.
    #[serde(default)]
    pub point_i: PointRef,
    /// Second body.
    pub body_j: String,
    /// Joint point on the second body.
    #[serde(default)]
    pub point_j: PointRef,
    /// Sliding direction of a prismatic joint in the frame of `body_i` (normalised by
    /// the engine); required for `prismatic`, rejected for the others.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axis: Option<[f64; 2]>,
}

/// The closed set of ideal joints.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum JointKind {
    /// Pin: the two points coincide (2 equations).
    Revolute,
    /// Slider: the relative angle keeps its initial value and `point_j` stays on the line
    /// through `point_i` along `axis` (2 equations).
    Prismatic,
    /// Weld: the points coincide and the relative angle keeps its initial value
    /// (3 equations).
    Fixed,
}

/// A prescribed motion of a revolute (rotation) or prismatic (translation) joint.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Driver {
    /// Unique name.
    pub name: String,
    /// The driven joint; the motor acts on its `body_j`.
    pub joint: String,
    /// Motion of the joint coordinate relative to its initial value.
    pub profile: Profile,
    /// Joint coordinate at t = 0 [rad or m]; by default the value of the approximate
    /// initial placement.
    #[serde(default)]
    pub initial: Option<f64>,
}

/// Motion profiles. Speeds are in rad/s (or m/s), times in s. Displacement is measured
/// from the joint's initial coordinate.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Profile {
    /// Constant speed from t = 0.
    ConstantSpeed {
        /// Speed.
        speed: f64,
    },
    /// Speed rises linearly from rest to `speed` over `ramp_time`, then stays constant.
    LinearRamp {
        /// Final speed.
        speed: f64,
        /// Duration of the ramp [s], > 0.
        ramp_time: f64,
    },
    /// Speed follows the cubic STEP from rest to `speed` over `ramp_time`.
    SmoothRamp {
        /// Final speed.
        speed: f64,
        /// Duration of the ramp [s], > 0.
        ramp_time: f64,
    },
    /// Tabulated displacement against time, natural cubic spline.
    TableAngle {
        /// Strictly increasing times [s], at least 2.
        time: Vec<f64>,
        /// Displacement at each time.
        value: Vec<f64>,
    },
    /// Tabulated speed against time, linear between points, displacement integrated.
    TableSpeed {
        /// Strictly increasing times [s], at least 2.
        time: Vec<f64>,
        /// Speed at each time.
        value: Vec<f64>,
    },
}

/// A value that is constant or tabulated against time (linear interpolation, held
/// constant outside the table).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum Signal<T> {
    /// Constant.
    Constant(T),
    /// Table against time.
    Table {
        /// Strictly increasing times [s].
        time: Vec<f64>,
        /// Value at each time.
        value: Vec<T>,
    },
}

/// Force elements and loads.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Force {
    /// Point-to-point spring-damper: tension `k (l - l0) + c dl/dt` along the line of the
    /// two points.
    SpringDamper {
        /// Unique name.
        name: String,
        /// First body.
        body_i: String,
        /// Attachment point on the first body.
        #[serde(default)]
        point_i: PointRef,
        /// Second body.
        body_j: String,
        /// Attachment point on the second body.
        #[serde(default)]
        point_j: PointRef,
        /// Stiffness [N/m], >= 0.
        #[serde(default)]
        stiffness: f64,
        /// Damping [N s/m], >= 0.
        #[serde(default)]
        damping: f64,
        /// Free length [m], >= 0.
        #[serde(default)]
        free_length: f64,
    },
    /// Rotational spring-damper: torque on `body_j` of
    /// `-k (phi_j - phi_i - free_angle) - c (omega_j - omega_i)`, opposite on `body_i`.
    RotationalSpringDamper {
        /// Unique name.
        name: String,
        /// First body.
        body_i: String,
        /// Second body.
        body_j: String,
        /// Stiffness [N m/rad], >= 0.
        #[serde(default)]
        stiffness: f64,
        /// Damping [N m s/rad], >= 0.
        #[serde(default)]
        damping: f64,
        /// Relative angle at which the spring is unloaded [rad].
        #[serde(default)]
        free_angle: f64,
    },
    /// A force [N] in global axes applied at a point of a body.
    AppliedForce {
        /// Unique name.
        name: String,
        /// Loaded body.
        body: String,
        /// Point of application.
        #[serde(default)]
        point: PointRef,
        /// Force vector (global axes), constant or against time.
        force: Signal<[f64; 2]>,
    },
    /// A torque [N m] (counter-clockwise positive) applied to a body.
    AppliedTorque {
        /// Unique name.
        name: String,
        /// Loaded body.
        body: String,
        /// Torque, constant or against time.
        torque: Signal<f64>,
    },
}

impl Force {
    /// The element's name.
    pub fn name(&self) -> &str {
        match self {
            Force::SpringDamper { name, .. }
            | Force::RotationalSpringDamper { name, .. }
            | Force::AppliedForce { name, .. }
            | Force::AppliedTorque { name, .. } => name,
        }
    }
}

impl Model {
    /// Parses a model from JSON (SI units), rejecting unknown keys.
    pub fn from_json(text: &str) -> Result<Model, crate::Error> {
        serde_json::from_str(text).map_err(|e| crate::Error::Model(format!("model JSON: {e}")))
    }
}
