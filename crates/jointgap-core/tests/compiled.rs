//! Compiled evaluations against interpreted ones: the same run to the bit (every
//! recorded sample of every channel, every step, every event), and the account of what
//! was compiled and why not.

use crate::common::*;
use jointgap_core::model::spatial::SpatialModel;
use jointgap_core::simulate::{simulate_spatial, Silent};
use jointgap_core::{simulate, Method, Model, SimOptions, SimResult, Status};
use serde_json::{json, Value};

fn options(t_end: f64, method: Method, compiled: bool) -> SimOptions {
    SimOptions {
        rate: Some(2000.0),
        every_step: true,
        energy: true,
        method,
        compiled,
        ..SimOptions::new(t_end)
    }
}

/// Runs `model` compiled and interpreted and asserts the two results are the same bits.
fn same_run(model: &Model, t_end: f64, method: Method) -> SimResult {
    same_run_of(|o| simulate(model, o).unwrap(), t_end, method)
}

/// [`same_run`] for a spatial model (JSON, SI units).
fn same_spatial_run(model: &Value, t_end: f64, method: Method) -> SimResult {
    let model = SpatialModel::from_json(&model.to_string()).expect("a valid model");
    same_run_of(|o| simulate_spatial(&model, o, &mut Silent).unwrap(), t_end, method)
}

/// [`same_run`] of the runs that `run` makes with the options it is given.
fn same_run_of(run: impl Fn(&SimOptions) -> SimResult, t_end: f64, method: Method) -> SimResult {
    let native = run(&options(t_end, method, true));
    let plain = run(&options(t_end, method, false));
    assert_eq!(native.status, Status::Finished, "{method:?}: {:?}", native.status);
    assert!(native.stats.compiled.starts_with("native code"), "{}", native.stats.compiled);
    assert!(native.stats.compiled.contains(" 0 interpreted"), "{}", native.stats.compiled);
    assert!(plain.stats.compiled.starts_with("interpreted: turned off by the run's options"));
    if matches!(method, Method::Sdirk4 | Method::Radau5) {
        for run in [&native, &plain] {
            assert!(run.stats.compiled.ends_with(" 0 of the applied forces only"), "{}", run.stats.compiled);
        }
    }
    let counts = |r: &SimResult| {
        let s = &r.stats;
        (
            s.accepted_steps,
            s.rejected_steps,
            s.rhs_evaluations,
            s.jacobian_evaluations,
            s.newton_iterations,
            s.projections,
            s.events,
        )
    };
    assert_eq!(counts(&native), counts(&plain), "{method:?}");
    assert_eq!(native.names, plain.names);
    let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&native.time), bits(&plain.time), "{method:?}: sample times");
    for (k, name) in native.names.iter().enumerate() {
        assert_eq!(bits(&native.data[k]), bits(&plain.data[k]), "{method:?}: channel {name}");
    }
    assert_eq!(native.impacts, plain.impacts, "{method:?}");
    native
}

/// The founding clearance case (0.5 mm, ADAMS impact law and Coulomb friction) with each
/// method: explicit, implicit, and the automatic switching between them.
#[test]
fn founding_case_runs_the_same_compiled() {
    let model = slider_crank_clearance();
    for method in [Method::Auto, Method::Dopri5, Method::Sdirk4, Method::Radau5] {
        let run = same_run(&model, 0.12, method);
        assert!(run.stats.events > 0, "{method:?}: the journal hits its bearing");
        assert!(run.stats.compile_time > 0.0 || run.stats.compiled.contains("from the cache"));
    }
}

/// Every force element (a spring-damper, a torsional one, an applied force and torque
/// from tables) and both kinds of driver row: the ideal slider-crank loaded.
#[test]
fn force_elements_and_tables_run_the_same_compiled() {
    let mut raw = serde_json::to_value(slider_crank(9.81)).unwrap();
    raw["forces"] = json!([
        {"name": "spring", "type": "spring_damper", "body_i": "ground", "point_i": [0.0, 0.1],
         "body_j": "slider", "point_j": [0.0, 0.0], "stiffness": 2e3, "damping": 15.0, "free_length": 0.3},
        {"name": "torsion", "type": "rotational_spring_damper", "body_i": "crank", "body_j": "rod",
         "stiffness": 40.0, "damping": 0.2, "free_angle": 0.1},
        {"name": "push", "type": "applied_force", "body": "slider", "point": [0.0, 0.0],
         "force": {"time": [0.0, 0.05, 0.1], "value": [[0.0, 0.0], [-50.0, 10.0], [20.0, 0.0]]}},
        {"name": "twist", "type": "applied_torque", "body": "rod", "torque": 1.5}
    ]);
    let model: Model = serde_json::from_value(raw).unwrap();
    same_run(&model, 0.15, Method::Auto);
    same_run(&model, 0.15, Method::Radau5);
}

/// Joints with play, a revolute's (a damped stop) and a prismatic one's (a Hertz stop
/// and gravity across the axis): a wheel and a slider, each bouncing between its stops.
#[test]
fn joints_with_play_run_the_same_compiled() {
    let model = |raw: serde_json::Value| -> Model { serde_json::from_value(raw).unwrap() };
    let wheel = model(json!({
        "gravity": [0.0, -9.81],
        "bodies": [{"name": "wheel", "mass": 1.0, "inertia": 2e-3, "omega": 3.0, "position": [0.01, 0.0]}],
        "joints": [{"name": "hub", "type": "revolute_with_play", "body_i": "ground", "point_i": [0.0, 0.0],
                    "body_j": "wheel", "point_j": [-0.01, 0.0],
                    "play": {"play": 0.02, "stiffness": 500.0,
                             "normal_law": {"type": "kelvin_voigt", "exponent": 1.0, "damping": 0.06}}}]
    }));
    let slider = model(json!({
        "gravity": [0.0, -9.81],
        "bodies": [{"name": "slider", "mass": 0.2, "inertia": 1e-4, "position": [0.1, 0.0], "velocity": [0.5, 0.0]}],
        "joints": [{"name": "rail", "type": "prismatic_with_play", "body_i": "ground", "point_i": [0.0, 0.0],
                    "body_j": "slider", "point_j": [0.0, 0.0], "axis": [1.0, 0.0],
                    "play": {"play": 0.004, "stiffness": 1e8, "normal_law": {"type": "hertz"}}}]
    }));
    for m in [&wheel, &slider] {
        for method in [Method::Auto, Method::Radau5] {
            let run = same_run(m, 0.05, method);
            assert!(run.stats.events > 0, "{method:?}: the stops are met");
        }
    }
}

/// The founding slider-crank whose slider has play in its guide (a block 50 x 50 mm in a
/// guide 50.5 mm wide, damped linear corners and Coulomb friction): each of the four
/// corners is a block with its own ways.
#[test]
fn block_in_its_guide_runs_the_same_compiled() {
    let mut raw = serde_json::to_value(slider_crank_clearance()).unwrap();
    let joints = raw["joints"].as_array_mut().unwrap();
    let k = joints.iter().position(|j| j["name"] == "slider_guide").unwrap();
    joints[k] = json!({"name": "slider_guide", "type": "clearance_translational", "body_i": "ground",
        "point_i": [0.0, 0.0], "body_j": "slider", "point_j": [0.0, 0.0], "axis": [1.0, 0.0],
        "clearance": {"block_length": 0.05, "block_height": 0.05, "clearance": 0.5e-3, "stiffness": 2e9,
                      "normal_law": {"type": "lankarani_nikravesh", "exponent": 1.0, "restitution": 0.7},
                      "friction": {"type": "coulomb", "mu_s": 0.08, "mu_d": 0.05, "v_s": 1e-4, "v_d": 0.01016}}});
    let model: Model = serde_json::from_value(raw).unwrap();
    for method in [Method::Auto, Method::Radau5] {
        let run = same_run(&model, 0.1, method);
        let corners =
            run.impacts.iter().filter(|j| j.joint == "slider_guide" && !j.impacts.is_empty()).count();
        assert!(corners >= 2, "{method:?}: corners that hit the guide: {corners}");
    }
}

/// A gear pair with backlash, its pinion driven by a torque that reverses (a table), so
/// that the teeth cross the backlash and meet the other flank; with a constant mesh
/// stiffness, and with one that varies along the mesh cycle (its table read in a block
/// of its own, a way per interval the pinion turns through).
#[test]
fn gear_meshes_run_the_same_compiled() {
    let (r1, n) = (0.02, 2.0);
    let gears = |stiffness: serde_json::Value| -> Model {
        serde_json::from_value(json!({
            "gravity": [0.0, -9.81],
            "bodies": [
                {"name": "pinion", "mass": 0.3, "inertia": 1e-4, "omega": 4.0},
                {"name": "wheel", "mass": 1.2, "inertia": 2e-3, "position": [r1 * (1.0 + n), 0.0]}
            ],
            "joints": [
                {"name": "pinion_pin", "type": "revolute", "body_i": "ground", "point_i": [0.0, 0.0], "body_j": "pinion", "point_j": [0.0, 0.0]},
                {"name": "wheel_pin", "type": "revolute", "body_i": "ground", "point_i": [r1 * (1.0 + n), 0.0], "body_j": "wheel", "point_j": [0.0, 0.0]},
                {"name": "mesh", "type": "gear_pair", "body_i": "pinion", "point_i": [0.0, 0.0], "body_j": "wheel", "point_j": [0.0, 0.0],
                 "gear": {"ratio": n, "pitch_radius": r1, "backlash": 0.4e-3, "mesh_stiffness": stiffness,
                          "normal_law": {"type": "kelvin_voigt", "exponent": 1.0, "damping": 2e3}}}
            ],
            "forces": [{"type": "applied_torque", "name": "motor", "body": "pinion",
                        "torque": {"time": [0.0, 0.02, 0.04, 0.06], "value": [2.0, -2.0, 2.0, -2.0]}}]
        }))
        .unwrap()
    };
    let constant = gears(json!(1e8));
    for method in [Method::Auto, Method::Radau5] {
        let run = same_run(&constant, 0.06, method);
        assert!(run.stats.events > 1, "{method:?}: the teeth meet both flanks");
    }
    let cycle = gears(json!({"angle": [0.0, 0.02, 0.05, 0.1, 0.2, 0.25, 0.3142],
                             "value": [1e8, 1.2e8, 1.5e8, 1.5e8, 1.3e8, 1.1e8, 1e8]}));
    for method in [Method::Auto, Method::Radau5] {
        let run = same_run(&cycle, 0.06, method);
        assert!(run.stats.events > 1, "{method:?}: the teeth meet both flanks");
        // The teeth's contact and the table's intervals (the pinion turns through four).
        assert!(ways(&run) >= 6, "{method:?}: {}", run.stats.compiled);
    }
}

/// Turned off with the exact Jacobians, nothing is recorded.
#[test]
fn turned_off_records_nothing() {
    let opts = SimOptions { exact_jacobian: false, ..options(0.02, Method::Radau5, false) };
    let run = simulate(&slider_crank_clearance(), &opts).unwrap();
    assert_eq!(run.stats.compiled, "interpreted: turned off by the run's options");
}

/// The founding case's rod-slider joint with `wear` (its `bearing_wear` and
/// `journal_wear`).
pub fn worn_founding_case(wear: Value) -> Model {
    let mut raw = serde_json::to_value(slider_crank_clearance()).unwrap();
    let joint = raw["joints"].as_array_mut().unwrap().iter_mut().find(|j| j["name"] == "rod_slider").unwrap();
    for (key, table) in wear.as_object().unwrap() {
        joint["clearance"][key] = table.clone();
    }
    serde_json::from_value(raw).unwrap()
}

/// Depths `f(theta)` [m] at `n` equally spaced angles.
fn wear_table(n: usize, f: impl Fn(f64) -> f64) -> Value {
    json!((0..n).map(|k| f(std::f64::consts::TAU * k as f64 / n as f64)).collect::<Vec<_>>())
}

/// Worn parts: the search over the profiles runs interpreted and hands the compiled
/// code where the rims lie, whose last Newton step, wear and contact laws are compiled.
/// The founding case with a bearing worn into an oval and a pocket and a journal worn
/// at two sides, and a dry spatial journal in a bearing worn into an oval.
#[test]
fn worn_parts_run_the_same_compiled() {
    let pocket = |t: f64| {
        let d = (t - 1.0) / 0.3;
        2e-5 * (1.0 + (2.0 * t).cos()) + if d.abs() < 1.0 { 6e-5 * (1.0 - d * d) } else { 0.0 }
    };
    let model = worn_founding_case(json!({
        "bearing_wear": wear_table(72, pocket),
        "journal_wear": wear_table(48, |t| 1e-5 * (1.0 + (2.0 * t).cos())),
    }));
    for method in [Method::Auto, Method::Radau5] {
        let run = same_run(&model, 0.12, method);
        assert!(run.stats.events > 0, "{method:?}: the journal hits its bearing");
    }
    let mut journal = crate::spatial_joint_kinds::lubricated_journal(50.0, 100.0, 0.0, [0.0; 3], [1e-3; 3]);
    let dry = journal["joints"][0].as_object_mut().unwrap();
    dry.remove("lubrication");
    dry.insert("type".into(), json!("clearance_cylindrical"));
    journal["joints"][0]["clearance"]["bearing_wear"] = wear_table(36, |t| 2e-5 * (1.0 + (2.0 * t).cos()));
    for method in [Method::Auto, Method::Radau5] {
        let run = same_spatial_run(&journal, 0.02, method);
        assert!(run.stats.events > 0, "{method:?}: the journal hits its bearing");
    }
}

/// What the compiler does not cover runs interpreted, and the run says why: a Schur
/// complement factored sparse (a chain of 60 links whose joints are listed out of
/// order).
#[test]
fn what_is_not_compiled_says_why() {
    let chain = crate::schur::chain_listed(60, |k| 37 * k % 60);
    let run = simulate(&chain, &options(0.001, Method::Auto, true)).unwrap();
    assert_eq!(
        run.stats.compiled,
        "interpreted: the Schur complement of its 120 rows is factored sparse, which is not compiled yet"
    );
    assert_eq!(run.stats.compile_time, 0.0);
}

/// A journal tilted in its lubricated bearing under a load, spinning: the film's two
/// halves (their eccentricities, rates and each film form at each) and the dry laws of
/// the cylindrical joint beside them.
#[test]
fn spatial_oil_films_run_the_same_compiled() {
    for film in ["short", "short_pi", "long", "long_pi"] {
        let mut model =
            crate::spatial_joint_kinds::lubricated_journal(50.0, 100.0, 0.002, [0.0, 0.01, 0.0], [1e-3; 3]);
        model["joints"][0]["lubrication"]["film"] = json!(film);
        for method in [Method::Auto, Method::Radau5] {
            same_spatial_run(&model, 0.02, method);
        }
    }
}

/// A box in its channel, thrown across it and spinning: each of its sixteen points (a
/// corner against a wall) is a block with its own ways.
#[test]
fn spatial_block_in_its_channel_runs_the_same_compiled() {
    let block = crate::spatial_joint_kinds::block_in_channel([0.2, 0.05, -0.04], [3.0, 2.0, -4.0]);
    for method in [Method::Auto, Method::Radau5] {
        let run = same_spatial_run(&block, 0.05, method);
        let points = run.impacts.iter().filter(|p| !p.impacts.is_empty()).count();
        assert!(points >= 3, "{method:?}: points that hit a wall: {points}");
    }
}

/// The founding case with its rod-slider joint lubricated (film model `film`, an oil of
/// 0.4 Pa s).
pub(crate) fn lubricated_founding_case(film: &str) -> Model {
    let mut raw = serde_json::to_value(slider_crank_clearance()).unwrap();
    let joint = raw["joints"].as_array_mut().unwrap().iter_mut().find(|j| j["name"] == "rod_slider").unwrap();
    joint["type"] = json!("lubricated_revolute");
    joint["lubrication"] = json!({"length": 7.5e-3, "viscosity": 0.4, "film": film});
    serde_json::from_value(raw).unwrap()
}

/// Every oil film form: the short and the long bearing's positive-pressure (Gumbel)
/// films and their pi-films. The Sommerfeld substitution, the film's moments, the end of
/// the long bearing's positive-pressure arc (a root found by iteration, called whole),
/// its force and torque, with the dry laws where the film is thinner than its threshold.
#[test]
fn oil_films_run_the_same_compiled() {
    for film in ["short", "short_pi", "long", "long_pi"] {
        for method in [Method::Auto, Method::Radau5] {
            same_run(&lubricated_founding_case(film), 0.1, method);
        }
    }
}

/// Two clearance joints (crank-rod and rod-slider): each joint's contact is a block with
/// its own ways, so one path covers every combination of the two joints' branches and
/// every evaluation runs compiled (with whole-evaluation paths the combinations
/// multiplied past the paths' limit).
#[test]
fn two_clearance_joints_add_their_ways() {
    let model = slider_crank_clearance();
    let mut raw = serde_json::to_value(&model).unwrap();
    let joints = raw["joints"].as_array_mut().unwrap();
    let clearance = joints.iter().find(|j| j["name"] == "rod_slider").unwrap().clone();
    let k = joints.iter().position(|j| j["name"] == "crank_rod").unwrap();
    joints[k] = json!({"name": "crank_rod", "type": "clearance_revolute", "body_i": "crank", "point_i": "A",
                       "body_j": "rod", "point_j": "A", "clearance": clearance["clearance"]});
    let model: Model = serde_json::from_value(raw).unwrap();
    for method in [Method::Auto, Method::Radau5] {
        let run = same_run(&model, 0.1, method);
        // Free flight and contact at least, at each joint.
        assert!(ways(&run) >= 4, "{method:?}: {}", run.stats.compiled);
        assert!(
            run.impacts.iter().all(|j| !j.impacts.is_empty()),
            "{method:?}: both journals hit their bearings"
        );
    }
}

/// The ways through the blocks of a run compiled as one path, read from its account.
fn ways(run: &SimResult) -> usize {
    let account = &run.stats.compiled;
    let after = account.strip_prefix("native code: 1 paths and ").expect("a compiled run of one path");
    after.split(' ').next().and_then(|n| n.parse().ok()).expect("a count of ways")
}

/// The paths a run took from the process's cache, read from its account.
fn from_cache(run: &SimResult) -> usize {
    let account = &run.stats.compiled;
    let end = account.find(" from the cache").expect("a compiled run's account");
    let start = account[..end].rfind(' ').map_or(0, |k| k + 1);
    account[start..end].parse().expect("a count")
}

/// A variant whose numbers differ (another clearance, another damping) records the same
/// graphs, the model's numbers being their parameters: it runs the code compiled for the
/// first, and still gives the interpreted run's bits.
#[test]
fn variants_share_their_code() {
    let model = slider_crank_clearance();
    let mut raw = serde_json::to_value(&model).unwrap();
    let joint = raw["joints"].as_array_mut().unwrap().iter_mut().find(|j| j["name"] == "rod_slider").unwrap();
    joint["clearance"]["clearance"] = json!(0.4e-3);
    joint["clearance"]["normal_law"]["c_max"] = json!(20000.0);
    let variant: Model = serde_json::from_value(raw).unwrap();
    same_run(&model, 0.08, Method::Dopri5);
    let run = same_run(&variant, 0.08, Method::Dopri5);
    assert!(from_cache(&run) > 0, "{}", run.stats.compiled);
}

/// The spatial four-bar with a spherical clearance joint with each method: the
/// quaternions' normalising and rotation matrices, the five rows of the revolute joints
/// and the rotation driver's angle row (its `atan2` and wrap), the ball joint, the ball in
/// its socket with its friction, gravity and the gyroscopic moments.
#[test]
fn spatial_four_bar_runs_the_same_compiled() {
    let model = spatial_four_bar_clearance();
    for method in [Method::Auto, Method::Dopri5, Method::Sdirk4, Method::Radau5] {
        let run = same_spatial_run(&model, 0.06, method);
        assert!(run.stats.events > 0, "{method:?}: the ball hits its socket");
    }
}

/// The spatial force elements: a spring-damper, and a force and a torque from tables in
/// body axes, on the spatial four-bar.
#[test]
fn spatial_force_elements_run_the_same_compiled() {
    let mut model = spatial_four_bar_clearance();
    let table = |values: Value| json!({"time": [0.0, 0.02, 0.05], "value": values});
    model["forces"] = json!([
        {"name": "spring", "type": "spring_damper", "body_i": "ground", "point_i": [0.2, 0.1, 0.3],
         "body_j": "rocker", "point_j": "B", "stiffness": 800.0, "damping": 2.0, "free_length": 0.05},
        {"name": "push", "type": "applied_force", "body": "coupler", "point": [0.01, 0.0, 0.0], "frame": "body",
         "force": table(json!([[0.0, 0.0, 0.0], [3.0, -2.0, 1.0], [0.0, 1.0, 0.0]]))},
        {"name": "twist", "type": "applied_torque", "body": "rocker", "frame": "body",
         "torque": table(json!([[0.0, 0.0, 0.0], [0.0, 0.05, 0.02], [0.1, 0.0, 0.0]]))}
    ]);
    same_spatial_run(&model, 0.06, Method::Auto);
    same_spatial_run(&model, 0.06, Method::Radau5);
}

/// Spatial joints with play: a wheel on a slanted axle between its angular stops, and a
/// part on a slanted rail between its stops, with gravity across the axis (damped and
/// Hertz stops).
#[test]
fn spatial_joints_with_play_run_the_same_compiled() {
    let damped = json!({"type": "kelvin_voigt", "exponent": 1.0, "damping": 0.06});
    for (kind, law, stiffness, turning, velocity) in [
        ("revolute_with_play", damped, 500.0, [0.0, 1.8, 2.4], [0.0; 3]),
        ("prismatic_with_play", json!({"type": "hertz"}), 1e8, [0.0; 3], [0.0, 0.3, 0.4]),
    ] {
        let model = json!({
            "dimension": 3, "gravity": [0.0, -9.81, 0.0],
            "bodies": [{"name": "part", "mass": 0.2, "inertia": {"principal": {"moments": [2e-3, 3e-3, 4e-3]}},
                        "position": [0.01, 0.0, 0.0], "angular_velocity": turning, "velocity": velocity}],
            "joints": [{"name": "stop", "type": kind, "body_i": "ground", "point_i": [0.01, 0.0, 0.0],
                        "body_j": "part", "point_j": [0.0, 0.0, 0.0], "axis": [0.0, 0.6, 0.8],
                        "play": {"play": 0.02, "stiffness": stiffness, "normal_law": law}}]
        });
        for method in [Method::Auto, Method::Radau5] {
            let run = same_spatial_run(&model, 0.05, method);
            assert!(run.stats.events > 0, "{kind} {method:?}: the stops are met");
        }
    }
}

/// The founding case written as a spatial model: its journal, free to tilt, in a round
/// bearing, touching at both ends (each carrying half the law), with two methods; and
/// with thrust faces 10 um off the journal's ends.
#[test]
fn spatial_journal_in_its_bearing_runs_the_same_compiled() {
    let model = crate::spatial_clearance::slider_crank_clearance_3d();
    let mut thrust = model.clone();
    let joint =
        thrust["joints"].as_array_mut().unwrap().iter_mut().find(|j| j["name"] == "rod_slider").unwrap();
    joint["axial_clearance"] = json!(1e-5);
    for (model, methods) in
        [(&model, [Method::Auto, Method::Radau5]), (&thrust, [Method::Auto, Method::Dopri5])]
    {
        for method in methods {
            let run = same_spatial_run(model, 0.12, method);
            assert!(run.stats.events > 0, "{method:?}: the journal hits its bearing");
        }
    }
}
