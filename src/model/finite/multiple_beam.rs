//! Every scattering order of a beam at any R (isotropic media,
//! `docs/model.md` §10.5): the mean contribution to a sphere of a beam's
//! segments 2, 3, …, n (or all), exact, and their small-sphere limit.
//!
//! A beam's path interacts first at x₁ with the density n(x₁) of §9.8 and,
//! with probability a, scatters there isotropically: the rest of the path
//! is a fresh point source at x₁ of at most n segments (its segment 0 is
//! the beam's segment 1, §9.8's order 1). Its segments 1, 2, … hit the
//! sphere at distance d with G′(d) = G(d) − H(d) of §10.3 (`fresh_hits`:
//! a·I + Σ_{k=2}^{n−1} a^k c_k * H, with every order a·I + C′ * H), so
//!
//!   ⟨𝒞⟩_{2..n}(s) = a (cΦ/𝓕)(4π)^{−1} ∫ n(x₁) G′(|x₁ − x(s)|) d³x₁,
//!
//! §9.8's volume integral with G′ in place of H. G′ decays like e^{−νσd}
//! (every order; e^{−σd} for a finite one), so the shells run out to
//! d_cut = D + (ln(1/goal) + 40)/ν free paths, D the distance from x(s)
//! to the farthest point of the beam's disk; G′ is radially decreasing
//! (so are c₁, every c_m, H and their convolutions), so the shells beyond
//! add at most G′(d_cut)·∫n ≤ G′(d_cut), which is the bar of the cut, and
//! the value is at least (1 − e^{−1})G′(D + 1/σ) (the volume's first free
//! path lies within D + 1/σ), so the cut's share is ~e^{−(ln(1/goal) + 39)}
//! of it wherever x is (with every order; a finite order's c_k carries a
//! factor ~d^{k−3} beside e^{−σd}, up to ~e^{20} at order 9 over the span,
//! so there ~e^{−(ln(1/goal) + 19)}: still far below the goal; the bound
//! itself is in the bar either way) — also far down a beam that runs beside the camera
//! ray, where most of the value comes from the disk, not from the nearest
//! part of the beam. G′ is read from tables that reach d_cut over the
//! camera ray's table range (D is convex along the ray, largest at an
//! end); the integral itself is tabled along the camera ray per pass as
//! order 1's is (`scattered_beam`).
//!
//! As R → 0, H(d) → (πR²/σ)c₁(d), so the fresh path's segment k's hits tend
//! to (πR²/σ)a^k c_{k+1}(d): the small-sphere ⟨𝒞⟩ of segments 2..n is
//! a(Φ/(4πσ)) ∫ n(x₁) C(|x₁ − x|) d³x₁ with C = Σ_{m=2}^{n} a^m c_m (the
//! start density of a point light's segments 2..n), d²C(d) = σ²d·ρ₁(σd),
//! ρ₁ = r C at σ = 1 (`start_density`).

use super::beam::BeamLight;
use super::fresh_hits::FreshHits;
use super::multiple::TailTable;
use super::scattered_beam::along_ray_cuts;
use super::start_density::StartDensity;
use super::{FiniteField, FiniteLight, OncePerPass};
use crate::model::beam_source::{ShellFactor, Shells};
use crate::model::chebyshev::{sample_options, Piecewise};
use crate::quad::{decay_lengths, CheckRule, Estimate, Failure, Options, Outcome};
use std::sync::Arc;

/// Free paths (in units of 1/(νσ)) the shells run beyond the farthest
/// point of the beam's disk besides ln(1/goal): G′ there is below ~e^{−39}
/// of the goal times the value with every order, ~e^{−19} at order 9
/// (module docs).
const CUT_MARGIN: f64 = 40.0;

/// Goals finer than this get no tables (MPFR): every order is f64 only.
const FINEST_GOAL: f64 = 1e-13;

/// Which limit a beam's table of orders ≥ 2 is of.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum BeamLimit {
    /// Exact at the scene's R (G′).
    Exact,
    /// The small-sphere limit R → 0 (C).
    SmallSphere,
}

/// One beam's along-ray table and its shift, or why it could not be built.
type BeamTable<T> = Result<(Piecewise<T>, T), String>;

/// One volume integral per beam tabled along the camera ray for one pass:
/// the beams' means of orders ≥ 2, exact or in the small-sphere limit, or
/// their same-path pairs of every order (`multiple_beam_pairs`, §10.6).
pub(super) struct AlongRay<T> {
    /// Per light in scene order: the beam's interpolant of its volume
    /// integral times e^{shift} and that shift, or why it could not be
    /// built (`None` for a point light).
    tables: Vec<Option<BeamTable<T>>>,
    lo: T,
    hi: T,
    /// A bar relative to every value (that of the tables the volume
    /// integrals read).
    rel: T,
}

/// The along-ray tables of the beams' orders ≥ 2 of one pass.
type BeamBeyond<T> = AlongRay<T>;

/// The beams' tables of orders ≥ 2 of one computation, one per pass.
pub(super) struct BeamBeyondTables<T> {
    limit: BeamLimit,
    passes: OncePerPass<BeamBeyond<T>>,
    /// A cap on the goal a pass's tables are built at (none coarser), if
    /// set (`once_per_pass::capped_tables`).
    finest: Option<f64>,
}

impl<T> BeamBeyondTables<T> {
    /// No table yet, of the `limit` given.
    pub(super) fn new(limit: BeamLimit) -> Self {
        BeamBeyondTables { limit, passes: OncePerPass::default(), finest: None }
    }

    /// These tables built at goals no coarser than `finest`.
    pub(super) fn finest(self, finest: Option<f64>) -> Self {
        BeamBeyondTables { finest, ..self }
    }
}

impl<T: CheckRule> BeamBeyondTables<T> {
    /// The tables of the pass with `opts`.
    fn for_pass(&self, ff: &FiniteField<T>, density: &StartDensity<T>, opts: &Options) -> Option<Arc<BeamBeyond<T>>> {
        let opts = &crate::model::once_per_pass::capped_tables(opts, self.finest);
        self.passes.get_or_build(opts, || build_beyond(ff, density, self.limit, opts))
    }

    /// `result` with every table's evaluations added.
    pub(super) fn charge<E>(&self, result: Result<Estimate<T>, E>) -> Result<Estimate<T>, E> {
        self.passes.charge(result)
    }
}

/// The rate (in units of σ) G′ and C decay at: ν with every order, 1 for
/// a finite one.
pub(super) fn decay_rate<T: CheckRule>(density: &StartDensity<T>) -> T {
    match density.last_order() {
        None => density.decay(),
        Some(_) => density.mass().lit(1.0),
    }
}

/// (ln(1/goal) + [`CUT_MARGIN`])/(νσ): how far beyond the farthest point of
/// the beam's disk the shells run.
pub(super) fn cut_span<T: CheckRule>(ff: &FiniteField<T>, density: &StartDensity<T>, opts: &Options) -> T {
    let free_paths = (1.0 / opts.rel_tol).ln() + CUT_MARGIN;
    ff.sigma.lit(free_paths) / (decay_rate(density) * ff.sigma.clone())
}

/// The along-ray range of the beams' tables and its cuts: the table range
/// ([`FiniteField::table_range`], [`along_ray_cuts`]) widened to where the
/// camera ray's weight σe^{−σs} is below e^{−256} of e^{−c₀} (s ≥ (c₀ +
/// 256)/σ), with cuts every 4^k/σ from the old end: beyond the range the
/// values are bounded without their distance (each later segment hits at
/// most once), times e^{c₀}, so the range must reach where that weight has
/// made the bound negligible. A beam 250 free paths from the camera ray
/// (c₀ ≈ 250) has a table range ending 7.5/σ beyond it, where the bound
/// left a bar of 3·10⁻⁴ of the value.
fn beams_range<T: CheckRule>(ff: &FiniteField<T>) -> (T, T, Vec<T>) {
    let (lo, hi) = ff.table_range();
    let mut cuts = along_ray_cuts(ff);
    let lengths = decay_lengths(&lo);
    let longest = *lengths.last().expect("non-empty");
    let far = (ff.shift.clone() + lo.lit(longest)) / ff.sigma.clone() - ff.center.clone();
    if far <= hi {
        return (lo, hi, cuts);
    }
    for k in lengths {
        let c = hi.clone() + lo.lit(k) / ff.sigma.clone();
        if c < far {
            cuts.push(c);
        }
    }
    cuts.push(far.clone());
    (lo, far, cuts)
}

/// The start density of a fresh path's segments 2, 3, … (every order, or
/// up to n − 1 where the beam's paths have n scatterings: the segments of
/// the path after the beam's first scattering at x₁ beyond its segments 0
/// and 1, whose hits are H and a·I), `None` at n = 2: given
/// `density`, the start density of a point light's segments 2..=n. One
/// range of orders, not each order apart (`FreshHits` takes either): a
/// single order j ≥ 3 vanishes at r → 0 where its cut integral keeps an
/// absolute error, and its table of (a^j c_j * H) inside a sphere of R =
/// 0.05 could not meet the mean's goals (a bar of 4·10⁻⁷ against 10⁻¹⁰),
/// while a range from order 2 does not vanish there.
fn after_first_scattering<T: CheckRule>(
    density: &StartDensity<T>,
    albedo: &T,
) -> Result<Option<StartDensity<T>>, crate::model::OracleError> {
    match density.last_order() {
        None => Ok(Some(density.clone())),
        Some(n) if n <= 2 => Ok(None),
        Some(n) => StartDensity::new(albedo, 2, Some(n - 1)).map(Some),
    }
}

/// The farthest shell from any camera-ray point of the beams' range
/// ([`beams_range`]) that the volume integrals read: R + the largest
/// distance from an end of the range to the farthest point of a beam's
/// disk (a maximum of distances, convex along the ray, so largest at an
/// end) + [`cut_span`]; `None` without beams.
pub(super) fn beams_reach<T: CheckRule>(ff: &FiniteField<T>, density: &StartDensity<T>, opts: &Options) -> Option<T> {
    let (lo, hi, _) = beams_range(ff);
    let span = cut_span(ff, density, opts);
    let mut reach = None;
    for light in &ff.lights {
        if let FiniteLight::Beam(b) = light {
            for x in [&lo, &hi] {
                let d = b.seen_at(ff, x).farthest_on_disk() + span.clone() + ff.radius.clone();
                reach = Some(reach.map_or(d.clone(), |r: T| r.max_of(d)));
            }
        }
    }
    reach
}

impl<T: CheckRule> AlongRay<T> {
    /// The tables of `ff`'s beams for the pass with `opts`, to a tenth of
    /// its goal (as order 1's), of `volume(beam, x, shift, samples' options)`
    /// — the beam's volume integral at x times e^{shift}, shift = ν_rel
    /// times the beam's path bound (`BeamLight::scattered_shift`; ν_rel =
    /// [`decay_rate`] of `density`) — each value bearing `rel` besides its
    /// table's bar; `None` without beams or at a goal finer than
    /// [`FINEST_GOAL`].
    pub(super) fn build(
        ff: &FiniteField<T>,
        density: &StartDensity<T>,
        rel: T,
        opts: &Options,
        volume: impl Fn(&BeamLight<T>, &T, &T, &Options) -> Outcome<T>,
    ) -> (Option<AlongRay<T>>, u64) {
        let goal = opts.rel_tol / 10.0;
        if goal < FINEST_GOAL || !ff.lights.iter().any(|l| matches!(l, FiniteLight::Beam(_))) {
            return (None, 0);
        }
        let (lo, hi, cuts) = beams_range(ff);
        let samples = sample_options(&lo, goal, opts.rule, &opts.budget);
        let nu_rel = decay_rate(density);
        let mut spent = 0;
        let tables = ff
            .lights
            .iter()
            .map(|light| {
                let FiniteLight::Beam(b) = light else { return None };
                // Its every-order light decays like e^{−νσ·distance}.
                let shift = nu_rel.clone() * b.scattered_shift(ff);
                match Piecewise::build(|x: &T| volume(b, x, &shift, &samples), &cuts, goal) {
                    Ok(t) => {
                        spent += t.evaluations;
                        Some(Ok((t, shift)))
                    }
                    Err(f) => {
                        spent += f.evaluations;
                        Some(Err(f.to_string()))
                    }
                }
            })
            .collect();
        (Some(AlongRay { tables, lo, hi, rel }), spent)
    }

    /// The volume integral of light `index` at x times e^{c₀} and its
    /// relative bar (the table's piece's there, the bar of what it read, and the rounding of
    /// the exponent c₀ − shift); `Ok(None)` beyond the table range, `Err`
    /// with the reason where the light's table could not be built.
    pub(super) fn value(&self, ff: &FiniteField<T>, index: usize, x: &T) -> Result<Option<(T, T)>, String> {
        if *x < self.lo || *x > self.hi {
            return Ok(None);
        }
        let Some(Some(built)) = self.tables.get(index) else { return Ok(None) };
        let (t, shift) = built.as_ref().map_err(|why| format!("the beam's along-ray table failed: {why}"))?;
        let rounding = x.eps() * x.lit(4.0) * (x.lit(1.0) + ff.shift.abs() + shift.abs());
        let rel = t.rel_error_at(x) + self.rel.clone() + rounding;
        Ok(Some((t.eval(x) * (ff.shift.clone() - shift.clone()).exp(), rel)))
    }
}

/// Builds the tables of `ff`'s beams' orders ≥ 2 for the pass with `opts`
/// ([`AlongRay::build`]), or `None` (no beam, a goal finer than
/// [`FINEST_GOAL`], or a table of G′ that could not be built).
fn build_beyond<T: CheckRule>(
    ff: &FiniteField<T>,
    density: &StartDensity<T>,
    limit: BeamLimit,
    opts: &Options,
) -> (Option<BeamBeyond<T>>, u64) {
    if opts.rel_tol / 10.0 < FINEST_GOAL {
        return (None, 0);
    }
    let (sigma, r, a) = (&ff.sigma, &ff.radius, &ff.albedo);
    let span = cut_span(ff, density, opts);
    let Some(reach) = beams_reach(ff, density, opts) else { return (None, 0) };
    let mut spent = 0;
    // G′'s parts beyond a·I in one density (`after_first_scattering`).
    let later = match after_first_scattering(density, a) {
        Ok(later) => later,
        Err(_) => return (None, 0),
    };
    let parts = 1 + later.iter().count();
    let tail_reach = sigma.clone() * reach.clone() * sigma.lit(2.0) + sigma.lit(200.0);
    let mut tails = Vec::new();
    let densities: &[StartDensity<T>] = match (limit, &later) {
        (BeamLimit::Exact, Some(later)) => std::slice::from_ref(later),
        (BeamLimit::Exact, None) => &[],
        (BeamLimit::SmallSphere, _) => std::slice::from_ref(density),
    };
    for d in densities {
        let (tail, used) = TailTable::build(d, &tail_reach, opts);
        spent += used;
        tails.push(tail);
    }
    let fresh = match limit {
        BeamLimit::SmallSphere => None,
        BeamLimit::Exact => {
            let nu = sigma.clone() * decay_rate(density);
            let beyond = densities.iter().zip(&tails).map(|(d, t)| (d, t.as_ref())).collect();
            let (fresh, used) = FreshHits::build((sigma, r, a), (&nu, &reach), parts, None, None, beyond, opts);
            spent += used;
            match fresh {
                Some(f) => Some(f),
                None => return (None, spent),
            }
        }
    };
    let rel = fresh.as_ref().map_or(r.lit(0.0), |f| f.rel_error.clone());
    let volume = |b: &BeamLight<T>, x: &T, shift: &T, samples: &Options| match &fresh {
        Some(fresh) => b.beyond_volume(ff, fresh, parts, &span, x, shift, samples),
        None => b.small_sphere_beyond_volume(ff, density, tails[0].as_ref(), x, shift, samples),
    };
    let (along, used) = AlongRay::build(ff, density, rel, opts, volume);
    (along, spent + used)
}

/// ∫ n(x₁) F(|x₁ − x|) d³x₁·e^{shift} over the shells about the point `at`
/// out to `cut` (the caller bounds the rest), F a radial factor read once
/// per shell (`factor`, decaying at `decay`, kinked at R): the kernel
/// d²·σe^{shift − σt}·F(d) of a beam's volume integrals of every order,
/// its mean's (F = G′) and its pairs' (F = 𝒮, `multiple_beam_pairs`).
pub(super) fn shells_to_cut<T: CheckRule>(
    ff: &FiniteField<T>,
    at: &crate::model::beam_source::BeamPoint<T>,
    (factor, decay): (&crate::model::beam_source::ShellFactorFn<'_, T>, &T),
    (cut, shift): (&T, &T),
    opts: &Options,
) -> Outcome<T> {
    let sigma = &ff.sigma;
    let kernel = |t: &T, d: &T, f: &ShellFactor<T>| {
        d.clone()
            * d.clone()
            * sigma.clone()
            * f.rest.clone()
            * (shift.clone() + f.ln.clone() - sigma.clone() * t.clone()).exp()
    };
    let shells = Shells { knee: Some(&ff.radius), decay: decay.clone(), factor: Some(factor), cut: Some(cut.clone()) };
    at.integral_over_shells(&kernel, &shells, opts, true)
}

impl<T: CheckRule> BeamLight<T> {
    /// ∫ n(x₁) G′(|x₁ − x(s)|) d³x₁·e^{shift} at s = center + x (module
    /// docs), shells out to `span` beyond the farthest point of the disk,
    /// the rest bounded by G′ there with its tables' bar (in the bar).
    #[allow(clippy::too_many_arguments)]
    fn beyond_volume(
        &self,
        ff: &FiniteField<T>,
        fresh: &FreshHits<'_, T>,
        parts: usize,
        span: &T,
        x: &T,
        shift: &T,
        opts: &Options,
    ) -> Outcome<T> {
        let sigma = &ff.sigma;
        let at = self.seen_at(ff, x);
        let cut = at.farthest_on_disk() + span.clone();
        let factor = |d: &T, o: &Options| -> Result<ShellFactor<T>, Failure<T>> {
            let g = fresh.beyond_radial(parts, d, o)?;
            Ok(ShellFactor { ln: -(sigma.clone() * g.reach), rest: g.rest, rel: g.rel })
        };
        let e = shells_to_cut(ff, &at, (&factor, fresh.nu()), (&cut, shift), opts)?;
        let g = fresh.beyond_radial(parts, &cut, opts)?;
        let bar = x.lit(1.0) + g.rel + fresh.rel_error.clone();
        let beyond = g.rest * (shift.clone() - sigma.clone() * g.reach).exp() * bar;
        let error = e.error.clone() + beyond;
        Ok(Estimate { error, ..e })
    }

    /// ∫ n(x₁) C(|x₁ − x(s)|) d³x₁·e^{shift} at s = center + x (module
    /// docs: the small-sphere limit), ρ₁ from `tail`'s radial table where
    /// it serves, else by quadrature.
    fn small_sphere_beyond_volume(
        &self,
        ff: &FiniteField<T>,
        density: &StartDensity<T>,
        tail: Option<&TailTable<T>>,
        x: &T,
        shift: &T,
        opts: &Options,
    ) -> Outcome<T> {
        let sigma = &ff.sigma;
        let factor = |d: &T, o: &Options| -> Result<ShellFactor<T>, Failure<T>> {
            let sd = sigma.clone() * d.clone();
            if let Some((ln, rel)) = tail.and_then(|t| t.ln_radial(&sd)) {
                return Ok(ShellFactor { ln, rest: d.lit(1.0), rel });
            }
            let e = density.radial(&sd, &Options { abs_tol: 0.0, ..o.clone() })?;
            let rel = if e.value.is_zero() { e.error.clone() } else { e.error.clone() / e.value.abs() };
            Ok(ShellFactor { ln: d.lit(0.0), rest: e.value, rel })
        };
        // d²C(d)·σe^{shift − σt} = σ³d·ρ₁(σd)·e^{shift − σt}.
        let kernel = |t: &T, d: &T, f: &ShellFactor<T>| {
            sigma.clone()
                * sigma.clone()
                * sigma.clone()
                * d.clone()
                * f.rest.clone()
                * (shift.clone() + f.ln.clone() - sigma.clone() * t.clone()).exp()
        };
        let decay = sigma.clone() * decay_rate(density);
        let shells = Shells { knee: None, decay, factor: Some(&factor), cut: None };
        self.seen_at(ff, x).integral_over_shells(&kernel, &shells, opts, true)
    }

    /// ⟨𝒞⟩_{2..n}·e^{c₀} at s = center + x, exact at R or its small-sphere
    /// limit (as `tables` are), from the pass's along-ray table (module
    /// docs); beyond the tables' range, where σe^{−σs} has made every
    /// value negligible, 0 with a bound as its bar (each later segment
    /// hits at most once; the small-sphere C has the mass Σ a^m and n is
    /// at most σ/(πa²)); a failure where the table could not be built.
    /// Isotropic media only (the caller's check). Not in the
    /// paper (its §3 leaves the field unspecified; its §3a has no beams).
    pub(super) fn beyond_moment(
        &self,
        ff: &FiniteField<T>,
        density: &StartDensity<T>,
        tables: &BeamBeyondTables<T>,
        index: usize,
        x: &T,
        opts: &Options,
    ) -> Outcome<T> {
        let f = x.lit(1.0) / (x.pi() * x.lit(4.0));
        let front = match tables.limit {
            BeamLimit::Exact => ff.per_hit_power(1, &self.flux) * f * ff.albedo.clone(),
            BeamLimit::SmallSphere => ff.albedo.clone() * self.flux.clone() * f / ff.sigma.clone(),
        };
        let table = tables.for_pass(ff, density, opts);
        let fail = |reason: String| Failure { reason, best_guess: None, error_estimate: None, evaluations: 0 };
        if let Some(t) = &table {
            if let Some((v, rel)) = t.value(ff, index, x).map_err(fail)? {
                let bar = v.abs() * rel;
                return Ok(Estimate::known(v, bar, 1, opts.rule).scaled(&front));
            }
        }
        let most = match tables.limit {
            // The fresh path's later segments hit at most once each.
            BeamLimit::Exact => density.mass() / ff.albedo.clone(),
            // n ≤ σ/(πa²) and ∫C d³x = Σ a^m (each c_m a probability density).
            BeamLimit::SmallSphere => {
                density.mass() * ff.sigma.clone() / (x.pi() * self.radius.clone() * self.radius.clone())
            }
        };
        let bound = most * ff.shift.clone().exp() * front;
        match table {
            // Beyond the table range the camera ray's weight σe^{−σs} makes
            // the bound negligible: carried as the bar.
            Some(_) => Ok(Estimate::known(x.lit(0.0), bound, 0, opts.rule)),
            // A spent budget ends a table's build too: say so.
            None => Err(fail(opts.budget.exhausted().unwrap_or_else(|| {
                // The goal the tables were asked for (the pass's, capped).
                let opts = &crate::model::once_per_pass::capped_tables(opts, tables.finest);
                if opts.rel_tol / 10.0 < FINEST_GOAL {
                    format!(
                        "a beam's scattering orders ≥ 2 need tables to a tenth of the pass's goal {:e}, finer than \
                         f64's {FINEST_GOAL:e} (docs/model.md §10.5)",
                        opts.rel_tol
                    )
                } else {
                    format!(
                        "the tables of a beam's scattering orders ≥ 2 (G′ of docs/model.md §10.5) could not be built \
                         to a tenth of the pass's goal {:e}",
                        opts.rel_tol
                    )
                }
            }))),
        }
    }
}
