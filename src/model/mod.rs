//! The noise model of the seed paper, derived (not copied; `docs/model.md`),
//! in the order the model flows: scene → [`field`] → [`moments`] →
//! [`correlations`] → [`noise`].
//!
//! Everything is generic over the working precision (`f64` or MPFR); every
//! integral is computed by the engine in [`crate::quad`] and carries its error
//! bar.

pub mod along;
pub mod angular;
pub mod beam_angular;
pub mod beam_fluence;
pub mod beam_source;
pub mod chebyshev;
pub mod correlations;
pub mod cross_segment;
pub mod field;
pub mod finite;
pub mod moments;
pub mod noise;
pub(crate) mod once_per_pass;
pub mod periodic;
pub mod same_path;
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
        /// Why (the engine's [`Failure::reason`]).
        reason: String,
        /// The unreliable best guess of the quantity, if there is one.
        guess: Option<BestGuess>,
        /// Integrand evaluations spent before failing.
        evaluations: u64,
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
            OracleError::Quadrature { what, reason, guess, evaluations } => {
                let guess = match guess {
                    Some(g) => g.to_string(),
                    None => "no best guess available".into(),
                };
                write!(f, "{what}: NOT CONVERGED: {reason} ({guess}) after {evaluations} evaluations")
            }
            OracleError::NotRepresentable(msg) => write!(f, "not representable in f64: {msg}"),
        }
    }
}

impl std::error::Error for OracleError {}

impl OracleError {
    /// A failed integral of the model as the oracle's error. Its best
    /// guess is in the model's internal scaling (every W carried as
    /// W·e^{c₀}, `field::Field::shift`) until [`OracleError::unshifted`]
    /// restores the report's units.
    pub(crate) fn quad<T: crate::real::Real>(what: &'static str) -> impl FnOnce(Failure<T>) -> OracleError {
        move |f| OracleError::Quadrature {
            what,
            reason: f.reason,
            guess: f.best_guess.map(|v| BestGuess {
                value: v.to_f64(),
                error: f.error_estimate.map(|e| e.to_f64_up()),
                shift: None,
            }),
            evaluations: f.evaluations,
        }
    }

    /// The failure of one part of a sum: its best guess is not the sum's.
    pub(crate) fn of_a_part(self) -> OracleError {
        match self {
            OracleError::Quadrature { what, reason, evaluations, .. } => {
                OracleError::Quadrature { what, reason, guess: None, evaluations }
            }
            other => other,
        }
    }

    /// This error with its best guess known to carry e^{c₀} (c₀ = `shift`),
    /// to be printed in the report's units.
    pub fn unshifted(self, shift: f64) -> OracleError {
        match self {
            OracleError::Quadrature { what, reason, guess, evaluations } => OracleError::Quadrature {
                what,
                reason,
                guess: guess.map(|g| BestGuess { shift: Some(shift), ..g }),
                evaluations,
            },
            other => other,
        }
    }
}

/// The unreliable best guess of an integral that did not converge, as the
/// model computed it: times e^{c₀} (`shift`), in f64 (where the shifted
/// values are representable; the true ones may underflow).
#[derive(Debug, Clone, PartialEq)]
pub struct BestGuess {
    /// The shifted value.
    pub value: f64,
    /// The error estimate at the time of failure, if any (shifted too).
    pub error: Option<f64>,
    /// c₀, once known (`None`: the model's internal scaling, not shown).
    pub shift: Option<f64>,
}

impl fmt::Display for BestGuess {
    /// `unreliable best guess V ± E` in the report's units, V·e^{−c₀}
    /// formed through logarithms (it may lie below the smallest double).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Some(shift) = self.shift else {
            return write!(f, "a best guess exists in the model's internal scaling only, not shown");
        };
        write!(f, "unreliable best guess {}", times_exp(self.value, -shift))?;
        if let Some(e) = self.error {
            write!(f, " ± {}", times_exp(e, -shift))?;
        }
        Ok(())
    }
}

/// v·e^{k} in scientific notation, 7 digits, without under- or overflow.
fn times_exp(v: f64, k: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v:e}");
    }
    let l = v.abs().log10() + k / std::f64::consts::LN_10;
    let (mut exponent, mut mantissa) = (l.floor(), 10f64.powf(l - l.floor()));
    if mantissa >= 9.9999995 {
        (exponent, mantissa) = (exponent + 1.0, mantissa / 10.0);
    }
    format!("{:.6}e{}", mantissa.copysign(v), exponent)
}
