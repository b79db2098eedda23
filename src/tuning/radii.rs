//! The noise model and the geometric rates at each sphere radius the
//! search visits, computed once per radius and kept (every other parameter
//! is explicit), each oracle run charged to the optimisation's one budget.

use super::objective::ModelAtRadius;
use super::rates::{Rates, PILOT_RAYS};
use super::search::Radius;
use crate::model::OracleError;
use crate::oracle::{run_within, Precision};
use crate::quad::Budget;
use mcrt_scene::Scene;
use std::collections::BTreeMap;

/// Radii already evaluated, by the bits of R.
#[derive(Debug)]
pub struct RadiusCache<'s> {
    scene: &'s Scene,
    budget: Budget,
    pilot_rays: u64,
    map: BTreeMap<u64, Radius>,
}

impl<'s> RadiusCache<'s> {
    /// A cache for `scene` whose oracle runs share `budget`.
    pub fn new(scene: &'s Scene, budget: Budget, pilot_rays: Option<u64>) -> RadiusCache<'s> {
        RadiusCache { scene, budget, pilot_rays: pilot_rays.unwrap_or(PILOT_RAYS), map: BTreeMap::new() }
    }

    /// The model and rates at radius `r` (computed on first use).
    pub fn at(&mut self, r: f64) -> Result<Radius, super::TuningError> {
        if let Some(x) = self.map.get(&r.to_bits()) {
            return Ok(*x);
        }
        let mut scene = self.scene.clone();
        scene.estimator.radius = r;
        let scene = scene.validated().map_err(|e| super::TuningError::Radius(r, e.to_string()))?;
        let report = run_within(&scene, Precision::F64, None, &self.budget).map_err(super::TuningError::Oracle)?;
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
