//! A spatial model as plain data: what the user describes, in SI units and radians,
//! with 3-vectors and orientations. The contract between the front end and the spatial
//! engine, as [`crate::model::Model`] is for planar mechanisms; a model file says which
//! it is once (`dimension = 3`).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::{Clearance, Driver, Signal};

/// A spatial mechanism.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SpatialModel {
    /// Always 3: what tells a spatial model from a planar one.
    pub dimension: u8,
    /// Model name, for reports.
    #[serde(default)]
    pub name: String,
    /// Uniform gravity [m/s^2], global axes.
    #[serde(default = "default_gravity")]
    pub gravity: [f64; 3],
    /// Moving rigid bodies. The ground is implicit and named `ground`.
    #[serde(default)]
    pub bodies: Vec<Body>,
    /// Joints.
    #[serde(default)]
    pub joints: Vec<Joint>,
    /// Prescribed motions of joints (revolute, prismatic, cylindrical).
    #[serde(default)]
    pub drivers: Vec<Driver>,
    /// Force elements and applied loads.
    #[serde(default)]
    pub forces: Vec<Force>,
    /// Named points fixed in the ground frame [m].
    #[serde(default)]
    pub ground_points: BTreeMap<String, [f64; 3]>,
    /// Points whose motion the run reports as channels.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub markers: Vec<Marker>,
}

fn default_gravity() -> [f64; 3] {
    crate::defaults::GRAVITY_3D
}

/// An orientation: the rotation from a frame to the global axes (or to its body's
/// frame, for an inertia's principal frame), in one of three forms.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Orientation {
    /// Unit quaternion `(e0, e1, e2, e3)`, scalar first.
    Quaternion([f64; 4]),
    /// A turn by `angle` [rad] about `axis`.
    AxisAngle {
        /// Axis (normalised by the engine).
        axis: [f64; 3],
        /// Angle [rad].
        angle: f64,
    },
    /// Three successive turns [rad] about the axes named by `convention` (e.g. `ZYX`:
    /// yaw, pitch, roll about the turning axes).
    Euler {
        /// The axes in order, upper case for turns about the turning (body) axes.
        convention: String,
        /// The three angles [rad].
        angles: [f64; 3],
    },
}

/// A body's inertia about its centre of mass [kg m^2].
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Inertia {
    /// Principal moments, about the body frame's axes or about the axes of `frame`
    /// (the principal frame's orientation in the body frame).
    Principal {
        /// `(J1, J2, J3)`.
        moments: [f64; 3],
        /// The principal axes in the body frame; the body frame's own by default.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        frame: Option<Orientation>,
    },
    /// The full symmetric tensor in the body frame, row by row.
    Tensor([[f64; 3]; 3]),
}

/// A rigid body; its frame sits at its centre of mass.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Body {
    /// Unique name.
    pub name: String,
    /// Mass [kg], > 0.
    pub mass: f64,
    /// Inertia about the centre of mass.
    pub inertia: Inertia,
    /// Approximate initial position of the centre of mass [m]; assembly corrects it.
    #[serde(default)]
    pub position: [f64; 3],
    /// Approximate initial orientation of the body frame; unturned by default.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orientation: Option<Orientation>,
    /// Initial velocity of the centre of mass [m/s], global axes.
    #[serde(default)]
    pub velocity: [f64; 3],
    /// Initial angular velocity [rad/s], global axes.
    #[serde(default)]
    pub angular_velocity: [f64; 3],
    /// Named points in the body frame (from the centre of mass) [m].
    #[serde(default)]
    pub points: BTreeMap<String, [f64; 3]>,
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
    /// Coordinates in the body frame (global for the ground).
    Local([f64; 3]),
}

impl Default for PointRef {
    fn default() -> Self {
        PointRef::Local([0.0; 3])
    }
}

/// The kinds of spatial joint.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum JointKind {
    /// Ball joint: the points coincide (3 equations).
    Spherical,
    /// Pin: the points coincide and the axes stay parallel (5).
    Revolute,
    /// The axes stay on one line: turning about it and sliding along it are free (4).
    Cylindrical,
    /// Slider: body j slides along the axis without turning (5).
    Prismatic,
    /// Hooke's joint: the points coincide and the two cross axes stay perpendicular (4).
    Universal,
    /// Weld (6).
    Fixed,
    /// Body j's point stays in body i's plane (normal `axis`) and the two normals stay
    /// parallel (3).
    Planar,
    /// Ball joint with clearance: no constraint, a contact force element between the
    /// socket (on body i at point i) and the ball (on body j at point j).
    ClearanceSpherical,
    /// Revolute joint with radial clearance, whose journal may tilt: no constraint, a
    /// contact force element between the bearing (body i, point i, `axis`) and the
    /// journal (body j, point j, `axis_j`) of the given `length`.
    ClearanceCylindrical,
    /// Revolute joint whose angle about the axis is free within a play, then stopped by a
    /// contact torque (5 equations). See [`crate::model::Play`].
    RevoluteWithPlay,
    /// Prismatic joint whose travel along the axis is free within a play, then stopped
    /// by a contact force (5 equations). See [`crate::model::Play`].
    PrismaticWithPlay,
    /// Prismatic joint with lateral clearance: a box-shaped block (body j, point j: its
    /// centre) in a guide channel of rectangular section (body i, point i on its
    /// centreline, along `axis`, its height across `height_axis`); no constraint, a
    /// contact element at the block's eight corners.
    ClearanceTranslational,
    /// A cylindrical clearance joint carried by an oil film (`lubrication`), with the
    /// dry laws where the film is thinner than its threshold.
    LubricatedCylindrical,
}

/// A joint between body `body_i` and body `body_j` (either may be `ground`).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Joint {
    /// Unique name.
    pub name: String,
    /// Joint kind.
    #[serde(rename = "type")]
    pub kind: JointKind,
    /// First body (reactions are reported on the second).
    pub body_i: String,
    /// Joint point on the first body.
    pub point_i: PointRef,
    /// Second body.
    pub body_j: String,
    /// Joint point on the second body.
    pub point_j: PointRef,
    /// The joint's axis in the frame of body i (revolute, cylindrical, prismatic: the
    /// axis; universal: body i's cross axis; planar: the plane's normal).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axis: Option<[f64; 3]>,
    /// The axis in the frame of body j; by default the same line as `axis` at the
    /// placement (a universal joint needs it: body j's cross axis).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axis_j: Option<[f64; 3]>,
    /// A spatial translational clearance joint's height direction in the frame of body
    /// i, perpendicular to `axis`: `block_height` and `guide_width` are measured along
    /// it, `block_depth` and `guide_depth` across both.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height_axis: Option<[f64; 3]>,
    /// Contact data of a clearance joint (hole on body i, pin on body j): radii,
    /// stiffness or materials, laws; required for the clearance kinds, rejected for the
    /// others.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clearance: Option<Clearance>,
    /// The play of a `revolute_with_play` or `prismatic_with_play`; required for those.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub play: Option<crate::model::Play>,
    /// The oil film of a `lubricated_cylindrical` joint; required for it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lubrication: Option<crate::model::Lubrication>,
    /// Length of a cylindrical clearance joint's journal [m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length: Option<f64>,
    /// Axial clearance of a cylindrical clearance joint [m]: the gap on each side
    /// between the journal's ends and the bearing's thrust faces, with the journal
    /// centred; no thrust faces when not given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axial_clearance: Option<f64>,
    /// Joint coordinate at t = 0 (angle about the axis [rad] of a revolute or
    /// cylindrical joint, travel along it [m] of a prismatic one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial: Option<f64>,
    /// Its rate at t = 0 [rad/s or m/s].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial_rate: Option<f64>,
}

/// The frame a load's vector is given in.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum LoadFrame {
    /// Global axes.
    #[default]
    Ground,
    /// The loaded body's axes (the load turns with it).
    Body,
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
        /// Attachment on the first body.
        point_i: PointRef,
        /// Second body.
        body_j: String,
        /// Attachment on the second body.
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
    /// A force [N] at a point of a body.
    AppliedForce {
        /// Unique name.
        name: String,
        /// Loaded body.
        body: String,
        /// Point of application; the centre of mass by default.
        #[serde(default)]
        point: PointRef,
        /// Force vector, constant or against time.
        force: Signal<[f64; 3]>,
        /// Axes of the vector.
        #[serde(default)]
        frame: LoadFrame,
    },
    /// A torque [N m] on a body.
    AppliedTorque {
        /// Unique name.
        name: String,
        /// Loaded body.
        body: String,
        /// Torque vector, constant or against time.
        torque: Signal<[f64; 3]>,
        /// Axes of the vector.
        #[serde(default)]
        frame: LoadFrame,
    },
}

impl Force {
    /// The element's name.
    pub fn name(&self) -> &str {
        match self {
            Force::SpringDamper { name, .. }
            | Force::AppliedForce { name, .. }
            | Force::AppliedTorque { name, .. } => name,
        }
    }
}

/// A point whose position, velocity and acceleration are output channels.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Marker {
    /// Unique name.
    pub name: String,
    /// The body the point belongs to (or `ground`).
    pub body: String,
    /// The point.
    pub point: PointRef,
}

impl SpatialModel {
    /// Parses a spatial model from JSON (SI units), rejecting unknown keys.
    pub fn from_json(text: &str) -> Result<SpatialModel, crate::error::Error> {
        let model: SpatialModel =
            serde_json::from_str(text).map_err(|e| crate::error::Error::Model(format!("model JSON: {e}")))?;
        if model.dimension != 3 {
            return Err(crate::error::Error::Model(format!(
                "model: dimension = {} where a spatial model has 3",
                model.dimension
            )));
        }
        Ok(model)
    }
}
