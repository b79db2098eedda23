//! The noise model and the geometric rates at each sphere radius the
//! search visits, computed once per radius and kept (every other parameter
//! is explicit), each oracle run charged to the optimisation's one budget.
//!
//! For a scene the finite-sphere model covers only at q = 1 and N_B = 1
//! (single-scattered light, [`super::Searched::StandardMethod`]) the cache
//! runs the oracle on the scene with q = 1 and N_B = 1 and only what that
//! Var L needs (`Scope::Prediction`): the finite-sphere μ, M₂, P and the
//! bias at every R, without the pair integrals other q and N_B would need,
//! to [`SCATTERED_REL_TOL`], each run with an evaluation budget of its own
//! of the cache's size (one such run can cost a third of the default).

use super::objective::ModelAtRadius;
use super::rates::{Rates, PILOT_RAYS};
use super::search::Radius;
use crate::model::OracleError;
use crate::oracle::{run_within_scoped, Precision, Scope};
use crate::quad::Budget;
use mcrt_scene::Scene;
use std::collections::BTreeMap;

/// The oracle's relative tolerance for scenes with single-scattered light
/// (its default, 10⁻¹⁰ in f64, elsewhere): the RMSE is wanted to ~10⁻³
/// (its bar is mostly the cost model's, several per cent), and 10⁻⁴ keeps
/// the quadrature's bars ten times below that at a half of the cost of
/// 10⁻⁶ (on `point-isotropic-order1` at q = 1, N_B = 1: 0.65 s against
/// 1.3 s a radius; a beam's, `beam-isotropic` at order 1: 8 s and 3·10⁸
/// evaluations against 17 s and 6·10⁸).
pub const SCATTERED_REL_TOL: f64 = 1e-4;

/// Radii already evaluated, by the bits of R.
#[derive(Debug)]
pub struct RadiusCache<'s> {
    scene: &'s Scene,
    budget: Budget,
    pilot_rays: u64,
    /// Whether the oracle runs at q = 1, N_B = 1 (`Searched::StandardMethod`).
    standard_method: bool,
    /// The oracle's relative tolerance (`None`: its default).
    rel_tol: Option<f64>,
    map: BTreeMap<u64, Radius>,
}

impl<'s> RadiusCache<'s> {
    /// A cache for `scene` whose oracle runs share `budget`: of the models
    /// `optimize` searches ([`super::Searched::of`]).
    pub fn new(scene: &'s Scene, budget: Budget, pilot_rays: Option<u64>) -> RadiusCache<'s> {
        let standard_method = super::Searched::of(scene) == super::Searched::StandardMethod;
        let rel_tol = standard_method.then_some(SCATTERED_REL_TOL);
        let pilot_rays = pilot_rays.unwrap_or(PILOT_RAYS);
        RadiusCache { scene, budget, pilot_rays, standard_method, rel_tol, map: BTreeMap::new() }
    }

    /// A cache of the oracle's prediction for `scene` as it is (its q and
    /// N_B): the small-sphere model for single-scattered light with q < 1
    /// or N_B > 1, with the finite-sphere bias where the oracle has it.
    pub fn as_given(scene: &'s Scene, budget: Budget) -> RadiusCache<'s> {
        let rel_tol = Some(SCATTERED_REL_TOL);
        RadiusCache { scene, budget, pilot_rays: PILOT_RAYS, standard_method: false, rel_tol, map: BTreeMap::new() }
    }

    /// The model and rates at radius `r` (computed on first use).
    pub fn at(&mut self, r: f64) -> Result<Radius, super::TuningError> {
        if let Some(x) = self.map.get(&r.to_bits()) {
            return Ok(*x);
        }
        let mut scene = self.scene.clone();
        scene.estimator.radius = r;
        let scope = if self.standard_method {
            (scene.estimator.q, scene.estimator.camera_rays) = (1.0, 1);
            Scope::Prediction
        } else {
            Scope::Everything
        };
        let scene = scene.validated().map_err(|e| super::TuningError::Radius(r, e.to_string()))?;
        // The standard method's runs each get a budget of the cache's size:
        // a beam's single-scattered light costs ~3·10⁸ evaluations a radius
        // and a search visits ~40 (at most ~100) radii.
        let own_budget;
        let budget = if self.standard_method {
            own_budget = Budget::new(self.budget.limit());
            &own_budget
        } else {
            &self.budget
        };
        let report = run_within_scoped(&scene, Precision::F64, self.rel_tol, budget, scope)
            .map_err(super::TuningError::Oracle)?;
        if self.standard_method && report.finite.is_none() {
            let why = report.finite_not_used.as_deref().unwrap_or("the finite-sphere model was not computed");
            return Err(super::TuningError::Oracle(OracleError::Unsupported(format!(
                "R = {r:e}: the finite-sphere model at q = 1, N_B = 1, which optimize needs for single-scattered \
                 light: {why}"
            ))));
        }
        let model = ModelAtRadius::from_report(&report).map_err(super::TuningError::Oracle)?;
        let rates = Rates::estimate(&scene, self.pilot_rays).map_err(|e| super::TuningError::Radius(r, e))?;
        let x = Radius { model, rates };
        self.map.insert(r.to_bits(), x);
        Ok(x)
    }

    /// Every radius evaluated so far, ascending.
    pub fn all(&self) -> Vec<Radius> {
        let mut v: Vec<Radius> = self.map.values().copied().collect();
        v.sort_by(|a, b| a.model.radius.total_cmp(&b.model.radius));
        v
    }
}

impl From<OracleError> for super::TuningError {
    fn from(e: OracleError) -> Self {
        super::TuningError::Oracle(e)
    }
}
