//! The samples' shape: their standardised central moments up to the
//! sixth, and the shape of the same samples with one value deleted (for the
//! influence of one value on the verdict).

use serde::Serialize;

/// What the samples' moments say about their distribution: count, mean,
/// standard deviation and the standardised central moments m_k/m₂^{k/2}
/// for k = 3…6 (all with 1/M; formed exactly from the power sums, then
/// rounded to doubles). The deviation is kept rather than m₂, which
/// underflows first.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Shape {
    /// M, the number of values.
    pub count: u64,
    /// The sample mean.
    pub mean: f64,
    /// √m₂, m₂ = Σ (L − mean)²/M.
    pub sd: f64,
    /// γ = m₃/m₂^{3/2}.
    pub skewness: f64,
    /// κ = m₄/m₂² (1 ≤ κ ≤ M − 1).
    pub kurtosis: f64,
    /// m₅/m₂^{5/2}.
    pub fifth: f64,
    /// m₆/m₂³.
    pub sixth: f64,
}

impl Shape {
    /// The unbiased sample variance s² = m₂·M/(M − 1) over `scale`
    /// (formed as a square of sd/√scale, so that it does not underflow
    /// before the ratio does).
    pub fn variance_over(&self, scale: f64) -> f64 {
        let n = self.count as f64;
        (self.sd / scale.sqrt()).powi(2) * (n / (n - 1.0))
    }

    /// (Σ d²)²/Σ d⁴ = M/κ (d = L − mean): about how many values carry the
    /// sum of squared deviations (M for equal |d|, 1 when one value does).
    pub fn effective_count(&self) -> f64 {
        self.count as f64 / self.kurtosis
    }

    /// a = √((κ − (M − 3)/(M − 1))/M), the relative standard error of s²
    /// (Var s² = σ⁴(κ − (M − 3)/(M − 1))/M; κ ≥ 1 > (M − 3)/(M − 1)).
    pub fn variance_relative_se(&self) -> f64 {
        let n = self.count as f64;
        ((self.kurtosis - (n - 3.0) / (n - 1.0)) / n).sqrt()
    }

    /// The skewness of the squared deviations d² (whose mean s² is):
    /// (m₆ − 3m₄m₂ + 2m₂³)/(m₄ − m₂²)^{3/2}; 0 when d² is constant to 10⁻⁶
    /// (κ − 1 ≤ 10⁻⁶: its spread, and so its skewness, is then rounding).
    pub fn skewness_of_squares(&self) -> f64 {
        let spread = self.kurtosis - 1.0;
        if spread > 1e-6 {
            (self.sixth - 3.0 * self.kurtosis + 2.0) / spread.powf(1.5)
        } else {
            0.0
        }
    }

    /// The standardised central moments c₀ … c₆ (c₀ = 1, c₁ = 0, c₂ = 1).
    fn standardised(&self) -> [f64; 7] {
        [1.0, 0.0, 1.0, self.skewness, self.kurtosis, self.fifth, self.sixth]
    }

    /// The shape with one value `y` removed (`None` when fewer than 4
    /// values would remain, or when removing it leaves so little spread
    /// that the doubles below lose the moments: the verdict then rests on
    /// that value alone).
    ///
    /// With v = (y − mean)/√m₂ and δ = v/(M − 1) (the mean moves by −δ√m₂),
    /// the central sums of the rest, in units of m₂^{k/2}, are
    /// Σ (d + δ)^k − (v + δ)^k over all M values:
    /// C'_k = M Σ_j C(k, j) δ^{k−j} c_j − (v + δ)^k, c_j the standardised
    /// central moments. Each C'_k of even k is a sum of terms known to a
    /// few 2⁻⁵³ of themselves; it must exceed 10⁴ times that rounding, or
    /// the deleted value carried (nearly) all of that moment.
    pub fn deleted(&self, y: f64) -> Option<Shape> {
        if self.count < 5 {
            return None;
        }
        let n = self.count as f64;
        let c = self.standardised();
        let v = (y - self.mean) / self.sd;
        let delta = v / (n - 1.0);
        let mut sums = [0.0; 7];
        for (k, sum) in sums.iter_mut().enumerate().skip(2) {
            let (mut value, mut magnitude) = (0.0, 0.0);
            for (j, cj) in c.iter().enumerate().take(k + 1) {
                let term = n * binomial(k, j) * delta.powi((k - j) as i32) * cj;
                value += term;
                magnitude += term.abs();
            }
            let own = (v + delta).powi(k as i32);
            value -= own;
            magnitude += own.abs();
            if k % 2 == 0 && !(value > 1e4 * 16.0 * f64::EPSILON * magnitude) {
                return None;
            }
            *sum = value;
        }
        let rest = n - 1.0;
        let m2 = sums[2] / rest;
        let standard = |k: usize| (sums[k] / rest) / m2.powf(k as f64 / 2.0);
        Some(Shape {
            count: self.count - 1,
            mean: self.mean - delta * self.sd,
            sd: self.sd * m2.sqrt(),
            skewness: standard(3),
            // 1 ≤ κ ≤ M − 1 (μ₄ ≥ μ₂², μ₄ ≤ (M − 1)μ₂²), against rounding.
            kurtosis: standard(4).clamp(1.0, rest - 1.0),
            fifth: standard(5),
            sixth: standard(6),
        })
    }
}

/// C(k, j) for k ≤ 6.
fn binomial(k: usize, j: usize) -> f64 {
    (0..j).fold(1.0, |acc, i| acc * (k - i) as f64 / (i + 1) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn shape_of(values: &[f64]) -> Shape {
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let m = |k: i32| values.iter().map(|x| (x - mean).powi(k)).sum::<f64>() / n;
        let s = |k: i32| m(k) / m(2).powf(k as f64 / 2.0);
        Shape {
            count: values.len() as u64,
            mean,
            sd: m(2).sqrt(),
            skewness: s(3),
            kurtosis: s(4),
            fifth: s(5),
            sixth: s(6),
        }
    }

    #[test]
    fn deleting_a_value_gives_the_shape_of_the_rest() {
        let values = [0.0, 0.0, 1.5, 0.2, 7.0, 0.0, 3.3, 0.1, 0.0, 12.0];
        let all = shape_of(&values);
        for k in 0..values.len() {
            let mut rest = values.to_vec();
            let y = rest.remove(k);
            let (got, want) = (all.deleted(y).unwrap(), shape_of(&rest));
            assert_eq!(got.count, want.count);
            let pairs = [
                (got.mean, want.mean),
                (got.sd, want.sd),
                (got.skewness, want.skewness),
                (got.kurtosis, want.kurtosis),
                (got.fifth, want.fifth),
                (got.sixth, want.sixth),
            ];
            for (a, b) in pairs {
                assert!((a - b).abs() <= 1e-11 * b.abs().max(1.0), "{k}: {got:?} against {want:?}");
            }
        }
        // The only spread gone: the verdict would rest on that value.
        assert!(shape_of(&[0.0, 0.0, 0.0, 0.0, 0.0, 5.0]).deleted(5.0).is_none());
    }

    #[test]
    fn the_skewness_of_squares_is_that_of_d_squared() {
        let values = [0.0, 0.0, 1.5, 0.2, 7.0, 0.0, 3.3, 0.1, 0.0, 12.0];
        let shape = shape_of(&values);
        let squares: Vec<f64> = values.iter().map(|x| (x - shape.mean).powi(2)).collect();
        let want = shape_of(&squares).skewness;
        assert!((shape.skewness_of_squares() - want).abs() < 1e-12 * want.abs(), "{want}");
    }
}
