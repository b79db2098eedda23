//! `mcrt-noise check SCENE --values FILE`: a renderer's per-iteration values
//! (from any language) checked against the prediction.

use mcrt_noise::{check, predict, CheckOptions, Samples, Scene};
use serde::Deserialize;
use std::path::Path;

/// What `check` reads besides the scene.
pub struct CheckArgs<'a> {
    /// The values file (`-`: standard input).
    pub values: &'a Path,
    /// Family-wise false-alarm rate.
    pub false_alarm_rate: f64,
    /// Power of the detectable-error figures.
    pub power: f64,
    /// Relative resolution targets (mean, Var L).
    pub targets: (Option<f64>, Option<f64>),
    /// One JSON object instead of the text.
    pub json: bool,
}

/// Power sums as JSON: `{"count": M, "sums": [ΣL, ΣL², ΣL³, ΣL⁴]}`, with
/// an optional bound on their relative error.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SumsFile {
    count: u64,
    sums: [f64; 4],
    sums_relative_error: Option<f64>,
}

/// Runs the check; `Ok(pass)`, or `Err` on bad input.
pub fn check_cmd(scene: &Scene, args: &CheckArgs) -> Result<bool, String> {
    let options = options(args)?;
    let samples = read_samples(args.values)?;
    let prediction = predict(scene).map_err(|e| e.to_string())?;
    let verdict = check(&prediction, &samples, &options);
    if args.json {
        println!("{}", serde_json::to_string_pretty(&verdict).map_err(|e| e.to_string())?);
    } else {
        println!("{verdict}");
    }
    Ok(verdict.pass)
}

fn options(args: &CheckArgs) -> Result<CheckOptions, String> {
    let flag = |name: &str, e: mcrt_noise::scene::FieldError| format!("--{name} = {}: must be {}", e.value, e.allowed);
    let mut o = CheckOptions::new(args.false_alarm_rate).map_err(|e| flag("false-alarm-rate", e))?;
    o = o.with_power(args.power).map_err(|e| flag("power", e))?;
    if let Some(m) = args.targets.0 {
        o = o.with_mean_target(m).map_err(|e| flag("target-mean", e))?;
    }
    if let Some(v) = args.targets.1 {
        o = o.with_variance_target(v).map_err(|e| flag("target-variance", e))?;
    }
    Ok(o)
}

/// The values: one number per line, a JSON array, or power sums as JSON.
fn read_samples(path: &Path) -> Result<Samples, String> {
    let text = if path == Path::new("-") {
        std::io::read_to_string(std::io::stdin()).map_err(|e| format!("--values -: {e}"))?
    } else {
        std::fs::read_to_string(path).map_err(|e| format!("--values {}: {e}", path.display()))?
    };
    let at = path.display();
    let trimmed = text.trim_start();
    if trimmed.starts_with('{') {
        let f: SumsFile = serde_json::from_str(&text).map_err(|e| format!("--values {at}: power sums JSON: {e}"))?;
        let eps = f.sums_relative_error.unwrap_or(f.count as f64 * f64::EPSILON / 2.0);
        return Samples::from_power_sums(f.count, f.sums, eps).map_err(|e| format!("--values {at}: {e}"));
    }
    let mut samples = Samples::new();
    if trimmed.starts_with('[') {
        let values: Vec<f64> = serde_json::from_str(&text).map_err(|e| format!("--values {at}: JSON array: {e}"))?;
        samples.extend(values).map_err(|e| format!("--values {at}: {e}"))?;
        return Ok(samples);
    }
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let l: f64 = line.parse().map_err(|_| format!("--values {at}: line {}: {line:?} is not a number", i + 1))?;
        samples.push(l).map_err(|e| format!("--values {at}: line {}: {e}", i + 1))?;
    }
    Ok(samples)
}
