//! A renderer's per-iteration pixel values, accumulated exactly.

use mcrt_reference::moments::PowerSums;
use serde::Serialize;
use std::fmt;

/// A measured quantity and its standard error.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Measured {
    /// The sample estimate.
    pub value: f64,
    /// Its standard error.
    pub standard_error: f64,
}

/// The per-iteration values L of one pixel, accumulated as exact power sums
/// Σ L, Σ L², Σ L³, Σ L⁴ (2 300-bit MPFR numbers: any sum of up to 2⁶⁴
/// doubles is exact), and the number of nonzero values among them. Exact
/// sums make the result independent of the order of accumulation: samples
/// pushed by several threads and merged give the same numbers, bit for bit,
/// as one thread pushing them all.
///
/// ```
/// use mcrt_noise::Samples;
///
/// let mut a = Samples::new();
/// let mut b = Samples::new();
/// a.extend([1.0, 2.0])?;
/// b.extend([3.0, 0.0])?;
/// let merged = a.merge(&b);
/// let mut one = Samples::new();
/// one.extend([0.0, 3.0, 2.0, 1.0])?;
/// assert_eq!(merged.mean(), one.mean());
/// assert_eq!(merged.mean().unwrap().value, 1.5);
/// assert_eq!(merged.nonzero(), Some(3));
/// assert!(one.push(f64::NAN).is_err());
/// # Ok::<(), mcrt_noise::SampleError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Samples {
    sums: PowerSums,
    /// Relative error bound of the sums (0 when accumulated here).
    sums_relative_error: f64,
    /// How many of the values are nonzero: exact when pushed here, `None`
    /// for power sums given without it.
    nonzero: Option<u64>,
}

impl Default for Samples {
    /// No samples (none of them nonzero).
    fn default() -> Self {
        Samples { sums: PowerSums::default(), sums_relative_error: 0.0, nonzero: Some(0) }
    }
}

/// A value that cannot be a sample, or sums that cannot be samples.
#[derive(Debug, Clone, PartialEq)]
pub enum SampleError {
    /// L or L⁴ is not a finite double (|L| ≥ ~10⁷⁷: rescale the light's flux,
    /// L is linear in it).
    NotFinite {
        /// Index of the value among those pushed (0-based, counting accepted ones).
        index: u64,
        /// The value.
        value: f64,
    },
    /// Power sums given from outside are unusable: a field out of its range
    /// (the message names the field, the value and the range).
    InvalidSums(String),
    /// Power sums (and nonzero count) that no real numbers have: a necessary
    /// inequality fails, even allowing for the sums' stated relative error.
    Unrealisable {
        /// How many values the sums claim.
        count: u64,
        /// How many of them are nonzero, if stated.
        nonzero: Option<u64>,
        /// Σ L, Σ L², Σ L³, Σ L⁴ as given.
        sums: [f64; 4],
        /// Their stated relative error.
        sums_relative_error: f64,
        /// The inequality that fails.
        violated: SumsInequality,
        /// Its two sides, formed exactly from the sums as given (no
        /// allowance), in decimal.
        sides: (String, String),
    },
}

/// A necessary condition on the power sums S_k = Σ L^k of M real numbers of
/// which N are nonzero (N = M when the nonzero count is not stated), in the
/// central moments μ_k = Σ (L − S₁/M)^k / M where it is about spread.
/// `Samples::from_power_sums` derives each one in its source; the check
/// allows for the sums' stated relative error, so only sums that are
/// impossible by more than their rounding are refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum SumsInequality {
    /// (Σ L)² ≤ N Σ L² (Cauchy–Schwarz; with N = M: s² ≥ 0).
    SquareOfSumAtMostNTimesSumOfSquares,
    /// (Σ L²)² ≤ N Σ L⁴ (Cauchy–Schwarz).
    SquareOfSumOfSquaresAtMostNTimesFourthSum,
    /// (Σ L³)² ≤ Σ L² · Σ L⁴ (Cauchy–Schwarz).
    SquareOfThirdSumAtMostSecondTimesFourth,
    /// Σ L⁴ ≤ (Σ L²)² (no L² exceeds Σ L²).
    FourthSumAtMostSquareOfSecond,
    /// μ₄ ≥ μ₂² (the variance of (L − mean)² is not negative).
    CentralFourthAtLeastSquareOfSecond,
    /// μ₂ μ₄ ≥ μ₃² + μ₂³ (Pearson: the moment matrix of 1, L, L² is
    /// positive semi-definite).
    Pearson,
    /// μ₄ ≤ (M − 1) μ₂² (no squared deviation exceeds (M − 1)/M of their sum).
    CentralFourthAtMostMMinusOneTimesSquare,
    /// N ≥ 1 nonzero values need Σ L² > 0.
    NonzeroValuesNeedPositiveSquares,
}

impl fmt::Display for SumsInequality {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            SumsInequality::SquareOfSumAtMostNTimesSumOfSquares => "(Σ L)² ≤ N·Σ L²",
            SumsInequality::SquareOfSumOfSquaresAtMostNTimesFourthSum => "(Σ L²)² ≤ N·Σ L⁴",
            SumsInequality::SquareOfThirdSumAtMostSecondTimesFourth => "(Σ L³)² ≤ Σ L²·Σ L⁴",
            SumsInequality::FourthSumAtMostSquareOfSecond => "Σ L⁴ ≤ (Σ L²)²",
            SumsInequality::CentralFourthAtLeastSquareOfSecond => "μ₄ ≥ μ₂² (central moments)",
            SumsInequality::Pearson => "μ₂·μ₄ ≥ μ₃² + μ₂³ (central moments; Pearson)",
            SumsInequality::CentralFourthAtMostMMinusOneTimesSquare => "μ₄ ≤ (M − 1)·μ₂² (central moments)",
            SumsInequality::NonzeroValuesNeedPositiveSquares => "Σ L² > 0 when N ≥ 1",
        })
    }
}

impl SumsInequality {
    /// Whether the inequality involves N, the number of nonzero values.
    fn uses_nonzero(self) -> bool {
        matches!(
            self,
            SumsInequality::SquareOfSumAtMostNTimesSumOfSquares
                | SumsInequality::SquareOfSumOfSquaresAtMostNTimesFourthSum
                | SumsInequality::NonzeroValuesNeedPositiveSquares
        )
    }
}

impl fmt::Display for SampleError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SampleError::NotFinite { index, value } => write!(
                f,
                "sample {index} = {value:e}: must be finite with a finite fourth power (|L| < 1e77; rescale the flux)"
            ),
            SampleError::InvalidSums(why) => write!(f, "power sums: {why}"),
            SampleError::Unrealisable { count, nonzero, sums, sums_relative_error, violated, sides } => {
                write!(f, "power sums: sums = {sums:?} with count = {count}")?;
                if let Some(k) = nonzero {
                    write!(f, " and nonzero = {k}")?;
                }
                write!(f, ": not the power sums of real numbers: {violated} must hold")?;
                if violated.uses_nonzero() {
                    match nonzero {
                        Some(k) => write!(f, " (N = nonzero = {k})")?,
                        None => write!(f, " (N = count = {count}, no nonzero count given)")?,
                    }
                }
                write!(
                    f,
                    ", but its left side is {} and its right side {}, even allowing for the stated relative error {sums_relative_error:e} \
                     of each sum",
                    sides.0, sides.1
                )
            }
        }
    }
}

impl std::error::Error for SampleError {}

impl Samples {
    /// No samples yet.
    pub fn new() -> Samples {
        Samples::default()
    }

    /// Power sums accumulated elsewhere (for instance by a renderer in
    /// another language): `count` values and Σ Lᵏ for k = 1…4, with a bound
    /// on their relative error (`sums_relative_error`, in [0, 10⁻³): 0 if
    /// they are exact; about (count + 2) · 2⁻⁵³ for plain f64 summation of
    /// powers formed by multiplication; compensated summation gives a few
    /// 2⁻⁵³). The check adds the effect of that error to the prediction's
    /// bars. How many values are nonzero is unknown (the check then says
    /// that it could not check sparsity): [`Samples::with_nonzero`] states it.
    ///
    /// Sums that no `count` real numbers have are refused
    /// ([`SampleError::Unrealisable`], naming the [`SumsInequality`] that
    /// fails): for instance Σ L⁴ above (Σ L²)².
    ///
    /// ```
    /// use mcrt_noise::{SampleError, Samples, SumsInequality};
    /// let s = Samples::from_power_sums(4, [10.0, 30.0, 100.0, 354.0], 0.0)?;
    /// assert_eq!(s.mean().unwrap().value, 2.5);
    /// assert_eq!(s.nonzero(), None);
    /// assert!(Samples::from_power_sums(4, [10.0, 1.0, 100.0, 354.0], 0.0).is_err());
    /// let err = Samples::from_power_sums(10_000, [11.1, 0.8, 0.5, 1e10], 1e-12).unwrap_err();
    /// assert!(matches!(
    ///     err,
    ///     SampleError::Unrealisable { violated: SumsInequality::FourthSumAtMostSquareOfSecond, .. }
    /// ));
    /// # Ok::<(), mcrt_noise::SampleError>(())
    /// ```
    pub fn from_power_sums(count: u64, sums: [f64; 4], sums_relative_error: f64) -> Result<Samples, SampleError> {
        if !(0.0..1e-3).contains(&sums_relative_error) {
            return Err(SampleError::InvalidSums(format!(
                "sums_relative_error = {sums_relative_error:e}: must be in [0, 1e-3)"
            )));
        }
        if count == 0 {
            return Err(SampleError::InvalidSums("count = 0: must be >= 1".into()));
        }
        let power_sums = PowerSums::from_f64_sums(count, sums)
            .ok_or_else(|| SampleError::InvalidSums(format!("sums = {sums:?}: must be finite")))?;
        let samples = Samples { sums: power_sums, sums_relative_error, nonzero: None };
        samples.realisable(None)?;
        Ok(samples)
    }

    /// These power sums with the number of nonzero values among them stated
    /// (in [0, count]), so that the check can tell sparse values (a few
    /// nonzero among many zeros) from enough of them
    /// ([`crate::check::MIN_NONZERO`]). The sums are checked again with N =
    /// `nonzero` (zeros add nothing to them: (Σ L)² ≤ N Σ L², …). For
    /// samples pushed one by one the count is already exact, and must agree.
    ///
    /// ```
    /// use mcrt_noise::Samples;
    /// let s = Samples::from_power_sums(10, [3.0, 3.0, 3.0, 3.0], 0.0)?.with_nonzero(3)?;
    /// assert_eq!(s.nonzero(), Some(3));
    /// // Three ones cannot be two nonzero values: (Σ L)² = 9 > 2·Σ L² = 6.
    /// let err = Samples::from_power_sums(10, [3.0, 3.0, 3.0, 3.0], 0.0)?.with_nonzero(2).unwrap_err();
    /// assert!(err.to_string().contains("(Σ L)² ≤ N·Σ L²"), "{err}");
    /// assert!(Samples::from_power_sums(10, [3.0, 3.0, 3.0, 3.0], 0.0)?.with_nonzero(11).is_err());
    /// # Ok::<(), mcrt_noise::SampleError>(())
    /// ```
    pub fn with_nonzero(self, nonzero: u64) -> Result<Samples, SampleError> {
        let count = self.count();
        if nonzero > count {
            return Err(SampleError::InvalidSums(format!("nonzero = {nonzero}: must be in [0, count = {count}]")));
        }
        if let Some(known) = self.nonzero {
            if known != nonzero {
                return Err(SampleError::InvalidSums(format!(
                    "nonzero = {nonzero}: these samples were pushed one by one and have exactly {known} nonzero \
                     values"
                )));
            }
            return Ok(self);
        }
        self.realisable(Some(nonzero))?;
        Ok(Samples { nonzero: Some(nonzero), ..self })
    }

    /// Whether these sums can be those of real numbers (`nonzero` of them
    /// nonzero, if stated).
    fn realisable(&self, nonzero: Option<u64>) -> Result<(), SampleError> {
        let sums = self.exact_sums();
        realisable(self.count(), nonzero, &sums, self.sums_relative_error).map_err(|(violated, sides)| {
            SampleError::Unrealisable {
                count: self.count(),
                nonzero,
                sums: sums.each_ref().map(rug::Float::to_f64),
                sums_relative_error: self.sums_relative_error,
                violated,
                sides,
            }
        })
    }

    /// Adds one iteration's L.
    pub fn push(&mut self, l: f64) -> Result<(), SampleError> {
        let fourth = (l * l) * (l * l);
        if !(l.is_finite() && fourth.is_finite()) {
            return Err(SampleError::NotFinite { index: self.sums.count, value: l });
        }
        self.sums.push(l);
        self.nonzero = self.nonzero.map(|k| k + u64::from(l != 0.0));
        Ok(())
    }

    /// Adds every value of `values`, stopping at the first that cannot be a sample.
    pub fn extend<I: IntoIterator<Item = f64>>(&mut self, values: I) -> Result<(), SampleError> {
        values.into_iter().try_for_each(|l| self.push(l))
    }

    /// These samples and `other`'s together (exact: the order does not matter).
    pub fn merge(mut self, other: &Samples) -> Samples {
        self.nonzero = self.nonzero.zip(other.nonzero).map(|(a, b)| a + b);
        self.sums = self.sums.merge(&other.sums);
        self.sums_relative_error = self.sums_relative_error.max(other.sums_relative_error);
        self
    }

    /// How many values.
    pub fn count(&self) -> u64 {
        self.sums.count
    }

    /// How many values are nonzero: exact for values pushed here (and
    /// merges of such), `None` for power sums given without the count
    /// ([`Samples::with_nonzero`]).
    pub fn nonzero(&self) -> Option<u64> {
        self.nonzero
    }

    /// The sums' relative error bound (0 when accumulated here).
    pub fn sums_relative_error(&self) -> f64 {
        self.sums_relative_error
    }

    /// The sample mean and its standard error √(s²/M) (`None` below 4 values).
    pub fn mean(&self) -> Option<Measured> {
        self.sums.summary().map(|s| Measured { value: s.mean.value, standard_error: s.mean.se })
    }

    /// The unbiased sample variance s² and its standard error from the
    /// fourth central moment, Var(s²) = μ₄/M − σ⁴(M − 3)/(M(M − 1)) (`None`
    /// below 4 values).
    pub fn variance(&self) -> Option<Measured> {
        self.sums.summary().map(|s| Measured { value: s.variance.value, standard_error: s.variance.se })
    }

    /// The mean and s², each with a standard error a z-test can use, or
    /// why it has none: all values equal (zero spread: a standard error of
    /// 0 is no error bar), or the value or its error beyond the range of a
    /// double (`None` below 4 values).
    pub(crate) fn estimates(&self) -> Option<(Result<Measured, String>, Result<Measured, String>)> {
        if self.count() < 4 {
            return None;
        }
        let as_measured = |r: Result<mcrt_reference::moments::WithError, String>| {
            r.map(|w| Measured { value: w.value, standard_error: w.se })
        };
        if self.all_equal() {
            let why = format!(
                "all {} values are equal ({:.6e}): zero spread, so there is no standard error and no z-score",
                self.count(),
                self.mean().map_or(f64::NAN, |m| m.value)
            );
            return Some((Err(why.clone()), Err(why)));
        }
        let e = self.sums.estimates();
        Some((as_measured(e.mean), as_measured(e.variance)))
    }

    /// Whether every value is the same: M·Σ L² = (Σ L)², exactly.
    fn all_equal(&self) -> bool {
        use rug::Float;
        let [s1, s2, _, _] = self.exact_sums();
        let p = 2 * SUM_BITS + 128;
        Float::with_val(p, &s2 * self.count()) == Float::with_val(p, &s1 * &s1)
    }

    /// The exact sums, read back from [`PowerSums::to_hex`].
    fn exact_sums(&self) -> [rug::Float; 4] {
        self.sums.to_hex().map(|hex| {
            let parsed = rug::Float::parse_radix(&hex, 16).expect("PowerSums::to_hex is MPFR's own format");
            rug::Float::with_val(SUM_BITS, parsed)
        })
    }

    /// Bounds on the error of the mean and of s² caused by the sums'
    /// relative error ε: |δ mean| ≤ ε|Σ L|/M and
    /// |δ s²| ≤ ε(Σ L² + 2(Σ L)²/M)/(M − 1) (0 for exact sums).
    pub(crate) fn rounding_bounds(&self) -> (f64, f64) {
        let eps = self.sums_relative_error;
        if eps == 0.0 {
            return (0.0, 0.0);
        }
        let n = self.count() as f64;
        match (self.mean(), self.variance()) {
            (Some(m), Some(v)) => {
                let s1 = m.value * n;
                let s2 = (v.value * (n - 1.0) + s1 * m.value).abs();
                (eps * m.value.abs(), eps * (s2 + 2.0 * s1 * m.value) / (n - 1.0))
            }
            _ => (0.0, 0.0),
        }
    }
}

/// Width of the power sums as read back from [`PowerSums::to_hex`] (that of
/// the exact sums).
const SUM_BITS: u32 = 2300;

/// Whether power sums S₁…S₄ of M = `count` numbers, N = `nonzero` of them
/// nonzero (N = M if not stated), can come from real numbers, each sum known
/// to relative error ε = `eps`. Each inequality is necessary (derived below);
/// the sums are refused only if it fails for every set of sums within ε of
/// those given (the returned sides are formed from the sums as given).
///
/// The raw inequalities take each sum as an interval Ŝ_k ± ε'|Ŝ_k|, ε' =
/// 1.01 ε (|S − Ŝ| ≤ ε|S| ≤ ε|Ŝ|/(1 − ε), ε < 10⁻³), and each side at its
/// most favourable end. The central sums c₂ = MS₂ − S₁² (= M²μ₂), c₃ =
/// M²S₃ − 3MS₂S₁ + 2S₁³ (= M³μ₃), c₄ = M³S₄ − 4M²S₃S₁ + 6MS₂S₁² − 3S₁⁴
/// (= M⁴μ₄) are polynomials whose terms are products of k sums, each off by
/// at most ~kε of itself (`1.01` covers the higher orders); their bounds
/// ĉ ± e are then used as intervals the same way. Everything is formed at
/// 14 400 bits, room for products of six 2 300-bit sums: a rounding there
/// lies far below any stated ε.
///
/// Derivations, for real L₁…L_M:
/// 1. (Σ L)² ≤ N Σ L²: Cauchy–Schwarz over the N nonzero values, (Σ 1·L)² ≤
///    (Σ 1)(Σ L²). With N = M this is c₂ ≥ 0.
/// 2. (Σ L²)² ≤ N Σ L⁴: the same with L² in place of L.
/// 3. (Σ L³)² ≤ Σ L² · Σ L⁴: Cauchy–Schwarz on the vectors (L_i) and (L_i²).
/// 4. Σ L⁴ ≤ (Σ L²)²: every L_i² ≤ Σ_j L_j², so Σ L_i⁴ = Σ L_i²·L_i² ≤
///    (Σ L_j²)·Σ L_i².
/// 5. μ₄ ≥ μ₂², i.e. c₄ ≥ c₂²: the mean of d² (d = L − mean) squared is at
///    most the mean of d⁴ (the variance of d² is not negative).
/// 6. μ₂μ₄ ≥ μ₃² + μ₂³, i.e. c₂c₄ ≥ c₃² + c₂³ (Pearson): the matrix
///    Σ_i vᵢvᵢᵀ, vᵢ = (1, dᵢ, dᵢ²), is positive semi-definite; its
///    determinant is M³(μ₂μ₄ − μ₃² − μ₂³). (It implies 5 when μ₂ > 0.)
/// 7. μ₄ ≤ (M − 1)μ₂², i.e. c₄ ≤ (M − 1)c₂²: the deviations sum to 0, so
///    dᵢ = −Σ_{j≠i} d_j and, by Cauchy–Schwarz, dᵢ² ≤ (M − 1)(Σ d² − dᵢ²),
///    i.e. dᵢ² ≤ (M − 1)/M · Σ d²; then Σ d⁴ ≤ max dᵢ² · Σ d² ≤
///    (M − 1)/M (Σ d²)², which is the inequality (Σ d² = Mμ₂, Σ d⁴ = Mμ₄).
///    It binds at M = 1 (μ₂ = 0) and M = 2 (μ₄ = μ₂²).
/// 8. N ≥ 1 needs S₂ > 0 (a nonzero L has L² > 0; with ε < 1 a sum within
///    ε of 0 relative is 0).
fn realisable(
    count: u64,
    nonzero: Option<u64>,
    sums: &[rug::Float; 4],
    eps: f64,
) -> Result<(), (SumsInequality, (String, String))> {
    use rug::Float;
    use SumsInequality as I;
    const P: u32 = 6 * SUM_BITS + 6 * 64 + 216;
    let f = |x: &Float| Float::with_val(P, x);
    let n = Float::with_val(P, count);
    let k = Float::with_val(P, nonzero.unwrap_or(count));
    let [s1, s2, s3, s4] = sums.each_ref().map(f);
    let zero = Float::new(P);
    let eps1 = eps * 1.01;
    // An interval's ends, and its smallest and largest |x|.
    let hi = |x: &Float, e: &Float| Float::with_val(P, x + e);
    let lo = |x: &Float, e: &Float| Float::with_val(P, x - e);
    let min_abs = |x: &Float, e: &Float| Float::with_val(P, Float::with_val(P, x.abs_ref()) - e).max(&zero);
    let max_abs = |x: &Float, e: &Float| Float::with_val(P, Float::with_val(P, x.abs_ref()) + e);
    let raw_err = |x: &Float| Float::with_val(P, x.abs_ref()) * eps1;
    let [e1, e2, e3, e4] = [&s1, &s2, &s3, &s4].map(raw_err);
    let sq = |x: &Float| Float::with_val(P, x * x);
    let mul = |a: &Float, b: &Float| Float::with_val(P, a * b);
    let show = |x: Float| format!("{x:.6e}");
    let fail = |which, l: Float, r: Float| Err((which, (show(l), show(r))));
    // 1, 2, 3, 4: raw sums.
    if sq(&min_abs(&s1, &e1)) > mul(&k, &hi(&s2, &e2)) {
        return fail(I::SquareOfSumAtMostNTimesSumOfSquares, sq(&s1), mul(&k, &s2));
    }
    if sq(&min_abs(&s2, &e2)) > mul(&k, &hi(&s4, &e4)) {
        return fail(I::SquareOfSumOfSquaresAtMostNTimesFourthSum, sq(&s2), mul(&k, &s4));
    }
    let (s2_hi, s4_hi) = (hi(&s2, &e2).max(&zero), hi(&s4, &e4).max(&zero));
    if sq(&min_abs(&s3, &e3)) > mul(&s2_hi, &s4_hi) {
        return fail(I::SquareOfThirdSumAtMostSecondTimesFourth, sq(&s3), mul(&s2, &s4));
    }
    if lo(&s4, &e4) > sq(&max_abs(&s2, &e2)) {
        return fail(I::FourthSumAtMostSquareOfSecond, s4.clone(), sq(&s2));
    }
    if nonzero.is_some_and(|k| k >= 1) && s2.is_zero() {
        return fail(I::NonzeroValuesNeedPositiveSquares, s2.clone(), zero.clone());
    }
    // 5, 6, 7: central sums, each with the bound of its terms' rounding.
    let s1sq = sq(&s1);
    let n2 = sq(&n);
    let central = |terms: &[(Float, u32)]| {
        let value = terms.iter().fold(Float::new(P), |acc, (t, _)| acc + t);
        let err = terms
            .iter()
            .fold(Float::new(P), |acc, (t, k)| acc + Float::with_val(P, t.abs_ref()) * (eps1 * f64::from(*k)));
        (value, err)
    };
    let (c2, ec2) = central(&[(mul(&n, &s2), 1), (-s1sq.clone(), 2)]);
    let (c3, ec3) = central(&[(mul(&n2, &s3), 1), (mul(&mul(&n, &s2), &s1) * -3i32, 2), (mul(&s1sq, &s1) * 2u32, 3)]);
    let (c4, ec4) = central(&[
        (mul(&mul(&n2, &n), &s4), 1),
        (mul(&mul(&n2, &s3), &s1) * -4i32, 2),
        (mul(&mul(&n, &s2), &s1sq) * 6u32, 3),
        (sq(&s1sq) * -3i32, 4),
    ]);
    let c2_lo = lo(&c2, &ec2).max(&zero);
    let c2_hi = hi(&c2, &ec2).max(&zero);
    let c4_hi = hi(&c4, &ec4);
    if c4_hi < sq(&c2_lo) {
        // Shown as μ₄ and μ₂² (c₄/M⁴, c₂²/M⁴).
        let m4 = sq(&n2);
        return fail(I::CentralFourthAtLeastSquareOfSecond, Float::with_val(P, &c4 / &m4), sq(&c2) / m4);
    }
    // max over the intervals of c₂(c₄ − c₂²) − c₃² ≤ c₂_hi (c₄_hi − c₂_lo²) − min c₃²
    // (both factors ≥ 0 here).
    let spread = Float::with_val(P, &c4_hi - sq(&c2_lo));
    if mul(&c2_hi, &spread) < sq(&min_abs(&c3, &ec3)) {
        // Shown as μ₂μ₄ and μ₃² + μ₂³ (each over M⁶).
        let m6 = mul(&sq(&n2), &n2);
        let left = mul(&c2, &c4) / &m6;
        let right = Float::with_val(P, sq(&c3) + mul(&sq(&c2), &c2)) / &m6;
        return fail(I::Pearson, left, right);
    }
    let m_minus_1 = Float::with_val(P, &n - 1u32);
    if lo(&c4, &ec4) > mul(&m_minus_1, &sq(&max_abs(&c2, &ec2))) {
        // Shown as μ₄ and (M − 1)μ₂².
        let m4 = sq(&n2);
        let right = mul(&m_minus_1, &sq(&c2)) / &m4;
        return fail(I::CentralFourthAtMostMMinusOneTimesSquare, Float::with_val(P, &c4 / &m4), right);
    }
    Ok(())
}
