//! Dimensional wear coefficients of common journal-bearing pairs for Archard's law `dV =
//! k F ds` (docs/wear.md, "Wear coefficients"): `k = K / H`, Archard's dimensionless
//! coefficient over the softer part's hardness, from the pin-on-ring measurements of
//! Archard (J. Appl. Phys. 24 (1953) 981) as Hutchings and Shipway (Tribology, 2nd ed.
//! 2017, ch. 5) tabulate them. Boundary lubrication lowers K by orders of magnitude; the
//! lubricated entries take K = 1e-7, the order of mild lubricated wear in the same source,
//! and are only a starting point: a measured coefficient for the pair should replace them.

use serde::Serialize;

/// One pair's coefficient.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct WearPair {
    /// Name a model, a command or a call gives.
    pub name: &'static str,
    /// The pair in words.
    pub pair: &'static str,
    /// Archard's dimensionless coefficient K.
    pub archard_k: f64,
    /// Vickers hardness of the softer part [Pa].
    pub hardness: f64,
    /// `k = K / H` [1/Pa = m^2/N].
    pub coefficient: f64,
}

/// One kilogram-force per square millimetre [Pa]: Archard's hardness unit.
const KGF_PER_MM2: f64 = 9.80665e6;

/// Archard's K of mild lubricated wear.
const LUBRICATED_K: f64 = 1e-7;

const fn pair(name: &'static str, pair: &'static str, archard_k: f64, hardness_kgf_mm2: f64) -> WearPair {
    let hardness = hardness_kgf_mm2 * KGF_PER_MM2;
    WearPair { name, pair, archard_k, hardness, coefficient: archard_k / hardness }
}

/// The pairs: dry from Archard's table (mild steel on mild steel, 60/40 brass on tool
/// steel, beryllium bronze on tool steel), lubricated with [`LUBRICATED_K`].
pub const WEAR_PAIRS: [WearPair; 6] = [
    pair("steel_steel_dry", "steel journal on a steel bearing, dry", 7e-3, 186.0),
    pair("steel_brass_dry", "steel journal in a brass bearing, dry", 6e-4, 95.0),
    pair("steel_bronze_dry", "steel journal in a bronze bearing, dry", 3.7e-5, 210.0),
    pair("steel_steel_lubricated", "steel on steel, boundary lubricated", LUBRICATED_K, 186.0),
    pair("steel_brass_lubricated", "steel in brass, boundary lubricated", LUBRICATED_K, 95.0),
    pair("steel_bronze_lubricated", "steel in bronze, boundary lubricated", LUBRICATED_K, 210.0),
];

/// The pair a wear prediction takes when none is given: the founding slider-crank's
/// steel journal in its brass bearing, dry.
pub const DEFAULT_WEAR_PAIR: &str = "steel_brass_dry";

#[cfg(test)]
mod tests {
    use super::*;

    /// By hand: mild steel, K = 7e-3 over 186 kgf/mm^2 = 1.8240e9 Pa gives 3.8377e-12
    /// 1/Pa, that is 3.84e-3 mm^3/(N m); beryllium bronze 3.7e-5 over 2.0594e9 Pa gives
    /// 1.797e-14 1/Pa.
    #[test]
    fn coefficients_by_hand() {
        let k = |name: &str| WEAR_PAIRS.iter().find(|p| p.name == name).expect(name).coefficient;
        assert!((k("steel_steel_dry") / 3.8377e-12 - 1.0).abs() < 1e-4);
        assert!((k("steel_bronze_dry") / 1.7967e-14 - 1.0).abs() < 1e-4);
        assert!(WEAR_PAIRS.iter().any(|p| p.name == DEFAULT_WEAR_PAIR));
        for dry in WEAR_PAIRS.iter().filter(|p| p.name.ends_with("_dry")) {
            let wet = dry.name.replace("_dry", "_lubricated");
            assert!(k(&wet) < 1e-2 * dry.coefficient, "{wet}");
        }
    }
}
