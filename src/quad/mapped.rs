//! The integrand in the engine's piece variable: the map of a semi-infinite
//! tail, evaluation counting, and the refusal of non-finite values.

use super::budget::{Budget, Meter};
use super::{Failure, Sample, SampleFn};
use crate::real::Real;

/// A piece [a, b] of the (possibly mapped) integration variable.
#[derive(Debug, Clone)]
pub(crate) struct Piece<T> {
    pub a: T,
    pub b: T,
}

/// Map of a semi-infinite [a, ∞) onto the piece variable u ∈ [0, 1).
#[derive(Debug, Clone)]
pub(crate) enum TailMap<T> {
    /// t = a + u/(1 − u), dt = du/(1 − u)².
    Rational,
    /// t = a − ln(1 − u)/λ, dt = du/(λ(1 − u)).
    Exponential(T),
}

impl<T: Real> TailMap<T> {
    pub(crate) fn to_t(&self, a: &T, u: &T) -> (T, T) {
        let one_minus = u.lit(1.0) - u.clone();
        match self {
            TailMap::Rational => {
                (a.clone() + u.clone() / one_minus.clone(), u.lit(1.0) / (one_minus.clone() * one_minus))
            }
            // ln(1 − u) as ln1p(−u): near u = 0 the plain form rounds 1 − u
            // to 1 and puts nodes exactly on the lower limit.
            TailMap::Exponential(rate) => {
                (a.clone() - (-u.clone()).ln_1p() / rate.clone(), u.lit(1.0) / (rate.clone() * one_minus))
            }
        }
    }
    pub(crate) fn to_u(&self, a: &T, t: &T) -> T {
        let d = t.clone() - a.clone();
        match self {
            TailMap::Rational => d.clone() / (t.lit(1.0) + d),
            TailMap::Exponential(rate) => t.lit(1.0) - (-(rate.clone() * d)).exp(),
        }
    }
}

/// Counters shared by the passes of one integration.
#[derive(Debug, Default)]
pub(crate) struct Tally {
    pub evaluations: u64,
    pub calls: u64,
    pub all_zero: bool,
}

/// The integrand in the piece variable: applies the semi-infinite map and its
/// Jacobian, counts evaluations, rejects non-finite values.
pub(crate) struct Mapped<'f, 'g, T> {
    f: &'f mut SampleFn<'g, T>,
    /// Charges every call to the computation's budget.
    meter: Meter<'f>,
    /// Semi-infinite [a, ∞): the piece variable u ∈ [0, 1) and its map.
    semi: Option<(T, TailMap<T>)>,
    pub tally: Tally,
}

impl<'f, 'g, T: Real> Mapped<'f, 'g, T> {
    /// The integrand `f` on a domain whose tail (if any) is mapped by `semi`.
    pub fn new(f: &'f mut SampleFn<'g, T>, semi: Option<(T, TailMap<T>)>, budget: &'f Budget) -> Self {
        Mapped { f, meter: Meter::new(budget), semi, tally: Tally { all_zero: true, ..Tally::default() } }
    }

    pub fn eval(&mut self, u: &T) -> Result<Sample<T>, Failure<T>> {
        let (t, jac) = match &self.semi {
            None => (u.clone(), None),
            Some((a, map)) => {
                let (t, jac) = map.to_t(a, u);
                (t, Some(jac))
            }
        };
        let mut s = (self.f)(&t)?;
        self.tally.calls += 1;
        self.tally.evaluations += s.evaluations;
        if let Some(reason) = self.meter.tick() {
            return Err(self.fail(format!("{reason}; stopped while sampling"), None));
        }
        if !s.value.is_finite() || !s.error.is_finite() {
            return Err(Failure {
                reason: format!("integrand is not finite at x = {:e} (value {:e})", t.to_f64(), s.value.to_f64()),
                best_guess: None,
                error_estimate: None,
                evaluations: self.tally.evaluations,
            });
        }
        if !s.value.is_zero() {
            self.tally.all_zero = false;
        }
        if let Some(j) = jac {
            if !j.is_finite() {
                return Ok(Sample { value: u.lit(0.0), error: u.lit(0.0), evaluations: s.evaluations });
            }
            s.value = s.value * j.clone();
            s.error = s.error * j;
        }
        Ok(s)
    }

    pub fn fail(&self, reason: String, best: Option<(T, T)>) -> Failure<T> {
        let (best_guess, error_estimate) = match best {
            Some((v, e)) => (Some(v), Some(e)),
            None => (None, None),
        };
        Failure { reason, best_guess, error_estimate, evaluations: self.tally.evaluations }
    }
}
