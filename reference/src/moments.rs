//! Exact power sums of the per-trial luminance, and the mean, the variance
//! and their standard errors from them.
//!
//! Σ L, Σ L², Σ L³, Σ L⁴ are kept *exactly*: each power Lᵏ is formed
//! exactly (at most 212 significant bits) and added to an integer
//! superaccumulator ([`crate::exact::ExactSum`]) as wide as the terms need,
//! so no sum of doubles, of any spread and any count, is ever rounded. Sums
//! are therefore independent of the order of addition: the result is
//! bit-identical for any number of threads and any split of the trial range
//! into shards, and the central moments are formed from them exactly too
//! ([`crate::exact::Dyadic`]), without cancellation, then rounded once.
//!
//! The tracer accumulates the sums of L/2^E (E from the scene, so that
//! L/2^E is of order 1 whatever the flux, R or σ_ext) and shifts them by
//! 2^{kE}: exact, and the same sums as of L itself wherever L⁴ is a normal
//! double. A mean or variance beyond the range of a double is then still
//! computed, and reported with its error in words rather than as inf or 0
//! ([`PowerSums::estimates`]).
//!
//! Standard errors: of the mean, √(s²/M); of the unbiased variance s², from
//! the fourth central moment, Var(s²) = μ₄/M − σ⁴(M − 3)/(M(M − 1)), with the
//! sample moments in place of μ₄, σ² (tested against the exponential
//! distribution, `tests/moments.rs`).

use crate::exact::{self, Dyadic, ExactSum, Powers};
use serde::{Deserialize, Serialize};

/// Exact Σ Lᵏ, k = 1…4, over `count` trials.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PowerSums {
    pub count: u64,
    sums: [ExactSum; 4],
}

/// A value and its standard error.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WithError {
    pub value: f64,
    pub se: f64,
}

/// Mean and variance of L with standard errors.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub mean: WithError,
    /// Unbiased sample variance s² of L.
    pub variance: WithError,
}

/// The mean and the variance, each with its standard error or the reason
/// it is not given (never inf, NaN, or a standard error of 0).
#[derive(Debug, Clone, PartialEq)]
pub struct Estimates {
    pub mean: Result<WithError, String>,
    pub variance: Result<WithError, String>,
}

impl Estimates {
    /// Both, or the reason(s) either is not given.
    pub fn summary(&self) -> Result<Summary, String> {
        match (&self.mean, &self.variance) {
            (Ok(mean), Ok(variance)) => Ok(Summary { mean: *mean, variance: *variance }),
            (Err(a), Err(b)) if a == b => Err(a.clone()),
            (Err(a), Err(b)) => Err(format!("{a}; {b}")),
            (Err(why), _) | (_, Err(why)) => Err(why.clone()),
        }
    }
}

/// A quotient num/den, or its square root, of exact numbers (den > 0).
#[derive(Debug, Clone)]
struct Quotient {
    num: Dyadic,
    den: Dyadic,
    root: bool,
}

impl Quotient {
    fn to_f64(&self) -> f64 {
        if self.root {
            self.num.sqrt_div_to_f64(&self.den)
        } else {
            self.num.div_to_f64(&self.den)
        }
    }

    fn sci(&self, digits: usize) -> String {
        if self.root {
            self.num.sqrt_div_to_sci(&self.den, digits)
        } else {
            self.num.div_to_sci(&self.den, digits)
        }
    }
}

/// A value and its standard error as doubles, or why they cannot be: the
/// error is 0, or either is beyond the range of a double.
fn as_double(name: &str, value: &Quotient, se: &Quotient) -> Result<WithError, String> {
    let representable = |q: &Quotient, x: f64| q.num.is_zero() || (x.is_finite() && x.abs() >= f64::MIN_POSITIVE);
    let (v, e) = (value.to_f64(), se.to_f64());
    if se.num.is_zero() {
        return Err(format!("{name}: its standard error is 0, so it is not resolved"));
    }
    if !(representable(value, v) && representable(se, e)) {
        return Err(format!(
            "{name} ≈ {} ± {} (s.e.), outside the range of a double ({:.1e} … {:.1e}), so not \
             given as a number; L is linear in the lights' flux: scale the fluxes by a power of two",
            value.sci(5),
            se.sci(1),
            f64::MIN_POSITIVE,
            f64::MAX
        ));
    }
    Ok(WithError { value: v, se: e })
}

/// The mean, its standard error, s² and its standard error, exactly.
struct Moments {
    mean: Quotient,
    se_mean: Quotient,
    variance: Quotient,
    se_variance: Quotient,
}

impl PowerSums {
    /// Adds one trial's L. Panics if L or L⁴ is not a finite double (|L| ≥
    /// ~10⁷⁷); callers check first: `Samples::push` refuses such values, and
    /// the tracer pushes L/2^E, which stays far inside the range (E from the
    /// scene; the sums are then [`PowerSums::scaled`] by 2^E, exactly).
    pub fn push(&mut self, l: f64) {
        let fourth = (l * l) * (l * l);
        assert!(l.is_finite() && fourth.is_finite(), "a trial's luminance {l:e} or its fourth power is not finite");
        self.push_powers(&Powers::<4>::of(l).expect("finite"));
    }

    /// Adds one value's powers, formed exactly (L has 53 significant bits,
    /// L⁴ 212; rounding them to doubles first made 1000 equal values give a
    /// negative s² and a NaN standard error). `Samples` forms the powers to
    /// the sixth once and adds the fifth and sixth to its own sums.
    pub fn push_powers<const K: usize>(&mut self, powers: &Powers<K>) {
        const { assert!(K >= 4, "the first four powers") };
        self.count += 1;
        for (k, sum) in self.sums.iter_mut().enumerate() {
            powers.add_to(k + 1, sum);
        }
    }

    /// Adds another set of sums (exact).
    pub fn merge(mut self, other: &PowerSums) -> PowerSums {
        self.count += other.count;
        for (a, b) in self.sums.iter_mut().zip(&other.sums) {
            a.merge(b);
        }
        self
    }

    /// The sums of L·2^`exp` for these sums of L (exact: a shift). A run
    /// accumulates the sums of L/2^E, which never overflow, and scales them
    /// by 2^E once per chunk (`run::trace`).
    pub fn scaled(mut self, exp: i32) -> PowerSums {
        for (k, sum) in self.sums.iter_mut().enumerate() {
            sum.mul_pow2((k as i64 + 1) * i64::from(exp));
        }
        self
    }

    /// Σ L … Σ L⁴, exactly.
    pub fn exact_sums(&self) -> [Dyadic; 4] {
        self.sums.each_ref().map(ExactSum::to_dyadic)
    }

    /// Mean, its standard error, s² and its standard error, exactly as
    /// quotients (`None` below 4 trials).
    fn moments(&self) -> Option<Moments> {
        if self.count < 4 {
            return None;
        }
        // The central sums c₂ = M·S₂ − S₁² (= M²μ₂) and c₄ = M³S₄ − 4M²S₃S₁
        // + 6M S₂S₁² − 3S₁⁴ (= M⁴μ₄) are polynomials in the exact sums, formed
        // exactly: equal values give μ₂ = 0 exactly, and no cancellation can
        // make it negative.
        let m = Dyadic::from(self.count);
        let m1 = Dyadic::from(self.count - 1);
        let m3 = Dyadic::from(self.count) - Dyadic::from(3u64);
        let [s1, s2, s3, s4] = self.exact_sums();
        let s1sq = &s1 * &s1;
        let m2 = &m * &m;
        let c2 = &(&m * &s2) - &s1sq;
        let c4 = (&(&m2 * &m) * &s4) - (&(&m2 * &s3) * &s1).mul_u64(4) + (&(&m * &s2) * &s1sq).mul_u64(6)
            - (&s1sq * &s1sq).mul_u64(3);
        // s² = c₂/(M(M − 1)); √(s²/M) = √(c₂/(M²(M − 1))).
        let mm1 = &m * &m1;
        // Var(s²) = μ₄/M − s⁴(M − 3)/(M(M − 1)) = [c₄(M − 1)³ − c₂²(M − 3)M²] / (M⁵(M − 1)³).
        let m1_cubed = &(&m1 * &m1) * &m1;
        let var_num = (&c4 * &m1_cubed) - &(&(&c2 * &c2) * &m3) * &m2;
        let var_den = &(&(&m2 * &m2) * &m) * &m1_cubed;
        Some(Moments {
            mean: Quotient { num: s1, den: m.clone(), root: false },
            se_mean: Quotient { num: c2.clone().max(Dyadic::zero()), den: &m * &mm1, root: true },
            variance: Quotient { num: c2, den: mm1, root: false },
            se_variance: Quotient { num: var_num.max(Dyadic::zero()), den: var_den, root: true },
        })
    }

    /// Mean, variance and their standard errors as doubles (`None` below 4
    /// trials, where the variance's error is not defined). A value beyond
    /// the range of a double is rounded to ±inf or 0 here: [`PowerSums::estimates`]
    /// says so instead.
    pub fn summary(&self) -> Option<Summary> {
        let m = self.moments()?;
        Some(Summary {
            mean: WithError { value: m.mean.to_f64(), se: m.se_mean.to_f64() },
            variance: WithError { value: m.variance.to_f64(), se: m.se_variance.to_f64() },
        })
    }

    /// The mean and the variance, each with its standard error, or the
    /// reason it is not given: fewer than 4 values; all values equal (no
    /// spread: standard errors of 0 would make any z-score infinite); a
    /// value or its error outside the range of a double (printed here at
    /// full range, with its error).
    pub fn estimates(&self) -> Estimates {
        let Some(m) = self.moments() else {
            let why = format!(
                "fewer than 4 trials ({}): the variance's standard error is not defined (merge shards first)",
                self.count
            );
            return Estimates { mean: Err(why.clone()), variance: Err(why) };
        };
        if m.variance.num <= Dyadic::zero() {
            let why = if m.variance.num.is_zero() {
                format!(
                    "all {} values are equal ({:.6e}): no spread, so the standard errors are 0 and the mean and \
                     variance are not resolved",
                    self.count,
                    m.mean.to_f64()
                )
            } else {
                "the power sums are inconsistent (negative variance)".to_string()
            };
            return Estimates { mean: Err(why.clone()), variance: Err(why) };
        }
        Estimates {
            mean: as_double("mean L", &m.mean, &m.se_mean),
            variance: as_double("Var L", &m.variance, &m.se_variance),
        }
    }

    /// Sums given as doubles (for instance accumulated by a renderer in
    /// another language), taken as exact. `None` if a sum is not finite.
    pub fn from_f64_sums(count: u64, sums: [f64; 4]) -> Option<PowerSums> {
        let mut out = PowerSums { count, ..PowerSums::default() };
        for (a, b) in out.sums.iter_mut().zip(sums) {
            a.add_f64(b.is_finite().then_some(b)?);
        }
        Some(out)
    }

    /// The exact sums as hexadecimal strings (for shard files; C99's
    /// hexadecimal floating point, every digit: [`exact::to_hex`]).
    pub fn to_hex(&self) -> [String; 4] {
        self.exact_sums().each_ref().map(exact::to_hex)
    }

    /// Sums read back from [`PowerSums::to_hex`] (or from the MPFR
    /// radix-16 form of shard files written before 8 December 2026).
    pub fn from_hex(count: u64, hex: &[String; 4]) -> Result<PowerSums, String> {
        let mut out = PowerSums { count, ..PowerSums::default() };
        for (k, text) in hex.iter().enumerate() {
            let x = exact::from_hex(text).map_err(|e| format!("sums[{k}] = \"{}\": {e}", clip(text)))?;
            out.sums[k] = ExactSum::from_dyadic(&x);
        }
        out.check_real()?;
        Ok(out)
    }

    /// Whether these can be the sums of non-negative numbers of which
    /// `nonzero` are > 0 (a tracer's L, a sum of non-negative hit
    /// contributions), checked exactly on top of [`PowerSums::check_real`]:
    /// Σ L ≥ 0 and Σ L³ ≥ 0; all four sums 0 or all > 0; (Σ L²)² ≤ Σ L · Σ L³
    /// and (Σ L³)² ≤ Σ L² · Σ L⁴ (Cauchy–Schwarz on √L·L^{k/2}); (Σ L)² ≤
    /// k Σ L² over the k = `nonzero` values > 0 (with the two before it,
    /// this implies (Σ L²)² ≤ k Σ L⁴). Exact. The error names the sum.
    pub fn check_non_negative(&self, nonzero: u64) -> Result<(), String> {
        let s = self.exact_sums();
        let why = "every L is a sum of non-negative hit contributions";
        for k in [0, 2] {
            if s[k].is_negative() {
                return Err(format!(
                    "sums[{k}] (Σ L{}) = {}: must be >= 0 ({why})",
                    ["", "²", "³", "⁴"][k],
                    s[k].div_to_sci(&Dyadic::from(1u64), 6)
                ));
            }
        }
        if !self.is_zero() && s.iter().any(Dyadic::is_zero) {
            return Err(format!(
                "sums: not the power sums of non-negative numbers (Σ L, Σ L², Σ L³, Σ L⁴ must be all 0 or all > 0; {why})"
            ));
        }
        let k = Dyadic::from(nonzero);
        for (lhs, rhs, rule) in [
            (&s[1] * &s[1], &s[0] * &s[2], "(Σ L²)² <= Σ L · Σ L³"),
            (&s[2] * &s[2], &s[1] * &s[3], "(Σ L³)² <= Σ L² · Σ L⁴"),
            (&s[0] * &s[0], &k * &s[1], "(Σ L)² <= k Σ L²"),
        ] {
            if lhs > rhs {
                return Err(format!(
                    "sums: not the power sums of non-negative numbers, {nonzero} of them > 0 (k = \
                     counters.nonzero_trials): {rule} fails ({why})"
                ));
            }
        }
        Ok(())
    }

    /// Whether every sum is 0 (every L was 0).
    pub fn is_zero(&self) -> bool {
        self.sums.iter().all(ExactSum::is_zero)
    }

    /// Whether these can be the sums of `count` real numbers: Σ L² ≥ 0,
    /// Σ L⁴ ≥ 0, M Σ L² ≥ (Σ L)², M Σ L⁴ ≥ (Σ L²)² (Cauchy–Schwarz; exact),
    /// all 0 when M = 0.
    pub fn check_real(&self) -> Result<(), String> {
        let s = self.exact_sums();
        if self.count == 0 {
            return match s.iter().position(|x| !x.is_zero()) {
                Some(k) => Err(format!("sums[{k}]: must be 0 for 0 trials")),
                None => Ok(()),
            };
        }
        let m = Dyadic::from(self.count);
        if s[1].is_negative() || s[3].is_negative() || &m * &s[1] < &s[0] * &s[0] || &m * &s[3] < &s[1] * &s[1] {
            return Err(format!(
                "sums: not the power sums of {} real numbers (need Σ L², Σ L⁴ >= 0, M Σ L² >= (Σ L)², \
                 M Σ L⁴ >= (Σ L²)²)",
                self.count
            ));
        }
        Ok(())
    }
}

/// A field's text as an error message shows it (at most 40 characters).
fn clip(text: &str) -> String {
    match text.char_indices().nth(40) {
        Some((end, _)) => format!("{}…", &text[..end]),
        None => text.to_string(),
    }
}
