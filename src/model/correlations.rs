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

use super::angular::{Direction, Features, Measure, Pole};
use super::beam_source::ScatteredBeam;
use super::field::{Component, Field, Geometry};
use super::moments::{phase_poles, ray_domain};
use super::scattered::{source_features, Scattered};
use super::OracleError;
use crate::quad::{integrate, integrate_nested, CheckRule, Domain, Estimate, Options, Outcome};
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

/// A light's single-scattered field, as the pair integrals see it.
enum ScatteredLight<'a, T> {
    /// A point light's (`scattered`).
    Point(&'a Scattered<T>),
    /// A beam's, in isotropic media (`beam_angular`).
    Beam(&'a ScatteredBeam<T>),
}

impl<T> Clone for ScatteredLight<'_, T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T> Copy for ScatteredLight<'_, T> {}

impl<T: CheckRule> ScatteredLight<'_, T> {
    /// ∫ g(ϑ) L₁ dω (or / sin ϑ) at s = center + x, times e^{c₀} like
    /// every integral of the field (a beam's is carried times its own c_b).
    fn view_integral(
        &self,
        field: &Field<T>,
        x: &T,
        features: &Features<T>,
        measure: Measure,
        g: &(dyn Fn(&Direction<T>, &Options) -> Outcome<T> + Sync),
        opts: &Options,
    ) -> Outcome<T> {
        let sigma = &field.sigma_ext;
        match self {
            ScatteredLight::Point(sc) => {
                let at = sc.at(x, sigma, &field.sigma_sc);
                at.view_shared(&sc.shared, sigma, &field.phase, features, measure, g, opts)
            }
            ScatteredLight::Beam(beam) => {
                let scale = (field.shift.clone() - beam.shift.clone()).exp();
                if scale.is_zero() {
                    return Ok(Estimate::known(x.lit(0.0), x.lit(0.0), 0, opts.rule));
                }
                let o = Options { abs_tol: (opts.abs_tol / scale.to_f64()).min(f64::MAX), ..opts.clone() };
                let view = beam.view(x, sigma, &field.albedo);
                Ok(view.view_integral(features, measure, g, &o)?.scaled(&scale))
            }
        }
    }
}

/// Exact integral (23) or (24) (appendix), summed over the field's
/// components, with the corrected correlation of [`pointwise`]. Domain:
/// R > 0; uncollided fields. Fails (`OracleError::Unsupported`) when no
/// light reaches the camera ray.
pub fn exact<T: CheckRule>(field: &Field<T>, r: &T, which: Which, opts: &Options) -> Result<Estimate<T>, OracleError> {
    let like = r.clone();
    let mut total: Option<Estimate<T>> = None;
    let terms: Vec<_> = field
        .components
        .iter()
        .flat_map(|c| [true, false].map(|forward| (c, forward)))
        .filter_map(|(c, forward)| first_sphere_range(c, forward, &like).map(|range| (c, forward, range)))
        .collect();
    // A term's failure carries no best guess of the sum when there are several.
    let several = terms.len() + field.scattered.len() + field.scattered_beams.len() > 1;
    let part = |e: OracleError| if several { e.of_a_part() } else { e };
    for (c, forward, (lo, hi)) in terms {
        let lo = lo.max_of(field.x_camera());
        let e = one_term(field, c, r, which, forward, &lo, hi.as_ref(), opts).map_err(part)?;
        total = Some(match total {
            None => e,
            Some(t) => t.plus(e),
        });
    }
    let lights =
        field.scattered.iter().map(ScatteredLight::Point).chain(field.scattered_beams.iter().map(ScatteredLight::Beam));
    for light in lights {
        let e = scattered_term(field, light, r, which, opts).map_err(part)?;
        total = Some(match total {
            None => e,
            Some(t) => t.plus(e),
        });
    }
    total.ok_or_else(|| OracleError::Unsupported("the camera ray meets no light".into()))
}

/// The features of g = f(−μ)²·(separation integral) at one camera-ray
/// point s: near both poles it varies on the angular scale R·min(1, σ)
/// (where T = 2R/sin ϑ meets the decay length) and falls like 1/ϑ beyond;
/// the backward range switches from T to s at sin ϑ = 2R/s; the pair
/// orientation switches at μ = 0.
pub fn pair_features<T: Real>(field: &Field<T>, r: &T, s_abs: &T) -> Features<T> {
    let (plus_phase, minus_phase) = phase_poles(field);
    let (near_0, near_pi) = source_features(&field.phase, r);
    let scale = r.clone() * field.sigma_ext.clone().min_of(r.lit(1.0)) / r.lit(10.0);
    let floor = |phase: Option<T>| Some(phase.map_or(scale.clone(), |p| p.min_of(scale.clone())));
    let two_r = r.lit(2.0) * r.clone();
    let kink = if two_r < *s_abs { vec![(two_r / s_abs.clone()).asin()] } else { Vec::new() };
    Features {
        plus: Pole { floor: floor(plus_phase), marks: Vec::new() },
        minus: Pole { floor: floor(minus_phase), marks: kink },
        equator_jump: true,
        source_near_0: near_0,
        source_near_pi: near_pi,
    }
}

/// One scattered component's part of (23) or (24): outer over the
/// first-met sphere's position s, with weight σ²e^{−σs} (23) or
/// 2σ²e^{−2σs} (24) times K, and inner the angular integral of
/// f(−μ)²·L₁·(separation integral of the orientation sign μ gives).
fn scattered_term<T: CheckRule>(
    field: &Field<T>,
    light: ScatteredLight<'_, T>,
    r: &T,
    which: Which,
    opts: &Options,
) -> Result<Estimate<T>, OracleError> {
    let what = match which {
        Which::Eq23 => "correlation integral (23), single-scattered light",
        Which::Eq24 => "correlation integral (24), single-scattered light",
    };
    let x0 = field.x_camera();
    let domain = match light {
        ScatteredLight::Point(_) => ray_domain(field, &x0, None),
        ScatteredLight::Beam(beam) => ray_domain(field, &x0, None).with_breakpoints(beam.equator_crossings()),
    };
    integrate_nested(|x: &T, inner: &Options| scattered_at(field, light, r, which, x, inner), &domain, opts)
        .map_err(OracleError::quad(what))
}

/// The integrand of [`scattered_term`] at s = center + x: the first-met
/// sphere's weight σ²e^{−σs} (23) or 2σ²e^{−2σs} (24) times K times the
/// angular integral of f(−μ)²·L₁·(separation integral).
fn scattered_at<T: CheckRule>(
    field: &Field<T>,
    light: ScatteredLight<'_, T>,
    r: &T,
    which: Which,
    x: &T,
    inner: &Options,
) -> Outcome<T> {
    let sigma = field.sigma_ext.clone();
    let k = k_factor(field, r) * if which == Which::Eq24 { r.lit(2.0) } else { r.lit(1.0) };
    let two_r = r.lit(2.0) * r.clone();
    let decay = if which == Which::Eq24 { r.lit(2.0) } else { r.lit(1.0) };
    let s_abs = field.s_of(x);
    let outer = k * sigma.clone() * sigma.clone() * (-(decay * sigma.clone() * s_abs.clone())).exp();
    if outer.is_zero() || !(s_abs > x.lit(0.0)) {
        return Ok(Estimate::known(x.lit(0.0), x.lit(0.0), 0, inner.rule));
    }
    let g = |d: &Direction<T>, o: &Options| {
        let f = field.phase_at(&d.mu);
        let f2 = f.clone() * f;
        let forward = d.mu >= d.mu.lit(0.0);
        let j_opts = Options { abs_tol: (o.abs_tol / f2.to_f64()).min(f64::MAX), ..o.clone() };
        let j = separation(&sigma, which, forward, &d.mu, &d.sin, &s_abs, &two_r, &j_opts)?;
        Ok(Estimate::known(f2.clone() * j.value, f2 * j.error, j.evaluations, o.rule))
    };
    let o = Options { abs_tol: (inner.abs_tol / outer.to_f64()).min(f64::MAX), ..inner.clone() };
    let features = pair_features(field, r, &s_abs);
    let e = light.view_integral(field, x, &features, Measure::Solid, &g, &o)?;
    Ok(Estimate::known(outer.clone() * e.value, outer * e.error, e.evaluations, inner.rule))
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
            if outer.is_zero() {
                return Ok(Estimate::known(zero.clone(), zero, 0, inner.rule));
            }
            // The inner tolerance is for outer·J: J's own is abs_tol/|outer|.
            let j_opts = Options { abs_tol: (inner.abs_tol / outer.abs().to_f64()).min(f64::MAX), ..inner.clone() };
            let j = separation(&sigma, which, forward, &l.mu, &l.sin, &field.s_of(x), &two_r, &j_opts)?;
            Ok(Estimate::known(outer.clone() * j.value, outer.abs() * j.error, j.evaluations, inner.rule))
        },
        &ray_domain(field, lo, hi).with_breakpoints(if forward { None } else { reach_kink(field, c, r, lo, hi) }),
        opts,
    )
    .map_err(OracleError::quad(what))
}

/// The separation integral of one pair orientation at the first-met
/// sphere's position `s_first` (absolute s):
/// ∫₀^{t_max} A(t sin ϑ/2R) e^{−rate·t} dt, t_max = T = 2R/sin ϑ forwards,
/// min(T, s_first) backwards (the nearer sphere cannot lie behind the
/// camera), rate = σ(1 + μ) forwards, σ|μ| backwards in (23),
/// −σ(1 − |μ|) backwards in (24) (derivation: `docs/model.md` §5).
///
/// Over the full range [0, T) it is T·J(rate·T), J(β) = ∫₀¹ A(y) e^{−βy} dy,
/// a special function summed as a series with a rigorous truncation bound
/// (`special::overlap_a_laplace`, tested against quadrature), in every pass.
/// Where the series does not apply (large β, or the range cut at s_first),
/// it is integrated with the rule of `inner`, so each pass keeps its own.
#[allow(clippy::too_many_arguments)]
pub fn separation<T: CheckRule>(
    sigma: &T,
    which: Which,
    forward: bool,
    mu: &T,
    sin: &T,
    s_first: &T,
    two_r: &T,
    inner: &Options,
) -> Outcome<T> {
    let zero = mu.lit(0.0);
    let one = mu.lit(1.0);
    let abs_mu = mu.abs();
    let rate = match (which, forward) {
        (_, true) => sigma.clone() * (one.clone() + mu.clone()),
        (Which::Eq23, false) => sigma.clone() * abs_mu,
        (Which::Eq24, false) => -(sigma.clone() * (one - abs_mu)),
    };
    let edge = two_r.clone() / sin.clone();
    let full_range = edge.is_finite() && (forward || edge <= *s_first);
    if full_range {
        if let Some((j, bound)) = overlap_a_laplace(&(rate.clone() * edge.clone())) {
            return Ok(Estimate::known(edge.clone() * j, edge.abs() * bound, 1, inner.rule));
        }
    }
    let mut top = if edge.is_finite() { Some(edge.clone()) } else { None };
    if !forward {
        top = Some(match top {
            Some(t) if t < *s_first => t,
            _ => s_first.clone(),
        });
    }
    let Some(t_max) = top else {
        // sin ϑ = 0 exactly, forwards: A ≡ π/2 on [0, ∞), ∫ = π/(2 rate).
        let value = mu.pi() / (mu.lit(2.0) * rate);
        return Ok(Estimate::known(value, zero, 1, inner.rule));
    };
    if !(t_max > zero) {
        return Ok(Estimate::known(zero.clone(), zero, 0, inner.rule));
    }
    if !edge.is_finite() {
        // sin ϑ = 0 exactly, backwards: ∫₀^{t_max} (π/2) e^{−rate t} dt.
        let half_pi = mu.pi() / mu.lit(2.0);
        let value = if rate.is_zero() {
            half_pi * t_max
        } else {
            half_pi * (mu.lit(1.0) - (-(rate.clone() * t_max)).exp()) / rate
        };
        return Ok(Estimate::known(value, zero, 1, inner.rule));
    }
    // T ∫₀^Y A(y) e^{−βy} dy, Y = t_max/T ≤ 1, β = rate·T, in y = sin ε
    // (ε = π/2 − φ, y = cos φ): T ∫₀^{ε_Y} A(sin ε) cos ε e^{−β sin ε} dε,
    // an entire integrand (the (1 − y)^{3/2} edge of A at y = 1 becomes φ³),
    // with y = sin ε exact near y = 0, where a large β puts the content.
    let beta = rate * edge.clone();
    let y_top = (t_max / edge.clone()).min_of(mu.lit(1.0));
    let eps_top = y_top.asin();
    let half_pi = mu.pi() / mu.lit(2.0);
    let h = |eps: &T| {
        let (sin, cos) = (eps.sin(), eps.cos());
        overlap_a_of_angle(&(half_pi.clone() - eps.clone()), &cos, &sin) * cos * (-(beta.clone() * sin)).exp()
    };
    // For large β the content lies where β sin ε is of order 1: breakpoints
    // at β sin ε = 1, 10, 100.
    let cuts: Vec<T> = if beta > zero {
        [1.0, 10.0, 100.0].iter().map(|k| mu.lit(*k) / beta.clone()).filter(|c| *c < y_top).map(|c| c.asin()).collect()
    } else {
        Vec::new()
    };
    let j_opts = Options { abs_tol: (inner.abs_tol / edge.to_f64()).min(f64::MAX), ..inner.clone().declared() };
    let e = integrate(h, &Domain::finite(zero, eps_top).with_breakpoints(cuts), &j_opts)?;
    Ok(Estimate { value: e.value * edge.clone(), error: e.error * edge, ..e })
}

/// A(cos φ) = φ − sin φ cos φ for φ ∈ [0, π/2], from the angle (no arccos):
/// below φ = 0.1 by its series (2φ − sin 2φ)/2 = Σ_{k≥1} (−1)^{k+1}
/// (2φ)^{2k+1}/(2(2k+1)!), which avoids the cancellation of φ³ against φ.
fn overlap_a_of_angle<T: Real>(phi: &T, sin: &T, cos: &T) -> T {
    if *phi < phi.lit(0.1) {
        let x = phi.clone() * phi.lit(2.0);
        let x2 = x.clone() * x.clone();
        let mut term = x.clone() * x2.clone() / phi.lit(6.0);
        let mut sum = term.clone();
        let mut k = 1.0;
        while term.abs() > sum.abs() * sum.eps() {
            term = -(term * x2.clone()) / phi.lit((2.0 * k + 2.0) * (2.0 * k + 3.0));
            sum = sum + term.clone();
            k += 1.0;
        }
        sum / phi.lit(2.0)
    } else {
        phi.clone() - sin.clone() * cos.clone()
    }
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
    // H̃ of the delta components: Σ f²W/sin ϑ.
    let direct = |x: &T| {
        let mut h = x.lit(0.0);
        for c in &field.components {
            if let Some(l) = c.at(x, &sigma) {
                let f = field.phase_at(&l.mu);
                h = h + f.clone() * f * l.w / l.sin;
            }
        }
        h
    };
    let weight = |x: &T| front.clone() * sigma.clone() * (-(decay.clone() * sigma.clone() * field.s_of(x))).exp();
    let domain = ray_domain(field, &x0, None);
    if !field.is_smooth() {
        return integrate(|x: &T| weight(x) * direct(x), &domain, opts).map(Ok).map_err(OracleError::quad(what));
    }
    // Smooth part of H̃: ∫ f² L₁ /sin ϑ dω = ∫∫ f² L₁ dϑ dφ, in the frame
    // about u, where the 1/sin ϑ is absorbed by the measure.
    let g = |d: &Direction<T>, o: &Options| {
        let f = field.phase_at(&d.mu);
        Ok(Estimate::known(f.clone() * f, d.mu.lit(0.0), 1, o.rule))
    };
    integrate_nested(
        |x: &T, inner: &Options| {
            let w = weight(x);
            if w.is_zero() {
                return Ok(Estimate::known(x.lit(0.0), x.lit(0.0), 0, inner.rule));
            }
            let o = Options { abs_tol: (inner.abs_tol / w.to_f64()).min(f64::MAX), ..inner.clone() };
            let mut e = Estimate::known(x.lit(0.0), x.lit(0.0), 0, inner.rule);
            let lights = field
                .scattered
                .iter()
                .map(ScatteredLight::Point)
                .chain(field.scattered_beams.iter().map(ScatteredLight::Beam));
            for light in lights {
                // The pair integrals' breakpoints, so that Λ is shared with them.
                let features = pair_features(field, r, &field.s_of(x));
                let part = light.view_integral(field, x, &features, Measure::Planar, &g, &o)?;
                e.value = e.value + part.value;
                e.error = e.error + part.error;
                e.evaluations += part.evaluations;
            }
            Ok(Estimate::known(w.clone() * (direct(x) + e.value), w * e.error, e.evaluations + 1, inner.rule))
        },
        &domain,
        opts,
    )
    .map(Ok)
    .map_err(OracleError::quad(what))
}
