//! Choosing the estimator's parameters: the (q, R, N_F, N_B) with the least
//! predicted relative RMSE after a wall-time budget, bias included (the
//! seed paper's purpose, §1 and §5).
//!
//! - [`cost`]: the cost of one iteration, expected operation counts times
//!   per-operation costs;
//! - [`rates`]: the geometric rates the counts need (searching and hitting
//!   segments), measured by walking forward rays;
//! - [`calibration`]: per-operation costs fitted from timed tracer runs;
//! - [`objective`]: RMSE = √(b(R)² + Var L/M) after the budget, M = T/τ;
//! - [`search`]: the search over (q, N_F, N_B) at one R, explicit in them;
//! - [`radii`]: the model and rates per radius, computed once;
//! - [`optimize`] (here): the search over R, the comparisons (q = 1,
//!   several spheres per camera ray (q ≤ 1/2), the cylinder limit, the
//!   scene's own parameters, the asymptotic rule's R, N_B = 1) and the
//!   sensitivity of the optimum.
//!
//! Where the finite-sphere model does not cover the scene (scattered
//! light), the bias is not predicted: R is held at the scene's and only
//! (q, N_F, N_B) are chosen, for the noise alone.

pub mod calibration;
pub mod cost;
pub mod maps;
pub mod objective;
pub mod radii;
pub mod rates;
pub mod reference_costs;
pub mod search;
pub mod sensitivity;

use crate::model::OracleError;
use crate::quad::Budget;
use cost::{CostTable, Parameters};
use mcrt_scene::Scene;
use radii::RadiusCache;
use search::{golden, Constraints, Radius, Scored};
use serde::Serialize;

/// Why an optimisation failed.
#[derive(Debug, Clone, PartialEq)]
pub enum TuningError {
    /// The oracle failed at some radius.
    Oracle(OracleError),
    /// A radius the scene or the tracer cannot take, or its rates failed.
    Radius(f64, String),
    /// No parameters fit the budget (one iteration takes longer).
    Infeasible(String),
    /// A bad option (the message names it, its value and the range).
    Option(String),
}

impl std::fmt::Display for TuningError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TuningError::Oracle(e) => write!(f, "{e}"),
            TuningError::Radius(r, why) => write!(f, "R = {r:e}: {why}"),
            TuningError::Infeasible(why) | TuningError::Option(why) => f.write_str(why),
        }
    }
}

impl std::error::Error for TuningError {}

/// What to optimise for.
#[derive(Debug, Clone)]
pub struct Options {
    /// The wall-time budget T, seconds of one core.
    pub budget: f64,
    /// At most this many spheres per iteration (memory), if given.
    pub max_spheres: Option<f64>,
    /// The radii searched, [lo, hi] (finite-sphere scenes; default σR in [10⁻³, 0.5]).
    pub radius_range: Option<(f64, f64)>,
    /// Per-operation costs.
    pub costs: CostTable,
    /// Oracle evaluations for the whole optimisation (every radius).
    pub evaluations: u64,
}

impl Options {
    /// A budget of `seconds` with `costs`, default range and evaluations.
    pub fn new(seconds: f64, costs: CostTable) -> Options {
        Options {
            budget: seconds,
            max_spheres: None,
            radius_range: None,
            costs,
            evaluations: crate::quad::DEFAULT_EVALUATIONS,
        }
    }
}

/// One alternative beside the optimum.
#[derive(Debug, Clone, Serialize)]
pub struct Alternative {
    /// Its name, e.g. "q = 1 (one sphere per camera ray)".
    pub name: String,
    /// Its best parameters and RMSE, or why there are none.
    pub scored: Result<Scored, String>,
    /// How it was chosen.
    pub note: String,
}

/// The optimisation's answer.
#[derive(Debug, Clone, Serialize)]
pub struct Optimum {
    /// `"finite-sphere"` or `"small-sphere"`.
    pub model: &'static str,
    /// Whether the bias b(R) is predicted (finite-sphere model).
    pub bias_predicted: bool,
    /// The constraints searched under.
    pub budget: f64,
    /// The memory limit, if any.
    pub max_spheres: Option<f64>,
    /// The radii searched.
    pub radius_range: (f64, f64),
    /// The costs used.
    pub costs: CostTable,
    /// The best parameters.
    pub best: Scored,
    /// The comparisons.
    pub alternatives: Vec<Alternative>,
    /// The range of each parameter within 10 % of the best RMSE.
    pub sensitivity: sensitivity::Sensitivity,
    /// Every radius evaluated (model and rates), ascending.
    pub radii: Vec<Radius>,
}

/// The best parameters for `scene` under `opts`.
///
/// ```no_run
/// use mcrt_noise::tuning::{optimize, cost::CostTable, Options};
/// let scene = mcrt_noise::Scene::from_toml_str(&std::fs::read_to_string("scenes/point-isotropic.toml")?)?;
/// let best = optimize(&scene, &Options::new(1.0, CostTable::reference_machine()))?;
/// println!("{:?}: relative RMSE {:.3e}", best.best.parameters, best.best.rmse.relative);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn optimize(scene: &Scene, opts: &Options) -> Result<Optimum, TuningError> {
    check_options(opts)?;
    let mut cache = RadiusCache::new(scene, Budget::new(opts.evaluations), None);
    optimize_with(scene, opts, &mut cache)
}

/// [`optimize`] with the radii's models kept in `cache` (for maps after it).
pub fn optimize_with(scene: &Scene, opts: &Options, cache: &mut RadiusCache) -> Result<Optimum, TuningError> {
    check_options(opts)?;
    let own = cache.at(scene.estimator.radius)?;
    let bias_predicted = own.model.bias.is_some();
    let sigma = scene.medium.sigma_ext;
    let range = opts.radius_range.unwrap_or((1e-3 / sigma, 0.5 / sigma));
    let free = Constraints::free(opts.budget, opts.max_spheres);
    let best = if bias_predicted {
        best_over_radii(scene, opts, cache, &free, range)?
    } else {
        own.best(scene, &opts.costs, &free).ok_or_else(|| infeasible(opts, scene))?
    };
    let alternatives = alternatives(scene, opts, cache, &best, range, bias_predicted)?;
    let sensitivity = sensitivity::of(scene, opts, cache, &best, bias_predicted)?;
    Ok(Optimum {
        model: own.model.model,
        bias_predicted,
        budget: opts.budget,
        max_spheres: opts.max_spheres,
        radius_range: if bias_predicted { range } else { (scene.estimator.radius, scene.estimator.radius) },
        costs: opts.costs.clone(),
        best,
        alternatives,
        sensitivity,
        radii: cache.all(),
    })
}

fn check_options(opts: &Options) -> Result<(), TuningError> {
    if !(opts.budget.is_finite() && opts.budget > 0.0 && opts.budget <= 1e9) {
        return Err(TuningError::Option(format!("--budget {}: must be seconds in (0, 1e9]", opts.budget)));
    }
    if let Some(m) = opts.max_spheres {
        if !(m.is_finite() && m >= 1.0) {
            return Err(TuningError::Option(format!("--max-spheres {m}: must be a count >= 1")));
        }
    }
    if let Some((lo, hi)) = opts.radius_range {
        if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && lo < hi) {
            return Err(TuningError::Option(format!("--radius-range {lo},{hi}: must be 0 < lo < hi, finite")));
        }
    }
    opts.costs.validate().map_err(TuningError::Option)
}

fn infeasible(opts: &Options, scene: &Scene) -> TuningError {
    TuningError::Infeasible(format!(
        "no parameters fit a budget of {} s: one iteration with N_F = N_B = 1, q = 1 takes longer at these \
         costs (R = {})",
        opts.budget, scene.estimator.radius
    ))
}

/// The best point over R: a grid of 4 radii per decade over `range`, then
/// golden section on log R around the best grid point.
fn best_over_radii(
    scene: &Scene,
    opts: &Options,
    cache: &mut RadiusCache,
    c: &Constraints,
    (lo, hi): (f64, f64),
) -> Result<Scored, TuningError> {
    let steps = ((hi / lo).log10() * 4.0).ceil().max(2.0) as usize;
    let grid: Vec<f64> = (0..=steps).map(|k| lo * (hi / lo).powf(k as f64 / steps as f64)).collect();
    let mut scored = Vec::new();
    for &r in &grid {
        scored.push(cache.at(r)?.best(scene, &opts.costs, c));
    }
    let (k, best) = scored
        .iter()
        .enumerate()
        .filter_map(|(k, s)| s.map(|s| (k, s)))
        .min_by(|a, b| a.1.rmse.relative.total_cmp(&b.1.rmse.relative))
        .ok_or_else(|| infeasible(opts, scene))?;
    let (a, b) = (grid[k.saturating_sub(1)].ln(), grid[(k + 1).min(grid.len() - 1)].ln());
    // Golden section needs the cache mutably inside a Fn: collect the
    // evaluations through a RefCell.
    let cell = std::cell::RefCell::new(cache);
    let err = std::cell::RefCell::new(None);
    let f = |lr: f64| {
        let mut cache = cell.borrow_mut();
        match cache.at(lr.exp()) {
            Ok(x) => x.best(scene, &opts.costs, c).map_or(f64::INFINITY, |s| s.rmse.relative),
            Err(e) => {
                err.borrow_mut().get_or_insert(e);
                f64::INFINITY
            }
        }
    };
    let refined = golden(a, b, 16, f);
    if let Some(e) = err.into_inner() {
        return Err(e);
    }
    let cache = cell.into_inner();
    Ok(match refined.and_then(|lr| cache.at(lr.exp()).ok()).and_then(|x| x.best(scene, &opts.costs, c)) {
        Some(s) if s.rmse.relative < best.rmse.relative => s,
        _ => best,
    })
}

/// The comparisons: q = 1, the cylinder limit, the scene's own parameters,
/// the asymptotic rule's R, N_B = 1.
fn alternatives(
    scene: &Scene,
    opts: &Options,
    cache: &mut RadiusCache,
    best: &Scored,
    range: (f64, f64),
    bias_predicted: bool,
) -> Result<Vec<Alternative>, TuningError> {
    let free = Constraints::free(opts.budget, opts.max_spheres);
    let fixed_r = |cache: &mut RadiusCache, c: &Constraints| -> Result<Option<Scored>, TuningError> {
        if bias_predicted {
            best_over_radii(scene, opts, cache, c, range).map(Some).or_else(|e| match e {
                TuningError::Infeasible(_) => Ok(None),
                e => Err(e),
            })
        } else {
            Ok(cache.at(scene.estimator.radius)?.best(scene, &opts.costs, c))
        }
    };
    let none = |what: &str| format!("no {what} parameters fit the budget");
    let mut out = Vec::new();
    let q1 = fixed_r(cache, &Constraints { q: Some(1.0), ..free })?;
    out.push(Alternative {
        name: "q = 1 (one sphere per camera ray, the standard method)".into(),
        scored: q1.ok_or_else(|| none("q = 1")),
        note: "R, N_F, N_B optimised with q held at 1".into(),
    });
    let several = fixed_r(cache, &Constraints { q_max: Some(0.5), ..free })?;
    out.push(Alternative {
        name: "several spheres per camera ray (q ≤ 1/2)".into(),
        scored: several.ok_or_else(|| none("q ≤ 1/2")),
        note: "R, q, N_F, N_B optimised with q at most 1/2 (at least two spheres per camera ray on average)".into(),
    });
    let cyl = fixed_r(cache, &Constraints { cylinder: true, ..free })?;
    out.push(Alternative {
        name: "q → 0 (the cylinder limit)".into(),
        scored: cyl.ok_or_else(|| none("cylinder")),
        note: "Var L at q = 0 in closed form ((7)–(9) with q = 0); cost of one integration volume per camera \
               ray and one contribution per crossing segment (the sphere method itself would need 1/q → ∞ \
               spheres); R, N_F, N_B optimised"
            .into(),
    });
    let own = Parameters::of(scene);
    let at_own = cache.at(own.radius)?;
    out.push(Alternative {
        name: "the scene's own parameters".into(),
        scored: at_own
            .scored_at(scene, &opts.costs, &free, &own)
            .ok_or_else(|| "the scene's own parameters do not fit the budget".to_string()),
        note: format!("q = {}, R = {}, N_F = {}, N_B = {}", own.q, own.radius, own.forward_rays, own.camera_rays),
    });
    if bias_predicted {
        out.push(asymptotic_rule(scene, opts, cache, best, range)?);
    }
    let nb1 = fixed_r(cache, &Constraints { camera_rays: Some(1), ..free })?;
    out.push(Alternative {
        name: "N_B = 1 (one camera ray per iteration)".into(),
        scored: nb1.ok_or_else(|| none("N_B = 1")),
        note: "R, q, N_F optimised with N_B held at 1".into(),
    });
    Ok(out)
}

/// The R an asymptotic rule picks (bias ≈ b₂R², noise ≈ V₂/R²): with b₂ =
/// b(R_lo)/R_lo² at the smallest radius searched and V₂ = q M₂R²/(N_F N_B)
/// (the small-sphere M₂ ∝ 1/R²) at the optimum's q, N_F, N_B, τ and T,
/// RMSE² ≈ b₂²R⁴ + V₂τ/(R²T) is least at R⁶ = V₂τ/(2b₂²T). Scored by the
/// exact model with the optimum's other parameters.
fn asymptotic_rule(
    scene: &Scene,
    opts: &Options,
    cache: &mut RadiusCache,
    best: &Scored,
    range: (f64, f64),
) -> Result<Alternative, TuningError> {
    let small = cache.at(range.0)?;
    let b2 = small.model.bias.map_or(0.0, |b| b.value) / (range.0 * range.0);
    let p = best.parameters;
    // The small-sphere M₂ ∝ 1/R²: M₂R² is the same at every radius.
    let m2_r2 = small.model.small_sphere_m2.value * range.0 * range.0;
    let v2 = p.q * m2_r2 / (p.forward_rays as f64 * p.camera_rays as f64);
    let r6 = v2 * best.rmse.seconds_per_iteration / (2.0 * b2 * b2 * opts.budget);
    let r = r6.powf(1.0 / 6.0);
    let name = "R of the asymptotic rule (bias ∝ R², noise ∝ 1/R²)".to_string();
    if !(r.is_finite() && r > 0.0) {
        return Ok(Alternative { name, scored: Err(format!("b₂ = {b2:e}: no finite R")), note: String::new() });
    }
    let at = cache.at(r)?;
    let params = Parameters { radius: r, ..p };
    Ok(Alternative {
        name,
        scored: at
            .scored_at(scene, &opts.costs, &Constraints::free(opts.budget, opts.max_spheres), &params)
            .ok_or_else(|| format!("R = {r:e} does not fit the budget")),
        note: format!(
            "R = (V₂τ/(2b₂²T))^(1/6) = {r:.4e} with b₂ = {b2:.4e} (b(R)/R² at R = {:.1e}) and V₂ = {v2:.4e}; \
             q, N_F, N_B the optimum's",
            range.0
        ),
    })
}

impl Radius {
    /// The score of exactly `p` (its R must be this radius').
    pub fn scored_at(&self, scene: &Scene, costs: &CostTable, c: &Constraints, p: &Parameters) -> Option<Scored> {
        let (rmse, counts) = self.score(scene, costs, c, p.q, p.forward_rays as f64, p.camera_rays as f64)?;
        Some(Scored { parameters: Parameters { radius: self.model.radius, ..*p }, rmse, counts })
    }
}
