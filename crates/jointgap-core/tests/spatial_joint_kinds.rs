//! The spatial joints with contact that carry the planar ones into space, each against an
//! independent computation: the block in its guide channel (dropped flat, against the
//! Hertz closed form and the planar block whose two corners stand for the channel's
//! four; energy over many corner impacts as it tumbles), and the lubricated cylindrical
//! joint (an aligned journal under load against Ocvirk's steady short bearing, the film's
//! energy account while a tilted journal whirls, the passage into dry contact).

use jointgap_core::model::spatial::SpatialModel;
use jointgap_core::simulate::{simulate_spatial, Silent};
use jointgap_core::{simulate, Method, Model, SimOptions, SimResult, Status};
use serde_json::{json, Value};

const K: f64 = 2e9;
/// Block 40 x 10 x 20 mm in a channel 10.5 x 20.4 mm: 0.25 mm of play on each side
/// across the height, 0.2 mm across the depth.
const LENGTH: f64 = 0.04;
const HEIGHT: f64 = 0.01;
const WIDTH: f64 = 0.0105;
const DEPTH: f64 = 0.02;
const GUIDE_DEPTH: f64 = 0.0204;

fn run_spatial(model: Value, opts: &SimOptions) -> SimResult {
    let model = SpatialModel::from_json(&model.to_string()).unwrap();
    let res = simulate_spatial(&model, opts, &mut Silent).unwrap();
    assert_eq!(res.status, Status::Finished, "{:?}", res.status);
    res
}

fn channel<'a>(res: &'a SimResult, name: &str) -> &'a [f64] {
    res.channel(name).unwrap_or_else(|| panic!("no channel {name} in {:?}", res.names))
}

/// A free block (0.5 kg) in a ground channel along x, its height across y, moving at `v`
/// and turning at `w`.
pub(crate) fn block_in_channel(v: [f64; 3], w: [f64; 3]) -> Value {
    json!({
        "dimension": 3, "gravity": [0.0, 0.0, 0.0],
        "bodies": [{"name": "block", "mass": 0.5,
                    "inertia": {"principal": {"moments": [2e-5, 7e-5, 7e-5]}},
                    "velocity": v, "angular_velocity": w}],
        "joints": [{"name": "guide", "type": "clearance_translational", "body_i": "ground",
                    "point_i": [0.0, 0.0, 0.0], "body_j": "block", "point_j": [0.0, 0.0, 0.0],
                    "axis": [1.0, 0.0, 0.0], "height_axis": [0.0, 1.0, 0.0],
                    "clearance": {"block_length": LENGTH, "block_height": HEIGHT, "guide_width": WIDTH,
                                  "block_depth": DEPTH, "guide_depth": GUIDE_DEPTH,
                                  "stiffness": K, "normal_law": {"type": "hertz"}}}]
    })
}

/// Dropped flat onto the channel's lower wall, the block lands on its four lower corners
/// at once: the Hertz impact of mass m on a stiffness 4K (peak penetration `(5 m v0^2 /
/// (16 K))^(2/5)`, contact time `2.94 delta_max / v0`); the planar block, whose two lower
/// corners each carry 2K, lands alike to the integration's accuracy.
#[test]
fn spatial_block_dropped_flat_matches_hertz_and_the_planar_block() {
    let (m, v0) = (0.5, 0.4);
    let gap = 0.5 * (WIDTH - HEIGHT);
    let opts = SimOptions {
        rate: Some(2e7),
        rtol: 1e-10,
        atol: 1e-14,
        method: Method::Dopri5,
        ..SimOptions::new(2.5 * gap / v0)
    };
    let res = run_spatial(block_in_channel([0.3, -v0, 0.0], [0.0; 3]), &opts);
    let planar = Model::from_json(
        &json!({
            "gravity": [0.0, 0.0],
            "bodies": [{"name": "block", "mass": m, "inertia": 7e-5, "velocity": [0.3, -v0]}],
            "joints": [{"name": "guide", "type": "clearance_translational", "body_i": "ground",
                        "point_i": [0.0, 0.0], "body_j": "block", "point_j": [0.0, 0.0], "axis": [1.0, 0.0],
                        "clearance": {"block_length": LENGTH, "block_height": HEIGHT, "guide_width": WIDTH,
                                      "stiffness": 2.0 * K, "normal_law": {"type": "hertz"}}}]
        })
        .to_string(),
    )
    .unwrap();
    let planar = simulate(&planar, &opts).unwrap();
    let planar_impact = &planar.impacts.iter().find(|i| i.point == Some(3)).unwrap().impacts[0];
    let delta_max = (5.0 * m * v0 * v0 / (16.0 * K)).powf(0.4);
    // The lower corners' points against the height wall: corners 3, 4, 7, 8.
    let lower = [5, 7, 13, 15];
    for i in &res.impacts {
        let point = i.point.expect("a block has numbered points");
        if !lower.contains(&point) {
            assert!(i.impacts.is_empty(), "point {point} touches: {:?}", i.impacts);
            continue;
        }
        assert_eq!(i.impacts.len(), 1, "p{point}: {:?}", i.impacts);
        let imp = &i.impacts[0];
        assert!((imp.onset_time - gap / v0).abs() < 1e-9, "p{point} onset at {}", imp.onset_time);
        let duration = imp.duration.expect("separated");
        assert!((imp.max_penetration / delta_max - 1.0).abs() < 5e-3, "p{point}: {}", imp.max_penetration);
        assert!((duration / (2.94 * delta_max / v0) - 1.0).abs() < 5e-3, "p{point} duration {duration:e}");
        assert!(
            (imp.peak_force / (K * delta_max.powf(1.5)) - 1.0).abs() < 5e-3,
            "p{point}: {}",
            imp.peak_force
        );
        assert!((imp.max_penetration / planar_impact.max_penetration - 1.0).abs() < 1e-6);
        assert!((duration / planar_impact.duration.unwrap() - 1.0).abs() < 1e-6);
        assert!((imp.peak_force / (0.5 * planar_impact.peak_force) - 1.0).abs() < 1e-6);
    }
    let last = |c: &str| *channel(&res, c).last().unwrap();
    assert!((last("block.vy") - v0).abs() < 1e-6 * v0, "rebound {}", last("block.vy"));
    assert!((last("guide.speed") - 0.3).abs() < 1e-12 && last("guide.offset_depth").abs() < 1e-15);
    for tilt in ["guide.tilt_along", "guide.tilt_height", "guide.tilt_depth"] {
        assert!(last(tilt).abs() < 1e-12, "{tilt} {}", last(tilt));
    }
}

/// Elastic corners without friction conserve kinetic plus contact energy over many
/// impacts of a block sliding, rattling and tumbling in its channel, on both walls.
#[test]
fn spatial_block_conserves_energy_over_many_impacts() {
    let res = run_spatial(
        block_in_channel([0.5, 0.2, 0.15], [1.0, 1.5, -0.8]),
        &SimOptions {
            rate: Some(1e5),
            rtol: 1e-10,
            atol: 1e-14,
            method: Method::Dopri5,
            ..SimOptions::new(0.05)
        },
    );
    let count = |odd: usize| -> usize {
        res.impacts.iter().filter(|i| i.point.unwrap() % 2 == odd).map(|i| i.impacts.len()).sum()
    };
    let (height_wall, depth_wall) = (count(1), count(0));
    assert!(
        height_wall >= 10 && depth_wall >= 10,
        "impacts: {height_wall} on the height walls, {depth_wall} on the depth walls"
    );
    let (ke, pe) = (channel(&res, "system.kinetic_energy"), channel(&res, "system.potential_energy"));
    let e0 = ke[0] + pe[0];
    let drift = ke.iter().zip(pe).map(|(k, p)| ((k + p) / e0 - 1.0).abs()).fold(0.0, f64::max);
    assert!(drift < 1e-6, "energy drift {drift:e}");
    let speed = channel(&res, "guide.speed");
    let vx = channel(&res, "block.vx");
    assert!(
        speed.iter().zip(vx).all(|(s, v)| (s - v).abs() < 1e-12),
        "the speed along a ground channel is vx"
    );
    assert!(vx.iter().all(|v| (v - 0.5).abs() < 1e-9), "frictionless: the slide along the channel is kept");
}

const C: f64 = 5e-5;
const R: f64 = 0.02;
const L: f64 = 0.01;
const MU: f64 = 0.05;
/// A flywheel's moments [kg m^2]: the film's torque changes its spin by < 1e-6 relative.
const FLYWHEEL: [f64; 3] = [25.0, 25.0, 50.0];

/// A journal spinning at `omega` in a ground bearing along z, carried by a short film,
/// under a load `load` along -y at its centre; turned by `tilt` about x and moving at `v`
/// at the start; its principal moments `moments` (a heavy flywheel keeps its spin).
pub(crate) fn lubricated_journal(load: f64, omega: f64, tilt: f64, v: [f64; 3], moments: [f64; 3]) -> Value {
    json!({
        "dimension": 3, "gravity": [0.0, 0.0, 0.0],
        "bodies": [{"name": "journal", "mass": 1.0, "inertia": {"principal": {"moments": moments}},
                    "orientation": {"axis_angle": {"axis": [1.0, 0.0, 0.0], "angle": tilt}},
                    "velocity": v, "angular_velocity": [0.0, 0.0, omega]}],
        "joints": [{"name": "bearing", "type": "lubricated_cylindrical", "body_i": "ground",
                    "point_i": [0.0, 0.0, 0.0], "body_j": "journal", "point_j": [0.0, 0.0, 0.0],
                    "axis": [0.0, 0.0, 1.0], "axis_j": [0.0, 0.0, 1.0], "length": L, "axial_clearance": 1e-4,
                    "clearance": {"journal_radius": R, "clearance": C, "stiffness": 1e10,
                                  "normal_law": {"type": "hunt_crossley", "restitution": 0.5}},
                    "lubrication": {"length": L, "viscosity": MU}}],
        "forces": [{"type": "applied_force", "name": "load", "body": "journal", "force": [0.0, -load, 0.0]}]
    })
}

/// An aligned journal under a constant load settles where the short bearing's steady
/// film carries it, as the planar lubricated joint does (its test gives the relation):
/// eccentricity ratio 0.6, attitude `atan(pi sqrt(1 - eps^2) / (4 eps))`, both halves
/// alike, the film's force balancing the load, no contact.
#[test]
fn aligned_journal_settles_at_the_ocvirk_eccentricity_and_attitude() {
    let (omega, eps) = (100.0, 0.6_f64);
    let pi = std::f64::consts::PI;
    let load = MU * omega * R * L.powi(3) / (4.0 * C * C) * eps / (1.0 - eps * eps).powi(2)
        * (16.0 * eps * eps + pi * pi * (1.0 - eps * eps)).sqrt();
    let res = run_spatial(
        lubricated_journal(load, omega, 0.0, [0.0; 3], FLYWHEEL),
        &SimOptions { rate: Some(1e3), rtol: 1e-9, atol: 1e-14, ..SimOptions::new(0.5) },
    );
    let last = res.time.len() - 1;
    for half in ["p1", "p2"] {
        let ratio = channel(&res, &format!("bearing.{half}.eccentricity_ratio"))[last];
        assert!((ratio - eps).abs() < 1e-4, "{half}: eccentricity ratio {ratio} vs {eps}");
    }
    let (ex, ey) = (channel(&res, "bearing.ex")[last], channel(&res, "bearing.ey")[last]);
    let phi = f64::atan2(ex, -ey);
    let expected = (pi * (1.0 - eps * eps).sqrt() / (4.0 * eps)).atan();
    assert!((phi - expected).abs() < 1e-4, "attitude {phi} vs {expected}");
    let film = ["film_fx", "film_fy", "film_fz"].map(|q| channel(&res, &format!("bearing.{q}"))[last]);
    assert!(
        (film[1] - load).abs() < 1e-6 * load && film[0].abs() < 1e-6 * load && film[2].abs() < 1e-9 * load
    );
    assert!(res.impacts.iter().all(|i| i.impacts.is_empty()));
    let mode = channel(&res, "bearing.p1.film_mode");
    assert!(mode.iter().all(|&m| m == 0.0));
}

/// A tilted journal whirling in its film: the energy balance (kinetic energy plus the
/// film's and contacts' losses less the load's work) stays constant, so the film's loads
/// on the two bodies (forces at the halves' points, torques about the axis) do the work
/// its power account says; the film straightens the journal (the tilt shrinks).
#[test]
fn tilted_journal_film_keeps_the_energy_balance_and_straightens_it() {
    let res = run_spatial(
        lubricated_journal(50.0, 200.0, 0.002, [0.0, 0.01, 0.0], [1e-4, 1e-4, 2e-4]),
        &SimOptions {
            rate: Some(1e4),
            rtol: 1e-10,
            atol: 1e-14,
            energy: true,
            method: Method::Dopri5,
            ..SimOptions::new(0.05)
        },
    );
    let b = channel(&res, "system.energy_balance");
    let scale = channel(&res, "system.contact_dissipation").iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(scale > 1e-4, "the film dissipates: {scale}");
    let drift = b.iter().map(|x| (x - b[0]).abs()).fold(0.0, f64::max);
    assert!(drift < 1e-6 * scale.max(channel(&res, "system.kinetic_energy")[0]), "drift {drift:e}");
    // The angle between the journal's axis and the bearing's: body z against global z,
    // `cos = cos(pitch) cos(roll)` for the ZYX angles.
    let (pitch, roll) = (channel(&res, "journal.pitch"), channel(&res, "journal.roll"));
    let tilt = |k: usize| (pitch[k].cos() * roll[k].cos()).min(1.0).acos();
    let last = res.time.len() - 1;
    assert!(tilt(last) < 0.1 * tilt(0), "the halves' eccentricities {} -> {}", tilt(0), tilt(last));
}

/// A load far beyond what the film carries presses the journal through it: the dry laws
/// take over at both ends (mode mixed, then dry), with impacts listed.
#[test]
fn overloaded_spatial_film_passes_into_dry_contact() {
    let res = run_spatial(
        lubricated_journal(2e5, 100.0, 0.0, [0.0; 3], FLYWHEEL),
        &SimOptions { rate: Some(1e3), rtol: 1e-9, atol: 1e-14, ..SimOptions::new(0.2) },
    );
    let last = res.time.len() - 1;
    for half in ["p1", "p2"] {
        let mode = channel(&res, &format!("bearing.{half}.film_mode"));
        assert!(mode[0] == 0.0 && mode[last] >= 1.0, "{half}: film mode {} -> {}", mode[0], mode[last]);
    }
    assert!(res.impacts.iter().filter(|i| i.point.unwrap() <= 2).all(|i| !i.impacts.is_empty()));
    let fy = channel(&res, "bearing.fy")[last] + channel(&res, "bearing.film_fy")[last];
    assert!((fy - 2e5).abs() < 1e-3 * 2e5, "force on the journal {fy}");
}

/// Bad input to the spatial joints with contact: each a clear error naming the joint and
/// the key.
#[test]
fn bad_spatial_joint_data_is_named() {
    let error = |edit: &dyn Fn(&mut Value), base: Value| -> String {
        let mut m = base;
        edit(&mut m["joints"][0]);
        match SpatialModel::from_json(&m.to_string()) {
            Err(e) => e.to_string(),
            Ok(model) => {
                simulate_spatial(&model, &SimOptions::new(1e-3), &mut Silent).unwrap_err().to_string()
            }
        }
    };
    let block = || block_in_channel([0.0; 3], [0.0; 3]);
    let journal = || lubricated_journal(1.0, 1.0, 0.0, [0.0; 3], FLYWHEEL);
    for (edit, base, expected) in [
        (&(|j: &mut Value| j["height_axis"] = Value::Null) as &dyn Fn(&mut Value), block(), "height_axis"),
        (&|j: &mut Value| j["height_axis"] = json!([0.1, 1.0, 0.0]), block(), "not perpendicular"),
        (&|j: &mut Value| j["clearance"]["guide_depth"] = Value::Null, block(), "block_depth, guide_depth"),
        (
            &|j: &mut Value| j["clearance"]["block_depth"] = json!(0.03),
            block(),
            "block_depth = 0.03 m does not fit",
        ),
        (&|j: &mut Value| j["clearance"]["block_height"] = json!(0.011), block(), "block_height"),
        (
            &|j: &mut Value| j["type"] = json!("clearance_cylindrical"),
            journal(),
            "'lubrication' belongs to lubricated_cylindrical",
        ),
        (&|j: &mut Value| j["lubrication"]["viscosity"] = json!(0.0), journal(), "viscosity = 0"),
        (&|j: &mut Value| j["lubrication"] = Value::Null, journal(), "lubrication"),
    ] {
        let e = error(edit, base);
        assert!(e.contains(expected), "{e}");
        assert!(e.contains("guide") || e.contains("bearing"), "names the joint: {e}");
    }
}
