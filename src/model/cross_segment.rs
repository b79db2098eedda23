//! The two segments of one path at two spheres, in the small-sphere model:
//! the R → 0 form of the cross-segment terms X₂₃, X₂₄ of single-scattered
//! light (erratum E10, `docs/model.md` §3c). Isotropic media, point lights.
//!
//! The uncollided first segment of a path hits the sphere at s, interacts
//! at x₁ beyond it and scatters; the second segment hits the sphere at s′.
//! The finite-sphere model computes this exactly (`finite::cross_segments`);
//! as R → 0 it grows like ln(1/R) (the second segment's hit chance falls
//! like R²/(4d²) with the distance d from x₁ to the sphere, and
//! ∫ds′ dt/d² diverges logarithmically as x₁ nears the camera line), so the
//! paper's (23), (24), which miss it, are wrong by O(ln(1/R)) against their
//! O(1/R). With the first segment along v₁ = (x(s) − y)/D (D = |x(s) − y|,
//! α its angle to u, d_y the light's distance from the camera line,
//! sin α = d_y/D), x₁ = x(s) + t v₁ at the distance b₁ = t sin α from the
//! camera line and the abscissa z₁ = s + t cos α, the sphere at s′ seen at
//! the angle θ from x₁ (s′ = z₁ + b₁ tan θ, d = b₁/cos θ):
//!
//!   X = K (R⁴/16) ∫₀^∞ ds σ³e^{−σ(D + s)}/(D d_y) · { ∫₀^∞ [E(t) − πŵ₀ 1(σt < 1)] dt/t
//!                                                  + πŵ₀ (¼ + ln(4 sin α/(σR))) },
//!
//!   E(t) = e^{−σt} ∫_{s′ ≥ 0} ŵ(s′) e^{−σ b₁/cos θ} dθ,
//!
//! ŵ the pair's weight over σ²e^{−σs}: e^{−σ max(0, s′ − s)} for C₂₃
//! (K = κ), e^{−σs′} for C₂₄ (K = 2κ), ŵ₀ = ŵ(s); κR⁴ = albedo³𝓕Φ/(16π⁴).
//! The constant ¼ + ln(4 sin α) is the inner region's (x₁ within O(R/sin α)
//! of the sphere at s, where the chord's hit interval, the reach condition
//! and the exact hit chance H of §9.5 enter), derived in closed form in
//! §3c. Deviation from the paper: (23), (24) do not have this term at all.
//!
//! The t-integral is taken in closed form (a Frullani integral per
//! direction θ, [`Route::ClosedInT`]): two levels of quadrature (s, θ)
//! instead of three; the three-level route is kept as its check.

use super::correlations::Which;
use super::field::Field;
use super::moments::ray_domain;
use super::scattered::Scattered;
use super::OracleError;
use crate::quad::{integrate, integrate_nested, integrate_within_pass, CheckRule, Domain, Estimate, Options, Outcome};
use crate::special::exp_int_e1;
use mcrt_scene::Phase;

/// The R → 0 form of X₂₃ (`Which::Eq23`) or X₂₄ (`Which::Eq24`) summed over
/// the field's single-scattered point lights, times e^{c₀} (module docs):
/// what the two segments of one path add to (23), (24) in the small-sphere
/// model. `None` where there is nothing to add (no single-scattered point
/// light). Domain: isotropic media (the Henyey–Greenstein phase function
/// would weigh the angle between the segments: not derived, refused), every
/// light off the camera line (a light on it sends its first segments along
/// the spheres: refused), R > 0 with σR and R/d_y at most [`MAX_SCALE`]
/// for every light (the range the form was checked over: refused beyond).
/// The goal is never looser than 10⁻⁴ relative (below).
///
/// ```
/// use mcrt_noise::model::{correlations::Which, cross_segment::cross_segment, field::Field};
/// use mcrt_noise::quad::Options;
/// use mcrt_noise::Scene;
///
/// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic-order1.toml"))?;
/// let scene = Scene::from_toml_str(&text)?;
/// let field = Field::from_scene(&scene, &1.0f64)?;
/// let opts = Options { max_evals: 1_000_000_000, ..Options::rel(1e-4) };
/// let x23 = cross_segment(&field, &0.1, Which::Eq23, &opts)?.expect("a scattered point light");
/// assert!(x23.value > 0.0 && x23.error < 1e-4 * x23.value);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn cross_segment<T: CheckRule>(
    field: &Field<T>,
    r: &T,
    which: Which,
    opts: &Options,
) -> Result<Option<Estimate<T>>, OracleError> {
    cross_segment_by(field, r, which, opts, Route::ClosedInT)
}

/// How the level in t (the distance from the sphere at s to the
/// scattering point x₁) of [`cross_segment`] is taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Route {
    /// In closed form, the order of the θ- and t-integrals swapped
    /// ([`cross_segment`]'s route: two levels of quadrature, s and θ).
    ClosedInT,
    /// By quadrature, t outside θ (three levels: s, t, θ): the route the
    /// closed form is checked against (`tests`, below).
    QuadratureInT,
}

/// [`cross_segment`] with the t-level taken by `route`. Same domain.
pub fn cross_segment_by<T: CheckRule>(
    field: &Field<T>,
    r: &T,
    which: Which,
    opts: &Options,
    route: Route,
) -> Result<Option<Estimate<T>>, OracleError> {
    if field.scattered.is_empty() && field.scattered_beams.is_empty() {
        return Ok(None);
    }
    if !field.scattered_beams.is_empty() {
        return Err(OracleError::Unsupported(NOT_FOR_BEAMS.into()));
    }
    if field.phase != Phase::Isotropic {
        return Err(OracleError::Unsupported(NOT_ISOTROPIC.into()));
    }
    // Never looser than 10⁻⁴: at 10⁻³ the three nested levels' coarse pass
    // chased its own noise through the whole budget (10⁹ evaluations spent
    // on `point-isotropic-order1` at R = 0.2, where 10⁻⁴ takes 5·10⁷); a
    // tighter goal only narrows the bar.
    let opts = Options { rel_tol: opts.rel_tol.min(1e-4), ..opts.clone() }.declared();
    let mut total: Option<Estimate<T>> = None;
    for sc in &field.scattered {
        if sc.d.is_zero() {
            return Err(OracleError::Unsupported(ON_THE_LINE.into()));
        }
        let (sigma_r, r_over_d) = ((field.sigma_ext.clone() * r.clone()).to_f64(), (r.clone() / sc.d.clone()).to_f64());
        if sigma_r > MAX_SCALE || r_over_d > MAX_SCALE {
            return Err(OracleError::Unsupported(format!(
                "the small-sphere cross-segment terms of (23), (24) (E10) are an R → 0 form, checked against the \
                 exact ones up to σR = {MAX_SCALE} and R = {MAX_SCALE}× a light's distance from the camera line \
                 (docs/model.md §3c); here σR = {sigma_r:.3} (estimator.radius × medium.sigma_ext) and R/d = \
                 {r_over_d:.3} for a light {:.3e} from the camera line",
                sc.d.to_f64()
            )));
        }
        let e = one_light(field, sc, r, which, &opts, route).map_err(OracleError::quad(what(which)))?;
        total = Some(match total {
            None => e,
            Some(t) => t.plus(e),
        });
    }
    Ok(total)
}

/// The largest σR and R/d_y (d_y a light's distance from the camera line)
/// at which the R → 0 form is used: the range over which it was checked
/// against the finite-sphere model's exact terms (`tests/cross_segment.rs`,
/// `docs/model.md` §3c: 19 % of X off at σR = R/d_y = 0.2, the gap of first
/// order in R below).
pub const MAX_SCALE: f64 = 0.2;

/// Why Henyey–Greenstein media get no cross-segment term.
pub const NOT_ISOTROPIC: &str = "the small-sphere cross-segment terms of (23), (24) (E10) are derived for isotropic \
     media only: medium.phase must be isotropic";

/// Why a beam's single-scattered light gets none.
pub const NOT_FOR_BEAMS: &str =
    "the small-sphere cross-segment terms of (23), (24) (E10) are derived for point lights \
     only (a beam's first segments are parallel, its R → 0 form is not derived; the finite-sphere model has them, \
     docs/model.md §9.11)";

/// Why a light on the camera line gets none.
const ON_THE_LINE: &str = "the small-sphere cross-segment terms of (23), (24) (E10) need every point light off the \
     camera line (its first segments would run along the spheres)";

fn what(which: Which) -> &'static str {
    match which {
        Which::Eq23 => "cross-segment term of (23), single-scattered light",
        Which::Eq24 => "cross-segment term of (24), single-scattered light",
    }
}

/// One light's X (module docs), times e^{c₀}: X = I₁ + ln(1/(σR))·I₂, the
/// two integrals independent of R, so that neither their cost nor their
/// relative goals depend on how far X's two parts cancel (they do where R
/// leaves the form's range: at σR = 0.5 X is near 0, and a relative goal of
/// X itself was out of reach).
fn one_light<T: CheckRule>(
    field: &Field<T>,
    sc: &Scattered<T>,
    r: &T,
    which: Which,
    opts: &Options,
    route: Route,
) -> Outcome<T> {
    let like = r;
    let sigma = field.sigma_ext.clone();
    let pi = like.pi();
    let pi4 = pi.clone() * pi.clone() * pi.clone() * pi.clone();
    let pair = if which == Which::Eq24 { like.lit(2.0) } else { like.lit(1.0) };
    let a3 = field.albedo.clone() * field.albedo.clone() * field.albedo.clone();
    // K R⁴/16 · σ³ = pair · albedo³ 𝓕 Φ σ³/(256 π⁴).
    let front = pair * a3 * field.total_flux.clone() * sc.flux.clone() * sigma.clone() * sigma.clone() * sigma.clone()
        / (like.lit(256.0) * pi4);
    let d_y = sc.d.clone();
    let x0 = field.x_camera();
    // The chord at s = center + x: its weight (0 where it underflows or at
    // the camera) and where it runs.
    let chord = |x: &T| -> Option<(T, Sphere<T>)> {
        let s = field.s_of(x);
        let ds = (field.center.clone() - sc.a.clone()) + x.clone();
        let dist = (ds.clone() * ds.clone() + d_y.clone() * d_y.clone()).sqrt();
        // ŵ₀ = e^{−σs} of C₂₄ joins the exponent; the inner integrals are
        // then O(1) (no absolute goal near the floor of values).
        let own = if which == Which::Eq24 { s.clone() } else { like.lit(0.0) };
        let weight = front.clone() * (sc.shift.clone() - sigma.clone() * (dist.clone() + s.clone() + own)).exp()
            / (dist.clone() * d_y.clone());
        if weight.is_zero() || !(s > like.lit(0.0)) {
            return None;
        }
        Some((weight, Sphere { s, sin_a: d_y.clone() / dist.clone(), cos_a: ds / dist, sigma: sigma.clone(), which }))
    };
    let domain = ray_domain(field, &x0, None);
    let half = Options { abs_tol: opts.abs_tol / 2.0, ..opts.clone() };
    let log_r = (like.lit(1.0) / (sigma.clone() * r.clone())).ln();
    let i2_opts = Options { abs_tol: (half.abs_tol / log_r.abs().to_f64().max(1.0)).min(f64::MAX), ..half.clone() };
    let i2 = integrate(|x: &T| chord(x).map_or(like.lit(0.0), |(weight, _)| weight * pi.clone()), &domain, &i2_opts)?;
    // I₁ may cancel to near 0 (σR near 1): its goal is also relative to
    // I₂'s scale, the size of X's parts.
    let scale = i2.value.abs().to_f64() * (log_r.abs().to_f64() + 1.0);
    let i1_opts = Options { abs_tol: half.abs_tol.max(half.rel_tol * scale / 2.0), ..half.clone() };
    let i1 = integrate_nested(
        |x: &T, inner: &Options| {
            let Some((weight, at)) = chord(x) else {
                return Ok(Estimate::known(like.lit(0.0), like.lit(0.0), 0, inner.rule));
            };
            let o = Options { abs_tol: (inner.abs_tol / weight.to_f64()).min(f64::MAX), ..inner.clone() };
            let t_part = match route {
                Route::ClosedInT => at.over_t_closed(&o)?,
                Route::QuadratureInT => at.over_t(&o)?,
            };
            let log = pi.clone() * (like.lit(0.25) + (like.lit(4.0) * at.sin_a.clone()).ln());
            Ok(t_part.plus(Estimate::known(log, like.lit(0.0), 0, inner.rule)).scaled(&weight))
        },
        &domain,
        &i1_opts,
    )?;
    Ok(i1.plus(i2.scaled(&log_r)))
}

/// The first hit at s: where the chord's direction lies.
struct Sphere<T> {
    s: T,
    sin_a: T,
    cos_a: T,
    sigma: T,
    which: Which,
}

impl<T: CheckRule> Sphere<T> {
    /// ∫₀^∞ [E(t) − πŵ₀ 1(σt < 1)] dt/t over ŵ₀, with cuts at 1/σ (where
    /// the subtraction stops), at 10/σ and where x₁ crosses the camera's
    /// plane (z₁ = 0).
    fn over_t(&self, opts: &Options) -> Outcome<T> {
        let like = &self.s;
        let one_over = like.lit(1.0) / self.sigma.clone();
        let mut cuts: Vec<T> = [0, 1].iter().map(|k| one_over.clone() * like.lit(10f64.powi(*k))).collect();
        if self.cos_a < like.lit(0.0) {
            cuts.push(self.s.clone() / (-self.cos_a.clone()));
        }
        let domain = Domain::semi_infinite(like.lit(0.0)).with_decay(self.sigma.clone()).with_breakpoints(cuts);
        integrate_within_pass(
            |t: &T, o: &Options| {
                if t.is_zero() {
                    // A set of measure zero, where (E − πŵ₀)/t is 0/0.
                    return Ok(Estimate::known(like.lit(0.0), like.lit(0.0), 1, o.rule));
                }
                let subtract = self.sigma.clone() * t.clone() < like.lit(1.0);
                let o2 = Options { abs_tol: o.abs_tol * t.to_f64(), ..o.clone() };
                Ok(self.e_minus(t, subtract, &o2)?.scaled(&(like.lit(1.0) / t.clone())))
            },
            &domain,
            // The bracket is O(π) (the log term's scale): a floor of a
            // hundredth of the relative goal of it, so that far-tail t, where
            // E(t) ~ e^{−σt}, is not chased to a relative goal of its own
            // (the coarse pass of the s-level asks for relative goals only).
            &Options { abs_tol: opts.abs_tol.max(opts.rel_tol * std::f64::consts::PI / 100.0), ..opts.clone() },
        )
    }

    /// The same integral as [`Sphere::over_t`], ∫₀^∞ [E(t) − πŵ₀ 1(σt < 1)] dt/t
    /// over ŵ₀, with the t-integral in closed form (the θ-integral outside
    /// it). For a fixed direction θ from x₁ to the sphere at s′, every
    /// length of the path is t times a function of θ: with
    /// k(θ) = cos α + sin α tan θ (s′ = s + t k), the exponent of E is
    /// −σ t c(θ), c = 1 + sin α/cos θ + k⁺ (C₂₃) or 1 + sin α/cos θ + k
    /// (C₂₄), c ≥ 1 + cos α > 0, and s′ ≥ 0 holds for t ≤ T = s/(−k) where
    /// k < 0 (for all t where k ≥ 0). Swapping the two integrals (the
    /// integrand is absolutely integrable in (θ, t): ~σc near t = 0, ~ln c
    /// in θ), the t-integral of each θ is a Frullani integral,
    ///
    ///   ∫₀^∞ [e^{−σct} 1(t < T) − 1(σt < 1)] dt/t = −γ − ln c − E₁(σcT)
    ///
    /// (E₁ only where k < 0; `special::exp_int_e1`, accurate to a few ulps),
    /// so that the bracket is ∫_{−π/2}^{π/2} [−γ − ln c(θ) − E₁(σ c T)] dθ,
    /// one level of quadrature instead of two. It is taken in the halves
    /// θ ≥ 0 and θ ≤ 0, each in its distance φ from ±π/2 (cos θ = sin φ,
    /// tan θ = ±cot φ), where c = 1 + cos α + sin α·cot(φ/2) or
    /// 1 + cos α + sin α·tan(φ/2) (formed so, without cancellation, wherever
    /// k ≥ 0 or for C₂₄), with a cut at the kink k = 0 (the switch of C₂₃'s
    /// weight, and where the reach T becomes finite); ln c is logarithmically
    /// singular at φ = 0, an end of the piece. Domain: s > 0, sin α > 0.
    fn over_t_closed(&self, opts: &Options) -> Outcome<T> {
        let like = &self.s;
        let zero = like.lit(0.0);
        let one = like.lit(1.0);
        let half_pi = like.pi() / like.lit(2.0);
        let gamma = like.euler_gamma();
        // 1 + cos α, from sin²α/(1 − cos α) where it would cancel.
        let one_plus_cos = if self.cos_a >= zero {
            one.clone() + self.cos_a.clone()
        } else {
            self.sin_a.clone() * self.sin_a.clone() / (one.clone() - self.cos_a.clone())
        };
        let half = |sign: f64, o: &Options| -> Outcome<T> {
            // The kink k = 0: cot φ = −sign·cos α/sin α.
            let kink = match (sign > 0.0, self.cos_a < zero) {
                (true, true) => Some((self.sin_a.clone() / (-self.cos_a.clone())).atan()),
                (false, false) if self.cos_a > zero => Some((self.sin_a.clone() / self.cos_a.clone()).atan()),
                _ => None,
            };
            let cuts: Vec<T> = kink.into_iter().filter(|c| *c > zero && *c < half_pi).collect();
            integrate_within_pass(
                |phi: &T, o2: &Options| {
                    let (sin, cos) = (phi.sin(), phi.cos());
                    if !(sin > zero) {
                        // φ = 0: a set of measure zero (c = ∞ there).
                        return Ok(Estimate::known(zero.clone(), zero.clone(), 1, o2.rule));
                    }
                    let k = self.cos_a.clone() + like.lit(sign) * self.sin_a.clone() * cos.clone() / sin.clone();
                    let c = if self.which == Which::Eq24 || k > zero {
                        // (1 ± cos φ)/sin φ = cot(φ/2) or tan(φ/2).
                        let ratio = if sign > 0.0 {
                            (one.clone() + cos) / sin.clone()
                        } else {
                            sin.clone() / (one.clone() + cos)
                        };
                        one_plus_cos.clone() + self.sin_a.clone() * ratio
                    } else {
                        one.clone() + self.sin_a.clone() / sin
                    };
                    let mut v = -(gamma.clone() + c.ln());
                    if k < zero {
                        let x = self.sigma.clone() * c * self.s.clone() / (-k);
                        v = v - exp_int_e1(&x);
                    }
                    Ok(Estimate::known(v, zero.clone(), 1, o2.rule))
                },
                &Domain::finite(zero.clone(), half_pi.clone()).with_breakpoints(cuts),
                o,
            )
        };
        // The bracket is O(π) (the log term's scale): the same floor as
        // `over_t`'s, split between the halves.
        let floor = opts.abs_tol.max(opts.rel_tol * std::f64::consts::PI / 100.0);
        let each = Options { abs_tol: floor / 2.0, ..opts.clone() };
        let up = half(1.0, &each)?;
        let down = half(-1.0, &each)?;
        Ok(up.plus(down))
    }

    /// (E(t) − πŵ₀)/ŵ₀ (`subtract`) or E(t)/ŵ₀: the θ-integral in the halves
    /// θ ≥ 0 and θ ≤ 0, each in its distance φ from ±π/2 (tan θ = ±cot φ,
    /// cos θ = sin φ, exact near the poles, where the decay length is a
    /// sliver of angle σb₁), the subtraction made node by node.
    fn e_minus(&self, t: &T, subtract: bool, opts: &Options) -> Outcome<T> {
        let like = t;
        let zero = like.lit(0.0);
        let half_pi = like.pi() / like.lit(2.0);
        let b1 = t.clone() * self.sin_a.clone();
        let z1 = self.s.clone() + t.clone() * self.cos_a.clone();
        // ŵ(s′)e^{−σ(t + d)}/ŵ₀ = e^{−σ(t + d + (s′ − s)⁺ or (s′ − s))}: the
        // node's value is an exponential (minus 1 when subtracted, by
        // exp_m1, so that it keeps its accuracy where x₁ is next to the
        // sphere and the difference is far below the rounding of 1).
        let w0 = if subtract { like.lit(1.0) } else { zero.clone() };
        // s′ = z₁ + sign·b₁ cot φ ≥ 0 for φ in [lo, π/2] (sign +1) or ...
        let half = |sign: f64, o: &Options| -> Outcome<T> {
            // The valid range of φ (s′ ≥ 0) and the missing part's share.
            let (lo, hi) = if sign > 0.0 {
                if z1 >= zero {
                    (zero.clone(), half_pi.clone())
                } else {
                    (zero.clone(), (b1.clone() / (-z1.clone())).atan())
                }
            } else if z1 > zero {
                ((b1.clone() / z1.clone()).atan(), half_pi.clone())
            } else {
                (half_pi.clone(), half_pi.clone())
            };
            let missing = -(w0.clone() * (half_pi.clone() - (hi.clone() - lo.clone())));
            if !(hi > lo) {
                return Ok(Estimate::known(missing, zero.clone(), 0, o.rule));
            }
            let mut cuts: Vec<T> = [-1, 1]
                .iter()
                .map(|k| (self.sigma.clone() * b1.clone() / like.lit(10f64.powi(*k))).atan())
                .filter(|c| *c > lo && *c < hi)
                .collect();
            // The kink of C₂₃'s weight at s′ = s: φ = π − α above, α below.
            if self.which == Which::Eq23 {
                let kink = match (sign > 0.0, self.cos_a < zero) {
                    (true, true) => Some((self.sin_a.clone() / (-self.cos_a.clone())).atan()),
                    (false, false) => Some((self.sin_a.clone() / self.cos_a.clone()).atan()),
                    _ => None,
                };
                cuts.extend(kink.filter(|c| *c > lo && *c < hi));
            }
            let e = integrate_within_pass(
                |phi: &T, o2: &Options| {
                    let (sin, cos) = (phi.sin(), phi.cos());
                    // s′ − s = t cos α ± b₁ cot φ, formed without s.
                    let beyond = t.clone() * self.cos_a.clone() + like.lit(sign) * b1.clone() * cos / sin.clone();
                    let extra = match self.which {
                        Which::Eq23 => beyond.max_of(zero.clone()),
                        Which::Eq24 => beyond,
                    };
                    let exponent = -(self.sigma.clone() * (t.clone() + b1.clone() / sin + extra));
                    let v = if subtract { exponent.exp_m1() } else { exponent.exp() };
                    Ok(Estimate::known(v, zero.clone(), 1, o2.rule))
                },
                &Domain::finite(lo, hi).with_breakpoints(cuts),
                o,
            )?;
            Ok(e.plus(Estimate::known(missing, zero.clone(), 0, o.rule)))
        };
        let each = Options { abs_tol: opts.abs_tol / 2.0, ..opts.clone() };
        let up = half(1.0, &each)?;
        let down = half(-1.0, &each)?;
        Ok(up.plus(down))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quad::Rule;

    /// The t-level in closed form ([`Sphere::over_t_closed`]) against its
    /// quadrature ([`Sphere::over_t`]), in both rules, for chords ahead of
    /// and behind the light (cos α of both signs, the kink k = 0 in either
    /// half), next to the camera and far from it, for both pairs: equal
    /// within the two bars.
    #[test]
    fn the_closed_t_level_matches_its_quadrature() {
        for which in [Which::Eq23, Which::Eq24] {
            for (s, alpha) in
                [(0.5f64, 0.3f64), (2.0, 2.5), (0.01, 1.2), (5.0, 0.05), (0.3, std::f64::consts::PI - 0.02)]
            {
                for sigma in [1.0f64, 0.3] {
                    let at = Sphere { s, sin_a: alpha.sin(), cos_a: alpha.cos(), sigma, which };
                    for rule in [Rule::TanhSinh, Rule::Check] {
                        let o = Options { rule, ..Options::rel(1e-9) }.declared();
                        let closed = at.over_t_closed(&o).unwrap();
                        let quad = at.over_t(&o).unwrap();
                        let gap = (closed.value - quad.value).abs();
                        assert!(
                            gap <= closed.error + quad.error,
                            "{which:?} s {s} α {alpha} σ {sigma} {rule:?}: closed {closed:?} quadrature {quad:?}"
                        );
                        assert!(closed.error < 1e-8 * closed.value.abs().max(1.0), "{closed:?}");
                    }
                }
            }
        }
    }

    /// X₂₃, X₂₄ on `point-isotropic-order1` at R = 0.01 by the two routes
    /// (each cross-checked by the engine's two passes): equal within the
    /// two bars, the closed route with fewer evaluations.
    #[test]
    fn the_closed_route_matches_the_quadrature_route() {
        let text = include_str!("../../scenes/point-isotropic-order1.toml");
        let scene = mcrt_scene::Scene::from_toml_str(text).unwrap();
        let field = Field::from_scene(&scene, &1.0f64).unwrap();
        for which in [Which::Eq23, Which::Eq24] {
            let o = Options { max_evals: 1_000_000_000, ..Options::rel(1e-5) };
            let closed = cross_segment_by(&field, &0.01, which, &o, Route::ClosedInT).unwrap().unwrap();
            let quad = cross_segment_by(&field, &0.01, which, &o, Route::QuadratureInT).unwrap().unwrap();
            let gap = (closed.value - quad.value).abs();
            assert!(gap <= closed.error + quad.error, "{which:?}: closed {closed:?} quadrature {quad:?}");
            assert!(closed.evaluations < quad.evaluations, "{which:?}: closed {closed:?} quadrature {quad:?}");
        }
    }
}
