//! Contact materials: a small library of engineering metals and the generalised
//! stiffness of a journal in a bearing (docs/physics.md section 3; sources in
//! docs/clearance-joints.md) and of a ball in its socket (docs/spatial-clearance.md).

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

/// The contact modulus `E* = 1 / (sigma_j + sigma_b)`, `sigma = (1 - nu^2) / E`, of
/// two materials in contact [Pa] (Johnson 1985, section 4.2): what sets the width of a
/// Hertz contact.
pub fn contact_modulus(a: &Material, b: &Material) -> f64 {
    let sigma = |m: &Material| (1.0 - m.poisson_ratio.powi(2)) / m.youngs_modulus;
    1.0 / (sigma(a) + sigma(b))
}

/// The Hertz stiffness of a ball of radius `r_ball` in a concave spherical seat of radius
/// `r_socket` (larger), `K = 4/3 E* sqrt(R*)` [N/m^1.5] with `1/E* = sigma_ball +
/// sigma_socket`, `sigma = (1 - nu^2) / E`, and `R* = R_B R_S / (R_S - R_B)`: two
/// bodies of revolution in point contact, the seat's curvature counted negative
/// (Johnson 1985, section 4.2; docs/spatial-clearance.md). It is the formula that
/// [`journal_bearing_stiffness`] borrows for a journal (the sphere's, with the bearing
/// radius negative), so it is that function, with the ball as the journal and the socket
/// as the bearing.
pub fn ball_socket_stiffness(ball: &Material, socket: &Material, r_ball: f64, r_socket: f64) -> f64 {
    journal_bearing_stiffness(ball, socket, r_ball, r_socket)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A steel ball (207 GPa, nu 0.3) of radius 10 mm in a brass seat (97 GPa, nu 0.3)
    /// of 10.1 mm: by hand, `E* = 1 / (0.91/207e9 + 0.91/97e9) = 7.2582e10 Pa`, `R* =
    /// 10 x 10.1 / 0.1 mm = 1.01 m`, `K = 4/3 x 7.2582e10 x sqrt(1.01) = 9.7258e10
    /// N/m^1.5`. And through Hertz's contact radius (Johnson 1985, section 4.2): a
    /// load P spreads over `a = (3 P R* / (4 E*))^(1/3)` and the two approach by `delta =
    /// a^2 / R*`, where `K delta^1.5` must give P back.
    #[test]
    fn ball_in_seat_stiffness() {
        let ball = Material { youngs_modulus: 207e9, poisson_ratio: 0.3 };
        let seat = Material { youngs_modulus: 97e9, poisson_ratio: 0.3 };
        let k = ball_socket_stiffness(&ball, &seat, 10.0e-3, 10.1e-3);
        assert!((k / 9.7258e10 - 1.0).abs() < 1e-4, "K = {k:e}");
        let (e_star, r_star): (f64, f64) = (7.258169e10, 1.01);
        for p in [1.0, 250.0, 4e4] {
            let a = (3.0 * p * r_star / (4.0 * e_star)).cbrt();
            let delta = a * a / r_star;
            assert!((k * delta.powf(1.5) / p - 1.0).abs() < 1e-6, "P = {p}");
        }
    }

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
