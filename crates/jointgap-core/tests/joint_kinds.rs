//! The joints with contact beyond the revolute clearance joint, each against an
//! independent computation: the translational clearance joint (a block dropped flat
//! against the Hertz closed form, the moment of a corner's force, energy over many
//! corner impacts, the first contact of a slider-crank against the smooth mechanism
//! without its guide), joint play (free within the play, the restitution of a linear
//! spring-dashpot stop) and the gear pair (without backlash, a rigid ratio coupling).

use jointgap_core::{simulate, Method, Model, SimOptions, SimResult, Status};
use serde_json::{json, Value};

const K: f64 = 2e9;
/// Block 40 x 10 mm in a guide 10.5 mm wide: 0.25 mm of play on each side.
const LENGTH: f64 = 0.04;
const HEIGHT: f64 = 0.01;
const WIDTH: f64 = 0.0105;

fn model(v: Value) -> Model {
    Model::from_json(&v.to_string()).unwrap()
}

fn run(m: &Model, opts: &SimOptions) -> SimResult {
    let res = simulate(m, opts).unwrap();
    assert_eq!(res.status, Status::Finished, "{:?}", res.status);
    res
}

fn channel<'a>(res: &'a SimResult, name: &str) -> &'a [f64] {
    res.channel(name).unwrap_or_else(|| panic!("no channel {name} in {:?}", res.names))
}

/// A free block (mass `m`, inertia `i`) in a ground guide along x, placed at `y` and
/// angle `phi` with velocity `v` and spin `omega`.
fn block_in_guide(y: f64, phi: f64, v: [f64; 2], omega: f64, law: Value) -> Model {
    model(json!({
        "gravity": [0.0, 0.0],
        "bodies": [{"name": "block", "mass": 0.5, "inertia": 1e-4, "position": [0.0, y], "angle": phi,
                    "velocity": v, "omega": omega}],
        "joints": [{"name": "guide", "type": "clearance_translational", "body_i": "ground", "point_i": [0.0, 0.0],
                    "body_j": "block", "point_j": [0.0, 0.0], "axis": [1.0, 0.0],
                    "clearance": {"block_length": LENGTH, "block_height": HEIGHT, "guide_width": WIDTH,
                                  "stiffness": K, "normal_law": law}}]
    }))
}

/// Dropped flat onto the lower surface, the block lands on its two lower corners at
/// once: each carries `K delta^1.5`, so the peak penetration is
/// `(5 m v0^2 / (8 K))^(2/5)` and the contact lasts `2.94 delta_max / v0` (the Hertz
/// impact of mass m on a stiffness 2K), and the rebound is elastic.
#[test]
fn block_dropped_flat_matches_hertz() {
    let (m, v0) = (0.5, 0.4);
    let gap = 0.5 * (WIDTH - HEIGHT);
    let res = run(
        &block_in_guide(0.0, 0.0, [0.3, -v0], 0.0, json!({"type": "hertz"})),
        &SimOptions {
            rate: Some(2e7),
            rtol: 1e-10,
            atol: 1e-14,
            method: Method::Dopri5,
            ..SimOptions::new(2.5 * gap / v0)
        },
    );
    let delta_max = (5.0 * m * v0 * v0 / (8.0 * K)).powf(0.4);
    for (point, name) in [(3, "p3"), (4, "p4")] {
        let impacts = &res.impacts.iter().find(|i| i.point == Some(point)).unwrap().impacts;
        assert_eq!(impacts.len(), 1, "{name}: {impacts:?}");
        let imp = &impacts[0];
        assert!((imp.onset_time - gap / v0).abs() < 1e-9, "{name} onset at {}", imp.onset_time);
        assert!(
            (imp.max_penetration / delta_max - 1.0).abs() < 5e-3,
            "{name}: {} vs {delta_max}",
            imp.max_penetration
        );
        let duration = imp.duration.expect("separated");
        assert!((duration / (2.94 * delta_max / v0) - 1.0).abs() < 5e-3, "{name} duration {duration:e}");
        assert!(
            (imp.peak_force / (K * delta_max.powf(1.5)) - 1.0).abs() < 5e-3,
            "{name} peak {}",
            imp.peak_force
        );
    }
    // The upper corners never touch, the block neither turns nor slows along the guide.
    for point in [1, 2] {
        assert!(res.impacts.iter().find(|i| i.point == Some(point)).unwrap().impacts.is_empty());
    }
    let last = |c: &str| *channel(&res, c).last().unwrap();
    assert!((last("block.vy") - v0).abs() < 1e-6 * v0, "rebound {}", last("block.vy"));
    assert!(last("block.omega").abs() < 1e-9 && (last("block.vx") - 0.3).abs() < 1e-12);
}

/// Turning as it falls, the block meets the guide at its lowest corner first (the rear
/// lower one for a counter-clockwise tilt), and while that corner alone touches, the
/// block's angular acceleration is the moment of the corner's force about its centre
/// over its inertia, `(c - r) x F / I`, and its acceleration the force over its mass.
#[test]
fn tilted_block_touches_at_one_corner_with_its_moment() {
    let res = run(
        &block_in_guide(0.0, 0.0, [0.0, -0.3], 5.0, json!({"type": "hertz"})),
        &SimOptions {
            rate: Some(1e6),
            rtol: 1e-10,
            atol: 1e-14,
            method: Method::Dopri5,
            ..SimOptions::new(3e-3)
        },
    );
    let first = res
        .impacts
        .iter()
        .filter_map(|i| i.impacts.first().map(|imp| (imp.onset_time, i.point.unwrap())))
        .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a });
    assert_eq!(first.1, 3, "first corner to touch: {first:?}");
    let phi = channel(&res, "block.angle");
    let (ax, ay, alpha) =
        (channel(&res, "block.ax"), channel(&res, "block.ay"), channel(&res, "block.alpha"));
    let fns: Vec<&[f64]> = (1..=4).map(|p| channel(&res, &format!("guide.p{p}.fn"))).collect();
    let mut checked = 0;
    for k in 0..res.time.len() {
        let alone = fns[2][k] > 0.0 && [0, 1, 3].iter().all(|&p| fns[p][k] == 0.0);
        if !alone {
            continue;
        }
        // The rear lower corner, from the block's pose.
        let (c, s) = (phi[k].cos(), phi[k].sin());
        let arm = [-0.5 * LENGTH * c + 0.5 * HEIGHT * s, -0.5 * LENGTH * s - 0.5 * HEIGHT * c];
        let moment = arm[0] * fns[2][k]; // F = (0, F_N) on the block
        assert!((alpha[k] * 1e-4 - moment).abs() < 1e-9 * moment.abs().max(1e-6), "t = {}", res.time[k]);
        assert!((ay[k] * 0.5 - fns[2][k]).abs() < 1e-9 * fns[2][k] && ax[k].abs() < 1e-9);
        checked += 1;
    }
    assert!(checked > 20, "only {checked} samples with the one corner in contact");
}

/// Elastic corners without friction conserve kinetic plus contact energy over many
/// impacts of a block sliding, rattling and turning in its guide.
#[test]
fn elastic_corners_conserve_energy_over_many_impacts() {
    let res = run(
        &block_in_guide(0.0, 0.0, [0.5, 0.2], 1.5, json!({"type": "hertz"})),
        &SimOptions {
            rate: Some(1e5),
            rtol: 1e-10,
            atol: 1e-14,
            method: Method::Dopri5,
            ..SimOptions::new(0.05)
        },
    );
    let impacts: usize = res.impacts.iter().map(|i| i.impacts.len()).sum();
    assert!(impacts >= 20, "{impacts} impacts");
    assert!(res.impacts.iter().all(|i| !i.impacts.is_empty()), "every corner touches");
    let (ke, pe) = (channel(&res, "system.kinetic_energy"), channel(&res, "system.potential_energy"));
    let e0 = ke[0] + pe[0];
    let drift = ke.iter().zip(pe).map(|(k, p)| ((k + p) / e0 - 1.0).abs()).fold(0.0, f64::max);
    assert!(drift < 1e-6, "energy drift {drift:e}");
    let vx = channel(&res, "block.vx");
    assert!(vx.iter().all(|v| (v - 0.5).abs() < 1e-9), "frictionless: the slide along the guide is kept");
}

/// The founding slider-crank (crank 0.05 m, rod 0.12 m, at 5000 rpm after a ramp,
/// docs/tutorial-founding-case.md) whose slider has play in its guide.
fn slider_crank(guide: Option<Value>) -> Model {
    let mut joints = vec![
        json!({"name": "crank_pin", "type": "revolute", "body_i": "ground", "point_i": [0.0, 0.0], "body_j": "crank", "point_j": [-0.025, 0.0]}),
        json!({"name": "crank_rod", "type": "revolute", "body_i": "crank", "point_i": [0.025, 0.0], "body_j": "rod", "point_j": [-0.06, 0.0]}),
        json!({"name": "rod_slider", "type": "revolute", "body_i": "rod", "point_i": [0.06, 0.0], "body_j": "slider", "point_j": [0.0, 0.0]}),
    ];
    joints.extend(guide);
    model(json!({
        "bodies": [
            {"name": "crank", "mass": 0.3, "inertia": 1e-4, "position": [0.025, 0.0]},
            {"name": "rod", "mass": 0.21, "inertia": 2.5e-4, "position": [0.11, 0.0]},
            {"name": "slider", "mass": 0.14, "inertia": 1e-5, "position": [0.17, 0.0]}
        ],
        "joints": joints,
        "drivers": [{"name": "motor", "joint": "crank_pin",
                     "profile": {"type": "smooth_ramp", "speed": 523.6, "ramp_time": 0.01}}]
    }))
}

/// Until the slider first meets its guide, the mechanism with a translational
/// clearance joint moves as the same mechanism without the guide (no force acts): the
/// first onset the clearance joint locates is the first time, in a run of the
/// guide-less mechanism, that a corner of the slider reaches a surface, found here from
/// its pose by the corners' own geometry.
#[test]
fn slider_crank_first_contact_matches_the_smooth_mechanism() {
    let guide = json!({"name": "guide", "type": "clearance_translational", "body_i": "ground", "point_i": [0.0, 0.0],
        "body_j": "slider", "point_j": [0.0, 0.0], "axis": [1.0, 0.0],
        "clearance": {"block_length": LENGTH, "block_height": HEIGHT, "guide_width": WIDTH, "stiffness": K,
                      "normal_law": {"type": "hertz"}}});
    let opts = SimOptions {
        rate: Some(2e5),
        rtol: 1e-10,
        atol: 1e-14,
        method: Method::Dopri5,
        ..SimOptions::new(0.03)
    };
    let with_guide = run(&slider_crank(Some(guide)), &opts);
    let onset = with_guide
        .impacts
        .iter()
        .filter_map(|i| i.impacts.first().map(|imp| imp.onset_time))
        .fold(f64::INFINITY, f64::min);
    assert!(onset.is_finite() && onset < 0.03, "no contact: {onset}");
    let free = run(&slider_crank(None), &SimOptions { t_end: onset * 1.2, ..opts });
    let (y, phi) = (channel(&free, "slider.y"), channel(&free, "slider.angle"));
    // The largest excess of a corner over the half width: |y| + L/2 |sin| + h/2 cos.
    let excess: Vec<f64> = y
        .iter()
        .zip(phi)
        .map(|(y, p)| y.abs() + 0.5 * LENGTH * p.sin().abs() + 0.5 * HEIGHT * p.cos() - 0.5 * WIDTH)
        .collect();
    let k = excess.iter().position(|&e| e > 0.0).expect("the free slider leaves the guide's width");
    let (t0, t1) = (free.time[k - 1], free.time[k]);
    let crossing = t0 + (t1 - t0) * (-excess[k - 1]) / (excess[k] - excess[k - 1]);
    assert!((crossing - onset).abs() < 2e-7, "first contact at {onset} vs the free mechanism's {crossing}");
}

/// A wheel on a revolute joint with play turns freely through the play: no torque,
/// constant speed, until it meets the stop exactly at `(play/2) / omega`. A linear
/// spring-dashpot stop (Kelvin-Voigt, n = 1, not clipped) returns it at
/// `exp(-zeta pi / sqrt(1 - zeta^2))` times its approach speed,
/// `zeta = c / (2 sqrt(K J))`: the damped oscillator's half period.
#[test]
fn revolute_play_is_free_then_stops_with_the_laws_restitution() {
    let (j, omega, play, k, c): (f64, f64, f64, f64, f64) = (2e-3, 3.0, 0.02, 500.0, 0.06);
    let m = model(json!({
        "gravity": [0.0, 0.0],
        "bodies": [{"name": "wheel", "mass": 1.0, "inertia": j, "omega": omega}],
        "joints": [{"name": "hub", "type": "revolute_with_play", "body_i": "ground", "point_i": [0.0, 0.0],
                    "body_j": "wheel", "point_j": [0.0, 0.0],
                    "play": {"play": play, "stiffness": k,
                             "normal_law": {"type": "kelvin_voigt", "exponent": 1.0, "damping": c, "clip": false}}}]
    }));
    let res = run(
        &model_clone(&m),
        &SimOptions {
            rate: Some(1e5),
            rtol: 1e-11,
            atol: 1e-14,
            method: Method::Dopri5,
            ..SimOptions::new(0.03)
        },
    );
    let impacts = &res.impacts[0].impacts;
    assert!(!impacts.is_empty());
    let hit = 0.5 * play / omega;
    assert!((impacts[0].onset_time - hit).abs() < 1e-10, "onset {} vs {hit}", impacts[0].onset_time);
    let (torque, w, angle) =
        (channel(&res, "hub.torque"), channel(&res, "wheel.omega"), channel(&res, "hub.play_angle"));
    for i in 0..res.time.len() {
        if res.time[i] < hit {
            assert_eq!(torque[i], 0.0, "torque inside the play at t = {}", res.time[i]);
            assert!((w[i] - omega).abs() < 1e-12 && (angle[i] - omega * res.time[i]).abs() < 1e-12);
        }
    }
    let zeta = c / (2.0 * (k * j).sqrt());
    let expected = (-zeta * std::f64::consts::PI / (1.0 - zeta * zeta).sqrt()).exp();
    let duration = impacts[0].duration.expect("separated");
    let back = res.time.iter().position(|&t| t > impacts[0].onset_time + duration + 1e-4).unwrap();
    assert!((-w[back] / omega - expected).abs() < 1e-6, "restitution {} vs {expected}", -w[back] / omega);
    let period = std::f64::consts::PI / ((k / j).sqrt() * (1.0 - zeta * zeta).sqrt());
    assert!((duration / period - 1.0).abs() < 1e-6, "duration {duration} vs {period}");
}

fn model_clone(m: &Model) -> Model {
    m.clone()
}

/// A slider on a prismatic joint with play travels freely, then bounces between its
/// elastic stops conserving energy, the stops' force the only force along the axis.
#[test]
fn prismatic_play_bounces_between_its_stops() {
    let m = model(json!({
        "gravity": [0.0, -9.81],
        "bodies": [{"name": "slider", "mass": 0.2, "inertia": 1e-4, "position": [0.1, 0.0], "velocity": [0.5, 0.0]}],
        "joints": [{"name": "rail", "type": "prismatic_with_play", "body_i": "ground", "point_i": [0.0, 0.0],
                    "body_j": "slider", "point_j": [0.0, 0.0], "axis": [1.0, 0.0],
                    "play": {"play": 0.004, "stiffness": 1e8, "normal_law": {"type": "hertz"}}}]
    }));
    let res = run(
        &m,
        &SimOptions {
            rate: Some(1e5),
            rtol: 1e-10,
            atol: 1e-14,
            method: Method::Dopri5,
            ..SimOptions::new(0.05)
        },
    );
    assert!(res.impacts[0].impacts.len() >= 5);
    let (x, vx, f) = (channel(&res, "slider.x"), channel(&res, "slider.vx"), channel(&res, "rail.force"));
    assert!(x.iter().all(|x| (x - 0.1).abs() < 0.002 + 2.5e-4), "stays within the play");
    // Between the stops the speed is the initial one (each rebound elastic, to the
    // integration's accuracy).
    assert!(vx.iter().zip(f).all(|(v, f)| *f != 0.0 || (v.abs() - 0.5).abs() < 1e-6));
    let ax = channel(&res, "slider.ax");
    assert!(ax.iter().zip(f).all(|(a, f)| (a * 0.2 - f).abs() < 1e-9 * f.abs().max(1.0)));
    let (ke, pe) = (channel(&res, "system.kinetic_energy"), channel(&res, "system.potential_energy"));
    let drift = ke.iter().zip(pe).map(|(k, p)| ((k + p) / (ke[0] + pe[0]) - 1.0).abs()).fold(0.0, f64::max);
    assert!(drift < 1e-6, "energy drift {drift:e}");
}

/// Two gears without backlash, stiff and damped, driven from rest by a torque T on
/// gear 1: they move as the rigid ratio coupling `phi_2 = -phi_1 / n`, with
/// `phi_1'' = T / (J1 + J2 / n^2)`, and the tooth torque on gear 2 is `J2 phi_2''`.
#[test]
fn gear_pair_without_backlash_is_a_rigid_ratio_coupling() {
    let (r1, n, j1, j2, torque) = (0.03, 2.5, 4e-4, 3e-3, 2.0);
    let k = 1e8;
    let m = model(json!({
        "gravity": [0.0, 0.0],
        "bodies": [
            {"name": "pinion", "mass": 0.3, "inertia": j1, "position": [0.0, 0.0]},
            {"name": "wheel", "mass": 1.2, "inertia": j2, "position": [r1 * (1.0 + n), 0.0]}
        ],
        "joints": [
            {"name": "pinion_pin", "type": "revolute", "body_i": "ground", "point_i": [0.0, 0.0], "body_j": "pinion", "point_j": [0.0, 0.0]},
            {"name": "wheel_pin", "type": "revolute", "body_i": "ground", "point_i": [r1 * (1.0 + n), 0.0], "body_j": "wheel", "point_j": [0.0, 0.0]},
            {"name": "mesh", "type": "gear_pair", "body_i": "pinion", "point_i": [0.0, 0.0], "body_j": "wheel", "point_j": [0.0, 0.0],
             "gear": {"ratio": n, "pitch_radius": r1, "backlash": 0.0, "mesh_stiffness": k,
                      "normal_law": {"type": "kelvin_voigt", "exponent": 1.0, "damping": 4e3}}}
        ],
        "forces": [{"type": "applied_torque", "name": "motor", "body": "pinion", "torque": torque}]
    }));
    let res = run(&m, &SimOptions { rate: Some(1e4), rtol: 1e-10, atol: 1e-14, ..SimOptions::new(0.2) });
    let alpha_1 = torque / (j1 + j2 / (n * n));
    let (p1, p2) = (channel(&res, "pinion.angle"), channel(&res, "wheel.angle"));
    let (t2, t1) = (channel(&res, "mesh.torque_2"), channel(&res, "mesh.torque_1"));
    let last = res.time.len() - 1;
    let t = res.time[last];
    assert!(
        (p1[last] / (0.5 * alpha_1 * t * t) - 1.0).abs() < 1e-4,
        "pinion {} vs {}",
        p1[last],
        0.5 * alpha_1 * t * t
    );
    assert!(
        (p2[last] + p1[last] / n).abs() < 1e-4 * p1[last].abs(),
        "ratio: {} vs {}",
        p2[last],
        -p1[last] / n
    );
    for i in (last / 2)..=last {
        assert!(
            (t2[i] - j2 * (-alpha_1 / n)).abs() < 1e-3 * j2 * alpha_1 / n,
            "tooth torque on the wheel {}",
            t2[i]
        );
        assert!(
            (t1[i] - (j1 * alpha_1 - torque)).abs() < 1e-3 * torque,
            "tooth torque on the pinion {}",
            t1[i]
        );
    }
}

/// A block taller than its guide, a negative play, a zero viscosity, a zero gear ratio:
/// each refused with an error naming the joint and the value.
#[test]
fn bad_joint_data_is_named() {
    let law = json!({"type": "hertz"});
    let cases = [
        (
            json!({"name": "j", "type": "clearance_translational", "body_i": "ground", "point_i": [0, 0], "body_j": "b", "point_j": [0, 0],
                   "axis": [1, 0], "clearance": {"block_length": 0.04, "block_height": 0.011, "guide_width": 0.0105, "stiffness": K, "normal_law": law}}),
            "block_height = 0.011 m does not fit the guide",
        ),
        (
            json!({"name": "j", "type": "revolute_with_play", "body_i": "ground", "point_i": [0, 0], "body_j": "b", "point_j": [0, 0],
                   "play": {"play": -0.01, "stiffness": 10.0, "normal_law": law}}),
            "play = -0.01 rad must be zero or positive",
        ),
        (
            json!({"name": "j", "type": "lubricated_revolute", "body_i": "ground", "point_i": [0, 0], "body_j": "b", "point_j": [0, 0],
                   "clearance": {"bearing_radius": 0.01, "clearance": 1e-4, "stiffness": K, "normal_law": law},
                   "lubrication": {"length": 0.02, "viscosity": 0.0}}),
            "viscosity = 0 Pa s must be positive",
        ),
        (
            json!({"name": "j", "type": "gear_pair", "body_i": "ground", "point_i": [0, 0], "body_j": "b", "point_j": [0, 0],
                   "gear": {"ratio": 0.0, "pitch_radius": 0.02, "mesh_stiffness": 1e8, "normal_law": law}}),
            "ratio = 0 must be positive",
        ),
        (
            json!({"name": "j", "type": "gear_pair", "body_i": "ground", "point_i": [0, 0], "body_j": "b", "point_j": [0, 0],
                   "gear": {"ratio": 2.0, "pitch_radius": 0.02, "mesh_stiffness": 1e8, "normal_law": law}}),
            "the gears' centres are 0.000000 m apart",
        ),
        (
            json!({"name": "j", "type": "revolute_with_play", "body_i": "ground", "point_i": [0, 0], "body_j": "b", "point_j": [0, 0]}),
            "a revolute_with_play joint needs its 'play' table",
        ),
    ];
    for (joint, expected) in cases {
        let m = model(json!({"bodies": [{"name": "b", "mass": 1.0, "inertia": 1e-3}], "joints": [joint]}));
        let err = simulate(&m, &SimOptions::new(0.01)).unwrap_err().to_string();
        assert!(err.contains("joint 'j'") && err.contains(expected), "{err}\n expected {expected}");
    }
}

/// A joint keeps the tables its type does not use, with a warning that names them, so
/// that its kind changes by its type alone.
#[test]
fn unused_tables_are_kept_with_a_warning() {
    let m = model(json!({
        "gravity": [0.0, 0.0],
        "bodies": [{"name": "b", "mass": 1.0, "inertia": 1e-3}],
        "joints": [{"name": "j", "type": "revolute", "body_i": "ground", "point_i": [0, 0], "body_j": "b", "point_j": [0, 0],
                    "clearance": {"bearing_radius": 0.01, "clearance": 1e-4, "stiffness": K, "normal_law": {"type": "hertz"}},
                    "lubrication": {"length": 0.02, "viscosity": 0.05}}]
    }));
    let res = run(&m, &SimOptions::new(0.01));
    for table in ["clearance", "lubrication"] {
        assert!(
            res.warnings.iter().any(|w| w.contains("joint 'j'") && w.contains(&format!("'{table}' table"))),
            "{:?}",
            res.warnings
        );
    }
}

/// Gears with backlash: the pinion turns freely until its tooth has crossed half the
/// backlash on the pitch circle, `t = (b / 2) / (r1 omega)`, with the wheel at rest and
/// no tooth force; a mesh stiffness given as a table against the pinion's angle is read
/// there, periodic over the table's span.
#[test]
fn gear_backlash_is_crossed_freely_and_the_mesh_stiffness_follows_its_table() {
    let (r1, n, omega, backlash) = (0.02, 2.0, 4.0, 0.4e-3);
    let table = json!({"angle": [0.0, 0.1, 0.2, 0.3142], "value": [1e8, 1.5e8, 1.5e8, 1e8]});
    let m = model(json!({
        "gravity": [0.0, 0.0],
        "bodies": [
            {"name": "pinion", "mass": 0.3, "inertia": 1e-4, "omega": omega},
            {"name": "wheel", "mass": 1.2, "inertia": 2e-3, "position": [r1 * (1.0 + n), 0.0]}
        ],
        "joints": [
            {"name": "pinion_pin", "type": "revolute", "body_i": "ground", "point_i": [0.0, 0.0], "body_j": "pinion", "point_j": [0.0, 0.0]},
            {"name": "wheel_pin", "type": "revolute", "body_i": "ground", "point_i": [r1 * (1.0 + n), 0.0], "body_j": "wheel", "point_j": [0.0, 0.0]},
            {"name": "mesh", "type": "gear_pair", "body_i": "pinion", "point_i": [0.0, 0.0], "body_j": "wheel", "point_j": [0.0, 0.0],
             "gear": {"ratio": n, "pitch_radius": r1, "backlash": backlash, "mesh_stiffness": table,
                      "normal_law": {"type": "hertz", "exponent": 1.0}}}
        ]
    }));
    let res = run(
        &m,
        &SimOptions {
            rate: Some(1e5),
            rtol: 1e-11,
            atol: 1e-14,
            method: Method::Dopri5,
            ..SimOptions::new(0.01)
        },
    );
    let hit = 0.5 * backlash / (r1 * omega);
    let onset = res.impacts[0].impacts[0].onset_time;
    assert!((onset - hit).abs() < 1e-10, "onset {onset} vs {hit}");
    let (w2, f, k) =
        (channel(&res, "wheel.omega"), channel(&res, "mesh.fn"), channel(&res, "mesh.stiffness"));
    let angle = channel(&res, "pinion.angle");
    let mean = (1e8 + 1.5e8 + 1.5e8 + 1e8) / 4.0;
    for i in 0..res.time.len() {
        if res.time[i] < hit {
            assert!(w2[i] == 0.0 && f[i] == 0.0, "t = {}", res.time[i]);
        }
        // The line of centres stays along x: the pinion's angle is its angle to it.
        let x = angle[i].rem_euclid(0.3142);
        let expected = if x < 0.1 {
            1e8 + 5e7 * x / 0.1
        } else if x < 0.2 {
            1.5e8
        } else {
            1.5e8 - 5e7 * (x - 0.2) / 0.1142
        };
        assert!((k[i] - expected).abs() < 1e-6 * mean, "stiffness {} vs {expected} at {x}", k[i]);
    }
}

/// A spatial wheel on a revolute joint with play about a tilted axis, and a spatial
/// slider on a prismatic joint with play: as the planar ones, free through the play (no
/// torque, constant speed) until `(p/2) / speed`, then the linear spring-dashpot stop
/// returns them at `exp(-zeta pi / sqrt(1 - zeta^2))` times their approach speed.
#[test]
fn spatial_joints_with_play_are_free_then_stop_with_the_laws_restitution() {
    use jointgap_core::model::spatial::SpatialModel;
    use jointgap_core::simulate::{simulate_spatial, Silent};
    let (play, k, c): (f64, f64, f64) = (0.02, 500.0, 0.06);
    let axis = [0.0, 0.6, 0.8];
    let law = json!({"type": "kelvin_voigt", "exponent": 1.0, "damping": c, "clip": false});
    for (kind, inertia, speed, name) in
        [("revolute_with_play", 2e-3, 3.0, "hub"), ("prismatic_with_play", 2e-3, 0.5, "rail")]
    {
        let rotation = kind == "revolute_with_play";
        let motion = axis.map(|a| a * speed);
        let model = json!({
            "dimension": 3, "gravity": [0.0, 0.0, 0.0],
            "bodies": [{"name": "part", "mass": inertia, "inertia": {"principal": {"moments": [inertia, inertia, inertia]}},
                        "angular_velocity": if rotation { motion } else { [0.0; 3] },
                        "velocity": if rotation { [0.0; 3] } else { motion }}],
            "joints": [{"name": name, "type": kind, "body_i": "ground", "point_i": [0.0, 0.0, 0.0],
                        "body_j": "part", "point_j": [0.0, 0.0, 0.0], "axis": axis,
                        "play": {"play": play, "stiffness": k, "normal_law": law}}]
        });
        let model = SpatialModel::from_json(&model.to_string()).unwrap();
        let opts = SimOptions {
            rate: Some(1e5),
            rtol: 1e-11,
            atol: 1e-14,
            method: Method::Dopri5,
            ..SimOptions::new(0.03)
        };
        let res = simulate_spatial(&model, &opts, &mut Silent).unwrap();
        assert_eq!(res.status, Status::Finished, "{kind}: {:?}", res.status);
        let impacts = &res.impacts[0].impacts;
        let hit = 0.5 * play / speed;
        assert!(
            (impacts[0].onset_time - hit).abs() < 1e-10,
            "{kind}: onset {} vs {hit}",
            impacts[0].onset_time
        );
        let effort = channel(&res, &format!("{name}.{}", if rotation { "torque" } else { "force" }));
        let rate = channel(&res, &format!("{name}.{}", if rotation { "omega" } else { "speed" }));
        for i in 0..res.time.len() {
            if res.time[i] < hit {
                assert!(effort[i] == 0.0 && (rate[i] - speed).abs() < 1e-12, "{kind} at t = {}", res.time[i]);
            }
        }
        let zeta = c / (2.0 * (k * inertia).sqrt());
        let expected = (-zeta * std::f64::consts::PI / (1.0 - zeta * zeta).sqrt()).exp();
        let back = impacts[0].onset_time + impacts[0].duration.expect("separated") + 1e-4;
        let after = res.time.iter().position(|&t| t > back).unwrap();
        assert!(
            (-rate[after] / speed - expected).abs() < 1e-6,
            "{kind}: restitution {} vs {expected}",
            -rate[after] / speed
        );
    }
}

/// A journal spinning at `omega` in a fixed lubricated bearing (short film) under a
/// constant load `W` along -y (no gravity).
fn loaded_journal(load: f64, omega: f64, film: &str, t_end: f64) -> SimResult {
    let (c, r, l, mu) = (5e-5, 0.02, 0.01, 0.05);
    let m = model(json!({
        "gravity": [0.0, 0.0],
        // A heavy flywheel keeps the spin: the film's torque changes it by < 1e-6 relative.
        "bodies": [{"name": "journal", "mass": 1.0, "inertia": 50.0, "omega": omega}],
        "joints": [{"name": "bearing", "type": "lubricated_revolute", "body_i": "ground", "point_i": [0.0, 0.0],
                    "body_j": "journal", "point_j": [0.0, 0.0],
                    "clearance": {"journal_radius": r, "clearance": c, "stiffness": 1e10,
                                  "normal_law": {"type": "hunt_crossley", "restitution": 0.5}},
                    "lubrication": {"length": l, "viscosity": mu, "film": film}}],
        "forces": [{"type": "applied_force", "name": "load", "body": "journal", "force": [0.0, -load]}]
    }));
    run(&m, &SimOptions { rate: Some(1e3), rtol: 1e-9, atol: 1e-14, ..SimOptions::new(t_end) })
}

/// Under a constant load the journal settles where the short bearing's steady film
/// carries it: the eccentricity ratio of Ocvirk's load relation
/// `W = mu omega R L^3 / (4 c^2) eps / (1 - eps^2)^2 sqrt(16 eps^2 + pi^2 (1 - eps^2))`
/// and the attitude angle `tan(phi) = pi sqrt(1 - eps^2) / (4 eps)` between the load line
/// and the line of centres, the journal displaced from the load line in the sense of its
/// spin; the film carries the load alone (no contact) and its force balances it.
#[test]
fn loaded_journal_settles_at_the_ocvirk_eccentricity_and_attitude() {
    let (c, r, l, mu, omega): (f64, f64, f64, f64, f64) = (5e-5, 0.02, 0.01, 0.05, 100.0);
    let eps: f64 = 0.6;
    let pi = std::f64::consts::PI;
    let load = mu * omega * r * l.powi(3) / (4.0 * c * c) * eps / (1.0 - eps * eps).powi(2)
        * (16.0 * eps * eps + pi * pi * (1.0 - eps * eps)).sqrt();
    let res = loaded_journal(load, omega, "short", 0.5);
    let last = res.time.len() - 1;
    let ratio = channel(&res, "bearing.eccentricity_ratio")[last];
    assert!((ratio - eps).abs() < 1e-4, "eccentricity ratio {ratio} vs {eps}");
    let (ex, ey) = (channel(&res, "bearing.ex")[last], channel(&res, "bearing.ey")[last]);
    // The load points along -y; the line of centres is turned from it by +phi (the spin
    // is counter-clockwise).
    let phi = f64::atan2(ex, -ey);
    let expected = (pi * (1.0 - eps * eps).sqrt() / (4.0 * eps)).atan();
    assert!((phi - expected).abs() < 1e-4, "attitude {phi} vs {expected}");
    let (fx, fy) = (channel(&res, "bearing.film_fx")[last], channel(&res, "bearing.film_fy")[last]);
    assert!((fy - load).abs() < 1e-6 * load && fx.abs() < 1e-6 * load, "film force ({fx}, {fy}) vs {load}");
    assert!(channel(&res, "bearing.film_mode").iter().all(|&m| m == 0.0));
    assert!(res.impacts[0].impacts.is_empty());
    // The shear torque at the steady state: Petroff's over sqrt(1 - eps^2), less e F_t / 2
    // (F_t the film force across the line of centres).
    let couette = -2.0 * pi * mu * r.powi(3) * l * omega / (c * (1.0 - eps * eps).sqrt());
    let across = -load * phi.sin(); // the load's part across n, which the film balances
    let torque = channel(&res, "bearing.friction_torque")[last];
    let expected_torque = couette - 0.5 * eps * c * (-across);
    assert!(
        (torque - expected_torque).abs() < 1e-3 * expected_torque.abs(),
        "torque {torque} vs {expected_torque}"
    );
}

/// A load far beyond what the film can carry at its threshold (three times the
/// roughness) presses the journal through the film: the dry laws take over (mode mixed,
/// then dry contact), an impact is listed, and at rest the film's force at the capped
/// eccentricity and the dry contact force together balance the load.
#[test]
fn overloaded_film_passes_into_dry_contact() {
    let res = loaded_journal(2e5, 100.0, "short", 0.2);
    let last = res.time.len() - 1;
    let mode = channel(&res, "bearing.film_mode");
    assert!(mode[0] == 0.0 && mode[last] >= 1.0, "film mode {} -> {}", mode[0], mode[last]);
    assert!(!res.impacts[0].impacts.is_empty(), "the dry laws' onset is located");
    let thickness = channel(&res, "bearing.film_thickness")[last];
    assert!(thickness < 3e-6, "film thickness {thickness} below the threshold");
    let (fx, fy) = (channel(&res, "bearing.fx")[last], channel(&res, "bearing.fy")[last]);
    assert!((fy - 2e5).abs() < 1e-3 * 2e5 && fx.abs() < 1e-3 * 2e5, "force on the journal ({fx}, {fy})");
    let dry = channel(&res, "bearing.fn")[last];
    let film = channel(&res, "bearing.film_fy")[last];
    assert!(dry > 0.0 && film > 0.0 && dry > film, "dry {dry} and film {film}");
}
