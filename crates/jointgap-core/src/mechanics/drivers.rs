//! Motion profiles of drivers: displacement, speed and acceleration against time, and
//! the corner times at which a step must stop because a derivative jumps.

use crate::model::Profile;

/// Displacement, speed and acceleration of a profile at one time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Motion<T = f64> {
    /// Displacement from the initial joint coordinate [rad or m].
    pub position: T,
    /// Speed [rad/s or m/s].
    pub speed: T,
    /// Acceleration [rad/s^2 or m/s^2].
    pub acceleration: T,
}

/// A checked, ready-to-evaluate motion profile.
#[derive(Debug, Clone)]
pub enum MotionProfile {
    /// `theta = w t`.
    Constant {
        /// Speed.
        speed: f64,
    },
    /// Speed `w t / T` up to `T`, then `w`.
    LinearRamp {
        /// Final speed.
        speed: f64,
        /// Ramp time.
        ramp_time: f64,
    },
    /// Speed `w STEP(t, 0, 0, T, 1)`, then `w`.
    SmoothRamp {
        /// Final speed.
        speed: f64,
        /// Ramp time.
        ramp_time: f64,
    },
    /// Natural cubic spline through tabulated displacement.
    Spline(CubicSpline),
    /// Speed linear between points, displacement integrated exactly.
    SpeedTable {
        /// Times.
        time: Vec<f64>,
        /// Speeds.
        speed: Vec<f64>,
        /// Displacement at each table time.
        position: Vec<f64>,
    },
}

/// Natural cubic spline: value, first and second derivative; clamped linearly outside.
#[derive(Debug, Clone)]
pub struct CubicSpline {
    t: Vec<f64>,
    y: Vec<f64>,
    /// Second derivatives at the knots.
    m: Vec<f64>,
}

impl CubicSpline {
    /// Builds the spline (tridiagonal solve); needs >= 2 strictly increasing times.
    pub fn new(t: Vec<f64>, y: Vec<f64>) -> Self {
        let n = t.len();
        let mut m = vec![0.0; n];
        if n > 2 {
            // Thomas algorithm on the interior knots.
            let mut c_prime = vec![0.0; n];
            let mut d_prime = vec![0.0; n];
            for i in 1..n - 1 {
                let h0 = t[i] - t[i - 1];
                let h1 = t[i + 1] - t[i];
                let a = h0 / 6.0;
                let b = (h0 + h1) / 3.0;
                let c = h1 / 6.0;
                let d = (y[i + 1] - y[i]) / h1 - (y[i] - y[i - 1]) / h0;
                let denom = b - a * c_prime[i - 1];
                c_prime[i] = c / denom;
                d_prime[i] = (d - a * d_prime[i - 1]) / denom;
            }
            for i in (1..n - 1).rev() {
                m[i] = d_prime[i] - c_prime[i] * m[i + 1];
            }
        }
        CubicSpline { t, y, m }
    }

    fn eval(&self, x: f64, x_piece: f64) -> Motion {
        let n = self.t.len();
        let (t, y, m) = (&self.t, &self.y, &self.m);
        if x_piece < t[0] || x_piece >= t[n - 1] {
            // Outside the table: continue with the end slope, no acceleration.
            let (i0, i1, at_end) = if x_piece < t[0] { (0, 1, false) } else { (n - 2, n - 1, true) };
            let h = t[i1] - t[i0];
            let slope = if at_end {
                (y[i1] - y[i0]) / h + h * (m[i0] + 2.0 * m[i1]) / 6.0
            } else {
                (y[i1] - y[i0]) / h - h * (2.0 * m[i0] + m[i1]) / 6.0
            };
            let (tx, yx) = if at_end { (t[i1], y[i1]) } else { (t[i0], y[i0]) };
            return Motion { position: yx + slope * (x - tx), speed: slope, acceleration: 0.0 };
        }
        let i = t.partition_point(|&v| v <= x_piece) - 1;
        let h = t[i + 1] - t[i];
        let a = (t[i + 1] - x) / h;
        let b = (x - t[i]) / h;
        let position =
            a * y[i] + b * y[i + 1] + ((a * a * a - a) * m[i] + (b * b * b - b) * m[i + 1]) * h * h / 6.0;
        let speed = (y[i + 1] - y[i]) / h - (3.0 * a * a - 1.0) * h * m[i] / 6.0
            + (3.0 * b * b - 1.0) * h * m[i + 1] / 6.0;
        let acceleration = a * m[i] + b * m[i + 1];
        Motion { position, speed, acceleration }
    }
}

impl MotionProfile {
    /// Checks a profile, naming the driver in errors.
    pub fn new(profile: &Profile, driver: &str) -> Result<Self, crate::error::Error> {
        // The profile's keys, as the model file writes them (`profile.speed`).
        let who = crate::error::Named::driver(driver);
        let error = |key: &str, problem: String| who.error(&format!("profile.{key}"), problem);
        let finite = |what: &str, v: f64| -> Result<(), crate::error::Error> {
            if v.is_finite() {
                Ok(())
            } else {
                Err(error(what, format!("{what} = {v} is not finite")))
            }
        };
        let table = |time: &[f64], value: &[f64]| -> Result<(), crate::error::Error> {
            if time.len() < 2 || time.len() != value.len() {
                return Err(error(
                    "time",
                    format!(
                        "a table needs at least 2 times and as many values (got {} times, {} values)",
                        time.len(),
                        value.len()
                    ),
                ));
            }
            if let Some(k) =
                time.windows(2).position(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
            {
                return Err(error(
                    "time",
                    format!(
                        "table times must increase strictly (time[{}] = {} then {})",
                        k,
                        time[k],
                        time[k + 1]
                    ),
                ));
            }
            if let Some((key, v)) = time
                .iter()
                .map(|v| ("time", v))
                .chain(value.iter().map(|v| ("value", v)))
                .find(|(_, v)| !v.is_finite())
            {
                return Err(error(key, format!("table value {v} is not finite")));
            }
            Ok(())
        };
        Ok(match profile {
            Profile::ConstantSpeed { speed } => {
                finite("speed", *speed)?;
                MotionProfile::Constant { speed: *speed }
            }
            Profile::LinearRamp { speed, ramp_time } | Profile::SmoothRamp { speed, ramp_time } => {
                finite("speed", *speed)?;
                if !(ramp_time.is_finite() && *ramp_time > 0.0) {
                    return Err(error("ramp_time", format!("ramp_time = {ramp_time} s must be positive")));
                }
                if matches!(profile, Profile::LinearRamp { .. }) {
                    MotionProfile::LinearRamp { speed: *speed, ramp_time: *ramp_time }
                } else {
                    MotionProfile::SmoothRamp { speed: *speed, ramp_time: *ramp_time }
                }
            }
            Profile::TableAngle { time, value } => {
                table(time, value)?;
                MotionProfile::Spline(CubicSpline::new(time.clone(), value.clone()))
            }
            Profile::TableSpeed { time, value } => {
                table(time, value)?;
                let mut position = vec![0.0; time.len()];
                for k in 1..time.len() {
                    position[k] = position[k - 1] + 0.5 * (value[k] + value[k - 1]) * (time[k] - time[k - 1]);
                }
                MotionProfile::SpeedTable { time: time.clone(), speed: value.clone(), position }
            }
        })
    }

    /// Displacement, speed and acceleration at time `t`. At a corner the value is that of
    /// the piece that starts there (right limit).
    pub fn motion(&self, t: f64) -> Motion {
        self.motion_on(t, t)
    }

    /// Evaluates, at time `t`, the piece of the profile that contains `t_piece`. The
    /// integrator passes a time inside the current step so that stages on a corner use
    /// the polynomial of the step's own side, where the acceleration jumps.
    pub fn motion_on(&self, t: f64, t_piece: f64) -> Motion {
        const REST: Motion = Motion { position: 0.0, speed: 0.0, acceleration: 0.0 };
        match self {
            MotionProfile::Constant { speed } => {
                Motion { position: speed * t, speed: *speed, acceleration: 0.0 }
            }
            MotionProfile::LinearRamp { speed, ramp_time } => {
                let (w, tr) = (*speed, *ramp_time);
                if t_piece < 0.0 {
                    REST
                } else if t_piece < tr {
                    Motion { position: 0.5 * w * t * t / tr, speed: w * t / tr, acceleration: w / tr }
                } else {
                    Motion { position: 0.5 * w * tr + w * (t - tr), speed: w, acceleration: 0.0 }
                }
            }
            MotionProfile::SmoothRamp { speed, ramp_time } => {
                let (w, tr) = (*speed, *ramp_time);
                if t_piece < 0.0 {
                    REST
                } else if t_piece < tr {
                    let s = t / tr;
                    Motion {
                        position: w * tr * (s * s * s - 0.5 * s * s * s * s),
                        speed: w * s * s * (3.0 - 2.0 * s),
                        acceleration: w * 6.0 * s * (1.0 - s) / tr,
                    }
                } else {
                    Motion { position: 0.5 * w * tr + w * (t - tr), speed: w, acceleration: 0.0 }
                }
            }
            MotionProfile::Spline(spline) => spline.eval(t, t_piece),
            MotionProfile::SpeedTable { time, speed, position } => {
                let n = time.len();
                if t_piece < time[0] {
                    return Motion { position: speed[0] * (t - time[0]), speed: speed[0], acceleration: 0.0 };
                }
                if t_piece >= time[n - 1] {
                    return Motion {
                        position: position[n - 1] + speed[n - 1] * (t - time[n - 1]),
                        speed: speed[n - 1],
                        acceleration: 0.0,
                    };
                }
                let i = time.partition_point(|&v| v <= t_piece) - 1;
                let h = time[i + 1] - time[i];
                let a = (speed[i + 1] - speed[i]) / h;
                let dt = t - time[i];
                Motion {
                    position: position[i] + speed[i] * dt + 0.5 * a * dt * dt,
                    speed: speed[i] + a * dt,
                    acceleration: a,
                }
            }
        }
    }

    /// Times after 0 where the acceleration or its derivative jumps; steps stop there.
    pub fn corners(&self) -> Vec<f64> {
        match self {
            MotionProfile::Constant { .. } => vec![],
            MotionProfile::LinearRamp { ramp_time, .. } | MotionProfile::SmoothRamp { ramp_time, .. } => {
                vec![*ramp_time]
            }
            MotionProfile::Spline(s) => s.t.clone(),
            MotionProfile::SpeedTable { time, .. } => time.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Speed and acceleration of every profile equal the derivatives of its displacement.
    #[test]
    fn derivatives_match_finite_differences() {
        let profiles = [
            Profile::ConstantSpeed { speed: 3.0 },
            Profile::LinearRamp { speed: 31.4, ramp_time: 0.2 },
            Profile::SmoothRamp { speed: 31.4, ramp_time: 0.2 },
            Profile::TableAngle { time: vec![0.0, 0.1, 0.25, 0.4], value: vec![0.0, 0.3, -0.2, 1.0] },
            Profile::TableSpeed { time: vec![0.0, 0.1, 0.3], value: vec![0.0, 2.0, 1.0] },
        ];
        for p in &profiles {
            let mp = MotionProfile::new(p, "d").unwrap();
            for &t in &[0.013, 0.07, 0.15, 0.22, 0.33, 0.5] {
                let e = 1e-6;
                let (a, b) = (mp.motion(t - e), mp.motion(t + e));
                let m = mp.motion(t);
                assert!(
                    ((b.position - a.position) / (2.0 * e) - m.speed).abs() < 1e-6 * (1.0 + m.speed.abs()),
                    "{p:?} t={t}"
                );
                assert!(
                    ((b.speed - a.speed) / (2.0 * e) - m.acceleration).abs()
                        < 1e-4 * (1.0 + m.acceleration.abs()),
                    "{p:?} t={t}"
                );
            }
        }
    }

    #[test]
    fn linear_ramp_reaches_300_rpm() {
        let w = 300.0 * 2.0 * std::f64::consts::PI / 60.0;
        let mp = MotionProfile::new(&Profile::LinearRamp { speed: w, ramp_time: 0.2 }, "motor").unwrap();
        let m = mp.motion(0.2);
        assert!((m.speed - w).abs() < 1e-12);
        assert!((m.position - 0.5 * w * 0.2).abs() < 1e-12);
        assert!((mp.motion(0.1).acceleration - w / 0.2).abs() < 1e-9);
        // At the corner: the ramp's own piece from the left, constant speed from the right.
        assert!((mp.motion_on(0.2, 0.19).acceleration - w / 0.2).abs() < 1e-9);
        assert_eq!(mp.motion(0.2).acceleration, 0.0);
        // At the start the ramp is already accelerating (right limit).
        assert!((mp.motion(0.0).acceleration - w / 0.2).abs() < 1e-9);
        assert_eq!(mp.corners(), vec![0.2]);
    }

    #[test]
    fn spline_interpolates_knots() {
        let mp = MotionProfile::new(
            &Profile::TableAngle { time: vec![0.0, 1.0, 2.0, 3.0], value: vec![0.0, 1.0, 0.0, 2.0] },
            "d",
        )
        .unwrap();
        for (t, v) in [(0.0, 0.0), (1.0, 1.0), (2.0, 0.0), (3.0, 2.0)] {
            assert!((mp.motion(t).position - v).abs() < 1e-12);
            // The piece on either side of a knot meets it too.
            assert!((mp.motion_on(t, t - 0.5).position - v).abs() < 1e-12);
        }
    }

    #[test]
    fn bad_table_names_driver() {
        let e =
            MotionProfile::new(&Profile::TableSpeed { time: vec![0.0, 0.0], value: vec![1.0, 2.0] }, "motor")
                .unwrap_err()
                .to_string();
        assert!(e.contains("driver 'motor'") && e.contains("increase"), "{e}");
    }
}
