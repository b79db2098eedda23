//! Whether power sums can be those of real, non-negative numbers: the
//! necessary inequalities, each derived, checked allowing for the sums'
//! stated relative error.

use mcrt_reference::exact::Dyadic;
use serde::Serialize;
use std::fmt;

/// A necessary condition on the power sums S_k = Σ L^k (k = 1…6) of M real numbers of
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
    /// Σ L ≥ 0 and Σ L³ ≥ 0 (every L ≥ 0).
    OddSumsNonNegative,
    /// (Σ L²)² ≤ Σ L · Σ L³ (Cauchy–Schwarz on √L and L^{3/2}, L ≥ 0).
    SquareOfSecondAtMostFirstTimesThird,
    /// Σ L⁵ ≥ 0 and Σ L⁶ ≥ 0 (every L ≥ 0).
    HigherSumsNonNegative,
    /// (Σ L⁴)² ≤ Σ L² · Σ L⁶ (Cauchy–Schwarz on L and L³).
    SquareOfFourthAtMostSecondTimesSixth,
    /// (Σ L⁵)² ≤ Σ L⁴ · Σ L⁶ (Cauchy–Schwarz on L² and L³).
    SquareOfFifthAtMostFourthTimesSixth,
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
            SumsInequality::OddSumsNonNegative => "Σ L ≥ 0 and Σ L³ ≥ 0 (L ≥ 0)",
            SumsInequality::SquareOfSecondAtMostFirstTimesThird => "(Σ L²)² ≤ Σ L·Σ L³ (L ≥ 0)",
            SumsInequality::HigherSumsNonNegative => "Σ L⁵ ≥ 0 and Σ L⁶ ≥ 0 (L ≥ 0)",
            SumsInequality::SquareOfFourthAtMostSecondTimesSixth => "(Σ L⁴)² ≤ Σ L²·Σ L⁶",
            SumsInequality::SquareOfFifthAtMostFourthTimesSixth => "(Σ L⁵)² ≤ Σ L⁴·Σ L⁶",
        })
    }
}

impl SumsInequality {
    /// Whether the inequality involves N, the number of nonzero values.
    pub(super) fn uses_nonzero(self) -> bool {
        matches!(
            self,
            SumsInequality::SquareOfSumAtMostNTimesSumOfSquares
                | SumsInequality::SquareOfSumOfSquaresAtMostNTimesFourthSum
                | SumsInequality::NonzeroValuesNeedPositiveSquares
        )
    }
}

/// Whether power sums S₁…S₆ of M = `count` numbers, N = `nonzero` of them
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
/// ĉ ± e are then used as intervals the same way. Everything is formed exactly
/// (`mcrt_reference::exact::Dyadic`).
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
/// 9. S₁ ≥ 0 and S₃ ≥ 0: every L ≥ 0 (a pixel's L is a sum of non-negative
///    contributions; `Samples::push` refuses negative values too).
/// 10. S₂² ≤ S₁S₃: Cauchy–Schwarz on the vectors (√Lᵢ) and (Lᵢ^{3/2}),
///     real for L ≥ 0.
/// 11. S₅ ≥ 0 and S₆ ≥ 0 (L ≥ 0); S₄² ≤ S₂S₆ and S₅² ≤ S₄S₆: Cauchy–Schwarz
///     on (Lᵢ), (Lᵢ³) and on (Lᵢ²), (Lᵢ³).
pub(super) fn realisable(
    count: u64,
    nonzero: Option<u64>,
    sums: &[Dyadic; 6],
    eps: f64,
) -> Result<(), (SumsInequality, (String, String))> {
    use SumsInequality as I;
    let n = Dyadic::from(count);
    let k = Dyadic::from(nonzero.unwrap_or(count));
    let [s1, s2, s3, s4, s5, s6] = sums.clone();
    let zero = Dyadic::zero();
    let one = Dyadic::from(1u64);
    let eps1 = Dyadic::from_f64(eps * 1.01).expect("eps is finite");
    // An interval's ends, and its smallest and largest |x|.
    let hi = |x: &Dyadic, e: &Dyadic| x + e;
    let lo = |x: &Dyadic, e: &Dyadic| x - e;
    let min_abs = |x: &Dyadic, e: &Dyadic| (&x.abs() - e).max(Dyadic::zero());
    let max_abs = |x: &Dyadic, e: &Dyadic| &x.abs() + e;
    let raw_err = |x: &Dyadic| &x.abs() * &eps1;
    let [e1, e2, e3, e4] = [&s1, &s2, &s3, &s4].map(raw_err);
    let sq = |x: &Dyadic| x * x;
    let show = |x: &Dyadic, den: &Dyadic| x.div_to_sci(den, 5); // six significant digits
    let fail = |which, l: &Dyadic, r: &Dyadic, den: &Dyadic| Err((which, (show(l, den), show(r, den))));
    // 1, 2, 3, 4: raw sums.
    if sq(&min_abs(&s1, &e1)) > &k * &hi(&s2, &e2) {
        return fail(I::SquareOfSumAtMostNTimesSumOfSquares, &sq(&s1), &(&k * &s2), &one);
    }
    if sq(&min_abs(&s2, &e2)) > &k * &hi(&s4, &e4) {
        return fail(I::SquareOfSumOfSquaresAtMostNTimesFourthSum, &sq(&s2), &(&k * &s4), &one);
    }
    let (s2_hi, s4_hi) = (hi(&s2, &e2).max(zero.clone()), hi(&s4, &e4).max(zero.clone()));
    if sq(&min_abs(&s3, &e3)) > &s2_hi * &s4_hi {
        return fail(I::SquareOfThirdSumAtMostSecondTimesFourth, &sq(&s3), &(&s2 * &s4), &one);
    }
    if lo(&s4, &e4) > sq(&max_abs(&s2, &e2)) {
        return fail(I::FourthSumAtMostSquareOfSecond, &s4, &sq(&s2), &one);
    }
    if nonzero.is_some_and(|k| k >= 1) && s2.is_zero() {
        return fail(I::NonzeroValuesNeedPositiveSquares, &s2, &zero, &one);
    }
    // 9, 10: non-negative values.
    for s in [&s1, &s3] {
        if hi(s, &raw_err(s)) < zero {
            return fail(I::OddSumsNonNegative, s, &zero, &one);
        }
    }
    if sq(&min_abs(&s2, &e2)) > &hi(&s1, &e1).max(zero.clone()) * &hi(&s3, &e3).max(zero.clone()) {
        return fail(I::SquareOfSecondAtMostFirstTimesThird, &sq(&s2), &(&s1 * &s3), &one);
    }
    // 11: the fifth and sixth sums.
    let [e5, e6] = [&s5, &s6].map(raw_err);
    for (s, e) in [(&s5, &e5), (&s6, &e6)] {
        if hi(s, e) < zero {
            return fail(I::HigherSumsNonNegative, s, &zero, &one);
        }
    }
    let s6_hi = hi(&s6, &e6).max(zero.clone());
    if sq(&min_abs(&s4, &e4)) > &s2_hi * &s6_hi {
        return fail(I::SquareOfFourthAtMostSecondTimesSixth, &sq(&s4), &(&s2 * &s6), &one);
    }
    if sq(&min_abs(&s5, &e5)) > &s4_hi * &s6_hi {
        return fail(I::SquareOfFifthAtMostFourthTimesSixth, &sq(&s5), &(&s4 * &s6), &one);
    }
    // 5, 6, 7: central sums, each with the bound of its terms' rounding.
    let s1sq = sq(&s1);
    let n2 = sq(&n);
    let central = |terms: &[(Dyadic, u64)]| {
        let value = terms.iter().fold(Dyadic::zero(), |acc, (t, _)| &acc + t);
        let err = terms.iter().fold(Dyadic::zero(), |acc, (t, k)| &acc + &(&t.abs() * &eps1).mul_u64(*k));
        (value, err)
    };
    let (c2, ec2) = central(&[(&n * &s2, 1), (-&s1sq, 2)]);
    let (c3, ec3) = central(&[(&n2 * &s3, 1), (-(&(&n * &s2) * &s1).mul_u64(3), 2), ((&s1sq * &s1).mul_u64(2), 3)]);
    let (c4, ec4) = central(&[
        (&(&n2 * &n) * &s4, 1),
        (-(&(&n2 * &s3) * &s1).mul_u64(4), 2),
        ((&(&n * &s2) * &s1sq).mul_u64(6), 3),
        (-sq(&s1sq).mul_u64(3), 4),
    ]);
    let c2_lo = lo(&c2, &ec2).max(zero.clone());
    let c2_hi = hi(&c2, &ec2).max(zero.clone());
    let c4_hi = hi(&c4, &ec4);
    let m4 = sq(&n2);
    if c4_hi < sq(&c2_lo) {
        // Shown as μ₄ and μ₂² (c₄/M⁴, c₂²/M⁴).
        return fail(I::CentralFourthAtLeastSquareOfSecond, &c4, &sq(&c2), &m4);
    }
    // max over the intervals of c₂(c₄ − c₂²) − c₃² ≤ c₂_hi (c₄_hi − c₂_lo²) − min c₃²
    // (both factors ≥ 0 here).
    let spread = &c4_hi - &sq(&c2_lo);
    if &c2_hi * &spread < sq(&min_abs(&c3, &ec3)) {
        // Shown as μ₂μ₄ and μ₃² + μ₂³ (each over M⁶).
        let m6 = &m4 * &n2;
        return fail(I::Pearson, &(&c2 * &c4), &(&sq(&c3) + &(&sq(&c2) * &c2)), &m6);
    }
    let m_minus_1 = &n - &one;
    if lo(&c4, &ec4) > &m_minus_1 * &sq(&max_abs(&c2, &ec2)) {
        // Shown as μ₄ and (M − 1)μ₂².
        return fail(I::CentralFourthAtMostMMinusOneTimesSquare, &c4, &(&m_minus_1 * &sq(&c2)), &m4);
    }
    Ok(())
}
