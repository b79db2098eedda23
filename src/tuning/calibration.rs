//! Per-operation costs fitted from timed runs: each run gives its wall time
//! per iteration and its counters; the costs are the weighted least-squares
//! solution of time/iteration = Σ cost_i × count_i/iteration (relative
//! residuals, so that fast and slow runs count alike), with standard errors
//! from the residuals (σ̂² (AᵀA)⁻¹). A cost the data cannot make positive
//! (negative in the fit) is held at 0 and the rest refitted, one at a time
//! (non-negative least squares by elimination); the fit says which.

use super::cost::{expected_s_log2_s, CostTable, MIN_ITERATION_NS, OPERATIONS};
use mcrt_reference::Counters;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// The reference machine's costs (`tuning::cost::CostTable::reference_machine`);
/// see `reference_costs` for where they come from.
pub const REFERENCE_COSTS: CostTable = super::reference_costs::REFERENCE_COSTS;

/// One timed run.
#[derive(Debug, Clone, Serialize)]
pub struct Measurement {
    /// What was run (scene and parameters), for reports.
    pub label: String,
    /// N_B of the run.
    pub camera_rays: u64,
    /// q of the run.
    pub q: f64,
    /// What the run did (its counters, summed over its trials).
    pub counters: Counters,
    /// Wall time of the run in seconds (one thread).
    pub seconds: f64,
    /// Whether the scene's medium is Henyey–Greenstein.
    pub hg: bool,
}

impl Measurement {
    /// Seconds per iteration.
    pub fn seconds_per_iteration(&self) -> f64 {
        self.seconds / self.counters.trials as f64
    }

    /// The measured counts per iteration, in [`mcrt_scene::COST_KEYS`]'
    /// order (sorting and searching from the sphere count, as the model has them).
    pub fn counts_per_iteration(&self) -> [f64; OPERATIONS] {
        let c = &self.counters;
        let t = c.trials as f64;
        let spheres = c.sphere_placements as f64 / t;
        [
            1.0,
            c.forward_rays as f64 / t,
            self.camera_rays as f64,
            c.forward_segments as f64 / t,
            spheres,
            expected_s_log2_s(self.camera_rays as f64, self.q),
            c.candidate_tests as f64 / t * (1.0 + self.camera_rays as f64 / self.q).log2(),
            c.hits as f64 / t,
            // The model's HG cost is per hit in such a medium (the tracer
            // evaluates f once per hitting segment; a renderer may per hit).
            if self.hg { c.hits as f64 / t } else { 0.0 },
        ]
    }
}

/// The fitted costs and how well they fit.
#[derive(Debug, Clone, Serialize)]
pub struct Fit {
    /// The costs with their standard errors; a cost held at 0 carries its
    /// resolution instead ([`Fit::held_at_zero`]).
    pub costs: CostTable,
    /// Costs held at 0 because the fit made them negative (by name): not
    /// resolved from 0. Their standard error in `costs` is the data's
    /// resolution of them (what the fit's residual scatter allows were
    /// they free), not a measured 0 ± 0.
    pub held_at_zero: Vec<&'static str>,
    /// RMS of the relative residuals.
    pub rms_relative_residual: f64,
    /// Largest |relative residual|.
    pub max_relative_residual: f64,
}

const NAMES: [&str; OPERATIONS] = mcrt_scene::COST_KEYS;

impl Fit {
    /// The fitted `[cost]` table as a file (`calibrate --out`), a cost held
    /// at 0 marked where it stands: not resolved from 0, its standard error
    /// its resolution (read back, it is taken as that standard error).
    pub fn to_toml(&self) -> String {
        let mut out = String::new();
        for line in self.costs.to_toml().lines() {
            out.push_str(line);
            let key = line.split(" = ").next().unwrap_or("");
            if self.held_at_zero.contains(&key) {
                out.push_str("  # held at 0 by the fit (it made it negative): not resolved from 0; its std_error is its resolution");
            }
            out.push('\n');
        }
        out
    }
}

/// The rows of the fit over the costs `active`, each scaled by 1/time
/// (relative residuals): A with A x ≈ 1.
fn design(runs: &[Measurement], active: &[usize]) -> DMatrix<f64> {
    DMatrix::from_fn(runs.len(), active.len(), |i, k| {
        runs[i].counts_per_iteration()[active[k]] / (runs[i].seconds_per_iteration() * 1e9)
    })
}

/// Fits the costs to `runs`; `source` names the machine and date.
/// Needs more runs than free costs, and every cost exercised by some run.
pub fn fit(runs: &[Measurement], source: String) -> Result<Fit, String> {
    let exercised: Vec<usize> =
        (0..OPERATIONS).filter(|&j| runs.iter().any(|r| r.counts_per_iteration()[j] > 0.0)).collect();
    if let Some(j) = (0..OPERATIONS).find(|j| !exercised.contains(j)) {
        return Err(format!("cost.{}: no timed run exercises it, so the fit cannot measure it", NAMES[j]));
    }
    let mut active = exercised.clone();
    let mut held: Vec<&'static str> = Vec::new();
    loop {
        let (n, p) = (runs.len(), active.len());
        if p == 0 {
            return Err(format!(
                "the fit held every cost at 0 ({}): the timed runs do not resolve any; time longer runs (calibrate \
                 --seconds) on an otherwise idle machine",
                held.join(", ")
            ));
        }
        if n <= p {
            return Err(format!("{n} runs cannot fit {p} costs: time more parameter sets"));
        }
        let a = design(runs, &active);
        let b = DVector::from_element(n, 1.0);
        let svd = a.clone().svd(true, true);
        let x = svd.solve(&b, 1e-12).map_err(|e| format!("least squares: {e}"))?;
        if let Some((k, _)) = x.iter().enumerate().filter(|(_, v)| **v < 0.0).min_by(|a, b| a.1.total_cmp(b.1)) {
            held.push(NAMES[active[k]]);
            active.remove(k);
            continue;
        }
        let resid = &a * &x - &b;
        let s2 = resid.norm_squared() / (n - p) as f64;
        let cov = (a.transpose() * &a).try_inverse().ok_or("the timed runs do not separate the costs")? * s2;
        let mut c = [0.0; OPERATIONS];
        let mut full = [[0.0; OPERATIONS]; OPERATIONS];
        for (k, &j) in active.iter().enumerate() {
            c[j] = x[k];
            for (l, &i) in active.iter().enumerate() {
                full[j][i] = cov[(k, l)];
            }
        }
        // A held cost is not resolved from 0: its bar is its resolution
        // with every cost free at this fit's scatter, kept independent.
        let resolution = free_variances(runs, &exercised, s2)?;
        for &j in exercised.iter().filter(|&&j| !active.contains(&j)) {
            full[j][j] = resolution[j];
        }
        let e = std::array::from_fn(|j| full[j][j].max(0.0).sqrt());
        let max = resid.iter().fold(0.0f64, |m, r| m.max(r.abs()));
        let mut costs = CostTable::from_array(c, e, source);
        costs.covariance = Some(full);
        // A table `optimize` would refuse is no result: say why and what to do.
        if let Err(why) = costs.validate() {
            let held_text = if held.is_empty() { String::new() } else { format!(" (held at 0: {})", held.join(", ")) };
            let hint = if costs.least_iteration_ns() < MIN_ITERATION_NS {
                "; the timed runs do not resolve what one iteration costs: time longer runs (calibrate --seconds) on \
                 an otherwise idle machine"
            } else {
                ""
            };
            return Err(format!("the fit is not a usable [cost] table{held_text}: {why}{hint}"));
        }
        return Ok(Fit {
            costs,
            held_at_zero: held,
            rms_relative_residual: (resid.norm_squared() / n as f64).sqrt(),
            max_relative_residual: max,
        });
    }
}

/// The variance of each cost were all of `exercised` free, at the residual
/// variance `s2` (relative): s2·((AᵀA)⁻¹)ⱼⱼ, by cost index.
fn free_variances(runs: &[Measurement], exercised: &[usize], s2: f64) -> Result<[f64; OPERATIONS], String> {
    let a = design(runs, exercised);
    let inv = (a.transpose() * &a).try_inverse().ok_or("the timed runs do not separate the costs")?;
    let mut v = [0.0; OPERATIONS];
    for (k, &j) in exercised.iter().enumerate() {
        v[j] = s2 * inv[(k, k)];
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(q: f64, n_b: u64, n_f: u64, seg: f64, hits: u64, cand: u64, secs_ns: [f64; OPERATIONS]) -> Measurement {
        let trials = 1000u64;
        let counters = Counters {
            trials,
            forward_rays: n_f * trials,
            forward_segments: (n_f as f64 * seg) as u64 * trials,
            sphere_placements: (n_b as f64 / q) as u64 * trials,
            candidate_tests: cand * trials,
            hits: hits * trials,
            hg_evaluations: 0,
            ..Counters::default()
        };
        // Every third run in a Henyey–Greenstein medium.
        let hg = n_f % 3 == 0;
        let mut m = Measurement { label: String::new(), camera_rays: n_b, q, counters, seconds: 0.0, hg };
        let per: f64 = m.counts_per_iteration().iter().zip(secs_ns).map(|(n, c)| n * c).sum();
        m.seconds = per * 1e-9 * trials as f64;
        m
    }

    const SETS: [(f64, u64, u64, f64, u64, u64); 12] = [
        (1.0, 1, 10, 1.0, 0, 1),
        (0.5, 8, 200, 1.0, 3, 20),
        (0.1, 8, 51, 1.8, 40, 9),
        (0.02, 64, 20, 1.8, 200, 5),
        (1.0, 64, 1000, 1.0, 10, 100),
        (0.2, 1, 402, 2.5, 2, 60),
        (0.5, 256, 5, 1.0, 30, 2),
        (0.05, 16, 102, 1.0, 50, 30),
        (1.0, 8, 3000, 1.8, 1, 400),
        (0.01, 4, 30, 1.0, 25, 7),
        (0.3, 32, 66, 1.2, 80, 12),
        (0.7, 2, 700, 2.0, 5, 90),
    ];

    fn runs(truth: [f64; OPERATIONS]) -> Vec<Measurement> {
        SETS.iter().map(|&(q, nb, nf, seg, hits, cand)| run(q, nb, nf, seg, hits, cand, truth)).collect()
    }

    #[test]
    fn exact_timings_give_back_their_costs() {
        let truth = [1500.0, 50.0, 300.0, 40.0, 10.0, 2.0, 3.0, 6.0, 9.0];
        let f = fit(&runs(truth), "test".into()).unwrap();
        for (got, want) in f.costs.ns.iter().zip(truth) {
            assert!((got - want).abs() <= 1e-6 * want.max(1.0), "{:?}", f.costs);
        }
        assert!(f.held_at_zero.is_empty());
        assert!(f.max_relative_residual < 1e-9);
    }

    /// The outside probe, item 14: a cost the fit made negative was held
    /// at 0 and printed, and written, as `0.000 ± 0.000`, a measurement of
    /// exactly nothing. Timings whose HG cost is −5 ns (the data pull it
    /// below 0): it is held at 0, and its standard error is its resolution
    /// at the constrained fit's scatter, which is not 0 (the held cost
    /// leaves residuals), nor is it left out of the covariance.
    #[test]
    fn a_cost_held_at_zero_carries_its_resolution_not_zero() {
        let truth = [1500.0, 50.0, 300.0, 40.0, 10.0, 2.0, 3.0, 6.0, -5.0];
        let f = fit(&runs(truth), "test".into()).unwrap();
        assert_eq!(f.held_at_zero, vec!["hg_ns"]);
        let j = NAMES.iter().position(|k| *k == "hg_ns").unwrap();
        assert_eq!(f.costs.ns[j], 0.0);
        assert!(f.rms_relative_residual > 0.0);
        assert!(f.costs.std_errors[j] > 0.0, "{:?}", f.costs.std_errors);
        let var = f.costs.covariance.unwrap()[j][j];
        assert!((var - f.costs.std_errors[j].powi(2)).abs() <= 4.0 * f64::EPSILON * var, "{var}");
    }

    /// A CI run (3 December 2026, `calibrate --seconds 0.05` on a loaded
    /// machine) held trial, forward-ray and camera-ray costs all at 0 and
    /// wrote a table that `optimize --costs` then refused (iterations free,
    /// M unbounded). The fit itself refuses such a table, naming the costs
    /// held and the remedy: timings whose per-iteration costs are negative
    /// (the data pull them below 0), the rest positive.
    #[test]
    fn a_fit_whose_iterations_are_free_is_refused() {
        let truth = [-100.0, -5.0, -30.0, 40.0, 10.0, 2.0, 3.0, 6.0, 9.0];
        let measured = runs(truth);
        assert!(measured.iter().all(|m| m.seconds > 0.0), "the timings themselves are positive");
        let e = fit(&measured, "test".into()).unwrap_err();
        let held = e.split("(held at 0: ").nth(1).and_then(|t| t.split(')').next()).unwrap_or_else(|| panic!("{e}"));
        for key in ["trial_ns", "forward_ray_ns", "camera_ray_ns"] {
            assert!(held.contains(key), "{key} not named as held: {e}");
        }
        assert!(e.contains("must cost at least") && e.contains("calibrate --seconds"), "{e}");
        // Timings no cost can explain hold every cost: an error, not a
        // least-squares problem with no unknowns (nalgebra panics on one).
        let e = fit(&runs([-1.0; OPERATIONS]), "test".into()).unwrap_err();
        assert!(e.contains("held every cost at 0"), "{e}");
    }

    #[test]
    fn a_cost_no_run_exercises_is_refused() {
        let mut r = runs([1500.0, 50.0, 300.0, 40.0, 10.0, 2.0, 3.0, 6.0, 9.0]);
        r.iter_mut().for_each(|m| m.hg = false);
        let e = fit(&r, "test".into()).unwrap_err();
        assert!(e.contains("cost.hg_ns: no timed run exercises it"), "{e}");
    }
}
