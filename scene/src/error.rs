//! Errors of scene parsing and validation.

use std::fmt;

/// One invalid value: which field, what it was, what is allowed.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldError {
    /// Dotted path of the field, e.g. `estimator.q` or `lights[1].flux`.
    pub field: String,
    /// The offending value as written (after TOML decoding).
    pub value: String,
    /// The allowed range or form, e.g. `in (0, 1]`.
    pub allowed: String,
}

impl fmt::Display for FieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {}: must be {}", self.field, self.value, self.allowed)
    }
}

/// Why a scene was rejected.
#[derive(Debug, Clone, PartialEq)]
pub enum SceneError {
    /// The text is not TOML of the scene's shape: a syntax error, an unknown
    /// key, a missing key or a value of the wrong type. The message comes from
    /// the TOML decoder and names the key and the line.
    Parse(String),
    /// The text has the scene's shape but one or more values are out of range.
    /// All of them are listed, not only the first.
    Invalid(Vec<FieldError>),
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::Parse(msg) => write!(f, "scene is not valid TOML of the expected shape: {msg}"),
            SceneError::Invalid(errors) => {
                writeln!(f, "scene has {} invalid value(s):", errors.len())?;
                for e in errors {
                    writeln!(f, "  {e}")?;
                }
                Ok(())
            }
        }
    }
}

impl std::error::Error for SceneError {}

impl std::error::Error for FieldError {}
