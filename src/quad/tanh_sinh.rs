//! Primary rule: tanh–sinh (double-exponential) quadrature, refined level by
//! level on each piece, pieces bisected when the level cap is reached, under
//! global error control.

use super::nodes::{tanh_sinh_level, TsNode};
use super::{control, Failure, Mapped, Options, Piece, RuleResult};
use crate::real::Real;
use std::sync::Arc;

/// Levels computed before a panel's first error estimate (h = 1/4; 31 points
/// in f64): three levels give the two differences d₂, d₁ of the estimate.
const START_LEVEL: usize = 2;

/// Highest level before a panel is bisected instead: h = 1/128 in f64.
/// Tanh–sinh's error roughly squares per level, so each doubling of the
/// precision needs about one more level: 8 + ⌈log₂(p/53)⌉, capped by the
/// linear rule used up to 256 bits (7, 7, 8, 9, 11 at 64, 96, 128, 192,
/// 256 bits; 12 at 512, 13 at 1000, 15 at 4096). The linear rule alone
/// asked for level 26 at 1000 bits and 91 at 4096: 2^26 nodes per panel,
/// a table that never finished building (`kernel --precision 1000` hung).
fn max_level<T: Real>(like: &T) -> usize {
    let p = like.prec() as usize;
    let linear = 7 + p.saturating_sub(53) / 48;
    let doublings = (p.max(53) as f64 / 53.0).log2().ceil() as usize;
    linear.min(8 + doublings)
}

/// The levels of the node table a run has fetched so far (each level is
/// built once per thread and precision, on first use).
struct Levels<T> {
    like: T,
    levels: Vec<Arc<Vec<TsNode<T>>>>,
}

impl<T: Real + 'static> Levels<T> {
    fn new(like: &T) -> Self {
        Levels { like: like.clone(), levels: Vec::new() }
    }
    fn get(&mut self, level: usize) -> Arc<Vec<TsNode<T>>> {
        while self.levels.len() <= level {
            let next = tanh_sinh_level(&self.like, self.levels.len());
            self.levels.push(next);
        }
        self.levels[level].clone()
    }
}

/// One panel [a, b] integrated through `level`.
struct Panel<T> {
    a: T,
    b: T,
    level: usize,
    /// Σ over nodes of levels ≤ `level` of w·f (centre once, pairs ±), and the
    /// same for the inner error bars and for |w·f|.
    sum: T,
    err_sum: T,
    abs_sum: T,
    value: T,
    prev_value: T,
    prev2_value: T,
    prev3_value: T,
}

impl<T: Real> control::Panel<T> for Panel<T> {
    fn value(&self) -> T {
        self.value.clone()
    }
    fn quad_err(&self) -> T {
        self.quad_err()
    }
    fn floor(&self) -> T {
        self.floor()
    }
    fn error(&self) -> T {
        self.quad_err() + self.inner_err() + self.floor()
    }
}

impl<T: Real> Panel<T> {
    fn half(&self) -> T {
        (self.b.clone() - self.a.clone()) / self.a.lit(2.0)
    }
    fn h(&self) -> T {
        self.a.powi_like(-(self.level as i32))
    }
    /// Truncation estimate. With d₁ = |S_k − S_{k−1}| and d₂ = |S_{k−1} − S_{k−2}|:
    /// e_k ≈ d₁·(d₁/d₂) once the differences shrink, d₁ before. Tanh–sinh's
    /// error roughly squares per level, so this ratio estimate still lags the
    /// truth by a level; the sharper exponent model d₁(d₁/d₂)² (Bailey's) was
    /// tried and stops too early on I(10⁻⁶, 10⁻³) (the cross-check then
    /// refuses the result). This estimate steers the refinement; the reported
    /// bar also answers to the cross-check's conservative one (`reconcile`).
    fn quad_err(&self) -> T {
        let d1 = (self.value.clone() - self.prev_value.clone()).abs();
        let d2 = (self.prev_value.clone() - self.prev2_value.clone()).abs();
        let d3 = (self.prev2_value.clone() - self.prev3_value.clone()).abs();
        // Only once three differences shrink, and then with the larger
        // (older) of the last two ratios: a single small difference can be a
        // coincidence of the error's sign pattern.
        if self.level >= 3 && d1 < d2 && d2 < d3 {
            let ratio = (d1.clone() / d2.clone()).max_of(d2 / d3);
            d1 * ratio
        } else {
            d1
        }
    }
    fn inner_err(&self) -> T {
        self.half() * self.h() * self.err_sum.clone()
    }
    /// Rounding floor: 8 eps Σ|w f|.
    fn floor(&self) -> T {
        self.a.eps() * self.a.lit(8.0) * self.half().abs() * self.h() * self.abs_sum.clone()
            + self.a.underflow_floor() / self.a.lit(1024.0)
    }
}

/// Adds the nodes of `level` (which must be `p.level + 1`, or 0 for a new panel).
fn add_level<T: Real + 'static>(
    p: &mut Panel<T>,
    level: usize,
    table: &mut Levels<T>,
    f: &mut Mapped<'_, '_, T>,
) -> Result<(), Failure<T>> {
    let half = p.half();
    // A node closer to an end than a few ulps of that end's magnitude cannot
    // be placed there (it would round onto the end). If its weight is below
    // eps it is dropped; otherwise it is placed at that distance, keeping its
    // weight. Both rules depend on the node alone, so every level treats the
    // ends alike and the level differences converge. (On a panel short
    // against its position, say [−1, −1 + 10⁻¹²], dropping all such nodes
    // would lose a different 7 % of the weight at every level.) An end at 0
    // has no such zone: nodes approach it down to the underflow.
    let reach = |end: &T| end.abs() * end.eps() * end.lit(4.0);
    let (reach_a, reach_b) = (reach(&p.a), reach(&p.b));
    let negligible = p.a.eps();
    let place = |end: &T, offset: &T, reach: &T, toward_b: bool, comp: &T| -> Option<T> {
        let off = if offset < reach {
            if *comp < negligible || !(reach.clone() < half.clone()) {
                return None;
            }
            reach.clone()
        } else {
            offset.clone()
        };
        Some(if toward_b { end.clone() + off } else { end.clone() - off })
    };
    let nodes = table.get(level);
    for (i, node) in nodes.iter().enumerate() {
        let centre = level == 0 && i == 0;
        let offset = half.clone() * node.comp.clone();
        let points = if centre {
            [Some((p.a.clone() + p.b.clone()) / p.a.lit(2.0)), None]
        } else {
            [place(&p.a, &offset, &reach_a, true, &node.comp), place(&p.b, &offset, &reach_b, false, &node.comp)]
        };
        for x in points.into_iter().flatten() {
            // Far nodes may round onto (or past) an end: their weight is
            // below eps², so they are dropped rather than evaluated there.
            if !(x > p.a && x < p.b) {
                continue;
            }
            let s = f.eval(&x)?;
            p.sum = p.sum.clone() + node.weight.clone() * s.value.clone();
            p.err_sum = p.err_sum.clone() + node.weight.clone() * s.error;
            p.abs_sum = p.abs_sum.clone() + node.weight.clone() * s.value.abs();
        }
    }
    p.level = level;
    p.prev3_value = p.prev2_value.clone();
    p.prev2_value = p.prev_value.clone();
    p.prev_value = p.value.clone();
    p.value = p.half() * p.h() * p.sum.clone();
    Ok(())
}

fn new_panel<T: Real + 'static>(
    a: T,
    b: T,
    table: &mut Levels<T>,
    f: &mut Mapped<'_, '_, T>,
) -> Result<Panel<T>, Failure<T>> {
    let zero = a.lit(0.0);
    let mut p = Panel {
        level: 0,
        sum: zero.clone(),
        err_sum: zero.clone(),
        abs_sum: zero.clone(),
        value: zero.clone(),
        prev_value: zero.clone(),
        prev2_value: zero.clone(),
        prev3_value: zero,
        a,
        b,
    };
    for level in 0..=START_LEVEL {
        add_level(&mut p, level, table, f)?;
    }
    Ok(p)
}

/// Integrates all pieces to the goal of `opts` (or as close as the budget and
/// the rounding floor allow; the caller judges the final error bar).
pub(crate) fn integrate<T: Real + 'static>(
    f: &mut Mapped<'_, '_, T>,
    pieces: &[Piece<T>],
    opts: &Options,
) -> Result<RuleResult<T>, Failure<T>> {
    let like = pieces[0].a.clone();
    let mut table = Levels::new(&like);
    let top = max_level(&like);
    let mut panels = Vec::with_capacity(pieces.len());
    for piece in pieces {
        panels.push(new_panel(piece.a.clone(), piece.b.clone(), &mut table, f)?);
    }
    while let Some(worst) = control::next_to_refine(&panels, &like, f, opts, "tanh-sinh")? {
        if panels[worst].level < top {
            let next = panels[worst].level + 1;
            add_level(&mut panels[worst], next, &mut table, f)?;
        } else {
            let mid = control::midpoint(&panels[worst].a, &panels[worst].b, &panels, f)?;
            let p = panels.swap_remove(worst);
            panels.push(new_panel(p.a.clone(), mid.clone(), &mut table, f)?);
            panels.push(new_panel(mid, p.b, &mut table, f)?);
        }
    }
    Ok(control::result(&panels, &like))
}
