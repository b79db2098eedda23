//! Maps of the predicted relative RMSE around the optimum: over (q, R)
//! with N_F and N_B at the optimum's values, and over (q, N_B/N_F) at the
//! optimum's R with the scale of the ray counts chosen best in each cell
//! (N_F over its grid, N_B = max(1, round(ρ N_F))). Cells where no point
//! fits the budget or the bounds, or where the model lacks the pair
//! integrals that point needs (single-scattered light at q < 1 or N_B > 1,
//! `ModelAtRadius::variance`), are `None`; `mcrt-noise optimize --maps`
//! refuses such scenes.

use super::cost::Parameters;
use super::radii::RadiusCache;
use super::search::{log_integers, Constraints, Scored};
use super::{Options, TuningError};
use mcrt_scene::Scene;
use serde::Serialize;

/// A map: values on a log-spaced grid.
#[derive(Debug, Clone, Serialize)]
pub struct Map {
    /// What the x axis is, e.g. "q".
    pub x_name: String,
    /// What the y axis is, e.g. "R".
    pub y_name: String,
    /// x values (ascending).
    pub x: Vec<f64>,
    /// y values (ascending).
    pub y: Vec<f64>,
    /// rel. RMSE at (`x[i]`, `y[j]`) as `values[j][i]`.
    pub values: Vec<Vec<Option<f64>>>,
    /// Where the optimum lies, (x, y).
    pub optimum: (f64, f64),
}

/// `n` log-spaced values from `lo` to `hi`.
fn log_grid(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n).map(|k| lo * (hi / lo).powf(k as f64 / (n - 1) as f64)).collect()
}

/// RMSE over (q, R), N_F and N_B at `best`'s.
pub fn q_and_radius(
    scene: &Scene,
    opts: &Options,
    cache: &mut RadiusCache,
    best: &Scored,
    (lo, hi): (f64, f64),
    n: usize,
) -> Result<Map, TuningError> {
    let c = Constraints::free(opts.budget, opts.max_spheres);
    let qs = log_grid(1e-3, 1.0, n);
    let rs = log_grid(lo, hi, n);
    let mut values = Vec::new();
    for &r in &rs {
        let at = cache.at(r)?;
        values.push(
            qs.iter()
                .map(|&q| {
                    let p = Parameters { q, radius: r, ..best.parameters };
                    at.scored_at(scene, &opts.costs, &c, &p).map(|s| s.rmse.relative)
                })
                .collect(),
        );
    }
    Ok(Map {
        x_name: "q".into(),
        y_name: "R".into(),
        x: qs,
        y: rs,
        values,
        optimum: (best.parameters.q, best.parameters.radius),
    })
}

/// RMSE over (q, ρ = N_B/N_F) at `best`'s R, the best N_F per cell.
pub fn q_and_ray_ratio(
    scene: &Scene,
    opts: &Options,
    cache: &mut RadiusCache,
    best: &Scored,
    n: usize,
) -> Result<Map, TuningError> {
    let c = Constraints::free(opts.budget, opts.max_spheres);
    let at = cache.at(best.parameters.radius)?;
    let qs = log_grid(1e-3, 1.0, n);
    let rhos = log_grid(1e-5, 10.0, n);
    let nfs = log_integers(mcrt_scene::limits::MAX_FORWARD_RAYS as u64);
    let values = rhos
        .iter()
        .map(|&rho| {
            qs.iter()
                .map(|&q| {
                    nfs.iter()
                        .filter_map(|&n_f| {
                            let n_b = ((rho * n_f as f64).round() as u64).max(1);
                            let p = Parameters { q, forward_rays: n_f, camera_rays: n_b, ..best.parameters };
                            at.scored_at(scene, &opts.costs, &c, &p).map(|s| s.rmse.relative)
                        })
                        .min_by(f64::total_cmp)
                })
                .collect()
        })
        .collect();
    let p = best.parameters;
    Ok(Map {
        x_name: "q".into(),
        y_name: "N_B/N_F".into(),
        x: qs,
        y: rhos,
        values,
        optimum: (p.q, p.camera_rays as f64 / p.forward_rays as f64),
    })
}
