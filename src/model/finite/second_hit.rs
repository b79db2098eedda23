//! K(w), the chance that a path whose first segment crossed a sphere hits
//! it again with its second (isotropic scattering; `docs/model.md` §9.6),
//! and its table: K depends on σ, R and w only, not on the sphere or the
//! light, so the same-path moment ⟨𝒞₀𝒞₁⟩ at every camera-ray point
//! (`PointLight::same_path_moment`) integrates one table per quadrature
//! pass instead of a nested quadrature (at 10⁻⁶ on
//! `point-isotropic-order1`, R = 0.05: the single-scattered part of M₂ fell
//! from 2.5·10⁷ evaluations, 2.1 s, to ~6·10⁵).

use super::scattered::hit_chance;
use super::OncePerPass;
use crate::model::chebyshev::{sample_options, Piecewise};
use crate::model::field::graded_about;
use crate::quad::{integrate_within_pass, CheckRule, Domain, Estimate, Options, Outcome};
use std::sync::Arc;

/// K(w) = ∫₀^∞ σe^{−σu} H(√(u² + R² − w²)) du: the chance that a path
/// whose first segment passes a sphere's centre at p = √(R² − w²) and
/// interacts u past its closest point, scattering there isotropically,
/// hits the sphere with its second segment ([`hit_chance`]). The second
/// segment starts inside the sphere for u < w (H's √-kink at u = w, where
/// it leaves); beyond it H falls like R²/d² over the decades from R to
/// 1/σ. Domain: 0 ≤ w ≤ R, σ > 0. Not in the paper (§9.6).
pub(super) fn second_hit_after<T: CheckRule>(sigma: &T, r: &T, w: &T, opts: &Options) -> Outcome<T> {
    let p2 = (r.clone() - w.clone()) * (r.clone() + w.clone());
    let f = |u: &T, o: &Options| {
        let d = (u.clone() * u.clone() + p2.clone()).sqrt();
        let v = sigma.clone() * (-(sigma.clone() * u.clone())).exp() * hit_chance(sigma, r, &d);
        Ok(Estimate::known(v, u.lit(0.0), 1, o.rule))
    };
    let zero = w.lit(0.0);
    let far = w.lit(4.0) / sigma.clone();
    let mut cuts = vec![w.clone()];
    cuts.extend(graded_about(&zero, r, &far).into_iter().filter(|c| *c > zero));
    cuts.extend(graded_about(w, &(r.clone() / w.lit(1e3)), r).into_iter().filter(|c| *c > zero));
    let domain = Domain::semi_infinite(zero).with_breakpoints(cuts).with_decay(sigma.clone());
    integrate_within_pass(f, &domain, opts)
}

/// weight·K(w), K from the pass's `table` when there is one (its relative
/// bar is added to the whole integral by [`with_table_bar`]), else by
/// quadrature with the goal divided by the weight: the integrand of a
/// same-path moment ⟨𝒞₀𝒞₁⟩ (`PointLight::same_path_moment`,
/// `BeamLight::same_path_moment`). Domain: 0 ≤ w ≤ R, weight ≥ 0.
pub(super) fn weighted_second_hit<T: CheckRule>(
    sigma: &T,
    r: &T,
    w: &T,
    weight: T,
    table: Option<&SecondHitTable<T>>,
    opts: &Options,
) -> Outcome<T> {
    if weight.is_zero() {
        return Ok(Estimate::known(w.lit(0.0), w.lit(0.0), 0, opts.rule));
    }
    if let Some(t) = table {
        return Ok(Estimate::known(weight * t.eval(w), w.lit(0.0), 1, opts.rule));
    }
    let each = Options { abs_tol: (opts.abs_tol / weight.to_f64()).min(f64::MAX), ..opts.clone() };
    Ok(second_hit_after(sigma, r, w, &each)?.scaled(&weight))
}

/// An integral of [`weighted_second_hit`] with the table's relative bar
/// added: K ≥ 0 against a non-negative weight, so the table's relative bar
/// is a relative bar of the integral.
pub(super) fn with_table_bar<T: CheckRule>(
    e: Estimate<T>,
    table: Option<&SecondHitTable<T>>,
    opts: &Options,
) -> Estimate<T> {
    match table {
        Some(t) => {
            let error = e.error.clone() + e.value.abs() * t.rel_error.clone();
            Estimate::known(e.value, error, e.evaluations, opts.rule)
        }
        None => e,
    }
}

/// δ₀, δ₁ of [`SecondHitTable`]: the interpolant covers [δ₀R, (1 − δ₁)R].
/// K's gap across a margin is O(δ₀² ln δ₀) at w = 0 but O(δ₁ ln δ₁) at
/// w = R (p² ∝ R − w there), hence the narrower δ₁.
const MARGINS: (f64, f64) = (1e-9, 1e-14);

/// K(w) over w ∈ [0, R] for one quadrature pass, with a relative bar.
///
/// A piecewise Chebyshev interpolant of ln K (`chebyshev::Piecewise`) to a
/// tenth of the pass's tolerance on [δ₀R, (1 − δ₁)R] ([`MARGINS`]), graded
/// by decades towards both ends. K is not analytic at the ends of [0, R]: at
/// w = 0 the √-kink of H at the sphere's surface (u = w) leaves a w² ln w
/// term, at w = R (p → 0) the odd powers of d in H inside the sphere a
/// p² ln p term, and a Chebyshev tail there underestimates the error
/// (measured: 26× at w = R). Away from them every graded piece sees its
/// end's singularity a decade off, where the tail is a sound estimate. In
/// the margins K is taken at the interpolant's end, with the gap to K at
/// w = 0 and w = R (by quadrature; O(δ₀² ln δ₀) and O(σ²R²δ₁ ln δ₁))
/// added to the bar; a gap above a tenth of the tolerance (MPFR goals
/// below ~10⁻¹³, or σR ≳ 100 at f64's) refuses the table, and the
/// quadrature serves.
pub(super) struct SecondHitTable<T> {
    interpolant: Piecewise<T>,
    lo: T,
    hi: T,
    /// Relative bar of [`SecondHitTable::eval`] anywhere in [0, R].
    pub rel_error: T,
}

impl<T: CheckRule> SecondHitTable<T> {
    /// The table for a pass with `opts` (its rule, tolerance and budget),
    /// or `None` when it cannot vouch for its bar (module docs), and the
    /// evaluations spent either way. Domain: R > 0, σ > 0.
    pub(super) fn build(sigma: &T, r: &T, opts: &Options) -> (Option<SecondHitTable<T>>, u64) {
        Self::build_with(|w: &T, o: &Options| second_hit_after(sigma, r, w, o), r, opts)
    }

    /// A table of another function of w ∈ [0, R] with K's singular ends
    /// (the every-order K of `multiple_pairs`), computed by `k(w, options)`,
    /// with the same margins, grading and bar.
    pub(super) fn build_with(
        k: impl Fn(&T, &Options) -> Outcome<T>,
        r: &T,
        opts: &Options,
    ) -> (Option<SecondHitTable<T>>, u64) {
        let goal = opts.rel_tol / 10.0;
        let samples = sample_options(r, goal, opts.rule, &opts.budget);
        let (lo, top) = (r.clone() * r.lit(MARGINS.0), r.clone() * r.lit(MARGINS.1));
        let hi = r.clone() - top.clone();
        let mut cuts = vec![lo.clone(), hi.clone()];
        cuts.extend(graded_about(&r.lit(0.0), &lo, r));
        cuts.extend(graded_about(r, &top, r));
        let cuts: Vec<T> = cuts.into_iter().filter(|c| *c >= lo && *c <= hi).collect();
        // The margins' gaps first (four quadratures): a goal they cannot
        // meet gets no table before the costly part.
        let mut evaluations = 0;
        let mut gap = r.lit(0.0);
        for (end, edge) in [(r.lit(0.0), &lo), (r.clone(), &hi)] {
            let at_end = match k(&end, &samples) {
                Ok(e) => e,
                Err(f) => return (None, evaluations + f.evaluations),
            };
            evaluations += at_end.evaluations;
            let at_edge = match k(edge, &samples) {
                Ok(e) => e,
                Err(f) => return (None, evaluations + f.evaluations),
            };
            evaluations += at_edge.evaluations;
            let this = (at_end.value.clone() / at_edge.value.clone() - r.lit(1.0)).abs()
                + at_end.error / at_end.value
                + at_edge.error / at_edge.value;
            gap = gap.max_of(this);
        }
        if gap.to_f64() > goal {
            return (None, evaluations);
        }
        let interpolant = match Piecewise::build(|w| k(w, &samples), &cuts, goal) {
            Ok(i) => i,
            Err(f) => return (None, evaluations + f.evaluations),
        };
        evaluations += interpolant.evaluations;
        let rel_error = interpolant.rel_error.clone() + gap;
        (Some(SecondHitTable { interpolant, lo, hi, rel_error }), evaluations)
    }

    /// K(w), within the relative bar [`SecondHitTable::rel_error`]
    /// (w clamped to the interpolant's range). Domain: 0 ≤ w ≤ R.
    pub(super) fn eval(&self, w: &T) -> T {
        self.interpolant.eval(&w.clone().max_of(self.lo.clone()).min_of(self.hi.clone()))
    }
}

/// The K tables of one computation, one per pass (rule, tolerance), each
/// built once when first asked for ([`super::OncePerPass`]): `None` when
/// the table cannot vouch for its bar, and the quadrature serves.
pub(super) type SecondHitTables<T> = OncePerPass<SecondHitTable<T>>;

impl<T: CheckRule> SecondHitTables<T> {
    /// The table of the pass with `opts`.
    pub(super) fn for_pass(&self, sigma: &T, r: &T, opts: &Options) -> Option<Arc<SecondHitTable<T>>> {
        self.get_or_build(opts, || SecondHitTable::build(sigma, r, opts))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The K table against K by quadrature across [0, R]: at both ends (in
    /// the margins, where K is not analytic: w = 0, the w² ln w term; w = R,
    /// the p² ln p term, which at w = R put a plain interpolant 26× its bar
    /// off), next to them and between, at radii from 10⁻⁸ to 10 and σ up to
    /// 50: each value within the table's relative bar plus the quadrature's
    /// own, and that bar within the goal.
    #[test]
    fn the_second_hit_table_is_within_its_bar() {
        let goal = 1e-8;
        for (sigma, r) in [(1.0f64, 0.2f64), (1.0, 10.0), (1.0, 1e-8), (50.0, 0.2)] {
            let opts = Options::rel(goal).declared();
            let table = SecondHitTable::build(&sigma, &r, &opts).0;
            let table = table.unwrap_or_else(|| panic!("σ {sigma}, R {r}: no table at 1e-8"));
            assert!(table.rel_error <= goal, "σ {sigma}, R {r}: bar {:e}", table.rel_error);
            let fine = Options::rel(1e-13).declared();
            let mut fractions = vec![0.0, 1.0, MARGINS.0, 1.0 - MARGINS.1, 0.3, 0.5, 0.77];
            for k in 1..=15 {
                fractions.push(10f64.powi(-k));
                fractions.push(1.0 - 10f64.powi(-k));
            }
            for f in fractions {
                let w = f * r;
                let direct = second_hit_after(&sigma, &r, &w, &fine).unwrap();
                let off = (table.eval(&w) / direct.value - 1.0).abs();
                let allowed = table.rel_error + direct.error / direct.value + 4.0 * f64::EPSILON;
                assert!(off <= allowed, "σ {sigma}, R {r}, w/R = {f}: off {off:e}, allowed {allowed:e}");
            }
        }
    }

    /// A goal the margins cannot meet (their gap at w = R is ~σ²R²δ₁ ln δ₁,
    /// ~10⁻¹⁵ here) gets no table: the quadrature serves.
    #[test]
    #[cfg(feature = "mpfr")]
    fn a_goal_below_the_margins_gap_gets_no_table() {
        let opts = Options::rel(1e-20).declared();
        let r = rug::Float::with_val(128, 0.2);
        let sigma = rug::Float::with_val(128, 1.0);
        assert!(SecondHitTable::build(&sigma, &r, &opts).0.is_none());
    }
}
