//! The noise model and the geometric rates at each sphere radius the
//! search visits, computed once per radius and kept (every other parameter
//! is explicit).
//!
//! What a cache computes follows [`super::Searched`] for its scene
//! ([`RadiusCache::searched`]): for uncollided light, and for scattered
//! light the finite-sphere model does not cover, the oracle's prediction
//! for the scene with its q and N_B, every run charged to the cache's one
//! budget. For single-scattered light in an isotropic medium
//! ([`super::Searched::StandardMethod`]) the oracle on the scene with q = 1
//! and N_B = 1 and only what that Var L needs (`Scope::Prediction`): the
//! finite-sphere μ, M₂, P and the bias at every R, without the pair
//! integrals other q and N_B would need, to [`SCATTERED_REL_TOL`], each run
//! with a budget of its own of the cache's size and deadline
//! ([`Budget::renewed`]: one such run can cost a third of the default).
//! For scattering orders 2 to 9 and `"all"` the same, by
//! [`crate::oracle::every_order_mean`] (μ, M₂ with its same-path pairs, P,
//! the bias; Var L's integrals at 10⁻⁴ whatever the goal; for `"all"`
//! ~8–14 s and 1.4–2.5·10⁸ evaluations a radius on the README scene from
//! R = 10⁻³ to 0.5, for order 5 ~30 s).

use super::objective::ModelAtRadius;
use super::rates::{Rates, PILOT_RAYS};
use super::search::Radius;
use super::Searched;
use crate::model::OracleError;
use crate::oracle::{run_within_scoped, Precision, Scope};
use crate::quad::Budget;
use mcrt_scene::{ScatteringOrders, Scene};
use std::collections::BTreeMap;

/// The oracle's relative tolerance for scenes with single-scattered light
/// (its default, 10⁻¹⁰ in f64, elsewhere): the RMSE is wanted to ~10⁻³
/// (its bar is mostly the cost model's, several per cent), and 10⁻⁴ keeps
/// the quadrature's bars ten times below that at a half of the cost of
/// 10⁻⁶ (on `point-isotropic-order1` at q = 1, N_B = 1: 0.65 s against
/// 1.3 s a radius; a beam's, `beam-isotropic` at order 1: 8 s and 3·10⁸
/// evaluations against 17 s and 6·10⁸).
///
/// ```
/// assert!(mcrt_noise::tuning::radii::SCATTERED_REL_TOL <= 1e-4);
/// ```
pub const SCATTERED_REL_TOL: f64 = 1e-4;

/// Radii already evaluated, by the bits of R.
#[derive(Debug)]
pub struct RadiusCache<'s> {
    scene: &'s Scene,
    budget: Budget,
    pilot_rays: u64,
    /// What `optimize` searches for the scene (`Searched::of`).
    searched: Searched,
    /// Only the small-sphere model, with the scene's q and N_B
    /// ([`RadiusCache::small_sphere`]).
    small_sphere_only: bool,
    /// The oracle's relative tolerance (`None`: its default).
    rel_tol: Option<f64>,
    map: BTreeMap<u64, Radius>,
}

impl<'s> RadiusCache<'s> {
    /// A cache for `scene` whose oracle runs share `budget` (module docs),
    /// of the models `optimize` searches for it ([`Searched::of`]).
    ///
    /// ```no_run
    /// use mcrt_noise::{quad::Budget, tuning::{radii::RadiusCache, Searched}};
    /// let scene = mcrt_noise::Scene::from_toml_str(&std::fs::read_to_string("scenes/point-isotropic-order1.toml")?)?;
    /// let mut cache = RadiusCache::new(&scene, Budget::new(1_000_000_000), None);
    /// assert_eq!(cache.searched(), Searched::StandardMethod);
    /// let at = cache.at(0.1)?; // the finite-sphere model at q = 1, N_B = 1
    /// assert!(at.model.bias.is_some() && !at.model.has_pairs());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(scene: &'s Scene, budget: Budget, pilot_rays: Option<u64>) -> RadiusCache<'s> {
        let searched = Searched::of(scene);
        let rel_tol = (searched == Searched::StandardMethod).then_some(SCATTERED_REL_TOL);
        let pilot_rays = pilot_rays.unwrap_or(PILOT_RAYS);
        RadiusCache { scene, budget, pilot_rays, searched, small_sphere_only: false, rel_tol, map: BTreeMap::new() }
    }

    /// A cache of the small-sphere model for `scene` as it is (its q and
    /// N_B, so that its pair integrals are computed), with the
    /// finite-sphere bias where the oracle has it (`finite_mean`): the
    /// comparison beside the standard method of single-scattered light.
    pub(crate) fn small_sphere(scene: &'s Scene, budget: Budget) -> RadiusCache<'s> {
        let (searched, rel_tol) = (Searched::of(scene), Some(SCATTERED_REL_TOL));
        RadiusCache {
            scene,
            budget,
            pilot_rays: PILOT_RAYS,
            searched,
            small_sphere_only: true,
            rel_tol,
            map: BTreeMap::new(),
        }
    }

    /// What `optimize` searches with this cache: [`Searched::of`] its scene.
    ///
    /// ```
    /// use mcrt_noise::{quad::Budget, tuning::{radii::RadiusCache, Searched}};
    /// let scene = mcrt_noise::Scene::from_toml_str(&std::fs::read_to_string("scenes/point-isotropic.toml")?)?;
    /// assert_eq!(RadiusCache::new(&scene, Budget::new(1), None).searched(), Searched::Everything);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn searched(&self) -> Searched {
        self.searched
    }

    /// Whether this cache was built for `scene` by [`RadiusCache::new`].
    pub(crate) fn serves(&self, scene: &Scene) -> bool {
        !self.small_sphere_only && self.scene == scene
    }

    /// The model and rates at radius `r` (computed on first use).
    pub fn at(&mut self, r: f64) -> Result<Radius, super::TuningError> {
        if let Some(x) = self.map.get(&r.to_bits()) {
            return Ok(*x);
        }
        let mut scene = self.scene.clone();
        scene.estimator.radius = r;
        let standard = self.searched == Searched::StandardMethod && !self.small_sphere_only;
        let scope = if standard {
            (scene.estimator.q, scene.estimator.camera_rays) = (1.0, 1);
            Scope::Prediction
        } else {
            Scope::Everything
        };
        let scene = scene.validated().map_err(|e| super::TuningError::Radius(r, e.to_string()))?;
        // The standard method's runs each get a budget of the cache's size
        // and deadline: a beam's single-scattered light costs ~3·10⁸
        // evaluations a radius and a search visits ~40 (at most ~100) radii.
        let own_budget;
        let budget = if standard {
            own_budget = self.budget.renewed();
            &own_budget
        } else {
            &self.budget
        };
        let model = if super::every_order(&scene) {
            every_order_model(&scene, self.rel_tol, budget, self.small_sphere_only)?
        } else {
            self.report_model(&scene, budget, scope, standard)?
        };
        let rates = Rates::estimate(&scene, self.pilot_rays).map_err(|e| super::TuningError::Radius(r, e))?;
        let x = Radius { model, rates };
        self.map.insert(r.to_bits(), x);
        Ok(x)
    }

    /// The model at `scene`'s R from the oracle's report (orders 0 and 1).
    fn report_model(
        &self,
        scene: &Scene,
        budget: &Budget,
        scope: Scope,
        standard: bool,
    ) -> Result<ModelAtRadius, super::TuningError> {
        let r = scene.estimator.radius;
        let report = run_within_scoped(scene, Precision::F64, self.rel_tol, budget, scope)
            .map_err(super::TuningError::Oracle)?;
        if self.small_sphere_only {
            ModelAtRadius::small_sphere_from_report(&report)
        } else if standard && report.finite.is_none() {
            // Its failure (a computed one, NOT CONVERGED) as it is; else why it was not used.
            Err(report.finite_error.clone().unwrap_or_else(|| {
                let why = report.finite_not_used.as_deref().unwrap_or("not computed");
                OracleError::Unsupported(format!(
                    "R = {r:e}: the finite-sphere model at q = 1, N_B = 1, which optimize needs for \
                     single-scattered light: {why}"
                ))
            }))
        } else {
            ModelAtRadius::from_report(&report)
        }
        .map_err(super::TuningError::Oracle)
    }

    /// Every radius evaluated so far, ascending.
    pub fn all(&self) -> Vec<Radius> {
        let mut v: Vec<Radius> = self.map.values().copied().collect();
        v.sort_by(|a, b| a.model.radius.total_cmp(&b.model.radius));
        v
    }
}

/// The model of every scattering order at `scene`'s R (q = 1, N_B = 1 set
/// by the caller; [`ModelAtRadius::from_every_order`]); the small-sphere
/// comparison has no Var L of every order (the paper's model is of orders 0
/// and 1) and is refused, saying so.
fn every_order_model(
    scene: &Scene,
    rel_tol: Option<f64>,
    budget: &Budget,
    small_sphere_only: bool,
) -> Result<ModelAtRadius, super::TuningError> {
    if small_sphere_only {
        return Err(super::TuningError::Oracle(OracleError::Unsupported(
            "the small-sphere model has no Var L of every scattering order (the paper's §3a model is of orders 0 \
             and 1; docs/model.md §10)"
                .into(),
        )));
    }
    // Refused before any integral: what the model of every order does not
    // cover (its medium, lights), then an albedo the search cannot use,
    // then where it has no Var L.
    crate::oracle::every_order_scene_covered(scene)?;
    let albedo = scene.medium.albedo;
    let every = scene.effects.scattering_orders == ScatteringOrders::All;
    if !(albedo > 0.0 && (albedo < 1.0 || !every)) {
        let allowed = if every { "0 < albedo < 1" } else { "0 < albedo <= 1" };
        return Err(super::TuningError::Oracle(OracleError::Unsupported(format!(
            "medium.albedo = {albedo}: with effects.scattering_orders = {} optimize needs {allowed} (at 0 no light \
             scatters: use scattering_orders = 0; with \"all\" at 1 the orders never end, docs/model.md §10.1)",
            scene.effects.scattering_orders.as_toml()
        ))));
    }
    crate::oracle::every_order_variance_refusal(scene)?;
    let (report, failed) = crate::oracle::every_order_report(scene, rel_tol, budget)?;
    if let Some(e) = failed {
        return Err(super::TuningError::Oracle(e));
    }
    Ok(ModelAtRadius::from_every_order(&report, scene.estimator.radius)?)
}

impl From<OracleError> for super::TuningError {
    fn from(e: OracleError) -> Self {
        super::TuningError::Oracle(e)
    }
}
