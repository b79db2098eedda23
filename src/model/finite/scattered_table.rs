//! I(D) of §9.5 — the chance, per path, that a point light's single-scattered
//! second segment hits a sphere whose centre is D from the light — as one
//! table per quadrature pass (`docs/model.md` §9.6).
//!
//! I depends on σ, R and D only, not on which light or which sphere, so
//! every single-scattered ⟨𝒞^k⟩₁ of every light at every camera-ray point
//! (μ₁, the ⟨𝒞₁²⟩ of M₂, and P and Q, which meet ⟨𝒞₀⟩ + ⟨𝒞₁⟩ at every
//! node of their double integrals) reads one interpolant instead of a
//! quadrature of its own ([`super::scattered::hits_over_distance`]).
//!
//! The table is a piecewise Chebyshev interpolant (`chebyshev::Piecewise`,
//! of the logarithm) of g(D) = I(D)·e^{σ·max(D − R, 0)}, which is O(1)
//! wherever I is, over the distances the camera ray's table range
//! ([`FiniteField::table_range`]) puts between the lights and the spheres,
//! to a tenth of the pass's tolerance. I is not analytic at D = R, where
//! the sphere starts to hold the light (the logarithmic singularity of the
//! integrand at d = D meets the √-kink of H at d = R), so the interpolant
//! stops a window |D − R| ≤ 10⁻⁶R short of it on both sides, its pieces
//! graded by decades towards it (each then sees the singularity a decade
//! off, where its Chebyshev tail is a sound estimate); it is graded by
//! decades towards D = 0 too (down to 10⁻⁴R), and geometrically (ratio 4)
//! towards large D, where ln g bends like −2 ln D. Within the window, below
//! the table's lower end and beyond its upper one, the quadrature serves.

use super::scattered::hits_over_distance;
use super::scattered_beam::BeamAlongRay;
use super::{FiniteField, FiniteLight, OncePerPass};
use crate::model::chebyshev::{sample_options, Piecewise};
use crate::model::field::{graded_about, graded_by};
use crate::quad::{CheckRule, Estimate, Options};
use std::sync::Arc;

/// Half-width of the window about D = R left to the quadrature, relative to R.
pub(super) const WINDOW: f64 = 1e-6;

/// The table's lowest distance, relative to R (a light on or next to the
/// camera line): below it the quadrature serves.
pub(super) const LOWEST: f64 = 1e-4;

/// Goals finer than this get no table (MPFR): Chebyshev pieces of 32 nodes
/// would need to be many and short, and the quadrature serves.
const FINEST_GOAL: f64 = 1e-13;

/// g(D) = I(D)·e^{σ·max(D − R, 0)} over the distances of one computation,
/// for one quadrature pass, with a relative bar.
#[derive(Debug)]
pub(super) struct ScatteredTable<T> {
    /// Interpolants on [lo, R(1 − 10⁻⁶)] and [R(1 + 10⁻⁶), hi] (or the one
    /// of them that the range meets), as (from, to, interpolant).
    parts: Vec<(T, T, Piecewise<T>)>,
    /// Relative bar of the interpolant ([`ScatteredTable::hits`] adds the
    /// rounding of its exponent; a table built from another table's values
    /// adds that table's bar here).
    pub rel_error: T,
    /// The rate the tabled function is multiplied back by beyond R (σ for
    /// I(D)).
    decay: T,
}

impl<T: CheckRule> ScatteredTable<T> {
    /// The table of g over [max(lo, 10⁻⁴R), hi] (0 ≤ lo < hi) for a pass
    /// with `opts` (its rule, tolerance and budget), or `None` when the goal
    /// is finer than the table serves or the interpolation fails (module
    /// docs), and the evaluations spent either way.
    pub(super) fn build(sigma: &T, r: &T, lo: &T, hi: &T, opts: &Options) -> (Option<ScatteredTable<T>>, u64) {
        let g = |d: &T, samples: &Options| {
            let shift = sigma.clone() * (d.clone() - r.clone()).max_of(d.lit(0.0));
            hits_over_distance(sigma, r, d, &shift, samples, true)
        };
        Self::build_with(g, sigma, r, lo, hi, LOWEST, opts)
    }

    /// A table of g(D) = F(D)·e^{decay·max(D − R, 0)}, g computed by `g(D,
    /// sample options)`, with the same pieces, window and bar as I(D)'s
    /// (module docs): F(D) is another radial function of the distance
    /// between a light and a sphere of radius R that bends at D = R (the
    /// hits of every order beyond the first, `multiple`).
    pub(super) fn build_with(
        g: impl Fn(&T, &Options) -> crate::quad::Outcome<T>,
        decay: &T,
        r: &T,
        lo: &T,
        hi: &T,
        lowest: f64,
        opts: &Options,
    ) -> (Option<ScatteredTable<T>>, u64) {
        Self::build_with_window(g, decay, r, (lo, hi), (lowest, WINDOW), opts)
    }

    /// [`ScatteredTable::build_with`] with a window about R of half-width
    /// `window`·R of its own (a table whose callers bound the window's
    /// values instead of computing them, and want it narrow).
    pub(super) fn build_with_window(
        g: impl Fn(&T, &Options) -> crate::quad::Outcome<T>,
        decay: &T,
        r: &T,
        (lo, hi): (&T, &T),
        (lowest, window): (f64, f64),
        opts: &Options,
    ) -> (Option<ScatteredTable<T>>, u64) {
        let goal = opts.rel_tol / 10.0;
        let lo = &lo.clone().max_of(r.clone() * r.lit(lowest));
        if goal < FINEST_GOAL || !(hi > lo) {
            return (None, 0);
        }
        let samples = sample_options(r, goal, opts.rule, &opts.budget);
        let g = |d: &T| g(d, &samples);
        let delta = r.clone() * r.lit(window);
        let (below, above) = (r.clone() - delta.clone(), r.clone() + delta.clone());
        let mut grading = graded_about(r, &delta, r);
        grading.extend(graded_about(&r.lit(0.0), &lo.clone().min_of(r.clone()), r));
        grading.extend(graded_by(&r.lit(0.0), &lo.clone().max_of(r.clone()), hi, 4.0, 40));
        let mut parts = Vec::new();
        let mut evaluations = 0;
        let mut rel_error = r.lit(0.0);
        for (from, to) in [(lo.clone(), below.min_of(hi.clone())), (above.max_of(lo.clone()), hi.clone())] {
            if !(to > from) {
                continue;
            }
            let mut cuts = vec![from.clone(), to.clone()];
            cuts.extend(grading.iter().filter(|c| **c > from && **c < to).cloned());
            let interpolant = match Piecewise::build(&g, &cuts, goal) {
                Ok(i) => i,
                Err(f) => return (None, evaluations + f.evaluations),
            };
            evaluations += interpolant.evaluations;
            rel_error = rel_error.max_of(interpolant.rel_error.clone());
            parts.push((from, to, interpolant));
        }
        if parts.is_empty() {
            return (None, evaluations);
        }
        (Some(ScatteredTable { parts, rel_error, decay: decay.clone() }), evaluations)
    }

    /// Whether the table's pieces reach from `lo` to `hi` (the window about
    /// R apart).
    pub(super) fn reaches(&self, lo: &T, hi: &T) -> bool {
        let first = self.parts.first().map(|(from, _, _)| from <= lo);
        let last = self.parts.last().map(|(_, to, _)| to >= hi);
        first == Some(true) && last == Some(true)
    }

    /// I(D)·e^{shift} and its relative bar — the table's
    /// ([`ScatteredTable::rel_error`]) plus the rounding of the exponent
    /// shift − σ·max(D − R, 0), 4ε(1 + |shift| + σ·max(D − R, 0)), which
    /// matters where both terms are hundreds — or `None` where the table
    /// does not reach (the window about R, below its lower end, beyond its
    /// upper one).
    pub(super) fn hits(&self, sigma: &T, r: &T, big_d: &T, shift: &T) -> Option<(T, T)> {
        let (_, _, part) = self.parts.iter().find(|(from, to, _)| big_d >= from && big_d <= to)?;
        let _ = sigma;
        let decay = self.decay.clone() * (big_d.clone() - r.clone()).max_of(big_d.lit(0.0));
        let rounding = big_d.eps() * big_d.lit(4.0) * (big_d.lit(1.0) + shift.abs() + decay.clone());
        let exponent = shift.clone() - decay;
        Some((part.eval(big_d) * exponent.exp(), self.rel_error.clone() + rounding))
    }
}

/// The single-scattered tables of one computation, one per pass (rule,
/// tolerance), each built once when first asked for ([`OncePerPass`]):
/// I(D) of the point lights and the beams' volume integrals along the
/// camera ray ([`BeamAlongRay`]); `None` where no table can serve, and the
/// quadrature does.
pub(super) struct ScatteredTables<T> {
    points: OncePerPass<ScatteredTable<T>>,
    beams: OncePerPass<BeamAlongRay<T>>,
    /// A cap on the goal a pass's tables are built at (none coarser), if
    /// set (`once_per_pass::capped_tables`).
    finest: Option<f64>,
}

impl<T> Default for ScatteredTables<T> {
    fn default() -> Self {
        ScatteredTables { points: OncePerPass::default(), beams: OncePerPass::default(), finest: None }
    }
}

impl<T> ScatteredTables<T> {
    /// The tables of a computation with options `opts`, whose scale pass
    /// reads its primary pass's tables (`once_per_pass::fine_tables`).
    pub(super) fn for_computation(opts: &Options) -> Self {
        ScatteredTables { finest: Some(crate::model::once_per_pass::primary_goal(opts)), ..Self::default() }
    }
}

impl<T: CheckRule> ScatteredTables<T> {
    /// The I(D) table of the pass with `opts` over the distances of `ff`.
    pub(super) fn for_pass(&self, ff: &FiniteField<T>, opts: &Options) -> Option<Arc<ScatteredTable<T>>> {
        let opts = &crate::model::once_per_pass::capped_tables(opts, self.finest);
        self.points.get_or_build(opts, || match distance_range(ff) {
            Some((lo, hi)) => ScatteredTable::build(&ff.sigma, &ff.radius, &lo, &hi, opts),
            None => (None, 0),
        })
    }

    /// The beams' along-ray tables of the pass with `opts`.
    pub(super) fn beams_for_pass(&self, ff: &FiniteField<T>, opts: &Options) -> Option<Arc<BeamAlongRay<T>>> {
        let opts = &crate::model::once_per_pass::capped_tables(opts, self.finest);
        self.beams.get_or_build(opts, || BeamAlongRay::build(ff, opts))
    }

    /// `result` with every table's evaluations added ([`OncePerPass::charge`]).
    pub(super) fn charge<E>(&self, result: Result<Estimate<T>, E>) -> Result<Estimate<T>, E> {
        self.beams.charge(self.points.charge(result))
    }
}

/// [min, max] of the distance between a point light and a camera-ray
/// point of the table range, over the lights, widened to [0, max] and the
/// pairs' reach where every order's same-path pairs read the tables
/// ([`FiniteField::cover_pair_distances`]); `None` without point lights.
pub(super) fn distance_range<T: CheckRule>(ff: &FiniteField<T>) -> Option<(T, T)> {
    match (light_distance_range(ff), ff.pair_reach()) {
        (Some((lo, hi)), Some(reach)) => Some((lo.lit(0.0), hi.max_of(reach.clone()))),
        (range, _) => range,
    }
}

/// [min, max] of the distance between a point light and a camera-ray
/// point of the table range, over the lights; `None` without point lights.
pub(super) fn light_distance_range<T: CheckRule>(ff: &FiniteField<T>) -> Option<(T, T)> {
    let (x_lo, x_hi) = ff.table_range();
    let mut range: Option<(T, T)> = None;
    for light in &ff.lights {
        let FiniteLight::Point(p) = light else { continue };
        let (d_lo, dz_lo) = p.distance_to(ff, &x_lo);
        let (d_hi, dz_hi) = p.distance_to(ff, &x_hi);
        let zero = x_lo.lit(0.0);
        let nearest = if dz_lo <= zero && dz_hi >= zero { p.b.clone() } else { d_lo.clone().min_of(d_hi.clone()) };
        let farthest = d_lo.max_of(d_hi);
        range = Some(match range {
            None => (nearest, farthest),
            Some((a, b)) => (a.min_of(nearest), b.max_of(farthest)),
        });
    }
    range
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table against I(D) by quadrature: about D = R on both sides (the
    /// window's edges and decades off them), near the lower end (down to
    /// 10⁻⁴R for a light on the camera line), between and far out, at
    /// radii from 10⁻⁸ to 10 and σ up to 50: each value
    /// within the table's relative bar plus the quadrature's own, and that
    /// bar within the goal; inside the window no value.
    #[test]
    fn the_scattered_table_is_within_its_bar() {
        let goal = 1e-8;
        let cases = [(1.0f64, 0.2f64, 1e-3), (1.0, 10.0, 1e-3), (1.0, 1e-8, 1e-3), (50.0, 0.2, 1e-3), (1.0, 0.05, 0.0)];
        for (sigma, r, start) in cases {
            // start 0: a light on the camera line; the table starts at 10⁻⁴R.
            let (lo, hi) = (r * start, 40.0 / sigma + 3.0 * r);
            let opts = Options::rel(goal).declared();
            let (table, spent) = ScatteredTable::build(&sigma, &r, &lo, &hi, &opts);
            let table = table.unwrap_or_else(|| panic!("σ {sigma}, R {r}: no table at {goal:e}"));
            assert!(table.rel_error <= goal, "σ {sigma}, R {r}: bar {:e}", table.rel_error);
            let fine = Options::rel(1e-10).declared();
            let lo = lo.max(r * LOWEST);
            let mut points = vec![lo, hi, 0.5 * (lo + r), 1.7 * r + 0.1, 0.9 * hi, 1.5e-4 * r, 3e-4 * r, 2e-3 * r];
            for k in 0..=7 {
                let off = 10f64.powi(-k) * r;
                points.extend([r - off, r + off, r - 1.5 * off, r + 1.5 * off]);
            }
            let mut worst = 0.0f64;
            for d in points.into_iter().filter(|d| *d >= lo && *d <= hi) {
                let shift = 0.3;
                let inside = (d / r - 1.0).abs() <= WINDOW * (1.0 + 1e-9);
                let Some((got, bar)) = table.hits(&sigma, &r, &d, &shift) else {
                    assert!(inside, "σ {sigma}, R {r}, D {d}: no value outside the window");
                    continue;
                };
                assert!((d / r - 1.0).abs() >= WINDOW * (1.0 - 1e-9), "σ {sigma}, R {r}, D {d}: inside the window");
                let direct = hits_over_distance(&sigma, &r, &d, &shift, &fine, false)
                    .unwrap_or_else(|e| panic!("σ {sigma}, R {r}, D {d}: {e:?}"));
                let off = (got / direct.value - 1.0).abs();
                let allowed = bar + direct.error / direct.value + 8.0 * f64::EPSILON;
                worst = worst.max(off / allowed);
                assert!(off <= allowed, "σ {sigma}, R {r}, D/R = {}: off {off:e}, allowed {allowed:e}", d / r);
            }
            println!(
                "σ {sigma}, R {r}: bar {:.1e}, {} evaluations; largest deviation {worst:.2} of what is allowed",
                table.rel_error, spent
            );
        }
    }

    /// A goal finer than the table serves gets none: the quadrature serves.
    #[test]
    #[cfg(feature = "mpfr")]
    fn an_mpfr_goal_gets_no_table() {
        let opts = Options::rel(1e-20).declared();
        let f = |v: f64| rug::Float::with_val(128, v);
        assert!(ScatteredTable::build(&f(1.0), &f(0.2), &f(0.1), &f(10.0), &opts).0.is_none());
    }
}
