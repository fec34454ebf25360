//! What a model leaves out means, written once here; `simulate::all_defaults` hands these
//! and the run options' defaults to the front ends as data, so that the Python package
//! asks the binding for them and repeats none.

/// Uniform gravity of a model that gives none [m/s^2]: a vertical plane with y up, as a
/// model file without `gravity` has always meant.
pub const GRAVITY: [f64; 2] = [0.0, -9.81];

/// Uniform gravity of a spatial model that gives none [m/s^2]: z up.
pub const GRAVITY_3D: [f64; 3] = [0.0, 0.0, -9.81];

/// Exponent n of a normal contact law that gives none: Hertz's 3/2 of two elastic bodies
/// in contact, the value for metal contacts (docs/physics.md section 3).
pub const CONTACT_EXPONENT: f64 = 1.5;

/// Whether a normal contact law that does not say sets pulling forces to zero.
pub const CONTACT_CLIP: bool = true;

/// Composite RMS roughness of a lubricated joint's journal and bearing that gives none
/// [m]: a ground journal in a bored or honed bush (about 0.5 and 1 um each). The film
/// threshold is three times it (docs/lubrication.md).
pub const FILM_ROUGHNESS: f64 = 1e-6;

/// Pressure angle of a gear pair that gives none [rad]: the standard 20 degrees.
pub const PRESSURE_ANGLE: f64 = 20.0 * std::f64::consts::PI / 180.0;
