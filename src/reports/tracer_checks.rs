//! The generated `docs/tracer-checks.md`: the reference tracer against both
//! oracle models as R falls (the small-sphere model's own error, measured;
//! the finite-sphere model's agreement), the pair correlation measured
//! directly, and the tracer's speed.

use crate::model::correlations::pointwise;
use crate::model::field::Field;
use crate::oracle::{run, Precision};
use crate::quad::{integrate, Domain, Options};
use crate::reports::compare::{sides, small_sphere_sides, Side};
use mcrt_reference::correlation::pair_correlation;
use mcrt_reference::moments::WithError;
use mcrt_reference::{trace, HitMethod, Tracer};
use mcrt_scene::Scene;
use std::fmt::Write;
use std::path::Path;
use std::time::Instant;

/// Radii of the documented sweep.
pub const SWEEP_RADII: [f64; 5] = [0.2, 0.1, 0.05, 0.02, 0.01];
/// Trials per radius.
pub const SWEEP_TRIALS: u64 = 4_000_000;
/// The tracer's seed, for every measurement of the document.
pub const SWEEP_SEED: u64 = 11;
/// The sweep's scene.
pub const SWEEP_SCENE: &str = "point-isotropic";
/// Radii of the forward-peaked sweep (scene `point-hg-forward`, g = 0.9).
pub const HG_RADII: [f64; 3] = [0.2, 0.1, 0.05];
/// Trials per radius of the forward-peaked sweep.
pub const HG_TRIALS: u64 = 8_000_000;

/// The table of a sweep: tracer against both models.
fn sweep_table(w: &mut String, rows: &[SweepRow]) {
    writeln!(w).unwrap();
    writeln!(w, "| R | mean: tracer/small | z | tracer/finite | z | Var L: tracer/small | z | tracer/finite | z |")
        .unwrap();
    writeln!(w, "|---|---|---|---|---|---|---|---|---|").unwrap();
    let rel = |s: &Side| s.ratio_error;
    for r in rows {
        writeln!(
            w,
            "| {} | {:.5} ± {:.5} | {:+.2} | {:.5} ± {:.5} | {:+.2} | {:.5} ± {:.5} | {:+.2} | {:.5} ± {:.5} | {:+.2} |",
            r.radius,
            r.mean.ratio,
            rel(&r.mean),
            r.mean.z,
            r.finite_mean.ratio,
            rel(&r.finite_mean),
            r.finite_mean.z,
            r.variance.ratio,
            rel(&r.variance),
            r.variance.z,
            r.finite_variance.ratio,
            rel(&r.finite_variance),
            r.finite_variance.z
        )
        .unwrap();
    }
}

/// One radius of the sweep: the tracer beside the small-sphere model
/// (`mean`, `variance`) and beside the finite-sphere one.
#[derive(Debug, Clone)]
pub struct SweepRow {
    /// Sphere radius R (length).
    pub radius: f64,
    /// Mean luminance: small-sphere model beside the tracer.
    pub mean: Side,
    /// Var L of one iteration: small-sphere model beside the tracer.
    pub variance: Side,
    /// Mean luminance: the oracle's prediction (finite-sphere model where it exists) beside the tracer.
    pub finite_mean: Side,
    /// Var L: the oracle's prediction (finite-sphere model where it exists) beside the tracer.
    pub finite_variance: Side,
}

/// Oracle and tracer at each radius (the scene's other parameters kept).
pub fn sweep(scene: &Scene, radii: &[f64], trials: u64, seed: u64) -> Result<Vec<SweepRow>, String> {
    radii
        .iter()
        .map(|&radius| {
            let mut s = scene.clone();
            s.estimator.radius = radius;
            let oracle = run(&s, Precision::F64, None).map_err(|e| e.to_string())?;
            let tracer = Tracer::new(&s).map_err(|e| e.to_string())?;
            let summary = trace(&tracer, seed, 0..trials, HitMethod::Sorted, &|_| {}).estimates().summary()?;
            let (mean, variance) =
                small_sphere_sides(&oracle, &summary).ok_or("the oracle has no small-sphere Var L here")?;
            let (finite_mean, finite_variance) = sides(&oracle, &summary);
            Ok(SweepRow { radius, mean, variance, finite_mean, finite_variance })
        })
        .collect()
}

/// Trials per second and forward segments per second of `trials` trials on
/// the current rayon pool (the best of `repeats` runs).
pub fn speed(scene: &Scene, trials: u64, repeats: usize) -> Result<(f64, f64), String> {
    let tracer = Tracer::new(scene).map_err(|e| e.to_string())?;
    let mut best = f64::INFINITY;
    let mut segments = 0;
    for _ in 0..repeats {
        let start = Instant::now();
        let r = trace(&tracer, 1, 0..trials, HitMethod::Sorted, &|_| {});
        best = best.min(start.elapsed().as_secs_f64());
        segments = r.counters.forward_segments;
    }
    Ok((trials as f64 / best, segments as f64 / best))
}

/// The correlation check: position s of the first sphere.
pub const CORR_S: f64 = 0.8;
/// The correlation check's sphere radius R.
pub const CORR_RADIUS: f64 = 0.05;
/// Number of t-bins over t ∈ [0, 2.4 R].
pub const CORR_BINS: usize = 24;
/// Forward rays the tracer measures the correlation with.
pub const CORR_RAYS: u64 = 40_000_000;

/// One t-bin: the oracle's bin average of (21)–(22) (corrected) beside the
/// tracer's measurement.
#[derive(Debug, Clone)]
pub struct CorrRow {
    /// Lower end of the bin in t (length).
    pub t0: f64,
    /// Upper end of the bin in t (length).
    pub t1: f64,
    /// The oracle's bin average of ⟨𝒞(s)𝒞(s+t)⟩ (unshifted).
    pub oracle: f64,
    /// Its quadrature bar.
    pub oracle_error: f64,
    /// The tracer's bin average with its standard error.
    pub tracer: WithError,
}

/// ⟨𝒞(s)𝒞(s+t)⟩ over t-bins of width `max_t/bins`: oracle (the bin average
/// of `pointwise`, by quadrature) and tracer (`pair_correlation`).
pub fn correlation_rows(scene: &Scene, s: f64, max_t: f64, bins: usize, rays: u64) -> Result<Vec<CorrRow>, String> {
    let field = Field::from_scene(scene, &0.0f64).map_err(|e| e.to_string())?;
    let r = scene.estimator.radius;
    let x = s - field.center;
    let unshift = (-field.shift).exp();
    let edges: Vec<f64> = (0..=bins).map(|k| max_t * k as f64 / bins as f64).collect();
    let tracer = Tracer::new(scene).map_err(|e| e.to_string())?;
    let measured = pair_correlation(&tracer, SWEEP_SEED, 0..rays, s, &edges);
    // The correlation's support ends where the discs stop overlapping,
    // t·sin ϑ = 2R at the first-met sphere (s for light moving away from
    // the camera, s + t towards it): declared as a breakpoint, and beyond
    // it the integrand is zero by construction.
    let edge = overlap_edge(scene, s, max_t)?;
    let opts = Options { zero_guard: false, ..Options::rel(1e-10).declared() };
    edges
        .windows(2)
        .zip(measured)
        .map(|(w, m)| {
            let cuts: Vec<f64> = edge.iter().copied().filter(|e| *e > w[0] && *e < w[1]).collect();
            let domain = Domain::finite(w[0], w[1]).with_breakpoints(cuts);
            let e = integrate(|t: &f64| pointwise(&field, &x, t, &r), &domain, &opts).map_err(|f| f.to_string())?;
            let width = w[1] - w[0];
            Ok(CorrRow {
                t0: w[0],
                t1: w[1],
                oracle: e.value * unshift / width,
                oracle_error: e.error * unshift / width,
                tracer: m,
            })
        })
        .collect()
}

/// Where t·sin ϑ(first-met sphere) = 2R for the scene's single point light,
/// by bisection (`None` if beyond `max_t`). Geometry only.
fn overlap_edge(scene: &Scene, s: f64, max_t: f64) -> Result<Option<f64>, String> {
    let [mcrt_scene::Light::Point { position, .. }] = scene.lights[..] else {
        return Err("the correlation check needs a scene with one point light".into());
    };
    let (o, u, r) = (scene.camera.origin, scene.camera.direction, scene.estimator.radius);
    let sin_at = |s: f64| {
        let v = (o + u * s - position).normalize();
        (u.dot(v), v.cross(u).length())
    };
    let (mu, _) = sin_at(s);
    let g = |t: f64| {
        let first = if mu >= 0.0 { s } else { s + t };
        t * sin_at(first).1 - 2.0 * r
    };
    if g(max_t) <= 0.0 {
        return Ok(None);
    }
    let (mut lo, mut hi) = (0.0, max_t);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if g(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok(Some(hi))
}

/// The paper's (21) as printed in bin k, to first order in R: ½·(corrected
/// at 2t), whose bin average is half the mean of bins 2k and 2k + 1.
fn paper_bin(rows: &[CorrRow], k: usize) -> f64 {
    match (rows.get(2 * k), rows.get(2 * k + 1)) {
        (Some(a), Some(b)) => 0.25 * (a.oracle + b.oracle),
        (Some(a), None) => 0.5 * a.oracle,
        _ => 0.0,
    }
}

fn corr_svg(rows: &[CorrRow], radius: f64) -> Result<String, String> {
    use poloto::build;
    let mid = |r: &CorrRow| 0.5 * (r.t0 + r.t1) / radius;
    let oracle: Vec<[f64; 2]> = rows.iter().map(|r| [mid(r), r.oracle]).collect();
    let tracer: Vec<[f64; 2]> = rows.iter().map(|r| [mid(r), r.tracer.value]).collect();
    let plots =
        poloto::plots!(build::plot("oracle (21)-(22), corrected").line(oracle), build::plot("tracer").scatter(tracer));
    poloto::frame_build()
        .data(plots)
        .build_and_label(("<C(s)C(s+t)>, point-isotropic, s = 0.8".to_string(), "t / R", "bin average"))
        .append_to(poloto::header().light_theme())
        .render_string()
        .map_err(|e| e.to_string())
}

/// Tracer/oracle against log₁₀ R, with the variance's ±2 se band (at small
/// R the ratio is within noise of 1; |ratio − 1| on log axes would hide it).
fn svg(rows: &[SweepRow]) -> Result<String, String> {
    use poloto::build;
    let x = |r: &SweepRow| r.radius.log10();
    let ratio = |pick: fn(&SweepRow) -> &Side, k: f64| -> Vec<[f64; 2]> {
        rows.iter().map(|r| [x(r), pick(r).ratio + k * pick(r).tracer_se / pick(r).oracle]).collect()
    };
    let plots = poloto::plots!(
        build::plot("Var, small-sphere").scatter(ratio(|r| &r.variance, 0.0)),
        build::plot("+2se").line(ratio(|r| &r.variance, 2.0)),
        build::plot("-2se").line(ratio(|r| &r.variance, -2.0)),
        build::plot("mean, small-sphere").scatter(ratio(|r| &r.mean, 0.0)),
        build::plot("Var, finite-sphere").scatter(ratio(|r| &r.finite_variance, 0.0)),
        build::plot("mean, finite-sphere").scatter(ratio(|r| &r.finite_mean, 0.0))
    );
    poloto::frame_build()
        .data(plots)
        .build_and_label(("tracer/oracle, point-isotropic".to_string(), "log₁₀ R", "tracer/oracle"))
        .append_to(poloto::header().light_theme())
        .render_string()
        .map_err(|e| e.to_string())
}

/// The scenes the document reads from its scenes directory.
pub const SCENE_NAMES: [&str; 2] = [SWEEP_SCENE, "point-hg-forward"];

/// The tracer against the exact Var L of every scattering order at the
/// points of `tests/every_order_variance.rs` (`docs/model.md` §10.3).
fn every_order_section(w: &mut String, scenes_dir: &Path) -> Result<(), String> {
    use super::every_order_checks::{every_order_row, every_order_table, EVERY_ORDER_POINTS, GOAL};
    let path = scenes_dir.join(format!("{SWEEP_SCENE}.toml"));
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let readme = Scene::from_toml_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let rows = EVERY_ORDER_POINTS.iter().map(|p| every_order_row(p, &readme)).collect::<Result<Vec<_>, _>>()?;
    writeln!(w, "## Every scattering order: Var L against the tracer").unwrap();
    writeln!(w).unwrap();
    writeln!(
        w,
        "Scene `{SWEEP_SCENE}` with q = 1, N_B = 1 and each row's `scattering_orders` (2, 5 or \"all\"), albedo, R, \
         N_F and point lights (flux 1 each): Var L of one iteration, exact at R by the finite-sphere model of every \
         order (`docs/model.md` §10.3; the oracle at {GOAL:.0e}), against the reference tracer with no allowance \
         (seeds 61–73, the points of `tests/every_order_variance.rs`, which asserts |z| ≤ 4 and, where N_F ≤ 2, \
         z > 6 without the pairs). \"pairs' share\" is the same-path pairs' part of Var L, 2Σ⟨𝒞_j𝒞_k⟩/N_F: one \
         forward path meeting one sphere with two of its segments, which the paper's §3 structure (moments through \
         the forward field alone) leaves out; \"z without pairs\" tests Var L less that part. z = (tracer − \
         exact)/√(se² + bar²)."
    )
    .unwrap();
    writeln!(w).unwrap();
    w.push_str(&every_order_table(&rows));
    Ok(())
}

/// The whole document; the figure is written to `figures_dir`.
pub fn markdown(scenes_dir: &Path, figures_dir: &Path) -> Result<String, String> {
    let path = scenes_dir.join(format!("{SWEEP_SCENE}.toml"));
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let scene = Scene::from_toml_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let rows = sweep(&scene, &SWEEP_RADII, SWEEP_TRIALS, SWEEP_SEED)?;
    std::fs::create_dir_all(figures_dir).map_err(|e| e.to_string())?;
    let fig = figures_dir.join("tracer-ratio-point-isotropic.svg");
    std::fs::write(&fig, svg(&rows)?).map_err(|e| format!("{}: {e}", fig.display()))?;
    let mut corr_scene = scene.clone();
    corr_scene.estimator.radius = CORR_RADIUS;
    let corr = correlation_rows(&corr_scene, CORR_S, 2.4 * CORR_RADIUS, CORR_BINS, CORR_RAYS)?;
    let fig2 = figures_dir.join("tracer-correlation-point-isotropic.svg");
    std::fs::write(&fig2, corr_svg(&corr, CORR_RADIUS)?).map_err(|e| format!("{}: {e}", fig2.display()))?;
    let hg_rows = {
        let path = scenes_dir.join("point-hg-forward.toml");
        let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut hg = Scene::from_toml_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        hg.estimator.forward_rays = 20;
        hg.estimator.camera_rays = 2;
        sweep(&hg, &HG_RADII, HG_TRIALS, SWEEP_SEED)?
    };
    let mut bench = scene.clone();
    bench.estimator.radius = 0.05;
    let (trials_per_s, segments_per_s) = speed(&bench, 200_000, 3)?;
    let threads = rayon::current_num_threads();

    let mut s = String::new();
    let w = &mut s;
    writeln!(w, "# Tracer checks: the reference tracer against the oracle").unwrap();
    writeln!(w).unwrap();
    writeln!(
        w,
        "Generated by `cargo run --release -- tracer-checks --out docs/tracer-checks.md` (~6 min); do not edit by \
         hand. The tracer and its statistics: [tracer.md](tracer.md)."
    )
    .unwrap();
    writeln!(w).unwrap();
    writeln!(w, "## Both oracle models as R falls").unwrap();
    writeln!(w).unwrap();
    writeln!(
        w,
        "Scene `{SWEEP_SCENE}` (q = {}, N_F = {}, N_B = {}, scattering order 0) at each R; tracer: {SWEEP_TRIALS} \
         trials, seed {SWEEP_SEED}; oracle: f64. Ratios carry the tracer's standard error; z = (tracer − \
         oracle)/√(se² + bar²). The small-sphere model (§3–§6) rests on the assumptions of §4.3 (phase function and \
         attenuation taken at a sphere's centre, one forward segment through whole spheres), so tracer/small − 1 \
         measures its own error, which falls with R ([model-error.md](model-error.md): second order). The \
         finite-sphere model (`docs/model.md` §9) is exact at every R: tracer/finite is 1 within the tracer's \
         standard error at every R.",
        scene.estimator.q, scene.estimator.forward_rays, scene.estimator.camera_rays
    )
    .unwrap();
    sweep_table(w, &rows);
    writeln!(w).unwrap();
    writeln!(w, "![tracer/oracle against R, with the variance’s ±2 se band](figures/tracer-ratio-point-isotropic.svg)")
        .unwrap();
    writeln!(w).unwrap();
    writeln!(
        w,
        "Scene `point-hg-forward` (g = 0.9) with q = 0.5, N_F = 20, N_B = 2, {HG_TRIALS} trials, seed \
         {SWEEP_SEED}: a forward-peaked medium magnifies the small-sphere model's error."
    )
    .unwrap();
    sweep_table(w, &hg_rows);
    writeln!(w).unwrap();
    writeln!(
        w,
        "The statistical tests compare the tracer with the finite-sphere model with no allowance at all \
         (`tests/tracer_vs_finite.rs`: 14 points; `tests/tracer_vs_oracle.rs`: all its points, through the \
         library's `predict`, its two order-1 points with the correlations of two spheres of single-scattered \
         light (the second, with 3·10⁷ trials, ignored in CI: `--ignored point_7`); `tests/finite_order1*.rs`: single-scattered light from point lights and beams, with two spheres per camera ray for both, `docs/model.md` §9.7 and §9.11; \
         `tests/every_order.rs`: the exact mean of orders 2, 3, 5 and every order at nine points (order 3 at albedo 1), isotropic media, point lights, §10.2; \
         `tests/every_order_beams.rs`: a beam's exact mean of orders 2, 5 and every order at four points (one beside a point light, one running beside the camera ray), §10.5, and its Var L at q = 1, N_B = 1 at five points (orders 2, 3, 5 and every order, N_F 1 to 200, two beside a point light), with the same-path pairs rejected where they are left out, §10.6; \
         `tests/every_order_variance.rs`: Var L of orders 2, 5 and every order at q = 1, N_B = 1 at thirteen points, with the same-path pairs \
         the paper's §3 leaves out rejected where they matter, §10.3). The small-sphere \
         model's own error for single-scattered light, which serves Henyey–Greenstein media at order 1 with q < 1 \
         or N_B > 1 (their correlations of two spheres are not yet in the finite model), is measured at R = 0.1 with the order-1 points' q, N_F, N_B (plus two standard \
         errors) and carried to a scene's R by R ln(1/R) (`prec::model_error_scale`); `cargo test --release \
         --test tracer_vs_oracle -- --ignored --nocapture model_error` re-measures it (~3 min)."
    )
    .unwrap();
    writeln!(w).unwrap();
    every_order_section(w, scenes_dir)?;
    writeln!(w).unwrap();
    writeln!(w, "## The correlation ⟨𝒞(s)𝒞(s+t)⟩, measured directly").unwrap();
    writeln!(w).unwrap();
    writeln!(
        w,
        "Scene `{SWEEP_SCENE}` with R = {CORR_RADIUS}, first sphere at s = {CORR_S}; {CORR_RAYS} forward rays, seed \
         {SWEEP_SEED}. Tracer (`mcrt_reference::correlation::pair_correlation`): each forward ray's product of its \
         contributions to a sphere at s and one at s + t, averaged over each t-bin exactly (a segment that hits the \
         sphere at s hits every centre in its hit interval). Oracle: the bin average of the corrected (21)–(22) \
         (`model::correlations::pointwise`, by quadrature, the support's end t·sin ϑ = 2R declared). The paper's \
         (21) as printed (overlap R²A, argument t sin ϑ/R; errata E2, E3) would be half the curve at t = 0 and end at \
         half the separation: to first order in R it is ½·(corrected at 2t), shown in the last column. z = (tracer − \
         oracle)/se."
    )
    .unwrap();
    writeln!(w).unwrap();
    writeln!(w, "| t/R | oracle (corrected) | tracer | z | paper's (21), to O(R) |").unwrap();
    writeln!(w, "|---|---|---|---|---|").unwrap();
    for (k, c) in corr.iter().enumerate() {
        let z =
            if c.tracer.se > 0.0 { format!("{:+.2}", (c.tracer.value - c.oracle) / c.tracer.se) } else { "—".into() };
        let paper = format!("{:.4e}", paper_bin(&corr, k));
        writeln!(
            w,
            "| {:.1}–{:.1} | {:.4e} | {:.4e} ± {:.1e} | {z} | {paper} |",
            c.t0 / CORR_RADIUS,
            c.t1 / CORR_RADIUS,
            c.oracle,
            c.tracer.value,
            c.tracer.se
        )
        .unwrap();
    }
    writeln!(w).unwrap();
    writeln!(w, "![⟨𝒞(s)𝒞(s+t)⟩ against t/R](figures/tracer-correlation-point-isotropic.svg)").unwrap();
    writeln!(w).unwrap();
    writeln!(
        w,
        "Near the end of the support (t·sin ϑ → 2R) the tracer lies a few standard errors above the model, and a \
         little light remains just beyond it: there the two spheres' projections are not parallel, as §4.3 \
         assumes (a finite-R effect that vanishes with R). `tests/tracer_vs_oracle.rs` \
         (`correlation_of_two_spheres_matches_the_corrected_model`) checks half the rays on twice the bin width: \
         chi-square over the bins, p ≥ 10⁻³, and the paper's (21) rejected at t = 0."
    )
    .unwrap();
    writeln!(w).unwrap();
    writeln!(w, "## Speed").unwrap();
    writeln!(w).unwrap();
    writeln!(
        w,
        "Scene `{SWEEP_SCENE}` with R = 0.05, q = {}, N_F = {}, N_B = {}, order 0; 200 000 trials, best of 3, {threads} \
         threads, this machine (release build): **{:.3e} trials/s**, **{:.3e} forward segments/s**.",
        scene.estimator.q, scene.estimator.forward_rays, scene.estimator.camera_rays, trials_per_s, segments_per_s
    )
    .unwrap();
    Ok(s)
}
