//! Integrals along the camera ray of a single-sphere average ⟨𝒞⟩(s), shared
//! by the small-sphere model ([`super::moments`]) and the finite-sphere one
//! ([`super::finite`]): ∫σe^{−σs}g(s) ds for g = ⟨𝒞⟩, ⟨𝒞²⟩, ⟨𝒞⟩² (paper
//! (15)–(17)) and the pair integral Q of (17).
//!
//! A model hands its ⟨𝒞⟩ either as a plain function (closed forms: every
//! integral is then a plain cross-checked [`integrate`]) or as a value with
//! a bar whose inner work is done by the rule of the pass that asks
//! (tables, angular quadrature: the integrals are then nested, and each
//! pass computes its own).

use super::OracleError;
use crate::quad::{
    integrate, integrate_nested, integrate_within_pass, CheckRule, Domain, Estimate, Failure, Options, Outcome, Rule,
};
use crate::real::Real;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// The camera ray as the integrals need it: σ, the origin of the
/// integration variable (s = center + x), the model's shift c₀ (its ⟨𝒞⟩ is
/// carried as ⟨𝒞⟩·e^{c₀}) and the domain with every breakpoint of the
/// model's ⟨𝒞⟩ between two points (`None`: to ∞, with the decay e^{−σs}
/// declared).
///
/// Every integral is returned times e^{c₀}, the quadratic P and Q too: their
/// integrands are formed as σe^{−σs}⟨𝒞⟩²e^{c₀} = (√(σe^{−σs−c₀})·⟨𝒞⟩e^{c₀})²
/// and σe^{−σp−c₀}·⟨𝒞⟩e^{c₀}·G, never as the square of ⟨𝒞⟩e^{c₀}, which
/// overflows near the foot of a light close to the camera line and far from
/// the camera (e^{c₀}⟨𝒞⟩ ≈ e^{σ(|y − o| − b)} there, where the weight
/// e^{−σs} compensates). And they are integrated times an exact power of
/// two, [`RayLine::pair_scale`], divided back out of the result: P·e^{c₀}
/// is of the order e^{c₀ − σ·min(s + 2·path)} ≈ e^{−c₀}, 10⁻²⁸⁴ at
/// σ·distance ≈ 700, where the engine's underflow floor (~10⁻²⁸⁹) leaves it
/// no relative accuracy; a power of two changes no rounding, so wherever
/// the floor played no part the result is the same to the bit.
pub struct RayLine<'a, T> {
    /// σ = σ_ext (1/length).
    pub sigma: T,
    /// Origin of the integration variable: s = center + x.
    pub center: T,
    /// The model's shift c₀: ⟨𝒞⟩ is passed as ⟨𝒞⟩·e^{c₀}.
    pub shift: T,
    /// The exponent k of the power of two P and Q are integrated times
    /// ([`pair_scale_exponent`], which makes it even; an odd k is used as
    /// k − 1; 0 for none).
    pub pair_scale: i32,
    /// The domain in x from `lo` to `hi` (`None`: ∞, decay σ declared) with
    /// every breakpoint of ⟨𝒞⟩ in between.
    pub domain: &'a (dyn Fn(&T, Option<&T>) -> Domain<T> + Sync),
}

/// ⟨𝒞⟩ at x as a model gives it.
pub enum MeanSource<'a, T> {
    /// A plain value (closed form).
    Plain(&'a (dyn Fn(&T) -> T + Sync)),
    /// A value with a bar, computed with the rule and tolerances of the
    /// options; the f64 is the tolerance of any table behind it.
    WithBar(&'a (dyn Fn(&T, f64, &Options) -> Outcome<T> + Sync)),
}

impl<T: CheckRule> RayLine<'_, T> {
    /// s = center + x.
    pub fn s_of(&self, x: &T) -> T {
        self.center.clone() + x.clone()
    }

    /// The camera, in x.
    pub fn x_camera(&self) -> T {
        -self.center.clone()
    }

    /// σe^{−σs} at x.
    pub fn weight(&self, x: &T) -> T {
        self.sigma.clone() * (-(self.sigma.clone() * self.s_of(x))).exp()
    }

    /// √(σe^{−σs − c₀}) at x, formed as √σ·e^{−(σs + c₀)/2}: the weight of
    /// a quadratic integrand whose two factors each carry e^{c₀} is its
    /// square, applied one factor at a time (e^{−σs − c₀} alone underflows
    /// where ⟨𝒞⟩e^{c₀} is ~10¹⁷², at the foot of a far light near the line).
    /// Times 2^{k/2}, k = [`RayLine::pair_scale`] (exact).
    fn half_weight(&self, x: &T) -> T {
        let half = (self.sigma.clone() * self.s_of(x) + self.shift.clone()) / x.lit(2.0);
        self.sigma.sqrt() * x.powi_like(self.scale_exponent() / 2) * (-half).exp()
    }

    /// The even exponent actually used: 2⌊k/2⌋.
    fn scale_exponent(&self) -> i32 {
        2 * (self.pair_scale / 2)
    }

    /// `opts` for an integral formed times 2^k: its absolute goal scaled
    /// alike (exactly).
    fn scaled_options(&self, opts: &Options) -> Options {
        Options { abs_tol: (opts.abs_tol * 2f64.powi(self.scale_exponent())).min(f64::MAX), ..opts.clone() }
    }

    /// A result formed times 2^k (value, bar, or a failure's best guess),
    /// divided back: exactly, unless it falls below the smallest normal
    /// number, where rounding is absolute, at most half the smallest
    /// subnormal, which the bar gains (and which leaves a normal bar
    /// unchanged). A failure's message still quotes the scaled figures,
    /// and says so.
    fn unscaled(&self, e: Outcome<T>) -> Outcome<T> {
        let k = self.scale_exponent();
        if k == 0 {
            return e;
        }
        let back = |v: T| v.clone() * v.powi_like(-k);
        // The smallest subnormal: 2⁻¹⁰²²·eps (0 in MPFR, whose exponent range is vast).
        let bar = |v: T| back(v.clone()) + v.underflow_floor() * v.eps() * v.eps();
        match e {
            Ok(e) => Ok(Estimate { value: back(e.value), error: bar(e.error), check_value: back(e.check_value), ..e }),
            Err(f) => Err(Failure {
                reason: format!("{} (figures times 2^{k}, the integral's working scale)", f.reason),
                best_guess: f.best_guess.map(back),
                error_estimate: f.error_estimate.map(bar),
                ..f
            }),
        }
    }

    /// ∫₀^∞ σ e^{−σ s} g(s) ds for a plain g.
    pub fn integral(
        &self,
        what: &'static str,
        opts: &Options,
        g: impl Fn(&T) -> T,
    ) -> Result<Estimate<T>, OracleError> {
        integrate(|x: &T| self.weight(x) * g(x), &(self.domain)(&self.x_camera(), None), opts)
            .map_err(OracleError::quad(what))
    }

    /// ∫₀^∞ σ e^{−σ s} g(s) ds for a g that is itself computed with a bar
    /// by the pass's rule, as a nested integral.
    pub fn integral_nested(
        &self,
        what: &'static str,
        opts: &Options,
        g: impl Fn(&T, &Options) -> Outcome<T> + Sync,
    ) -> Result<Estimate<T>, OracleError> {
        integrate_nested(
            |x: &T, inner: &Options| {
                let w = self.weight(x);
                if w.is_zero() {
                    return Ok(Estimate::known(x.lit(0.0), x.lit(0.0), 0, inner.rule));
                }
                let e = g(x, &Options { abs_tol: (inner.abs_tol / w.to_f64()).min(f64::MAX), ..inner.clone() })?;
                Ok(Estimate::known(w.clone() * e.value, w * e.error, e.evaluations, inner.rule))
            },
            &(self.domain)(&self.x_camera(), None),
            opts,
        )
        .map_err(OracleError::quad(what))
    }

    /// ∫σe^{−σs}⟨𝒞⟩ ds (15).
    pub fn mean(&self, mean: &MeanSource<'_, T>, opts: &Options) -> Result<Estimate<T>, OracleError> {
        let what = "mean luminance (15)";
        match mean {
            MeanSource::Plain(m) => self.integral(what, opts, m),
            MeanSource::WithBar(m) => {
                let tol = table_tol(opts);
                self.integral_nested(what, opts, |x, o| m(x, tol.max(o.rel_tol), o))
            }
        }
    }

    /// P = ∫σe^{−σs}⟨𝒞⟩² ds, the single-sphere part of (17), times e^{c₀}
    /// (the integrand as the square of √(σe^{−σs−c₀})·⟨𝒞⟩e^{c₀}).
    pub fn p_single(&self, mean: &MeanSource<'_, T>, opts: &Options) -> Result<Estimate<T>, OracleError> {
        let what = "∫⟨𝒞⟩² of (17)";
        let domain = (self.domain)(&self.x_camera(), None);
        let root = |x: &T| self.half_weight(x);
        let scaled = &self.scaled_options(opts);
        let e = match mean {
            MeanSource::Plain(m) => integrate(
                |x: &T| {
                    let v = root(x) * m(x);
                    v.clone() * v
                },
                &domain,
                scaled,
            ),
            MeanSource::WithBar(m) => {
                let tol = table_tol(opts);
                integrate_nested(
                    |x: &T, o: &Options| {
                        let h = root(x);
                        if h.is_zero() {
                            return Ok(Estimate::known(x.lit(0.0), x.lit(0.0), 0, o.rule));
                        }
                        // The sample (h·m)²'s error is ≈ 2h²|m|·e_m: an absolute
                        // goal for m alone cannot bound it without |m|. Either
                        // m meets its relative goal r (the sample then r-close
                        // twice over) or its absolute one, e_m ≤ a, and then
                        // |m| ≤ a/r, so the sample's error ≤ 2h²a²/r + h²a²;
                        // a = √(r·abs_tol/2)/h keeps that at ≈ abs_tol. (It was
                        // abs_tol/h², 2|m| times too loose: where ⟨𝒞⟩e^{c₀} ≫ 1,
                        // in dense media, P failed with a bar 10⁻⁴ of itself.)
                        let r = o.rel_tol.max(f64::MIN_POSITIVE);
                        let m_abs = ((r * o.abs_tol / 2.0).sqrt() / h.to_f64()).min(f64::MAX);
                        let m = m(x, tol.max(o.rel_tol), &Options { abs_tol: m_abs, ..o.clone() })?;
                        let v = h.clone() * m.value.clone();
                        let e = h * m.error.clone();
                        let error = x.lit(2.0) * v.abs() * e.clone() + e.clone() * e;
                        Ok(Estimate::known(v.clone() * v, error, m.evaluations, o.rule))
                    },
                    &domain,
                    scaled,
                )
            }
        };
        self.unscaled(e).map_err(OracleError::quad(what))
    }

    /// Q = ∫∫_{t>0} ⟨𝒞⟩(s)⟨𝒞⟩(s+t) σ² e^{−σ(s+t)} ds dt, the pair part of
    /// (17), times e^{c₀}, computed with p = s + t as
    /// ∫₀^∞ σ e^{−σp−c₀} ⟨𝒞⟩e^{c₀}(p) G(p) dp, G(p) = ∫₀^p σ ⟨𝒞⟩e^{c₀}(s) ds.
    ///
    /// G is cumulative: rather than integrating from the camera again at
    /// every outer node, G(p) = G(p′) + ∫_{p′}^{p} σ⟨𝒞⟩ from the nearest
    /// p′ < p already known, whose bar it inherits. The memory is kept per
    /// pass (rule and tolerances), so the check pass builds its own G with
    /// its own rule and the two passes stay independent.
    pub fn q_pair(&self, mean: &MeanSource<'_, T>, opts: &Options) -> Result<Estimate<T>, OracleError> {
        let x0 = self.x_camera();
        // One memory per pass; the passes run side by side, each locks its own.
        let memory: Mutex<HashMap<PassKey, PassMemory<T>>> = Mutex::new(HashMap::new());
        let pass_memory = |inner: &Options| {
            memory
                .lock()
                .expect("no pass panics while holding the memory")
                .entry(PassKey::of(inner))
                .or_insert_with(|| Arc::new(Mutex::new(vec![Known::start(&x0)])))
                .clone()
        };
        let e = integrate_nested(
            |p: &T, inner: &Options| {
                let zero = || Ok(Estimate::known(p.lit(0.0), p.lit(0.0), 0, inner.rule));
                let half = self.half_weight(p);
                if !(p.clone() > x0.clone()) || half.is_zero() {
                    return zero();
                }
                let pass = pass_memory(inner);
                let mut known = pass.lock().expect("no pass panics while holding its memory");
                match mean {
                    MeanSource::WithBar(m) => self.pair_sample_with_bar(m, &mut known, p, &half, inner),
                    MeanSource::Plain(m) => {
                        let outer = half.clone() * (half * m(p));
                        if outer.is_zero() {
                            return zero();
                        }
                        let sigma = self.sigma.clone();
                        let short = short_options(&known, p, &outer, inner);
                        let g = cumulative_with(&mut known, p, inner, |a: &T, b: &T| {
                            integrate(|s: &T| sigma.clone() * m(s), &(self.domain)(a, Some(b)), &short)
                        })?;
                        Ok(Estimate::known(outer.clone() * g.value, outer.abs() * g.error, g.evaluations, inner.rule))
                    }
                }
            },
            &(self.domain)(&x0, None),
            &self.scaled_options(opts),
        );
        self.unscaled(e).map_err(OracleError::quad("∫∫⟨𝒞⟩⟨𝒞⟩ of (17)"))
    }

    /// σe^{−σp−c₀}⟨𝒞⟩e^{c₀}(p)G(p) where ⟨𝒞⟩ has a bar (`half` the
    /// square root of the weight): ⟨𝒞⟩(p) to the tolerance left by the G
    /// known below p (G grows with p), then G(p) cumulatively, each short
    /// piece an integral of the same pass.
    fn pair_sample_with_bar(
        &self,
        mean: &(dyn Fn(&T, f64, &Options) -> Outcome<T> + Sync),
        known: &mut Vec<Known<T>>,
        p: &T,
        half: &T,
        inner: &Options,
    ) -> Outcome<T> {
        let below = known[known.partition_point(|k| k.at <= *p) - 1].value.abs().to_f64();
        let h = half.to_f64();
        let m_abs = if below > 0.0 { (inner.abs_tol / (2.0 * h * (h * below))).min(f64::MAX) } else { 0.0 };
        let tol = inner.rel_tol;
        let m = mean(p, tol, &Options { abs_tol: m_abs, ..inner.clone() })?;
        let outer = half.clone() * (half.clone() * m.value.clone());
        if outer.is_zero() {
            return Ok(Estimate::known(p.lit(0.0), p.lit(0.0), m.evaluations, inner.rule));
        }
        let sigma = self.sigma.clone();
        let short = short_options(known, p, &outer, inner);
        let g = cumulative_with(known, p, inner, |a: &T, b: &T| {
            integrate_within_pass(
                |s: &T, o: &Options| {
                    let e = mean(s, tol, &Options { abs_tol: o.abs_tol / sigma.to_f64(), ..o.clone() })?;
                    Ok(Estimate::known(sigma.clone() * e.value, sigma.clone() * e.error, e.evaluations, o.rule))
                },
                &(self.domain)(a, Some(b)),
                &short,
            )
        })?;
        let value = outer.clone() * g.value.clone();
        let error =
            outer.abs() * g.error.clone() + (half.clone() * (half.clone() * g.value.clone())).abs() * m.error.clone();
        Ok(Estimate::known(value, error, g.evaluations + m.evaluations, inner.rule))
    }
}

/// The options of one short piece of G(p) = ∫₀^p σ⟨𝒞⟩, whose error is
/// multiplied by `outer` = σe^{−σp}⟨𝒞⟩(p) in Q's integrand: a thousandth
/// of the inner goal for outer·G, and of the relative goal for G itself
/// (G(p′) known below p), so that a chain of many pieces stays within the
/// inner budget without asking a piece for more than its own rounding
/// allows (a beam's edge crossed over 10⁻⁶ of the ray).
fn short_options<T: Real>(known: &[Known<T>], p: &T, outer: &T, inner: &Options) -> Options {
    let below = known[known.partition_point(|k| k.at <= *p) - 1].value.abs().to_f64();
    let short_abs = (inner.abs_tol / (1000.0 * outer.abs().to_f64())).max(inner.rel_tol * below / 1000.0);
    Options { abs_tol: short_abs.min(f64::MAX), ..inner.clone() }
}

/// The even exponent k (0 ≤ k ≤ 1020) of the power of two that P and Q
/// are integrated times (see [`RayLine`]): 2^k ≈ e^{σ·m − c₀}, at most,
/// where `m` is a lower bound of s + 2·(light → sphere path) over the
/// camera ray and the lights (`None`: none known, k = 0), so that P·e^{c₀}·2^k
/// ≲ 1 up to algebraic factors. Usually m ≥ c₀/σ (the path s + path ≥
/// c₀/σ, and path ≥ 0); where a looser bound gives less (the finite-sphere
/// model's D − R with a light within R of the line), k is clamped to 0.
///
/// ```
/// use mcrt_noise::model::along::pair_scale_exponent;
///
/// // σ = 490, c₀ = 688.06, m = 2.712: e^{σm − c₀} = e^{640.8} ≈ 2^{924.5}.
/// assert_eq!(pair_scale_exponent(490.0, 688.06, Some(2.712)), 924);
/// assert_eq!(pair_scale_exponent(1.0, 0.5, None), 0);
/// assert_eq!(pair_scale_exponent(1.0, 0.5, Some(0.1)), 0);
/// ```
pub fn pair_scale_exponent(sigma: f64, shift: f64, m: Option<f64>) -> i32 {
    let excess = m.map_or(0.0, |m| sigma * m - shift);
    let k = (excess / std::f64::consts::LN_2 / 2.0).floor() * 2.0;
    if k.is_finite() {
        k.clamp(0.0, 1020.0) as i32
    } else {
        0
    }
}

/// The least [`point_quadratic_path`] over `lights` given as (z, b) of
/// each point light, `None` for a light whose bound is not formed (a
/// beam): then `None` (no scale).
///
/// ```
/// use mcrt_noise::model::along::lowest_quadratic_path;
///
/// assert_eq!(lowest_quadratic_path([Some((-3.0, 4.0)), Some((0.0, 1.0))]), Some(2.0));
/// assert_eq!(lowest_quadratic_path([Some((-3.0, 4.0)), None]), None);
/// ```
pub fn lowest_quadratic_path(lights: impl IntoIterator<Item = Option<(f64, f64)>>) -> Option<f64> {
    lights.into_iter().try_fold(f64::INFINITY, |m, light| light.map(|(z, b)| m.min(point_quadratic_path(z, b))))
}

/// min over s ≥ 0 of s + 2√((s − z)² + b²): the quadratic path s + 2D of a
/// point light whose foot lies at abscissa `z`, `b` ≥ 0 from the camera
/// line: z + √3·b where the minimiser s = z − b/√3 is ≥ 0, else
/// 2√(z² + b²) at the camera.
///
/// ```
/// use mcrt_noise::model::along::point_quadratic_path;
///
/// // Foot at 1, distance 1: the minimiser s = 1 − 1/√3 lies ahead of the camera.
/// assert!((point_quadratic_path(1.0, 1.0) - (1.0 + 3f64.sqrt())).abs() < 1e-15);
/// // A light behind the camera: the minimum is at the camera, 2|y − o|.
/// assert_eq!(point_quadratic_path(-3.0, 4.0), 10.0);
/// ```
pub fn point_quadratic_path(z: f64, b: f64) -> f64 {
    let at = z - b / 3f64.sqrt();
    if at >= 0.0 {
        z + 3f64.sqrt() * b
    } else {
        2.0 * z.hypot(b)
    }
}

/// The tolerance of the ⟨𝒞⟩ tables for an integral with options `opts`:
/// that of its inner level in the primary pass (`integrate_nested`).
pub fn table_tol(opts: &Options) -> f64 {
    opts.rel_tol / 20.0
}

/// The G values one pass has computed, sorted by position.
type PassMemory<T> = Arc<Mutex<Vec<Known<T>>>>;

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

/// G(p) = G(p′) + ∫_{p′}^{p} from the nearest known p′ ≤ p, the piece
/// computed by `piece(p′, p)`; the new point is remembered.
fn cumulative_with<T: CheckRule>(
    known: &mut Vec<Known<T>>,
    p: &T,
    inner: &Options,
    piece: impl FnOnce(&T, &T) -> Result<Estimate<T>, Failure<T>>,
) -> Outcome<T> {
    let idx = known.partition_point(|k| k.at <= *p);
    let base = known[idx - 1].clone();
    if base.at == *p {
        return Ok(Estimate::known(base.value, base.error, 0, inner.rule));
    }
    let piece = piece(&base.at, p)?;
    let value = base.value + piece.value.clone();
    let error = base.error + piece.error.clone();
    known.insert(idx, Known { at: p.clone(), value: value.clone(), error: error.clone() });
    Ok(Estimate::known(value, error, piece.evaluations, inner.rule))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// P and Q of a smooth ⟨𝒞⟩ (plain, and with a bar through the nested
    /// path) integrated times 2⁴⁰ and divided back are the same to the bit
    /// as without the scale: a power of two changes no rounding where the
    /// engine's underflow floor plays no part.
    #[test]
    fn the_pair_scale_changes_no_bit() {
        let mean = |x: &f64| (-(x - 1.0) * (x - 1.0)).exp() + 0.5 / (1.0 + x * x);
        let with_bar = |x: &f64, _tol: f64, o: &Options| Ok(Estimate::known(mean(x), mean(x) * 1e-13, 1, o.rule));
        let domain = |lo: &f64, hi: Option<&f64>| match hi {
            Some(h) => Domain::finite(*lo, *h).with_breakpoints(vec![1.0]).with_decay(1.3),
            None => Domain::semi_infinite(*lo).with_breakpoints(vec![1.0]).with_decay(1.3),
        };
        let line = |k: i32| RayLine { sigma: 1.3, center: 0.0, shift: 0.2, pair_scale: k, domain: &domain };
        let opts = Options::rel(1e-8);
        for source in [MeanSource::Plain(&mean), MeanSource::WithBar(&with_bar)] {
            let (plain, scaled) = (line(0), line(40));
            let (p0, p1) = (plain.p_single(&source, &opts).unwrap(), scaled.p_single(&source, &opts).unwrap());
            let (q0, q1) = (plain.q_pair(&source, &opts).unwrap(), scaled.q_pair(&source, &opts).unwrap());
            for (what, a, b) in [("P", p0, p1), ("Q", q0, q1)] {
                assert!(a.value > 0.0 && a.error < 1e-7 * a.value, "{what}: {} ± {}", a.value, a.error);
                assert_eq!(a.value.to_bits(), b.value.to_bits(), "{what}: {} against {}", a.value, b.value);
                assert_eq!(a.error.to_bits(), b.error.to_bits(), "{what}'s bar: {} against {}", a.error, b.error);
                assert_eq!(a.evaluations, b.evaluations, "{what}'s evaluations");
            }
        }
    }
}
