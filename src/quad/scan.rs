//! Structure scan: finds edges of support the caller did not pass.
//!
//! Samples each piece of [a, b] on a grid that is geometric towards both ends
//! (a + (b−a)2^{−k}, b − (b−a)2^{−k}, k = 1…K) and uniform inside (64 cells).
//! Between two neighbouring samples of which one is zero and the other not,
//! the edge is located by bisection to the working precision. Non-finite
//! samples fail the integral. A support that fits between two grid points
//! (narrower than (b−a)/64 away from the ends, or than (b−a)2^{−K} at them) is
//! not seen; the all-zero guard of the caller covers the case where it is the
//! whole support.

use super::{Failure, Mapped};
use crate::real::Real;

const UNIFORM_CELLS: usize = 64;

/// Geometric levels towards each end: down to 2^{-K} of the piece.
fn geometric_levels<T: Real>(like: &T) -> i32 {
    (like.prec() as i32).min(120)
}

pub(crate) fn find_edges<T: Real>(f: &mut Mapped<'_, '_, T>, a: &T, b: &T, cuts: &[T]) -> Result<Vec<T>, Failure<T>> {
    let mut edges: Vec<T> = vec![a.clone()];
    edges.extend(cuts.iter().cloned());
    edges.push(b.clone());
    edges.sort_by(|x, y| x.partial_cmp(y).expect("finite"));
    let mut found = Vec::new();
    for w in edges.windows(2) {
        let (lo, hi) = (&w[0], &w[1]);
        if !(lo < hi) {
            continue;
        }
        let width = hi.clone() - lo.clone();
        let mut xs: Vec<T> = Vec::new();
        for k in 1..=geometric_levels(lo) {
            let d = width.clone() * lo.powi_like(-k);
            xs.push(lo.clone() + d.clone());
            xs.push(hi.clone() - d);
        }
        for i in 1..UNIFORM_CELLS {
            xs.push(lo.clone() + width.clone() * lo.lit(i as f64 / UNIFORM_CELLS as f64));
        }
        xs.retain(|x| x > lo && x < hi);
        xs.sort_by(|x, y| x.partial_cmp(y).expect("finite"));
        xs.dedup_by(|x, y| x == y);
        let mut samples = Vec::with_capacity(xs.len());
        for x in xs {
            let zero = f.eval(&x)?.value.is_zero();
            samples.push((x, zero));
        }
        for pair in samples.windows(2) {
            if pair[0].1 != pair[1].1 {
                found.push(bisect_edge(f, &pair[0].0, &pair[1].0, pair[0].1)?);
            }
        }
    }
    Ok(found)
}

/// The point between `x0` (zero-ness `zero0`) and `x1` where the integrand
/// switches between zero and non-zero, to the working precision.
fn bisect_edge<T: Real>(f: &mut Mapped<'_, '_, T>, x0: &T, x1: &T, zero0: bool) -> Result<T, Failure<T>> {
    let (mut lo, mut hi) = (x0.clone(), x1.clone());
    for _ in 0..(lo.prec() + 8) {
        let mid = (lo.clone() + hi.clone()) / lo.lit(2.0);
        if !(mid > lo && mid < hi) {
            break;
        }
        if f.eval(&mid)?.value.is_zero() == zero0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(hi)
}
