//! Plausibility of a model's magnitudes against its own size: warnings, not errors, for
//! values that a mechanism of this size almost never has and that a wrong unit easily
//! gives. A plain number is SI, so `bearing_radius = 7.5` is 7.5 m and `speed = 300` is
//! 300 rad/s (2865 rpm); both are legal, and both are flagged here. The rules are the
//! ones stated in docs/model-file.md ("Plausibility warnings"); each warning names the
//! element, the key and the value in SI units.

use crate::math::Vec2;
use crate::model::{FrictionSpec, JointKind, Model, Profile};
use crate::system::System;

/// Density of osmium, the densest element [kg/m^3]: no body weighs more than a solid
/// osmium cube whose side is the longest link of the mechanism.
const DENSEST: f64 = 22_590.0;
/// Fastest point speed of a linkage [m/s]: the crank pins and pistons of engines stay
/// below about 25 m/s, laboratory linkages below a few m/s.
const POINT_SPEED_LIMIT: f64 = 20.0;
/// Radial clearance above this fraction of the bearing radius is unusual (worn joints
/// reach a few per cent; new ones stay below 1 %).
const CLEARANCE_RATIO: f64 = 0.1;
/// A radius of gyration below this fraction of the body's own length is unusual (a
/// uniform bar's is 0.29 of its length).
const GYRATION_RATIO: f64 = 1e-3;

/// One body's geometry: every point the model places on it (its named points and the
/// points of its joints), in its centre-of-mass frame [m].
struct BodyGeometry {
    points: Vec<Vec2>,
}

impl BodyGeometry {
    /// The largest distance between two of its points or its centre of mass [m].
    fn length(&self) -> f64 {
        let mut all = self.points.clone();
        all.push(Vec2::zeros());
        let mut longest: f64 = 0.0;
        for (k, a) in all.iter().enumerate() {
            for b in &all[k + 1..] {
                longest = longest.max((a - b).norm());
            }
        }
        longest
    }

    /// The largest distance of its points from `centre` [m].
    fn reach(&self, centre: Vec2) -> f64 {
        self.points.iter().chain([Vec2::zeros()].iter()).map(|p| (p - centre).norm()).fold(0.0, f64::max)
    }
}

/// The warnings of a compiled model, in model order (bodies, joints, drivers).
pub(crate) fn warnings(model: &Model, sys: &System) -> Vec<String> {
    let mut geometry: Vec<BodyGeometry> = model
        .bodies
        .iter()
        .map(|b| BodyGeometry { points: b.points.values().map(|p| Vec2::new(p[0], p[1])).collect() })
        .collect();
    for j in &sys.joints {
        let (s_i, s_j) = match j.clearance.and_then(|c| sys.clearances[c].journal_bearing()) {
            Some(g) => (g.s_bearing, g.s_journal),
            None => (j.s_i, j.s_j),
        };
        for (body, s) in [(j.body_i, s_i), (j.body_j, s_j)] {
            if let Some(k) = body {
                geometry[k].points.push(s);
            }
        }
    }
    let lengths: Vec<f64> = geometry.iter().map(BodyGeometry::length).collect();
    let (longest, longest_body) = lengths.iter().zip(&model.bodies).fold((0.0, ""), |(l, n), (&lk, b)| {
        if lk > l {
            (lk, b.name.as_str())
        } else {
            (l, n)
        }
    });
    let scale = format!("the longest link ({} m, body '{longest_body}')", sig(longest));
    let mut out = Vec::new();

    for (k, b) in model.bodies.iter().enumerate() {
        let who = format!("body '{}'", b.name);
        if longest > 0.0 && b.mass > DENSEST * longest.powi(3) {
            out.push(format!(
                "{who}: mass = {} kg is more than a solid osmium cube as large as {scale} would weigh \
                 ({} kg); a plain number is in kg: check the unit",
                given(b.mass),
                sig(DENSEST * longest.powi(3))
            ));
        }
        let gyration = (b.inertia / b.mass).sqrt();
        if longest > 0.0 && gyration > longest {
            out.push(format!(
                "{who}: inertia = {} kg*m^2 puts the radius of gyration sqrt(inertia/mass) at {} m, \
                 beyond {scale}; a plain number is in kg*m^2: check the unit",
                given(b.inertia),
                sig(gyration)
            ));
        } else if b.inertia > 0.0 && gyration < GYRATION_RATIO * lengths[k] {
            out.push(format!(
                "{who}: inertia = {} kg*m^2 puts the radius of gyration sqrt(inertia/mass) at {} m, \
                 below 1/1000 of the body's length ({} m); check the unit",
                given(b.inertia),
                sig(gyration),
                sig(lengths[k])
            ));
        }
        let speed = (b.velocity[0].powi(2) + b.velocity[1].powi(2)).sqrt();
        if speed > POINT_SPEED_LIMIT {
            out.push(format!(
                "{who}: velocity = [{}, {}] m/s ({} m/s){}",
                given(b.velocity[0]),
                given(b.velocity[1]),
                sig(speed),
                too_fast()
            ));
        }
        let reach = geometry[k].reach(Vec2::zeros());
        if b.omega.abs() * reach > POINT_SPEED_LIMIT {
            out.push(format!(
                "{who}: omega = {} rad/s ({} rpm) moves its points at up to {} m/s{}",
                given(b.omega),
                sig(b.omega * 30.0 / std::f64::consts::PI),
                sig(b.omega.abs() * reach),
                too_fast()
            ));
        }
    }

    for (j, info) in model.joints.iter().zip(&sys.joints) {
        let who = format!("joint '{}'", j.name);
        let clearance = info.clearance.map(|c| &sys.clearances[c]);
        if let Some(g) = clearance.and_then(|c| c.journal_bearing()) {
            if longest > 0.0 && g.r_bearing > longest {
                out.push(format!(
                    "{who}: bearing_radius = {} m is {} times {scale}; a plain number is in metres: \
                     check the unit",
                    given(g.r_bearing),
                    sig(g.r_bearing / longest)
                ));
            } else if g.clearance > CLEARANCE_RATIO * g.r_bearing {
                out.push(format!(
                    "{who}: clearance = {} m is {} % of the bearing radius ({} m); radial clearances \
                     are usually below 1 %: check the unit",
                    given(g.clearance),
                    sig(100.0 * g.clearance / g.r_bearing),
                    given(g.r_bearing)
                ));
            }
        }
        if let Some(c) = clearance {
            if let FrictionSpec::Coulomb { mu_s, mu_d, .. } = c.friction() {
                if mu_d > mu_s {
                    out.push(format!(
                        "{who}: friction mu_d = {mu_d} is larger than mu_s = {mu_s}: the dynamic \
                         coefficient is usually the smaller, so the friction force will rise once \
                         sliding starts"
                    ));
                }
            }
        }
    }

    for (d, info) in model.drivers.iter().zip(&sys.drivers) {
        let who = format!("driver '{}'", d.name);
        let speed = fastest(&d.profile);
        let joint = &sys.joints[info.joint];
        if info.rotation {
            // The driven body turns about the joint point: its farthest point is the fastest.
            let reach = match (joint.body_j, joint.body_i) {
                (Some(k), _) => geometry[k].reach(joint.s_j),
                (None, Some(k)) => geometry[k].reach(joint.s_i),
                (None, None) => 0.0,
            };
            if speed * reach > POINT_SPEED_LIMIT {
                out.push(format!(
                    "{who}: speed = {} rad/s ({} rpm) moves the points of the driven body at up to {} m/s{}",
                    given(speed),
                    sig(speed * 30.0 / std::f64::consts::PI),
                    sig(speed * reach),
                    too_fast()
                ));
            }
        } else if speed > POINT_SPEED_LIMIT && joint.kind == JointKind::Prismatic {
            out.push(format!("{who}: speed = {} m/s{}", given(speed), too_fast()));
        }
    }
    out
}

fn too_fast() -> String {
    format!(
        ", faster than {POINT_SPEED_LIMIT} m/s, unusual for a linkage; a plain number is in rad/s \
         or m/s: check the unit (e.g. \"300 rpm\")"
    )
}

/// The largest speed a profile reaches [rad/s or m/s]; for a table of displacements, the
/// largest mean speed between two of its points.
fn fastest(profile: &Profile) -> f64 {
    match profile {
        Profile::ConstantSpeed { speed }
        | Profile::LinearRamp { speed, .. }
        | Profile::SmoothRamp { speed, .. } => speed.abs(),
        Profile::TableSpeed { value, .. } => value.iter().fold(0.0, |m, v| m.max(v.abs())),
        Profile::TableAngle { time, value } => time
            .windows(2)
            .zip(value.windows(2))
            .fold(0.0, |m, (t, v)| m.max(((v[1] - v[0]) / (t[1] - t[0])).abs())),
    }
}

/// A value the user gave, as short as it reads back exactly.
fn given(x: f64) -> String {
    let short = sig(x);
    if short.parse::<f64>() == Ok(x) {
        short
    } else if (1e-4..1e6).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A number with three significant digits, as a message shows it.
fn sig(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs().log10().floor();
    if !(-4.0..6.0).contains(&magnitude) {
        return format!("{x:.2e}");
    }
    let decimals = (2.0 - magnitude).max(0.0) as usize;
    let text = format!("{x:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

#[cfg(test)]
mod tests {
    use super::sig;

    #[test]
    fn three_significant_digits() {
        assert_eq!(sig(2864.788975654116), "2865");
        assert_eq!(sig(0.32), "0.32");
        assert_eq!(sig(7.5), "7.5");
        assert_eq!(sig(23.4375), "23.4");
        assert_eq!(sig(1e308), "1.00e308");
        assert_eq!(sig(-0.000123456), "-0.000123");
        assert_eq!(super::given(692.6), "692.6");
        assert_eq!(super::given(0.0006926), "0.0006926");
        assert_eq!(super::given(31.41592653589793), "31.41592653589793");
        assert_eq!(super::given(1e308), "1.00e308");
    }
}
