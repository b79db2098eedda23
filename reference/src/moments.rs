//! Exact power sums of the per-trial luminance, and the mean, the variance
//! and their standard errors from them.
//!
//! Σ L, Σ L², Σ L³, Σ L⁴ are kept *exactly* (MPFR numbers of 2 300 bits: any
//! sum of up to 2⁶⁴ doubles is exact at that width, since doubles span
//! 2⁻¹⁰⁷⁴…2¹⁰²⁴). Sums are therefore independent of the order of addition:
//! the result is bit-identical for any number of threads and any split of
//! the trial range into shards, and the central moments are formed at that
//! width too, without cancellation.
//!
//! Standard errors: of the mean, √(s²/M); of the unbiased variance s², from
//! the fourth central moment, Var(s²) = μ₄/M − σ⁴(M − 3)/(M(M − 1)), with the
//! sample moments in place of μ₄, σ² (tested against the exponential
//! distribution, `tests/moments.rs`).

use rug::{Assign, Float};
use serde::{Deserialize, Serialize};

/// Width of the exact sums, in bits.
const EXACT_BITS: u32 = 2300;

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

impl PowerSums {
    /// Adds one trial's L. Panics if L or L⁴ is not a finite double (|L| ≥
    /// ~10⁷⁷: the scene's flux is then beyond what the fourth-moment sums
    /// can hold; rescale the flux, L is linear in it).
    pub fn push(&mut self, l: f64) {
        let fourth = (l * l) * (l * l);
        assert!(l.is_finite() && fourth.is_finite(), "a trial's luminance {l:e} or its fourth power is not finite");
        self.count += 1;
        let mut power = l;
        for (k, sum) in self.sums.iter_mut().enumerate() {
            if k > 0 {
                power *= l;
            }
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

    /// Mean, variance and their standard errors (`None` below 4 trials,
    /// where the variance's error is not defined).
    pub fn summary(&self) -> Option<Summary> {
        if self.count < 4 {
            return None;
        }
        let prec = EXACT_BITS + 64;
        let m = Float::with_val(prec, self.count);
        let mean = Float::with_val(prec, &self.sums[0] / &m);
        let raw: Vec<Float> = self.sums.iter().map(|s| Float::with_val(prec, s / &m)).collect();
        // Central moments from the raw ones (exact inputs, wide arithmetic).
        let mean2 = Float::with_val(prec, &mean * &mean);
        let mu2 = Float::with_val(prec, &raw[1] - &mean2);
        let mu4 = {
            let mut t = raw[3].clone();
            t -= Float::with_val(prec, 4 * Float::with_val(prec, &raw[2] * &mean));
            t += Float::with_val(prec, 6 * Float::with_val(prec, &raw[1] * &mean2));
            t -= Float::with_val(prec, 3 * Float::with_val(prec, &mean2 * &mean2));
            t
        };
        let mut s2 = Float::with_val(prec, &mu2 * &m);
        s2 /= Float::with_val(prec, &m - 1u32);
        let se_mean = Float::with_val(prec, &s2 / &m).sqrt();
        // Var(s²) = μ₄/M − σ⁴(M − 3)/(M(M − 1)).
        let sigma4 = Float::with_val(prec, &s2 * &s2);
        let mut var_s2 = Float::with_val(prec, &mu4 / &m);
        let mut t = Float::with_val(prec, &sigma4 * Float::with_val(prec, &m - 3u32));
        t /= Float::with_val(prec, &m * Float::with_val(prec, &m - 1u32));
        var_s2 -= t;
        let mut zero = Float::new(prec);
        zero.assign(0);
        let se_var = var_s2.max(&zero).sqrt();
        Some(Summary {
            mean: WithError { value: mean.to_f64(), se: se_mean.to_f64() },
            variance: WithError { value: s2.to_f64(), se: se_var.to_f64() },
        })
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
            if sums[k].to_string_radix(16, None) != *text {
                return Err(format!("sum {} does not fit {EXACT_BITS} bits exactly", k + 1));
            }
        }
        Ok(PowerSums { count, sums })
    }
}
