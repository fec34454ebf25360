//! Friction laws: tangential force from the slip speed and the normal force
//! (docs/physics.md section 4). The model's `FrictionSpec` is the law; this module checks
//! its values and evaluates it.

use super::normal::{step, step_slope};
use crate::error::ElementError;
use crate::error::Error;
use crate::model::FrictionSpec;
use crate::scalar::{norm, Real};
use nalgebra::SVector;

/// Checks a friction law's values of clearance joint `joint`; its errors name the law's
/// key (`friction.mu_s`).
pub fn check(joint: &str, spec: &FrictionSpec) -> Result<(), Error> {
    let error =
        |name: &str, problem: String| ElementError::joint(joint, Some(&format!("friction.{name}")), problem);
    let coef = |name: &str, v: f64| {
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(error(name, format!("friction {name} = {v} must be zero or positive")))
        }
    };
    let speed = |name: &str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(error(name, format!("friction {name} = {v} m/s must be positive")))
        }
    };
    match *spec {
        FrictionSpec::None => {}
        FrictionSpec::Coulomb { mu_s, mu_d, v_s, v_d } => {
            coef("mu_s", mu_s)?;
            coef("mu_d", mu_d)?;
            let (v_s, v_d) = (speed("v_s", v_s)?, speed("v_d", v_d)?);
            if v_s >= v_d {
                return Err(error("v_s", format!("friction v_s = {v_s} m/s must be below v_d = {v_d} m/s")));
            }
        }
        FrictionSpec::ModifiedCoulomb { mu, v_0, v_1 } => {
            coef("mu", mu)?;
            let (v_0, v_1) = (coef("v_0", v_0)?, speed("v_1", v_1)?);
            if v_0 >= v_1 {
                return Err(error("v_0", format!("friction v_0 = {v_0} m/s must be below v_1 = {v_1} m/s")));
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
    pub fn force<T: Real>(&self, v_t: T, f_n: T) -> T {
        match *self {
            FrictionSpec::None => T::constant(0.0),
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
                    T::constant(0.0)
                } else if a <= v_1 {
                    (a - v_0) / (v_1 - v_0)
                } else {
                    T::constant(1.0)
                };
                c_d * -mu * f_n * v_t.signum()
            }
            FrictionSpec::ViscousCoulomb { mu, v_s, viscous } => {
                if f_n > 0.0 {
                    f_n * -mu * (v_t / v_s).tanh() - v_t * viscous
                } else {
                    T::constant(0.0)
                }
            }
        }
    }

    /// Friction force [N] for the slip `slip` [m/s], both by their components along a
    /// contact point's tangents, for a normal force `f_n` >= 0 [N]: opposite to the slip,
    /// `F_T = -F(|s|) s / |s|` with `F` the law's magnitude at the slip speed [`Self::force`].
    /// With one tangent (the plane) the law takes the slip's signed component as it is,
    /// which is the same force, so a planar run computes exactly what the scalar law does.
    #[inline]
    pub fn force_on_slip<T: Real, const N: usize>(&self, slip: &SVector<T, N>, f_n: T) -> SVector<T, N> {
        if N == 1 {
            return SVector::repeat(self.force(slip[0], f_n));
        }
        let speed = norm(slip);
        if speed > 0.0 {
            slip * (self.force(speed, f_n) / speed)
        } else {
            SVector::zeros()
        }
    }

    /// `|dF_T / dv_t|` [N s/m] at slip `v_t` and normal force `f_n`: the damping the law
    /// puts on the slip. Near sticking it is large (`mu_s f_n / v_s` and more), and it is
    /// what makes an explicit step unstable there.
    pub fn damping(&self, v_t: f64, f_n: f64) -> f64 {
        let a = v_t.abs();
        match *self {
            FrictionSpec::None => 0.0,
            FrictionSpec::Coulomb { mu_s, mu_d, v_s, v_d } => {
                let slope = if a <= v_s {
                    step_slope(v_t, -v_s, -mu_s, v_s, mu_s)
                } else {
                    step_slope(a, v_s, mu_s, v_d, mu_d)
                };
                slope.abs() * f_n
            }
            FrictionSpec::ModifiedCoulomb { mu, v_0, v_1 } => {
                if a > v_0 && a <= v_1 {
                    mu * f_n / (v_1 - v_0)
                } else {
                    0.0
                }
            }
            FrictionSpec::ViscousCoulomb { mu, v_s, viscous } => {
                let sech = 1.0 / (v_t / v_s).cosh();
                let coulomb = if f_n > 0.0 { mu * f_n * sech * sech / v_s } else { 0.0 };
                coulomb + viscous
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

    /// One law of each kind, with the founding case's Coulomb parameters.
    fn three_laws() -> [FrictionSpec; 3] {
        [
            FrictionSpec::Coulomb { mu_s: 0.08, mu_d: 0.05, v_s: 1e-4, v_d: 0.01016 },
            FrictionSpec::ModifiedCoulomb { mu: 0.1, v_0: 1e-4, v_1: 1e-3 },
            FrictionSpec::ViscousCoulomb { mu: 0.1, v_s: 1e-3, viscous: 2.0 },
        ]
    }

    /// The damping rate is |dF_T/dv_t| of each law, by central differences, at slips in
    /// every zone of each law (sticking, transition, sliding, both signs).
    #[test]
    fn damping_is_the_slope_of_the_force() {
        let laws = three_laws();
        let f_n = 150.0;
        for law in &laws {
            for v_t in [-0.3, -5e-3, -3e-4, -6e-5, 0.0, 2e-5, 7e-5, 4e-4, 2e-3, 9e-3, 0.2] {
                let e = 1e-9;
                let fd = (law.force(v_t + e, f_n) - law.force(v_t - e, f_n)) / (2.0 * e);
                let d = law.damping(v_t, f_n);
                assert!((d - fd.abs()).abs() <= 1e-5 * d.max(1.0), "{law:?} at {v_t}: {d} vs {fd}");
            }
        }
        // Sticking: the peak rate of the ADAMS law is 1.5 mu_s f_n / v_s, at zero slip.
        let adams = &laws[0];
        assert!((adams.damping(0.0, f_n) - 1.5 * 0.08 * f_n / 1e-4).abs() < 1e-6);
    }

    /// On a slip vector of two tangents: the force opposes the slip, with the law's
    /// magnitude at the slip speed; on one tangent it is the scalar law itself.
    #[test]
    fn friction_opposes_a_vector_slip() {
        let laws = three_laws();
        let f_n = 150.0;
        for law in &laws {
            for (sx, sy) in [(3e-5, -4e-5), (-6e-4, 8e-4), (0.3, 0.4), (-2e-3, 0.0)] {
                let slip = SVector::<f64, 2>::new(sx, sy);
                let speed = slip.norm();
                let f = law.force_on_slip(&slip, f_n);
                // Magnitude: the law at the speed (a negative force along the slip).
                assert!((f.norm() + law.force(speed, f_n)).abs() <= 1e-12 * f.norm().max(1e-9), "{law:?}");
                // Direction: opposite to the slip.
                assert!((f.dot(&slip) + f.norm() * speed).abs() <= 1e-12 * f.norm() * speed, "{law:?}");
                if law.force(speed, f_n) != 0.0 {
                    assert!(f.dot(&slip) < 0.0, "{law:?}: {f:?} against {slip:?}");
                }
            }
            assert_eq!(law.force_on_slip(&SVector::<f64, 2>::zeros(), f_n), SVector::<f64, 2>::zeros());
            for s in [-0.3, -4e-5, 0.0, 7e-5, 2e-3] {
                let one = law.force_on_slip(&SVector::<f64, 1>::new(s), f_n)[0];
                assert_eq!(one.to_bits(), law.force(s, f_n).to_bits(), "{law:?} at {s}");
            }
        }
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
        let e = check("gap", &bad).unwrap_err().to_string();
        assert!(e.contains("joint 'gap': friction v_s = 0.02 m/s must be below v_d = 0.01 m/s"), "{e}");
    }
}
