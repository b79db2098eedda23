//! How strict a check is and what it must resolve: the false-alarm rate and
//! its split between the tests, the power of the detectable-error
//! statements, the resolution targets, and the named constants of the
//! verdict's rules.

use mcrt_scene::FieldError;
use serde::Serialize;
use statrs::distribution::{ContinuousCDF, Normal};

/// The z-tests made on one set of samples: the mean and Var L.
pub const CHECKS: u32 = 2;

/// Default relative error of the mean a pass must be able to detect (10 %).
///
/// A pass states power: without a stated target, values that could not
/// catch a renderer whose mean is off by 10 % (at the stated power) are
/// NOT RESOLVED, and the verdict names the sample count that would. 10 %
/// is what a visible bug does to a pixel (a forgotten factor q, a wrong
/// normalisation: tens of per cent), and what a renderer's test of ~10⁵
/// iterations resolves on the bundled scenes.
pub const DEFAULT_TARGET_MEAN: f64 = 0.10;

/// Default relative error of Var L a pass must be able to detect (20 %):
/// twice the mean's, as Var L's standard error is √((κ − 1)/M) relative
/// (κ the kurtosis of L, tens to hundreds here) where the mean's is
/// √((Var L/⟨L⟩²)/M); 20 % still catches camera rays that share their
/// spheres (Var L doubled) and a sub-step drawn at the wrong rate (−55 %).
pub const DEFAULT_TARGET_VARIANCE: f64 = 0.20;

/// The largest change of a z-score that deleting one value may cause in a
/// resolved verdict. A verdict whose z moves by more when one value is
/// removed rests on that value (a firefly, or a tail the samples do not
/// yet resolve) and is NOT RESOLVED. It is also the margin of the
/// guarantee that no single value turns a failure into a pass: a sample
/// whose |z| exceeds the limit by more than this cannot pass with any one
/// value added (`docs/library.md`, "What a verdict assumes").
pub const MAX_INFLUENCE: f64 = 1.0;

/// Fewest values that must carry the spread, M/κ = (Σ d²)²/Σ d⁴ (d = L −
/// mean, κ the samples' kurtosis): below it the moments are dominated by a
/// few values (fireflies, or a tail the samples do not resolve yet) and
/// neither quantity is resolved. The normal approximations behind the
/// z-tests need Var L's relative standard error 1/√(M/κ) below ~0.2; a
/// handful of large values (three at 80 standard deviations among 2·10⁴
/// correct ones: M/κ ≈ 13) falls below it, the bundled scenes at the
/// sample counts their checks need (M/κ in the hundreds and more) do not.
pub const MIN_EFFECTIVE_COUNT: f64 = 30.0;

/// Share of the family-wise false-alarm rate spent on the tail test (the
/// largest value against the Markov and Cantelli bounds, which hold for
/// any distribution); the rest goes to the two z-tests, split by Šidák.
pub const TAIL_SHARE: f64 = 0.01;

/// Smallest family-wise false-alarm rate accepted: below it the per-check
/// tail probability is no longer a normal double, and the z limit would
/// not be finite.
pub const MIN_FALSE_ALARM_RATE: f64 = 1e-300;

/// How strict a check is, and what it must be able to resolve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CheckOptions {
    false_alarm_rate: f64,
    power: f64,
    targets: (f64, f64),
}

impl Default for CheckOptions {
    /// Family-wise false-alarm rate 10⁻³, power 0.9, targets
    /// [`DEFAULT_TARGET_MEAN`] and [`DEFAULT_TARGET_VARIANCE`].
    fn default() -> Self {
        CheckOptions { false_alarm_rate: 1e-3, power: 0.9, targets: (DEFAULT_TARGET_MEAN, DEFAULT_TARGET_VARIANCE) }
    }
}

fn invalid(field: &str, value: f64, allowed: &str) -> FieldError {
    FieldError { field: field.into(), value: short(value), allowed: allowed.into() }
}

/// A value as typed: plain decimals where they are short, else exponent
/// notation (1e-301, not 302 digits).
pub(crate) fn short(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-4..1e15).contains(&x.abs()) {
        x.to_string()
    } else {
        format!("{x:e}")
    }
}

impl CheckOptions {
    /// Options with the family-wise false-alarm rate `false_alarm_rate`
    /// (in [10⁻³⁰⁰, 0.5]): the probability that a correct renderer fails the
    /// check, over its tests together. Every rate accepted has a finite z
    /// limit.
    ///
    /// ```
    /// use mcrt_noise::CheckOptions;
    /// let strict = CheckOptions::new(1e-4)?.with_power(0.99)?.with_targets(0.01, 0.05)?;
    /// assert_eq!(strict.false_alarm_rate(), 1e-4);
    /// assert!(CheckOptions::new(0.0).unwrap_err().to_string().contains("false_alarm_rate = 0"));
    /// assert!(CheckOptions::new(1e-20)?.z_limit().is_finite());
    /// # Ok::<(), mcrt_noise::scene::FieldError>(())
    /// ```
    pub fn new(false_alarm_rate: f64) -> Result<CheckOptions, FieldError> {
        if !(MIN_FALSE_ALARM_RATE..=0.5).contains(&false_alarm_rate) {
            return Err(invalid("false_alarm_rate", false_alarm_rate, "in [1e-300, 0.5]"));
        }
        Ok(CheckOptions { false_alarm_rate, ..CheckOptions::default() })
    }

    /// The power at which the detectable error is stated (in [0.5, 1)):
    /// an error of the detectable size fails the check with at least this
    /// probability. Default 0.9.
    pub fn with_power(self, power: f64) -> Result<CheckOptions, FieldError> {
        if !(0.5..1.0).contains(&power) {
            return Err(invalid("power", power, "in [0.5, 1)"));
        }
        Ok(CheckOptions { power, ..self })
    }

    /// Relative errors of the mean and of Var L the samples must be able to
    /// detect (each finite and > 0; defaults [`DEFAULT_TARGET_MEAN`],
    /// [`DEFAULT_TARGET_VARIANCE`]). Samples whose detectable error
    /// exceeds a target are NOT RESOLVED, with the sample count that would
    /// meet it. A large target (1 = 100 %) asks for little, and the
    /// verdict says how little was shown.
    pub fn with_targets(self, mean: f64, variance: f64) -> Result<CheckOptions, FieldError> {
        self.with_mean_target(mean)?.with_variance_target(variance)
    }

    /// The resolution target of the mean (see [`CheckOptions::with_targets`]).
    pub fn with_mean_target(self, mean: f64) -> Result<CheckOptions, FieldError> {
        Ok(CheckOptions { targets: (target("target_mean", mean)?, self.targets.1), ..self })
    }

    /// The resolution target of Var L (see [`CheckOptions::with_targets`]).
    pub fn with_variance_target(self, variance: f64) -> Result<CheckOptions, FieldError> {
        Ok(CheckOptions { targets: (self.targets.0, target("target_variance", variance)?), ..self })
    }

    /// The family-wise false-alarm rate.
    pub fn false_alarm_rate(&self) -> f64 {
        self.false_alarm_rate
    }

    /// The power of the detectable-error statement.
    pub fn power(&self) -> f64 {
        self.power
    }

    /// The resolution targets (mean, Var L), relative.
    pub fn targets(&self) -> (f64, f64) {
        self.targets
    }

    /// The rate spent on the tail test, [`TAIL_SHARE`] of the family-wise
    /// rate.
    pub fn tail_rate(&self) -> f64 {
        self.false_alarm_rate * TAIL_SHARE
    }

    /// The rate of the two z-tests together: the family-wise rate less the
    /// tail test's share.
    pub fn z_tests_rate(&self) -> f64 {
        self.false_alarm_rate - self.tail_rate()
    }

    /// The rate of each z-test alone: Šidák's split of
    /// [`CheckOptions::z_tests_rate`], 1 − (1 − α_z)^{1/2}.
    pub fn per_check_rate(&self) -> f64 {
        super::family::sidak_split(self.z_tests_rate())
    }

    /// The |z| limit for independent z-scores: Šidák's split of
    /// [`CheckOptions::z_tests_rate`] over the [`CHECKS`] tests, the
    /// two-sided normal quantile of 1 − (1 − α_z)^{1/2}, from the lower
    /// tail (finite for every accepted rate: 37.0 at 10⁻³⁰⁰). It is the
    /// largest limit any correlation of the z-scores gives (Šidák's
    /// inequality) and the limit of the guarantees that rest on the
    /// influence of values. The verdict uses it whatever the z-scores'
    /// correlation, and says how much of the rate the two tests then spend
    /// ([`Verdict::z_tests_spend`](super::Verdict)).
    pub fn z_limit(&self) -> f64 {
        super::family::sidak_limit(self.z_tests_rate())
    }

    /// The normal quantile of the power, z_π.
    pub fn z_power(&self) -> f64 {
        Normal::standard().inverse_cdf(self.power)
    }
}

fn target(field: &str, v: f64) -> Result<f64, FieldError> {
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(invalid(field, v, "finite and > 0 (a relative error)"))
    }
}
