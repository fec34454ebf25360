//! Every engine error about an element is built in parts where it is found: a valid
//! model broken one value at a time gives an error whose category, element kind, name
//! and key are those of the value (the key as the model file writes it, dotted for a
//! nested one), and whose message is the one the docs and front ends quote.

use crate::common;

use jointgap_core::simulate::{check, prepare};
use jointgap_core::{simulate, Error, Model, SimOptions};
use serde_json::{json, Value};

/// The founding clearance slider-crank with a spring, a tabulated torque and a marker:
/// one element of each kind.
fn base() -> Value {
    let mut raw = serde_json::to_value(common::slider_crank_clearance()).unwrap();
    raw["forces"] = json!([
        {"type": "spring_damper", "name": "spring", "body_i": "ground", "point_i": [0.0, 0.0],
         "body_j": "rod", "point_j": "A", "stiffness": 10.0, "damping": 0.1, "free_length": 0.1},
        {"type": "applied_torque", "name": "load", "body": "crank",
         "torque": {"time": [0.0, 0.1], "value": [0.0, 1.0]}}
    ]);
    raw["markers"] = json!([{"name": "tip", "body": "rod", "point": "B"}]);
    raw
}

/// The base model with the value at JSON `pointer` replaced (or added).
fn broken(pointer: &str, value: Value) -> Model {
    let mut raw = base();
    let (parent, last) = pointer.rsplit_once('/').unwrap();
    let target = raw.pointer_mut(parent).unwrap_or_else(|| panic!("no {parent}"));
    match target {
        Value::Array(items) => items[last.parse::<usize>().unwrap()] = value,
        Value::Object(map) => {
            map.insert(last.to_string(), value);
        }
        _ => panic!("{parent} holds no values"),
    }
    serde_json::from_value(raw).unwrap()
}

/// The error of checking `model` (compiled, assembled, its first sample taken).
fn error_of(model: &Model) -> Error {
    match check(model) {
        Ok(_) => panic!("expected an error"),
        Err(e) => e,
    }
}

/// `(category, kind, element, key)` of an error.
type Parts = (&'static str, Option<&'static str>, Option<String>, Option<String>);

/// The [`Parts`] of an error, and its message.
fn parts_of(e: &Error) -> (Parts, String) {
    let p = e.parts();
    ((p.category, p.kind, p.element, p.key), e.to_string())
}

#[test]
fn the_base_model_is_valid() {
    let model: Model = serde_json::from_value(base()).unwrap();
    assert!(prepare(&model).is_ok());
}

#[test]
fn each_broken_value_is_named_by_its_element_and_key() {
    let bodies = "bodies: ground, crank, rod, slider";
    let no_body_j = format!("joint 'ground_crank': body_j 'nothing' is not a body of the model ({bodies})");
    let no_frame = format!("marker 'tip': frame 'nowhere' is not a body of the model ({bodies})");
    let cases: Vec<(&str, Value, &str, &str, &str, &str)> = vec![
        // (pointer, value, kind, element, key, message)
        ("/bodies/0/mass", json!(0.0), "body", "crank", "mass", "body 'crank': mass = 0 kg must be positive"),
        (
            "/bodies/1/inertia",
            json!(-1.0),
            "body",
            "rod",
            "inertia",
            "body 'rod': inertia = -1 kg m^2 must not be negative",
        ),
        ("/bodies/2/name", json!("ground"), "body", "ground", "name", "body 'ground': the name 'ground' is reserved"),
        (
            "/bodies/0/mass",
            json!(1e308),
            "body",
            "crank",
            "mass",
            "body 'crank': mass = 1e308 kg: its weight m |g| = inf N overflows the floating-point range \
             (about 1.8e308); check the value and its unit",
        ),
        (
            "/joints/0/body_j",
            json!("nothing"),
            "joint",
            "ground_crank",
            "body_j",
            &no_body_j,
        ),
        (
            "/joints/1/point_i",
            json!("Z"),
            "joint",
            "crank_rod",
            "point_i",
            "joint 'crank_rod': point_i 'Z' is not a point of body 'crank' (points: A, O)",
        ),
        ("/joints/1/body_j", json!("crank"), "joint", "crank_rod", "body_j", "joint 'crank_rod': connects body 'crank' to itself"),
        (
            "/joints/3/axis",
            json!([0.0, 0.0]),
            "joint",
            "slider_guide",
            "axis",
            "joint 'slider_guide': axis [0.0, 0.0] must be a non-zero vector",
        ),
        (
            "/joints/0/initial",
            json!(0.1),
            "joint",
            "ground_crank",
            "initial",
            "joint 'ground_crank': initial and initial_rate cannot be given for a driven joint (driver 'motor' \
             sets its motion): give its coordinate at t = 0 as the driver's initial",
        ),
        (
            "/joints/2/clearance/clearance",
            json!(-1.0),
            "joint",
            "rod_slider",
            "clearance",
            "joint 'rod_slider': clearance = -1 m must be positive",
        ),
        (
            "/joints/2/clearance/bearing_material/poisson_ratio",
            json!(0.6),
            "joint",
            "rod_slider",
            "bearing_material.poisson_ratio",
            "joint 'rod_slider': bearing_material poisson_ratio = 0.6 must lie in [0, 0.5)",
        ),
        (
            "/joints/2/clearance/journal_material",
            json!("unobtainium"),
            "joint",
            "rod_slider",
            "journal_material",
            "joint 'rod_slider': journal_material 'unobtainium' is not in the material library (steel, \
             stainless_steel, brass, bronze, aluminium_alloy, cast_iron, titanium_alloy)",
        ),
        (
            "/joints/2/clearance/normal_law/c_max",
            json!(-1.0),
            "joint",
            "rod_slider",
            "normal_law.c_max",
            "joint 'rod_slider': c_max = -1 N s/m must be zero or positive",
        ),
        (
            "/joints/2/clearance/friction/mu_s",
            json!(-0.1),
            "joint",
            "rod_slider",
            "friction.mu_s",
            "joint 'rod_slider': friction mu_s = -0.1 must be zero or positive",
        ),
        (
            "/drivers/0/profile/ramp_time",
            json!(0.0),
            "driver",
            "motor",
            "profile.ramp_time",
            "driver 'motor': ramp_time = 0 s must be positive",
        ),
        (
            "/drivers/0/joint",
            json!("rod_slider"),
            "driver",
            "motor",
            "joint",
            "driver 'motor': joint 'rod_slider' is a clearance_revolute joint; only revolute and prismatic \
             joints can be driven",
        ),
        (
            "/forces/0/damping",
            json!(-1.0),
            "force",
            "spring",
            "damping",
            "force 'spring': damping = -1 N s/m must be zero or positive",
        ),
        (
            "/forces/1/torque",
            json!({"time": [0.0, 0.1, 0.1], "value": [0.0, 1.0, 2.0]}),
            "force",
            "load",
            "torque.time",
            "force 'load': table times must increase strictly (time[1] = 0.1 then 0.1)",
        ),
        (
            "/markers/0/frame",
            json!("nowhere"),
            "marker",
            "tip",
            "frame",
            &no_frame,
        ),
    ];
    for (pointer, value, kind, element, key, message) in cases {
        let (parts, text) = parts_of(&error_of(&broken(pointer, value)));
        assert_eq!(
            parts,
            ("model", Some(kind), Some(element.to_string()), Some(key.to_string())),
            "{pointer}: {text}"
        );
        assert_eq!(text, message, "{pointer}");
    }
}

#[test]
fn assembly_errors_name_their_element_and_key() {
    // A weld of the crank to the ground leaves its driver nothing to move.
    let mut joints = base()["joints"].clone();
    joints.as_array_mut().unwrap().push(json!(
        {"name": "weld", "type": "fixed", "body_i": "ground", "point_i": [0.0, 0.0], "body_j": "crank", "point_j": "O"}
    ));
    let (parts, text) = parts_of(&error_of(&broken("/joints", joints)));
    assert_eq!(parts, ("assembly", Some("driver"), Some("motor".into()), Some("joint".into())));
    assert_eq!(text, "driver 'motor': the driven joint cannot move, the other constraints already fix it");

    // The crank angle fixes the crank-rod joint's coordinate.
    let mut raw: Value = serde_json::to_value(common::slider_crank(9.81)).unwrap();
    raw["joints"][1]["initial"] = json!(0.5);
    let (parts, text) = parts_of(&error_of(&serde_json::from_value(raw).unwrap()));
    assert_eq!(parts, ("assembly", Some("joint"), Some("crank_rod".into()), Some("initial".into())));
    assert_eq!(
        text,
        "joint 'crank_rod': the joints, drivers and the other initial conditions already fix this joint's \
         coordinate; leave its initial value and rate out"
    );
}

#[test]
fn an_error_of_the_whole_model_names_no_element_and_an_option_names_its_key() {
    let (parts, text) = parts_of(&error_of(&broken("/bodies", json!([]))));
    assert_eq!(parts, ("model", None, None, None));
    assert!(text.starts_with("the model has no bodies"), "{text}");

    let model: Model = serde_json::from_value(base()).unwrap();
    let options = |change: &dyn Fn(&mut SimOptions)| {
        let mut o = SimOptions::new(0.01);
        change(&mut o);
        match simulate(&model, &o) {
            Ok(_) => panic!("expected an options error"),
            Err(e) => e,
        }
    };
    let (parts, text) = parts_of(&options(&|o| o.rtol = 2.0));
    assert_eq!(parts, ("options", None, None, Some("rtol".into())));
    assert_eq!(text, "option rtol = 2: must lie in (0, 1)");
    let (parts, text) = parts_of(&options(&|o| o.channels = Some(vec!["nowhere.x".into()])));
    assert_eq!(parts, ("options", None, None, Some("channels".into())));
    assert_eq!(text, "channel 'nowhere.x' is not an output of this model");
}
