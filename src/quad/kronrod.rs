//! Low-floor rules for loose goals: adaptive bisection of Gauss–Kronrod
//! panels in a smoothing substitution, in a pair that cross-checks itself
//! (`docs/quadrature.md`): G7–K15 in x = a + (b − a) sin²(πs/2)
//! ([`super::Rule::Kronrod`]) and G10–K21 in the check rule's
//! x = a + (b − a)(3s² − 2s³) ([`super::Rule::KronrodCheck`]). Both maps
//! turn endpoint singularities (x − a)^α into s^{2α+1}-type ends; the two
//! rules share no node but a piece's midpoint.
//!
//! A panel costs 15 or 21 evaluations (the check rule's first panel 30,
//! tanh–sinh's first estimate 61 in f64): its value is the Kronrod rule's,
//! its truncation estimate |K − G|, the error of the embedded Gauss rule,
//! so it is conservative by design (QUADPACK's QK15, QK21 without their
//! sharpening). For nested integrals at loose goals, where every level's
//! cost is its floor per piece, not its goal. f64 only: the nodes are f64
//! constants, so above 53 bits tanh–sinh and the check rule run instead
//! (`Rule::at_precision`).

use super::check::{Map, Panel, PanelEstimate, PanelFn};
use super::{control, Failure, Mapped, Options, Piece, RuleResult};
use crate::real::Real;

/// A Gauss–Kronrod pair on [−1, 1] (QUADPACK `qk15`, `qk21`): the
/// non-negative Kronrod abscissae (descending, ending at 0), their weights,
/// and the Gauss weights of the odd-indexed abscissae, which are the Gauss
/// nodes (and of the centre too when the Gauss rule has one).
pub(crate) struct Pair {
    /// How failures name the rule.
    name: &'static str,
    xgk: &'static [f64],
    wgk: &'static [f64],
    wg: &'static [f64],
}

/// G7–K15 (15 evaluations a panel).
pub(crate) const G7_K15: Pair = Pair {
    name: "Gauss-Kronrod 7-15",
    xgk: &[
        0.991_455_371_120_812_6,
        0.949_107_912_342_758_5,
        0.864_864_423_359_769_1,
        0.741_531_185_599_394_4,
        0.586_087_235_467_691_1,
        0.405_845_151_377_397_2,
        0.207_784_955_007_898_5,
        0.0,
    ],
    wgk: &[
        0.022_935_322_010_529_22,
        0.063_092_092_629_978_55,
        0.104_790_010_322_250_2,
        0.140_653_259_715_525_9,
        0.169_004_726_639_267_9,
        0.190_350_578_064_785_4,
        0.204_432_940_075_298_9,
        0.209_482_141_084_727_8,
    ],
    wg: &[0.129_484_966_168_869_7, 0.279_705_391_489_276_7, 0.381_830_050_505_118_9, 0.417_959_183_673_469_4],
};

/// G10–K21 (21 evaluations a panel; G10 has no centre node).
pub(crate) const G10_K21: Pair = Pair {
    name: "Gauss-Kronrod 10-21",
    xgk: &[
        0.995_657_163_025_808_1,
        0.973_906_528_517_171_7,
        0.930_157_491_355_708_2,
        0.865_063_366_688_984_5,
        0.780_817_726_586_416_9,
        0.679_409_568_299_024_4,
        0.562_757_134_668_604_7,
        0.433_395_394_129_247_2,
        0.294_392_862_701_460_2,
        0.148_874_338_981_631_2,
        0.0,
    ],
    wgk: &[
        0.011_694_638_867_371_874,
        0.032_558_162_307_964_73,
        0.054_755_896_574_352,
        0.075_039_674_810_919_95,
        0.093_125_454_583_697_6,
        0.109_387_158_802_297_64,
        0.123_491_976_262_065_85,
        0.134_709_217_311_473_33,
        0.142_775_938_577_060_08,
        0.147_739_104_901_338_5,
        0.149_445_554_002_916_9,
    ],
    wg: &[
        0.066_671_344_308_688_14,
        0.149_451_349_150_580_6,
        0.219_086_362_515_982_04,
        0.269_266_719_309_996_36,
        0.295_524_224_714_752_87,
    ],
};

/// The pair's panel on [s0, s1] of g: (K, |K − G|, inner bars, ∫|g|).
fn panel<T: Real>(pair: &Pair, g: &mut PanelFn<'_, T>, s0: &T, s1: &T) -> Result<(T, T, T, T), Failure<T>> {
    let half = (s1.clone() - s0.clone()) / s0.lit(2.0);
    let mid = (s1.clone() + s0.clone()) / s0.lit(2.0);
    let zero = s0.lit(0.0);
    let (mut k, mut gauss, mut e, mut a) = (zero.clone(), zero.clone(), zero.clone(), zero);
    for (j, x) in pair.xgk.iter().enumerate() {
        let xs = if *x == 0.0 {
            [Some(mid.clone()), None]
        } else {
            let dx = half.clone() * s0.lit(*x);
            [Some(mid.clone() - dx.clone()), Some(mid.clone() + dx)]
        };
        let gauss_weight = (j % 2 == 1 || *x == 0.0).then(|| pair.wg.get(j / 2).copied()).flatten();
        for s in xs.into_iter().flatten() {
            let sample = g(&s)?;
            let w = s0.lit(pair.wgk[j]);
            k = k + w.clone() * sample.value.clone();
            e = e + w.clone() * sample.error;
            a = a + w * sample.value.abs();
            if let Some(wg) = gauss_weight {
                gauss = gauss + s0.lit(wg) * sample.value;
            }
        }
    }
    let err = (k.clone() - gauss).abs() * half.clone();
    Ok((k * half.clone(), err, e * half.clone(), a * half))
}

/// Integrates all pieces to the goal of `opts` with `pair` in `map` (f64;
/// see the module docs).
pub(crate) fn adaptive<T: Real>(
    pair: &Pair,
    map: Map,
    f: &mut Mapped<'_, '_, T>,
    pieces: &[Piece<T>],
    opts: &Options,
) -> Result<RuleResult<T>, Failure<T>> {
    let like = pieces[0].a.clone();
    // g(s) = f(x(s)) (b − a) φ'(s), x(s) = a + (b − a) φ(s), φ of `map`.
    let estimate = |piece_idx: usize, s0: &T, s1: &T, f: &mut Mapped<'_, '_, T>| {
        let piece = &pieces[piece_idx];
        let (value, quad_err, inner_err, abs) = panel(pair, &mut |s: &T| map.sample(f, piece, s), s0, s1)?;
        let est = PanelEstimate { value, quad_err, inner_err, abs, halves: [None, None] };
        Ok::<_, Failure<T>>(Panel { piece: piece_idx, s0: s0.clone(), s1: s1.clone(), est })
    };
    let (zero, one) = (like.lit(0.0), like.lit(1.0));
    let mut panels = Vec::new();
    for i in 0..pieces.len() {
        panels.push(estimate(i, &zero, &one, f)?);
    }
    while let Some(worst) = control::next_to_refine(&panels, &like, f, opts, pair.name)? {
        let mid = control::midpoint(&panels[worst].s0, &panels[worst].s1, &panels, f)?;
        let p = panels.swap_remove(worst);
        panels.push(estimate(p.piece, &p.s0, &mid, f)?);
        panels.push(estimate(p.piece, &mid, &p.s1, f)?);
    }
    Ok(control::result(&panels, &like))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫₋₁¹ x^k by the Kronrod and by the Gauss weights of `pair`.
    fn moments(pair: &Pair, k: i32) -> (f64, f64) {
        let (mut kr, mut ga) = (0.0, 0.0);
        for (j, x) in pair.xgk.iter().enumerate() {
            let n = if *x == 0.0 { 1.0 } else { 2.0 };
            kr += n * pair.wgk[j] * x.powi(k);
            if j % 2 == 1 || *x == 0.0 {
                ga += n * pair.wg.get(j / 2).copied().unwrap_or(0.0) * x.powi(k);
            }
        }
        (kr, ga)
    }

    /// Both pairs integrate the even powers exactly to their degrees (K15
    /// to 22, G7 to 13, K21 to 31, G10 to 19), and no further.
    #[test]
    fn the_weights_are_quadpacks() {
        for (pair, kd, gd) in [(&G7_K15, 22, 12), (&G10_K21, 30, 18)] {
            for k in (0..=kd).step_by(2) {
                let exact = 2.0 / (k as f64 + 1.0);
                let (kr, ga) = moments(pair, k);
                // The sum's rounding: its terms are positive and add up to
                // at most Σw = 2, so four ulps of 2.
                let ulps = 8.0 * f64::EPSILON;
                assert!((kr - exact).abs() <= ulps, "Kronrod x^{k}: {kr} against {exact}");
                if k <= gd {
                    assert!((ga - exact).abs() <= ulps, "Gauss x^{k}: {ga} against {exact}");
                }
            }
            // One degree further each is off by far more than rounding
            // (K21 on x³² by 4.4·10⁻¹²).
            let rounding = 8.0 * f64::EPSILON;
            let (kr, _) = moments(pair, kd + 2);
            assert!((kr - 2.0 / (kd as f64 + 3.0)).abs() > 100.0 * rounding, "Kronrod exact beyond its degree? {kr}");
            let (_, ga) = moments(pair, gd + 2);
            assert!((ga - 2.0 / (gd as f64 + 3.0)).abs() > 100.0 * rounding, "Gauss exact beyond its degree? {ga}");
        }
    }
}
