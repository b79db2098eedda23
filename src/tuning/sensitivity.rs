//! How fast the RMSE degrades away from the optimum: for each parameter,
//! the range over which the RMSE stays within 10 % of the best with the
//! other three held at the optimum (renderers choose round numbers).
//! Scanned on a fine log grid (q: 1/64 decade; R: 1/32 decade, within the
//! radii searched; N_F, N_B: every integer up to 64, then ~1.5 % steps)
//! outwards from the optimum until the RMSE exceeds 1.1 × best or the bound
//! is reached.

use super::cost::Parameters;
use super::radii::RadiusCache;
use super::search::{Scored, MIN_Q};
use super::Searched;
use super::{Options, TuningError};
use mcrt_scene::Scene;
use serde::Serialize;

/// RMSE within this factor of the best counts as "near the optimum".
pub const TOLERANCE: f64 = 1.1;

/// The scan's step in q (a factor; 1/64 decade).
pub fn q_step() -> f64 {
    10f64.powf(1.0 / 64.0)
}

/// The next count above `v` the scan visits (+1 up to 64, then +1.5 %).
/// Ranges are contiguous from the optimum: with M = ⌊T/τ⌋ the RMSE jumps
/// as M steps down, so it may dip below the tolerance again further out.
pub fn count_up(v: f64) -> f64 {
    if v < 64.0 {
        v + 1.0
    } else {
        (v * 1.015).ceil()
    }
}

/// The next count below `v` the scan visits.
pub fn count_down(v: f64) -> f64 {
    if v <= 64.0 {
        v - 1.0
    } else {
        (v / 1.015).floor()
    }
}

/// One parameter's range within [`TOLERANCE`] of the best.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Range {
    /// The smallest value within tolerance found.
    pub lo: f64,
    /// The largest.
    pub hi: f64,
    /// Whether `lo` is the bound of the search (the range may go further).
    pub lo_at_bound: bool,
    /// Whether `hi` is the bound of the search.
    pub hi_at_bound: bool,
}

/// The four ranges (`radius` is `None` where the bias is not predicted and
/// R is held at the scene's; `q` and `camera_rays` are `None` where they
/// are held at 1, [`super::Searched::StandardMethod`]).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Sensitivity {
    /// q.
    pub q: Option<Range>,
    /// R.
    pub radius: Option<Range>,
    /// N_F.
    pub forward_rays: Range,
    /// N_B.
    pub camera_rays: Option<Range>,
}

/// The sensitivity of `best`.
pub fn of(
    scene: &Scene,
    opts: &Options,
    cache: &mut RadiusCache,
    best: &Scored,
    searched: Searched,
    range: (f64, f64),
) -> Result<Sensitivity, TuningError> {
    let c = searched.constraints(opts);
    let (held, bias_predicted) = (searched == Searched::StandardMethod, searched != Searched::HeldRadius);
    let limit = best.rmse.relative * TOLERANCE;
    let p0 = best.parameters;
    let at = cache.at(p0.radius)?;
    let score = |p: &Parameters| at.scored_at(scene, &opts.costs, &c, p).map_or(f64::INFINITY, |s| s.rmse.relative);
    let step = q_step();
    let q = (!held)
        .then(|| scan(p0.q, MIN_Q, 1.0, |v| v * step, |v| v / step, |v| score(&Parameters { q: v, ..p0 }), limit));
    // A ray count from `start` within [1, max], stepped by count_up/count_down.
    let ray_count = |start: u64, max: f64, with: &dyn Fn(u64) -> Parameters| {
        scan(start as f64, 1.0, max, count_up, count_down, |v| score(&with(v as u64)), limit)
    };
    let n_f = ray_count(p0.forward_rays, mcrt_scene::limits::MAX_FORWARD_RAYS as f64, &|n| Parameters {
        forward_rays: n,
        ..p0
    });
    let n_b = (!held).then(|| {
        ray_count(p0.camera_rays, mcrt_scene::limits::MAX_CAMERA_RAYS as f64, &|n| Parameters { camera_rays: n, ..p0 })
    });
    let radius = if bias_predicted {
        let (lo_bound, hi_bound) = range;
        let mut err = None;
        let cell = std::cell::RefCell::new(&mut *cache);
        let r = scan(
            p0.radius,
            lo_bound.min(p0.radius),
            hi_bound.max(p0.radius),
            |v| v * 10f64.powf(1.0 / 32.0),
            |v| v / 10f64.powf(1.0 / 32.0),
            |v| match cell.borrow_mut().at(v) {
                Ok(x) => x
                    .scored_at(scene, &opts.costs, &c, &Parameters { radius: v, ..p0 })
                    .map_or(f64::INFINITY, |s| s.rmse.relative),
                Err(e) => {
                    err.get_or_insert(e);
                    f64::INFINITY
                }
            },
            limit,
        );
        if let Some(e) = err {
            return Err(e);
        }
        Some(r)
    } else {
        None
    };
    Ok(Sensitivity { q, radius, forward_rays: n_f, camera_rays: n_b })
}

/// The range around `v0` where `f ≤ limit`, stepping by `up`/`down` within [lo, hi].
fn scan(
    v0: f64,
    lo: f64,
    hi: f64,
    up: impl Fn(f64) -> f64,
    down: impl Fn(f64) -> f64,
    mut f: impl FnMut(f64) -> f64,
    limit: f64,
) -> Range {
    let mut top = v0;
    let mut hi_at_bound = false;
    loop {
        let next = up(top).min(hi);
        if next <= top {
            hi_at_bound = true;
            break;
        }
        if f(next) > limit {
            break;
        }
        top = next;
        if top >= hi {
            hi_at_bound = true;
            break;
        }
    }
    let mut bottom = v0;
    let mut lo_at_bound = false;
    loop {
        let next = down(bottom).max(lo);
        if next >= bottom {
            lo_at_bound = true;
            break;
        }
        if f(next) > limit {
            break;
        }
        bottom = next;
        if bottom <= lo {
            lo_at_bound = true;
            break;
        }
    }
    Range { lo: bottom, hi: top, lo_at_bound, hi_at_bound }
}

#[cfg(test)]
mod tests {
    use super::scan;

    #[test]
    fn the_scan_finds_where_a_parabola_leaves_ten_per_cent() {
        // f = 1 + (x − 10)²/100: f ≤ 1.1 for |x − 10| ≤ √10 ≈ 3.162.
        let r = scan(10.0, 0.0, 100.0, |v| v + 0.001, |v| v - 0.001, |x| 1.0 + (x - 10.0).powi(2) / 100.0, 1.1);
        assert!((r.hi - (10.0 + 10f64.sqrt())).abs() < 2e-3 && (r.lo - (10.0 - 10f64.sqrt())).abs() < 2e-3, "{r:?}");
        assert!(!r.lo_at_bound && !r.hi_at_bound);
        let flat = scan(5.0, 1.0, 8.0, |v| v + 1.0, |v| v - 1.0, |_| 1.0, 1.1);
        assert!(flat.lo == 1.0 && flat.hi == 8.0 && flat.lo_at_bound && flat.hi_at_bound, "{flat:?}");
    }
}
