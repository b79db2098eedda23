//! The search for the parameters with the least RMSE after a time budget.
//!
//! For a fixed R the noise model's integrals are fixed, and the search over
//! (q, N_F, N_B) costs nothing per point: for fixed (q, N_B), Var L = X +
//! Y/N_F and τ = U + V·N_F (every cost but the camera side's is
//! proportional to N_F), so Var L·τ, which the RMSE's noise term is T⁻¹
//! times, is least at N_F* = √(YU/(XV)); the two integers around it are
//! evaluated. (q, N_B) run over a grid (log-spaced q with q = 1, integer N_B
//! log-spaced), and the best point is refined: q by golden section between
//! its grid neighbours, N_B over its integer neighbourhood. Only R needs new
//! integrals (and a pilot walk for the rates, `Radius`), so it is searched
//! over a log grid and refined by golden section on log R. M = ⌊T/τ⌋ whole
//! iterations: besides the integers around N_F*, the largest N_F that keeps
//! its number of iterations (and one more) is tried.
//!
//! Bounds: the scene's (q ≥ 10⁻⁶, N_F ≤ 10⁸, N_B ≤ 10⁶) and the reference
//! tracer's (≤ 2²⁰ spheres and ≤ 2²⁴ segments per iteration), so that
//! every point can be traced; at least one iteration fits in the budget;
//! optionally at most `max_spheres` spheres per iteration (the paper's
//! memory limit).

use super::cost::{CostTable, IterationCounts, Parameters};
use super::objective::{ModelAtRadius, Rmse};
use super::rates::Rates;
use mcrt_scene::Scene;
use serde::Serialize;

/// Largest spheres per iteration the search considers (the tracer's bound).
pub const MAX_SPHERES: f64 = mcrt_reference::limits::MAX_SPHERES_PER_TRIAL;
/// Largest forward segments per iteration (the tracer's bound).
pub const MAX_SEGMENTS: f64 = mcrt_reference::limits::MAX_SEGMENTS_PER_TRIAL;
/// Smallest q searched (the scene's bound).
pub const MIN_Q: f64 = mcrt_scene::limits::MIN_Q;

/// What the search must respect besides the bounds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Constraints {
    /// The wall-time budget T in seconds (of one core, as the costs are).
    pub budget: f64,
    /// At most this many spheres per iteration (memory), if given.
    pub max_spheres: Option<f64>,
    /// q held at this value, if given (q = 1: the standard method).
    pub q: Option<f64>,
    /// q at most this, if given (q ≤ 1/2: several spheres per camera ray).
    pub q_max: Option<f64>,
    /// N_B held at this value, if given.
    pub camera_rays: Option<u64>,
    /// The cylinder limit q → 0: Var L at q = 0 (closed form) and the cost
    /// of one integration volume per camera ray (the sphere terms at q = 1,
    /// one contribution per camera ray and crossing segment) instead of the
    /// 1/q → ∞ spheres the sphere method would need.
    pub cylinder: bool,
}

impl Constraints {
    /// Only the budget (and the memory limit, if given) constrain.
    pub fn free(budget: f64, max_spheres: Option<f64>) -> Constraints {
        Constraints { budget, max_spheres, q: None, q_max: None, camera_rays: None, cylinder: false }
    }
}

/// A scored parameter set.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Scored {
    /// The parameters.
    pub parameters: Parameters,
    /// Their predicted RMSE after the budget.
    pub rmse: Rmse,
    /// The model's expected operation counts of one iteration.
    pub counts: IterationCounts,
}

/// Everything the search needs at one radius.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Radius {
    /// The noise model's integrals at R.
    pub model: ModelAtRadius,
    /// The geometric rates at R.
    pub rates: Rates,
}

impl Radius {
    /// The RMSE of (q, N_F, N_B) at this radius, or `None` if the point
    /// breaks a bound or the constraints (continuous counts allowed).
    pub fn score(
        &self,
        scene: &Scene,
        costs: &CostTable,
        c: &Constraints,
        q: f64,
        n_f: f64,
        n_b: f64,
    ) -> Option<(Rmse, IterationCounts)> {
        let spheres = n_b / q;
        let feasible = (MIN_Q..=c.q_max.unwrap_or(1.0)).contains(&q)
            && (1.0..=mcrt_scene::limits::MAX_FORWARD_RAYS as f64).contains(&n_f)
            && (1.0..=mcrt_scene::limits::MAX_CAMERA_RAYS as f64).contains(&n_b)
            && spheres <= MAX_SPHERES.min(mcrt_scene::limits::MAX_SPHERES_PER_ITERATION)
            && c.max_spheres.is_none_or(|m| spheres <= m)
            && n_f * self.rates.segments_per_ray <= MAX_SEGMENTS;
        if !feasible {
            return None;
        }
        let counts = self.counts(scene, c, q, n_f, n_b);
        let tau = self.seconds(scene, costs, c, &counts, q, n_f, n_b);
        if !(tau.0 > 0.0 && tau.0 <= c.budget) {
            return None;
        }
        let var = self.model.variance(if c.cylinder { 0.0 } else { q }, n_f, n_b)?;
        Some((Rmse::of(&self.model, var, tau, c.budget)?, counts))
    }

    /// τ and its standard error: the costs' (`CostTable::seconds`) and the
    /// rates' sampling errors, added in quadrature (τ is linear in each rate).
    #[allow(clippy::too_many_arguments)]
    fn seconds(
        &self,
        scene: &Scene,
        costs: &CostTable,
        c: &Constraints,
        counts: &IterationCounts,
        q: f64,
        n_f: f64,
        n_b: f64,
    ) -> (f64, f64) {
        let (t, e) = costs.seconds(counts);
        let shifted = |pc: f64, h: f64| {
            let mut r = *self;
            r.rates.candidate_fraction.value += pc;
            r.rates.hit_measure.value += h;
            costs.seconds(&r.counts(scene, c, q, n_f, n_b)).0 - t
        };
        let d_pc = shifted(self.rates.candidate_fraction.error, 0.0);
        let d_h = shifted(0.0, self.rates.hit_measure.error);
        (t, (e * e + d_pc * d_pc + d_h * d_h).sqrt())
    }

    /// The expected counts of one iteration (the cylinder's when `c.cylinder`).
    fn counts(&self, scene: &Scene, c: &Constraints, q: f64, n_f: f64, n_b: f64) -> IterationCounts {
        if !c.cylinder {
            return IterationCounts::predict(scene, &self.rates, q, n_f, n_b);
        }
        let mut counts = IterationCounts::predict(scene, &self.rates, 1.0, n_f, n_b);
        let crossings = counts.segments * self.rates.candidate_fraction.value * n_b;
        if counts.hg_evaluations > 0.0 {
            counts.hg_evaluations = crossings;
        }
        counts.hits = crossings;
        counts
    }

    /// The score of exactly `p` (its R must be this radius').
    pub fn scored_at(&self, scene: &Scene, costs: &CostTable, c: &Constraints, p: &Parameters) -> Option<Scored> {
        let (rmse, counts) = self.score(scene, costs, c, p.q, p.forward_rays as f64, p.camera_rays as f64)?;
        Some(Scored { parameters: Parameters { radius: self.model.radius, ..*p }, rmse, counts })
    }

    /// The scored integer point (q, N_F, N_B) at this radius.
    fn scored(&self, scene: &Scene, costs: &CostTable, c: &Constraints, q: f64, n_f: u64, n_b: u64) -> Option<Scored> {
        let (rmse, counts) = self.score(scene, costs, c, q, n_f as f64, n_b as f64)?;
        let parameters = Parameters { q, radius: self.model.radius, forward_rays: n_f, camera_rays: n_b };
        Some(Scored { parameters, rmse, counts })
    }

    /// The best N_F for (q, N_B): the integers around N_F* (and the largest
    /// N_F that fits the budget when N_F* does not).
    fn best_n_f(&self, scene: &Scene, costs: &CostTable, c: &Constraints, q: f64, n_b: u64) -> Option<Scored> {
        // Var = X + Y/N_F and τ = U + V N_F, read off at N_F = 1 and 2
        // (Var at q = 0 in the cylinder limit, as `score` has it).
        let q_var = if c.cylinder { 0.0 } else { q };
        let var = |n_f: f64| self.model.variance(q_var, n_f, n_b as f64).map(|v| v.value);
        let tau = |n_f: f64| costs.seconds(&self.counts(scene, c, q, n_f, n_b as f64)).0;
        let (var1, var2) = (var(1.0)?, var(2.0)?);
        let (y, x) = (2.0 * (var1 - var2), 2.0 * var2 - var1);
        let (v, u) = (tau(2.0) - tau(1.0), 2.0 * tau(1.0) - tau(2.0));
        let cap = ((c.budget - u) / v).min(MAX_SEGMENTS / self.rates.segments_per_ray).max(1.0);
        let star = if x > 0.0 && y > 0.0 && u > 0.0 && v > 0.0 { (y * u / (x * v)).sqrt() } else { cap };
        let star = star.clamp(1.0, cap.min(mcrt_scene::limits::MAX_FORWARD_RAYS as f64));
        // M = ⌊T/τ⌋ whole iterations: also the largest N_F that keeps the
        // count of iterations at N_F*'s, and one more iteration.
        let k = (c.budget / (u + v * star)).floor().max(1.0);
        let fits = |k: f64| ((c.budget / k - u) / v).floor();
        [star.floor(), star.ceil(), cap.floor(), fits(k), fits(k + 1.0)]
            .into_iter()
            .filter(|n| *n >= 1.0)
            .filter_map(|n| self.scored(scene, costs, c, q, n as u64, n_b))
            .min_by(|a, b| a.rmse.relative.total_cmp(&b.rmse.relative))
    }

    /// The best (q, N_F, N_B) at this radius under `c`.
    pub fn best(&self, scene: &Scene, costs: &CostTable, c: &Constraints) -> Option<Scored> {
        let qs: Vec<f64> = match c.q {
            _ if c.cylinder => vec![1.0],
            Some(q) => vec![q],
            None => {
                let top = c.q_max.unwrap_or(1.0);
                (0..=48).map(|k| top * 10f64.powf(-6.0 * f64::from(48 - k) / 48.0)).filter(|q| *q >= MIN_Q).collect()
            }
        };
        let nbs: Vec<u64> = match c.camera_rays {
            Some(n) => vec![n],
            None => log_integers(mcrt_scene::limits::MAX_CAMERA_RAYS as u64),
        };
        let mut best: Option<(usize, usize, Scored)> = None;
        for (i, &q) in qs.iter().enumerate() {
            for (j, &n_b) in nbs.iter().enumerate() {
                if let Some(s) = self.best_n_f(scene, costs, c, q, n_b) {
                    if best.as_ref().is_none_or(|b| s.rmse.relative < b.2.rmse.relative) {
                        best = Some((i, j, s));
                    }
                }
            }
        }
        let (i, j, mut top) = best?;
        // Refine N_B over the integers between its grid neighbours.
        if c.camera_rays.is_none() {
            let lo = nbs[j.saturating_sub(1)];
            let hi = nbs[(j + 1).min(nbs.len() - 1)];
            for n_b in lo..=hi {
                if let Some(s) = self.best_n_f(scene, costs, c, top.parameters.q, n_b) {
                    if s.rmse.relative < top.rmse.relative {
                        top = s;
                    }
                }
            }
        }
        // Refine q by golden section on log q between its grid neighbours.
        if c.q.is_none() && !c.cylinder {
            let n_b = top.parameters.camera_rays;
            let f = |lq: f64| self.best_n_f(scene, costs, c, lq.exp(), n_b);
            let (a, b) = (qs[i.saturating_sub(1)].ln(), qs[(i + 1).min(qs.len() - 1)].ln());
            if let Some(s) = golden(a, b, 40, |lq| f(lq).map_or(f64::INFINITY, |s| s.rmse.relative)).and_then(f) {
                if s.rmse.relative < top.rmse.relative {
                    top = s;
                }
            }
        }
        Some(top)
    }
}

/// Distinct integers 1, 2, 3, … growing by ~15 % up to `max` (and `max`).
pub fn log_integers(max: u64) -> Vec<u64> {
    let mut v = vec![1u64];
    while *v.last().unwrap() < max {
        let last = *v.last().unwrap();
        v.push(((last as f64 * 1.15).ceil() as u64).max(last + 1).min(max));
    }
    v
}

/// The minimiser of f on [a, b] by golden section, `steps` reductions
/// (assumes one minimum in the bracket; the caller keeps its grid best).
pub fn golden(mut a: f64, mut b: f64, steps: usize, f: impl Fn(f64) -> f64) -> Option<f64> {
    if !(a < b) {
        return (a == b).then_some(a);
    }
    let r = (5f64.sqrt() - 1.0) / 2.0;
    let (mut x1, mut x2) = (b - r * (b - a), a + r * (b - a));
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..steps {
        if f1 <= f2 {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - r * (b - a);
            f1 = f(x1);
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + r * (b - a);
            f2 = f(x2);
        }
    }
    let x = if f1 <= f2 { x1 } else { x2 };
    f(x).is_finite().then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn golden_section_finds_a_parabola_minimum() {
        // f is flat to an ulp of f(x*) within √eps of x*: x is good to ~1e-8.
        let x = golden(-3.0, 5.0, 60, |x| (x - 1.25) * (x - 1.25) + 2.0).unwrap();
        assert!((x - 1.25).abs() < 1e-7, "{x}");
        assert_eq!(golden(1.0, 1.0, 10, |x| x), Some(1.0));
        assert_eq!(golden(1.0, 2.0, 10, |_| f64::INFINITY), None);
    }

    #[test]
    fn log_integers_are_distinct_and_reach_the_end() {
        let v = log_integers(1_000_000);
        assert!(v.windows(2).all(|w| w[0] < w[1]));
        assert_eq!((v[0], *v.last().unwrap()), (1, 1_000_000));
        assert!(v.len() < 120, "{}", v.len());
    }
}
