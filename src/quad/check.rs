//! Cross-check rule: adaptive bisection of an interpolatory rule in the
//! smoothing substitution x = a + (b − a)(3s² − 2s³), which turns endpoint
//! singularities of the form (b − x)^α into (1 − s)^{2α+1}.
//!
//! f64 uses the `quadrature` crate's Clenshaw–Curtis rule; its limits are
//! kept from the user: it takes finite intervals only (we map), replaces
//! non-finite values by 0 (we record them and fail), stops at 257 points with
//! no flag and may misstate its error by 10¹³ (we never read its estimate: a
//! panel's error is the difference between the rule on the panel and on its
//! two halves). MPFR uses Gauss–Legendre with nodes computed at the working
//! precision, n = prec/2 points, and the panel error |G_n − G_{n/2}|.

use super::nodes::gauss_legendre;
use super::{control, goal, Failure, Mapped, Options, Piece, RuleResult, Sample};
use crate::real::Real;
use rug::Float;
use std::cell::RefCell;

/// The integrand of a panel in the substituted variable.
pub type PanelFn<'a, T> = dyn FnMut(&T) -> Result<Sample<T>, Failure<T>> + 'a;

/// A rule's estimate on one panel [s0, s1].
#[doc(hidden)]
#[derive(Debug, Clone)]
pub struct PanelEstimate<T> {
    pub value: T,
    /// Truncation error estimate of `value`.
    pub quad_err: T,
    /// Integrated error bars of nested inner integrals.
    pub inner_err: T,
    /// ∫|g| over the panel (for the rounding floor).
    pub abs: T,
    /// The rule's value on each half, when the estimate computed them (the
    /// children of a bisection can reuse them).
    pub halves: [Option<T>; 2],
}

/// A real type that has a cross-check rule.
pub trait CheckRule: Real + Send + Sync + 'static {
    /// Name shown in cross-check reports.
    const CHECK_NAME: &'static str;
    /// Whether the rule needs a per-call target (the f64 crate does).
    #[doc(hidden)]
    const NEEDS_TARGET: bool;

    /// The rule's estimate on [s0, s1]; `whole` is its value on the whole
    /// panel if a parent already computed it.
    #[doc(hidden)]
    fn panel(
        g: &mut PanelFn<'_, Self>,
        s0: &Self,
        s1: &Self,
        target: &Self,
        whole: Option<Self>,
    ) -> Result<PanelEstimate<Self>, Failure<Self>>;
}

/// The crate's Clenshaw–Curtis on [s0, s1]: (value, inner bound, ∫|g|).
fn clenshaw_curtis(g: &mut PanelFn<'_, f64>, s0: f64, s1: f64, target: f64) -> Result<(f64, f64, f64), Failure<f64>> {
    // The crate wants `Fn`; our integrand is `FnMut` and may fail.
    let state = RefCell::new((g, None::<Failure<f64>>, 0.0f64, 0.0f64, 0u32));
    let out = quadrature::clenshaw_curtis::integrate(
        |s| {
            let mut st = state.borrow_mut();
            if st.1.is_some() {
                return 0.0;
            }
            match (st.0)(&s) {
                Ok(sample) => {
                    st.2 = st.2.max(sample.error);
                    st.3 += sample.value.abs();
                    st.4 += 1;
                    sample.value
                }
                Err(e) => {
                    st.1 = Some(e);
                    0.0
                }
            }
        },
        s0,
        s1,
        target,
    );
    let (_, failure, max_err, sum_abs, count) = state.into_inner();
    if let Some(e) = failure {
        return Err(e);
    }
    // No weights are exposed: the inner bars are bounded by their maximum
    // times the width, ∫|g| (for the rounding floor) by the mean |g|.
    let width = s1 - s0;
    Ok((out.integral, max_err * width, sum_abs / f64::from(count.max(1)) * width))
}

impl CheckRule for f64 {
    const CHECK_NAME: &'static str = "Clenshaw-Curtis (quadrature crate)";
    const NEEDS_TARGET: bool = true;

    fn panel(
        g: &mut PanelFn<'_, f64>,
        s0: &f64,
        s1: &f64,
        target: &f64,
        whole: Option<f64>,
    ) -> Result<PanelEstimate<f64>, Failure<f64>> {
        let whole = match whole {
            Some(w) => w,
            None => clenshaw_curtis(g, *s0, *s1, *target)?.0,
        };
        let mid = 0.5 * (s0 + s1);
        let left = clenshaw_curtis(g, *s0, mid, *target)?;
        let right = clenshaw_curtis(g, mid, *s1, *target)?;
        let value = left.0 + right.0;
        Ok(PanelEstimate {
            value,
            quad_err: (whole - value).abs(),
            inner_err: left.1 + right.1,
            abs: left.2 + right.2,
            halves: [Some(left.0), Some(right.0)],
        })
    }
}

/// n-point Gauss–Legendre on [s0, s1]: (value, inner error, ∫|g|).
fn gauss_legendre_rule(
    g: &mut PanelFn<'_, Float>,
    s0: &Float,
    s1: &Float,
    n: usize,
) -> Result<(Float, Float, Float), Failure<Float>> {
    let nodes = gauss_legendre(s0, n);
    let half = (s1.clone() - s0.clone()) / s0.lit(2.0);
    let mid = (s1.clone() + s0.clone()) / s0.lit(2.0);
    let (mut v, mut e, mut a) = (s0.lit(0.0), s0.lit(0.0), s0.lit(0.0));
    for (x, w) in nodes.iter() {
        let xs = if x.is_zero() {
            [Some(mid.clone()), None]
        } else {
            [Some(mid.clone() - half.clone() * x.clone()), Some(mid.clone() + half.clone() * x.clone())]
        };
        for s in xs.into_iter().flatten() {
            let sample = g(&s)?;
            v += w.clone() * &sample.value;
            e += w.clone() * sample.error;
            a += w.clone() * sample.value.abs();
        }
    }
    Ok((v * half.clone(), e * half.clone(), a * half))
}

impl CheckRule for Float {
    const CHECK_NAME: &'static str = "Gauss-Legendre (MPFR nodes)";
    const NEEDS_TARGET: bool = false;

    fn panel(
        g: &mut PanelFn<'_, Float>,
        s0: &Float,
        s1: &Float,
        _target: &Float,
        _whole: Option<Float>,
    ) -> Result<PanelEstimate<Float>, Failure<Float>> {
        let n = (Real::prec(s0) as usize / 2).clamp(20, 600);
        let (value, inner_err, abs) = gauss_legendre_rule(g, s0, s1, n)?;
        let (coarse, _, _) = gauss_legendre_rule(g, s0, s1, n / 2)?;
        Ok(PanelEstimate { quad_err: (value.clone() - coarse).abs(), value, inner_err, abs, halves: [None, None] })
    }
}

/// A panel [s0, s1] in the substituted variable of piece `piece`.
struct Panel<T> {
    piece: usize,
    s0: T,
    s1: T,
    est: PanelEstimate<T>,
}

impl<T: Real> control::Panel<T> for Panel<T> {
    fn value(&self) -> T {
        self.est.value.clone()
    }
    fn quad_err(&self) -> T {
        self.est.quad_err.clone()
    }
    fn floor(&self) -> T {
        self.s0.eps() * self.s0.lit(8.0) * self.est.abs.clone() + self.s0.underflow_floor() / self.s0.lit(1024.0)
    }
    fn error(&self) -> T {
        self.est.quad_err.clone() + self.est.inner_err.clone() + self.floor()
    }
}

/// Integrates all pieces to the goal of `opts`.
pub(crate) fn adaptive<T: CheckRule>(
    f: &mut Mapped<'_, '_, T>,
    pieces: &[Piece<T>],
    opts: &Options,
) -> Result<RuleResult<T>, Failure<T>> {
    let like = pieces[0].a.clone();
    // g(s) = f(x(s)) (b − a) φ'(s), x(s) = a + (b − a) φ(s), φ = 3s² − 2s³.
    let estimate = |piece_idx: usize, s0: &T, s1: &T, target: &T, whole: Option<T>, f: &mut Mapped<'_, '_, T>| {
        let piece = &pieces[piece_idx];
        let width = piece.b.clone() - piece.a.clone();
        let mut g = |s: &T| -> Result<Sample<T>, Failure<T>> {
            let s2 = s.clone() * s.clone();
            let phi = s2.clone() * (s.lit(3.0) - s.lit(2.0) * s.clone());
            let dphi = s.lit(6.0) * s.clone() * (s.lit(1.0) - s.clone());
            let x = piece.a.clone() + width.clone() * phi;
            if !(x > piece.a && x < piece.b) {
                return Ok(Sample { value: s.lit(0.0), error: s.lit(0.0), evaluations: 0 });
            }
            let mut sample = f.eval(&x)?;
            let jac = width.clone() * dphi;
            sample.value = sample.value * jac.clone();
            sample.error = sample.error * jac;
            Ok(sample)
        };
        T::panel(&mut g, s0, s1, target, whole)
    };
    let (zero, one) = (like.lit(0.0), like.lit(1.0));
    // The per-call target of the f64 rule: a first call with +∞ (the
    // crate's cheapest) learns the scale, then the goal at that scale. It
    // only sets how hard the crate works; it never enters our error bar.
    let target = if T::NEEDS_TARGET {
        let inf = like.lit(f64::INFINITY);
        let mut scale = like.lit(0.0);
        for i in 0..pieces.len() {
            scale = scale + estimate(i, &zero, &one, &inf, None, f)?.abs;
        }
        goal(&scale, opts)
    } else {
        like.lit(0.0)
    };
    let mut panels = Vec::new();
    for i in 0..pieces.len() {
        let est = estimate(i, &zero, &one, &target, None, f)?;
        panels.push(Panel { piece: i, s0: zero.clone(), s1: one.clone(), est });
    }
    while let Some(worst) = control::next_to_refine(&panels, &like, f, opts, "the cross-check")? {
        let mid = control::midpoint(&panels[worst].s0, &panels[worst].s1, &panels, f)?;
        let p = panels.swap_remove(worst);
        let [left, right] = p.est.halves;
        let est = estimate(p.piece, &p.s0, &mid, &target, left, f)?;
        panels.push(Panel { piece: p.piece, s0: p.s0, s1: mid.clone(), est });
        let est = estimate(p.piece, &mid, &p.s1, &target, right, f)?;
        panels.push(Panel { piece: p.piece, s0: mid, s1: p.s1, est });
    }
    Ok(control::result(&panels, &like))
}
