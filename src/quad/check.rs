//! Cross-check rule: adaptive bisection of an interpolatory rule in the
//! smoothing substitution x = a + (b − a)(3s² − 2s³), which turns endpoint
//! singularities of the form (b − x)^α into (1 − s)^{2α+1}.
//!
//! The rule on a panel is Gauss–Legendre with nodes computed by Newton at the
//! working precision (an interpolatory rule unrelated to tanh–sinh, the
//! primary). f64: the 10-point rule, panel error |G(panel) − G(left) −
//! G(right)| (the children reuse their halves, so a bisection costs 20 new
//! values). MPFR: n = prec/2 points and the panel error |G_n − G_{n/2}|.
//!
//! (Until 2026-11 f64 used the `quadrature` crate's Clenshaw–Curtis. Its
//! calls share no values, it needs a scale call per piece to set its
//! target, and it was measured to take 2.3–3× the evaluations of G10 for the
//! same panels; the order-1 oracle's check pass of (23) dropped from 18 s to 7 s.)

use super::nodes::gauss_legendre;
use super::{control, Failure, Mapped, Options, Piece, RuleResult, Sample};
use crate::real::Real;
#[cfg(feature = "mpfr")]
use rug::Float;

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

    /// The rule's estimate on [s0, s1]; `whole` is its value on the whole
    /// panel if a parent already computed it.
    #[doc(hidden)]
    fn panel(
        g: &mut PanelFn<'_, Self>,
        s0: &Self,
        s1: &Self,
        whole: Option<Self>,
    ) -> Result<PanelEstimate<Self>, Failure<Self>>;
}

/// Points of the f64 panel rule.
const F64_POINTS: usize = 10;

impl CheckRule for f64 {
    const CHECK_NAME: &'static str = "Gauss-Legendre (10 points, bisection)";

    fn panel(
        g: &mut PanelFn<'_, f64>,
        s0: &f64,
        s1: &f64,
        whole: Option<f64>,
    ) -> Result<PanelEstimate<f64>, Failure<f64>> {
        // An even n: no node at a panel's midpoint, where the parent's
        // bisection put the children's common end.
        let n = F64_POINTS;
        let whole = match whole {
            Some(w) => w,
            None => gauss_legendre_rule(g, s0, s1, n)?.0,
        };
        let mid = 0.5 * (s0 + s1);
        let left = gauss_legendre_rule(g, s0, &mid, n)?;
        let right = gauss_legendre_rule(g, &mid, s1, n)?;
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
fn gauss_legendre_rule<T: Real + 'static>(
    g: &mut PanelFn<'_, T>,
    s0: &T,
    s1: &T,
    n: usize,
) -> Result<(T, T, T), Failure<T>> {
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
            v = v + w.clone() * sample.value.clone();
            e = e + w.clone() * sample.error;
            a = a + w.clone() * sample.value.abs();
        }
    }
    Ok((v * half.clone(), e * half.clone(), a * half))
}

#[cfg(feature = "mpfr")]
impl CheckRule for Float {
    const CHECK_NAME: &'static str = "Gauss-Legendre (MPFR nodes)";

    fn panel(
        g: &mut PanelFn<'_, Float>,
        s0: &Float,
        s1: &Float,
        _whole: Option<Float>,
    ) -> Result<PanelEstimate<Float>, Failure<Float>> {
        let n = (Real::prec(s0) as usize / 2).clamp(20, 600);
        let (value, inner_err, abs) = gauss_legendre_rule(g, s0, s1, n)?;
        let (coarse, _, _) = gauss_legendre_rule(g, s0, s1, n / 2)?;
        Ok(PanelEstimate { quad_err: (value.clone() - coarse).abs(), value, inner_err, abs, halves: [None, None] })
    }
}

/// A panel [s0, s1] in the substituted variable of piece `piece` (this
/// rule's and the Gauss–Kronrod pair's).
pub(super) struct Panel<T> {
    pub piece: usize,
    pub s0: T,
    pub s1: T,
    pub est: PanelEstimate<T>,
}

/// The smoothing substitution x = a + (b − a)φ(s) of a piece.
#[derive(Clone, Copy)]
pub(super) enum Map {
    /// φ = (1 − cos πs)/2 = sin²(πs/2) (the Gauss–Kronrod primary's).
    Cosine,
    /// φ = 3s² − 2s³ (this rule's).
    Cubic,
}

impl Map {
    /// (φ(s), φ′(s)).
    fn at<T: Real>(self, s: &T) -> (T, T) {
        match self {
            Map::Cosine => {
                // sin²(πs/2), not (1 − cos πs)/2: that rounds to 0 below
                // s ≈ 3·10⁻⁹ and keeps no relative accuracy near s = 0;
                // sin(π·min(s, 1 − s)) keeps φ′ accurate near s = 1.
                let half = (s.pi() * s.clone() / s.lit(2.0)).sin();
                let near = s.clone().min_of(s.lit(1.0) - s.clone());
                (half.clone() * half, s.pi() / s.lit(2.0) * (s.pi() * near).sin())
            }
            Map::Cubic => {
                let s2 = s.clone() * s.clone();
                (s2 * (s.lit(3.0) - s.lit(2.0) * s.clone()), s.lit(6.0) * s.clone() * (s.lit(1.0) - s.clone()))
            }
        }
    }

    /// g(s) = f(x(s)) (b − a) φ′(s) on `piece`: 0 (no evaluation) where
    /// x(s) rounds onto an end of the piece.
    pub(super) fn sample<T: Real>(
        self,
        f: &mut Mapped<'_, '_, T>,
        piece: &Piece<T>,
        s: &T,
    ) -> Result<Sample<T>, Failure<T>> {
        let (phi, dphi) = self.at(s);
        let width = piece.b.clone() - piece.a.clone();
        let x = piece.a.clone() + width.clone() * phi;
        if !(x > piece.a && x < piece.b) {
            return Ok(Sample { value: s.lit(0.0), error: s.lit(0.0), evaluations: 0 });
        }
        let mut sample = f.eval(&x)?;
        let jac = width * dphi;
        sample.value = sample.value * jac.clone();
        sample.error = sample.error * jac;
        Ok(sample)
    }
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
    let estimate = |piece_idx: usize, s0: &T, s1: &T, whole: Option<T>, f: &mut Mapped<'_, '_, T>| {
        let piece = &pieces[piece_idx];
        T::panel(&mut |s: &T| Map::Cubic.sample(f, piece, s), s0, s1, whole)
    };
    let (zero, one) = (like.lit(0.0), like.lit(1.0));
    let mut panels = Vec::new();
    for i in 0..pieces.len() {
        let est = estimate(i, &zero, &one, None, f)?;
        panels.push(Panel { piece: i, s0: zero.clone(), s1: one.clone(), est });
    }
    while let Some(worst) = control::next_to_refine(&panels, &like, f, opts, "the cross-check")? {
        let mid = control::midpoint(&panels[worst].s0, &panels[worst].s1, &panels, f)?;
        let p = panels.swap_remove(worst);
        let [left, right] = p.est.halves;
        let est = estimate(p.piece, &p.s0, &mid, left, f)?;
        panels.push(Panel { piece: p.piece, s0: p.s0, s1: mid.clone(), est });
        let est = estimate(p.piece, &mid, &p.s1, right, f)?;
        panels.push(Panel { piece: p.piece, s0: mid, s1: p.s1, est });
    }
    Ok(control::result(&panels, &like))
}
