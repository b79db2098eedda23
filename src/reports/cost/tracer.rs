//! The reference tracer's cost: speed on 1 and 2 threads, and its standard
//! errors against trials and wall time (what a Monte Carlo answer costs,
//! beside what the oracle's costs).

use super::bundled_scene;
use super::figures::Series;
use super::target::{duration, Ledger, Target};
use mcrt_reference::{trace, HitMethod, Tracer};
use std::fmt::Write;
use std::time::Instant;

/// Trial counts of the standard-error table (the largest takes ~5 s on 2 cores).
const TRIALS: [u64; 5] = [1_000, 10_000, 100_000, 300_000, 1_000_000];

/// The tracer's speed table and its standard-error table; the figure's
/// series (log₁₀ relative standard error against log₁₀ trials and log₁₀ ms).
pub(crate) fn section(s: &mut String, ledger: &mut Ledger) -> Result<(Vec<Series>, Vec<Series>), String> {
    let mut scene = bundled_scene("point-isotropic")?;
    scene.estimator.radius = 0.05;
    writeln!(s, "## The reference tracer on `scenes/point-isotropic.toml` with R = 0.05").unwrap();
    writeln!(s).unwrap();
    writeln!(s, "q = {}, N_F = {}, N_B = {}, order 0; 200 000 trials, best of 3. Target of issue 4: at least 10⁵ trials/s with 2 threads (a vectorised NumPy brute force of the same estimator: ~1.3·10⁴ trials/s on one core).", scene.estimator.q, scene.estimator.forward_rays, scene.estimator.camera_rays).unwrap();
    writeln!(s).unwrap();
    writeln!(s, "| threads | trials/s | forward segments/s | target | met |").unwrap();
    writeln!(s, "|---:|---:|---:|---|---|").unwrap();
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().map_err(|e| e.to_string())?;
        let (trials, segments) = pool.install(|| crate::reports::tracer_checks::speed(&scene, 200_000, 3))?;
        let target = if threads == 2 {
            Target::AtLeast { per_second: 1e5, unit: "trials", source: "issue 4" }
        } else {
            Target::None
        };
        let met = ledger.judge(&format!("tracer, {threads} threads"), target, Some(trials));
        writeln!(s, "| {threads} | {trials:.3e} | {segments:.3e} | {} | {met} |", target.cell()).unwrap();
    }
    writeln!(s).unwrap();
    writeln!(s, "### Standard error against trials and time").unwrap();
    writeln!(s).unwrap();
    writeln!(s, "Seed 1, all cores; relative standard errors of the mean and of Var L (s²). Both fall as M^(−1/2): 10× the accuracy costs 100× the time, where the oracle's cost grows with the digits asked for (above).").unwrap();
    writeln!(s).unwrap();
    writeln!(s, "| trials | mean L | rel. se | Var L | rel. se | wall time |").unwrap();
    writeln!(s, "|---:|---|---:|---|---:|---:|").unwrap();
    let tracer = Tracer::new(&scene).map_err(|e| e.to_string())?;
    let mut by_trials: [Vec<[f64; 2]>; 2] = Default::default();
    let mut by_time: [Vec<[f64; 2]>; 2] = Default::default();
    for m in TRIALS {
        let t0 = Instant::now();
        let run = trace(&tracer, 1, 0..m, HitMethod::Sorted, &|_| {});
        let secs = t0.elapsed().as_secs_f64();
        match run.estimates().summary() {
            Ok(sum) => {
                let rel_mean = sum.mean.se / sum.mean.value;
                let rel_var = sum.variance.se / sum.variance.value;
                let (lm, lt) = ((m as f64).log10(), (secs * 1e3).log10());
                for (k, rel) in [rel_mean, rel_var].into_iter().enumerate() {
                    by_trials[k].push([lm, rel.log10()]);
                    by_time[k].push([lt, rel.log10()]);
                }
                writeln!(
                    s,
                    "| {m} | {:.5e} ± {:.1e} | {rel_mean:.2e} | {:.5e} ± {:.1e} | {rel_var:.2e} | {} |",
                    sum.mean.value,
                    sum.mean.se,
                    sum.variance.value,
                    sum.variance.se,
                    duration(secs)
                )
                .unwrap();
            }
            Err(why) => writeln!(s, "| {m} | **{why}** | — | — | — | {} |", duration(secs)).unwrap(),
        }
    }
    let [a, b] = by_trials;
    let [c, d] = by_time;
    Ok((vec![("mean L".into(), a), ("Var L".into(), b)], vec![("mean L".into(), c), ("Var L".into(), d)]))
}
