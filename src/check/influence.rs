//! The influence of one value on a z-score: how far deleting one value of
//! the samples' range moves it. A pass must not rest on one value.

use super::shape::Shape;

/// Points scanned on each side of the mean by [`influence`], before the
/// extremes are refined.
const INFLUENCE_GRID: usize = 64;

/// What deleting one value does to a z-score.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Influence {
    /// The largest change, sup |z(S∖y) − z(S)| (infinite when deleting some
    /// value leaves no spread or no finite z).
    pub largest_change: f64,
    /// The least z of the samples with one value deleted (or of the
    /// samples themselves).
    pub lowest: f64,
    /// The greatest.
    pub highest: f64,
}

impl Influence {
    fn unbounded() -> Influence {
        Influence { largest_change: f64::INFINITY, lowest: f64::NEG_INFINITY, highest: f64::INFINITY }
    }
}

/// What deleting one value in `range` = [lo, hi] does to `z`: the least
/// and greatest z(shape without y) over y in the range, scanned on a grid
/// of [`INFLUENCE_GRID`] points each side of the mean (ends included) and
/// refined by golden-section search around every local extreme. The range
/// is the samples' own smallest and largest values: every value lies in
/// it, so every single value's deletion is covered (to the refinement's
/// resolution, 10⁻¹² of a grid step).
pub fn influence(shape: &Shape, range: (f64, f64), z: impl Fn(&Shape) -> f64) -> Influence {
    let z0 = z(shape);
    let deleted = |y: f64| shape.deleted(y).map(|s| z(&s)).filter(|z| z.is_finite());
    let (lo, hi) = (range.0.min(shape.mean), range.1.max(shape.mean));
    let mut grid: Vec<f64> = (0..=INFLUENCE_GRID)
        .map(|k| lo + (shape.mean - lo) * k as f64 / INFLUENCE_GRID as f64)
        .chain((1..=INFLUENCE_GRID).map(|k| shape.mean + (hi - shape.mean) * k as f64 / INFLUENCE_GRID as f64))
        .collect();
    grid.dedup();
    let mut values = Vec::with_capacity(grid.len());
    for &y in &grid {
        match deleted(y) {
            Some(v) => values.push(v),
            None => return Influence::unbounded(),
        }
    }
    let (mut lowest, mut highest) = (z0, z0);
    for sign in [1.0, -1.0] {
        for k in 0..values.len() {
            let at = |j: usize| sign * values[j];
            let left = if k > 0 { at(k - 1) } else { f64::NEG_INFINITY };
            let right = if k + 1 < values.len() { at(k + 1) } else { f64::NEG_INFINITY };
            if at(k) < left || at(k) < right {
                continue;
            }
            let (a, b) = (grid[k.saturating_sub(1)], grid[(k + 1).min(grid.len() - 1)]);
            match golden_max(&|y: f64| deleted(y).map(|v| sign * v), a, b) {
                Some(m) if sign > 0.0 => highest = highest.max(m).max(values[k]),
                Some(m) => lowest = lowest.min(-m).min(values[k]),
                None => return Influence::unbounded(),
            }
        }
    }
    Influence { largest_change: (highest - z0).max(z0 - lowest), lowest, highest }
}

/// z of the samples with their k largest values deleted, for k = 2 … the
/// number given (descending); `None` for a k whose deletion leaves no
/// spread or no finite z.
pub fn without_largest(shape: &Shape, largest: &[f64], z: impl Fn(&Shape) -> f64) -> Vec<(usize, Option<f64>)> {
    let mut current = Some(*shape);
    let mut out = Vec::new();
    for (i, y) in largest.iter().enumerate() {
        current = current.and_then(|s| s.deleted(*y));
        if i >= 1 {
            out.push((i + 1, current.map(|s| z(&s)).filter(|z| z.is_finite())));
        }
    }
    out
}

/// The maximum of `f` on [a, b] by golden-section search (60 steps:
/// the bracket shrinks by 10⁻¹²).
fn golden_max(f: &impl Fn(f64) -> Option<f64>, mut a: f64, mut b: f64) -> Option<f64> {
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let mut x1 = b - ratio * (b - a);
    let mut x2 = a + ratio * (b - a);
    let (mut f1, mut f2) = (f(x1)?, f(x2)?);
    let mut best = f1.max(f2);
    for _ in 0..60 {
        if f1 < f2 {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + ratio * (b - a);
            f2 = f(x2)?;
        } else {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - ratio * (b - a);
            f1 = f(x1)?;
        }
        best = best.max(f1).max(f2);
    }
    Some(best)
}
