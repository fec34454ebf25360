//! Normal contact force laws (docs/physics.md section 3).

use crate::error::ElementError;
use crate::error::Error;
use crate::model::NormalLawSpec;
use crate::scalar::Real;

/// A checked normal law; `k` and `n` are the stiffness and exponent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NormalLaw {
    /// `K delta^n`.
    Hertz,
    /// `K delta^n + c delta_dot`.
    KelvinVoigt {
        /// Damping c [N s/m].
        damping: f64,
    },
    /// `K delta^n (1 + h delta_dot / delta_dot(-))`: the hysteresis family (Hunt-Crossley,
    /// Lankarani-Nikravesh, Gonthier, Flores), which differ only in the factor `h(r)`.
    Hysteresis {
        /// Damping factor h(r).
        factor: f64,
    },
    /// `K delta^n + STEP(delta, 0, 0, d_max, c_max) delta_dot`.
    AdamsImpact {
        /// Full damping [N s/m].
        c_max: f64,
        /// Penetration of full damping [m].
        d_max: f64,
    },
}

/// A normal law with its stiffness and options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalForce {
    /// The law.
    pub law: NormalLaw,
    /// Stiffness K [N/m^n].
    pub stiffness: f64,
    /// Exponent n.
    pub exponent: f64,
    /// Pulling forces set to zero.
    pub clip: bool,
}

/// Onset speeds below this [m/s] are raised to it in the hysteresis laws, whose damping
/// grows as 1/onset speed and would be unbounded for a grazing contact.
pub const MIN_ONSET_SPEED: f64 = 1e-4;

/// Cubic STEP of ADAMS from `(x0, h0)` to `(x1, h1)`.
pub fn step<T: Real>(x: T, x0: f64, h0: f64, x1: f64, h1: f64) -> T {
    let mut s = (x - x0) / (x1 - x0);
    // As f64::clamp(0, 1).
    if s < 0.0 {
        s = T::constant(0.0);
    }
    if s > 1.0 {
        s = T::constant(1.0);
    }
    T::constant(h0) + s * (h1 - h0) * s * (T::constant(3.0) - s * 2.0)
}

/// `d/dx` of [`step`].
pub fn step_slope(x: f64, x0: f64, h0: f64, x1: f64, h1: f64) -> f64 {
    let s = (x - x0) / (x1 - x0);
    if (0.0..=1.0).contains(&s) {
        (h1 - h0) * 6.0 * s * (1.0 - s) / (x1 - x0)
    } else {
        0.0
    }
}

impl NormalForce {
    /// Checks a law of clearance joint `joint`, whose errors name the law's key.
    /// `d_max_default` comes from the material.
    pub fn new(
        joint: &str,
        spec: &NormalLawSpec,
        stiffness: f64,
        d_max_default: Option<f64>,
    ) -> Result<Self, Error> {
        let restitution = |r: f64| {
            if r > 0.0 && r <= 1.0 {
                Ok(r)
            } else {
                Err(ElementError::joint(
                    joint,
                    Some("normal_law.restitution"),
                    format!("restitution = {r} must lie in (0, 1]"),
                ))
            }
        };
        let (law, exponent, clip) = match *spec {
            NormalLawSpec::Hertz { exponent } => (NormalLaw::Hertz, exponent, true),
            NormalLawSpec::KelvinVoigt { exponent, damping, clip } => {
                if !(damping.is_finite() && damping >= 0.0) {
                    return Err(ElementError::joint(
                        joint,
                        Some("normal_law.damping"),
                        format!("damping = {damping} N s/m must be zero or positive"),
                    ));
                }
                (NormalLaw::KelvinVoigt { damping }, exponent, clip)
            }
            NormalLawSpec::HuntCrossley { exponent, restitution: r, clip } => {
                let r = restitution(r)?;
                (NormalLaw::Hysteresis { factor: 1.5 * (1.0 - r) }, exponent, clip)
            }
            NormalLawSpec::LankaraniNikravesh { exponent, restitution: r, clip } => {
                let r = restitution(r)?;
                (NormalLaw::Hysteresis { factor: 0.75 * (1.0 - r * r) }, exponent, clip)
            }
            NormalLawSpec::Gonthier { exponent, restitution: r, clip } => {
                let r = restitution(r)?;
                (NormalLaw::Hysteresis { factor: (1.0 - r * r) / r }, exponent, clip)
            }
            NormalLawSpec::Flores { exponent, restitution: r, clip } => {
                let r = restitution(r)?;
                (NormalLaw::Hysteresis { factor: 8.0 * (1.0 - r) / (5.0 * r) }, exponent, clip)
            }
            NormalLawSpec::AdamsImpact { exponent, c_max, d_max, clip } => {
                let d_max = d_max.or(d_max_default).ok_or_else(|| {
                    ElementError::joint(
                        joint,
                        Some("normal_law"),
                        "adams_impact needs d_max (or a bearing material from the library)".into(),
                    )
                })?;
                if !(d_max.is_finite() && d_max > 0.0) {
                    return Err(ElementError::joint(
                        joint,
                        Some("normal_law.d_max"),
                        format!("d_max = {d_max} m must be positive"),
                    ));
                }
                if !(c_max.is_finite() && c_max >= 0.0) {
                    return Err(ElementError::joint(
                        joint,
                        Some("normal_law.c_max"),
                        format!("c_max = {c_max} N s/m must be zero or positive"),
                    ));
                }
                (NormalLaw::AdamsImpact { c_max, d_max }, exponent, clip)
            }
        };
        if !(exponent.is_finite() && exponent >= 1.0) {
            return Err(ElementError::joint(
                joint,
                Some("normal_law.exponent"),
                format!("exponent = {exponent} must be at least 1"),
            ));
        }
        Ok(NormalForce { law, stiffness, exponent, clip })
    }

    /// Energy stored in the elastic part `K delta^n`: `K delta^(n+1) / (n+1)` [J].
    pub fn elastic_energy(&self, delta: f64) -> f64 {
        if delta <= 0.0 {
            0.0
        } else {
            self.stiffness * delta.powf(self.exponent + 1.0) / (self.exponent + 1.0)
        }
    }

    /// The elastic part `K delta^n` of the force [N] (zero for `delta <= 0`), whose
    /// work is the change of [`NormalForce::elastic_energy`].
    #[inline]
    pub fn elastic_force<T: Real>(&self, delta: T) -> T {
        if delta <= 0.0 {
            T::constant(0.0)
        } else {
            power(delta, self.exponent) * self.stiffness
        }
    }

    /// The gap [m] within which the law acts: zero, for a contact law presses only at
    /// positive penetration. A law that acts apart (a lubricated bearing's fluid film, at
    /// any eccentricity) says infinity, and its geometry then returns the contact point
    /// at every gap.
    #[inline]
    pub fn reach(&self) -> f64 {
        0.0
    }

    /// Normal force [N] (compressive positive) at penetration `delta` [m], rate
    /// `delta_dot` [m/s], with `onset_speed` the approach speed of the current impact.
    pub fn force<T: Real>(&self, delta: T, delta_dot: T, onset_speed: T) -> T {
        if delta <= 0.0 {
            return T::constant(0.0);
        }
        let elastic = self.elastic_force(delta);
        let f = match self.law {
            NormalLaw::Hertz => elastic,
            NormalLaw::KelvinVoigt { damping } => elastic + delta_dot * damping,
            NormalLaw::Hysteresis { factor } => {
                elastic
                    * (T::constant(1.0) + delta_dot * factor / onset_speed.max(T::constant(MIN_ONSET_SPEED)))
            }
            NormalLaw::AdamsImpact { c_max, d_max } => {
                elastic + step(delta, 0.0, 0.0, d_max, c_max) * delta_dot
            }
        };
        if self.clip {
            f.max(T::constant(0.0))
        } else {
            f
        }
    }
}

/// `delta^n` for `delta > 0`: Hertz's `n = 1.5` as `delta sqrt(delta)`, a few times
/// cheaper than `powf` (the force law runs at every evaluation and is a tenth of its
/// cost with `powf`) and, like it, within an ulp of the exact power.
#[inline]
fn power<T: Real>(delta: T, n: f64) -> T {
    if n == 1.5 {
        delta * delta.sqrt()
    } else if n == 1.0 {
        delta
    } else {
        delta.powf(T::constant(n))
    }
}

#[cfg(test)]
mod tests {
    use super::power;

    /// Against `powf` over penetrations from 1e-12 m to 1 mm: within two ulps.
    #[test]
    fn power_matches_powf() {
        for n in [1.0, 1.5, 2.2] {
            for k in 0..=180 {
                let delta = 1e-12 * 10f64.powf(k as f64 / 20.0);
                let (fast, exact) = (power(delta, n), delta.powf(n));
                assert!((fast - exact).abs() <= 2.0 * f64::EPSILON * exact, "n = {n}, delta = {delta:e}");
            }
        }
    }
}
