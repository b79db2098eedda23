//! `mcrt-noise calibrate`: the reference tracer timed on this machine over
//! varied parameters (one thread), the per-operation costs fitted
//! (`tuning::calibration`), and the cost model validated on other
//! parameter sets: predicted time per iteration (predicted counts × fitted
//! costs) against the measured one.

use crate::tuning::calibration::{fit, Fit, Measurement};
use crate::tuning::cost::{CostTable, IterationCounts};
use crate::tuning::rates::Rates;
use mcrt_reference::{trace, HitMethod, Tracer};
use mcrt_scene::{Phase, Scene};
use serde::Serialize;
use std::fmt::Write;
use std::path::Path;
use std::time::Instant;

/// A bundled scene with its estimator's parameters replaced.
#[derive(Debug, Clone, Copy)]
pub struct Case {
    /// `scenes/NAME.toml`.
    pub scene: &'static str,
    /// q.
    pub q: f64,
    /// R.
    pub radius: f64,
    /// N_F.
    pub forward_rays: u64,
    /// N_B.
    pub camera_rays: u64,
}

const fn case(scene: &'static str, q: f64, radius: f64, forward_rays: u64, camera_rays: u64) -> Case {
    Case { scene, q, radius, forward_rays, camera_rays }
}

/// The parameter sets the costs are fitted to: each cost dominant in some
/// (segments at large N_F, spheres and sorting at small q and large N_B,
/// searching and hits at large R, Henyey–Greenstein hits, scattered
/// segments at order 1, beams).
pub const CALIBRATION: [Case; 16] = [
    case("point-isotropic", 1.0, 0.01, 200, 1),
    case("point-isotropic", 1.0, 0.01, 20, 1),
    case("point-isotropic", 0.02, 0.01, 20, 64),
    case("point-isotropic", 0.1, 0.01, 20, 8),
    case("point-isotropic", 0.5, 0.3, 200, 64),
    case("point-isotropic", 1.0, 0.3, 2000, 8),
    case("point-isotropic", 0.02, 0.3, 200, 64),
    case("point-isotropic", 0.005, 0.01, 10, 16),
    case("point-isotropic-order1", 0.5, 0.1, 200, 8),
    case("point-isotropic-order1", 1.0, 0.01, 2000, 1),
    case("point-hg-forward", 0.5, 0.1, 200, 8),
    case("point-hg-forward", 0.1, 0.3, 200, 64),
    case("point-hg-backward", 1.0, 0.05, 1000, 4),
    case("beam-isotropic", 0.5, 0.05, 200, 8),
    case("beam-isotropic", 0.05, 0.2, 100, 32),
    case("point-isotropic", 1.0, 0.1, 5000, 256),
];

/// Other parameter sets the fitted model is validated on (none is a
/// calibration set).
pub const VALIDATION: [Case; 12] = [
    case("point-isotropic", 0.5, 0.05, 200, 8),
    case("point-isotropic", 1.0, 0.08, 16000, 900),
    case("point-isotropic", 0.2, 0.02, 50, 16),
    case("point-isotropic", 0.05, 0.15, 300, 4),
    case("point-isotropic", 1.0, 0.2, 500, 32),
    case("point-hg-forward", 0.5, 0.01, 200, 8),
    case("point-hg-forward", 1.0, 0.15, 3000, 16),
    case("point-hg-forward", 0.02, 0.05, 40, 8),
    case("point-isotropic-order1", 0.2, 0.05, 500, 4),
    case("point-hg-backward", 0.3, 0.2, 100, 2),
    case("beam-isotropic", 1.0, 0.1, 1000, 1),
    case("beam-isotropic", 0.1, 0.02, 60, 48),
];

/// The scenes the calibration reads from its scenes directory (each once).
pub fn scene_names() -> Vec<&'static str> {
    let mut names: Vec<&'static str> = CALIBRATION.iter().chain(&VALIDATION).map(|c| c.scene).collect();
    names.sort_unstable();
    names.dedup();
    names
}

impl Case {
    /// The case's scene, read from `scenes_dir`.
    pub fn scene(&self, scenes_dir: &Path) -> Result<Scene, String> {
        let path = scenes_dir.join(format!("{}.toml", self.scene));
        let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut s = Scene::from_toml_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        s.estimator.q = self.q;
        s.estimator.radius = self.radius;
        s.estimator.forward_rays = self.forward_rays;
        s.estimator.camera_rays = self.camera_rays;
        s.validated().map_err(|e| format!("{}: {e}", self.label()))
    }

    /// "scene q=… R=… N_F=… N_B=…".
    pub fn label(&self) -> String {
        format!("{} q={} R={} N_F={} N_B={}", self.scene, self.q, self.radius, self.forward_rays, self.camera_rays)
    }
}

/// Times `scene` on one thread for about `seconds`: three runs, the
/// fastest time per iteration kept (the least disturbed by other work),
/// the counters summed over all three.
pub fn time_scene(scene: &Scene, label: String, seconds: f64) -> Result<Measurement, String> {
    let tracer = Tracer::new(scene).map_err(|e| e.to_string())?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().map_err(|e| e.to_string())?;
    pool.install(|| {
        let probe = 16u64;
        let t0 = Instant::now();
        let mut run = trace(&tracer, 1, 0..probe, HitMethod::Sorted, &|_| {});
        let per = t0.elapsed().as_secs_f64() / probe as f64;
        let n = ((seconds / 3.0 / per.max(1e-9)) as u64).clamp(16, 1 << 30);
        tracer.check_trials(3 * n).map_err(|e| e.to_string())?;
        let mut best = f64::INFINITY;
        let mut start = probe;
        for _ in 0..3 {
            let t0 = Instant::now();
            let more = trace(&tracer, 1, start..start + n, HitMethod::Sorted, &|_| {});
            best = best.min(t0.elapsed().as_secs_f64() / n as f64);
            start += n;
            run = mcrt_reference::merge(&[run, more])?;
        }
        let trials = run.counters.trials;
        Ok(Measurement {
            label,
            camera_rays: scene.estimator.camera_rays,
            q: scene.estimator.q,
            counters: run.counters,
            seconds: best * trials as f64,
            hg: matches!(scene.medium.phase, Phase::HenyeyGreenstein { .. }),
        })
    })
}

/// One validation point: predicted and measured seconds per iteration.
#[derive(Debug, Clone, Serialize)]
pub struct Validation {
    /// The case.
    pub label: String,
    /// Predicted seconds per iteration and its standard error (costs' and rates').
    pub predicted: (f64, f64),
    /// Measured seconds per iteration (fastest of three runs).
    pub measured: f64,
}

impl Validation {
    /// predicted/measured − 1.
    pub fn relative_error(&self) -> f64 {
        self.predicted.0 / self.measured - 1.0
    }
}

/// The model's prediction for `scene` against its timing.
pub fn validate_scene(scene: &Scene, label: String, costs: &CostTable, seconds: f64) -> Result<Validation, String> {
    let rates = Rates::estimate(scene, crate::tuning::rates::PILOT_RAYS)?;
    let e = &scene.estimator;
    let counts = IterationCounts::predict(scene, &rates, e.q, e.forward_rays as f64, e.camera_rays as f64);
    let predicted = costs.seconds(&counts);
    let measured = time_scene(scene, label.clone(), seconds)?.seconds_per_iteration();
    Ok(Validation { label, predicted, measured })
}

/// Calibration and validation together.
#[derive(Debug, Clone, Serialize)]
pub struct Calibration {
    /// The fit.
    pub fit: Fit,
    /// The timed calibration runs.
    pub runs: Vec<Measurement>,
    /// The validation points.
    pub validation: Vec<Validation>,
}

/// Times [`CALIBRATION`], fits, and validates on [`VALIDATION`], about
/// `seconds` per case.
pub fn calibrate(scenes_dir: &Path, seconds: f64, source: String) -> Result<Calibration, String> {
    let mut runs = Vec::new();
    for c in CALIBRATION {
        runs.push(time_scene(&c.scene(scenes_dir)?, c.label(), seconds)?);
    }
    let fit = fit(&runs, source)?;
    let mut validation = Vec::new();
    for c in VALIDATION {
        validation.push(validate_scene(&c.scene(scenes_dir)?, c.label(), &fit.costs, seconds)?);
    }
    Ok(Calibration { fit, runs, validation })
}

/// Largest |predicted/measured − 1| the validation accepts (issue 12).
pub const VALIDATION_TOLERANCE: f64 = 0.15;

/// A fitted cost or error in ns: 3 decimals, or 4 significant digits
/// below 0.1 (a positive cost is never printed as `0.000`).
fn ns(x: f64) -> String {
    if x.abs() >= 0.1 || x == 0.0 {
        format!("{x:.3}")
    } else {
        format!("{x:.3e}")
    }
}

/// The calibration as Markdown: the costs, the fit's residuals, the
/// validation table with every point over the tolerance flagged.
pub fn markdown(c: &Calibration) -> String {
    let mut s = String::new();
    let names = [
        "iteration",
        "forward ray",
        "camera ray",
        "segment",
        "sphere",
        "sort (per S log₂ S)",
        "search (per candidate·log₂(1+S))",
        "hit",
        "HG evaluation",
    ];
    writeln!(s, "| operation | key | cost (ns) | standard error (ns) |").unwrap();
    writeln!(s, "|---|---|---:|---:|").unwrap();
    for (i, n) in names.iter().enumerate() {
        let key = c.fit.costs.keys[i];
        let (cost, error) = (c.fit.costs.ns[i], c.fit.costs.std_errors[i]);
        if c.fit.held_at_zero.contains(&key) {
            // Not a measurement of 0 ± 0: the constraint, and the data's resolution.
            writeln!(s, "| {n} | `{key}` | not resolved: held at 0 (the fit made it negative) | resolution {error:.3} (its standard error were it free) |").unwrap();
        } else {
            writeln!(s, "| {n} | `{key}` | {} | {} |", ns(cost), ns(error)).unwrap();
        }
    }
    writeln!(
        s,
        "\nFit over {} timed runs: RMS relative residual {:.1} %, largest {:.1} %.\n",
        c.runs.len(),
        100.0 * c.fit.rms_relative_residual,
        100.0 * c.fit.max_relative_residual
    )
    .unwrap();
    writeln!(
        s,
        "| validation case | predicted µs/iteration | measured µs/iteration | predicted/measured − 1 | within ±15 % |"
    )
    .unwrap();
    writeln!(s, "|---|---:|---:|---:|---|").unwrap();
    let mut worst = 0.0f64;
    for v in &c.validation {
        let e = v.relative_error();
        worst = worst.max(e.abs());
        writeln!(
            s,
            "| {} | {:.2} ± {:.2} | {:.2} | {:+.1} % | {} |",
            v.label,
            v.predicted.0 * 1e6,
            v.predicted.1 * 1e6,
            v.measured * 1e6,
            100.0 * e,
            if e.abs() <= VALIDATION_TOLERANCE { "yes" } else { "**NO**" }
        )
        .unwrap();
    }
    let within = c.validation.iter().filter(|v| v.relative_error().abs() <= VALIDATION_TOLERANCE).count();
    writeln!(
        s,
        "\n{within} of {} validation cases within ±15 %; the largest deviation {:.1} %.",
        c.validation.len(),
        100.0 * worst
    )
    .unwrap();
    s
}
