//! Friction laws: tangential force from the slip speed and the normal force
//! (PHYSICS.md section 4). The model's `FrictionSpec` is the law; this module checks its
//! values and evaluates it.

use super::normal::step;
use crate::model::FrictionSpec;
use crate::Error;

/// Checks a friction law's values; `who` names the joint.
pub fn check(who: &str, spec: &FrictionSpec) -> Result<(), Error> {
    let coef = |name: &str, v: f64| {
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(Error::Model(format!("{who}: friction {name} = {v} must be zero or positive")))
        }
    };
    let speed = |name: &str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(Error::Model(format!("{who}: friction {name} = {v} m/s must be positive")))
        }
    };
    match *spec {
        FrictionSpec::None => {}
        FrictionSpec::Coulomb { mu_s, mu_d, v_s, v_d } => {
            coef("mu_s", mu_s)?;
            coef("mu_d", mu_d)?;
            let (v_s, v_d) = (speed("v_s", v_s)?, speed("v_d", v_d)?);
            if v_s >= v_d {
                return Err(Error::Model(format!(
                    "{who}: friction v_s = {v_s} m/s must be below v_d = {v_d} m/s"
                )));
            }
        }
        FrictionSpec::ModifiedCoulomb { mu, v_0, v_1 } => {
            coef("mu", mu)?;
            let (v_0, v_1) = (coef("v_0", v_0)?, speed("v_1", v_1)?);
            if v_0 >= v_1 {
                return Err(Error::Model(format!(
                    "{who}: friction v_0 = {v_0} m/s must be below v_1 = {v_1} m/s"
                )));
            }
        }
        FrictionSpec::ViscousCoulomb { mu, v_s, viscous } => {
            coef("mu", mu)?;
            speed("v_s", v_s)?;
            coef("viscous", viscous)?;
        }
    }
    Ok(())
}

impl FrictionSpec {
    /// Tangential force [N] along the tangent `t`, opposing the slip `v_t` [m/s], for a
    /// normal force `f_n` >= 0 [N].
    pub fn force(&self, v_t: f64, f_n: f64) -> f64 {
        match *self {
            FrictionSpec::None => 0.0,
            FrictionSpec::Coulomb { mu_s, mu_d, v_s, v_d } => {
                let a = v_t.abs();
                let mu = if a <= v_s {
                    step(v_t, -v_s, -mu_s, v_s, mu_s)
                } else if a <= v_d {
                    v_t.signum() * step(a, v_s, mu_s, v_d, mu_d)
                } else {
                    v_t.signum() * mu_d
                };
                -mu * f_n
            }
            FrictionSpec::ModifiedCoulomb { mu, v_0, v_1 } => {
                let a = v_t.abs();
                let c_d = if a <= v_0 {
                    0.0
                } else if a <= v_1 {
                    (a - v_0) / (v_1 - v_0)
                } else {
                    1.0
                };
                -mu * c_d * f_n * v_t.signum()
            }
            FrictionSpec::ViscousCoulomb { mu, v_s, viscous } => {
                if f_n > 0.0 {
                    -mu * f_n * (v_t / v_s).tanh() - viscous * v_t
                } else {
                    0.0
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ADAMS law: mu_d when sliding fast, mu_s at v_s, zero at rest, odd in v_t.
    #[test]
    fn coulomb_levels_and_sign() {
        let law = FrictionSpec::Coulomb { mu_s: 0.08, mu_d: 0.05, v_s: 1e-4, v_d: 0.01016 };
        assert!((law.force(0.5, 100.0) + 5.0).abs() < 1e-12);
        assert!((law.force(-0.5, 100.0) - 5.0).abs() < 1e-12);
        assert!((law.force(1e-4, 100.0) + 8.0).abs() < 1e-12);
        assert_eq!(law.force(0.0, 100.0), 0.0);
        // Odd in the slip, to round-off.
        assert!(
            (law.force(3e-5, 100.0) + law.force(-3e-5, 100.0)).abs() < 1e-14 * law.force(3e-5, 100.0).abs()
        );
    }

    #[test]
    fn modified_coulomb_ramps_between_speeds() {
        let law = FrictionSpec::ModifiedCoulomb { mu: 0.1, v_0: 1e-4, v_1: 1e-3 };
        assert_eq!(law.force(5e-5, 10.0), 0.0);
        assert!((law.force(5.5e-4, 10.0) + 0.5).abs() < 1e-12);
        assert!((law.force(-1.0, 10.0) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn bad_values_name_the_joint() {
        let bad = FrictionSpec::Coulomb { mu_s: 0.08, mu_d: 0.05, v_s: 0.02, v_d: 0.01 };
        let e = check("joint 'gap'", &bad).unwrap_err().to_string();
        assert!(e.contains("joint 'gap': friction v_s = 0.02 m/s must be below v_d = 0.01 m/s"), "{e}");
    }
}
