//! Every scattering order at any R (isotropic media, point lights;
//! `docs/model.md` §10.2): the mean contribution to a sphere of a point
//! light's segments 2, 3, …, n (or all), exact, and the small-sphere mean of
//! every order, the limit the estimator's bias is measured from.
//!
//! Segment j ≥ 1 of a path starts at a point of density a^j c_j
//! ([`super::start_density`]) and, isotropic from there, hits the sphere at
//! distance d with the chance H(d) of §9.5 ([`super::scattered::hit_chance`]),
//! so the segments 2..=n together give
//!
//!   ⟨𝒞^k⟩_{2..n}(s) = (c^k Φ/𝓕)(4π)^{−k} (C * H)(D),  C = Σ_{j=2}^{n} a^j c_j,
//!
//! D = |y − x(s)| (the albedo of the path's survival is in C; c carries the
//! per-hit albedo of (5)). In bipolar coordinates about the light and the
//! sphere's centre, with T(t) = ∫_t^∞ r C(r) dr,
//!
//!   (C * H)(D) = (2π/D) ∫₀^∞ d H(d) [T(|D − d|) − T(D + d)] dd,
//!
//! T at σ being σ·T₁(σt), T₁ the tail at σ = 1 (`start_density`). Segment
//! 1 is §9.5's I(D) (its T is the logarithmic a E₁/4π, apart because of
//! that singularity). T₁ is read from a table per quadrature pass
//! ([`TailTable`], a piecewise Chebyshev interpolant of its logarithm); its
//! relative bar ρ enters each sample of the d-integral as ρ·(T(|D − d|) +
//! T(D + d)), so the cancellation of the difference at d ≪ D is in the bar.
//! (C * H)(D) is tabled in D per pass like I(D) (`scattered_table`, decay
//! rate νσ with every order, σ for a finite range).

use super::multiple_beam::{BeamBeyondTables, BeamLimit};
use super::point::PointLight;
use super::scattered::{bipolar_cuts, hit_chance_parts};
use super::scattered_table::ScatteredTable;
use super::start_density::StartDensity;
use super::{FiniteField, FiniteLight, OncePerPass};
use crate::model::chebyshev::{sample_options, Piecewise};
use crate::model::field::{graded_about, graded_by};
use crate::model::OracleError;
use crate::quad::{integrate_within_pass, CheckRule, Domain, Estimate, Options, Outcome};
use std::sync::Arc;

/// The tail T₁(t) = ∫_t^∞ r C(r) dr (σ = 1) of one pass, on [0, hi], and
/// the radial density ρ₁(r) = r C(r) itself, for differences of T over
/// short shells (where two values of T would cancel).
#[derive(Debug)]
pub(super) struct TailTable<T> {
    table: Piecewise<T>,
    radial: Option<Piecewise<T>>,
    hi: T,
}

/// Gauss–Legendre nodes per panel of a shell's ∫ρ₁. ρ₁ is a mixture of
/// e^{−ur}, u ≥ ν (the pole) or u ≥ 1 (the cut; its weights change sign,
/// so the rule's relative error below is per component), and 12 nodes
/// integrate e^{−λr} over a panel of half-width h with a relative error
/// that depends on c = λh: 10⁻²⁴ at c = 2, 3·10⁻¹⁴ at c = 6, 7.5·10⁻⁶ at
/// c = 20 (mpmath). Panels are at most 2 wide (σ-units: c ≤ 1 for the
/// pole and the cut's edge), and every component with larger u is
/// suppressed on the shell by e^{−(u − 1)t₀}, t₀ ≥ 2·(panel width), against
/// the slowest: the bar's 10⁻²⁰ covers the rule.
const SHELL_NODES: usize = 12;

/// Panels a shell may have before the adaptive rule serves instead.
const SHELL_PANELS: usize = 16;

/// νt beyond which a tail table does not reach (e^{−550} ≈ 10⁻²³⁹, with
/// room for T's prefactor above f64's least normal number).
const UNDERFLOW_REACH: f64 = 550.0;

/// The largest relative bar of a piece of the radial table that a shell
/// integral reads (a ln-bar of 0.02 and a little more): pieces accepted at
/// their samples' noise above it (the single orders ≥ 3 next to r = 0,
/// where ρ₁ = r c_j vanishes while the cut integral keeps an absolute
/// error; their bars reach e^{10²}) are not read, and the difference of
/// two values of T serves (there its x-weight makes its bar small).
const TRUSTED_PIECE: f64 = 0.0205;

/// Tail tables finer than this are not built (MPFR goals): the quadrature
/// serves.
const FINEST_GOAL: f64 = 1e-13;

impl<T: CheckRule> TailTable<T> {
    /// The table of `density`'s tail over [0, hi] (σ-units) to a
    /// 2000th of the pass's tolerance (the d-integrals' samples, which a
    /// table of (C * H)(D) asks for a 400th, difference two values of T,
    /// and their bars carry T's relative bar times the sum: a 20th of their
    /// goal), at least [`FINEST_GOAL`]; or `None` (a finer goal, or the
    /// interpolation failed), and the evaluations spent.
    pub(super) fn build(density: &StartDensity<T>, hi: &T, opts: &Options) -> (Option<TailTable<T>>, u64) {
        let goal = opts.rel_tol / 2000.0;
        if goal < FINEST_GOAL {
            return (None, 0);
        }
        // T₁ ≤ e^{−νt}·T₁(0)-like: beyond ~550/ν it would underflow the
        // f64 range the table's samples are computed in (at albedo 0.5,
        // ν = 0.957, T₁(913) = 0 ended every table); ln_tail's quadrature
        // serves out there.
        let hi = &hi.clone().min_of(hi.lit(UNDERFLOW_REACH) / density.decay());
        let samples = sample_options(hi, goal, opts.rule, &opts.budget);
        // Decades towards t = 0 (where r C(r) is finite but T is not
        // analytic), then a geometric grading (ratio 2) outwards.
        let zero = hi.lit(0.0);
        let mut cuts = vec![zero.clone(), hi.clone()];
        cuts.extend(graded_about(&zero, &hi.lit(1e-12), &hi.lit(1.0)).into_iter().filter(|c| *c > zero));
        cuts.extend(graded_by(&zero, &hi.lit(1.0), hi, 2.0, 60).into_iter().filter(|c| *c > zero));
        let table = match Piecewise::build(|t: &T| density.tail(t, &samples), &cuts, goal) {
            Ok(table) => table,
            Err(f) => return (None, f.evaluations),
        };
        let mut spent = table.evaluations;
        // ρ₁ from 10⁻¹² on (a shell's nodes lie at ≥ t₀ > 0).
        let radial_cuts: Vec<T> = cuts.iter().map(|c| c.clone().max_of(hi.lit(1e-12))).collect();
        let radial = match Piecewise::build(|r: &T| density.radial(r, &samples), &radial_cuts, goal / 20.0) {
            Ok(r) => {
                spent += r.evaluations;
                Some(r)
            }
            Err(f) => {
                spent += f.evaluations;
                None
            }
        };
        (Some(TailTable { table, radial, hi: hi.clone() }), spent)
    }

    /// (∫_{t₀}^{t₀+w} ρ₁ dr·e^{base}, relative bar) for a short shell
    /// (0 < w ≤ t₀/2, within the table), by [`SHELL_NODES`] Gauss–Legendre
    /// nodes on each of at most [`SHELL_PANELS`] panels no wider than 2
    /// (σ-units); `None` without the radial table, beyond it, for a shell
    /// that needs more panels, or one that meets a piece of the radial
    /// table whose bar is above [`TRUSTED_PIECE`].
    fn shell(&self, t0: &T, w: &T, base: &T) -> Option<(T, T, u64)> {
        let radial = self.radial.as_ref()?;
        let end = t0.clone() + w.clone();
        if end > self.hi || !(w.clone() * w.lit(2.0) <= *t0) {
            return None;
        }
        let panels = (w.to_f64() / 2.0).ceil().max(1.0);
        if panels > SHELL_PANELS as f64 {
            return None;
        }
        let step = w.clone() / w.lit(panels);
        let half = step.clone() * w.lit(0.5);
        // Each node's term bears its own piece's bar (the pieces next to
        // r = 0, accepted at their samples' noise, bear far larger ones).
        let (mut sum, mut bar) = (w.lit(0.0), w.lit(0.0));
        for k in 0..panels as usize {
            let mid = t0.clone() + step.clone() * w.lit(k as f64) + half.clone();
            for (x, wt) in crate::quad::gauss_legendre(w, SHELL_NODES).iter() {
                for r in [mid.clone() - half.clone() * x.clone(), mid.clone() + half.clone() * x.clone()] {
                    let term = wt.clone() * (radial.eval_ln(&r) + base.clone()).exp();
                    let term = if x.is_zero() { term * w.lit(0.5) } else { term };
                    let rel = radial.rel_error_at(&r);
                    if !(rel.to_f64() <= TRUSTED_PIECE) {
                        return None;
                    }
                    bar = bar + term.clone() * rel;
                    sum = sum + term;
                }
            }
        }
        let evaluations = (panels as u64) * 2 * SHELL_NODES as u64;
        // Every term underflowed: the value is 0 and bears nothing.
        let rel = if sum.is_zero() { sum.clone() } else { bar / sum.clone() };
        Some((sum * half, rel + w.lit(1e-20), evaluations))
    }

    /// (∫_{t₀}^{t₀+w} ρ₁ dr·e^{base}) by adaptive quadrature of the radial
    /// table (a shell whose two values of T would cancel, but too wide or
    /// too near r = 0 for [`TailTable::shell`]), its bar with the largest
    /// relative bar of the table's pieces it crosses added; `None` without
    /// the radial table, beyond it, or where the shell meets a piece whose
    /// bar is above [`TRUSTED_PIECE`].
    fn wide_shell(&self, t0: &T, w: &T, base: &T, opts: &Options) -> Option<Outcome<T>> {
        let radial = self.radial.as_ref()?;
        let end = t0.clone() + w.clone();
        if end > self.hi {
            return None;
        }
        let mut crossed = t0.lit(0.0);
        for (_, _, rel) in radial.parts_over(t0, &end) {
            if !(rel.to_f64() <= TRUSTED_PIECE) {
                return None;
            }
            crossed = crossed.max_of(rel);
        }
        let f = |r: &T| (radial.eval_ln(r) + base.clone()).exp();
        let cuts: Vec<T> = graded_about(&t0.lit(0.0), &t0.lit(1e-12), &t0.lit(1.0))
            .into_iter()
            .filter(|c| *c > *t0 && *c < end)
            .collect();
        let domain = Domain::finite(t0.clone(), end).with_breakpoints(cuts);
        let o = Options { abs_tol: 0.0, cross_check: false, ..opts.clone() };
        Some(crate::quad::integrate(f, &domain, &o).map(|e| {
            let bar = e.error.clone() + e.value.abs() * crossed;
            Estimate { error: bar, ..e }
        }))
    }

    /// (ln ρ₁(r), relative bar) from the radial table where it reaches and
    /// its piece's bar is at most [`TRUSTED_PIECE`] (r ≥ 10⁻¹², σ-units).
    pub(super) fn ln_radial(&self, r: &T) -> Option<(T, T)> {
        let radial = self.radial.as_ref()?;
        if *r > self.hi || *r < r.lit(1e-12) {
            return None;
        }
        let rel = radial.rel_error_at(r);
        (rel.to_f64() <= TRUSTED_PIECE).then(|| (radial.eval_ln(r), rel))
    }

    /// (ln T₁(t), relative bar) where the table reaches.
    fn ln_tail(&self, t: &T) -> Option<(T, T)> {
        if *t > self.hi {
            return None;
        }
        Some((self.table.eval_ln(t), self.table.rel_error.clone()))
    }
}

/// ln T₁(t) and its relative bar, from the table or by quadrature.
fn ln_tail<T: CheckRule>(density: &StartDensity<T>, table: Option<&TailTable<T>>, t: &T, opts: &Options) -> Outcome<T> {
    if let Some((v, rel)) = table.and_then(|tab| tab.ln_tail(t)) {
        return Ok(Estimate::known(v, rel, 1, opts.rule));
    }
    density.ln_tail(t, opts)
}

/// A radial function of the distance d to the sphere's centre, as
/// e^{−σ·reach}·rest with a relative bar: the hit chance H (reach the path
/// to the surface along the cap's rim) or a function built on it.
pub(super) struct Radial<T> {
    pub reach: T,
    pub rest: T,
    pub rel: T,
}

/// A [`Radial`] of the distance d, computed with the options it is handed.
pub(super) type RadialFn<'a, T> = dyn Fn(&T, &Options) -> Result<Radial<T>, crate::quad::Failure<T>> + Sync + 'a;

/// H(d) as a [`Radial`] (exact: no bar).
pub(super) fn hit_radial<T: CheckRule>(sigma: &T, r: &T, d: &T) -> Radial<T> {
    let (reach, rest) = hit_chance_parts(sigma, r, d);
    Radial { reach, rest, rel: d.lit(0.0) }
}

/// (C * H)(D)·e^{shift} for a sphere whose centre is D > 0 from the light
/// (module docs), as one level inside a pass (its rule): σ the medium's, R
/// the sphere's radius; `table` the pass's tail table, if any.
pub(super) fn multiple_hits<T: CheckRule>(
    density: &StartDensity<T>,
    table: Option<&TailTable<T>>,
    sigma: &T,
    r: &T,
    big_d: &T,
    shift: &T,
    opts: &Options,
) -> Outcome<T> {
    let radial = |d: &T, _: &Options| Ok(hit_radial(sigma, r, d));
    convolved(density, table, sigma, r, big_d, shift, &radial, opts)
}

/// (C * F)(D)·e^{shift} for a radial function F of the distance to the
/// sphere's centre ([`Radial`], kinked at d = R like H), its relative bar
/// carried into each sample: [`multiple_hits`] with F in place of H.
#[allow(clippy::too_many_arguments)]
pub(super) fn convolved<T: CheckRule>(
    density: &StartDensity<T>,
    table: Option<&TailTable<T>>,
    sigma: &T,
    r: &T,
    big_d: &T,
    shift: &T,
    radial: &RadialFn<'_, T>,
    opts: &Options,
) -> Outcome<T> {
    let ln_sigma = sigma.ln();
    let f = |d: &T, o: &Options| -> Outcome<T> {
        if d.is_zero() {
            return Ok(Estimate::known(d.lit(0.0), d.lit(0.0), 0, o.rule));
        }
        let Radial { reach, rest, rel: f_rel } = radial(d, o)?;
        let base = shift.clone() - sigma.clone() * reach + ln_sigma.clone();
        let front = d.clone() * rest;
        // A shell short against its radius: ∫ρ over it, not a difference of T.
        let (t0, width) = (
            sigma.clone() * (big_d.clone() - d.clone()).abs(),
            sigma.clone() * d.lit(2.0) * d.clone().min_of(big_d.clone()),
        );
        if let Some((v, rel, used)) = table.and_then(|tab| tab.shell(&t0, &width, &base)) {
            let value = front * v;
            return Ok(Estimate::known(value.clone(), value.abs() * (rel + f_rel), used, o.rule));
        }
        let near = ln_tail(density, table, &(sigma.clone() * (big_d.clone() - d.clone()).abs()), o)?;
        let far = ln_tail(density, table, &(sigma.clone() * (big_d.clone() + d.clone())), o)?;
        let (tn, tf) = ((base.clone() + near.value).exp(), (base.clone() + far.value).exp());
        // Two values of T that cancel by more than 4×: ∫ρ over the shell.
        if (tn.clone() + tf.clone()) > (tn.clone() - tf.clone()) * d.lit(4.0) {
            if let Some(e) = table.and_then(|tab| tab.wide_shell(&t0, &width, &base, o)) {
                let e = e?.scaled(&front);
                let error = e.error.clone() + e.value.abs() * f_rel;
                return Ok(Estimate { error, ..e });
            }
        }
        let value = front.clone() * (tn.clone() - tf.clone());
        // Relative bars ρ of each T: the difference carries ρ_n T_n + ρ_f T_f.
        let error = front * (tn * near.error + tf * far.error) + value.abs() * f_rel;
        Ok(Estimate::known(value, error, near.evaluations + far.evaluations, o.rule))
    };
    // I(D)'s cuts (d = D, where T's argument |D − d| turns; d = R; R·10^k
    // up to D), d = D/5 and 5D (where a shell becomes short enough for ∫ρ),
    // and decades about D.
    let mut cuts = bipolar_cuts(big_d, r);
    cuts.extend([big_d.clone() / big_d.lit(5.0), big_d.clone() * big_d.lit(5.0)]);
    cuts.extend(
        graded_about(big_d, &(big_d.clone() * big_d.lit(1e-6)), big_d).into_iter().filter(|c| c > &big_d.lit(0.0)),
    );
    let domain = Domain::semi_infinite(big_d.lit(0.0)).with_breakpoints(cuts).with_decay(sigma.clone());
    let factor = big_d.lit(2.0) * big_d.pi() / big_d.clone();
    let opts = &Options { abs_tol: (opts.abs_tol / factor.to_f64()).min(f64::MAX), ..opts.clone() };
    Ok(integrate_within_pass(f, &domain, opts)?.scaled(&factor))
}

/// The tables of every order beyond the first for one pass: T₁ and
/// (C * H)(D) over the computation's distances.
#[derive(Debug)]
pub(super) struct MultipleTable<T> {
    tail: Option<TailTable<T>>,
    hits: Option<ScatteredTable<T>>,
}

/// The multiple-scattering tables of one computation, one per pass: the
/// point lights' and the beams' (`multiple_beam`).
pub(super) struct MultipleTables<T> {
    passes: OncePerPass<MultipleTable<T>>,
    beams: BeamBeyondTables<T>,
    /// A cap on the goal a pass's tables are built at (none coarser): the
    /// primary pass's of the computation (`once_per_pass::capped_tables`),
    /// if set.
    finest: Option<f64>,
}

impl<T> Default for MultipleTables<T> {
    fn default() -> Self {
        MultipleTables { passes: OncePerPass::default(), beams: BeamBeyondTables::new(BeamLimit::Exact), finest: None }
    }
}

impl<T> MultipleTables<T> {
    /// The tables of a computation with options `opts`, whose scale pass
    /// reads its primary pass's tables (`once_per_pass::fine_tables`).
    pub(super) fn for_computation(opts: &Options) -> Self {
        let finest = Some(crate::model::once_per_pass::primary_goal(opts));
        MultipleTables { finest, beams: BeamBeyondTables::new(BeamLimit::Exact).finest(finest), ..Self::default() }
    }
}

impl<T> MultipleTable<T> {
    /// The (C * H)(D) table, if it could be built.
    pub(super) fn hits_table(&self) -> Option<&ScatteredTable<T>> {
        self.hits.as_ref()
    }
}

impl<T: CheckRule> MultipleTables<T> {
    /// The beams' tables of orders ≥ 2 (`multiple_beam`).
    pub(super) fn beams(&self) -> &BeamBeyondTables<T> {
        &self.beams
    }

    /// The tables of the pass with `opts` over the distances of `ff`.
    pub(super) fn for_pass(
        &self,
        ff: &FiniteField<T>,
        density: &StartDensity<T>,
        opts: &Options,
    ) -> Option<Arc<MultipleTable<T>>> {
        let opts = &crate::model::once_per_pass::capped_tables(opts, self.finest);
        self.passes.get_or_build(opts, || {
            let Some((lo, hi)) = super::scattered_table::distance_range(ff) else { return (None, 0) };
            // T is read at σ(D + d), d up to where the d-integral's tail is
            // cut (`quad`, decay rate σ): beyond, the quadrature serves.
            let reach = ff.sigma.clone() * (hi.clone() + ff.radius.clone()) * ff.sigma.lit(2.0) + ff.sigma.lit(200.0);
            let (tail, mut spent) = TailTable::build(density, &reach, opts);
            let decay = ff.sigma.clone() * density.decay();
            let g = |d: &T, o: &Options| {
                let shift = decay.clone() * (d.clone() - ff.radius.clone()).max_of(d.lit(0.0));
                multiple_hits(density, tail.as_ref(), &ff.sigma, &ff.radius, d, &shift, o)
            };
            let (hits, used) =
                ScatteredTable::build_with(g, &decay, &ff.radius, &lo, &hi, super::scattered_table::LOWEST, opts);
            spent += used;
            (Some(MultipleTable { tail, hits }), spent)
        })
    }

    /// `result` with every table's evaluations added.
    pub(super) fn charge<E>(&self, result: Result<Estimate<T>, E>) -> Result<Estimate<T>, E> {
        self.beams.charge(self.passes.charge(result))
    }
}

impl<T: CheckRule> PointLight<T> {
    /// ⟨𝒞⟩_{2..n}·e^{c₀} at s = center + x: the mean contribution of the
    /// light's paths' segments 2..=n (or all) to the sphere there (module
    /// docs), from the pass's tables where they reach, else by quadrature.
    /// Isotropic media only (the caller's check). Not in the paper, whose
    /// §3 stops at the field it leaves unspecified: exact at R.
    pub(super) fn multiple_moment(
        &self,
        ff: &FiniteField<T>,
        density: &StartDensity<T>,
        tables: &MultipleTables<T>,
        x: &T,
        opts: &Options,
    ) -> Outcome<T> {
        let (big_d, _) = self.distance_to(ff, x);
        let front = ff.per_hit_power(1, &self.flux) / (x.pi() * x.lit(4.0));
        let table = tables.for_pass(ff, density, opts);
        if let Some((v, rel)) =
            table.as_ref().and_then(|t| t.hits.as_ref()?.hits(&ff.sigma, &ff.radius, &big_d, &ff.shift))
        {
            let bar = v.abs() * rel;
            return Ok(Estimate::known(v, bar, 1, opts.rule).scaled(&front));
        }
        // Far out on the camera ray (beyond the tables, where σe^{−σs} has
        // made every value negligible) the bound (C * H) ≤ ∫C = Σ a^j
        // (H ≤ 1) serves when it is within the goal.
        let bound = density.mass() * ff.shift.clone().exp() * front.clone();
        if bound.to_f64() <= opts.abs_tol {
            return Ok(Estimate::known(x.lit(0.0), bound, 0, opts.rule));
        }
        let o = Options { abs_tol: (opts.abs_tol / front.to_f64()).min(f64::MAX), ..opts.clone() };
        let tail = table.as_ref().and_then(|t| t.tail.as_ref());
        let e = multiple_hits(density, tail, &ff.sigma, &ff.radius, &big_d, &ff.shift, &o)?.scaled(&front);
        Ok(e)
    }
}

impl<T: CheckRule> FiniteField<T> {
    /// Whether the model of every order covers this field's scene's mean
    /// (orders ≥ 2 in an isotropic medium; point lights and beams, the
    /// beams' in `multiple_beam`), or why not: the check to make before any
    /// costly integral.
    pub fn every_order_covered(&self) -> Result<(), OracleError> {
        self.higher_orders().map(|_| ())
    }

    /// The start density of the segments beyond the first, or an error
    /// naming what the model does not cover: orders ≥ 2 need an isotropic
    /// medium.
    pub(super) fn higher_orders(&self) -> Result<&StartDensity<T>, OracleError> {
        let density = match self.higher.as_ref() {
            None => {
                return Err(OracleError::Unsupported(
                    "the scene's forward paths stop before their second scattering".into(),
                ))
            }
            Some(Err(why)) => return Err(OracleError::Unsupported(why.clone())),
            Some(Ok(density)) => density,
        };
        if self.phase != mcrt_scene::Phase::Isotropic {
            return Err(every_order_phase_refusal(self.phase));
        }
        Ok(density)
    }

    /// μ_{2..n}(R)·e^{c₀} = ∫σe^{−σs}⟨𝒞⟩_{2..n} ds: the share of the mean
    /// luminance of the forward paths' segments beyond the first (module
    /// docs; a beam's from `multiple_beam`); with [`FiniteField::ray_total`] of the mean and
    /// [`FiniteField::scattered_mean`] it is the exact mean of a scene with
    /// orders ≥ 2 at its R.
    pub fn multiple_mean(&self, opts: &Options) -> Result<Estimate<T>, OracleError> {
        let tables = MultipleTables::for_computation(opts);
        tables.charge(self.multiple_mean_with(&tables, opts))
    }

    /// [`FiniteField::multiple_mean`] reading (and building) `tables`,
    /// whose evaluations the caller charges.
    pub(super) fn multiple_mean_with(
        &self,
        tables: &MultipleTables<T>,
        opts: &Options,
    ) -> Result<Estimate<T>, OracleError> {
        let density = self.higher_orders()?;
        self.with_line(|line| {
            line.integral_nested("finite-sphere ∫⟨𝒞⟩ of segments ≥ 2", opts, |x, o| {
                let share = Options { abs_tol: o.abs_tol / self.lights.len() as f64, ..o.clone() };
                self.sum_over_lights(x, o, |i, light| match light {
                    FiniteLight::Point(p) => p.multiple_moment(self, density, tables, x, &share),
                    FiniteLight::Beam(b) => b.beyond_moment(self, density, &tables.beams, i, x, &share),
                })
            })
        })
    }

    /// μ(0)·e^{c₀} of the orders 0..=n (`orders`, or all): the
    /// small-sphere mean luminance, the estimator's limit as R → 0 and the
    /// zero of its bias (module docs). As R → 0, H(d) → (πR²/σ)c₁(d), so
    /// segment j's ⟨𝒞⟩ tends to (Φ/(4πσ)) a^{j+1} c_{j+1}(D):
    /// μ(0) = Σ_lights (Φ/4π)∫e^{−σs} Σ_{m=1}^{n+1} a^m c_m(D(s)) ds, with
    /// a c₁ in closed form and the rest from [`StartDensity::radial`]. An
    /// independent route to the small-sphere model's mean of orders ≤ 1
    /// (docs/model.md §3a: L₁ integrated over directions), which `tests`
    /// compare with it. Domain: isotropic media, point lights not on the
    /// camera line (a beam's μ(0) of every order: `oracle::every_order_mean`).
    pub fn small_sphere_mean_every_order(
        &self,
        orders: mcrt_scene::ScatteringOrders,
        opts: &Options,
    ) -> Result<Estimate<T>, OracleError> {
        if self.lights.iter().any(|l| matches!(l, FiniteLight::Beam(_))) {
            return Err(OracleError::Unsupported(
                "small_sphere_mean_every_order covers point lights; a beam's small-sphere mean of every order is \
                 `oracle::every_order_mean`'s `small_sphere_mean`"
                    .into(),
            ));
        }
        self.small_sphere_mean_of_segments(orders, opts)
    }

    /// [`FiniteField::small_sphere_mean_every_order`] with beams, whose share
    /// is of their segments 2..=n only (their orders 0 and 1 are the
    /// small-sphere model's, `model::field`, as the oracle adds them):
    /// a(Φ/(4πσ))∫e^{−σs}∫n(x₁)C(|x₁ − x(s)|)d³x₁ ds (`multiple_beam`).
    pub(crate) fn small_sphere_mean_of_segments(
        &self,
        orders: mcrt_scene::ScatteringOrders,
        opts: &Options,
    ) -> Result<Estimate<T>, OracleError> {
        use mcrt_scene::ScatteringOrders::{All, Limited};
        self.order1_covered()?;
        if self.phase != mcrt_scene::Phase::Isotropic {
            return Err(OracleError::Unsupported("the small-sphere mean of every order covers isotropic media".into()));
        }
        let (beyond, beams_beyond) = match orders {
            Limited(0) => (None, None),
            Limited(1) => (Some(StartDensity::new(&self.albedo, 2, Some(2))?), None),
            Limited(n) => (
                Some(StartDensity::new(&self.albedo, 2, Some(n + 1))?),
                Some(StartDensity::new(&self.albedo, 2, Some(n))?),
            ),
            All => (Some(StartDensity::new(&self.albedo, 2, None)?), Some(StartDensity::new(&self.albedo, 2, None)?)),
        };
        let beam_tables = BeamBeyondTables::new(BeamLimit::SmallSphere);
        let sigma = &self.sigma;
        let mean = self.with_line(|line| {
            line.integral_nested("small-sphere ∫ of every order", opts, |x, o| {
                self.sum_over_lights(x, o, |i, light| {
                    let p = match light {
                        FiniteLight::Point(p) => p,
                        FiniteLight::Beam(b) => {
                            let Some(density) = &beams_beyond else {
                                return Ok(Estimate::known(x.lit(0.0), x.lit(0.0), 0, o.rule));
                            };
                            let share = Options { abs_tol: o.abs_tol / self.lights.len() as f64, ..o.clone() };
                            return b.beyond_moment(self, density, &beam_tables, i, x, &share);
                        }
                    };
                    let (big_d, _) = p.distance_to(self, x);
                    let sd = sigma.clone() * big_d.clone();
                    // (Φ/(4πσ))·a^m c_m(D), c_m(D) = σ²·(r C)₁(σD)/D: Φσ/(4πD)·(r C)₁.
                    let front = p.flux.clone() * sigma.clone() / (x.pi() * x.lit(4.0) * big_d.clone());
                    let first = self.albedo.clone() * (self.shift.clone() - sd.clone()).exp()
                        / (x.pi() * x.lit(4.0) * sd.clone());
                    // The radial part is multiplied by front·e^{c₀} below.
                    let scale = front.to_f64() * self.shift.exp().to_f64() * self.lights.len() as f64;
                    let o2 = Options { abs_tol: (o.abs_tol / scale).min(f64::MAX), ..o.clone() };
                    let mut part = Estimate::known(first, x.lit(0.0), 0, o.rule);
                    if let Some(beyond) = &beyond {
                        part = part.plus(beyond.radial(&sd, &o2)?.scaled(&self.shift.exp()));
                    }
                    Ok(part.scaled(&front))
                })
            })
        });
        beam_tables.charge(mean)
    }
}

/// The refusal of a scene with `scattering_orders` ≥ 2 in a medium other
/// than an isotropic one, naming the fields a user would change.
pub(crate) fn every_order_phase_refusal(phase: mcrt_scene::Phase) -> OracleError {
    let phase = match phase {
        mcrt_scene::Phase::Isotropic => "medium.phase.kind = \"isotropic\"".to_string(),
        mcrt_scene::Phase::HenyeyGreenstein { g } => format!("medium.phase.kind = \"henyey-greenstein\" (g = {g})"),
    };
    OracleError::Unsupported(format!(
        "effects.scattering_orders >= 2 with {phase}: the finite-sphere model of every order covers isotropic \
         media only (docs/model.md §10.4); allowed: medium.phase.kind = \"isotropic\", or scattering_orders <= 1"
    ))
}

#[cfg(test)]
#[path = "multiple_tests.rs"]
mod tests;
