//! Issue 21's speed row: the oracle of every scattering order (`"all"`) on
//! the README scene, f64 to 1e−6, against what the reference tracer needs
//! for the same Var L to 0.1 %.

use super::target::{duration, Ledger, Target};
use super::{best_of, bundled_scene};
use std::fmt::Write;
use std::time::Instant;

/// The README scene (`point-isotropic`, albedo 0.8) with every order at
/// q = 1 and N_B = 1 (where Var L of every order is modelled), at R = 0.2
/// with N_F = 20 and at the scene's own R = 0.01 with its N_F = 200: the
/// oracle's mean and Var L (`oracle::every_order_mean`, the mean to 1e−6,
/// Var L's integrals at 1e−4), best of 3, target ≤ 10 s on two cores; the
/// tracer's time for Var L to 0.1 % from a run of 2·10⁵ trials (its
/// standard error ∝ 1/√M), and the ratio.
pub(super) fn section(s: &mut String, ledger: &mut Ledger) -> Result<(), String> {
    writeln!(s, "## Every scattering order on the README scene (`scattering_orders = \"all\"`)").unwrap();
    writeln!(s).unwrap();
    writeln!(s, "`scenes/point-isotropic.toml` (albedo 0.8) with `scattering_orders = \"all\"`, q = 1 and N_B = 1, where the finite-sphere model of every order has Var L exact at R (`docs/model.md` §10.3; what `predict` and `mcrt-noise oracle` compute): the mean to 1e−6, Var L's integrals (P, the same-path pairs) at 10⁻⁴ (`oracle::EVERY_ORDER_VARIANCE_TOL`; their bars are the computed ones, ~10⁻⁶ relative); best of 3 runs on two cores. Target of issue 21: ≤ 10 s. The tracer's time for Var L to 0.1 % is extrapolated from one run of 2·10⁵ trials on both cores (its standard error falls as 1/√M).").unwrap();
    writeln!(s).unwrap();
    writeln!(s, "| R, N_F | Var L | evaluations | wall time | target | met | tracer for 0.1 % | tracer / oracle |")
        .unwrap();
    writeln!(s, "|---|---|---:|---:|---|---|---:|---:|").unwrap();
    let target = Target::AtMost { seconds: 10.0, source: "issue 21" };
    for (radius, n_f) in [(0.2, 20u64), (0.01, 200)] {
        let mut scene = bundled_scene("point-isotropic")?;
        scene.effects.scattering_orders = mcrt_scene::ScatteringOrders::All;
        (scene.estimator.q, scene.estimator.camera_rays) = (1.0, 1);
        (scene.estimator.radius, scene.estimator.forward_rays) = (radius, n_f);
        let budget = || crate::quad::Budget::new(crate::quad::DEFAULT_EVALUATIONS);
        let (out, secs) = best_of(3, || crate::oracle::every_order_mean(&scene, None, &budget()));
        let var = out.as_ref().ok().and_then(|m| m.variance.map(|v| (v, m.evaluations)));
        let label = format!("{radius}, {n_f}");
        let met = ledger.judge(&format!("every order, README scene, R = {radius}, f64"), target, var.map(|_| secs));
        let tracer = tracer_seconds(&scene)?;
        let (time, cell) = (duration(secs), target.cell());
        match (var, out) {
            (Some((v, evaluations)), _) => writeln!(
                s,
                "| {label} | {:.10e} ± {:.1e} | {evaluations} | {time} | {cell} | {met} | {} | {:.0} |",
                v.value,
                v.error,
                duration(tracer),
                tracer / secs
            ),
            (None, Ok(m)) => writeln!(
                s,
                "| {label} | **{}** | {} | {time} | {cell} | {met} | {} | — |",
                m.variance_missing.unwrap_or_default(),
                m.evaluations,
                duration(tracer)
            ),
            (None, Err(e)) => {
                writeln!(s, "| {label} | **{e}** | — | {time} | {cell} | {met} | {} | — |", duration(tracer))
            }
        }
        .unwrap();
    }
    Ok(())
}

/// Seconds the reference tracer needs for Var L of `scene` to 0.1 %
/// relative standard error, from a run of 2·10⁵ trials.
fn tracer_seconds(scene: &mcrt_scene::Scene) -> Result<f64, String> {
    let tracer = mcrt_reference::Tracer::new(scene).map_err(|e| e.to_string())?;
    let trials = 200_000u64;
    let t0 = Instant::now();
    let run = mcrt_reference::trace(&tracer, 1, 0..trials, mcrt_reference::HitMethod::Sorted, &|_| {});
    let secs = t0.elapsed().as_secs_f64();
    let sum = run.estimates().summary()?;
    let rel = sum.variance.se / sum.variance.value;
    Ok(secs * (rel / 1e-3).powi(2))
}
