//! The cost of one iteration: the operations a bi-directional renderer with
//! multiple integration spheres performs, counted in expectation, times
//! per-operation costs.
//!
//! One iteration of one pixel (as the reference tracer runs it, docs/tracer.md):
//! N_B camera rays (a renderer's primary rays: a cost of their own, next to
//! nothing in the tracer, whose camera rays are one line) each place on average 1/q spheres (sub-steps and
//! extinction draws), the S spheres of the iteration are sorted, N_F forward
//! rays are emitted and walked segment by segment, every segment whose line
//! passes within R of the camera line searches the sorted centres (two
//! binary searches, ~2 log₂ S comparisons), and every hit adds a
//! contribution (in a Henyey–Greenstein medium with a phase-function
//! evaluation of its own, costed per hit: the tracer evaluates f once per
//! hitting segment, a renderer may once per hit). So
//!
//! ```text
//! τ = c_trial + c_ray N_F + c_camera N_B + c_segment N_F ν + c_sphere N_B/q + c_sort E[S log₂ S]
//!     + c_search N_F ν p_c(R) log₂(1 + N_B/q) + (c_hit + c_HG) N_F N_B h(R)/q
//! ```
//!
//! with ν the expected segments of one forward ray, p_c(R) the probability
//! that a segment's hit interval is not empty and h(R) the expected
//! exponential measure of one forward ray's hit intervals (`rates`): the
//! spheres of one camera ray have density (σ/q)e^{−σs} along it, so one
//! forward ray hits h(R)/q of them on average. Only p_c and h depend on the
//! scene's geometry; everything else is explicit in (q, N_F, N_B).

use super::rates::Rates;
use mcrt_scene::{Phase, Scene};
use serde::Serialize;

/// The least cost of one iteration a table may give, ns (the sum of the
/// per-iteration, forward-ray and camera-ray costs, which every iteration
/// pays): all-zero costs made every iteration free (`optimize` then said
/// one iteration "takes longer" than the budget), and 1e-9 ns ones made
/// M = T/τ overflow u64. With τ ≥ 1 ns and T ≤ 1e9 s, M ≤ 1e18.
pub const MIN_ITERATION_NS: f64 = 1.0;

/// The number of costed operations, [`mcrt_scene::COST_KEYS`].
pub const OPERATIONS: usize = mcrt_scene::COST_KEYS.len();

/// Per-operation costs in nanoseconds with their standard errors (0 for
/// costs given by hand), in the order of [`mcrt_scene::COST_KEYS`] and
/// [`IterationCounts::as_array`]: per iteration, forward ray, camera ray,
/// forward segment, sphere, unit of S log₂ S (sorting), searching segment
/// and unit of log₂(1 + S), hit, hit in a Henyey–Greenstein medium.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CostTable {
    /// The operations' names (`trial_ns`, …), for reports.
    pub keys: [&'static str; OPERATIONS],
    /// The costs, ns.
    pub ns: [f64; OPERATIONS],
    /// Their standard errors, ns.
    pub std_errors: [f64; OPERATIONS],
    /// Where the costs come from (a calibration's machine and date, or the scene).
    pub source: String,
    /// The costs' covariance (ns²), from a calibration's fit: the costs are
    /// correlated (a run's time fixes their sum over its counts better than
    /// each alone), so time errors from it are smaller than from
    /// `std_errors` alone, which a `[cost]` table keeps (conservatively).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub covariance: Option<[[f64; OPERATIONS]; OPERATIONS]>,
}

impl CostTable {
    /// A table from costs and standard errors.
    pub fn from_array(ns: [f64; OPERATIONS], std_errors: [f64; OPERATIONS], source: String) -> CostTable {
        CostTable { keys: mcrt_scene::COST_KEYS, ns, std_errors, source, covariance: None }
    }

    /// Checks that every cost and error is a time in [0, 1e12] ns; the error names the key.
    pub fn validate(&self) -> Result<(), String> {
        for (name, v) in self.keys.iter().zip(self.ns) {
            if !(0.0..=1e12).contains(&v) {
                return Err(format!("cost.{name} = {v}: must be a time in nanoseconds in [0, 1e12]"));
            }
        }
        if self.std_errors.iter().any(|e| !(0.0..=1e12).contains(e)) {
            return Err(format!("cost.std_errors = {:?}: must be in [0, 1e12] ns", self.std_errors));
        }
        let least = self.least_iteration_ns();
        if !(least >= MIN_ITERATION_NS) {
            return Err(format!(
                "cost.trial_ns + cost.forward_ray_ns + cost.camera_ray_ns = {least:e} ns ({}): one iteration, with at \
                 least one forward and one camera ray, must cost at least {MIN_ITERATION_NS} ns (a few CPU cycles); \
                 with less, iterations are (nearly) free and their number in a budget, M = ⌊T/τ⌋, unbounded",
                self.source
            ));
        }
        Ok(())
    }

    /// What every iteration costs at least, whatever its parameters and
    /// integration volume: one trial, one forward ray, one camera ray (ns).
    pub fn least_iteration_ns(&self) -> f64 {
        let cost = |key: &str| self.keys.iter().position(|k| *k == key).map_or(0.0, |i| self.ns[i]);
        cost("trial_ns") + cost("forward_ray_ns") + cost("camera_ray_ns")
    }

    /// The scene's `[cost]` table, if it has one.
    pub fn from_scene(scene: &Scene) -> Option<CostTable> {
        scene.cost.map(|k| CostTable::from_array(k.ns, k.std_errors, "the scene's [cost] table".into()))
    }

    /// The table as a scene file's `[cost]` section (also a `--costs` file).
    pub fn to_toml(&self) -> String {
        let mut s = format!("# {}\n[cost]\n", self.source);
        // Shortest exact forms: the file gives back the fit (a cost of
        // 4e-5 ns was written 0.0000, as if held at 0).
        for (name, v) in self.keys.iter().zip(self.ns) {
            s.push_str(&format!("{name} = {v:?}\n"));
        }
        let e: Vec<String> = self.std_errors.iter().map(|e| format!("{e:?}")).collect();
        s.push_str(&format!("std_errors = [{}]\n", e.join(", ")));
        s
    }

    /// The reference machine's costs (2 cores, one thread timed;
    /// `mcrt-noise calibrate` on 2026-12-01), used when neither the scene's
    /// `[cost]` table nor `--costs` gives any. A renderer has costs of its own:
    /// give them, or the times are this tracer's.
    pub fn reference_machine() -> CostTable {
        super::reference_costs::REFERENCE_COSTS
    }

    /// Predicted wall time of one iteration with `counts`, in seconds, and
    /// its standard error from the costs' (with their covariance when the
    /// table has it; counts are expectations).
    pub fn seconds(&self, counts: &IterationCounts) -> (f64, f64) {
        let n = counts.as_array();
        let t: f64 = n.iter().zip(self.ns).map(|(n, c)| n * c).sum();
        let var: f64 = match &self.covariance {
            Some(cov) => (0..OPERATIONS).map(|i| (0..OPERATIONS).map(|j| n[i] * cov[i][j] * n[j]).sum::<f64>()).sum(),
            None => n.iter().zip(self.std_errors).map(|(n, e)| (n * e).powi(2)).sum(),
        };
        (t * 1e-9, var.max(0.0).sqrt() * 1e-9)
    }
}

/// Expected operation counts of one iteration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct IterationCounts {
    /// Always 1.
    pub trials: f64,
    /// N_F.
    pub forward_rays: f64,
    /// N_B.
    pub camera_rays: f64,
    /// N_F ν.
    pub segments: f64,
    /// N_B/q.
    pub spheres: f64,
    /// E[S log₂ S] for the S spheres of the iteration.
    pub sort_work: f64,
    /// N_F ν p_c(R) log₂(1 + N_B/q).
    pub search_work: f64,
    /// N_F N_B h(R)/q.
    pub hits: f64,
    /// Hits in a Henyey–Greenstein medium (the extra cost of evaluating
    /// its phase function for a contribution), else 0.
    pub hg_evaluations: f64,
}

/// The estimator's parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Parameters {
    /// Extinction probability per sub-step, (0, 1].
    pub q: f64,
    /// Sphere radius R (length).
    pub radius: f64,
    /// Forward rays per iteration, ≥ 1.
    pub forward_rays: u64,
    /// Camera rays per iteration, ≥ 1.
    pub camera_rays: u64,
}

impl Parameters {
    /// The scene's own parameters.
    pub fn of(scene: &Scene) -> Parameters {
        let e = &scene.estimator;
        Parameters { q: e.q, radius: e.radius, forward_rays: e.forward_rays, camera_rays: e.camera_rays }
    }

    /// `scene` with these parameters.
    pub fn apply(&self, scene: &Scene) -> Scene {
        let mut s = scene.clone();
        s.estimator.q = self.q;
        s.estimator.radius = self.radius;
        s.estimator.forward_rays = self.forward_rays;
        s.estimator.camera_rays = self.camera_rays;
        s
    }
}

impl IterationCounts {
    /// The counts in [`mcrt_scene::COST_KEYS`]'s order.
    pub fn as_array(&self) -> [f64; OPERATIONS] {
        [
            self.trials,
            self.forward_rays,
            self.camera_rays,
            self.segments,
            self.spheres,
            self.sort_work,
            self.search_work,
            self.hits,
            self.hg_evaluations,
        ]
    }

    /// Expected counts of one iteration of `scene` with parameters `p`
    /// (continuous N_F, N_B allowed), from the geometric `rates` at p's R.
    pub fn predict(scene: &Scene, rates: &Rates, q: f64, n_f: f64, n_b: f64) -> IterationCounts {
        let spheres = n_b / q;
        let segments = n_f * rates.segments_per_ray;
        let hits = n_f * n_b * rates.hit_measure.value / q;
        IterationCounts {
            trials: 1.0,
            forward_rays: n_f,
            camera_rays: n_b,
            segments,
            spheres,
            sort_work: expected_s_log2_s(n_b, q),
            search_work: segments * rates.candidate_fraction.value * (1.0 + spheres).log2(),
            hits,
            hg_evaluations: if matches!(scene.medium.phase, Phase::HenyeyGreenstein { .. }) { hits } else { 0.0 },
        }
    }
}

/// E[S log₂ S] for S, the spheres of one iteration: the sum of `n_b`
/// independent geometric counts with mean 1/q (S = N_B + a negative
/// binomial number of continuations). Summed exactly over S's distribution
/// while its mean is at most 64 (continuous N_B is rounded up to the next
/// count); beyond, by the second-order expansion m log₂ m + Var S/(2m ln 2),
/// within 1.7 % of the exact sum for one camera ray (q = 1/64: 429.4
/// against 422.3) and within 0.05 % from 8 camera rays on. The searches
/// evaluate it millions of times; the exact sum costs ~20 q⁻¹ terms.
pub fn expected_s_log2_s(n_b: f64, q: f64) -> f64 {
    let mean = n_b / q;
    let var = n_b * (1.0 - q) / (q * q);
    if q >= 1.0 {
        return mean * mean.log2().max(0.0);
    }
    if mean > 64.0 {
        return mean * mean.log2() + var / (2.0 * mean * std::f64::consts::LN_2);
    }
    // S = r + X, X ~ NegBin(r, q): P(X = k) = C(k + r − 1, k) q^r (1 − q)^k.
    let r = n_b.ceil().max(1.0);
    let mut p = q.powf(r); // P(X = 0)
    let mut total = 0.0;
    let mut mass = 0.0;
    let mut k = 0.0f64;
    while mass < 1.0 - 1e-13 && k < 1e7 {
        let s = r + k;
        total += p * s * s.log2();
        mass += p;
        p *= (k + r) / (k + 1.0) * (1.0 - q);
        k += 1.0;
        if p == 0.0 && k > mean {
            break;
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn s_log_s_is_exact_for_one_certain_sphere_and_close_to_the_expansion_for_many() {
        assert_eq!(expected_s_log2_s(1.0, 1.0), 0.0);
        assert_eq!(expected_s_log2_s(8.0, 1.0), 24.0);
        // One geometric count with q = 1/2: Σ k log₂ k 2^{−k}, by brute force.
        let brute: f64 = (1..200).map(|k| (k as f64) * (k as f64).log2() * 0.5f64.powi(k)).sum();
        // The sum stops once 1 − 10⁻¹³ of the mass is in: the tail left is ~10⁻¹³·k log₂ k ≈ 3e-11.
        assert!((expected_s_log2_s(1.0, 0.5) - brute).abs() < 1e-10);
        // At the switch (mean 64) the exact sum and the expansion agree to
        // 1.7 % for one camera ray and 0.03 % for eight.
        let expansion = |n_b: f64, q: f64| {
            let (m, v) = (n_b / q, n_b * (1.0 - q) / (q * q));
            m * f64::log2(m) + v / (2.0 * m * std::f64::consts::LN_2)
        };
        for (n_b, q, tol) in [(1.0, 1.0 / 64.0, 0.017), (8.0, 0.125, 3.1e-4)] {
            let exact = expected_s_log2_s(n_b, q);
            assert!(((expansion(n_b, q) - exact) / exact).abs() < tol, "{n_b}, {q}: {exact}");
        }
        assert_eq!(expected_s_log2_s(8.0, 0.1), expansion(8.0, 0.1));
    }
}
