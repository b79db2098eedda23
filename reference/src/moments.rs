//! Exact power sums of the per-trial luminance, and the mean, the variance
//! and their standard errors from them.
//!
//! Σ L, Σ L², Σ L³, Σ L⁴ are kept *exactly*: each power Lᵏ is formed
//! exactly (at most 212 significant bits) and added to an MPFR number of
//! 2 300 bits, which holds the sum of up to 2⁶⁴ such terms exactly as long
//! as they lie within ~2¹⁹⁰⁰ of each other (the tracer's L/2^E are of
//! order 1; a term smaller than 2⁻¹⁹⁰⁰ of the largest is rounded at 2⁻²³⁰⁰
//! relative, far below anything reported). Sums are therefore independent of the order of addition:
//! the result is bit-identical for any number of threads and any split of
//! the trial range into shards, and the central moments are formed at that
//! width too, without cancellation.
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

use rug::{Assign, Float};
use serde::{Deserialize, Serialize};

/// Width of the exact sums, in bits.
const EXACT_BITS: u32 = 2300;

/// Width of one trial's powers Lᵏ, k ≤ 4: exact for any double L.
const POWER_BITS: u32 = 4 * 53;

/// Exact Σ Lᵏ, k = 1…4, over `count` trials.
#[derive(Debug, Clone, PartialEq)]
pub struct PowerSums {
    pub count: u64,
    sums: [Float; 4],
}

impl Default for PowerSums {
    fn default() -> Self {
        PowerSums { count: 0, sums: std::array::from_fn(|_| Float::new(EXACT_BITS)) }
    }
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

/// A value and its standard error as doubles, or why they cannot be: the
/// error is 0, or either is beyond the range of a double.
fn as_double(name: &str, value: &Float, se: &Float) -> Result<WithError, String> {
    let representable = |x: &Float| x.is_zero() || (x.to_f64().is_finite() && x.to_f64().abs() >= f64::MIN_POSITIVE);
    if se.is_zero() {
        return Err(format!("{name}: its standard error is 0, so it is not resolved"));
    }
    if !(representable(value) && representable(se)) {
        return Err(format!(
            "{name} ≈ {value:.6e} ± {se:.2e} (s.e.), outside the range of a double ({:.1e} … {:.1e}), so not \
             given as a number; L is linear in the lights' flux: scale the fluxes by a power of two",
            f64::MIN_POSITIVE,
            f64::MAX
        ));
    }
    Ok(WithError { value: value.to_f64(), se: se.to_f64() })
}

impl PowerSums {
    /// Adds one trial's L. Panics if L or L⁴ is not a finite double (|L| ≥
    /// ~10⁷⁷); callers check first: `Samples::push` refuses such values, and
    /// the tracer pushes L/2^E, which stays far inside the range (E from the
    /// scene; the sums are then [`PowerSums::scaled`] by 2^E, exactly).
    pub fn push(&mut self, l: f64) {
        let fourth = (l * l) * (l * l);
        assert!(l.is_finite() && fourth.is_finite(), "a trial's luminance {l:e} or its fourth power is not finite");
        self.count += 1;
        // The powers themselves exactly: L has 53 significant bits, L⁴ 212.
        // (Rounding them to doubles first made 1000 equal values give a
        // negative s² and a NaN standard error.)
        let x = Float::with_val(POWER_BITS, l);
        let x2 = Float::with_val(POWER_BITS, &x * &x);
        let x3 = Float::with_val(POWER_BITS, &x2 * &x);
        let x4 = Float::with_val(POWER_BITS, &x2 * &x2);
        for (sum, power) in self.sums.iter_mut().zip([&x, &x2, &x3, &x4]) {
            *sum += power;
        }
    }

    /// Adds another set of sums (exact).
    pub fn merge(mut self, other: &PowerSums) -> PowerSums {
        self.count += other.count;
        for (a, b) in self.sums.iter_mut().zip(&other.sums) {
            *a += b;
        }
        self
    }

    /// The sums of L·2^`exp` for these sums of L (exact: a shift). A run
    /// accumulates the sums of L/2^E, which never overflow, and scales them
    /// by 2^E once per chunk (`run::trace`).
    pub fn scaled(mut self, exp: i32) -> PowerSums {
        for (k, sum) in self.sums.iter_mut().enumerate() {
            *sum <<= (k as i32 + 1) * exp;
        }
        self
    }

    /// Mean, its standard error, s² and its standard error, at full width
    /// (`None` below 4 trials).
    fn moments(&self) -> Option<[Float; 4]> {
        if self.count < 4 {
            return None;
        }
        // The central sums M·μ₂·M = M·S₂ − S₁² and M⁴·μ₄ = M³S₄ − 4M²S₃S₁ +
        // 6M S₂S₁² − 3S₁⁴ are polynomials in the exact sums: at 4·2300 bits
        // (+ the count's 64 bits per factor) they are exact too, so equal
        // values give μ₂ = 0 exactly and no cancellation can make it negative.
        let prec = 4 * EXACT_BITS + 4 * 64 + 64;
        let m = Float::with_val(prec, self.count);
        let [s1, s2_, s3, s4] = &self.sums;
        let s1 = Float::with_val(prec, s1);
        let s1sq = Float::with_val(prec, &s1 * &s1);
        let mean = Float::with_val(prec, &s1 / &m);
        let central2 = Float::with_val(prec, Float::with_val(prec, &m * s2_) - &s1sq);
        let mu2 = Float::with_val(prec, &central2 / Float::with_val(prec, &m * &m));
        let mu4 = {
            let m2 = Float::with_val(prec, &m * &m);
            let mut t = Float::with_val(prec, Float::with_val(prec, &m2 * &m) * s4);
            t -= Float::with_val(prec, Float::with_val(prec, &m2 * s3) * &s1) * 4u32;
            t += Float::with_val(prec, Float::with_val(prec, &m * s2_) * &s1sq) * 6u32;
            t -= Float::with_val(prec, &s1sq * &s1sq) * 3u32;
            t / Float::with_val(prec, &m2 * &m2)
        };
        let mut s2 = Float::with_val(prec, &mu2 * &m);
        s2 /= Float::with_val(prec, &m - 1u32);
        let se_mean = Float::with_val(prec, &s2 / &m).max(&Float::new(prec)).sqrt();
        // Var(s²) = μ₄/M − σ⁴(M − 3)/(M(M − 1)).
        let sigma4 = Float::with_val(prec, &s2 * &s2);
        let mut var_s2 = Float::with_val(prec, &mu4 / &m);
        let mut t = Float::with_val(prec, &sigma4 * Float::with_val(prec, &m - 3u32));
        t /= Float::with_val(prec, &m * Float::with_val(prec, &m - 1u32));
        var_s2 -= t;
        let mut zero = Float::new(prec);
        zero.assign(0);
        let se_var = var_s2.max(&zero).sqrt();
        Some([mean, se_mean, s2, se_var])
    }

    /// Mean, variance and their standard errors as doubles (`None` below 4
    /// trials, where the variance's error is not defined). A value beyond
    /// the range of a double is rounded to ±inf or 0 here: [`PowerSums::estimates`]
    /// says so instead.
    pub fn summary(&self) -> Option<Summary> {
        let [mean, se_mean, s2, se_var] = self.moments()?;
        Some(Summary {
            mean: WithError { value: mean.to_f64(), se: se_mean.to_f64() },
            variance: WithError { value: s2.to_f64(), se: se_var.to_f64() },
        })
    }

    /// The mean and the variance, each with its standard error, or the
    /// reason it is not given: fewer than 4 values; all values equal (no
    /// spread: standard errors of 0 would make any z-score infinite); a
    /// value or its error outside the range of a double (printed here at
    /// full range, with its error).
    pub fn estimates(&self) -> Estimates {
        let Some([mean, se_mean, s2, se_var]) = self.moments() else {
            let why = format!(
                "fewer than 4 trials ({}): the variance's standard error is not defined (merge shards first)",
                self.count
            );
            return Estimates { mean: Err(why.clone()), variance: Err(why) };
        };
        if s2 <= 0 {
            let why = if s2 == 0 {
                format!(
                    "all {} values are equal ({:.6e}): no spread, so the standard errors are 0 and the mean and \
                     variance are not resolved",
                    self.count,
                    mean.to_f64()
                )
            } else {
                "the power sums are inconsistent (negative variance)".to_string()
            };
            return Estimates { mean: Err(why.clone()), variance: Err(why) };
        }
        Estimates { mean: as_double("mean L", &mean, &se_mean), variance: as_double("Var L", &s2, &se_var) }
    }

    /// Sums given as doubles (for instance accumulated by a renderer in
    /// another language), taken as exact. `None` if a sum is not finite.
    pub fn from_f64_sums(count: u64, sums: [f64; 4]) -> Option<PowerSums> {
        if sums.iter().any(|s| !s.is_finite()) {
            return None;
        }
        let mut out = PowerSums { count, ..PowerSums::default() };
        for (a, b) in out.sums.iter_mut().zip(sums) {
            a.assign(b);
        }
        Some(out)
    }

    /// The exact sums as hexadecimal strings (for shard files).
    pub fn to_hex(&self) -> [String; 4] {
        std::array::from_fn(|k| self.sums[k].to_string_radix(16, None))
    }

    /// Sums read back from [`PowerSums::to_hex`].
    pub fn from_hex(count: u64, hex: &[String; 4]) -> Result<PowerSums, String> {
        let mut sums: [Float; 4] = std::array::from_fn(|_| Float::new(EXACT_BITS));
        for (k, text) in hex.iter().enumerate() {
            let parsed = Float::parse_radix(text, 16).map_err(|e| format!("sum {}: {e}", k + 1))?;
            sums[k].assign(parsed);
            if !sums[k].is_finite() {
                return Err(format!("sums[{k}] = \"{text}\": must be finite"));
            }
            if sums[k].to_string_radix(16, None) != *text {
                return Err(format!("sums[{k}] = \"{text}\": does not fit {EXACT_BITS} bits exactly"));
            }
        }
        let out = PowerSums { count, sums };
        out.check_real()?;
        Ok(out)
    }

    /// Whether these can be the sums of non-negative numbers of which
    /// `nonzero` are > 0 (a tracer's L, a sum of non-negative hit
    /// contributions), checked exactly on top of [`PowerSums::check_real`]:
    /// Σ L ≥ 0 and Σ L³ ≥ 0; all four sums 0 or all > 0; (Σ L²)² ≤ Σ L · Σ L³
    /// and (Σ L³)² ≤ Σ L² · Σ L⁴ (Cauchy–Schwarz on √L·L^{k/2}); (Σ L)² ≤
    /// k Σ L² over the k = `nonzero` values > 0 (with the two before it,
    /// this implies (Σ L²)² ≤ k Σ L⁴). The products are formed at twice the
    /// sums' width: exact. The error names the sum.
    pub fn check_non_negative(&self, nonzero: u64) -> Result<(), String> {
        let s = &self.sums;
        let why = "every L is a sum of non-negative hit contributions";
        for k in [0, 2] {
            if s[k] < 0 {
                return Err(format!(
                    "sums[{k}] (Σ L{}) = {:.6e}: must be >= 0 ({why})",
                    ["", "²", "³", "⁴"][k],
                    s[k].to_f64()
                ));
            }
        }
        if !self.is_zero() && s.iter().any(Float::is_zero) {
            return Err(format!(
                "sums: not the power sums of non-negative numbers (Σ L, Σ L², Σ L³, Σ L⁴ must be all 0 or all > 0; {why})"
            ));
        }
        let prec = 2 * EXACT_BITS + 64;
        let k = Float::with_val(prec, nonzero);
        let product = |a: &Float, b: &Float| Float::with_val(prec, a * b);
        for (lhs, rhs, rule) in [
            (product(&s[1], &s[1]), product(&s[0], &s[2]), "(Σ L²)² <= Σ L · Σ L³"),
            (product(&s[2], &s[2]), product(&s[1], &s[3]), "(Σ L³)² <= Σ L² · Σ L⁴"),
            (product(&s[0], &s[0]), product(&k, &s[1]), "(Σ L)² <= k Σ L²"),
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
        self.sums.iter().all(Float::is_zero)
    }

    /// Whether these can be the sums of `count` real numbers: Σ L² ≥ 0,
    /// Σ L⁴ ≥ 0, M Σ L² ≥ (Σ L)², M Σ L⁴ ≥ (Σ L²)² (Cauchy–Schwarz; exact at
    /// twice the sums' width), all 0 when M = 0.
    pub fn check_real(&self) -> Result<(), String> {
        let s = &self.sums;
        if self.count == 0 {
            return match s.iter().position(|x| !x.is_zero()) {
                Some(k) => Err(format!("sums[{k}]: must be 0 for 0 trials")),
                None => Ok(()),
            };
        }
        let prec = 2 * EXACT_BITS + 64;
        let m = Float::with_val(prec, self.count);
        let square = |x: &Float| Float::with_val(prec, x * x);
        let times_m = |x: &Float| Float::with_val(prec, x * &m);
        if s[1] < 0 || s[3] < 0 || times_m(&s[1]) < square(&s[0]) || times_m(&s[3]) < square(&s[1]) {
            return Err(format!(
                "sums: not the power sums of {} real numbers (need Σ L², Σ L⁴ >= 0, M Σ L² >= (Σ L)², \
                 M Σ L⁴ >= (Σ L²)²)",
                self.count
            ));
        }
        Ok(())
    }
}
