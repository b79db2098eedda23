//! The influence of one value on a z-score: how far deleting one value of
//! the samples' range moves it. A pass must not rest on one value.

use super::shape::Shape;

/// Points scanned on each side of the mean by [`influence`], before the
/// largest changes are refined.
const INFLUENCE_GRID: usize = 64;

/// The largest change of `z` when one value in `range` = [lo, hi] is
/// deleted from the samples: the supremum of |z(shape without y) − z(shape)|
/// over y in the range, scanned on a grid of [`INFLUENCE_GRID`] points each
/// side of the mean (ends included) and refined by golden-section search
/// around every local maximum. Infinite when deleting some y leaves no
/// spread or gives no finite z. The range is the samples' own smallest and
/// largest values: every value lies in it, so every single value's
/// influence is covered (up to the scan's resolution between grid points,
/// where the golden-section refinement finds the local maxima).
pub fn influence(shape: &Shape, range: (f64, f64), z: impl Fn(&Shape) -> f64) -> f64 {
    let z0 = z(shape);
    let change = |y: f64| shape.deleted(y).map(|s| (z(&s) - z0).abs()).filter(|d| d.is_finite());
    let (lo, hi) = (range.0.min(shape.mean), range.1.max(shape.mean));
    let mut grid: Vec<f64> = (0..=INFLUENCE_GRID)
        .map(|k| lo + (shape.mean - lo) * k as f64 / INFLUENCE_GRID as f64)
        .chain((1..=INFLUENCE_GRID).map(|k| shape.mean + (hi - shape.mean) * k as f64 / INFLUENCE_GRID as f64))
        .collect();
    grid.dedup();
    let mut values = Vec::with_capacity(grid.len());
    for &y in &grid {
        match change(y) {
            Some(d) => values.push(d),
            None => return f64::INFINITY,
        }
    }
    let mut best = values.iter().copied().fold(0.0, f64::max);
    for k in 0..values.len() {
        let left = if k > 0 { values[k - 1] } else { f64::NEG_INFINITY };
        let right = values.get(k + 1).copied().unwrap_or(f64::NEG_INFINITY);
        if values[k] >= left && values[k] >= right {
            let a = grid[k.saturating_sub(1)];
            let b = grid[(k + 1).min(grid.len() - 1)];
            match golden_max(&change, a, b) {
                Some(d) => best = best.max(d),
                None => return f64::INFINITY,
            }
        }
    }
    best
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
