//! The kernel of integral (23): the acceptance integral of the quadrature
//! engine and the building block of the correlation integrals.
//!
//! I(ϑ, R) = ∫₀^∞ ∫₀^∞ A(t sin ϑ / (2R)) e^{−t|cos ϑ|} e^{−(s+t)} ds dt
//!
//! (lengths in units of 1/σ_ext). A vanishes for t ≥ T = 2R/sin ϑ, where the
//! integrand has a kink of order 3/2 ((T − t)^{3/2}); [`kernel_integral`]
//! passes T to the engine and declares the structure complete,
//! [`kernel_integral_bare`] hands over the bare integrand and leaves the
//! engine to find the edge itself.

use crate::quad::{integrate, integrate_nested, CheckRule, Domain, Estimate, Failure, Options, Outcome, Structure};
use crate::real::Real;
use crate::special::{overlap_a, overlap_a_laplace};

/// Direction of the forward ray relative to the view direction, given by
/// sin ϑ and |cos ϑ|. Near the poles, pass the small angle to the nearest
/// pole ([`Angle::from_pole`]): in f64, θ = π − 10⁻⁶ carries an absolute
/// error ~2·10⁻¹⁶ in the input itself, i.e. 10⁻¹⁰ relative in sin θ.
#[derive(Debug, Clone)]
pub struct Angle<T> {
    /// sin ϑ ≥ 0.
    pub sin: T,
    /// |cos ϑ| ∈ [0, 1].
    pub abs_cos: T,
}

impl<T: Real> Angle<T> {
    /// From ϑ ∈ [0, π].
    pub fn from_theta(theta: &T) -> Self {
        Angle { sin: theta.sin(), abs_cos: theta.cos().abs() }
    }
    /// From the angle δ ≥ 0 to the nearest pole (ϑ = δ or ϑ = π − δ: the
    /// kernel depends on |cos ϑ| only).
    pub fn from_pole(delta: &T) -> Self {
        Angle { sin: delta.sin(), abs_cos: delta.cos() }
    }
}

/// The integrand A(t·k) e^{−(c t + s)} with k = sin ϑ/(2R), c = 1 + |cos ϑ|
/// computed once per integral.
struct Integrand<T> {
    k: T,
    c: T,
}

impl<T: Real> Integrand<T> {
    fn new(angle: &Angle<T>, r: &T) -> Self {
        Integrand { k: angle.sin.clone() / (r.lit(2.0) * r.clone()), c: angle.abs_cos.clone() + r.lit(1.0) }
    }
    fn at(&self, s: &T, t: &T) -> T {
        overlap_a(&(t.clone() * self.k.clone())) * (-(t.clone() * self.c.clone() + s.clone())).exp()
    }
}

/// I(ϑ, R) with its structure given: the inner t-integral ends at the support
/// edge T = 2R/sin ϑ, where the integrand vanishes like (T − t)^{3/2}.
/// Domain: sin ϑ ≥ 0, R > 0.
pub fn kernel_integral<T: CheckRule>(angle: &Angle<T>, r: &T, opts: &Options) -> Outcome<T> {
    let opts = opts.clone().declared();
    // A vanishes for t ≥ T: the inner integral runs over [0, T] only. At
    // the pole itself (sin ϑ = 0) there is no edge: [0, ∞), decaying at
    // rate c = 1 + |cos ϑ|. The outer s-integrand decays like e^{−s}.
    //
    // Near the poles or for large R the edge lies many decay lengths out
    // (T = 2·10⁹⁷ at ϑ = 10⁻¹⁰⁰, R = 10⁻³) and the content of [0, T] sits in
    // its first few 1/c; I tends to A(0)/c = π/(2c) as T → ∞. The inner
    // integral then stops at L = 4·4^K/c (e^{−4^K} < eps², `quad::decay_lengths`:
    // 1024/c in f64, 512 at the poles, shorter than the acceptance case
    // I(10⁻⁶, 10⁻³)'s T = 2000) and the rest is bounded, not sampled: since
    // A ≤ π/2, e^{−s} ∫_L^T A(t/T) e^{−ct} dt ≤ e^{−s} (π/2) e^{−cL}/c ≤ e^{−s} eps⁸,
    // added to the inner bar. (Sampling [0, T] itself printed I = 0 for
    // T = 10⁹⁷, and in MPFR e^{−ct} at t ~ T costs seconds.)
    let (inner_domain, tail_bound) = separation_domain(angle, r);
    let zero = r.lit(0.0);
    let g = Integrand::new(angle, r);
    let inner = |s: &T, inner: &Options| {
        let mut out = integrate(|t: &T| g.at(s, t), &inner_domain, inner)?;
        out.error = out.error + tail_bound.clone() * (-s.clone()).exp();
        Ok(out)
    };
    integrate_nested(inner, &Domain::semi_infinite(zero).with_decay(r.lit(1.0)), &opts)
}

/// The domain of the inner t-integral and the bound on what lies beyond it
/// (see [`kernel_integral`]): [0, T] when the edge T = 2R/sin ϑ lies within
/// L = 4·4^K/c, else [0, L] with the tail bound (π/2)e^{−cL}/c (times e^{−s});
/// [0, ∞) with decay rate c at the pole itself.
fn separation_domain<T: Real>(angle: &Angle<T>, r: &T) -> (Domain<T>, T) {
    let zero = r.lit(0.0);
    let edge = r.lit(2.0) * r.clone() / angle.sin.clone();
    let decay = angle.abs_cos.clone() + r.lit(1.0);
    let last_length = *crate::quad::decay_lengths(r).last().expect("non-empty");
    let cut = r.lit(4.0 * last_length) / decay.clone();
    if !edge.is_finite() {
        (Domain::semi_infinite(zero.clone()).with_decay(decay), zero)
    } else if edge > cut {
        let bound = r.pi() / r.lit(2.0) * (-(decay.clone() * cut.clone())).exp() / decay;
        (Domain::finite(zero, cut), bound)
    } else {
        (Domain::finite(zero.clone(), edge), zero)
    }
}

/// How [`kernel_integral_reduced`] obtained its value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KernelMethod {
    /// The series T·Σₙ (−cT)ⁿ/n! Mₙ with its truncation and rounding bound,
    /// cross-checked by the 1-D quadrature (itself cross-checked by its two rules).
    SeriesCheckedByQuadrature,
    /// The 1-D quadrature alone, cross-checked by its two rules (the series
    /// would cancel more digits than the precision has: cT > 2 in f64, > 64 in MPFR).
    Quadrature,
}

impl KernelMethod {
    /// A line for reports: which pass computed the value and which checked it.
    pub fn describe(self) -> &'static str {
        match self {
            KernelMethod::SeriesCheckedByQuadrature => {
                "series T·Σ(−cT)ⁿ/n!·Mₙ with its bound, cross-checked by 1-D quadrature (tanh-sinh and Gauss-Legendre)"
            }
            KernelMethod::Quadrature => {
                "1-D quadrature, tanh-sinh cross-checked by Gauss-Legendre (cT too large for the series)"
            }
        }
    }
}

/// I(ϑ, R) by the best exact method: what the `kernel` command reports.
///
/// The s-integral of (23)'s kernel is ∫₀^∞ e^{−s} ds = 1 exactly, so
/// I = ∫₀^T A(t/T) e^{−ct} dt = T·∫₀¹ A(x) e^{−cTx} dx (T = 2R/sin ϑ,
/// c = 1 + |cos ϑ|), a 1-D integral. Two independent passes:
/// - the power series of [`crate::special::overlap_a_laplace`] with its
///   rigorous bound, where it converges without cancelling more than the
///   precision affords (cT ≤ 2 in f64, ≤ 64 in MPFR with guard bits);
/// - the 1-D integral by the engine with the structure declared (the
///   (T − t)^{3/2} edge is an end of the domain; beyond 4·4^K decay lengths
///   the rest is bounded analytically, as in [`kernel_integral`]), which
///   cross-checks tanh–sinh by Gauss–Legendre itself.
///
/// The bar is max(e_series, |series − quadrature| + e_quadrature), the
/// engine's rule for a primary and its check; if it exceeds the goal of
/// `opts`, the result is a `Failure`. Where the series does not apply, the
/// quadrature's own cross-checked result is returned.
///
/// Domain: sin ϑ ≥ 0, R > 0. Deviation from the paper: none (the paper
/// gives (23) as a 2-D integral; the s-integral is done analytically). The
/// 2-D engine path stays in [`kernel_integral`] as the engine's benchmark.
pub fn kernel_integral_reduced<T: CheckRule>(
    angle: &Angle<T>,
    r: &T,
    opts: &Options,
) -> Result<(Estimate<T>, KernelMethod), Failure<T>> {
    let opts = opts.clone().declared();
    let (domain, tail_bound) = separation_domain(angle, r);
    let g = Integrand::new(angle, r);
    let zero = r.lit(0.0);
    let mut quad = integrate(|t: &T| g.at(&zero, t), &domain, &opts)?;
    quad.error = quad.error + tail_bound.clone();
    // The series covers the full range [0, T] only (not a cut one).
    let series = match &domain.hi {
        Some(edge) if tail_bound.is_zero() && domain.decay.is_none() => {
            overlap_a_laplace(&(g.c.clone() * edge.clone())).map(|(j, bound)| (edge.clone() * j, edge.clone() * bound))
        }
        _ => None,
    };
    let Some((value, bound)) = series else {
        return Ok((quad, KernelMethod::Quadrature));
    };
    // The series counts as one evaluation, charged like the quadrature's.
    opts.budget.charge(1);
    if let Some(reason) = opts.budget.overrun() {
        let reason = format!("{reason}; the series met its goal only past it");
        return Err(Failure {
            reason,
            best_guess: Some(value),
            error_estimate: Some(bound),
            evaluations: quad.evaluations + 1,
        });
    }
    let diff = (value.clone() - quad.value.clone()).abs();
    let bar = bound.clone().max_of(diff.clone() + quad.error.clone());
    let goal = crate::quad::goal(&value, &opts);
    if bar > goal {
        let reason = if diff > bound.clone() + quad.error.clone() {
            format!(
                "series and quadrature disagree by {:e}: series {:e} ± {:e}, quadrature {:e} ± {:e}",
                diff.to_f64(),
                value.to_f64(),
                bound.to_f64(),
                quad.value.to_f64(),
                quad.error.to_f64()
            )
        } else {
            format!("error bar {:e} above the goal {:e}", bar.to_f64(), goal.to_f64())
        };
        return Err(Failure {
            reason,
            best_guess: Some(value),
            error_estimate: Some(bar),
            evaluations: quad.evaluations,
        });
    }
    let estimate =
        Estimate { value, error: bar, check_value: quad.value.clone(), evaluations: quad.evaluations + 1, ..quad };
    Ok((estimate, KernelMethod::SeriesCheckedByQuadrature))
}

/// I(ϑ, R) as a bare 2-D integrand with no hints (structure unknown).
pub fn kernel_integral_bare<T: CheckRule>(angle: &Angle<T>, r: &T, opts: &Options) -> Outcome<T> {
    let opts = Options { structure: Structure::Unknown, ..opts.clone() };
    let inner_domain = Domain::semi_infinite(r.lit(0.0));
    let g = Integrand::new(angle, r);
    integrate_nested(
        |s: &T, inner: &Options| integrate(|t: &T| g.at(s, t), &inner_domain, inner),
        &Domain::semi_infinite(r.lit(0.0)),
        &opts,
    )
}

/// Quadrature-free reference for I(ϑ, R), to any number of digits.
///
/// The s-integral is 1, and with t = T x (T = 2R/sin ϑ, c = 1 + |cos ϑ|),
/// I = T ∫₀¹ A(x) e^{−cTx} dx = T Σₙ (−cT)ⁿ/n! Mₙ,
/// Mₙ = ∫₀¹ A(x) xⁿ dx = B(n/2 + 1, 3/2)/(n + 1)
/// (from A(x) = 2∫ₓ¹ √(1−y²) dy and an integration by parts), with
/// B(1, 3/2) = 2/3, B(3/2, 3/2) = π/8 and B(a + 1, b) = B(a, b)·a/(a + b).
/// The alternating series is summed at `prec` bits plus the cT/ln 2 bits its
/// terms cancel (cT = 4000 for I(10⁻⁶, 10⁻³): ~6000 bits, well under a second).
#[cfg(feature = "mpfr")]
pub fn kernel_series_reference(sin_theta: &rug::Float, abs_cos: &rug::Float, r: &rug::Float, prec: u32) -> rug::Float {
    use rug::Float;
    let t_edge = Float::with_val(prec, r * 2u32) / sin_theta;
    let ct = Float::with_val(prec, abs_cos + 1u32) * &t_edge;
    let extra = (ct.to_f64() / std::f64::consts::LN_2).ceil() as u32 + 64;
    let (sum, _, _) = crate::special::laplace_sum(&Float::with_val(prec + extra, &ct));
    Float::with_val(prec, sum * t_edge)
}

/// The acceptance cases of the numerical-core issue, with the independent
/// references it gives (20–25 significant digits): (label, ϑ or pole offset
/// δ as decimal, measured from a pole?, R, reference).
pub const ACCEPTANCE_CASES: [(&str, &str, bool, &str, &str); 6] = [
    ("I(1, 1e-3)", "1", false, "1e-3", "1.5828197124289608462e-3"),
    ("I(pi/2, 1e-3)", "pi/2", false, "1e-3", "1.332548290594632370694605e-3"),
    ("I(pi/2, 1e-9)", "pi/2", false, "1e-9", "1.333333332547935170291441e-9"),
    ("I(1e-6, 1e-3)", "1e-6", true, "1e-3", "0.785148163413269578752875"),
    ("I(1e-6, 1e-9)", "1e-6", true, "1e-9", "1.3317639581824350088917e-3"),
    ("I(pi - 1e-6, 1e-9)", "1e-6", true, "1e-9", "1.3317639581824350088917e-3"),
];

/// Parses a decimal (or `pi/2`, `pi`) at `prec` bits.
#[cfg(feature = "mpfr")]
pub fn parse_decimal(text: &str, prec: u32) -> Result<rug::Float, String> {
    use rug::float::Constant;
    use rug::Float;
    match text.trim() {
        "pi" => Ok(Float::with_val(prec, Constant::Pi)),
        "pi/2" => Ok(Float::with_val(prec, Constant::Pi) / 2u32),
        t => Float::parse(t).map(|v| Float::with_val(prec, v)).map_err(|e| format!("{t:?} is not a number: {e}")),
    }
}
