//! Every default a front end shows or fills in, gathered as data for the binding: the
//! model's (`crate::defaults`) and the run options' ([`SimOptions::new`]).

use serde::Serialize;

use super::options::SimOptions;
use crate::defaults::{CONTACT_CLIP, CONTACT_EXPONENT, GRAVITY};
use crate::mechanics::contact::wear_coefficients::{WearPair, DEFAULT_WEAR_PAIR, WEAR_PAIRS};

/// The defaults of the normal contact laws.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct NormalLawDefaults {
    /// [`CONTACT_EXPONENT`].
    pub exponent: f64,
    /// [`CONTACT_CLIP`].
    pub clip: bool,
}

/// Every default a front end shows or fills in, as data.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Defaults {
    /// [`GRAVITY`].
    pub gravity: [f64; 2],
    /// The normal laws' `exponent` and `clip`.
    pub normal_law: NormalLawDefaults,
    /// Every run option but `t_end`, which has none, as [`SimOptions::new`] fills
    /// them in (`null` where the engine decides per run, as the step budget).
    pub options: serde_json::Map<String, serde_json::Value>,
    /// The wear coefficients of common pairs ([`WEAR_PAIRS`]).
    pub wear_pairs: Vec<WearPair>,
    /// The pair a wear prediction takes by default ([`DEFAULT_WEAR_PAIR`]).
    pub wear_pair: &'static str,
}

/// The engine's defaults, for the binding.
pub fn defaults() -> Defaults {
    let mut options = match serde_json::to_value(SimOptions::new(1.0)) {
        Ok(serde_json::Value::Object(fields)) => fields,
        // A struct of numbers, flags and names always serialises to an object.
        _ => unreachable!("SimOptions serialises to a JSON object"),
    };
    options.remove("t_end");
    Defaults {
        gravity: GRAVITY,
        normal_law: NormalLawDefaults { exponent: CONTACT_EXPONENT, clip: CONTACT_CLIP },
        options,
        wear_pairs: WEAR_PAIRS.to_vec(),
        wear_pair: DEFAULT_WEAR_PAIR,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Model, NormalLawSpec};

    #[test]
    fn a_model_without_gravity_or_exponent_takes_the_defaults() {
        let model = Model::from_json(
            r#"{"joints": [{"name": "c", "type": "clearance_revolute", "body_i": "ground",
                "point_i": [0, 0], "body_j": "ground", "point_j": [0, 0],
                "clearance": {"normal_law": {"type": "kelvin_voigt", "damping": 1}}}]}"#,
        )
        .expect("parses");
        assert_eq!(model.gravity, GRAVITY);
        let law = &model.joints[0].clearance.as_ref().expect("clearance").normal_law;
        let NormalLawSpec::KelvinVoigt { exponent, clip, .. } = law else {
            panic!("kelvin_voigt expected, got {law:?}")
        };
        assert_eq!((*exponent, *clip), (CONTACT_EXPONENT, CONTACT_CLIP));
    }

    #[test]
    fn the_options_are_those_of_a_run_without_t_end() {
        let d = defaults();
        assert!(!d.options.contains_key("t_end"));
        let mut given = d.options.clone();
        given.insert("t_end".into(), 2.0.into());
        let parsed: SimOptions =
            serde_json::from_value(serde_json::Value::Object(given)).expect("options parse");
        assert_eq!(parsed, SimOptions::new(2.0));
        assert_eq!(d.options["rtol"], serde_json::json!(parsed.rtol));
    }
}
