//! A beam's same-path pairs of every order (isotropic media, q = 1, N_B = 1;
//! `docs/model.md` §10.6): how often one forward path of a beam hits one
//! sphere with two of its segments j < k, which M₂ needs beside
//! Σ_j⟨𝒞_j²⟩ = c f⟨𝒞⟩ for Var L.
//!
//! A beam's path is its ray (segment 0, collimated) and, after the ray's
//! first interaction at x₁ (density n(x₁) of §9.8) and a scattering there
//! (a), a fresh isotropic path at x₁ of at most n segments (every order: no
//! end). So the pairs split in two:
//!
//! - **the ray with a later segment**: the ray passes the centre at
//!   ρ ≤ R, reaches its closest point (e^{−στ(s)}) and, interacting u
//!   beyond it, its fresh path hits with G (`fresh_hits`): order 1's
//!   ⟨𝒞₀𝒞₁⟩ of `scattered_beam` with K_G(w) of `multiple_pairs` (the level
//!   of a segment followed by at most n more, which carries the albedo) in
//!   place of order 1's K;
//! - **two later segments**: those of the fresh path at x₁, whose pairs at
//!   distance d are the pair sum 𝒮(d) of a point light of orders n − 1
//!   (`PairOrders::fresh_terms`, the same tables), so they add
//!   2(c f)²(Φ/𝓕)·a∫n(x₁)𝒮(|x₁ − x(s)|) d³x₁: §9.8's volume integral with
//!   𝒮 in place of H, tabled over d ∈ [0, reach] per pass
//!   ([`BeamPairSums`]) and along the camera ray per pass as the beam's
//!   mean of every order is (`multiple_beam::AlongRay`).
//!
//! The shells run to d_cut = D + span (D the distance to the farthest
//! point of the beam's disk, span as the mean's, `multiple_beam::cut_span`);
//! beyond, 𝒮 ≤ M·G (each hit of segment j pairs with at most the later
//! segments, whose number is independent of the hit: at most n, or
//! a/(1 − a) expected with every order; M = n or 1/(1 − a)) and G is
//! radially decreasing, so the rest is at most M·G(d_cut)·∫n ≤ M·G(d_cut),
//! read from a table of G and carried as the bar.

use super::beam::BeamLight;
use super::fresh_hits::{from_table, FreshHits};
use super::multiple_beam::{shells_to_cut, AlongRay};
use super::multiple_pairs::{pair_sum, pair_table_options, PairTable};
use super::pair_orders::PairOrders;
use super::scattered_table::{ScatteredTable, LOWEST, WINDOW};
use super::start_density::StartDensity;
use super::{FiniteField, OncePerPass};
use crate::model::beam_source::ShellFactor;
use crate::quad::{CheckRule, Estimate, Failure, Options, Outcome};

/// The half-width of the pair sum's table's window about R, relative to R:
/// within it each shell's 𝒮 is bracketed by [0, M·G(R(1 − 2·10⁻⁶))]
/// instead of computed (its quadrature there costs ~10⁶ evaluations a
/// shell, and the shells' nodes crowd towards their knee at R); the window
/// is narrow enough that its shells' share of the volume integral, ~10⁻¹²
/// of it times M·G/𝒮, is far below any goal even with that bar (at 10⁻⁹R
/// albedo 0.99, M = 100, ended NOT CONVERGED).
const SUMS_WINDOW: f64 = 1e-12;

/// The tables of a pass a beam's pairs of every order read beside the
/// levels' K_G and 𝒦 (module docs).
pub(super) struct BeamPairSums<T> {
    /// 𝒮(d)·e^{ν(d − R)⁺} over [10⁻⁴R, reach] (the window about R apart),
    /// its bar with the 𝒦 tables' added.
    pub(super) sums: ScatteredTable<T>,
    /// G(d)·e^{ν(d − R)⁺} of the fresh path with all its segments over
    /// [10⁻⁴R, reach]: the bound beyond the shells' cut, and in the pair
    /// sum's window about R.
    pub(super) hits: ScatteredTable<T>,
    /// How far beyond the farthest point of the disk the shells run.
    span: T,
    /// The fresh path's hits per hit at most (M, module docs).
    most_hits: T,
}

/// G over [10⁻⁴R, reach] from `fresh`'s tables (all the parts `orders`
/// have): the bound of the shells' cut and of the pair sum's window about R
/// ([`BeamPairSums`]), built while `fresh` lives; `None` if it cannot be
/// built.
pub(super) fn hits_table<T: CheckRule>(
    fresh: &FreshHits<'_, T>,
    orders: &PairOrders<T>,
    (r, reach): (&T, &T),
    opts: &Options,
) -> (Option<ScatteredTable<T>>, u64) {
    let parts = orders.most_parts();
    let g = |d: &T, o: &Options| -> Outcome<T> {
        let g = fresh.radial(parts, d, o)?;
        let bar = g.rest.abs() * g.rel;
        Ok(Estimate::known(g.rest, bar, 1, o.rule))
    };
    let (table, used) = ScatteredTable::build_with(g, fresh.nu(), r, &r.lit(0.0), reach, LOWEST, opts);
    let table = table.map(|mut t| {
        t.rel_error = t.rel_error.clone() + fresh.rel_error.clone();
        t
    });
    (table, used)
}

impl<T: CheckRule> BeamPairSums<T> {
    /// The pair sum of the fresh path over [0, reach] from `table`'s levels
    /// and tails (at the rate ν = `nu`), with `hits` (from
    /// [`hits_table`]); `None` if the pair sum's table cannot be built.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn build(
        (sigma, r, a): (&T, &T, &T),
        nu: &T,
        orders: &PairOrders<T>,
        table: &PairTable<T>,
        hits: ScatteredTable<T>,
        (span, reach): (&T, &T),
        opts: &Options,
    ) -> (Option<Self>, u64) {
        let terms = orders.fresh_terms();
        let sum_of = |d: &T, o: &Options| {
            let shift = nu.clone() * (d.clone() - r.clone()).max_of(d.lit(0.0));
            pair_sum(sigma, r, a, orders, &terms, table, d, &shift, o)
        };
        let range = (&r.lit(0.0), reach);
        let (sums, used) = ScatteredTable::build_with_window(sum_of, nu, r, range, (LOWEST, SUMS_WINDOW), opts);
        let Some(mut sums) = sums else { return (None, used) };
        sums.rel_error = sums.rel_error.clone() + table.revisit_rel();
        let most_hits = orders.most_hits(orders.most_parts());
        (Some(BeamPairSums { sums, hits, span: span.clone(), most_hits }), used)
    }
}

/// The beams' along-ray tables of the pairs of their later segments, one
/// per pass.
pub(super) struct BeamPairTables<T> {
    passes: OncePerPass<AlongRay<T>>,
}

impl<T> Default for BeamPairTables<T> {
    fn default() -> Self {
        BeamPairTables { passes: OncePerPass::default() }
    }
}

impl<T: CheckRule> BeamPairTables<T> {
    /// `result` with every table's evaluations added.
    pub(super) fn charge<E>(&self, result: Result<Estimate<T>, E>) -> Result<Estimate<T>, E> {
        self.passes.charge(result)
    }
}

impl<T: CheckRule> BeamLight<T> {
    /// ∫ n(x₁) 𝒮(|x₁ − x(s)|) d³x₁·e^{shift} at s = center + x (module
    /// docs), 𝒮 from `sums`' table (held flat below its lowest distance,
    /// bracketed in its window about R), shells out to the span beyond the
    /// farthest point of the disk, the rest bounded by M·G there.
    #[allow(clippy::too_many_arguments)]
    fn pairs_volume(
        &self,
        ff: &FiniteField<T>,
        sums: &BeamPairSums<T>,
        nu: &T,
        x: &T,
        shift: &T,
        opts: &Options,
    ) -> Outcome<T> {
        let r = &ff.radius;
        let at = self.seen_at(ff, x);
        let cut = at.farthest_on_disk() + sums.span.clone();
        let factor = |d: &T, _: &Options| -> Result<ShellFactor<T>, Failure<T>> {
            let beyond_r = (d.clone() - r.clone()).max_of(d.lit(0.0));
            let ln = -(nu.clone() * beyond_r.clone());
            // The table's own bar is one of every value built on it (the
            // along-ray table's `rel`): each shell bears the rest.
            if let Some(k) = from_table(&sums.sums, nu, r, d) {
                let rel = (k.rel - sums.sums.rel_error.clone()).max_of(d.lit(0.0));
                return Ok(ShellFactor { ln, rest: k.rest, rel });
            }
            // Below the table's lowest distance (a shell about a camera-ray
            // point inside the beam): 𝒮 is smooth there (a source inside the
            // sphere), taken at the lowest distance with twice its change
            // over the decade above as the bar (as `FreshHits` takes G).
            let lowest = r.clone() * r.lit(LOWEST);
            let read = |at: &T| from_table(&sums.sums, nu, r, at);
            let missing = |what: &str| Failure {
                reason: format!("a beam's pairs of every order: the pair sum's table does not reach {what} {d:?}"),
                best_guess: None,
                error_estimate: None,
                evaluations: 0,
            };
            if *d < lowest {
                let (Some(s0), Some(s1)) = (read(&lowest), read(&(lowest.clone() * d.lit(10.0)))) else {
                    return Err(missing("the distance"));
                };
                let bar = (s0.rest.clone() - s1.rest).abs() * d.lit(2.0);
                let rel = bar / s0.rest.clone().abs();
                return Ok(ShellFactor { ln, rest: s0.rest, rel });
            }
            if (d.clone() - r.clone()).abs() > r.clone() * r.lit(SUMS_WINDOW * (1.0 + 1e-6)) {
                return Err(missing("the distance"));
            }
            // Within the table's window about R (|d − R| ≤ 10⁻¹²R, where 𝒮
            // jumps with the ray's first hit): 𝒮 ≤ M·G(d) ≤ M·G(R(1 − 2·10⁻⁶))
            // (G radially decreasing; read inside G's table, not on the end
            // of its piece at R(1 − 10⁻⁶)), taken as half that with a bar
            // of all of it.
            let edge = r.clone() * (r.lit(1.0) - r.lit(2.0 * WINDOW));
            let Some(g) = from_table(&sums.hits, nu, r, &edge) else {
                let reason = "a beam's pairs of every order: the table of G does not reach R".to_string();
                return Err(Failure { reason, best_guess: None, error_estimate: None, evaluations: 0 });
            };
            let half = sums.most_hits.clone() * g.rest * (d.lit(0.5) + d.lit(0.5) * g.rel) * (-ln.clone()).exp();
            Ok(ShellFactor { ln, rest: half, rel: d.lit(1.0) })
        };
        // d²·σe^{shift − σt}·𝒮(d).
        let e = shells_to_cut(ff, &at, (&factor, nu), (&cut, shift), opts)?;
        let Some(g) = from_table(&sums.hits, nu, r, &cut) else {
            let reason = "a beam's pairs of every order: the table of G does not reach the shells' cut".to_string();
            return Err(Failure { reason, best_guess: None, error_estimate: None, evaluations: e.evaluations });
        };
        let beyond_r = (cut.clone() - r.clone()).max_of(cut.lit(0.0));
        let beyond =
            sums.most_hits.clone() * g.rest * (shift.clone() - nu.clone() * beyond_r).exp() * (x.lit(1.0) + g.rel);
        let error = e.error.clone() + beyond;
        Ok(Estimate { error, ..e })
    }
}

impl<T: CheckRule> FiniteField<T> {
    /// The same-path pairs of beam `index` of every order at s = center + x,
    /// ·e^{c₀}, in M₂ (module docs): 2⟨𝒞₀ Σ_{k≥1}𝒞_k⟩ of its ray with K_G
    /// and 2(c f)²(Φ/𝓕)·a∫n 𝒮 of its later segments (from the pass's
    /// along-ray table in `along`, built from `table` at the options
    /// `tabled` (the pass's tables'); beyond its range, 0
    /// with the bound of the pairs of a fresh path as the bar). Isotropic
    /// media (the caller's check). Not in the paper (its §3 has no pairs
    /// of one path's segments; E9).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn beam_pairs(
        &self,
        beam: (&BeamLight<T>, usize),
        (density, orders, table): (&StartDensity<T>, &PairOrders<T>, &PairTable<T>),
        (along, tabled): (&BeamPairTables<T>, &Options),
        x: &T,
        opts: &Options,
    ) -> Outcome<T> {
        let (b, index) = beam;
        let fail = |reason: String| Failure { reason, best_guess: None, error_estimate: None, evaluations: 0 };
        let Some(sums) = table.beams.as_ref() else {
            return Err(fail(opts.budget.exhausted().unwrap_or_else(|| {
                "the tables of a beam's same-path pairs of every order (the pair sum of its fresh path and G, \
                 docs/model.md §10.6) could not be built within the goal"
                    .into()
            })));
        };
        let half = Options { abs_tol: opts.abs_tol / 2.0, ..opts.clone() };
        // The ray reads the level of a segment followed by at most n more.
        let ray_level = orders.terms[0].1;
        let ray = b.ray_pairs_every_order(self, x, &table.levels[ray_level].after, &half)?.scaled(&x.lit(2.0));
        let nu = self.sigma.clone() * orders.decay();
        // At the pair tables' goal (the outer one): a finer table would ask
        // its samples for more than the pair sum's table they read holds.
        let along = along.passes.get_or_build(tabled, || {
            let rel = sums.sums.rel_error.clone();
            AlongRay::build(self, density, rel, &pair_table_options(tabled), |b, x, shift, samples| {
                b.pairs_volume(self, sums, &nu, x, shift, samples)
            })
        });
        let f = x.lit(1.0) / (x.pi() * x.lit(4.0));
        let front = self.per_hit_power(2, &b.flux) * f.clone() * f * x.lit(2.0) * self.albedo.clone();
        let Some(along) = along else {
            return Err(fail(opts.budget.exhausted().unwrap_or_else(|| {
                format!(
                    "the along-ray table of a beam's same-path pairs of every order could not be built to {:e} (a \
                     tenth of the pair tables' goal, docs/model.md §10.6)",
                    pair_table_options(tabled).rel_tol / 10.0
                )
            })));
        };
        let volume = match along.value(self, index, x).map_err(fail)? {
            Some((v, rel)) => {
                let bar = v.abs() * rel;
                Estimate::known(v, bar, 1, opts.rule)
            }
            // Beyond the table range σe^{−σs} makes the bound negligible:
            // the fresh path's pairs are at most M² (n² or 1/(1 − a)²).
            None => {
                let bound = sums.most_hits.clone() * sums.most_hits.clone() * self.shift.clone().exp();
                Estimate::known(x.lit(0.0), bound, 0, opts.rule)
            }
        };
        Ok(ray.plus(volume.scaled(&front)))
    }
}
