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
/// the journal, runs as the round joint of radii `R_B + w_B`, `R_J - w_J` (clearance
/// `c + w_B + w_J`): the same impacts and forces through 0.25 s of the founding case, which
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
            "dry spatial clearance_cylindrical joint only",
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

/// The closed-form case: a journal (body `pin`, turning at `omega` on a carrier that
/// slides along y without turning) pressed by a constant load `F` down onto a bearing
/// fixed in the ground: steel on bronze-like materials, radii 7.5 and 7.0 mm, length 10
/// mm, a damped contact law that settles the first touch.
fn pressed_journal(load: f64, omega: f64) -> Model {
    serde_json::from_value(json!({
        "gravity": [0.0, 0.0],
        "bodies": [
            {"name": "carrier", "mass": 1.0, "inertia": 1e-3, "position": [0.0, -0.5e-3]},
            {"name": "pin", "mass": 0.5, "inertia": 1e-5, "position": [0.0, -0.5e-3]}
        ],
        "joints": [
            {"name": "slide", "type": "prismatic", "body_i": "ground", "point_i": [0.0, 0.0],
             "body_j": "carrier", "point_j": [0.0, 0.0], "axis": [0.0, 1.0]},
            {"name": "spin", "type": "revolute", "body_i": "carrier", "point_i": [0.0, 0.0],
             "body_j": "pin", "point_j": [0.0, 0.0]},
            {"name": "bearing", "type": "clearance_revolute", "body_i": "ground", "point_i": [0.0, 0.0],
             "body_j": "pin", "point_j": [0.0, 0.0],
             "clearance": {"bearing_radius": 7.5e-3, "clearance": 0.5e-3, "length": 0.01,
                           "bearing_material": {"youngs_modulus": 97e9, "poisson_ratio": 0.3},
                           "journal_material": {"youngs_modulus": 207e9, "poisson_ratio": 0.3},
                           "normal_law": {"type": "kelvin_voigt", "exponent": 1.5, "damping": 1e4}}}
        ],
        "drivers": [{"name": "motor", "joint": "spin", "profile": {"type": "constant_speed", "speed": omega}}],
        "forces": [{"type": "applied_force", "name": "load", "body": "carrier", "force": [0.0, -load]}]
    }))
    .unwrap()
}

/// A journal pressed by a constant load `F` and turning at constant speed `omega` in a
/// fixed bearing, for 4 revolutions: against Archard's closed form (Flores 2009,
/// section 3). The sliding distance is `R_J` per radian, so `int F_n ds = F omega R_J
/// t`; the bearing wears at the loaded spot (its bottom, at 270 deg) by the peak
/// pressure `p0 = 3 F / (4 b L)` of the elastic foundation's parabola of Hertz's half
/// width `b = sqrt(4 F R* / (pi L E*))` times `2 pi R_J` per revolution; the journal's whole circumference passes through the contact, so its
/// wear spreads uniformly, `F / L` per revolution; each part loses `F 2 pi R_J` per
/// revolution (per unit k).
#[test]
fn pressed_journal_against_closed_form() {
    let (load, omega, revolutions) = (200.0, 50.0, 4.0);
    let t_end = revolutions * std::f64::consts::TAU / omega;
    let cells = 3600;
    let opts = SimOptions {
        rate: Some(100.0),
        wear: Some(jointgap_core::WearOptions { cells, start: 0.0 }),
        ..SimOptions::new(t_end)
    };
    let res = run(&pressed_journal(load, omega), &opts);
    assert_eq!(res.wear.len(), 1);
    let w = &res.wear[0];
    assert_eq!(w.joint, "bearing");
    let (r_b, r_j, length) = (7.5e-3, 7.0e-3, 0.01);
    let load_distance = load * omega * r_j * t_end;
    assert!((w.load_distance / load_distance - 1.0).abs() < 1e-4, "{} vs {load_distance}", w.load_distance);
    for volume in [w.bearing_volume, w.journal_volume] {
        assert!((volume / w.load_distance - 1.0).abs() < 1e-12, "{volume} vs {}", w.load_distance);
    }
    let e_star = 1.0 / (0.91 / 97e9 + 0.91 / 207e9);
    let r_star = r_j * r_b / (r_b - r_j);
    let b = (4.0 * load * r_star / (std::f64::consts::PI * length * e_star)).sqrt();
    let p0 = 3.0 * load / (4.0 * b * length);
    let spot = w.bearing_depth[3 * cells / 4];
    let closed = p0 * std::f64::consts::TAU * r_j * revolutions;
    assert!((spot / closed - 1.0).abs() < 2e-3, "bearing at its bottom {spot:e} vs {closed:e}");
    // The peak is the loaded spot, and the bearing is unworn a contact width away (and
    // a little more: the first touch presses harder for an instant).
    let peak = w.bearing_depth.iter().cloned().fold(0.0, f64::max);
    assert_eq!(peak, spot);
    let away = ((b / r_b) / (std::f64::consts::TAU / cells as f64)).ceil() as usize + 4;
    assert_eq!(w.bearing_depth[3 * cells / 4 + away], 0.0);
    assert_eq!(w.bearing_depth[3 * cells / 4 - away], 0.0);
    let uniform = load / length * revolutions;
    // Away from where the journal first touched (its bottom at t = 0, 270 deg in its
    // frame), whose damped first impact the closed form leaves out: the first
    // millisecond turns it by 0.05 rad.
    for (c, d) in w.journal_depth.iter().enumerate() {
        let from_start = (w.angles[c] - 1.5 * std::f64::consts::PI).abs();
        if from_start > 0.2 {
            assert!((d / uniform - 1.0).abs() < 1e-3, "journal cell {c}: {d:e} vs {uniform:e}");
        }
    }
}

/// The founding case with a bearing length, run for 0.1 s accumulating wear on a grid of
/// `cells`.
fn founding_wear(cells: usize) -> SimResult {
    let model = founding_with(json!({"length": 0.02}));
    run(
        &model,
        &SimOptions {
            rate: Some(1000.0),
            wear: Some(jointgap_core::WearOptions { cells, start: 0.0 }),
            ..SimOptions::new(0.1)
        },
    )
}

/// Conservation on the founding case: each part's worn volume, the sum over its cells of
/// depth x cell arc x length, is `int F_n ds` (per unit k), and refining the grid from 90
/// to 1440 cells leaves the totals as they are (the run itself does not change: the wear
/// is only accumulated) while the depth concentrates.
#[test]
fn founding_case_conserves_the_worn_volume() {
    let coarse = founding_wear(90);
    let fine = founding_wear(1440);
    let (c, f) = (&coarse.wear[0], &fine.wear[0]);
    assert_eq!(c.joint, "rod_slider");
    assert!(c.load_distance > 0.0);
    assert!((c.load_distance / f.load_distance - 1.0).abs() < 1e-14);
    for w in [c, f] {
        let n = w.angles.len() as f64;
        for (depth, r) in [(&w.bearing_depth, 7.5e-3), (&w.journal_depth, 7.0e-3)] {
            let volume: f64 = depth.iter().sum::<f64>() * r * std::f64::consts::TAU / n * 0.02;
            assert!((volume / w.load_distance - 1.0).abs() < 1e-12, "{volume} vs {}", w.load_distance);
        }
        assert!((w.bearing_volume / w.load_distance - 1.0).abs() < 1e-12);
        assert!((w.journal_volume / w.load_distance - 1.0).abs() < 1e-12);
    }
    let max = |d: &[f64]| d.iter().cloned().fold(0.0, f64::max);
    assert!(max(&f.bearing_depth) > max(&c.bearing_depth));
    // Wear does not move the run.
    assert_eq!(coarse.data, fine.data);
    let plain = run(
        &founding_with(json!({"length": 0.02})),
        &SimOptions { rate: Some(1000.0), ..SimOptions::new(0.1) },
    );
    assert_eq!(plain.data, coarse.data);
    assert!(plain.wear.is_empty());
}

/// A run asked for wear needs each revolute clearance joint's length, and a grid of at
/// least 8 cells; a run that stops early returns the wear it accumulated.
#[test]
fn wear_options_and_a_stopped_run() {
    let opts = |cells| SimOptions {
        wear: Some(jointgap_core::WearOptions { cells, start: 0.0 }),
        ..SimOptions::new(0.1)
    };
    let e = simulate(&founding_with(json!({})), &opts(90)).expect_err("no length").to_string();
    assert!(e.contains("rod_slider") && e.contains("length"), "{e}");
    let e = simulate(&founding_with(json!({"length": 0.02})), &opts(7)).expect_err("7 cells").to_string();
    assert!(e.contains("wear.cells = 7"), "{e}");
    let stopped =
        simulate(&founding_with(json!({"length": 0.02})), &SimOptions { max_steps: Some(300), ..opts(90) })
            .unwrap();
    assert!(matches!(stopped.status, jointgap_core::Status::Failed { .. }), "{:?}", stopped.status);
    assert!(stopped.wear[0].load_distance > 0.0);
}

/// The founding case in an oval-worn bearing (`w_B = a (1 + cos 2 theta)`, a = 20 um)
/// runs to its end with each method: the worn contact's penetration and normal are
/// smooth enough for the event location and the implicit methods' Newton iterations;
/// and the extra clearance changes the impacts.
#[test]
fn an_oval_bearing_runs_with_every_method() {
    let a = 2e-5;
    let wear: Vec<f64> =
        (0..48).map(|k| a * (1.0 + (2.0 * std::f64::consts::TAU * k as f64 / 48.0).cos())).collect();
    let worn = founding_with(json!({"bearing_wear": wear}));
    let round = run(&founding_with(json!({})), &SimOptions { rate: Some(1000.0), ..SimOptions::new(0.3) });
    for method in [jointgap_core::Method::Auto, jointgap_core::Method::Sdirk4, jointgap_core::Method::Radau5]
    {
        let res = run(&worn, &SimOptions { rate: Some(1000.0), method, ..SimOptions::new(0.3) });
        assert!(res.data.iter().flatten().all(|x| x.is_finite()));
        assert!(!res.impacts[0].impacts.is_empty());
        assert_ne!(res.impacts[0].impacts.len(), 0);
        assert_ne!(res.channel("rod_slider.fn"), round.channel("rod_slider.fn"));
    }
}

/// The option's start time: the wear before it counts nothing, so that a run from the
/// start to `T` and one counting from `T/2` differ by the first half's share, here half
/// the load's work (constant load and speed after the first touch).
#[test]
fn wear_counts_from_its_start_time() {
    let (load, omega) = (200.0, 50.0);
    let t_end = 4.0 * std::f64::consts::TAU / omega;
    let wear = |start: f64| {
        let opts = SimOptions {
            rate: Some(100.0),
            wear: Some(jointgap_core::WearOptions { cells: 360, start }),
            ..SimOptions::new(t_end)
        };
        run(&pressed_journal(load, omega), &opts).wear[0].load_distance
    };
    let (whole, half) = (wear(0.0), wear(0.5 * t_end));
    let expected = load * omega * 7.0e-3 * 0.5 * t_end;
    assert!((half / expected - 1.0).abs() < 1e-3, "{half} vs {expected}");
    assert!((whole / (2.0 * expected) - 1.0).abs() < 1e-3, "{whole}");
}
