//! Wear in revolute clearance joints (docs/wear.md): the worn profile as the contact's
//! geometry, and the Archard wear a run accumulates.

use crate::common;

use jointgap_core::simulate::check;
use jointgap_core::{simulate, Model, SimOptions, SimResult};
use serde_json::{json, Value};

/// The founding clearance slider-crank with the rod-slider joint's `clearance` entries
/// replaced by `entries`, and an explicit stiffness (that of the founding case's
/// materials and radii), so that a change of radii leaves the law as it is.
fn founding_with(entries: Value) -> Model {
    let mut raw = serde_json::to_value(common::slider_crank_clearance()).unwrap();
    let joints = raw["joints"].as_array_mut().unwrap();
    let joint = joints.iter_mut().find(|j| j["name"] == "rod_slider").unwrap();
    let c = joint["clearance"].as_object_mut().unwrap();
    c.remove("bearing_material");
    c.remove("journal_material");
    c.insert("stiffness".into(), json!(3.136e10));
    for (k, v) in entries.as_object().unwrap() {
        c.insert(k.clone(), v.clone());
    }
    serde_json::from_value(raw).unwrap()
}

fn run(model: &Model, opts: &SimOptions) -> SimResult {
    let res = simulate(model, opts).unwrap();
    assert_eq!(res.status, jointgap_core::output::Status::Finished);
    res
}

/// A circular profile given as data, a constant wear `w_B` of the bearing and `w_J` of
/// the journal, runs as the round joint of radii `R_B + w_B`, `R_J - w_J` (clearance `c
/// + w_B + w_J`): the same impacts and forces through 0.25 s of the founding case, which
/// covers its first impacts and a stretch of continuous contact. The two differ by
/// rounding alone (the worn contact finds its normal by an angle), which the impacts
/// amplify to the integrator's tolerance: 3.5e-6 of the peak force at rtol 1e-9, below
/// 1e-6 at 1e-11.
#[test]
fn circular_profile_as_data_is_the_round_joint() {
    let (wb, wj) = (4e-5, 1.5e-5);
    let worn = founding_with(json!({"bearing_wear": vec![wb; 24], "journal_wear": vec![wj; 16]}));
    let round = founding_with(json!({"bearing_radius": 7.5e-3 + wb, "clearance": 0.5e-3 + wb + wj}));
    let opts = SimOptions { rate: Some(2000.0), rtol: 1e-11, atol: 1e-14, ..SimOptions::new(0.25) };
    let (a, b) = (run(&worn, &opts), run(&round, &opts));
    assert_eq!(a.impacts[0].impacts.len(), b.impacts[0].impacts.len());
    assert!(a.impacts[0].impacts.len() > 3, "{}", a.impacts[0].impacts.len());
    for name in ["rod_slider.fn", "rod_slider.penetration", "slider.ax"] {
        let (x, y) = (a.channel(name).unwrap(), b.channel(name).unwrap());
        let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let worst = x.iter().zip(y).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(worst < 1e-6 * scale, "{name}: differs by {worst:e} of {scale:e}");
    }
}

/// Bad wear data is an error naming the joint and the key: a negative or NaN depth, too
/// few points, a table on a joint kind that does not take it, a bad length.
#[test]
fn bad_wear_data_names_the_joint_and_key() {
    let cases: Vec<(Model, &str, &str)> = vec![
        (
            founding_with(json!({"bearing_wear": [0.0, 0.0, -1e-6, 0.0, 0.0, 0.0, 0.0, 0.0]})),
            "bearing_wear",
            "bearing_wear[2] = -0.000001 m",
        ),
        (founding_with(json!({"journal_wear": vec![0.0; 7]})), "journal_wear", "at least 8"),
        (founding_with(json!({"length": -0.01})), "length", "positive"),
        (
            {
                let mut raw =
                    serde_json::to_value(founding_with(json!({"bearing_wear": vec![1e-6; 8]}))).unwrap();
                let joint = raw["joints"]
                    .as_array_mut()
                    .unwrap()
                    .iter_mut()
                    .find(|j| j["name"] == "rod_slider")
                    .unwrap();
                joint["type"] = json!("lubricated_revolute");
                joint["lubrication"] = json!({"length": 0.01, "viscosity": 0.05});
                serde_json::from_value(raw).unwrap()
            },
            "bearing_wear",
            "planar clearance_revolute joint only",
        ),
    ];
    for (model, key, says) in cases {
        let e = check(&model).expect_err(key);
        let message = e.to_string();
        assert_eq!(e.parts().key.as_deref(), Some(key), "{message}");
        assert!(message.contains("rod_slider") && message.contains(says), "{message}");
    }
    // NaN has no JSON: through the model's own type.
    let mut model = founding_with(json!({}));
    let joint = model.joints.iter_mut().find(|j| j.name == "rod_slider").unwrap();
    joint.clearance.as_mut().unwrap().journal_wear = Some(vec![f64::NAN; 8]);
    let e = check(&model).expect_err("NaN");
    assert_eq!(e.parts().key.as_deref(), Some("journal_wear"), "{e}");
    assert!(e.to_string().contains("journal_wear[0] = NaN m"), "{e}");
}
