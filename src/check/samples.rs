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
/// doubles is exact). Exact sums make the result independent of the order
/// of accumulation: samples pushed by several threads and merged give the
/// same numbers, bit for bit, as one thread pushing them all.
///
/// ```
/// use mcrt_noise::Samples;
///
/// let mut a = Samples::new();
/// let mut b = Samples::new();
/// a.extend([1.0, 2.0])?;
/// b.extend([3.0, 4.0])?;
/// let merged = a.merge(&b);
/// let mut one = Samples::new();
/// one.extend([4.0, 3.0, 2.0, 1.0])?;
/// assert_eq!(merged.mean(), one.mean());
/// assert_eq!(merged.mean().unwrap().value, 2.5);
/// assert!(one.push(f64::NAN).is_err());
/// # Ok::<(), mcrt_noise::SampleError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Samples {
    sums: PowerSums,
    /// Relative error bound of the sums (0 when accumulated here).
    sums_relative_error: f64,
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
    /// Power sums given from outside are unusable.
    InvalidSums(String),
}

impl fmt::Display for SampleError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SampleError::NotFinite { index, value } => write!(
                f,
                "sample {index} = {value:e}: must be finite with a finite fourth power (|L| < 1e77; rescale the flux)"
            ),
            SampleError::InvalidSums(why) => write!(f, "power sums: {why}"),
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
    /// on their relative error (`sums_relative_error`: 0 if they are exact;
    /// about count · 2⁻⁵³ for plain f64 summation; compensated summation
    /// gives ~2⁻⁵³). The check adds the effect of that error to the
    /// prediction's bars.
    ///
    /// ```
    /// use mcrt_noise::Samples;
    /// let s = Samples::from_power_sums(4, [10.0, 30.0, 100.0, 354.0], 0.0)?;
    /// assert_eq!(s.mean().unwrap().value, 2.5);
    /// assert!(Samples::from_power_sums(4, [10.0, 1.0, 100.0, 354.0], 0.0).is_err());
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
        if let Err(why) = realisable(count, &sums, sums_relative_error) {
            return Err(SampleError::InvalidSums(format!(
                "sums = {sums:?} with count = {count}: not the power sums of real numbers ({why}), even allowing \
                 for the stated relative error {sums_relative_error:e} of each sum"
            )));
        }
        Ok(Samples { sums: power_sums, sums_relative_error })
    }

    /// Adds one iteration's L.
    pub fn push(&mut self, l: f64) -> Result<(), SampleError> {
        let fourth = (l * l) * (l * l);
        if !(l.is_finite() && fourth.is_finite()) {
            return Err(SampleError::NotFinite { index: self.sums.count, value: l });
        }
        self.sums.push(l);
        Ok(())
    }

    /// Adds every value of `values`, stopping at the first that cannot be a sample.
    pub fn extend<I: IntoIterator<Item = f64>>(&mut self, values: I) -> Result<(), SampleError> {
        values.into_iter().try_for_each(|l| self.push(l))
    }

    /// These samples and `other`'s together (exact: the order does not matter).
    pub fn merge(mut self, other: &Samples) -> Samples {
        self.sums = self.sums.merge(&other.sums);
        self.sums_relative_error = self.sums_relative_error.max(other.sums_relative_error);
        self
    }

    /// How many values.
    pub fn count(&self) -> u64 {
        self.sums.count
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

/// Whether power sums S₁…S₄ of `count` numbers can come from real numbers,
/// each sum known to relative error `eps`: the central sums c₂ = nS₂ − S₁²
/// (n²μ₂) and c₄ = n³S₄ − 4n²S₃S₁ + 6nS₂S₁² − 3S₁⁴ (n⁴μ₄) must satisfy
/// c₂ ≥ 0 and c₄ ≥ c₂² (μ₄ ≥ μ₂²: the variance of (L − μ)² is not
/// negative), each up to the rounding the stated error allows. Formed
/// exactly (2400-bit products of the f64 sums).
fn realisable(count: u64, sums: &[f64; 4], eps: f64) -> Result<(), String> {
    use rug::Float;
    const P: u32 = 2400;
    let n = Float::with_val(P, count);
    let [s1, s2, s3, s4] = sums.map(|x| Float::with_val(P, x));
    let n2 = Float::with_val(P, &n * &n);
    let s1sq = Float::with_val(P, &s1 * &s1);
    let terms2 = [Float::with_val(P, &n * &s2), -s1sq.clone()];
    let terms4 = [
        Float::with_val(P, Float::with_val(P, &n2 * &n) * &s4),
        Float::with_val(P, Float::with_val(P, &n2 * &s3) * &s1) * -4i32,
        Float::with_val(P, Float::with_val(P, &n * &s2) * &s1sq) * 6u32,
        Float::with_val(P, &s1sq * &s1sq) * -3i32,
    ];
    // A product of k sums is off by at most ~k·eps of itself.
    let err = |terms: &[Float], ks: &[u32]| {
        terms
            .iter()
            .zip(ks)
            .fold(Float::new(P), |acc, (t, k)| acc + Float::with_val(P, t.abs_ref()) * (eps * f64::from(*k) * 1.01))
    };
    let c2 = terms2.iter().fold(Float::new(P), |acc, t| acc + t);
    let c4 = terms4.iter().fold(Float::new(P), |acc, t| acc + t);
    let (e2, e4) = (err(&terms2, &[1, 2]), err(&terms4, &[1, 2, 3, 4]));
    if Float::with_val(P, &c2 + &e2) < 0 {
        return Err("Σ L² < (Σ L)²/n".into());
    }
    let c2_low = Float::with_val(P, &c2 - &e2).max(&Float::new(P));
    if Float::with_val(P, &c4 + &e4) < Float::with_val(P, &c2_low * &c2_low) {
        return Err("the fourth central moment is below the square of the second".into());
    }
    Ok(())
}
