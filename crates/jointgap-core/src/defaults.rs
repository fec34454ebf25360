//! The engine's defaults: what a model or a run leaves out means, written once here and
//! handed to the front ends as data ([`defaults`]), so that the Python package asks the
//! binding for them and repeats none.

use serde::Serialize;

/// Uniform gravity of a model that gives none [m/s^2]: a vertical plane with y up, as a
/// model file without `gravity` has always meant.
pub const GRAVITY: [f64; 2] = [0.0, -9.81];

/// Exponent n of a normal contact law that gives none: Hertz's 3/2 of two elastic bodies
/// in contact, the value for metal contacts (docs/physics.md section 3).
pub const CONTACT_EXPONENT: f64 = 1.5;

/// Whether a normal contact law that does not say sets pulling forces to zero.
pub const CONTACT_CLIP: bool = true;

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
    /// Every run option but `t_end`, which has none, as [`crate::simulate::options::SimOptions::new`] fills
    /// them in (`null` where the engine decides per run, as the step budget).
    pub options: serde_json::Map<String, serde_json::Value>,
}

/// The engine's defaults, for the binding.
pub fn defaults() -> Defaults {
    let mut options = match serde_json::to_value(crate::simulate::options::SimOptions::new(1.0)) {
        Ok(serde_json::Value::Object(fields)) => fields,
        // A struct of numbers, flags and names always serialises to an object.
        _ => unreachable!("SimOptions serialises to a JSON object"),
    };
    options.remove("t_end");
    Defaults {
        gravity: GRAVITY,
        normal_law: NormalLawDefaults { exponent: CONTACT_EXPONENT, clip: CONTACT_CLIP },
        options,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_model_without_gravity_or_exponent_takes_the_defaults() {
        let model = crate::Model::from_json(
            r#"{"joints": [{"name": "c", "type": "clearance_revolute", "body_i": "ground",
                "point_i": [0, 0], "body_j": "ground", "point_j": [0, 0],
                "clearance": {"normal_law": {"type": "kelvin_voigt", "damping": 1}}}]}"#,
        )
        .expect("parses");
        assert_eq!(model.gravity, GRAVITY);
        let law = &model.joints[0].clearance.as_ref().expect("clearance").normal_law;
        let crate::model::NormalLawSpec::KelvinVoigt { exponent, clip, .. } = law else {
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
        let parsed: crate::simulate::options::SimOptions =
            serde_json::from_value(serde_json::Value::Object(given)).expect("options parse");
        assert_eq!(parsed, crate::simulate::options::SimOptions::new(2.0));
        assert_eq!(d.options["rtol"], serde_json::json!(parsed.rtol));
    }
}
