//! Global error control shared by both rules: refine the panel with the
//! largest truncation estimate until the summed error meets the goal, the
//! rounding floor is reached, or the budget runs out.

use super::{goal, Failure, Mapped, Options, RuleResult};
use crate::real::Real;

/// What global control needs to know of a panel.
pub(crate) trait Panel<T> {
    fn value(&self) -> T;
    /// Truncation estimate (what refining the panel can reduce).
    fn quad_err(&self) -> T;
    /// Rounding floor of the panel (what refining cannot reduce).
    fn floor(&self) -> T;
    /// Total error: truncation + inner bars + floor.
    fn error(&self) -> T;
}

/// Panels one rule may bisect an integral into before it is declared not to
/// converge. Every integral of the test suite and of the bundled scenes
/// (f64 and MPFR, the hard cases of `tests/oracle.rs` and `tests/finite.rs`
/// included) needed fewer than 50; a rule that keeps bisecting is stuck on
/// something it cannot resolve (noise in the integrand, a wrong rule), and
/// the control's cost grows with the square of the panel count, so a stuck
/// rule must end here rather than after millions of evaluations.
pub(crate) const MAX_PANELS: usize = 2000;

/// The next panel to refine, or `None` when the goal is met or no panel can
/// improve (every truncation estimate at its rounding floor). Fails when the
/// evaluation budget (this level's or the computation's) is spent, or the
/// panels number [`MAX_PANELS`].
pub(crate) fn next_to_refine<T: Real, P: Panel<T>>(
    panels: &[P],
    like: &T,
    f: &Mapped<'_, '_, T>,
    opts: &Options,
    rule: &str,
) -> Result<Option<usize>, Failure<T>> {
    let (value, error) = totals(panels, like);
    if error <= goal(&value, opts) {
        return Ok(None);
    }
    let (worst, worst_err) = panels
        .iter()
        .enumerate()
        .map(|(i, p)| (i, p.quad_err()))
        .fold((0, like.lit(-1.0)), |acc, (i, e)| if e > acc.1 { (i, e) } else { acc });
    if worst_err <= panels[worst].floor() {
        return Ok(None);
    }
    if panels.len() >= MAX_PANELS {
        let reason = format!(
            "{rule} bisected into {} panels without meeting the goal (limit {MAX_PANELS}): {}",
            panels.len(),
            error_split(panels, &error, &goal(&value, opts))
        );
        return Err(f.fail(reason, Some((value, error))));
    }
    // Where the error of the level that stops lies, as for the panel limit:
    // whether refining was still paying or inner bars had filled its goal.
    let split = || error_split(panels, &error, &goal(&value, opts));
    if let Some(reason) = opts.budget.exhausted() {
        return Err(f.fail(format!("{reason}; stopped in {rule} ({})", split()), Some((value, error))));
    }
    if f.tally.calls >= opts.max_evals {
        let reason = format!("evaluation budget {} exhausted by {rule} ({})", opts.max_evals, split());
        return Err(f.fail(reason, Some((value, error))));
    }
    Ok(Some(worst))
}

/// Where a stuck rule's error lies (at the panel limit, or where the
/// budget ran out): its total against the goal, split into
/// the truncation estimates (what refining shrinks) and the bars the
/// samples carried in (inner integrals', tables'), which refining does
/// not shrink; when those alone fill half the goal, the reason says so,
/// since the inner goals are then what must change, not this level.
fn error_split<T: Real, P: Panel<T>>(panels: &[P], error: &T, goal: &T) -> String {
    let zero = error.lit(0.0);
    let truncation = panels.iter().fold(zero.clone(), |a, p| a + p.quad_err());
    let rounding = panels.iter().fold(zero.clone(), |a, p| a + p.floor());
    let carried = (error.clone() - truncation.clone() - rounding).max_of(zero);
    let hint = if carried.clone() * error.lit(2.0) >= *goal {
        "; the samples' own bars fill at least half of what it aims at, and refining does not shrink them"
    } else {
        ""
    };
    format!(
        "error {:.3e} against the {:.3e} it aims at, of which truncation {:.3e} and the samples' own bars {:.3e}{hint}",
        error.to_f64(),
        goal.to_f64(),
        truncation.to_f64(),
        carried.to_f64()
    )
}

/// The panel's midpoint, or a failure when it cannot be bisected further.
pub(crate) fn midpoint<T: Real, P: Panel<T>>(
    a: &T,
    b: &T,
    panels: &[P],
    f: &Mapped<'_, '_, T>,
) -> Result<T, Failure<T>> {
    let mid = (a.clone() + b.clone()) / a.lit(2.0);
    if mid > *a && mid < *b {
        return Ok(mid);
    }
    let like = a.clone();
    Err(f.fail(format!("panel at {:e} cannot be bisected further", a.to_f64()), Some(totals(panels, &like))))
}

/// (Σ values, Σ errors).
fn totals<T: Real, P: Panel<T>>(panels: &[P], like: &T) -> (T, T) {
    let zero = like.lit(0.0);
    panels.iter().fold((zero.clone(), zero), |(v, e), p| (v + p.value(), e + p.error()))
}

/// The result of a rule once control is done. Its bar includes one
/// underflow floor for the whole integral (the panels carry 1/1024 of it
/// each, only to stop refining below it).
pub(crate) fn result<T: Real, P: Panel<T>>(panels: &[P], like: &T) -> RuleResult<T> {
    let (value, error) = totals(panels, like);
    RuleResult { value, error: error + like.underflow_floor(), pieces: panels.len() }
}
