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
//! summed over the field's delta components. Spheres lie along the camera ray
//! with density (σ_ext/q) e^{−σ_ext s} and carry the weight q, so every
//! single-sphere sum becomes ∫ … σ_ext e^{−σ_ext s} ds.

use super::field::Field;
use super::OracleError;
use crate::quad::{integrate, integrate_nested, CheckRule, Domain, Estimate, Failure, Options, Rule};
use crate::real::Real;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

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

/// [lo, hi) in x along the camera ray with every component's breakpoints
/// and the attenuation e^{−σ_ext s} declared as the tail's decay.
pub fn ray_domain<T: Real>(field: &Field<T>, lo: &T, hi: Option<&T>) -> Domain<T> {
    let mut d = match hi {
        Some(h) => Domain::finite(lo.clone(), h.clone()),
        None => Domain::semi_infinite(lo.clone()).with_decay(field.sigma_ext.clone()),
    };
    for c in &field.components {
        d = d.with_breakpoints(c.breakpoints());
    }
    d
}

/// ∫₀^∞ σ e^{−σ s} g(s) ds for a plain g.
fn along_ray<T: CheckRule>(
    field: &Field<T>,
    what: &'static str,
    opts: &Options,
    g: impl Fn(&T) -> T,
) -> Result<Estimate<T>, OracleError> {
    let sigma = field.sigma_ext.clone();
    let x0 = field.x_camera();
    integrate(
        |x: &T| sigma.clone() * (-(sigma.clone() * field.s_of(x))).exp() * g(x),
        &ray_domain(field, &x0, None),
        opts,
    )
    .map_err(OracleError::quad(what))
}

/// Mean pixel luminance ⟨⟨L⟩⟩ = ∫ σ e^{−σs} ⟨𝒞⟩(s) ds (paper (15)).
pub fn mean_luminance<T: CheckRule>(field: &Field<T>, opts: &Options) -> Result<Estimate<T>, OracleError> {
    along_ray(field, "mean luminance (15)", opts, |s| mean_contribution(field, s))
}

/// M₂ = ∫ σ e^{−σs} ⟨𝒞²⟩(s) ds, the single-sphere part of (16).
pub fn m2<T: CheckRule>(field: &Field<T>, r: &T, opts: &Options) -> Result<Estimate<T>, OracleError> {
    along_ray(field, "∫⟨𝒞²⟩ of (16)", opts, |s| second_moment(field, s, r))
}

/// P = ∫ σ e^{−σs} ⟨𝒞⟩(s)² ds, the single-sphere part of (17).
pub fn p_single<T: CheckRule>(field: &Field<T>, opts: &Options) -> Result<Estimate<T>, OracleError> {
    along_ray(field, "∫⟨𝒞⟩² of (17)", opts, |s| {
        let m = mean_contribution(field, s);
        m.clone() * m
    })
}

/// Q = ∫∫_{t>0} ⟨𝒞⟩(s)⟨𝒞⟩(s+t) σ² e^{−σ(s+t)} ds dt, the pair part of (17),
/// computed with p = s + t as ∫₀^∞ σ e^{−σp} ⟨𝒞⟩(p) G(p) dp,
/// G(p) = ∫₀^p σ ⟨𝒞⟩(s) ds.
///
/// G is cumulative: rather than integrating from the camera again at every
/// outer node, G(p) = G(p′) + ∫_{p′}^{p} σ⟨𝒞⟩ from the nearest p′ < p already
/// known, whose bar it inherits. The memory is kept per pass (rule and
/// tolerances), so the check pass builds its own G with its own rule and the
/// two passes stay independent.
pub fn q_pair<T: CheckRule>(field: &Field<T>, opts: &Options) -> Result<Estimate<T>, OracleError> {
    let sigma = field.sigma_ext.clone();
    let x0 = field.x_camera();
    // One memory per pass; the passes run side by side, each locks its own.
    let memory: Mutex<HashMap<PassKey, Arc<Mutex<Vec<Known<T>>>>>> = Mutex::new(HashMap::new());
    integrate_nested(
        |p: &T, inner: &Options| {
            let outer = sigma.clone() * (-(sigma.clone() * field.s_of(p))).exp() * mean_contribution(field, p);
            if !(p.clone() > x0.clone()) || outer.is_zero() {
                return Ok(Estimate::known(p.lit(0.0), p.lit(0.0), 0, inner.rule));
            }
            let pass = memory
                .lock()
                .expect("no pass panics while holding the memory")
                .entry(PassKey::of(inner))
                .or_insert_with(|| Arc::new(Mutex::new(vec![Known::start(&x0)])))
                .clone();
            let mut known = pass.lock().expect("no pass panics while holding its memory");
            let g = cumulative(field, &mut known, p, inner)?;
            Ok(Estimate::known(outer.clone() * g.value, outer.abs() * g.error, g.evaluations, inner.rule))
        },
        &ray_domain(field, &x0, None),
        opts,
    )
    .map_err(OracleError::quad("∫∫⟨𝒞⟩⟨𝒞⟩ of (17)"))
}

/// The options of a pass, as a hashable key.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
struct PassKey(Rule, u64, u64);

impl PassKey {
    fn of(o: &Options) -> Self {
        PassKey(o.rule, o.rel_tol.to_bits(), o.abs_tol.to_bits())
    }
}

/// G at a point already computed: value and bar.
#[derive(Debug, Clone)]
struct Known<T> {
    at: T,
    value: T,
    error: T,
}

impl<T: Real> Known<T> {
    fn start(x0: &T) -> Self {
        Known { at: x0.clone(), value: x0.lit(0.0), error: x0.lit(0.0) }
    }
}

/// G(p) from the nearest known point below p (kept sorted), with the short
/// integral's tolerance a thousandth of the inner one so that a chain of many
/// pieces stays within the inner budget.
fn cumulative<T: CheckRule>(
    field: &Field<T>,
    known: &mut Vec<Known<T>>,
    p: &T,
    inner: &Options,
) -> Result<Estimate<T>, Failure<T>> {
    let idx = known.partition_point(|k| k.at <= *p);
    let base = known[idx - 1].clone();
    if base.at == *p {
        return Ok(Estimate::known(base.value, base.error, 0, inner.rule));
    }
    let sigma = field.sigma_ext.clone();
    let short = Options { abs_tol: inner.abs_tol / 1000.0, ..inner.clone() };
    let piece =
        integrate(|s: &T| sigma.clone() * mean_contribution(field, s), &ray_domain(field, &base.at, Some(p)), &short)?;
    let value = base.value + piece.value.clone();
    let error = base.error + piece.error.clone();
    known.insert(idx, Known { at: p.clone(), value: value.clone(), error: error.clone() });
    Ok(Estimate::known(value, error, piece.evaluations, inner.rule))
}
