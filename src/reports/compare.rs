//! The tracer's measurement beside the oracle's prediction: the `trace`
//! report (mean and variance of L with standard errors, counters, speed)
//! and the `compare` verdict (z-scores of mean and variance).
//!
//! z = (tracer − oracle)/√(se² + bar²), with se the tracer's standard error
//! and bar the oracle's error bar, against the oracle's prediction: the
//! finite-sphere model (exact at the scene's R) for uncollided light; for
//! scenes with scattered light the small-sphere model of §4.3, whose own
//! O(R) error `compare` does not include (it says so) and the statistical
//! tests (`tests/tracer_vs_oracle.rs`) allow for as measured.

use crate::oracle::Report;
use mcrt_reference::moments::{Estimates, Summary, WithError};
use mcrt_reference::{Counters, Run};
use serde::Serialize;

/// The JSON of `mcrt-noise trace`.
#[derive(Debug, Clone, Serialize)]
pub struct TraceReport {
    /// The run's seed.
    pub seed: u64,
    /// Trial ranges [start, end) covered.
    pub trials: Vec<[u64; 2]>,
    /// Trials run (each one iteration: one sample of L).
    pub trial_count: u64,
    /// Sample mean of L with its standard error; `None` (JSON null) when not
    /// resolved, the reason in `not_resolved` (below 4 trials, where the
    /// variance's error is not defined, a small shard is still written and
    /// merges normally; fewer than 100 trials with hits, `Run::estimates`;
    /// no spread; beyond the range of a double).
    pub mean: Option<WithError>,
    /// Unbiased sample variance of L with its standard error (from the 4th moment); `None` likewise.
    pub variance: Option<WithError>,
    /// Why the mean or the variance is not given (absent when both are).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub not_resolved: Option<String>,
    /// What the run did, summed over its trials.
    pub counters: Counters,
    /// Wall time of the run (ms); `None` (JSON null) when not measured, the
    /// reason in `time_not_measured` (merged shards).
    pub wall_time_ms: Option<f64>,
    /// Trials per second of wall time; `None` likewise.
    pub trials_per_second: Option<f64>,
    /// Forward segments traced per second of wall time; `None` likewise.
    pub forward_segments_per_second: Option<f64>,
    /// Why the time and the rates are not given (absent when they are).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_not_measured: Option<String>,
}

/// The reason `merge` gives no time (its shards were traced elsewhere).
pub const MERGED_TIME: &str = "time not measured: merged from shards (each shard's trace reported its own time)";

impl TraceReport {
    /// The report of a run that took `wall_seconds`, or `Err(reason)` when
    /// its time was not measured (merged shards: [`MERGED_TIME`]).
    pub fn new(run: &Run, wall_seconds: Result<f64, String>) -> TraceReport {
        let estimates = run.estimates();
        let reasons: Vec<&String> =
            [&estimates.mean, &estimates.variance].into_iter().filter_map(|e| e.as_ref().err()).collect();
        let not_resolved = match reasons.as_slice() {
            [] => None,
            [one] => Some(one.to_string()),
            [a, b] if a == b => Some(a.to_string()),
            [a, b] => Some(format!("{a}; {b}")),
            _ => unreachable!("two estimates"),
        };
        // A time of 0 is below the clock's resolution, not a time: no rate from it.
        let seconds = wall_seconds.and_then(|t| {
            if t > 0.0 {
                Ok(t)
            } else {
                Err("time not measured: the run took less than the clock's resolution".to_string())
            }
        });
        let per_second = |n: u64| seconds.as_ref().ok().map(|t| n as f64 / t);
        TraceReport {
            seed: run.seed,
            trials: run.ranges.iter().map(|r| [r.start, r.end]).collect(),
            trial_count: run.counters.trials,
            mean: estimates.mean.ok(),
            variance: estimates.variance.ok(),
            not_resolved,
            counters: run.counters,
            wall_time_ms: seconds.as_ref().ok().map(|t| t * 1e3),
            trials_per_second: per_second(run.counters.trials),
            forward_segments_per_second: per_second(run.counters.forward_segments),
            time_not_measured: seconds.err(),
        }
    }

    /// A readable table.
    pub fn table(&self) -> String {
        let c = &self.counters;
        let d = &c.draws;
        let why = self.not_resolved.as_deref().unwrap_or("");
        let time = match (self.wall_time_ms, self.trials_per_second, self.forward_segments_per_second) {
            (Some(ms), Some(trials), Some(segments)) => format!(
                "time {} ms, one measurement  ({trials:.3e} trials/s, {segments:.3e} segments/s)",
                three_digits(ms)
            ),
            _ => self.time_not_measured.clone().unwrap_or_else(|| "time not measured".into()),
        };
        let stats = match (&self.mean, &self.variance) {
            (Some(m), Some(v)) => format!(
                "mean L          {:.10e} ± {:.2e} (s.e.)\nVar L           {:.10e} ± {:.2e} (s.e., from the 4th \
                 moment)\n",
                m.value, m.se, v.value, v.se
            ),
            // A single missing quantity: its reason starts with its name.
            (Some(m), None) => format!("mean L          {:.10e} ± {:.2e} (s.e.)\n{why}\n", m.value, m.se),
            (None, Some(v)) => {
                format!("{why}\nVar L           {:.10e} ± {:.2e} (s.e., from the 4th moment)\n", v.value, v.se)
            }
            (None, None) => format!("mean L, Var L   {why}\n"),
        };
        format!(
            "trials {}  seed {}\n\
             {stats}\
             forward rays {}  segments {}  spheres {}  candidate tests {}  hits {}  HG evaluations {}\n\
             draws: sub-step {}  extinction {}  light {}  emission dir {}  emission pos {}  free path {}  \
             roulette {}  phase {}\n\
             {time}\n",
            self.trial_count,
            self.seed,
            c.forward_rays,
            c.forward_segments,
            c.sphere_placements,
            c.candidate_tests,
            c.hits,
            c.hg_evaluations,
            d.sub_step,
            d.extinction,
            d.light_choice,
            d.emission_direction,
            d.emission_position,
            d.free_path,
            d.roulette,
            d.phase,
        )
    }
}

/// `x` (> 0) to three significant digits, without an exponent for the
/// times a run takes (0.0123, 1.23, 123, 12345): never rounded to 0.
fn three_digits(x: f64) -> String {
    let decimals = (2 - x.log10().floor() as i32).clamp(0, 20) as usize;
    format!("{x:.decimals$}")
}

/// One quantity, oracle beside tracer.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Side {
    /// The oracle's value.
    pub oracle: f64,
    /// The oracle's error bar.
    pub oracle_error: f64,
    /// The tracer's estimate.
    pub tracer: f64,
    /// The tracer's standard error.
    pub tracer_se: f64,
    /// tracer/oracle.
    pub ratio: f64,
    /// The ratio's error bar: the tracer's standard error and the oracle's
    /// bar propagated, √(se² + ratio²·bar²)/|oracle| (independent errors,
    /// to first order).
    pub ratio_error: f64,
    /// (tracer − oracle)/√(se² + bar²).
    pub z: f64,
}

impl Side {
    /// The oracle's value and bar beside the tracer's estimate, with ratio
    /// and z. The tracer's estimate should be resolved (`Run::estimates`:
    /// s.e. > 0), or z is infinite; [`Side::finite`] says whether it is.
    pub fn new(oracle: f64, oracle_error: f64, tracer: WithError) -> Side {
        let z = (tracer.value - oracle) / (tracer.se * tracer.se + oracle_error * oracle_error).sqrt();
        let ratio = tracer.value / oracle;
        let ratio_error = tracer.se.hypot(ratio * oracle_error) / oracle.abs();
        Side { oracle, oracle_error, tracer: tracer.value, tracer_se: tracer.se, ratio, ratio_error, z }
    }

    /// Every number of the side finite (no inf or NaN ratio or z).
    pub fn finite(&self) -> bool {
        [self.oracle, self.oracle_error, self.tracer, self.tracer_se, self.ratio, self.ratio_error, self.z]
            .iter()
            .all(|x| x.is_finite())
    }
}

/// Mean and variance, the oracle's prediction (`Report::prediction`: the
/// finite-sphere model where it exists) beside the tracer.
pub fn sides(oracle: &Report, tracer: &Summary) -> (Side, Side) {
    let p = &oracle.prediction;
    (Side::new(p.mean.value, p.mean.error, tracer.mean), Side::new(p.variance.value, p.variance.error, tracer.variance))
}

/// Mean and variance of the small-sphere model (§4.3) beside the tracer;
/// `None` where the report has no small-sphere Var L ([`Report::variance`]).
pub fn small_sphere_sides(oracle: &Report, tracer: &Summary) -> Option<(Side, Side)> {
    let variance = oracle.variance.as_ref()?;
    Some((
        Side::new(oracle.mean_luminance.value, oracle.mean_luminance.error, tracer.mean),
        Side::new(variance.exact.value, variance.exact.error, tracer.variance),
    ))
}

/// The JSON of `mcrt-noise compare`.
#[derive(Debug, Clone, Serialize)]
pub struct Comparison {
    /// Trials the tracer ran.
    pub trials: u64,
    /// The tracer's seed.
    pub seed: u64,
    /// Mean luminance L, oracle beside tracer (null when not resolved).
    pub mean: Option<Side>,
    /// Var L of one iteration, oracle beside tracer (null when not resolved).
    pub variance: Option<Side>,
    /// |z| ≤ this for both quantities passes.
    pub z_limit: f64,
    /// The oracle model compared against (`ReportPrediction::model`).
    pub model: &'static str,
    /// Both resolved and |z| ≤ `z_limit`.
    pub pass: bool,
    /// One line: AGREE or DISAGREE with both z, the limit and the model
    /// compared against; or NOT RESOLVED with the reason (fewer than 100
    /// trials with hits, no spread, a value beyond a double, or a z that would
    /// not be finite).
    pub verdict: String,
}

/// |z| beyond this fails `compare` (two-sided 6·10⁻⁵ for a normal z).
pub const Z_LIMIT: f64 = 4.0;

impl Comparison {
    /// The verdict of the tracer's `trials` (seed `seed`) against the
    /// oracle's prediction: AGREE, DISAGREE, or NOT RESOLVED when the tracer
    /// has not resolved the mean or the variance (`Run::estimates`) or a
    /// z-score would not be finite. `pass` only for AGREE.
    pub fn new(oracle: &Report, tracer: &Estimates, trials: u64, seed: u64) -> Comparison {
        let p = &oracle.prediction;
        let side = |name: &str, value: f64, error: f64, measured: &Result<WithError, String>| {
            let m = measured.as_ref().map_err(|why| why.clone())?;
            let s = Side::new(value, error, *m);
            if s.finite() {
                Ok(s)
            } else {
                Err(format!(
                    "{name}: oracle {value:e} ± {error:e} against tracer {:e} ± {:e} gives no finite ratio and z",
                    m.value, m.se
                ))
            }
        };
        let mean = side("mean L", p.mean.value, p.mean.error, &tracer.mean);
        let variance = side("Var L", p.variance.value, p.variance.error, &tracer.variance);
        let basis = if oracle.finite.is_some() {
            "the finite-sphere model, exact at this R".to_string()
        } else {
            "the small-sphere model, whose own O(R) error is not included".to_string()
        };
        let (pass, verdict) = match (&mean, &variance) {
            (Ok(m), Ok(v)) => {
                let pass = m.z.abs() <= Z_LIMIT && v.z.abs() <= Z_LIMIT;
                let verdict = format!(
                    "{}: mean z = {:+.2}, variance z = {:+.2} (limit |z| <= {Z_LIMIT}; against {basis})",
                    if pass { "AGREE" } else { "DISAGREE" },
                    m.z,
                    v.z
                );
                (pass, verdict)
            }
            (Err(why), _) | (_, Err(why)) => (false, format!("NOT RESOLVED: {why}")),
        };
        let model = p.model;
        Comparison { trials, seed, mean: mean.ok(), variance: variance.ok(), z_limit: Z_LIMIT, model, pass, verdict }
    }

    /// A readable table.
    pub fn table(&self) -> String {
        let row = |name: &str, s: &Option<Side>| match s {
            Some(s) => format!(
                "{name:<9} oracle {:.8e} ± {:.1e}   tracer {:.8e} ± {:.1e}   ratio {:.5} ± {:.1e}   z {:+.2}\n",
                s.oracle, s.oracle_error, s.tracer, s.tracer_se, s.ratio, s.ratio_error, s.z
            ),
            None => format!("{name:<9} not resolved (below)\n"),
        };
        format!(
            "trials {}  seed {}\n{}{}{}\n",
            self.trials,
            self.seed,
            row("mean L", &self.mean),
            row("Var L", &self.variance),
            self.verdict
        )
    }
}
