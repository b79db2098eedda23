//! The noise model of the seed paper, derived (not copied; `docs/model.md`),
//! in the order the model flows: scene → [`field`] → [`moments`] →
//! [`correlations`] → [`noise`].
//!
//! Everything is generic over the working precision (`f64` or MPFR); every
//! integral is computed by the engine in [`crate::quad`] and carries its error
//! bar.

pub mod along;
pub mod angular;
pub mod chebyshev;
pub mod correlations;
pub mod field;
pub mod finite;
pub mod moments;
pub mod noise;
pub mod periodic;
pub mod scattered;

use crate::quad::Failure;
use std::fmt;

/// Why the oracle cannot answer for a scene.
#[derive(Debug, Clone, PartialEq)]
pub enum OracleError {
    /// The scene asks for an effect the oracle does not model (the tracer may).
    Unsupported(String),
    /// An integral did not converge; its reason is carried.
    Quadrature {
        /// Which quantity's integral failed.
        what: &'static str,
        /// The engine's [`Failure`] message (`NOT CONVERGED: …`).
        reason: String,
    },
    /// A result the oracle computed is not representable as a finite f64
    /// (or a ratio's denominator underflowed to 0): the scene's numbers
    /// leave the range of f64. Names the quantity and what to change.
    NotRepresentable(String),
}

impl fmt::Display for OracleError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OracleError::Unsupported(msg) => write!(f, "unsupported: {msg}"),
            OracleError::Quadrature { what, reason } => write!(f, "{what}: {reason}"),
            OracleError::NotRepresentable(msg) => write!(f, "not representable in f64: {msg}"),
        }
    }
}

impl std::error::Error for OracleError {}

impl OracleError {
    pub(crate) fn quad<T: crate::real::Real>(what: &'static str) -> impl FnOnce(Failure<T>) -> OracleError {
        move |f| OracleError::Quadrature { what, reason: f.to_string() }
    }
}
