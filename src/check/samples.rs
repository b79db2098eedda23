//! A renderer's per-iteration pixel values, accumulated exactly.

use super::extremes::{check_against_sums, Extremes};
use super::realisable::{realisable, SumsInequality};
use super::shape::Shape;
use mcrt_reference::exact::{Dyadic, ExactSum, Powers};
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
/// Σ L … Σ L⁶ (the powers of a double are formed exactly and their sums do
/// not round: `mcrt_reference::exact`), the number of nonzero
/// values, the smallest value and the few largest. All of these are
/// independent of the order of accumulation: samples pushed by several
/// threads and merged give the same numbers, bit for bit, as one thread
/// pushing them all.
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
/// assert_eq!(merged, one);
/// assert!(one.push(f64::NAN).is_err());
/// # Ok::<(), mcrt_noise::SampleError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Samples {
    sums: PowerSums,
    /// Σ L⁵ and Σ L⁶, exact (for the skewness of the squared deviations,
    /// which Var L's test corrects for).
    higher: [ExactSum; 2],
    /// Relative error bound of the sums (0 when accumulated here).
    sums_relative_error: f64,
    /// How many of the values are nonzero: exact when pushed here, `None`
    /// for power sums given without it.
    nonzero: Option<u64>,
    /// The smallest value and the few largest: exact when pushed here,
    /// `None` for power sums given without them.
    extremes: Option<Extremes>,
}

impl Default for Samples {
    /// No samples (none of them nonzero).
    fn default() -> Self {
        Samples {
            sums: PowerSums::default(),
            higher: Default::default(),
            sums_relative_error: 0.0,
            nonzero: Some(0),
            extremes: Some(Extremes::empty()),
        }
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
    /// L is negative: a pixel's L is a sum of non-negative contributions
    /// (flux, transmittance, phase function and the estimator's weights
    /// are all ≥ 0), so a negative value is a bug upstream of the check.
    Negative {
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
        /// Σ L … Σ L⁶ as given.
        sums: Vec<f64>,
        /// Their stated relative error.
        sums_relative_error: f64,
        /// The inequality that fails.
        violated: SumsInequality,
        /// Its two sides, formed exactly from the sums as given (no
        /// allowance), in decimal.
        sides: (String, String),
    },
}

impl fmt::Display for SampleError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SampleError::NotFinite { index, value } => write!(
                f,
                "sample {index} = {value:e}: must be finite with a finite fourth power (|L| < 1e77; rescale the flux)"
            ),
            SampleError::Negative { index, value } => write!(
                f,
                "sample {index} = {value:e}: must be >= 0 (a pixel's L is a sum of non-negative contributions)"
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
    /// another language): `count` values and Σ Lᵏ for k = 1…6, with a bound
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
    /// // The values 1, 2, 3, 4.
    /// let s = Samples::from_power_sums(4, [10.0, 30.0, 100.0, 354.0, 1300.0, 4890.0], 0.0)?;
    /// assert_eq!(s.mean().unwrap().value, 2.5);
    /// assert_eq!(s.nonzero(), None);
    /// assert!(Samples::from_power_sums(4, [10.0, 1.0, 100.0, 354.0, 1300.0, 4890.0], 0.0).is_err());
    /// let err = Samples::from_power_sums(10_000, [11.1, 0.8, 0.5, 1e10, 1e10, 1e20], 1e-12).unwrap_err();
    /// assert!(matches!(
    ///     err,
    ///     SampleError::Unrealisable { violated: SumsInequality::FourthSumAtMostSquareOfSecond, .. }
    /// ));
    /// # Ok::<(), mcrt_noise::SampleError>(())
    /// ```
    pub fn from_power_sums(count: u64, sums: [f64; 6], sums_relative_error: f64) -> Result<Samples, SampleError> {
        if !(0.0..1e-3).contains(&sums_relative_error) {
            return Err(SampleError::InvalidSums(format!(
                "sums_relative_error = {sums_relative_error:e}: must be in [0, 1e-3)"
            )));
        }
        if count == 0 {
            return Err(SampleError::InvalidSums("count = 0: must be >= 1".into()));
        }
        let first = [sums[0], sums[1], sums[2], sums[3]];
        let power_sums = PowerSums::from_f64_sums(count, first)
            .filter(|_| sums[4].is_finite() && sums[5].is_finite())
            .ok_or_else(|| SampleError::InvalidSums(format!("sums = {sums:?}: must be finite")))?;
        let higher = [sums[4], sums[5]].map(|x| {
            let mut sum = ExactSum::default();
            sum.add_f64(x);
            sum
        });
        let samples = Samples { sums: power_sums, higher, sums_relative_error, nonzero: None, extremes: None };
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
    /// let s = Samples::from_power_sums(10, [3.0, 3.0, 3.0, 3.0, 3.0, 3.0], 0.0)?.with_nonzero(3)?;
    /// assert_eq!(s.nonzero(), Some(3));
    /// // Three ones cannot be two nonzero values: (Σ L)² = 9 > 2·Σ L² = 6.
    /// let err = Samples::from_power_sums(10, [3.0, 3.0, 3.0, 3.0, 3.0, 3.0], 0.0)?.with_nonzero(2).unwrap_err();
    /// assert!(err.to_string().contains("(Σ L)² ≤ N·Σ L²"), "{err}");
    /// assert!(Samples::from_power_sums(10, [3.0, 3.0, 3.0, 3.0, 3.0, 3.0], 0.0)?.with_nonzero(11).is_err());
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

    /// These power sums with their smallest and largest value stated: the
    /// same as [`Samples::with_extremes`] with the largest alone.
    ///
    /// ```
    /// use mcrt_noise::Samples;
    /// let sums = [10.0, 30.0, 100.0, 354.0, 1300.0, 4890.0]; // 1, 2, 3, 4
    /// let s = Samples::from_power_sums(4, sums, 0.0)?.with_range(1.0, 4.0)?;
    /// assert_eq!(s.range(), Some((1.0, 4.0)));
    /// assert!(Samples::from_power_sums(4, sums, 0.0)?.with_range(1.0, 3.0).is_err());
    /// # Ok::<(), mcrt_noise::SampleError>(())
    /// ```
    pub fn with_range(self, smallest: f64, largest: f64) -> Result<Samples, SampleError> {
        self.with_extremes(smallest, &[largest])
    }

    /// These power sums with their smallest value and their largest values
    /// (1 to [`TOP_VALUES`](crate::check::TOP_VALUES) of them, any order)
    /// stated. With them the check measures the influence of one value on
    /// the verdict over the values' range, the joint influence of the
    /// largest few, and tests the largest value itself against the tail
    /// bound. Without them no quantity is resolved: the power sums alone
    /// allow one value to carry the whole fourth moment. Refused when the
    /// sums cannot come from values with these extremes
    /// (`check::extremes::check_against_sums` says which conditions; they
    /// are necessary only, so the guarantees resting on the extremes assume
    /// them honest). For samples pushed one by one the extremes are already
    /// exact, and must agree.
    ///
    /// ```
    /// use mcrt_noise::Samples;
    /// let sums = [10.0, 30.0, 100.0, 354.0, 1300.0, 4890.0]; // 1, 2, 3, 4
    /// let s = Samples::from_power_sums(4, sums, 0.0)?.with_extremes(1.0, &[4.0, 3.0])?;
    /// assert_eq!(s.largest_values(), &[4.0, 3.0]);
    /// assert!(Samples::from_power_sums(4, sums, 0.0)?.with_extremes(1.0, &[4.0, 2.5]).is_err());
    /// # Ok::<(), mcrt_noise::SampleError>(())
    /// ```
    pub fn with_extremes(self, smallest: f64, largest: &[f64]) -> Result<Samples, SampleError> {
        if let Some(known) = &self.extremes {
            let given = Extremes::new(smallest, largest);
            let prefix = &known.largest()[..given.largest().len().min(known.largest().len())];
            if known.smallest() != Some(smallest) || prefix != given.largest() {
                return Err(SampleError::InvalidSums(format!(
                    "min = {smallest:e}, largest = {largest:?}: these samples were pushed one by one, and their \
                     smallest and largest values are {:e} and {:?}",
                    known.smallest().unwrap_or(f64::NAN),
                    known.largest()
                )));
            }
            return Ok(self);
        }
        check_against_sums(smallest, largest, self.count(), &self.exact_sums(), self.sums_relative_error)
            .map_err(SampleError::InvalidSums)?;
        Ok(Samples { extremes: Some(Extremes::new(smallest, largest)), ..self })
    }

    /// The smallest and largest value: exact for values pushed here (and
    /// merges of such), `None` for power sums given without them
    /// ([`Samples::with_extremes`]) and for no values.
    pub fn range(&self) -> Option<(f64, f64)> {
        self.extremes.as_ref().and_then(Extremes::range)
    }

    /// The largest values known, in descending order (up to
    /// [`TOP_VALUES`](crate::check::TOP_VALUES); empty when unknown).
    pub fn largest_values(&self) -> &[f64] {
        self.extremes.as_ref().map_or(&[], Extremes::largest)
    }

    /// The samples' shape (mean, standard deviation, skewness, kurtosis;
    /// central moments formed exactly from the sums, then rounded), or
    /// `None` below 4 values, without spread, or when the mean or the
    /// deviation is not a normal double ([`Samples::estimates`] says which).
    pub(crate) fn shape(&self) -> Option<Shape> {
        if self.count() < 4 || self.all_equal() {
            return None;
        }
        // M^k Σ (L − mean)^k = Σ_j C(k, j) S_j (−S₁)^{k−j} M^j (S₀ = M, mean =
        // S₁/M) =: C_k, exactly; μ_k = C_k/M^{k+1}, and the standardised
        // moment μ_k/μ₂^{k/2} is C_k M^{k/2−1}/C₂^{k/2}: a quotient for even
        // k, the signed root of C_k² M^{k−2}/C₂^k for odd k.
        let n = Dyadic::from(self.count());
        let s = self.exact_sums();
        let minus_s1 = -&s[0];
        let central = |k: u32| {
            let mut binomial = 1u64;
            (0..=k).fold(Dyadic::zero(), |acc, j| {
                if j > 0 {
                    binomial = binomial * u64::from(k - j + 1) / u64::from(j);
                }
                let sum = if j == 0 { n.clone() } else { s[j as usize - 1].clone() };
                &acc + &(&(&sum * &minus_s1.pow(k - j)) * &n.pow(j)).mul_u64(binomial)
            })
        };
        let c2 = central(2);
        if c2 <= Dyadic::zero() {
            return None;
        }
        let standard = |k: u32| {
            let ck = central(k);
            if k % 2 == 0 {
                (&ck * &n.pow(k / 2 - 1)).div_to_f64(&c2.pow(k / 2))
            } else {
                let magnitude = (&(&ck * &ck) * &n.pow(k - 2)).sqrt_div_to_f64(&c2.pow(k));
                if ck.is_negative() {
                    -magnitude
                } else {
                    magnitude
                }
            }
        };
        let sd = c2.sqrt_div_to_f64(&n.pow(3));
        let mean = s[0].div_to_f64(&n);
        // 1 ≤ κ ≤ M − 1 (μ₄ ≥ μ₂², μ₄ ≤ (M − 1)μ₂²), against the sums' rounding.
        let kurtosis = standard(4).clamp(1.0, self.count() as f64 - 1.0);
        let normal = |x: f64| x == 0.0 || x.is_normal();
        (normal(mean) && sd.is_normal()).then(|| Shape {
            count: self.count(),
            mean,
            sd,
            skewness: standard(3),
            kurtosis,
            fifth: standard(5),
            sixth: standard(6),
        })
    }

    /// The largest value, or when unknown a lower bound of it from the
    /// sums: the larger of √(Σ L⁴/Σ L²) and Σ L⁶/Σ L⁵ (every L ≤ max, so
    /// Σ L^{k+j} ≤ max^j·Σ L^k), less the sums' relative error; and whether
    /// it is exact.
    pub(crate) fn largest(&self) -> (f64, bool) {
        if let Some(max) = self.largest_values().first() {
            return (*max, true);
        }
        let [_, s2, _, s4, s5, s6] = self.exact_sums();
        let ratio = |a: &Dyadic, b: &Dyadic| if b.is_zero() { 0.0 } else { a.div_to_f64(b) };
        let bound = ratio(&s4, &s2).sqrt().max(ratio(&s6, &s5));
        (bound * (1.0 - 2.02 * self.sums_relative_error), false)
    }

    /// Whether these sums can be those of real numbers (`nonzero` of them
    /// nonzero, if stated).
    fn realisable(&self, nonzero: Option<u64>) -> Result<(), SampleError> {
        let sums = self.exact_sums();
        realisable(self.count(), nonzero, &sums, self.sums_relative_error).map_err(|(violated, sides)| {
            SampleError::Unrealisable {
                count: self.count(),
                nonzero,
                sums: sums.iter().map(Dyadic::to_f64).collect(),
                sums_relative_error: self.sums_relative_error,
                violated,
                sides,
            }
        })
    }

    /// Adds one iteration's L (finite, ≥ 0, with a finite fourth power).
    pub fn push(&mut self, l: f64) -> Result<(), SampleError> {
        let fourth = (l * l) * (l * l);
        if !(l.is_finite() && fourth.is_finite()) {
            return Err(SampleError::NotFinite { index: self.sums.count, value: l });
        }
        if l < 0.0 {
            return Err(SampleError::Negative { index: self.sums.count, value: l });
        }
        // −0 is 0 (and kept as +0 among the extremes).
        let l = l.abs();
        let powers = Powers::<6>::of(l).expect("finite");
        self.sums.push_powers(&powers);
        powers.add_to(5, &mut self.higher[0]);
        powers.add_to(6, &mut self.higher[1]);
        self.nonzero = self.nonzero.map(|k| k + u64::from(l != 0.0));
        if let Some(e) = &mut self.extremes {
            e.push(l);
        }
        Ok(())
    }

    /// Adds every value of `values`, stopping at the first that cannot be a sample.
    pub fn extend<I: IntoIterator<Item = f64>>(&mut self, values: I) -> Result<(), SampleError> {
        values.into_iter().try_for_each(|l| self.push(l))
    }

    /// These samples and `other`'s together (exact: the order does not matter).
    pub fn merge(mut self, other: &Samples) -> Samples {
        self.nonzero = self.nonzero.zip(other.nonzero).map(|(a, b)| a + b);
        self.extremes = self.extremes.as_ref().zip(other.extremes.as_ref()).map(|(a, b)| a.merge(b));
        self.sums = self.sums.merge(&other.sums);
        for (a, b) in self.higher.iter_mut().zip(&other.higher) {
            a.merge(b);
        }
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
        let [s1, s2, _, _, _, _] = self.exact_sums();
        &s2 * &Dyadic::from(self.count()) == &s1 * &s1
    }

    /// The exact sums Σ L … Σ L⁶.
    fn exact_sums(&self) -> [Dyadic; 6] {
        let [a, b, c, d] = self.sums.exact_sums();
        let [e, f] = self.higher.each_ref().map(ExactSum::to_dyadic);
        [a, b, c, d, e, f]
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
