//! Single-sphere averages over the forward-ray ensemble and the integrals of
//! them along the camera ray (paper (13), (15)–(17), (19), (20); derivation in
//! `docs/model.md`).
//!
//! For a sphere of radius R at x(s), one forward ray (carrying the total flux
//! 𝓕) contributes 𝒞 = albedo·f(−μ)·𝓕/(πR²) when it hits (eq. (5), with
//! σ_sc/σ_ext = albedo). A ray crosses the sphere's projected disk πR² with
//! direction in dω with probability (L/𝓕)·πR²·dω, so
//!
//! - ⟨𝒞⟩(s)  = albedo Σ f(−μ) W           (paper (19), with the albedo it drops)
//! - ⟨𝒞²⟩(s) = albedo² 𝓕/(πR²) Σ f(−μ)² W  (paper (20), likewise)
//!
//! summed over the field's delta components, plus, for single-scattered
//! light, albedo ∫ f(−μ) L₁ dω and albedo² 𝓕/(πR²) ∫ f(−μ)² L₁ dω (angular
//! integrals with bars, `scattered`, `angular`; the integrals along the ray
//! are then nested, and ⟨𝒞⟩₁ comes from a per-pass Chebyshev table).
//! Spheres lie along the camera ray with density (σ_ext/q) e^{−σ_ext s} and
//! carry the weight q, so every single-sphere sum becomes
//! ∫ … σ_ext e^{−σ_ext s} ds.

use super::along::{lowest_quadratic_path, pair_scale_exponent, MeanSource, RayLine};
use super::angular::{Direction, Features, Pole};
use super::chebyshev::{sample_options, Piecewise};
use super::field::{Field, Geometry};
use super::same_path;
use super::scattered::source_features;
use super::OracleError;
use crate::quad::{decay_lengths, CheckRule, Domain, Estimate, Failure, Options, Outcome, Rule};
use crate::real::Real;
use std::sync::Arc;

/// ⟨𝒞⟩ at s = field.center + x: mean contribution of one forward ray to a
/// sphere there, paper (19). Domain: any x (0 where no light reaches).
/// Deviation: carries the albedo σ_sc/σ_ext of (5), which (19) drops (E7).
pub fn mean_contribution<T: Real>(field: &Field<T>, s: &T) -> T {
    let mut sum = s.lit(0.0);
    for c in &field.components {
        if let Some(l) = c.at(s, &field.sigma_ext) {
            sum = sum + field.phase_at(&l.mu) * l.w;
        }
    }
    field.albedo.clone() * sum
}

/// ⟨𝒞²⟩ at s = field.center + x for spheres of radius `r` > 0, paper (20).
/// Deviation: carries albedo² (E7).
pub fn second_moment<T: Real>(field: &Field<T>, s: &T, r: &T) -> T {
    let mut sum = s.lit(0.0);
    for c in &field.components {
        if let Some(l) = c.at(s, &field.sigma_ext) {
            let f = field.phase_at(&l.mu);
            sum = sum + f.clone() * f * l.w;
        }
    }
    field.albedo.clone() * field.albedo.clone() * field.total_flux.clone() * sum / (s.pi() * r.clone() * r.clone())
}

/// The poles of f(−μ) (and f²): a Henyey–Greenstein peak of width 1 − |g|
/// at −μ = 1 (v = −u) for g > 0, at v = +u for g < 0.
pub fn phase_poles<T: Real>(field: &Field<T>) -> (Option<T>, Option<T>) {
    match field.phase {
        mcrt_scene::Phase::HenyeyGreenstein { g } if g > 0.0 => (None, Some(field.sigma_ext.lit(1.0 - g))),
        mcrt_scene::Phase::HenyeyGreenstein { g } if g < 0.0 => (Some(field.sigma_ext.lit(1.0 + g)), None),
        _ => (None, None),
    }
}

/// ∫ L₁ g dω at s = field.center + x, summed over the scattered
/// components (zero for an uncollided field); `opts.abs_tol` is for the sum.
pub fn smooth_part<T: CheckRule>(
    field: &Field<T>,
    x: &T,
    features: &Features<T>,
    g: &(dyn Fn(&Direction<T>, &Options) -> Outcome<T> + Sync),
    opts: &Options,
) -> Outcome<T> {
    let mut total = Estimate::known(x.lit(0.0), x.lit(0.0), 0, opts.rule);
    let share = Options { abs_tol: opts.abs_tol / field.scattered.len().max(1) as f64, ..opts.clone() };
    for sc in &field.scattered {
        let at = sc.at(x, &field.sigma_ext, &field.sigma_sc);
        let e = at.integral(&field.sigma_ext, &field.phase, features, g, &share)?;
        total.value = total.value + e.value;
        total.error = total.error + e.error;
        total.evaluations += e.evaluations;
    }
    Ok(total)
}

/// Σ ∫L₁dω·e^{c_b} over the beams' single-scattered light at s = center + x
/// (isotropic media, where every single-sphere g is a constant times it;
/// zero without such light); `opts.abs_tol` is for the sum.
fn beams_fluence<T: CheckRule>(field: &Field<T>, x: &T, opts: &Options) -> Outcome<T> {
    let mut total = Estimate::known(x.lit(0.0), x.lit(0.0), 0, opts.rule);
    let share = Options { abs_tol: opts.abs_tol / field.scattered_beams.len().max(1) as f64, ..opts.clone() };
    for beam in &field.scattered_beams {
        total = total.plus(beam.fluence(x, &field.sigma_ext, &field.albedo, &share)?);
    }
    Ok(total)
}

/// ∫ L₁ g dω at x for a g that is a function of f(−μ) only (`g_const`,
/// its value in the isotropic medium that beams at order 1 need): the
/// point lights' angular integrals plus the beams' fluence times g.
fn single_sphere_part<T: CheckRule>(
    field: &Field<T>,
    x: &T,
    g: &(dyn Fn(&Direction<T>, &Options) -> Outcome<T> + Sync),
    g_const: T,
    opts: &Options,
) -> Outcome<T> {
    let half = Options { abs_tol: opts.abs_tol / 2.0, ..opts.clone() };
    let points = smooth_part(field, x, &phase_only(field), g, &half)?;
    if field.scattered_beams.is_empty() {
        return Ok(points);
    }
    let scale = (field.shift.clone() - field.beams_shift.clone()).exp();
    let front = g_const * scale;
    let o = Options { abs_tol: (half.abs_tol / front.to_f64()).min(f64::MAX), ..opts.clone() };
    Ok(points.plus(beams_fluence(field, x, &o)?.scaled(&front)))
}

/// Features of a g that is a power of f(−μ) only.
fn phase_only<T: Real>(field: &Field<T>) -> Features<T> {
    let (plus, minus) = phase_poles(field);
    let (near_0, near_pi) = source_features(&field.phase, &field.sigma_ext);
    Features {
        plus: Pole { floor: plus, marks: Vec::new() },
        minus: Pole { floor: minus, marks: Vec::new() },
        equator_jump: false,
        source_near_0: near_0,
        source_near_pi: near_pi,
    }
}

/// ⟨𝒞⟩ at s = field.center + x with its error bar: the uncollided part
/// ([`mean_contribution`]) plus albedo ∫ f(−μ) L₁ dω of the scattered light.
pub fn mean_contribution_estimate<T: CheckRule>(field: &Field<T>, x: &T, opts: &Options) -> Outcome<T> {
    let direct = mean_contribution(field, x);
    let g = |d: &Direction<T>, o: &Options| Ok(Estimate::known(field.phase_at(&d.mu), d.mu.lit(0.0), 1, o.rule));
    let albedo = field.albedo.clone();
    let o = Options { abs_tol: opts.abs_tol / albedo.to_f64(), ..opts.clone() };
    let e = single_sphere_part(field, x, &g, field.phase_at(&x.lit(0.0)), &o)?;
    Ok(Estimate::known(direct + albedo.clone() * e.value, albedo * e.error, e.evaluations + 1, opts.rule))
}

/// ⟨𝒞²⟩ at s = field.center + x with its error bar, one segment per hit
/// (uncollided plus scattered, [`second_moment`]; the same-path double hits
/// are [`m2_same_path`]).
pub fn second_moment_estimate<T: CheckRule>(field: &Field<T>, x: &T, r: &T, opts: &Options) -> Outcome<T> {
    let direct = second_moment(field, x, r);
    let g = |d: &Direction<T>, o: &Options| {
        let f = field.phase_at(&d.mu);
        Ok(Estimate::known(f.clone() * f, d.mu.lit(0.0), 1, o.rule))
    };
    let front =
        field.albedo.clone() * field.albedo.clone() * field.total_flux.clone() / (x.pi() * r.clone() * r.clone());
    let o = Options { abs_tol: opts.abs_tol / front.to_f64(), ..opts.clone() };
    let e = smooth_part(field, x, &phase_only(field), &g, &o)?;
    let mut total =
        Estimate::known(direct + front.clone() * e.value, front.clone() * e.error, e.evaluations + 1, opts.rule);
    if !field.scattered_beams.is_empty() {
        // Isotropic (Field refuses beams at order 1 otherwise): f² times the fluence.
        let f = field.phase_at(&x.lit(0.0));
        // The inner level's tolerance: the mean's and P's table key in the same pass.
        total = total.plus(beams_fluence_tabled(field, x, opts.rel_tol, opts)?.scaled(&(front * f.clone() * f)));
    }
    Ok(total)
}

/// The scattered part of ⟨𝒞⟩ along the camera ray as a piecewise Chebyshev
/// table, built once per (rule, tolerance) and shared (the mean luminance,
/// P and Q need ⟨𝒞⟩ at thousands of points; each value is an angular
/// integral). Covers x from the camera to the last ray breakpoint plus
/// 4^K decay lengths (`table_range`); pieces at the ray breakpoints and 1,
/// 4, 16, … decay lengths. The table interpolates ln c₁, so the attenuated tail
/// keeps its relative accuracy. Each pass builds its own with its own rule, so the passes stay
/// independent.
pub fn scattered_mean_table<T: CheckRule>(
    field: &Field<T>,
    rule: Rule,
    rel_tol: f64,
    budget: &crate::quad::Budget,
) -> Result<Arc<Piecewise<T>>, Failure<T>> {
    along_ray_table(field, &field.tables, |x, o| scattered_mean(field, x, o), &[], rule, rel_tol, budget)
}

/// The beams' single-scattered fluence Σ ∫L₁dω·e^{c_b} along the camera ray
/// (c_b = [`Field::beams_shift`])
/// as the same kind of table as [`scattered_mean_table`], for the M₂ of a
/// beam's order-1 scene (each value a 2-D quadrature, `beam_source`).
fn beams_fluence_table<T: CheckRule>(
    field: &Field<T>,
    rule: Rule,
    rel_tol: f64,
    budget: &crate::quad::Budget,
) -> Result<Arc<Piecewise<T>>, Failure<T>> {
    // The fluence bends like δ ln δ where the ray crosses a beam's surface:
    // pieces graded by decades towards it, so that each sees the
    // singularity a decade off.
    // (The disk's face, crossed inside the beam, likewise.) Outside a thin
    // beam it falls like a line source's, ~1/p: decades about the ray's
    // closest approach to the axis too (`ScatteredBeam::line_source_grading`).
    let width = field.sigma_ext.lit(1e-10) / field.sigma_ext.clone();
    let grading: Vec<T> = field
        .scattered_beams
        .iter()
        .flat_map(|b| {
            let (scale, width) = (b.radius.clone() * b.radius.lit(4.0), width.clone());
            let kinks =
                b.ray_breakpoints().into_iter().flat_map(move |k| super::field::graded_about(&k, &width, &scale));
            kinks.chain(b.line_source_grading(&field.sigma_ext))
        })
        .collect();
    along_ray_table(field, &field.beam_tables, |x, o| beams_fluence(field, x, o), &grading, rule, rel_tol, budget)
}

/// A table of f along the camera ray in `store`, built once per (rule,
/// tolerance) whichever integral asks first, the others waiting for it
/// ([`scattered_mean_table`]; `once_per_pass`).
fn along_ray_table<T: CheckRule>(
    field: &Field<T>,
    store: &super::field::MeanTables<T>,
    f: impl Fn(&T, &Options) -> Outcome<T>,
    grading: &[T],
    rule: Rule,
    rel_tol: f64,
    budget: &crate::quad::Budget,
) -> Result<Arc<Piecewise<T>>, Failure<T>> {
    let built = store.get_or_build_at(rule, rel_tol, || {
        let table = build_along_ray_table(field, f, grading, rule, rel_tol, budget);
        let spent = match &table {
            Ok(t) => t.evaluations,
            Err(e) => e.evaluations,
        };
        (Some(table.map(Arc::new)), spent)
    });
    (*built.expect("every build returns its outcome")).clone()
}

/// The table of [`along_ray_table`], built.
fn build_along_ray_table<T: CheckRule>(
    field: &Field<T>,
    f: impl Fn(&T, &Options) -> Outcome<T>,
    grading: &[T],
    rule: Rule,
    rel_tol: f64,
    budget: &crate::quad::Budget,
) -> Result<Piecewise<T>, Failure<T>> {
    let (lo, end) = table_range(field);
    let mut cuts: Vec<T> =
        ray_domain(field, &lo, None).breakpoints.into_iter().filter(|b| *b > lo && *b < end).collect();
    let last = cuts.iter().cloned().fold(lo.clone(), |m, b| m.max_of(b));
    // The engine's cuts of a decaying tail (the last of them is `end`).
    for k in decay_lengths(&lo) {
        cuts.push(last.clone() + lo.lit(k) / field.sigma_ext.clone());
    }
    cuts.extend(grading.iter().filter(|c| **c > lo && **c < end).cloned());
    cuts.push(lo.clone());
    cuts.push(end);
    let opts = sample_options(&lo, rel_tol, rule, budget);
    Piecewise::build(|x: &T| f(x, &opts), &cuts, rel_tol / 4.0)
}

/// [x_camera, last ray breakpoint + 4^K/σ]: where the table is used, the
/// last of the engine's cuts of a decaying tail (`quad::decay_lengths`);
/// past it the integrand is below anything a goal can see, and the few
/// values needed there are bounded (`scattered_mean_bound`).
fn table_range<T: Real>(field: &Field<T>) -> (T, T) {
    let lo = field.x_camera();
    let last = ray_domain(field, &lo, None).breakpoints.iter().cloned().fold(lo.clone(), |m, b| m.max_of(b));
    let longest = *decay_lengths(&lo).last().expect("non-empty");
    let end = last + lo.lit(longest) / field.sigma_ext.clone();
    (lo, end)
}

/// albedo ∫ f(−μ) L₁ dω at x: the point lights' scattered part of ⟨𝒞⟩
/// (no table; the beams' is [`beams_fluence_tabled`]).
pub(crate) fn scattered_mean<T: CheckRule>(field: &Field<T>, x: &T, opts: &Options) -> Outcome<T> {
    let g = |d: &Direction<T>, o: &Options| Ok(Estimate::known(field.phase_at(&d.mu), d.mu.lit(0.0), 1, o.rule));
    let e = smooth_part(field, x, &phase_only(field), &g, opts)?;
    let albedo = field.albedo.clone();
    Ok(Estimate { value: e.value * albedo.clone(), error: e.error * albedo, ..e })
}

/// ⟨𝒞⟩ at x with the scattered part from the table of the pass (`opts`
/// gives its rule; `table_tol` its tolerance): value and bar (the table's
/// relative error times the scattered part).
pub fn mean_contribution_tabled<T: CheckRule>(field: &Field<T>, x: &T, table_tol: f64, opts: &Options) -> Outcome<T> {
    let direct = mean_contribution(field, x);
    let mut total = Estimate::known(direct, x.lit(0.0), 1, opts.rule);
    if !field.scattered.is_empty() {
        total = total.plus(points_mean_tabled(field, x, table_tol, opts)?);
    }
    if !field.scattered_beams.is_empty() {
        // Isotropic (Field refuses beams at order 1 otherwise): albedo f times the fluence.
        let front = field.albedo.clone() * field.phase_at(&x.lit(0.0));
        total = total.plus(beams_fluence_tabled(field, x, table_tol, opts)?.scaled(&front));
    }
    Ok(total)
}

/// The point lights' part of the scattered ⟨𝒞⟩ at x from the table of the
/// pass ([`mean_contribution_tabled`]).
fn points_mean_tabled<T: CheckRule>(field: &Field<T>, x: &T, table_tol: f64, opts: &Options) -> Outcome<T> {
    let (lo, end) = table_range(field);
    if *x > end {
        // Far out, only the bound: the value is B/2 ± B/2.
        let half = scattered_mean_bound(field, x) / x.lit(2.0);
        return Ok(Estimate::known(half.clone(), half, 1, opts.rule));
    }
    if *x < lo {
        return scattered_mean(field, x, &Options { abs_tol: 0.0, ..opts.clone() });
    }
    let table = scattered_mean_table(field, opts.rule, table_tol, &opts.budget)?;
    let c1 = table.eval(x);
    let error = c1.abs() * table.rel_error.clone();
    Ok(Estimate::known(c1, error, 1, opts.rule))
}

/// Σ of the beams' fluence ∫L₁dω·e^{c₀} at x from the table of the pass
/// (`opts` gives its rule, `table_tol` its tolerance: the mean, M₂ and P
/// of one computation share it), the table's relative error in the bar
/// (with the rounding of the exponent c₀ − c_b of its scale); beyond the
/// table's range B/2 ± B/2 of the bound B
/// ([`super::beam_source::ScatteredBeam::fluence_bound`]).
fn beams_fluence_tabled<T: CheckRule>(field: &Field<T>, x: &T, table_tol: f64, opts: &Options) -> Outcome<T> {
    let scale = (field.shift.clone() - field.beams_shift.clone()).exp();
    let (lo, end) = table_range(field);
    if *x > end {
        // Far out, only the bound: the value is B/2 ± B/2.
        let mut bound = x.lit(0.0);
        for beam in &field.scattered_beams {
            bound = bound + beam.fluence_bound(x, &field.sigma_ext, &field.albedo);
        }
        let half = bound * scale / x.lit(2.0);
        return Ok(Estimate::known(half.clone(), half, 1, opts.rule));
    }
    if *x < lo {
        return Ok(beams_fluence(field, x, &Options { abs_tol: 0.0, ..opts.clone() })?.scaled(&scale));
    }
    let table = beams_fluence_table(field, opts.rule, table_tol, &opts.budget)?;
    let v = table.eval(x) * scale;
    let rounding = x.eps() * x.lit(4.0) * (x.lit(1.0) + field.shift.abs() + field.beams_shift.abs());
    let error = v.abs() * (table.rel_error.clone() + rounding);
    Ok(Estimate::known(v, error, 1, opts.rule))
}

/// An upper bound of the scattered part of ⟨𝒞⟩ at x: every single-scattered
/// path from the light to x is at least r long (triangle inequality), so
/// the single-scattered fluence is at most e^{−σr} times its value without
/// attenuation, σ_sc Φ π/(16 r) (∫ d³y/(|y|²|y − x|²) = π³/r), and
/// ⟨𝒞⟩₁ = albedo ∫ f L₁ dω ≤ albedo·max f·σ_sc Φ π e^{c₀ − σr}/(16 r)
/// (point lights; a beam's, [`super::beam_source::ScatteredBeam::fluence_bound`]).
pub fn scattered_mean_bound<T: Real>(field: &Field<T>, x: &T) -> T {
    let f_max = field.phase_at(&x.lit(1.0)).max_of(field.phase_at(&x.lit(-1.0)));
    let mut sum = x.lit(0.0);
    for sc in &field.scattered {
        let at = sc.at(x, &field.sigma_ext, &field.sigma_sc);
        // at.front = σ_sc Φ e^{c₀ − σr}/(4π r).
        sum = sum + at.front.clone() * x.pi() * x.pi() / x.lit(4.0);
    }
    field.albedo.clone() * f_max * sum
}

/// [lo, hi) in x along the camera ray with every component's breakpoints
/// and the attenuation e^{−σ_ext s} declared as the tail's decay.
pub fn ray_domain<T: Real>(field: &Field<T>, lo: &T, hi: Option<&T>) -> Domain<T> {
    let mut d = match hi {
        Some(h) => Domain::finite(lo.clone(), h.clone()).with_decay(field.sigma_ext.clone()),
        None => Domain::semi_infinite(lo.clone()).with_decay(field.sigma_ext.clone()),
    };
    for c in &field.components {
        d = d.with_breakpoints(c.breakpoints(&field.sigma_ext));
    }
    for sc in &field.scattered {
        d = d.with_breakpoints(sc.ray_breakpoints());
    }
    for beam in &field.scattered_beams {
        d = d.with_breakpoints(beam.ray_breakpoints());
    }
    d
}

/// The camera ray of the small-sphere model, for the integrals of
/// [`super::along`].
fn with_line<T: CheckRule, R>(field: &Field<T>, f: impl FnOnce(&RayLine<'_, T>) -> R) -> R {
    let domain = |lo: &T, hi: Option<&T>| ray_domain(field, lo, hi);
    f(&RayLine {
        sigma: field.sigma_ext.clone(),
        center: field.center.clone(),
        shift: field.shift.clone(),
        pair_scale: pair_scale_exponent(field.sigma_ext.to_f64(), field.shift.to_f64(), quadratic_path(field)),
        domain: &domain,
    })
}

/// A lower bound of s + 2·(light → sphere path) over the camera ray and
/// the lights, for P's and Q's scale ([`pair_scale_exponent`]); `None`
/// with a beam (not formed: no scale).
fn quadratic_path<T: CheckRule>(field: &Field<T>) -> Option<f64> {
    lowest_quadratic_path(field.components.iter().map(|c| match &c.geometry {
        Geometry::Point { a, d } => Some((a.to_f64(), d.to_f64())),
        Geometry::Beam { .. } => None,
    }))
}

/// ⟨𝒞⟩ of the small-sphere model as [`super::along`] takes it, handed to `f`.
fn with_mean<T: CheckRule, R>(field: &Field<T>, f: impl FnOnce(&RayLine<'_, T>, &MeanSource<'_, T>) -> R) -> R {
    let plain = |x: &T| mean_contribution(field, x);
    let tabled = |x: &T, tol: f64, o: &Options| mean_contribution_tabled(field, x, tol, o);
    let source = if field.is_smooth() { MeanSource::WithBar(&tabled) } else { MeanSource::Plain(&plain) };
    with_line(field, |line| f(line, &source))
}

/// Mean pixel luminance ⟨⟨L⟩⟩ = ∫ σ e^{−σs} ⟨𝒞⟩(s) ds (paper (15)).
pub fn mean_luminance<T: CheckRule>(field: &Field<T>, opts: &Options) -> Result<Estimate<T>, OracleError> {
    with_mean(field, |line, mean| line.mean(mean, opts))
}

/// M₂ = ∫ σ e^{−σs} ⟨𝒞²⟩(s) ds, the single-sphere part of (16).
pub fn m2<T: CheckRule>(field: &Field<T>, r: &T, opts: &Options) -> Result<Estimate<T>, OracleError> {
    let what = "∫⟨𝒞²⟩ of (16)";
    with_line(field, |line| {
        if field.is_smooth() {
            line.integral_nested(what, opts, |x, o| second_moment_estimate(field, x, r, o))
        } else {
            line.integral(what, opts, |s| second_moment(field, s, r))
        }
    })
}

/// M₂ₓ = ∫ σ e^{−σs} ⟨𝒞²⟩ₓ(s) ds: the same-path double hits of
/// [`same_path`] (E9), the part of M₂ the paper's (20) misses once forward
/// paths scatter; an exact zero for an uncollided field. Small-sphere limit,
/// O(1/R) against the O(1/R²) of [`m2`].
pub fn m2_same_path<T: CheckRule>(field: &Field<T>, r: &T, opts: &Options) -> Result<Estimate<T>, OracleError> {
    if !field.is_smooth() {
        let zero = r.lit(0.0);
        return Ok(Estimate::known(zero.clone(), zero, 0, opts.rule));
    }
    with_line(field, |line| {
        line.integral_nested("∫⟨𝒞²⟩ₓ, same-path double hits (E9)", opts, |x, o| {
            same_path::second_moment_term(field, x, r, o)
        })
    })
}

/// P = ∫ σ e^{−σs} ⟨𝒞⟩(s)² ds, the single-sphere part of (17) (times
/// e^{c₀}, like every integral of the field: [`RayLine::p_single`]).
pub fn p_single<T: CheckRule>(field: &Field<T>, opts: &Options) -> Result<Estimate<T>, OracleError> {
    with_mean(field, |line, mean| line.p_single(mean, opts))
}

/// Q = ∫∫_{t>0} ⟨𝒞⟩(s)⟨𝒞⟩(s+t) σ² e^{−σ(s+t)} ds dt, the pair part of (17)
/// (times e^{c₀}: [`RayLine::q_pair`]).
pub fn q_pair<T: CheckRule>(field: &Field<T>, opts: &Options) -> Result<Estimate<T>, OracleError> {
    with_mean(field, |line, mean| line.q_pair(mean, opts))
}
