//! Cross-check rule: adaptive bisection of an interpolatory rule in the
//! smoothing substitution x = a + (b − a)(3s² − 2s³), which turns endpoint
//! singularities of the form (b − x)^α into (1 − s)^{2α+1}.
//!
//! f64 uses the `quadrature` crate's Clenshaw–Curtis rule on each panel; its
//! limits are kept from the user: it takes finite intervals only (we map),
//! replaces non-finite values by 0 (we record them and fail), stops at 257
//! points with no flag and may misstate its error by 10¹³ (we never read its
//! estimate: a panel's error is the difference between the rule on the panel
//! and on its two halves). MPFR uses Gauss–Legendre with nodes computed at
//! the working precision.

use super::nodes::gauss_legendre;
use super::tanh_sinh::sum;
use super::{goal, Failure, Mapped, Options, Piece, RuleResult, Sample};
use crate::real::Real;
use rug::Float;
use std::cell::RefCell;

/// A real type that has a cross-check rule.
pub trait CheckRule: Real + 'static {
    /// Name shown in cross-check reports.
    const CHECK_NAME: &'static str;

    /// Rule on one panel [s0, s1] of the substituted variable of `piece`:
    /// (value, integrated inner error bar, ∫|g|).
    #[doc(hidden)]
    fn panel_rule(g: &mut dyn FnMut(&Self) -> Result<Sample<Self>, Failure<Self>>, s0: &Self, s1: &Self, target: &Self)
        -> Result<(Self, Self, Self), Failure<Self>>;
}

impl CheckRule for f64 {
    const CHECK_NAME: &'static str = "Clenshaw-Curtis (quadrature crate)";

    fn panel_rule(g: &mut dyn FnMut(&f64) -> Result<Sample<f64>, Failure<f64>>, s0: &f64, s1: &f64, target: &f64)
        -> Result<(f64, f64, f64), Failure<f64>> {
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
            *s0,
            *s1,
            *target,
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
}

impl CheckRule for Float {
    const CHECK_NAME: &'static str = "Gauss-Legendre (MPFR nodes)";

    fn panel_rule(g: &mut dyn FnMut(&Float) -> Result<Sample<Float>, Failure<Float>>, s0: &Float, s1: &Float, _target: &Float)
        -> Result<(Float, Float, Float), Failure<Float>> {
        let n = (Real::prec(s0) as usize / 3).clamp(20, 400);
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
}

/// A panel [s0, s1] in the substituted variable of piece `piece`.
struct Panel<T> {
    piece: usize,
    s0: T,
    s1: T,
    /// Rule on the whole panel.
    whole: T,
    /// Rule on the two halves: (value, inner error, ∫|g|) each.
    halves: [(T, T, T); 2],
}

impl<T: Real> Panel<T> {
    fn value(&self) -> T {
        self.halves[0].0.clone() + self.halves[1].0.clone()
    }
    fn quad_err(&self) -> T {
        (self.whole.clone() - self.value()).abs()
    }
    fn floor(&self) -> T {
        self.s0.eps() * self.s0.lit(8.0) * (self.halves[0].2.clone() + self.halves[1].2.clone()) + self.s0.underflow_floor()
    }
    fn error(&self) -> T {
        self.quad_err() + self.halves[0].1.clone() + self.halves[1].1.clone() + self.floor()
    }
}

/// Integrates all pieces to the goal of `opts`.
pub(crate) fn adaptive<T: CheckRule>(f: &mut Mapped<'_, '_, T>, pieces: &[Piece<T>], opts: &Options) -> Result<RuleResult<T>, Failure<T>> {
    let like = pieces[0].a.clone();
    // The per-call target of the f64 rule: first +∞ (the crate's cheapest
    // call) to learn the scale, then the goal at that scale. It
    // only sets how hard the crate works; it never enters our error bar.
    let target = std::cell::RefCell::new(like.lit(f64::INFINITY));
    // g(s) = f(x(s)) (b − a) φ'(s), x(s) = a + (b − a) φ(s), φ = 3s² − 2s³.
    let mut run = |piece: &Piece<T>, s0: &T, s1: &T, f: &mut Mapped<'_, '_, T>| {
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
        let tgt = target.borrow().clone();
        T::panel_rule(&mut g, s0, s1, &tgt)
    };
    let make = |piece_idx: usize, s0: T, s1: T, whole: T, f: &mut Mapped<'_, '_, T>, run: &mut dyn FnMut(&Piece<T>, &T, &T, &mut Mapped<'_, '_, T>) -> Result<(T, T, T), Failure<T>>| -> Result<Panel<T>, Failure<T>> {
        let mid = (s0.clone() + s1.clone()) / s0.lit(2.0);
        let left = run(&pieces[piece_idx], &s0, &mid, f)?;
        let right = run(&pieces[piece_idx], &mid, &s1, f)?;
        Ok(Panel { piece: piece_idx, s0, s1, whole, halves: [left, right] })
    };
    let (zero, one) = (like.lit(0.0), like.lit(1.0));
    let mut scale = like.lit(0.0);
    for piece in pieces {
        scale = scale + run(piece, &zero, &one, f)?.2;
    }
    *target.borrow_mut() = goal(&scale, opts) * like.lit(1.0);
    let mut panels = Vec::new();
    for (i, piece) in pieces.iter().enumerate() {
        let (zero, one) = (like.lit(0.0), like.lit(1.0));
        let whole = run(piece, &zero, &one, f)?.0;
        panels.push(make(i, zero, one, whole, f, &mut run)?);
    }
    loop {
        let value = sum(panels.iter().map(Panel::value), &like);
        let error = sum(panels.iter().map(Panel::error), &like);
        if error <= goal(&value, opts) {
            break;
        }
        let (worst, worst_err) = panels
            .iter()
            .enumerate()
            .map(|(i, p)| (i, p.quad_err()))
            .fold((0, like.lit(-1.0)), |acc, (i, e)| if e > acc.1 { (i, e) } else { acc });
        if worst_err <= panels[worst].floor() {
            break;
        }
        if f.tally.calls >= opts.max_evals {
            return Err(f.fail(format!("evaluation budget {} exhausted by the cross-check", opts.max_evals), Some((value, error))));
        }
        let p = panels.swap_remove(worst);
        let mid = (p.s0.clone() + p.s1.clone()) / p.s0.lit(2.0);
        if !(mid > p.s0 && mid < p.s1) {
            return Err(f.fail("cross-check panel cannot be bisected further".into(), Some((value, error))));
        }
        let [left, right] = p.halves;
        panels.push(make(p.piece, p.s0, mid.clone(), left.0, f, &mut run)?);
        panels.push(make(p.piece, mid, p.s1, right.0, f, &mut run)?);
    }
    Ok(RuleResult {
        value: sum(panels.iter().map(Panel::value), &like),
        error: sum(panels.iter().map(Panel::error), &like),
        pieces: panels.len(),
    })
}
