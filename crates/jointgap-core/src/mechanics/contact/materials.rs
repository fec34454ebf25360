//! Contact materials: a small library of engineering metals and the generalised
//! stiffness of a journal in a bearing (docs/physics.md section 3; sources in
//! docs/clearance-joints.md).

use crate::error::{Error, Named};
use crate::model::{Material, MaterialRef};

/// A library entry: name, Young's modulus [Pa], Poisson's ratio, typical d_max [m].
pub struct LibraryMaterial {
    /// Name used in model files.
    pub name: &'static str,
    /// Young's modulus [Pa].
    pub youngs_modulus: f64,
    /// Poisson's ratio.
    pub poisson_ratio: f64,
    /// Typical penetration of full damping for the ADAMS IMPACT law [m].
    pub d_max: f64,
}

/// Elastic constants from Shigley's Mechanical Engineering Design, Table A-5; d_max is
/// the 0.01 mm that MSC ADAMS recommends for metal contacts.
pub const LIBRARY: [LibraryMaterial; 7] = [
    LibraryMaterial { name: "steel", youngs_modulus: 207e9, poisson_ratio: 0.292, d_max: 1e-5 },
    LibraryMaterial { name: "stainless_steel", youngs_modulus: 190e9, poisson_ratio: 0.305, d_max: 1e-5 },
    LibraryMaterial { name: "brass", youngs_modulus: 106e9, poisson_ratio: 0.324, d_max: 1e-5 },
    LibraryMaterial { name: "bronze", youngs_modulus: 111e9, poisson_ratio: 0.349, d_max: 1e-5 },
    LibraryMaterial { name: "aluminium_alloy", youngs_modulus: 71.7e9, poisson_ratio: 0.333, d_max: 1e-5 },
    LibraryMaterial { name: "cast_iron", youngs_modulus: 100e9, poisson_ratio: 0.211, d_max: 1e-5 },
    LibraryMaterial { name: "titanium_alloy", youngs_modulus: 114e9, poisson_ratio: 0.33, d_max: 1e-5 },
];

/// Resolves a material reference; `who` and `field` name it in errors. Returns the
/// properties and the library's typical d_max when the material came from the library.
pub fn resolve(who: Named, field: &str, m: &MaterialRef) -> Result<(Material, Option<f64>), Error> {
    match m {
        MaterialRef::Named(name) => LIBRARY
            .iter()
            .find(|l| l.name == name)
            .map(|l| {
                (Material { youngs_modulus: l.youngs_modulus, poisson_ratio: l.poisson_ratio }, Some(l.d_max))
            })
            .ok_or_else(|| {
                let names: Vec<&str> = LIBRARY.iter().map(|l| l.name).collect();
                who.error(
                    field,
                    format!("{field} '{name}' is not in the material library ({})", names.join(", ")),
                )
            }),
        MaterialRef::Custom(mat) => {
            if !(mat.youngs_modulus.is_finite() && mat.youngs_modulus > 0.0) {
                return Err(who.error(
                    &format!("{field}.youngs_modulus"),
                    format!("{field} youngs_modulus = {} Pa must be positive", mat.youngs_modulus),
                ));
            }
            if !(0.0..0.5).contains(&mat.poisson_ratio) {
                return Err(who.error(
                    &format!("{field}.poisson_ratio"),
                    format!("{field} poisson_ratio = {} must lie in [0, 0.5)", mat.poisson_ratio),
                ));
            }
            Ok((mat.clone(), None))
        }
    }
}

/// `K = 4 / (3 (sigma_j + sigma_b)) sqrt(R_j R_b / (R_j + R_b))` with `sigma = (1 -
/// nu^2) / E`, the journal radius positive and the bearing radius negative (Lankarani
/// and Nikravesh 1990; the founding paper's Eq. 4-5) [N/m^1.5].
pub fn journal_bearing_stiffness(
    journal: &Material,
    bearing: &Material,
    r_journal: f64,
    r_bearing: f64,
) -> f64 {
    let sigma = |m: &Material| (1.0 - m.poisson_ratio.powi(2)) / m.youngs_modulus;
    let (ri, rj) = (r_journal, -r_bearing);
    4.0 / (3.0 * (sigma(journal) + sigma(bearing))) * (ri * rj / (ri + rj)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The founding case: stainless steel 207 GPa in brass 97 GPa, nu 0.3, radii 7.0
    /// and 7.5 mm give K = 3.136e10 N/m^1.5 (docs/physics.md section 5).
    #[test]
    fn founding_case_stiffness() {
        let journal = Material { youngs_modulus: 207e9, poisson_ratio: 0.3 };
        let bearing = Material { youngs_modulus: 97e9, poisson_ratio: 0.3 };
        let k = journal_bearing_stiffness(&journal, &bearing, 7.0e-3, 7.5e-3);
        assert!((k / 3.136e10 - 1.0).abs() < 5e-4, "K = {k:e}");
    }
}
