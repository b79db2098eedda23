//! Choosing the estimator's parameters: the (q, R, N_F, N_B) with the least
//! predicted relative RMSE after a wall-time budget, bias included (the
//! seed paper's purpose, §1 and §5).
//!
//! - [`cost`]: the cost of one iteration, expected operation counts times
//!   per-operation costs;
//! - [`rates`]: the geometric rates the counts need (searching and hitting
//!   segments), measured by walking forward rays;
//! - `calibration` (feature `cli`): per-operation costs fitted from timed tracer runs;
//! - [`objective`]: RMSE = √(b(R)² + Var L/M) after the budget, M = T/τ;
//! - [`search`]: the search over (q, N_F, N_B) at one R, explicit in them;
//! - [`radii`]: the model and rates per radius, computed once;
//! - [`alternatives`]: the comparisons beside the optimum;
//! - [`sensitivity`]: each parameter's range within 10 % of the best;
//! - [`maps`]: the RMSE over (q, R) and (q, N_B/N_F);
//! - [`optimize`] (here): the search over R, the comparisons (q = 1,
//!   several spheres per camera ray (q ≤ 1/2), the cylinder limit, the
//!   scene's own parameters, the asymptotic rule's R, N_B = 1) and the
//!   sensitivity of the optimum.
//!
//! What is searched follows where the finite-sphere model is exact
//! ([`Searched`]): every (q, R, N_F, N_B) for uncollided light; R and N_F
//! with q = 1 and N_B = 1 (the standard method) for single-scattered light
//! in an isotropic medium, whose Var L at other q and N_B needs pair
//! integrals too slow to score a search with (`docs/model.md` §9.7), with the
//! small-sphere model's (q, N_F, N_B) at the scene's R beside it, and for
//! scattering orders ≥ 2 and `"all"` (point lights and beams in an
//! isotropic medium, §10.3, §10.6: ~10 s a radius for `"all"` and order 2,
//! ~30 s for order 5, about a minute with a beam, minutes a search), with
//! no small-sphere model beside it; elsewhere
//! (Henyey–Greenstein media at order 1) the bias is not predicted, R is
//! held at the scene's and only (q, N_F, N_B) are chosen, for the noise
//! alone; Henyey–Greenstein media at orders ≥ 2, and orders above 9, are
//! refused (no Var L).

pub mod alternatives;
#[cfg(feature = "cli")]
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
use cost::{CostTable, IterationCounts};
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

/// Which parameters `optimize` searches, from where the finite-sphere
/// model (exact at R, bias predicted) covers the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Searched {
    /// Uncollided light: every (q, R, N_F, N_B), by the finite-sphere model.
    Everything,
    /// Single-scattered light in an isotropic medium (point lights and
    /// beams), and scattering orders ≥ 2 and `"all"` (point lights and beams
    /// in an isotropic medium): the finite-sphere model gives Var L at q = 1 and
    /// N_B = 1 only (in a search), so R and N_F are searched there (bias
    /// predicted), and for single scattering the small-sphere model's
    /// (q, N_F, N_B) at the scene's R is an alternative.
    StandardMethod,
    /// Other scattered light: the small-sphere model; R held at the
    /// scene's, the bias not predicted, (q, N_F, N_B) chosen for the noise.
    HeldRadius,
}

impl Searched {
    /// What `optimize` searches for `scene`.
    ///
    /// ```
    /// use mcrt_noise::tuning::Searched;
    /// let text = std::fs::read_to_string("scenes/point-isotropic-order1.toml")?;
    /// let scene = mcrt_noise::Scene::from_toml_str(&text)?;
    /// assert_eq!(Searched::of(&scene), Searched::StandardMethod);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn of(scene: &Scene) -> Searched {
        use mcrt_scene::ScatteringOrders::Limited;
        match scene.effects.scattering_orders {
            Limited(0) => Searched::Everything,
            _ if crate::oracle::finite_sphere_covers_the_standard_method(scene) => Searched::StandardMethod,
            _ => Searched::HeldRadius,
        }
    }
}

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
    /// Oracle evaluations for the whole optimisation (every radius); with
    /// single-scattered light searched at the standard method
    /// ([`Searched::StandardMethod`]) each radius's oracle run, and the
    /// small-sphere comparison beside it, has a budget of its own of this
    /// size (a beam's costs ~3·10⁸ a radius; scattering orders ≥ 2 need
    /// up to 1.4·10⁹ a radius, order 9: give them
    /// [`crate::prec::EVERY_ORDER_PREDICTION_EVALUATIONS`], as `mcrt-noise
    /// optimize` does).
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
    /// Which parameters were searched.
    pub searched: Searched,
    /// The scene's `scattering_orders` as in its file (`"0"`, `"1"`,
    /// `"all"`, …): what light the model covers.
    pub scattering_orders: String,
    /// Whether the bias b(R) is predicted at every R searched (finite-sphere
    /// model). Where R is held it may still be known at the scene's R
    /// (`best.rmse.relative_bias`: the exact mean of single-scattered light
    /// in a Henyey–Greenstein medium, `docs/model.md` §9.9).
    pub bias_predicted: bool,
    /// The constraints searched under.
    pub budget: f64,
    /// The memory limit, if any.
    pub max_spheres: Option<f64>,
    /// The radii searched ((R, R) where R is held).
    pub radius_range: (f64, f64),
    /// The radii asked for (`--radius-range`), if any: where R is held,
    /// the range holds it and is not searched.
    pub radius_range_requested: Option<(f64, f64)>,
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
    check_radius_range(scene, opts.radius_range)?;
    if !cache.serves(scene) {
        return Err(TuningError::Option(
            "the radius cache was built for another scene (or is not `RadiusCache::new`'s): its models would not \
             be this scene's"
                .into(),
        ));
    }
    let searched = cache.searched();
    // Every order the model does not cover (or has no Var L of) is refused
    // first, before any integral, not told to move its R.
    if searched == Searched::HeldRadius && every_order(scene) {
        cache.at(scene.estimator.radius)?;
    }
    if searched == Searched::HeldRadius {
        check_held_radius(scene, opts.radius_range)?;
    }
    let own = cache.at(scene.estimator.radius)?;
    // Not one iteration in the budget: say so before any search.
    let least = IterationCounts::predict(scene, &own.rates, 1.0, 1.0, 1.0);
    let tau_min = opts.costs.seconds(&least).0;
    if tau_min > opts.budget {
        return Err(TuningError::Option(format!(
            "--budget {}: must be at least one iteration, {tau_min:.3e} s with N_F = N_B = 1, q = 1 at these costs",
            opts.budget
        )));
    }
    let bias_predicted = searched != Searched::HeldRadius;
    let sigma = scene.medium.sigma_ext;
    let range = opts.radius_range.unwrap_or((1e-3 / sigma, 0.5 / sigma));
    let free = searched.constraints(opts);
    let best = if bias_predicted {
        best_over_radii(scene, opts, cache, &free, range)?
    } else {
        own.best(scene, &opts.costs, &free).ok_or_else(|| infeasible(opts, scene))?
    };
    let alternatives = match searched {
        Searched::StandardMethod => alternatives::beside_the_standard_method(scene, opts, cache, &best, range)?,
        _ => alternatives::alternatives(scene, opts, cache, &best, range, bias_predicted)?,
    };
    let sensitivity = sensitivity::of(scene, opts, cache, &best, searched, range)?;
    Ok(Optimum {
        model: own.model.model,
        searched,
        scattering_orders: scene.effects.scattering_orders.to_string(),
        bias_predicted,
        budget: opts.budget,
        max_spheres: opts.max_spheres,
        radius_range: if bias_predicted { range } else { (scene.estimator.radius, scene.estimator.radius) },
        radius_range_requested: opts.radius_range,
        costs: opts.costs.clone(),
        best,
        alternatives,
        sensitivity,
        radii: cache.all(),
    })
}

impl Searched {
    /// The constraints of the search: none but the budget (and memory),
    /// and q = 1, N_B = 1 for [`Searched::StandardMethod`].
    ///
    /// ```
    /// use mcrt_noise::tuning::{cost::CostTable, Options, Searched};
    /// let c = Searched::StandardMethod.constraints(&Options::new(1.0, CostTable::reference_machine()));
    /// assert_eq!((c.q, c.camera_rays), (Some(1.0), Some(1)));
    /// ```
    pub fn constraints(self, opts: &Options) -> Constraints {
        let free = Constraints::free(opts.budget, opts.max_spheres);
        match self {
            Searched::StandardMethod => Constraints { q: Some(1.0), camera_rays: Some(1), ..free },
            _ => free,
        }
    }
}

/// Whether `scene` has scattering orders beyond the first (2 to 9 or
/// `"all"`), whose model of every order (`docs/model.md` §10) needs a
/// larger evaluation budget a radius ([`Options::evaluations`]).
///
/// ```
/// let text = std::fs::read_to_string("scenes/point-isotropic-all.toml")?;
/// let scene = mcrt_noise::Scene::from_toml_str(&text)?;
/// assert!(mcrt_noise::tuning::every_order(&scene));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn every_order(scene: &Scene) -> bool {
    crate::oracle::orders_beyond_the_first(scene)
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

/// The radii searched must be ones the scene may have: σ_ext·R within the
/// bounds of `estimator.radius` (`mcrt_scene::limits`). This also bounds
/// the grid over R (4 radii per decade: at most 61); `1e-300,1e300` made
/// it 10⁶⁰⁰ long (infinite in f64) and panicked with "capacity overflow".
fn check_radius_range(scene: &Scene, range: Option<(f64, f64)>) -> Result<(), TuningError> {
    use mcrt_scene::limits::{MAX_OPTICAL_RADIUS, MIN_OPTICAL_RADIUS};
    let Some((lo, hi)) = range else { return Ok(()) };
    let sigma = scene.medium.sigma_ext;
    let (min, max) = (MIN_OPTICAL_RADIUS / sigma, MAX_OPTICAL_RADIUS / sigma);
    if sigma * lo < MIN_OPTICAL_RADIUS || sigma * hi > MAX_OPTICAL_RADIUS {
        return Err(TuningError::Option(format!(
            "--radius-range {lo:e},{hi:e}: both radii must be in [{min:e}, {max:e}] (σ_ext·R in \
             [{MIN_OPTICAL_RADIUS:e}, {MAX_OPTICAL_RADIUS:e}], the bounds of estimator.radius, with σ_ext = {sigma})"
        )));
    }
    Ok(())
}

/// With scattered light the finite-sphere model does not cover
/// ([`Searched::HeldRadius`]) R is held at the scene's (the bias is not
/// predicted, so R cannot be chosen): a `--radius-range` is honoured only
/// if it holds that R, else refused rather than ignored.
fn check_held_radius(scene: &Scene, range: Option<(f64, f64)>) -> Result<(), TuningError> {
    let r = scene.estimator.radius;
    match range {
        Some((lo, hi)) if !(lo..=hi).contains(&r) => Err(TuningError::Option(format!(
            "--radius-range {lo:e},{hi:e}: the scene has scattered light the finite-sphere model does not cover \
             (effects.scattering_orders = {}, medium.phase = {}; it covers single scattering in an isotropic \
             medium and orders 2 to 9 and \"all\" with point lights and beams in one, whose R is searched), so its bias is not predicted, R cannot be searched and is held at the \
             scene's estimator.radius = {r}, outside the range; set estimator.radius within it, or omit \
             --radius-range",
            scene.effects.scattering_orders.as_toml(),
            match scene.medium.phase {
                mcrt_scene::Phase::Isotropic => "\"isotropic\"".to_string(),
                mcrt_scene::Phase::HenyeyGreenstein { g } => format!("henyey-greenstein with g = {g}"),
            }
        ))),
        _ => Ok(()),
    }
}

fn infeasible(opts: &Options, scene: &Scene) -> TuningError {
    TuningError::Infeasible(format!(
        "no parameters fit a budget of {} s: one iteration with N_F = N_B = 1, q = 1 takes longer at these \
         costs (R = {})",
        opts.budget, scene.estimator.radius
    ))
}

/// Steps of the grid over R at most: 4 per decade of the widest range
/// the scene's bounds allow (σ_ext·R in [1e-12, 1e3], 15 decades).
const MAX_RADIUS_STEPS: f64 = 60.0;

/// The best point over R: a grid of 4 radii per decade over `range`, then
/// golden section on log R around the best grid point.
pub(crate) fn best_over_radii(
    scene: &Scene,
    opts: &Options,
    cache: &mut RadiusCache,
    c: &Constraints,
    (lo, hi): (f64, f64),
) -> Result<Scored, TuningError> {
    // 4 radii per decade; the range is within the scene's bounds of R
    // (`check_radius_range`: 15 decades, 60 steps), and the cap guards a
    // library caller's range.
    let steps = ((hi / lo).log10() * 4.0).ceil().clamp(2.0, MAX_RADIUS_STEPS) as usize;
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
