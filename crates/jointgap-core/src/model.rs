//! The model as plain data: what the user describes, in SI units and radians.
//!
//! This is the contract between the file/Python front end and the engine. It is
//! deserialised with unknown keys rejected, then checked by [`crate::system`], which
//! names the offending element in every error.

use serde::{Deserialize, Serialize};

pub mod spatial;

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
    /// By default [`crate::defaults::GRAVITY`].
    #[serde(default = "default_gravity")]
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
    /// Points whose motion the run reports as channels.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub markers: Vec<Marker>,
}

/// A point of a body whose position, velocity and acceleration are output channels,
/// measured in the ground frame or in the frame of another body.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Marker {
    /// Unique name; the channels are `<name>.x`, `.y`, `.vx`, `.vy`, `.ax`, `.ay`.
    pub name: String,
    /// The body the point belongs to (or `ground`).
    pub body: String,
    /// The point: a named point of the body or a vector in its frame [m].
    pub point: PointRef,
    /// The body in whose frame the motion is measured; the ground by default.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frame: Option<String>,
}

/// A rigid body in the plane; coordinates are those of its centre of mass.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Body {
    /// Unique name.
    pub name: String,
    /// Mass [kg], > 0.
    pub mass: f64,
    /// Moment of inertia about the centre of mass [kg m^2], >= 0; zero (a point mass)
    /// only where the body's joints fix its rotation.
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
    /// Joint point on the first body; required, since no default can be right for it.
    pub point_i: PointRef,
    /// Second body.
    pub body_j: String,
    /// Joint point on the second body; required.
    pub point_j: PointRef,
    /// Sliding direction of a prismatic joint in the frame of `body_i` (normalised by
    /// the engine); required for `prismatic`, rejected for the others.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axis: Option<[f64; 2]>,
    /// Contact data of a `clearance_revolute` or `lubricated_revolute` (bearing on body i,
    /// journal on body j) or a `clearance_translational` (guide on body i, block on body
    /// j); required for those types. Another type warns that it ignores it, so that a
    /// joint switches kind by its `type` alone.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clearance: Option<Clearance>,
    /// The oil film of a `lubricated_revolute`; required for that type.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lubrication: Option<Lubrication>,
    /// The play of a `revolute_with_play` or `prismatic_with_play`; required for those.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub play: Option<Play>,
    /// The teeth of a `gear_pair`; required for that type.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gear: Option<Gear>,
    /// Joint coordinate at t = 0 of a revolute (relative angle `phi_j - phi_i` [rad]) or
    /// prismatic joint (travel of `point_j` from `point_i` along the axis [m]); assembly
    /// solves the other coordinates. By default free: assembly keeps it near the placement.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial: Option<f64>,
    /// Rate of that coordinate at t = 0 [rad/s or m/s]; assembly solves the other
    /// velocities. By default free.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial_rate: Option<f64>,
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
    /// Revolute joint with radial clearance: no constraint, a contact force element
    /// between the bearing (hole on body i at point i) and the journal (pin on body j at
    /// point j). See [`Clearance`].
    ClearanceRevolute,
    /// Revolute joint with clearance and an oil film: the film's force (see
    /// [`Lubrication`]) and, where the film is thinner than its threshold, the contact
    /// laws of its [`Clearance`].
    LubricatedRevolute,
    /// Slider with clearance in its guide: no constraint, a block (body j, centred at
    /// point j) between the two surfaces of a guide (body i, centreline through point i
    /// along `axis`), touching at its four corners. See [`Clearance`].
    ClearanceTranslational,
    /// Revolute joint whose relative angle is free within a play, then stopped by a
    /// contact torque (2 equations). See [`Play`].
    RevoluteWithPlay,
    /// Prismatic joint whose travel is free within a play, then stopped by a contact
    /// force (2 equations). See [`Play`].
    PrismaticWithPlay,
    /// Two gears (body i: gear 1 centred at point i; body j: gear 2 centred at point j)
    /// in mesh with backlash: no constraint, a tooth force along the line of action.
    /// Each gear turns on its own revolute joint. See [`Gear`].
    GearPair,
}

impl JointKind {
    /// The name a model gives the kind in `type`.
    pub fn type_name(self) -> &'static str {
        match self {
            JointKind::Revolute => "revolute",
            JointKind::Prismatic => "prismatic",
            JointKind::Fixed => "fixed",
            JointKind::ClearanceRevolute => "clearance_revolute",
            JointKind::LubricatedRevolute => "lubricated_revolute",
            JointKind::ClearanceTranslational => "clearance_translational",
            JointKind::RevoluteWithPlay => "revolute_with_play",
            JointKind::PrismaticWithPlay => "prismatic_with_play",
            JointKind::GearPair => "gear_pair",
        }
    }

    /// The ideal joint whose equations the kind keeps (a joint with play keeps its ideal
    /// kind's); `None` for a kind that has no equations.
    pub fn equations(self) -> Option<JointKind> {
        match self {
            JointKind::Revolute | JointKind::RevoluteWithPlay => Some(JointKind::Revolute),
            JointKind::Prismatic | JointKind::PrismaticWithPlay => Some(JointKind::Prismatic),
            JointKind::Fixed => Some(JointKind::Fixed),
            JointKind::ClearanceRevolute
            | JointKind::LubricatedRevolute
            | JointKind::ClearanceTranslational
            | JointKind::GearPair => None,
        }
    }

    /// The joint's coordinate, where it has one: `Some(true)` a relative angle (the
    /// revolute kinds), `Some(false)` a travel along the axis (the prismatic kinds).
    pub fn coordinate(self) -> Option<bool> {
        match self {
            JointKind::Revolute
            | JointKind::RevoluteWithPlay
            | JointKind::ClearanceRevolute
            | JointKind::LubricatedRevolute => Some(true),
            JointKind::Prismatic | JointKind::PrismaticWithPlay | JointKind::ClearanceTranslational => {
                Some(false)
            }
            JointKind::Fixed | JointKind::GearPair => None,
        }
    }

    /// Whether the kind takes an `axis` (a sliding direction).
    pub fn has_axis(self) -> bool {
        self.coordinate() == Some(false)
    }
}

/// Geometry, stiffness and laws of a clearance revolute joint. Give two of
/// `bearing_radius`, `journal_radius`, `clearance`; give `stiffness` or both materials.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Clearance {
    /// Radius of the hole [m].
    #[serde(default)]
    pub bearing_radius: Option<f64>,
    /// Radius of the pin [m].
    #[serde(default)]
    pub journal_radius: Option<f64>,
    /// Radial clearance `bearing_radius - journal_radius` [m], > 0.
    #[serde(default)]
    pub clearance: Option<f64>,
    /// Explicit contact stiffness K [N/m^n]; by default from the materials and radii.
    #[serde(default)]
    pub stiffness: Option<f64>,
    /// Bearing material: a library name or explicit properties.
    #[serde(default)]
    pub bearing_material: Option<MaterialRef>,
    /// Journal material: a library name or explicit properties.
    #[serde(default)]
    pub journal_material: Option<MaterialRef>,
    /// Normal contact force law.
    pub normal_law: NormalLawSpec,
    /// Tangential (friction) law; none by default.
    #[serde(default)]
    pub friction: FrictionSpec,
    /// Length of a translational clearance joint's block along the guide [m], > 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub block_length: Option<f64>,
    /// Height of the block across the guide [m]; give two of `block_height`,
    /// `guide_width` and `clearance` (then `guide_width - block_height`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub block_height: Option<f64>,
    /// Distance between the guide's two surfaces [m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub guide_width: Option<f64>,
    /// Depth of a spatial block across its channel (across the guide's axis and height
    /// direction) [m]; give two of `block_depth`, `guide_depth` and `depth_clearance`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub block_depth: Option<f64>,
    /// Distance between a spatial channel's two side walls [m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub guide_depth: Option<f64>,
    /// `guide_depth - block_depth` [m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth_clearance: Option<f64>,
    /// Length of a revolute clearance joint's bearing along its axis [m], > 0: the
    /// length of the line contact whose pressure wears the parts (docs/wear.md); needed
    /// when a run accumulates wear.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length: Option<f64>,
    /// Wear depth of a revolute clearance joint's bearing [m], >= 0, at `N >= 8` equally
    /// spaced angles `2 pi k / N` in the bearing body's frame, measured from its x axis
    /// about the joint's point: the hole's radius becomes `bearing_radius + w_B(theta)`
    /// (docs/wear.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bearing_wear: Option<Vec<f64>>,
    /// Wear depth of the journal [m], >= 0, at `N >= 8` equally spaced angles in the
    /// journal body's frame from its x axis about the joint's point: the journal's radius
    /// becomes `journal_radius - w_J(theta)`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub journal_wear: Option<Vec<f64>>,
}

/// The oil film of a lubricated revolute joint (docs/lubrication.md).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Lubrication {
    /// Bearing length along the axis [m], > 0.
    pub length: f64,
    /// Dynamic viscosity of the oil [Pa s], > 0.
    pub viscosity: f64,
    /// Film model; by default the short bearing with positive pressure only.
    #[serde(default)]
    pub film: FilmModel,
    /// Composite RMS roughness of journal and bearing [m], > 0; the film threshold is
    /// three times it. By default [`crate::defaults::FILM_ROUGHNESS`].
    #[serde(default = "default_roughness")]
    pub roughness: f64,
}

/// The play of a joint with play: its coordinate (relative angle of a revolute, travel
/// of a prismatic) is free within `centre +- play/2`, then a contact law stops it.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Play {
    /// Total free rotation [rad] or travel [m], >= 0.
    pub play: f64,
    /// Coordinate at the middle of the play [rad or m]; by default the coordinate at the
    /// model's given placement.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub centre: Option<f64>,
    /// Contact stiffness K [N m/rad^n or N/m^n], > 0.
    pub stiffness: f64,
    /// The contact law, its penetration the angle (or travel) beyond the play.
    pub normal_law: NormalLawSpec,
}

/// A gear pair's teeth (docs/gears.md).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Gear {
    /// Pitch radius of gear 2 over that of gear 1 (tooth counts z2/z1), > 0: external
    /// gears turning in opposite senses.
    pub ratio: f64,
    /// Pitch radius of gear 1 [m], > 0.
    pub pitch_radius: f64,
    /// Circumferential backlash on the pitch circle [m], >= 0.
    #[serde(default)]
    pub backlash: f64,
    /// Pressure angle [rad], in [0, 45 deg); by default
    /// [`crate::defaults::PRESSURE_ANGLE`].
    #[serde(default = "default_pressure_angle")]
    pub pressure_angle: f64,
    /// Mesh stiffness [N/m^n]: constant, or against gear 1's angle to the line of centres.
    pub mesh_stiffness: MeshStiffness,
    /// The contact law of the teeth, its penetration along the line of action.
    pub normal_law: NormalLawSpec,
}

/// A gear mesh's stiffness.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum MeshStiffness {
    /// The same at every angle [N/m^n].
    Constant(f64),
    /// Against gear 1's angle to the line of centres [rad], periodic with the table's
    /// span (its last angle minus its first), linear between points.
    Table {
        /// Strictly increasing angles [rad], at least 2.
        angle: Vec<f64>,
        /// Stiffness at each angle [N/m^n], > 0.
        value: Vec<f64>,
    },
}

/// A material from the library (by name) or given explicitly.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum MaterialRef {
    /// A name from the library (`steel`, `stainless_steel`, `brass`, ...).
    Named(String),
    /// Explicit elastic properties.
    Custom(Material),
}

/// Elastic properties of a contact material.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Young's modulus [Pa], > 0.
    pub youngs_modulus: f64,
    /// Poisson's ratio, in [0, 0.5).
    pub poisson_ratio: f64,
}

fn default_gravity() -> [f64; 2] {
    crate::defaults::GRAVITY
}
fn default_roughness() -> f64 {
    crate::defaults::FILM_ROUGHNESS
}
fn default_pressure_angle() -> f64 {
    crate::defaults::PRESSURE_ANGLE
}
fn default_exponent() -> f64 {
    crate::defaults::CONTACT_EXPONENT
}
fn default_clip() -> bool {
    crate::defaults::CONTACT_CLIP
}

/// Normal contact force laws, `F_N` as a function of penetration `delta > 0` and its
/// rate (docs/physics.md section 3). `clip` (default true) sets pulling forces to zero.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum NormalLawSpec {
    /// Hertz, elastic: `K delta^n`.
    Hertz {
        /// Exponent n (1.5 for metals).
        #[serde(default = "default_exponent")]
        exponent: f64,
    },
    /// Kelvin-Voigt: `K delta^n + c delta_dot` (n = 1 for the linear spring).
    KelvinVoigt {
        /// Exponent n.
        #[serde(default = "default_exponent")]
        exponent: f64,
        /// Damping c [N s/m].
        damping: f64,
        /// Set pulling forces to zero.
        #[serde(default = "default_clip")]
        clip: bool,
    },
    /// Hunt and Crossley (1975): `K delta^n [1 + 3(1-r)/2 delta_dot/delta_dot(-)]`.
    HuntCrossley {
        /// Exponent n.
        #[serde(default = "default_exponent")]
        exponent: f64,
        /// Coefficient of restitution r in (0, 1].
        restitution: f64,
        /// Set pulling forces to zero.
        #[serde(default = "default_clip")]
        clip: bool,
    },
    /// Lankarani and Nikravesh (1990): `K delta^n [1 + 3(1-r^2)/4 delta_dot/delta_dot(-)]`.
    LankaraniNikravesh {
        /// Exponent n.
        #[serde(default = "default_exponent")]
        exponent: f64,
        /// Coefficient of restitution r in (0, 1].
        restitution: f64,
        /// Set pulling forces to zero.
        #[serde(default = "default_clip")]
        clip: bool,
    },
    /// Gonthier et al. (2004): `K delta^n [1 + (1-r^2)/r delta_dot/delta_dot(-)]`.
    Gonthier {
        /// Exponent n.
        #[serde(default = "default_exponent")]
        exponent: f64,
        /// Coefficient of restitution r in (0, 1].
        restitution: f64,
        /// Set pulling forces to zero.
        #[serde(default = "default_clip")]
        clip: bool,
    },
    /// Flores et al. (2011): `K delta^n [1 + 8(1-r)/(5r) delta_dot/delta_dot(-)]`.
    Flores {
        /// Exponent n.
        #[serde(default = "default_exponent")]
        exponent: f64,
        /// Coefficient of restitution r in (0, 1].
        restitution: f64,
        /// Set pulling forces to zero.
        #[serde(default = "default_clip")]
        clip: bool,
    },
    /// ADAMS IMPACT: `K delta^n + STEP(delta, 0, 0, d_max, c_max) delta_dot`.
    AdamsImpact {
        /// Exponent n.
        #[serde(default = "default_exponent")]
        exponent: f64,
        /// Full damping coefficient c_max [N s/m], >= 0.
        c_max: f64,
        /// Penetration at which damping is full, d_max [m], > 0; by default the
        /// bearing material's typical value from the library.
        #[serde(default)]
        d_max: Option<f64>,
        /// Set pulling forces to zero (ADAMS does).
        #[serde(default = "default_clip")]
        clip: bool,
    },
}

/// Friction laws: the tangential force opposes the slip `v_t` (docs/physics.md section 4).
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum FrictionSpec {
    /// Frictionless.
    #[default]
    None,
    /// ADAMS / SolidWorks-Motion Coulomb with static and dynamic coefficients blended by
    /// STEP functions between the transition speeds `v_s < v_d` [m/s].
    Coulomb {
        /// Static coefficient.
        mu_s: f64,
        /// Dynamic coefficient.
        mu_d: f64,
        /// Stiction transition speed [m/s].
        v_s: f64,
        /// Friction transition speed [m/s].
        v_d: f64,
    },
    /// Ambrosio (2003): `mu c_d(|v_t|)` with `c_d` 0 below `v_0`, linear to 1 at `v_1`.
    ModifiedCoulomb {
        /// Friction coefficient.
        mu: f64,
        /// Speed below which there is no friction [m/s].
        v_0: f64,
        /// Speed from which friction is full [m/s].
        v_1: f64,
    },
    /// `mu F_N tanh(v_t / v_s) + viscous v_t`.
    ViscousCoulomb {
        /// Friction coefficient.
        mu: f64,
        /// Regularisation speed [m/s].
        v_s: f64,
        /// Viscous coefficient [N s/m].
        viscous: f64,
    },
}

/// Fluid-film model of a lubricated journal bearing: how the Reynolds equation is
/// simplified and over which part of the film its pressure is taken (docs/lubrication.md).
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum FilmModel {
    /// Short bearing (Ocvirk: the axial pressure flow dominates, for L/D below about
    /// 0.5) with half-Sommerfeld (Gumbel) cavitation in its exact form: only the positive
    /// pressure acts, over the half of the film that the squeeze and wedge motions place.
    #[default]
    Short,
    /// Long bearing (Sommerfeld: the circumferential flow dominates, for L/D above about
    /// 2) with Gumbel cavitation: the pressure, zero at the widest film, acts where it is
    /// positive.
    Long,
    /// Short bearing with the pressure taken over a fixed half of the film (the
    /// "pi-film" of Pinkus & Sternlicht 1961 used by Flores et al., Mech. Mach. Theory
    /// 41 (2006) 247), for reproducing papers: it keeps negative pressure.
    ShortPi,
    /// Long bearing with the pressure taken over the same fixed half of the film as
    /// [`FilmModel::ShortPi`], for reproducing papers.
    LongPi,
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
    /// Joint coordinate from which the profile's displacement is measured [rad or m];
    /// by default its value at the approximate initial placement. The coordinate at
    /// t = 0 is this plus the profile's displacement at t = 0 (zero for the ramps).
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
        /// Attachment point on the first body; required.
        point_i: PointRef,
        /// Second body.
        body_j: String,
        /// Attachment point on the second body; required.
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
        /// Point of application; by default the centre of mass.
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
    pub fn from_json(text: &str) -> Result<Model, crate::error::Error> {
        serde_json::from_str(text).map_err(|e| crate::error::Error::Model(format!("model JSON: {e}")))
    }
}
