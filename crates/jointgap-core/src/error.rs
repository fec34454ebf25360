//! An engine error in parts, for the front ends that locate it in a model file: its
//! category (model, assembly, options), the element's kind and name, the offending key
//! and the problem. Each is built in parts where it is found, and the binding raises the
//! parts as the attributes of its exception, so that no front end reads them back out of
//! the message.

use serde::Serialize;

/// Errors that stop a run before it starts. Each message names the offending element
/// or option; [`Error::parts`] gives the element, the key and the problem apart.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A value of a model element is invalid, or the element cannot be assembled, said in
    /// parts.
    #[error("{0}")]
    Element(ElementError),
    /// The model as a whole is malformed or physically invalid (no one element).
    #[error("{0}")]
    Model(String),
    /// The initial configuration cannot satisfy the constraints (no one element).
    #[error("{0}")]
    Assembly(String),
    /// A run option is invalid: `key` names it, `problem` is the whole message.
    #[error("{problem}")]
    Options {
        /// The option's name (`rtol`, `channels`, ...).
        key: &'static str,
        /// What is wrong, naming the option and its value.
        problem: String,
    },
}

/// The kinds of model element an error can name, as the messages name them.
pub const ELEMENT_KINDS: [&str; 5] = ["body", "joint", "driver", "force", "marker"];

/// An error about one element, built in parts where it is found; it reads
/// `<kind> '<element>': <problem>`, as every engine error about an element does.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ElementError {
    /// `model` (a value is invalid) or `assembly` (the element cannot be placed).
    pub category: &'static str,
    /// One of [`ELEMENT_KINDS`].
    pub kind: &'static str,
    /// The element's name.
    pub element: String,
    /// The offending key as the model file writes it, dotted for a nested one
    /// (`normal_law.restitution`); `None` where no one key is at fault.
    pub key: Option<String>,
    /// What is wrong.
    pub problem: String,
}

impl ElementError {
    /// A model error about `key` of the element `element` of kind `kind`.
    pub fn model(kind: &'static str, element: &str, key: Option<&str>, problem: String) -> Error {
        Error::Element(ElementError {
            category: "model",
            kind,
            element: element.to_string(),
            key: key.map(str::to_string),
            problem,
        })
    }

    /// An error about a key of clearance joint `joint`.
    pub fn joint(joint: &str, key: Option<&str>, problem: String) -> Error {
        Self::model("joint", joint, key, problem)
    }

    /// An assembly error about `key` of the element `element` of kind `kind`.
    pub fn assembly(kind: &'static str, element: &str, key: Option<&str>, problem: String) -> Error {
        Error::Element(ElementError {
            category: "assembly",
            kind,
            element: element.to_string(),
            key: key.map(str::to_string),
            problem,
        })
    }
}

impl std::fmt::Display for ElementError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} '{}': {}", self.kind, self.element, self.problem)
    }
}

/// A model element as the checks name it, its kind and name: it builds the element's
/// errors and reads `<kind> '<name>'` in labels.
#[derive(Debug, Clone, Copy)]
pub struct Named<'a> {
    /// One of [`ELEMENT_KINDS`].
    pub kind: &'static str,
    /// The element's name.
    pub name: &'a str,
}

impl<'a> Named<'a> {
    /// Body `name`.
    pub fn body(name: &'a str) -> Self {
        Named { kind: "body", name }
    }

    /// Joint `name`.
    pub fn joint(name: &'a str) -> Self {
        Named { kind: "joint", name }
    }

    /// Driver `name`.
    pub fn driver(name: &'a str) -> Self {
        Named { kind: "driver", name }
    }

    /// Force element `name`.
    pub fn force(name: &'a str) -> Self {
        Named { kind: "force", name }
    }

    /// Marker `name`.
    pub fn marker(name: &'a str) -> Self {
        Named { kind: "marker", name }
    }

    /// The model error of this element's `key`.
    pub fn error(&self, key: &str, problem: String) -> Error {
        ElementError::model(self.kind, self.name, Some(key), problem)
    }

    /// The model error of this element as a whole, no one key at fault.
    pub fn error_of_element(&self, problem: String) -> Error {
        ElementError::model(self.kind, self.name, None, problem)
    }
}

impl std::fmt::Display for Named<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} '{}'", self.kind, self.name)
    }
}

/// An error's parts, as the binding hands them on.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ErrorParts {
    /// `model`, `assembly` or `options`.
    pub category: &'static str,
    /// The element's kind (one of [`ELEMENT_KINDS`]); `None` for an error about the
    /// model as a whole or the options.
    pub kind: Option<&'static str>,
    /// The element's name.
    pub element: Option<String>,
    /// The offending key (an option's name for the options), where one is at fault.
    pub key: Option<String>,
    /// What is wrong, without the element.
    pub problem: String,
}

impl Error {
    /// The error in parts, as it was built.
    pub fn parts(&self) -> ErrorParts {
        let whole = |category, text: &String| ErrorParts {
            category,
            kind: None,
            element: None,
            key: None,
            problem: text.clone(),
        };
        match self {
            Error::Element(e) => ErrorParts {
                category: e.category,
                kind: Some(e.kind),
                element: Some(e.element.clone()),
                key: e.key.clone(),
                problem: e.problem.clone(),
            },
            Error::Model(text) => whole("model", text),
            Error::Assembly(text) => whole("assembly", text),
            Error::Options { key, problem } => {
                ErrorParts { key: Some(key.to_string()), ..whole("options", problem) }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_element_error_reads_as_the_others_and_keeps_its_parts() {
        let e = ElementError::joint(
            "pin",
            Some("normal_law.restitution"),
            "restitution = 2 must lie in (0, 1]".into(),
        );
        assert_eq!(e.to_string(), "joint 'pin': restitution = 2 must lie in (0, 1]");
        let p = e.parts();
        assert_eq!(
            (p.category, p.kind, p.element.as_deref(), p.key.as_deref()),
            ("model", Some("joint"), Some("pin"), Some("normal_law.restitution"))
        );
        assert_eq!(p.problem, "restitution = 2 must lie in (0, 1]");
    }

    #[test]
    fn an_error_naming_no_element_is_kept_whole_and_an_option_names_its_key() {
        let text = "model 'x': y = inf at the initial state";
        let p = Error::Model(text.into()).parts();
        assert_eq!(
            (p.category, p.kind, p.element, p.key, p.problem.as_str()),
            ("model", None, None, None, text)
        );
        let p = Error::Options { key: "rtol", problem: "option rtol = 2: must lie in (0, 1)".into() }.parts();
        assert_eq!((p.category, p.kind, p.key.as_deref()), ("options", None, Some("rtol")));
        assert_eq!(p.problem, "option rtol = 2: must lie in (0, 1)");
        let e = ElementError::assembly("driver", "motor", Some("joint"), "cannot move".into());
        assert_eq!(e.to_string(), "driver 'motor': cannot move");
        assert_eq!(e.parts().category, "assembly");
    }
}
