//! Correlations of one forward ray's contributions to two spheres, and their
//! integrals (23), (24), exact and for R → 0 (25), (26). Derivation and the
//! paper's slips: `docs/model.md`.
//!
//! One straight segment with direction v hits spheres at x(s) and x(s + t)
//! when it crosses both projected disks in the plane ⊥ v: their centres are
//! l = t sin ϑ apart, the overlap is 2R² A(l/2R), and the ray must survive
//! the path t|cos ϑ| between them. With the radiance taken at the sphere the
//! ray meets first (x(s) if cos ϑ ≥ 0, x(s + t) if cos ϑ < 0),
//!
//! ⟨𝒞(s)𝒞(s+t)⟩ = K Σ f(−μ)² W A(t sin ϑ / 2R) e^{−σ t |μ|} at the first sphere,
//! K = 2 albedo² 𝓕 / (π² R²).
//!
//! (The paper's (21) has A(t sin ϑ/R), no factor 2 and p = t for cos ϑ < 0.)
//! At t = 0 this gives ⟨𝒞²⟩ back (A(0) = π/2), a check the paper's form fails.
//!
//! Integrals, with the inner t-integral over [0, T), T = 2R/sin ϑ:
//!
//! ```text
//! (23) = K Σ [ ∫_{μ(s)≥0} σ² e^{−σs}  f²W(s) ∫ A e^{−σt(1+μ)} dt ds
//!            + ∫_{μ(p)<0} σ² e^{−σp}  f²W(p) ∫_{t<p} A e^{−σt|μ|} dt dp ]
//! (24) = 2K Σ [ ∫_{μ≥0}   σ² e^{−2σs} f²W ∫ A e^{−σt(1+μ)} dt ds
//!             + ∫_{μ<0}   σ² e^{−2σp} f²W ∫_{t<p} A e^{σt(1−|μ|)} dt dp ]
//! ```
//!
//! For R → 0, ∫₀^T A dt = 4R/(3 sin ϑ), so with H̃(s) = Σ f²W/sin ϑ,
//! (25) ≈ (8 albedo² 𝓕 σ/(3π² R)) ∫ σ e^{−σs} H̃ ds and
//! (26) ≈ (16 albedo² 𝓕 σ/(3π² R)) ∫ σ e^{−2σs} H̃ ds.

use super::field::{Component, Field, Geometry};
use super::moments::ray_domain;
use super::OracleError;
use crate::quad::{integrate, integrate_nested, CheckRule, Domain, Estimate, Options, Rule};
use crate::real::Real;
use crate::special::{overlap_a, overlap_a_laplace};

/// Which correlation integral.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Which {
    /// (23): weight σ² e^{−σ(s+t)}.
    Eq23,
    /// (24): weight 2σ² e^{−σ(2s+t)}.
    Eq24,
}

/// K = 2 albedo² 𝓕/(π² R²).
fn k_factor<T: Real>(field: &Field<T>, r: &T) -> T {
    let pi = r.pi();
    r.lit(2.0) * field.albedo.clone() * field.albedo.clone() * field.total_flux.clone()
        / (pi.clone() * pi * r.clone() * r.clone())
}

/// ⟨𝒞(s)𝒞(s+t)⟩ at one pair of sphere positions (s = field.center + x),
/// paper (21), (22). Domain: t ≥ 0, R > 0. Value K Σ f(−μ)² W A(t sin ϑ/2R)
/// e^{−σ t|μ|}, with μ, W taken at the sphere the ray meets first. Deviations
/// (E2, E3, E5): factor 2 in K (overlap 2R²A), A's argument l/2R, first
/// sphere s + t backwards. At t = 0 it equals ⟨𝒞²⟩(s) (A(0) = π/2), which
/// the tests check.
pub fn pointwise<T: Real>(field: &Field<T>, s: &T, t: &T, r: &T) -> T {
    let k = k_factor(field, r);
    let two_r = r.lit(2.0) * r.clone();
    let far = s.clone() + t.clone();
    let mut sum = s.lit(0.0);
    for c in &field.components {
        for (x, forward) in [(s, true), (&far, false)] {
            let Some(l) = c.at(x, &field.sigma_ext) else { continue };
            if (l.mu >= s.lit(0.0)) != forward {
                continue;
            }
            let f = field.phase_at(&l.mu);
            let overlap = overlap_a(&(t.clone() * l.sin.clone() / two_r.clone()));
            sum = sum + f.clone() * f * l.w * overlap * (-(field.sigma_ext.clone() * t.clone() * l.mu.abs())).exp();
        }
    }
    k * sum
}

/// The s-range of a component where the first-met sphere is the nearer one
/// (μ ≥ 0, `forward` = true) or the farther one (μ < 0).
fn first_sphere_range<T: Real>(c: &Component<T>, forward: bool, like: &T) -> Option<(T, Option<T>)> {
    let (lo, hi) = c.support();
    let (lo, hi) = match &c.geometry {
        Geometry::Point { a, .. } => {
            let a = c.x_of(a);
            if forward {
                (lo.max_of(a.clone()), hi)
            } else {
                let top = a.clone();
                (
                    lo,
                    Some(match hi {
                        Some(h) if h < top => h,
                        _ => top,
                    }),
                )
            }
        }
        Geometry::Beam { mu, .. } => {
            if (mu.clone() >= like.lit(0.0)) != forward {
                return None;
            }
            (lo, hi)
        }
    };
    match &hi {
        Some(h) if !(h.clone() > lo.clone()) => None,
        _ => Some((lo, hi)),
    }
}

/// Exact integral (23) or (24) (appendix), summed over the field's
/// components, with the corrected correlation of [`pointwise`]. Domain:
/// R > 0; uncollided fields. Fails (`OracleError::Unsupported`) when no
/// light reaches the camera ray.
pub fn exact<T: CheckRule>(field: &Field<T>, r: &T, which: Which, opts: &Options) -> Result<Estimate<T>, OracleError> {
    let like = r.clone();
    let mut total: Option<Estimate<T>> = None;
    for c in &field.components {
        for forward in [true, false] {
            let Some((lo, hi)) = first_sphere_range(c, forward, &like) else { continue };
            let lo = lo.max_of(field.x_camera());
            let e = one_term(field, c, r, which, forward, &lo, hi.as_ref(), opts)?;
            total = Some(match total {
                None => e,
                Some(t) => Estimate {
                    value: t.value + e.value,
                    error: t.error + e.error,
                    evaluations: t.evaluations + e.evaluations,
                    check_value: t.check_value + e.check_value,
                    ..t
                },
            });
        }
    }
    total.ok_or_else(|| OracleError::Unsupported("the camera ray meets no light".into()))
}

/// One component, one orientation: outer over the first-met sphere's
/// position, inner over the separation t ∈ [0, T) (and t < p backwards).
#[allow(clippy::too_many_arguments)]
fn one_term<T: CheckRule>(
    field: &Field<T>,
    c: &Component<T>,
    r: &T,
    which: Which,
    forward: bool,
    lo: &T,
    hi: Option<&T>,
    opts: &Options,
) -> Result<Estimate<T>, OracleError> {
    let sigma = field.sigma_ext.clone();
    let k = k_factor(field, r) * if which == Which::Eq24 { r.lit(2.0) } else { r.lit(1.0) };
    let two_r = r.lit(2.0) * r.clone();
    let what = match which {
        Which::Eq23 => "correlation integral (23)",
        Which::Eq24 => "correlation integral (24)",
    };
    integrate_nested(
        |x: &T, inner: &Options| {
            let zero = x.lit(0.0);
            let local = c.at(x, &sigma);
            let Some(l) = local else {
                return Ok(Estimate::known(zero.clone(), zero, 0, inner.rule));
            };
            let f = field.phase_at(&l.mu);
            // Outer weight σ² e^{−σx} (23) or σ² e^{−2σx} (24), times K f² W.
            let decay = if which == Which::Eq24 { x.lit(2.0) } else { x.lit(1.0) };
            let outer = k.clone()
                * sigma.clone()
                * sigma.clone()
                * (-(decay * sigma.clone() * field.s_of(x))).exp()
                * f.clone()
                * f
                * l.w.clone();
            // Inner exponent rate: e^{−rate t}.
            let abs_mu = l.mu.abs();
            let rate = match (which, forward) {
                (Which::Eq23, true) | (Which::Eq24, true) => sigma.clone() * (x.lit(1.0) + l.mu.clone()),
                (Which::Eq23, false) => sigma.clone() * abs_mu,
                (Which::Eq24, false) => -(sigma.clone() * (x.lit(1.0) - abs_mu)),
            };
            let edge = two_r.clone() / l.sin.clone();
            // Primary pass, full separation range [0, T): the inner integral
            // is T·∫₀¹ A(y) e^{−rate·T·y} dy, summed as a series with its own
            // error bound. The check pass (rule Check) keeps quadrature, so
            // the two passes remain independent computations.
            let full_range = edge.is_finite() && (forward || edge <= field.s_of(x));
            if full_range {
                if let Some((j, bound)) = overlap_a_laplace(&(rate.clone() * edge.clone())) {
                    let value = outer.clone() * edge.clone() * j;
                    let error = (outer.clone() * edge.clone()).abs() * bound;
                    return Ok(Estimate::known(value, error, 1, Rule::TanhSinh));
                }
            }
            let mut top = if edge.is_finite() { Some(edge) } else { None };
            if !forward {
                // The nearer sphere s − t must lie at s − t ≥ 0.
                let s_abs = field.s_of(x);
                top = Some(match top {
                    Some(t) if t < s_abs => t,
                    _ => s_abs,
                });
            }
            let scale = l.sin.clone() / two_r.clone();
            let g =
                |t: &T| outer.clone() * overlap_a(&(t.clone() * scale.clone())) * (-(rate.clone() * t.clone())).exp();
            let inner_opts = inner.clone().declared();
            // Where T ≫ 1/rate (sin ϑ → 0), the integrand lives in the first
            // few decay lengths of a long interval: breakpoints at 1, 10, 100,
            // 1000 decay lengths keep every piece's content spread over it
            // (a rule sampling a long piece coarsely would otherwise see only
            // the e^{−rate·t} edge at its start).
            let lengths: Vec<T> = if rate > x.lit(0.0) {
                [1.0, 10.0, 100.0, 1000.0].iter().map(|k| x.lit(*k) / rate.clone()).collect()
            } else {
                Vec::new()
            };
            match top {
                Some(t_max) if t_max > zero => {
                    integrate(g, &Domain::finite(zero, t_max).with_breakpoints(lengths), &inner_opts)
                }
                Some(_) => Ok(Estimate::known(zero.clone(), zero, 0, inner.rule)),
                None => integrate(g, &Domain::semi_infinite(zero).with_decay(rate.clone()), &inner_opts),
            }
        },
        &ray_domain(field, lo, hi).with_breakpoints(if forward { None } else { reach_kink(field, c, r, lo, hi) }),
        opts,
    )
    .map_err(OracleError::quad(what))
}

/// Backwards (μ < 0), the inner range is t < min(p, T(p)), T = 2R/sin ϑ(p):
/// the outer integrand has a kink where p = T(p), i.e. p sin ϑ(p) = 2R.
/// p sin ϑ(p) grows with p on the backward range (for a point light
/// p d/r(p), r decreasing towards a), so the root is found by bisection.
fn reach_kink<T: Real>(field: &Field<T>, c: &Component<T>, r: &T, lo: &T, hi: Option<&T>) -> Option<T> {
    let two_r = r.lit(2.0) * r.clone();
    let hi = hi?.clone();
    // In x: s(x) sin ϑ(x) − 2R.
    let g = |x: &T| -> T {
        let l = c.at(x, &field.sigma_ext).map(|l| l.sin).unwrap_or_else(|| x.lit(0.0));
        field.s_of(x) * l - two_r.clone()
    };
    let (mut a, mut b) = (lo.clone(), hi);
    if !(g(&a) < r.lit(0.0) && g(&b) > r.lit(0.0)) {
        return None;
    }
    for _ in 0..(r.prec() + 8) {
        let m = (a.clone() + b.clone()) / r.lit(2.0);
        if !(m > a && m < b) {
            break;
        }
        if g(&m) < r.lit(0.0) {
            a = m;
        } else {
            b = m;
        }
    }
    Some(b)
}

/// Asymptotic (R → 0) value of (23) or (24), the forms (25), (26), or `Err`
/// with the reason when it does not exist (a component seen along the view
/// direction: sin ϑ ≡ 0, where ∫∫ h dϑ dφ diverges). Deviation: twice the
/// paper's (25), (26) and with albedo² (E6, E7).
pub fn asymptotic<T: CheckRule>(
    field: &Field<T>,
    r: &T,
    which: Which,
    opts: &Options,
) -> Result<Result<Estimate<T>, String>, OracleError> {
    for c in &field.components {
        let on_axis = match &c.geometry {
            Geometry::Point { d, .. } => d.is_zero(),
            Geometry::Beam { sin, .. } => sin.is_zero(),
        };
        if on_axis {
            return Ok(Err("a light is seen exactly along the view direction (sin ϑ ≡ 0): ∫∫ f²F dϑ dφ diverges and the R → 0 form does not exist".into()));
        }
    }
    let sigma = field.sigma_ext.clone();
    let pi = r.pi();
    let (coeff, decay) = match which {
        Which::Eq23 => (r.lit(8.0), r.lit(1.0)),
        Which::Eq24 => (r.lit(16.0), r.lit(2.0)),
    };
    let front = coeff * field.albedo.clone() * field.albedo.clone() * field.total_flux.clone() * sigma.clone()
        / (r.lit(3.0) * pi.clone() * pi * r.clone());
    let x0 = field.x_camera();
    let what = match which {
        Which::Eq23 => "asymptotic (25)",
        Which::Eq24 => "asymptotic (26)",
    };
    integrate(
        |x: &T| {
            let mut h = x.lit(0.0);
            for c in &field.components {
                if let Some(l) = c.at(x, &sigma) {
                    let f = field.phase_at(&l.mu);
                    h = h + f.clone() * f * l.w / l.sin;
                }
            }
            front.clone() * sigma.clone() * (-(decay.clone() * sigma.clone() * field.s_of(x))).exp() * h
        },
        &ray_domain(field, &x0, None),
        opts,
    )
    .map(Ok)
    .map_err(OracleError::quad(what))
}
