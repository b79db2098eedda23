//! The same-path pairs of orders ≥ 2 and of every order (isotropic media,
//! point lights: `docs/model.md` §10.3; a beam's, which read these tables,
//! are `multiple_beam_pairs`, §10.6): how often one forward path hits
//! one sphere with two of its segments j < k, which M₂ needs beside
//! Σ_j⟨𝒞_j²⟩ = c f ⟨𝒞⟩, so that Var L at q = 1 and N_B = 1 is exact at
//! any R.
//!
//! A segment is a fresh isotropic source wherever it starts (the light for
//! j = 0, an interaction point after), and everything after its end, if it
//! scatters there (a), is a fresh source too, whose hits of the sphere at
//! distance d′ are G(d′) = H + a·I + C′ * H (segments 0, 1 and ≥ 2 of a
//! fresh path: §9.5, §10.2). So the pairs of a segment starting at
//! distance d from the centre are
//!
//!   𝒦(d) = E[1{the segment hits}·a·G(|end − x|)] = ½∫_cap sin ψ e^{−σ d cos ψ} K_G(d sin ψ) dψ,
//!   K_G(p) = ∫₀^∞ σe^{−σu} a·G(√(u² + p²)) du
//!
//! (u measured from the closest point; the cap is that of §9.6), and every
//! segment of every order starts at δ_light + C_all, C_all = a c₁ + C′:
//!
//!   E[Σ_{j<k} hit_j hit_k] = 𝒦(D) + a·(c₁ * 𝒦)(D) + (C′ * 𝒦)(D),
//!
//! the last two by the bipolar integrals of §9.5 and §10.2 with 𝒦 in
//! place of H. Per pass, G(d′) over [10⁻⁴R, R + 50/σ] is read from tables
//! of its parts (`fresh_hits`): the pass's tables of I(D) and (C′ * H)(D)
//! — those P builds on the same field, made to reach there by
//! `FiniteField::cover_pair_distances` (else tables of their own,
//! `ScatteredTable`, decay νσ) — and the tail tables T of the start
//! densities (`multiple::TailTable`); then tables follow, each from the
//! one before, each carrying the bar of the table it reads: K_G(w) over
//! the sphere's cross-section (`SecondHitTable`, w = √(R² − p²)), 𝒦(d)
//! (`ScatteredTable`, decay σ), and the pair sum itself over the distances
//! between the lights and the camera ray's spheres (`ScatteredTable`,
//! decay νσ), which the camera-ray integral reads.
//! Order 1's own term (§9.6) is the case G = H, C_all = 0.
//!
//! With orders up to n (2 ≤ n ≤ 9) what follows segment j is a fresh path
//! of at most m = n − j segments, whose hits are G_m = H + Σ_{k<m} part_k
//! (`fresh_hits`): each level m has its K_G and 𝒦 tables, and segment j
//! starts at a^j c_j, so
//!
//!   E[Σ_{j<k} hit_j hit_k] = 𝒦_n(D) + a·(c₁ * 𝒦_{n−1})(D) + Σ_{j=2}^{n−1} (a^j c_j * 𝒦_{n−j})(D)
//!
//! ([`PairOrders`]); every order is the one level of G with its parts a·I
//! and C′ * H, and three terms.

use super::fresh_hits::{from_table, FreshHits};
use super::multiple::{convolved, MultipleTables, Radial, RadialFn, TailTable};
use super::multiple_beam::{beams_reach, cut_span};
use super::multiple_beam_pairs::{hits_table, BeamPairSums, BeamPairTables};
use super::pair_orders::{PairOrders, Start};
use super::point::cap_half_angle;
use super::scattered_table::{ScatteredTable, ScatteredTables};
use super::second_hit::SecondHitTable;
use super::start_density::StartDensity;
use super::{FiniteField, FiniteLight, OncePerPass};
use crate::model::field::graded_about;
use crate::model::once_per_pass::fine_tables;
use crate::model::OracleError;
use crate::quad::{integrate_within_pass, CheckRule, Domain, Estimate, Failure, Options, Outcome};
use crate::special::exp_int_e1_scaled;
use std::sync::Arc;

/// P and the same-path pairs of every order, or why they could not be
/// computed ([`FiniteField::every_order_second_moments`]).
pub type SecondMoments<T> = Result<(Estimate<T>, Estimate<T>), OracleError>;

/// The K_G and 𝒦 tables of one level of remaining segments.
pub(super) struct Level<T> {
    /// K_G over the sphere's cross-section (it carries the albedo).
    pub(super) after: SecondHitTable<T>,
    revisit: ScatteredTable<T>,
}

/// The tables of one pass (module docs).
pub(super) struct PairTable<T> {
    /// The tail tables of the orders' start densities
    /// ([`PairOrders::densities`]).
    tails: Vec<Option<TailTable<T>>>,
    /// Per level of remaining segments ([`PairOrders::levels`]).
    pub(super) levels: Vec<Level<T>>,
    /// E[Σ_{j<k} hit_j hit_k](D)·e^{νσ(D − R)⁺} over the computation's
    /// distances between lights and spheres, read by every camera-ray
    /// point (`None` when it could not be built: the quadrature serves).
    pairs: Option<ScatteredTable<T>>,
    /// What a beam's pairs read beside the levels (`multiple_beam_pairs`),
    /// where the scene has beams (`None` also when they could not be built).
    pub(super) beams: Option<BeamPairSums<T>>,
    /// Whether G was read from the pass's I(D) and (C′ * H)(D) tables
    /// (else from tables of its own): what the unit test asserts.
    #[cfg_attr(not(test), allow(dead_code))]
    g_from_shared: bool,
}

/// What the pair tables cover: the point lights' distances [lo, hi] and
/// the beams' (span, reach) of their shells, where there are such lights.
type Ranges<T> = (Option<(T, T)>, Option<(T, T)>);

/// The pair tables of one computation, one per pass.
pub(super) struct PairTables<T> {
    passes: OncePerPass<PairTable<T>>,
}

impl<T> Default for PairTables<T> {
    fn default() -> Self {
        PairTables { passes: OncePerPass::default() }
    }
}

impl<T: CheckRule> PairTable<T> {
    /// The largest relative bar of the levels' 𝒦 tables.
    pub(super) fn revisit_rel(&self) -> T {
        let bars = self.levels.iter().map(|l| l.revisit.rel_error.clone());
        bars.reduce(|m, b| m.max_of(b)).expect("a pair table has a level")
    }

    /// Builds the tables for a pass with `opts` (module docs), the pair
    /// sum's over the point lights' distances [lo, hi] where there are
    /// point lights, a beam's ([`BeamPairSums`]) over [0, reach] with the
    /// shells' span where there are beams; G's parts from
    /// `mean_tables` (the pass's I(D) and (C′ * H)(D), where they reach
    /// [10⁻⁴R, R + 50/σ]) or tables of their own (`None` if any cannot be
    /// built within its goal).
    fn build(
        ff: &FiniteField<T>,
        orders: &PairOrders<T>,
        (points, beams): Ranges<T>,
        mean_tables: (Option<&ScatteredTable<T>>, Option<&ScatteredTable<T>>),
        opts: &Options,
    ) -> (Option<Self>, u64) {
        let (sigma, r, a) = (&ff.sigma, &ff.radius, &ff.albedo);
        let mut spent = 0;
        // The farthest distance a pair sum is asked for: the point lights'
        // or a beam's shells' reach.
        let widest = match (&points, &beams) {
            (Some((_, hi)), Some((_, reach))) => hi.clone().max_of(reach.clone()),
            (Some((_, hi)), None) => hi.clone(),
            (None, Some((_, reach))) => reach.clone(),
            (None, None) => return (None, 0),
        };
        let far = widest + r.clone() + sigma.lit(100.0) / sigma.clone();
        let reach = sigma.clone() * far.clone() * sigma.lit(2.0) + sigma.lit(200.0);
        let mut tails = Vec::new();
        for density in &orders.densities {
            let (tail, used) = TailTable::build(density, &reach, opts);
            spent += used;
            tails.push(tail);
        }
        let nu = sigma.clone() * orders.decay();
        let beyond = orders.densities.iter().zip(&tails).map(|(d, t)| (d, t.as_ref())).collect();
        let every = orders.every();
        let (once, more) = mean_tables;
        // A beam's cut reads G as far as its shells reach.
        let mut g_reach = r.clone() + sigma.lit(super::fresh_hits::FRESH_REACH) / sigma.clone();
        if let Some((_, reach)) = &beams {
            g_reach = g_reach.max_of(reach.clone());
        }
        let (fresh, used) = FreshHits::build(
            (sigma, r, a),
            (&nu, &g_reach),
            orders.most_parts(),
            once,
            more.filter(|_| every),
            beyond,
            opts,
        );
        spent += used;
        let Some(fresh) = fresh else { return (None, spent) };
        let mut levels = Vec::new();
        for &parts in &orders.levels {
            let (level, used) = Level::build(ff, &fresh, parts, &orders.most_hits(parts), &far, opts);
            spent += used;
            match level {
                Some(l) => levels.push(l),
                None => return (None, spent),
            }
        }
        // With every order part 2 is the pass's (C′ * H)(D) table, if there.
        let g_from_shared = fresh.from_shared && (!every || more.is_some());
        let beam_hits = beams.as_ref().map(|(_, reach)| {
            let (hits, used) = hits_table(&fresh, orders, (r, reach), opts);
            spent += used;
            hits
        });
        drop(fresh);
        let mut table = PairTable { tails, levels, pairs: None, beams: None, g_from_shared };
        if let (Some((span, reach)), Some(Some(hits))) = (&beams, beam_hits) {
            let (sums, used) = BeamPairSums::build((sigma, r, a), &nu, orders, &table, hits, (span, reach), opts);
            spent += used;
            table.beams = sums;
        }
        let Some((lo, hi)) = points else { return (Some(table), spent) };
        let (lo, hi) = (&lo, &hi);
        // The pair sum itself over the distances the camera ray puts between
        // lights and spheres: each camera-ray point then reads one value
        // instead of its convolutions (its samples read 𝒦 without a bar).
        let pairs_of = |d: &T, o: &Options| {
            let shift = nu.clone() * (d.clone() - r.clone()).max_of(d.lit(0.0));
            pair_sum(sigma, r, a, orders, &orders.terms, &table, d, &shift, o)
        };
        let (pairs, used) = ScatteredTable::build_with(pairs_of, &nu, r, lo, hi, super::scattered_table::LOWEST, opts);
        spent += used;
        let revisit_rel = table.revisit_rel();
        table.pairs = pairs.map(|mut p| {
            p.rel_error = p.rel_error.clone() + revisit_rel;
            p
        });
        (Some(table), spent)
    }
}

impl<T: CheckRule> Level<T> {
    /// K_G and 𝒦 for a segment after which G has `parts` parts (at most
    /// `most_hits` hits beyond its tables), 𝒦 over [0, `far`].
    fn build(
        ff: &FiniteField<T>,
        fresh: &FreshHits<'_, T>,
        parts: usize,
        most_hits: &T,
        far: &T,
        opts: &Options,
    ) -> (Option<Self>, u64) {
        let (sigma, r, a) = (&ff.sigma, &ff.radius, &ff.albedo);
        // K_G reads G at the ends of segments through the sphere, u beyond
        // their closest point: within R + U of the centre except with
        // chance e^{−σU} (below).
        let reach_g = fresh.reach();
        // K_G(w) = ∫σe^{−σu} a G(√(u² + R² − w²)) du.
        let after_of = |w: &T, o: &Options| -> Outcome<T> {
            let p2 = (r.clone() - w.clone()) * (r.clone() + w.clone());
            let f = |u: &T, io: &Options| -> Outcome<T> {
                let d = (u.clone() * u.clone() + p2.clone()).sqrt();
                if d > *reach_g {
                    // Beyond the tables: G is at most the fresh path's
                    // hits (its segments; 1/(1 − a) with every order,
                    // each hits at most once).
                    let bound = a.clone() * sigma.clone() * (-(sigma.clone() * u.clone())).exp() * most_hits.clone();
                    return Ok(Estimate::known(u.lit(0.0), bound, 0, io.rule));
                }
                let g = fresh.radial(parts, &d, io)?;
                let v = a.clone() * sigma.clone() * (-(sigma.clone() * (u.clone() + g.reach))).exp() * g.rest;
                Ok(Estimate::known(v.clone(), v.abs() * g.rel, 1, io.rule))
            };
            let zero = w.lit(0.0);
            let mut cuts = vec![w.clone()];
            cuts.extend(graded_about(&zero, r, &(w.lit(4.0) / sigma.clone())).into_iter().filter(|c| *c > zero));
            cuts.extend(graded_about(w, &(r.clone() / w.lit(1e3)), r).into_iter().filter(|c| *c > zero));
            let domain = Domain::semi_infinite(zero).with_breakpoints(cuts).with_decay(sigma.clone());
            integrate_within_pass(f, &domain, o)
        };
        let mut spent = 0;
        let (after, used) = SecondHitTable::build_with(after_of, r, opts);
        spent += used;
        let Some(mut after) = after else { return (None, spent) };
        // K_G read G from its tables without a bar: a relative bar of G is
        // one of K_G (G = H, no parts, has none).
        if parts > 0 {
            after.rel_error = after.rel_error.clone() + fresh.rel_error.clone();
        }
        // 𝒦(d)·e^{σ(d − R)⁺}.
        let revisit_of = |d: &T, o: &Options| {
            revisit(sigma, r, &after, d, &(sigma.clone() * (d.clone() - r.clone()).max_of(d.lit(0.0))), o, false)
        };
        let (revisit, used) =
            ScatteredTable::build_with(revisit_of, sigma, r, &r.lit(0.0), far, super::scattered_table::LOWEST, opts);
        spent += used;
        let Some(mut revisit) = revisit else { return (None, spent) };
        revisit.rel_error = revisit.rel_error.clone() + after.rel_error.clone();
        (Some(Level { after, revisit }), spent)
    }
}

/// 𝒦(d)·e^{shift} from the K_G table (module docs): ½∫ over the cap, in
/// w = √(R² − p²) for d > R (sin ψ dψ = w dw/(d·√(d² − R² + w²))), in ψ
/// for d ≤ R; the table's relative bar added.
fn revisit<T: CheckRule>(
    sigma: &T,
    r: &T,
    after: &SecondHitTable<T>,
    d: &T,
    shift: &T,
    o: &Options,
    with_table_bar: bool,
) -> Outcome<T> {
    let half = d.lit(0.5);
    let e = if d > r {
        let gap = (d.clone() - r.clone()) * (d.clone() + r.clone());
        let f = |w: &T, io: &Options| -> Outcome<T> {
            let reach = (gap.clone() + w.clone() * w.clone()).sqrt();
            let v =
                w.clone() / (d.clone() * reach.clone()) * (shift.clone() - sigma.clone() * reach).exp() * after.eval(w);
            Ok(Estimate::known(v, w.lit(0.0), 1, io.rule))
        };
        let domain = Domain::finite(d.lit(0.0), r.clone()).with_breakpoints(graded_about(&d.lit(0.0), &gap.sqrt(), r));
        integrate_within_pass(f, &domain, o)?
    } else {
        let f = |psi: &T, io: &Options| -> Outcome<T> {
            let p = d.clone() * psi.sin();
            let w = ((r.clone() - p.clone()) * (r.clone() + p)).sqrt();
            let v = psi.sin() * (shift.clone() - sigma.clone() * d.clone() * psi.cos()).exp() * after.eval(&w);
            Ok(Estimate::known(v, w.lit(0.0), 1, io.rule))
        };
        integrate_within_pass(f, &Domain::finite(d.lit(0.0), cap_half_angle(d, r)), o)?
    };
    let table_bar = if with_table_bar { e.value.abs() * after.rel_error.clone() } else { e.value.lit(0.0) };
    let error = e.error.clone() + table_bar;
    Ok(Estimate { error, ..e }.scaled(&half))
}

/// E[Σ_{j<k} hit_j hit_k]·e^{shift} for a sphere whose centre is D from a
/// point light (module docs): Σ over `terms` (those of `orders`, or a
/// beam's fresh path's, [`PairOrders::fresh_terms`]) of (start density *
/// 𝒦 of its level)(D) — with every order 𝒦(D) + a(c₁ * 𝒦)(D) +
/// (C′ * 𝒦)(D) — 𝒦 from the pass's tables without their bar (the caller
/// adds it) or, where they do not reach, by quadrature with its own.
#[allow(clippy::too_many_arguments)]
pub(super) fn pair_sum<T: CheckRule>(
    sigma: &T,
    r: &T,
    a: &T,
    orders: &PairOrders<T>,
    terms: &[(Start, usize)],
    t: &PairTable<T>,
    big_d: &T,
    shift: &T,
    o: &Options,
) -> Outcome<T> {
    let share = Options { abs_tol: o.abs_tol / terms.len() as f64, ..o.clone() };
    let mut total = Estimate::known(big_d.lit(0.0), big_d.lit(0.0), 0, o.rule);
    for &(start, level) in terms {
        let level = &t.levels[level];
        let radial = |d: &T, io: &Options| -> Result<Radial<T>, Failure<T>> {
            if let Some(k) = from_table(&level.revisit, sigma, r, d) {
                return Ok(Radial { rel: d.lit(0.0), ..k });
            }
            let reach = (d.clone() - r.clone()).max_of(d.lit(0.0));
            let io = Options { abs_tol: 0.0, ..io.clone() };
            let e = revisit(sigma, r, &level.after, d, &(sigma.clone() * reach.clone()), &io, true)?;
            let rel = e.error.clone() / e.value.clone().abs();
            Ok(Radial { reach, rest: e.value, rel })
        };
        let term = match start {
            Start::Light => {
                let own = radial(big_d, &share)?;
                let v = (shift.clone() - sigma.clone() * own.reach).exp() * own.rest;
                Estimate::known(v.clone(), v.abs() * own.rel, 1, o.rule)
            }
            Start::FirstInteraction => c1_convolved(sigma, r, big_d, shift, &radial, &share)?.scaled(a),
            Start::Beyond(i) => {
                convolved(&orders.densities[i], t.tails[i].as_ref(), sigma, r, big_d, shift, &radial, &share)?
            }
        };
        total = total.plus(term);
    }
    Ok(total)
}

/// (c₁ * F)(D)·e^{shift} = (σ/(2D))∫₀^∞ d F(d)[E₁(σ|D − d|) − E₁(σ(D + d))] dd
/// (§9.5 with F in place of H), F's relative bar carried into each sample.
fn c1_convolved<T: CheckRule>(
    sigma: &T,
    r: &T,
    big_d: &T,
    shift: &T,
    radial: &RadialFn<'_, T>,
    opts: &Options,
) -> Outcome<T> {
    let f = |d: &T, o: &Options| -> Outcome<T> {
        let near = (big_d.clone() - d.clone()).abs() * sigma.clone();
        if d.is_zero() || near.is_zero() {
            return Ok(Estimate::known(d.lit(0.0), d.lit(0.0), 0, o.rule));
        }
        let far = (big_d.clone() + d.clone()) * sigma.clone();
        let Radial { reach, rest, rel } = radial(d, o)?;
        let base = shift.clone() - sigma.clone() * reach;
        let near_part = (base.clone() - near.clone()).exp() * exp_int_e1_scaled(&near);
        let far_part = (base - far.clone()).exp() * exp_int_e1_scaled(&far);
        let v = d.clone() * rest * (near_part - far_part);
        Ok(Estimate::known(v.clone(), v.abs() * rel, 1, o.rule))
    };
    let mut cuts = vec![big_d.clone(), r.clone()];
    let gap = (big_d.clone() - r.clone()).abs();
    if gap < *r && !gap.is_zero() {
        cuts.extend(graded_about(big_d, &gap, r).into_iter().filter(|c| *c > gap.lit(0.0)));
        cuts.extend(graded_about(r, &gap, r).into_iter().filter(|c| *c > gap.lit(0.0)));
    }
    cuts.extend(graded_about(&big_d.lit(0.0), r, big_d).into_iter().filter(|c| c > r));
    let domain = Domain::semi_infinite(big_d.lit(0.0)).with_breakpoints(cuts).with_decay(sigma.clone());
    let factor = sigma.clone() / (big_d.lit(2.0) * big_d.clone());
    let opts = &Options { abs_tol: (opts.abs_tol / factor.to_f64()).min(f64::MAX), ..opts.clone() };
    Ok(integrate_within_pass(f, &domain, opts)?.scaled(&factor))
}

/// The options the pair tables of the pass with `opts` are built at (the
/// outer goal: [`FiniteField::pair_tables`]).
pub(super) fn pair_table_options(opts: &Options) -> Options {
    Options { rel_tol: (opts.rel_tol * 5.0).min(1e-3), ..opts.clone() }
}

impl<T: CheckRule> FiniteField<T> {
    /// The pair tables of the pass with `opts`.
    fn pair_tables(
        &self,
        tables: &PairTables<T>,
        mean: (&ScatteredTables<T>, &MultipleTables<T>),
        density: &StartDensity<T>,
        orders: &PairOrders<T>,
        opts: &Options,
    ) -> Option<Arc<PairTable<T>>> {
        // The tables of I(D) and (C′ * H)(D) of the same pass (its rule and
        // goal; P's on this field), G's parts where they reach from 0
        // (`cover_pair_distances`; without it they are not asked for).
        let wide = self.pair_reach().is_some();
        let once = if wide { mean.0.for_pass(self, opts) } else { None };
        let more = if wide { mean.1.for_pass(self, density, opts) } else { None };
        // The tables serve the outer goal (the pass's inner goal times the
        // 20 of `integrate_nested`): four tables deep, each at a tenth of
        // the goal before it, the pass's own goal would leave the brackets
        // of G about d = R and d = 0 (~10⁻¹⁰) above the K_G table's samples'.
        let table_opts = pair_table_options(opts);
        tables.passes.get_or_build(&table_opts, || {
            let points = super::scattered_table::light_distance_range(self);
            let beams =
                beams_reach(self, density, &table_opts).map(|reach| (cut_span(self, density, &table_opts), reach));
            let shared = (once.as_deref(), more.as_ref().and_then(|m| m.hits_table()));
            PairTable::build(self, orders, (points, beams), shared, &table_opts)
        })
    }

    /// ∫σe^{−σs}·2(c f)²Σ_lights(Φ/𝓕)E[Σ_{j<k} hit_j hit_k] ds·e^{c₀}: the
    /// same-path pairs of the simulated orders (≥ 2 or every order) in M₂
    /// (module docs), reading (and building) the tables of I(D) and
    /// (C * H)(D), whose evaluations the caller charges. Isotropic media,
    /// point lights and beams (`multiple_beam_pairs`).
    fn multiple_pairs_with(
        &self,
        mean: (&ScatteredTables<T>, &MultipleTables<T>),
        opts: &Options,
    ) -> Result<Estimate<T>, OracleError> {
        let density = self.higher_orders()?;
        let orders = PairOrders::of(density, &self.albedo)?;
        let tables = PairTables::default();
        let beam_tables = BeamPairTables::default();
        let (sigma, r) = (&self.sigma, &self.radius);
        let f = r.lit(1.0) / (r.pi() * r.lit(4.0));
        let what = match density.last_order() {
            None => "finite-sphere same-path pairs of every order",
            Some(_) => "finite-sphere same-path pairs of a finite order",
        };
        let result = self.with_line(|line| {
            line.integral_nested(what, opts, |x, o| {
                // The tables of the scale pass (whose goal is coarser) are
                // those of the primary pass with its rule: built once.
                let tabled = fine_tables(o, opts);
                let Some(t) = self.pair_tables(&tables, mean, density, &orders, &tabled) else {
                    // A spent budget ends a table's build too: say so.
                    let reason = o.budget.exhausted().unwrap_or_else(|| {
                        "the tables of the same-path pairs of orders ≥ 2 could not be built within the goal".into()
                    });
                    return Err(Failure { reason, best_guess: None, error_estimate: None, evaluations: 0 });
                };
                let mut total = Estimate::known(x.lit(0.0), x.lit(0.0), 0, o.rule);
                for (i, light) in self.lights.iter().enumerate() {
                    let p = match light {
                        FiniteLight::Point(p) => p,
                        FiniteLight::Beam(b) => {
                            let share = Options { abs_tol: o.abs_tol / self.lights.len() as f64, ..o.clone() };
                            let along = (&beam_tables, &tabled);
                            let e = self.beam_pairs((b, i), (density, &orders, &t), along, x, &share)?;
                            total = total.plus(e);
                            continue;
                        }
                    };
                    let (big_d, _) = p.distance_to(self, x);
                    let front = self.per_hit_power(2, &p.flux) * f.clone() * f.clone() * x.lit(2.0);
                    let from_pairs = t.pairs.as_ref().and_then(|tab| tab.hits(sigma, r, &big_d, &self.shift));
                    let e = if let Some((v, rel)) = from_pairs {
                        Estimate::known(v.clone(), v.abs() * rel, 1, o.rule)
                    } else {
                        let share = Options {
                            abs_tol: (o.abs_tol / (front.to_f64() * self.lights.len() as f64)).min(f64::MAX),
                            ..o.clone()
                        };
                        let e =
                            pair_sum(sigma, r, &self.albedo, &orders, &orders.terms, &t, &big_d, &self.shift, &share)?;
                        // 𝒦 was read without its bar.
                        let error = e.error.clone() + e.value.abs() * t.revisit_rel();
                        Estimate { error, ..e }
                    };
                    total = total.plus(e.scaled(&front));
                }
                Ok(total)
            })
        });
        beam_tables.charge(tables.passes.charge(result))
    }

    /// The mean of segment 1 (§9.5) and of segments ≥ 2 (§10.2), reading
    /// one set of tables of I(D) and (C * H)(D) per pass: what
    /// [`FiniteField::scattered_mean`] and [`FiniteField::multiple_mean`]
    /// give.
    pub fn every_order_means(&self, opts: &Options) -> Result<(Estimate<T>, Estimate<T>), OracleError> {
        let scattered = ScatteredTables::for_computation(opts);
        let multiple = MultipleTables::for_computation(opts);
        let single = self.scattered_mean_with(&scattered, opts);
        let beyond = self.multiple_mean_with(&multiple, opts);
        Ok((scattered.charge(single)?, multiple.charge(beyond)?))
    }

    /// P = ∫σe^{−σs}⟨𝒞⟩² ds·e^{c₀} and the same-path pairs of M₂ (module
    /// docs) of the simulated orders (≥ 2 or every order; isotropic media,
    /// point lights and beams), reading one set of tables of I(D) and (C * H)(D) per
    /// pass, built by P and charged to it. Call
    /// [`FiniteField::cover_pair_distances`] first, or the pairs build
    /// tables of G's parts of their own.
    pub fn every_order_second_moments(&self, opts: &Options) -> SecondMoments<T> {
        // Their scale passes read the primary passes' tables.
        let scattered = ScatteredTables::for_computation(opts);
        let multiple = MultipleTables::for_computation(opts);
        // A failed P ends it: the pairs alone would give no Var L.
        let p = self.every_order_p_with(&scattered, &multiple, opts)?;
        let pairs = self.multiple_pairs_with((&scattered, &multiple), opts)?;
        // Every table, whichever asked first, charged to P.
        Ok((multiple.charge(scattered.charge(Ok::<_, OracleError>(p)))?, pairs))
    }

    /// P of the simulated orders (⟨𝒞⟩ of segments 0, 1 and ≥ 2: §9.2,
    /// §9.5, §10.2), reading (and building) the tables, whose evaluations
    /// the caller charges.
    fn every_order_p_with(
        &self,
        scattered: &ScatteredTables<T>,
        multiple: &MultipleTables<T>,
        opts: &Options,
    ) -> Result<Estimate<T>, OracleError> {
        let density = self.higher_orders()?;
        let with_bar = |x: &T, _tol: f64, o: &Options| -> Outcome<T> {
            let half = Options { abs_tol: o.abs_tol / 2.0, ..o.clone() };
            let first = self.order1_mean_with_bar(x, scattered, &half)?;
            let mut rest = Estimate::known(x.lit(0.0), x.lit(0.0), 0, o.rule);
            let share = Options { abs_tol: half.abs_tol / self.lights.len() as f64, ..half.clone() };
            for (i, light) in self.lights.iter().enumerate() {
                rest = rest.plus(match light {
                    FiniteLight::Point(p) => p.multiple_moment(self, density, multiple, x, &share)?,
                    FiniteLight::Beam(b) => b.beyond_moment(self, density, multiple.beams(), i, x, &share)?,
                });
            }
            Ok(first.plus(rest))
        };
        let source = crate::model::along::MeanSource::WithBar(&with_bar);
        self.with_line(|line| line.p_single(&source, opts))
    }
}

#[cfg(test)]
#[path = "multiple_pairs_tests.rs"]
mod tests;
