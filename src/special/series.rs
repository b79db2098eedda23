//! Shared power series.

use crate::real::Real;

/// Σ_{k≥0} β_k u^k / ((k + 3/2)(k + c))^m, β_k = C(1/2, k)(−1/2)^k, for
/// 0 ≤ u ≤ 1/2, m ∈ {0, 1} selecting whether the extra (k + 3/2) divides.
///
/// With m = 0 and c = 3/2 this is the expansion of A(1 − u) / (2√2 u^{3/2}),
/// see [`super::overlap_a`]; with m = 1 it integrates that once more. For
/// k ≥ 1 every term is negative and |β_k| ≤ 2^{-k}, so the sum is well
/// conditioned. The number of terms is fixed first ((u/2)^K below the working
/// epsilon) and the sum is evaluated by Horner's rule from the smallest term,
/// which keeps its rounding error near one ulp.
pub(crate) fn sqrt_half_series<T: Real>(u: &T, c: f64, extra: bool) -> T {
    let eps = u.eps().to_f64().max(f64::MIN_POSITIVE);
    let ratio = (u.to_f64() / 2.0).max(f64::MIN_POSITIVE);
    let terms = ((eps / 8.0).ln() / ratio.ln()).ceil().clamp(1.0, 100_000.0) as usize;
    let horner = |coeffs: &[T]| {
        let mut sum = u.lit(0.0);
        for coeff in coeffs[..=terms.min(coeffs.len() - 1)].iter().rev() {
            sum = sum * u.clone() + coeff.clone();
        }
        sum
    };
    // f64 is the hot path of the oracle's inner loops: its three tables are
    // built once per process, not looked up per call.
    if let Some(table) = f64_table(c, extra) {
        if let Some(coeffs) = (table as &dyn std::any::Any).downcast_ref::<Vec<T>>() {
            return horner(coeffs);
        }
    }
    horner(&coefficients(u, c, extra))
}

/// The f64 coefficient tables of the three series in use, built once.
fn f64_table(c: f64, extra: bool) -> Option<&'static Vec<f64>> {
    use std::sync::OnceLock;
    static TABLES: [OnceLock<Vec<f64>>; 3] = [OnceLock::new(), OnceLock::new(), OnceLock::new()];
    let slot = match (c, extra) {
        (1.5, false) => 0,
        (2.5, true) => 1,
        (3.5, true) => 2,
        _ => return None,
    };
    Some(TABLES[slot].get_or_init(|| coefficients(&0.0f64, c, extra).as_ref().clone()))
}

/// β_k/(k + c) (or β_k/((k + 3/2)(k + c))) for k = 0…K with (1/4)^K below
/// the working epsilon (enough for every u ≤ 1/2), cached per precision.
fn coefficients<T: Real>(like: &T, c: f64, extra: bool) -> std::sync::Arc<Vec<T>> {
    let kind = 100 + (c * 4.0) as u32 * 2 + extra as u32;
    let eps = like.eps().to_f64().max(f64::MIN_POSITIVE);
    let terms = ((eps / 8.0).ln() / 0.25f64.ln()).ceil() as usize + 1;
    crate::quad::cached(kind, like, terms, || {
        let mut out = Vec::with_capacity(terms + 1);
        let mut beta = like.lit(1.0);
        for k in 0..=terms {
            let kf = k as f64;
            if k > 0 {
                // β_k = β_{k−1} (2k − 3)/(4k), exact integers at any precision.
                beta = beta * like.lit(2.0 * kf - 3.0) / like.lit(4.0 * kf);
            }
            let denom = if extra { like.lit((kf + 1.5) * (kf + c)) } else { like.lit(kf + c) };
            out.push(beta.clone() / denom);
        }
        out
    })
}

/// y − sin y for 0 ≤ y ≤ 2.2, by its Taylor series y³/3! − y⁵/5! + …,
/// free of the cancellation of the direct difference at small y.
pub(crate) fn y_minus_sin<T: Real>(y: &T) -> T {
    let eps = y.eps();
    let y2 = y.clone() * y.clone();
    let mut term = y2.clone() * y.clone() / y.lit(6.0);
    let mut sum = term.clone();
    for k in 2..100_000 {
        let kf = k as f64;
        term = -(term * y2.clone()) / y.lit((2.0 * kf) * (2.0 * kf + 1.0));
        sum = sum + term.clone();
        if term.abs() <= eps.clone() * sum.abs() * y.lit(0.25) {
            break;
        }
    }
    sum
}
