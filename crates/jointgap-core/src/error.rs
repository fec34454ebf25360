//! An engine error in parts, for the front ends that locate it in a model file: its
//! category (model, assembly, options), the element's kind and name, the offending key
//! and the problem. The binding raises these as the attributes of its exception, so that
//! no front end reads them back out of the message.

use serde::Serialize;

/// Errors that stop a run before it starts. Each message names the offending element;
/// [`Error::parts`] gives the element, the key and the problem apart.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A value of a model element is invalid, said in parts.
    #[error("{0}")]
    Element(ElementError),
    /// The model is malformed or physically invalid.
    #[error("{0}")]
    Model(String),
    /// The initial configuration cannot satisfy the constraints.
    #[error("{0}")]
    Assembly(String),
    /// The run options are invalid.
    #[error("{0}")]
    Options(String),
}

/// The kinds of model element an error can name, as the messages name them.
pub const ELEMENT_KINDS: [&str; 5] = ["body", "joint", "driver", "force", "marker"];

/// An error about one value of one element, built in parts where it is found; it reads
/// `<kind> '<element>': <problem>`, as every engine error about an element does.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ElementError {
    /// One of [`ELEMENT_KINDS`].
    pub kind: &'static str,
    /// The element's name.
    pub element: String,
    /// The offending key, dotted for a nested one (`normal_law.restitution`).
    pub key: Option<String>,
    /// What is wrong.
    pub problem: String,
}

impl ElementError {
    /// An error about a key of clearance joint `joint`.
    pub fn joint(joint: &str, key: Option<&str>, problem: String) -> Error {
        Error::Element(ElementError {
            kind: "joint",
            element: joint.to_string(),
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
    /// The offending key, where the check that failed knows it.
    pub key: Option<String>,
    /// What is wrong, without the element.
    pub problem: String,
}

impl Error {
    /// The error in parts. An [`Error::Element`] carries them; the other variants hold
    /// a message of the form `<kind> '<element>': <problem>` (or a bare problem), which
    /// is split here, the one place that knows that form, with no key.
    pub fn parts(&self) -> ErrorParts {
        let (category, text) = match self {
            Error::Element(e) => {
                return ErrorParts {
                    category: "model",
                    kind: Some(e.kind),
                    element: Some(e.element.clone()),
                    key: e.key.clone(),
                    problem: e.problem.clone(),
                }
            }
            Error::Model(text) => ("model", text),
            Error::Assembly(text) => ("assembly", text),
            Error::Options(text) => ("options", text),
        };
        let named = ELEMENT_KINDS.iter().find_map(|&kind| {
            let rest = text.strip_prefix(kind)?.strip_prefix(" '")?;
            let (element, problem) = rest.split_once('\'')?;
            Some((kind, element, problem.strip_prefix(": ")?))
        });
        match named {
            Some((kind, element, problem)) => ErrorParts {
                category,
                kind: Some(kind),
                element: Some(element.to_string()),
                key: None,
                problem: problem.to_string(),
            },
            None => ErrorParts { category, kind: None, element: None, key: None, problem: text.clone() },
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
    fn a_message_naming_an_element_is_split_and_one_naming_none_is_kept_whole() {
        let p = Error::Assembly("body 'rod': it's 'odd': mass = 0".into()).parts();
        assert_eq!((p.category, p.kind, p.element.as_deref()), ("assembly", Some("body"), Some("rod")));
        assert_eq!((p.key, p.problem.as_str()), (None, "it's 'odd': mass = 0"));
        let p = Error::Options("option rtol = 2: must lie in (0, 1)".into()).parts();
        assert_eq!((p.category, p.kind, p.element), ("options", None, None));
        assert_eq!(p.problem, "option rtol = 2: must lie in (0, 1)");
        let p = Error::Model("model 'x': y = inf at the initial state".into()).parts();
        assert_eq!((p.kind, p.problem.as_str()), (None, "model 'x': y = inf at the initial state"));
    }
}
