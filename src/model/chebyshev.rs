//! Piecewise Chebyshev interpolation of a positive function with an error
//! estimate, at any working precision. The interpolant is of ln f, so that
//! a function falling by e^{−30} over a piece (an attenuated tail) keeps its
//! *relative* accuracy everywhere, and an absolute error δ of ln f is a
//! relative error e^δ − 1 ≈ δ of f.
//!
//! Used where one costly 1-D function (the single-scattered source
//! sin ψ·L₁(ψ) at one camera-ray point, itself a quadrature) is needed at
//! hundreds of thousands of points of a 2-D angular integral. On each piece
//! [a, b] the function is sampled at the n Chebyshev points of the first
//! kind (interior points only: no endpoint, where limits may be awkward),
//! n = 16 or 32, and evaluated from its Chebyshev coefficients by
//! Clenshaw's recurrence. The Chebyshev coefficients c_k give the estimate: a piece is
//! accepted when |c_{n−2}| + |c_{n−1}| ≤ tol·max|f| (or is down to 4× the
//! samples' own bars, where their noise rules), with error bar
//! 2(|c_{n−2}| + |c_{n−1}|) plus the samples' own bars times the nodes'
//! Lebesgue constant (below 3.21: interpolation can magnify the samples'
//! errors that much); otherwise it is bisected. The caller grades the
//! pieces towards known singular points.
//!
//! The bar is reported *relative*: ρ = max over pieces of the bar of ln f
//! (times 1.01 for e^δ − 1, or e^δ − 1 itself where larger), so that any
//! integral of the interpolant against a non-negative weight carries the
//! relative error ρ; each piece keeps its own too
//! ([`Piecewise::rel_error_at`], [`Piecewise::parts_over`]), for a sum over
//! many pieces where a few next to a singular point, accepted at their
//! samples' noise, bear far more than the rest.

use crate::quad::{Budget, Failure, Options, Outcome, Rule};
use crate::real::Real;

/// One piece: interpolation data on [a, b].
#[derive(Debug, Clone)]
struct Piece<T> {
    a: T,
    b: T,
    /// Values at the first-kind nodes, and the Chebyshev coefficients.
    values: Vec<T>,
    coeffs: Vec<T>,
    /// This piece's own relative bar (the largest is
    /// [`Piecewise::rel_error`]).
    rel_error: T,
}

/// A piecewise Chebyshev interpolant.
#[derive(Debug, Clone)]
pub struct Piecewise<T> {
    pieces: Vec<Piece<T>>,
    /// Relative error bound ρ (see the module doc).
    pub rel_error: T,
    /// Function evaluations spent (counting the samples' own).
    pub evaluations: u64,
}

const ORDERS: [usize; 2] = [16, 32];

/// An upper bound of the Lebesgue constant of interpolation at the n
/// first-kind Chebyshev points, (2/π) ln n + 1 (Rivlin, *An Introduction
/// to the Approximation of Functions*, 1969, §4.2: Λ_n < (2/π) ln n + 1):
/// how much the samples' own errors can grow in the interpolant (3.21 at
/// n = 32; computed, the constant itself is 3.17).
fn lebesgue_bound(n: usize) -> f64 {
    2.0 / std::f64::consts::PI * (n as f64).ln() + 1.0
}

/// Options for computing the samples of a table built to `rel_tol` with
/// the rule `rule`: a fortieth of the tolerance (at least 64 ulps),
/// relative only, no cross-check of their own (the table belongs to one
/// pass; the other pass builds its own with the other rule). `budget` is
/// the asking computation's, shared.
pub fn sample_options<T: Real>(like: &T, rel_tol: f64, rule: Rule, budget: &Budget) -> Options {
    Options {
        budget: budget.clone(),
        rel_tol: (rel_tol / 40.0).max(64.0 * like.eps().to_f64()),
        abs_tol: 0.0,
        rule,
        cross_check: false,
        zero_guard: false,
        ..Options::rel(rel_tol).declared()
    }
}
/// Pieces a table may add by bisection beyond those its declared cuts
/// make (which scale with the scene: a thin beam declares ~40 graded cuts
/// along the ray, so a fixed total of 400 would have refused about ten
/// thin beams before a single sample; the cuts are bounded by the light
/// count, so the total stays bounded too).
const MAX_PIECES: usize = 400;

impl<T: Real> Piecewise<T> {
    /// Interpolates f (value with bar) over the pieces between consecutive
    /// `cuts` (in any order, repeats allowed; the smallest and largest are
    /// the ends) to relative tolerance `rel_tol`.
    pub fn build(mut f: impl FnMut(&T) -> Outcome<T>, cuts: &[T], rel_tol: f64) -> Result<Self, Failure<T>> {
        let mut cuts = cuts.to_vec();
        cuts.sort_by(|a, b| a.partial_cmp(b).expect("finite cuts"));
        cuts.dedup_by(|a, b| a == b);
        let mut todo: Vec<(T, T)> =
            cuts.windows(2).filter(|w| w[0] < w[1]).map(|w| (w[0].clone(), w[1].clone())).collect();
        todo.reverse();
        let declared = todo.len();
        let limit = MAX_PIECES + declared;
        let like = cuts[0].clone();
        let mut pieces = Vec::new();
        let mut rel_error = like.lit(0.0);
        let mut evaluations = 0u64;
        while let Some((a, b)) = todo.pop() {
            if pieces.len() + todo.len() > limit {
                return Err(Failure {
                    reason: format!(
                        "Chebyshev interpolation needed more than {limit} pieces ({declared} declared, {MAX_PIECES} more by bisection)"
                    ),
                    best_guess: None,
                    error_estimate: None,
                    evaluations,
                });
            }
            let mut accepted = None;
            for &n in &ORDERS {
                // A failure carries every evaluation spent before it.
                let (mut piece, bar, evals) = sample(&mut f, &a, &b, n).map_err(|mut e| {
                    e.evaluations += evaluations;
                    e
                })?;
                evaluations += evals;
                piece.coeffs = coefficients(&piece.values);
                let tail = piece.coeffs[n - 2].abs() + piece.coeffs[n - 1].abs();
                // Accepted when the tail is below the goal, or when it is
                // down to the samples' own noise (then their bar rules).
                if tail <= like.lit(rel_tol) || tail <= bar.clone() * like.lit(4.0) {
                    // Plus the rounding of ln f and of the recurrence: 8 eps (1 + max |ln f|).
                    let big = piece.values.iter().fold(like.lit(1.0), |m, v| m.max_of(v.abs() + like.lit(1.0)));
                    let rounding = like.eps() * like.lit(8.0) * big;
                    // The samples' noise reaches the interpolant magnified
                    // by at most the Lebesgue constant of the nodes.
                    let mut err = tail * like.lit(2.0) + bar * like.lit(lebesgue_bound(n)) + rounding;
                    // Chop trailing coefficients whose sum stays below a tenth
                    // of that bar (cheaper evaluation); their sum joins it.
                    let mut dropped = like.lit(0.0);
                    while piece.coeffs.len() > 2 {
                        let last = piece.coeffs[piece.coeffs.len() - 1].abs();
                        if dropped.clone() + last.clone() > err.clone() / like.lit(10.0) {
                            break;
                        }
                        dropped = dropped + last;
                        piece.coeffs.pop();
                    }
                    // A bar δ of ln f is one of e^δ − 1 of f: 1.01δ for
                    // δ ≤ 0.02, more beyond (pieces accepted at their
                    // samples' noise can bear tenths).
                    // (e^700 keeps a hopeless piece's bar finite in f64.)
                    let ln_bar = err + dropped;
                    let capped = ln_bar.clone().min_of(like.lit(700.0));
                    err = (ln_bar * like.lit(1.01)).max_of(capped.exp() - like.lit(1.0));
                    accepted = Some((piece, err));
                    break;
                }
            }
            match accepted {
                Some((mut piece, rel)) => {
                    rel_error = rel_error.max_of(rel.clone());
                    piece.rel_error = rel;
                    pieces.push(piece);
                }
                None => {
                    let mid = (a.clone() + b.clone()) / like.lit(2.0);
                    if !(mid > a && mid < b) {
                        return Err(Failure {
                            reason: format!(
                                "Chebyshev interpolation cannot split [{:e}, {:e}]",
                                a.to_f64(),
                                b.to_f64()
                            ),
                            best_guess: None,
                            error_estimate: None,
                            evaluations,
                        });
                    }
                    todo.push((mid.clone(), b));
                    todo.push((a, mid));
                }
            }
        }
        pieces.sort_by(|p, q| p.a.partial_cmp(&q.a).expect("finite piece ends"));
        Ok(Piecewise { pieces, rel_error, evaluations })
    }

    /// Whether x lies in the covered range [a of the first piece, b of the
    /// last], where [`Piecewise::eval`] interpolates (outside it clamps).
    pub fn covers(&self, x: &T) -> bool {
        match (self.pieces.first(), self.pieces.last()) {
            (Some(first), Some(last)) => *x >= first.a && *x <= last.b,
            _ => false,
        }
    }

    /// The interpolant at x (clamped to the covered range): e^{p(x)}, p the
    /// Chebyshev interpolant of ln f, by Clenshaw's recurrence.
    pub fn eval(&self, x: &T) -> T {
        self.eval_ln(x).exp()
    }

    /// The relative bar of the piece that holds x (clamped like
    /// [`Piecewise::eval`]): at most [`Piecewise::rel_error`], and far below
    /// it away from the pieces accepted at their samples' noise, so that a
    /// sum of values over many pieces can carry each piece's own.
    pub fn rel_error_at(&self, x: &T) -> T {
        self.piece(x).rel_error.clone()
    }

    /// The parts of [lo, hi] (lo < hi) within each piece, as (from, to,
    /// the piece's relative bar), in order; beyond the covered range the
    /// first or last piece's (as [`Piecewise::eval`] clamps to them).
    pub fn parts_over(&self, lo: &T, hi: &T) -> Vec<(T, T, T)> {
        let last = self.pieces.len() - 1;
        self.pieces
            .iter()
            .enumerate()
            .filter(|(i, p)| (p.b > *lo || *i == last) && (p.a < *hi || *i == 0))
            .map(|(i, p)| {
                let from = if i == 0 { lo.clone() } else { p.a.clone().max_of(lo.clone()) };
                let to = if i == last { hi.clone() } else { p.b.clone().min_of(hi.clone()) };
                (from, to, p.rel_error.clone())
            })
            .filter(|(from, to, _)| to > from)
            .collect()
    }

    /// The piece that holds x (the first or last beyond the range).
    fn piece(&self, x: &T) -> &Piece<T> {
        let i = self.pieces.partition_point(|p| p.b < *x).min(self.pieces.len() - 1);
        &self.pieces[i]
    }

    /// ln of [`Piecewise::eval`]: the interpolant p(x) itself, for a caller
    /// that puts it into one exponent with others.
    pub fn eval_ln(&self, x: &T) -> T {
        let p = self.piece(x);
        let two = x.lit(2.0);
        let t = (two.clone() * x.clone() - p.a.clone() - p.b.clone()) / (p.b.clone() - p.a.clone());
        let t2 = two * t.clone();
        let (mut b1, mut b2) = (x.lit(0.0), x.lit(0.0));
        for c in p.coeffs.iter().skip(1).rev() {
            // c − b₂ does not wait for b₁: one multiply and one add on the
            // recurrence's critical path instead of three operations.
            let b0 = t2.clone() * b1.clone() + (c.clone() - b2);
            b2 = b1;
            b1 = b0;
        }
        p.coeffs[0].clone() / x.lit(2.0) + t * b1 - b2
    }
}

/// Samples ln f at the n first-kind Chebyshev points of [a, b]: the piece,
/// the largest bar of ln f (relative bar of f) and the evaluations. A value
/// that is not positive is an error.
fn sample<T: Real>(
    f: &mut impl FnMut(&T) -> Outcome<T>,
    a: &T,
    b: &T,
    n: usize,
) -> Result<(Piece<T>, T, u64), Failure<T>> {
    let pi = a.pi();
    let two = a.lit(2.0);
    let mut values = Vec::with_capacity(n);
    let mut bar = a.lit(0.0);
    let mut evals = 0;
    for j in 0..n {
        let angle = pi.clone() * a.lit((2 * j + 1) as f64) / a.lit((2 * n) as f64);
        let t = angle.cos();
        let x = ((a.clone() + b.clone()) + (b.clone() - a.clone()) * t.clone()) / two.clone();
        let e = f(&x).map_err(|mut e| {
            e.evaluations += evals;
            e
        })?;
        evals += e.evaluations;
        if !(e.value > a.lit(0.0)) || !e.value.is_finite() {
            return Err(Failure {
                reason: format!(
                    "interpolated function is not positive and finite at {:e}: {:e}",
                    x.to_f64(),
                    e.value.to_f64()
                ),
                best_guess: None,
                error_estimate: None,
                evaluations: evals,
            });
        }
        bar = bar.max_of(e.error.clone() / e.value.clone());
        values.push(e.value.ln());
    }
    Ok((Piece { a: a.clone(), b: b.clone(), values, coeffs: Vec::new(), rel_error: a.lit(0.0) }, bar, evals))
}

/// The first-kind Chebyshev coefficients of the samples at the nodes
/// t_j = cos((2j + 1)π/(2n)): c_k = (2/n) Σ_j f_j cos(k(2j + 1)π/(2n)), so
/// that the interpolant is c₀/2 + Σ_{k≥1} c_k T_k(t).
fn coefficients<T: Real>(values: &[T]) -> Vec<T> {
    let n = values.len();
    let like = &values[0];
    let pi = like.pi();
    (0..n)
        .map(|k| {
            let mut s = like.lit(0.0);
            for (j, v) in values.iter().enumerate() {
                // k(2j + 1) reduced modulo 4n keeps the angle in [0, 2π).
                let m = (k * (2 * j + 1)) % (4 * n);
                let angle = pi.clone() * like.lit(m as f64) / like.lit((2 * n) as f64);
                s = s + v.clone() * angle.cos();
            }
            s * like.lit(2.0) / like.lit(n as f64)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quad::Estimate;

    fn known(v: f64) -> Outcome<f64> {
        Ok(Estimate::known(v, 0.0, 1, Rule::TanhSinh))
    }

    /// Each piece keeps its own bar: samples with a noise of 10⁻³ of
    /// themselves on [0, 1] (where the tail cannot reach the goal: accepted
    /// at the noise) and none on [1, 3]; `parts_over` splits a range at
    /// the pieces' ends and stretches its ends beyond the covered range.
    #[test]
    fn pieces_keep_their_own_bars() {
        let f = |x: &f64| {
            let v = (-x).exp() * (1.0 + x * x);
            let noise = if *x < 1.0 { 1e-3 } else { 0.0 };
            Ok(Estimate::known(v, v * noise, 1, Rule::TanhSinh))
        };
        let p = Piecewise::build(f, &[0.0, 1.0, 3.0], 1e-12).unwrap();
        let (near, far) = (p.rel_error_at(&0.5), p.rel_error_at(&2.0));
        assert!(near >= 1e-3 && near == p.rel_error && far < 1e-11, "bars {near:e}, {far:e}");
        assert_eq!(p.rel_error_at(&-1.0), near, "clamped below");
        let parts = p.parts_over(&-0.5, &4.0);
        assert_eq!((parts[0].0, parts.last().unwrap().1), (-0.5, 4.0), "{parts:?}");
        assert!(parts.windows(2).all(|w| w[0].1 == w[1].0), "contiguous: {parts:?}");
        assert!(parts.iter().any(|q| q.0 == 1.0), "split at the piece end 1: {parts:?}");
        assert_eq!(p.parts_over(&1.5, &2.5).len(), p.parts_over(&1.5, &2.5).iter().filter(|q| q.2 == far).count());
    }

    #[test]
    fn interpolates_a_smooth_function_to_its_bar() {
        let cuts = [0.0, 1.0, 3.0];
        let p = Piecewise::build(|x: &f64| known((-x).exp() * (1.0 + x * x)), &cuts, 1e-13).unwrap();
        let mut worst = 0.0f64;
        for i in 0..=3000 {
            let x = 3.0 * i as f64 / 3000.0;
            let exact = (-x).exp() * (1.0 + x * x);
            worst = worst.max(((p.eval(&x) - exact) / exact).abs());
        }
        assert!(worst <= p.rel_error && p.rel_error < 1e-12, "worst {worst:e}, bar {:e}", p.rel_error);
    }

    #[test]
    fn graded_pieces_handle_x_log_x() {
        // 1 + x ln x on [0, 1], pieces graded towards the singular end.
        let mut cuts = vec![0.0];
        cuts.extend((0..=12).rev().map(|k| 10f64.powi(-k)));
        let f = |x: f64| 1.0 + x * x.ln();
        let p = Piecewise::build(|x: &f64| known(f(*x)), &cuts, 1e-12).unwrap();
        let mut worst = 0.0f64;
        for i in 1..=2000 {
            let x = (i as f64 / 2000.0).powi(6);
            worst = worst.max(((p.eval(&x) - f(x)) / f(x)).abs());
        }
        assert!(worst <= p.rel_error.max(1e-14), "worst {worst:e}, bar {:e}", p.rel_error);
    }

    /// The piece limit counts the bisections beyond the declared cuts: 600
    /// declared pieces of a smooth function build (a fixed total of 400
    /// refused them unsampled), and a function that would need ~10⁴ pieces
    /// still ends at the limit, with a message that says how it was reached.
    #[test]
    fn the_piece_limit_counts_bisections_beyond_the_declared_cuts() {
        let cuts: Vec<f64> = (0..=600).map(|k| k as f64 / 600.0).collect();
        let p = Piecewise::build(|x: &f64| known(1.0 + x * x), &cuts, 1e-12).unwrap();
        assert!(p.covers(&0.5) && p.rel_error < 1e-12);
        let wiggly = Piecewise::build(|x: &f64| known(2.0 + (1e5 * x).sin()), &cuts, 1e-12);
        let Err(failure) = wiggly else { panic!("~10⁴ pieces are not built") };
        let reason = failure.reason;
        assert!(reason.contains("more than 1000 pieces (600 declared, 400 more by bisection)"), "{reason}");
    }
}
