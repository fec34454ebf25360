//! Models shared by the engine's integration tests, written inline as JSON.
#![allow(dead_code)]

use jointgap_core::Model;
use serde_json::{json, Value};

pub const R: f64 = 0.08;
pub const L: f64 = 0.32;
pub const W: f64 = 300.0 * 2.0 * std::f64::consts::PI / 60.0;
pub const T_RAMP: f64 = 0.2;

/// The founding slider-crank with ideal joints (docs/physics.md section 5).
pub fn slider_crank(gravity: f64) -> Model {
    Model::from_json(
        &json!({
            "name": "slider_crank",
            "gravity": [0.0, -gravity],
            "bodies": [
                {"name": "crank", "mass": 2.37, "inertia": 0.01201, "position": [R / 2.0, 0.0],
                 "points": {"O": [-R / 2.0, 0.0], "A": [R / 2.0, 0.0]}},
                {"name": "rod", "mass": 0.72, "inertia": 0.0006926, "position": [R + L / 2.0, 0.0],
                 "points": {"A": [-L / 2.0, 0.0], "B": [L / 2.0, 0.0]}},
                {"name": "slider", "mass": 2.28, "inertia": 0.001, "position": [R + L, 0.0]}
            ],
            "joints": [
                {"name": "ground_crank", "type": "revolute", "body_i": "ground", "point_i": [0.0, 0.0], "body_j": "crank", "point_j": "O"},
                {"name": "crank_rod", "type": "revolute", "body_i": "crank", "point_i": "A", "body_j": "rod", "point_j": "A"},
                {"name": "rod_slider", "type": "revolute", "body_i": "slider", "point_i": [0.0, 0.0], "body_j": "rod", "point_j": "B"},
                {"name": "slider_guide", "type": "prismatic", "body_i": "ground", "point_i": [0.0, 0.0], "body_j": "slider", "point_j": [0.0, 0.0], "axis": [1.0, 0.0]}
            ],
            "drivers": [
                {"name": "motor", "joint": "ground_crank",
                 "profile": {"type": "linear_ramp", "speed": W, "ramp_time": T_RAMP}}
            ]
        })
        .to_string(),
    )
    .unwrap()
}

/// The founding slider-crank with the rod-slider joint a clearance joint (docs/physics.md
/// section 5: 0.5 mm radial clearance, ADAMS impact law, ADAMS Coulomb friction).
pub fn slider_crank_clearance() -> Model {
    let mut raw = serde_json::to_value(slider_crank(9.81)).unwrap();
    let joints = raw["joints"].as_array_mut().unwrap();
    let k = joints.iter().position(|j| j["name"] == "rod_slider").unwrap();
    joints[k] = json!({
        "name": "rod_slider", "type": "clearance_revolute", "body_i": "slider", "point_i": [0.0, 0.0], "body_j": "rod",
        "point_j": "B",
        "clearance": {"bearing_radius": 7.5e-3, "clearance": 0.5e-3,
                      "bearing_material": {"youngs_modulus": 97e9, "poisson_ratio": 0.3},
                      "journal_material": {"youngs_modulus": 207e9, "poisson_ratio": 0.3},
                      "normal_law": {"type": "adams_impact", "exponent": 1.5, "c_max": 27960.0,
                                     "d_max": 1e-5},
                      "friction": {"type": "coulomb", "mu_s": 0.08, "mu_d": 0.05, "v_s": 1e-4,
                                   "v_d": 0.01016}}
    });
    serde_json::from_value(raw).unwrap()
}

/// Crank angle and its derivatives for the ramp.
pub fn crank(t: f64) -> (f64, f64, f64) {
    if t < T_RAMP {
        (0.5 * W * t * t / T_RAMP, W * t / T_RAMP, W / T_RAMP)
    } else {
        (0.5 * W * T_RAMP + W * (t - T_RAMP), W, 0.0)
    }
}

/// Closed-form slider position, velocity and acceleration (docs/physics.md section 6).
pub fn slider_closed_form(t: f64) -> (f64, f64, f64) {
    let (th, w, al) = crank(t);
    let (s, c) = th.sin_cos();
    let root = (L * L - R * R * s * s).sqrt();
    let x = R * c + root;
    let dx = -R * s - R * R * s * c / root; // dx/dtheta
    let d2x = -R * c - R * R * (c * c - s * s) / root - R.powi(4) * s * s * c * c / root.powi(3);
    (x, dx * w, d2x * w * w + dx * al)
}

/// The spatial four-bar (RSSR) of examples/spatial_four_bar_clearance.toml: a driven
/// crank about z, a rocker about x, and a coupler between a ball joint and a ball in its
/// socket with 0.1 mm clearance (Lankarani-Nikravesh contact and Coulomb friction).
pub fn spatial_four_bar_clearance() -> Value {
    json!({
        "dimension": 3, "name": "spatial_four_bar_clearance", "gravity": [0.0, 0.0, -9.81],
        "bodies": [
            {"name": "crank", "mass": 0.157, "inertia": {"principal": {"moments": [6.5e-06, 0.000132, 0.000136]}},
             "position": [0.05, 0.0, 0.0], "points": {"O": [-0.05, 0.0, 0.0], "A": [0.05, 0.0, 0.0]}},
            {"name": "coupler", "mass": 0.628,
             "inertia": {"principal": {"moments": [2.6e-05, 0.00837, 0.00839],
                         "frame": {"axis_angle": {"axis": [0.0, -0.625, 0.73951], "angle": 1.3181162843374175}}}},
             "position": [0.15, 0.147902, 0.125],
             "points": {"A": [-0.05, -0.147902, -0.125], "B": [0.05, 0.147902, 0.125]}},
            {"name": "rocker", "mass": 0.471, "inertia": {"principal": {"moments": [2e-05, 0.00353, 0.00355]}},
             "position": [0.2, 0.147902, 0.225],
             "orientation": {"euler": {"convention": "XYZ", "angles": [0.16744807526022734, 0.0, std::f64::consts::FRAC_PI_2]}},
             "points": {"D": [-0.15, 0.0, 0.0], "B": [0.15, 0.0, 0.0]}}
        ],
        "joints": [
            {"name": "ground_crank", "type": "revolute", "body_i": "ground", "point_i": "O", "body_j": "crank",
             "point_j": "O", "axis": [0.0, 0.0, 1.0]},
            {"name": "crank_coupler", "type": "spherical", "body_i": "crank", "point_i": "A", "body_j": "coupler",
             "point_j": "A"},
            {"name": "coupler_rocker", "type": "clearance_spherical", "body_i": "rocker", "point_i": "B",
             "body_j": "coupler", "point_j": "B",
             "clearance": {"bearing_radius": 0.01, "clearance": 0.0001, "bearing_material": "steel",
                           "journal_material": "steel",
                           "normal_law": {"type": "lankarani_nikravesh", "exponent": 1.5, "restitution": 0.9, "clip": true},
                           "friction": {"type": "coulomb", "mu_s": 0.1, "mu_d": 0.08, "v_s": 0.0001, "v_d": 0.01}}},
            {"name": "ground_rocker", "type": "revolute", "body_i": "ground", "point_i": "D", "body_j": "rocker",
             "point_j": "D", "axis": [1.0, 0.0, 0.0]}
        ],
        "drivers": [{"name": "motor", "joint": "ground_crank", "profile": {"type": "constant_speed", "speed": std::f64::consts::TAU}}],
        "ground_points": {"O": [0.0, 0.0, 0.0], "D": [0.2, 0.0, 0.2]}
    })
}
