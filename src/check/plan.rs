//! How many samples a check needs, from a pilot of the renderer's values:
//! so that a renderer's test can size itself before rendering.

use super::options::{CheckOptions, MAX_INFLUENCE, MIN_EFFECTIVE_COUNT};
use super::predict::Prediction;
use super::samples::Samples;
use super::statistics::{self, Null};
use super::verdict::{check, count_text, largest_influence, Status, Verdict, MIN_NONZERO};
use serde::Serialize;
use std::fmt;

/// The sample count a check needs, each requirement's share, and the
/// pilot's own verdict.
#[derive(Debug, Clone, Serialize)]
pub struct Plan {
    /// The values the plan was made from.
    pub pilot_samples: u64,
    /// The resolution targets planned for (mean, Var L), relative.
    pub targets: (f64, f64),
    /// The largest of the requirements below: about how many samples the
    /// check needs (`None` when a requirement cannot be met by any count,
    /// or could not be estimated: `notes` says which).
    pub samples: Option<f64>,
    /// For the mean's target (the mean's z is scaled by the predicted
    /// Var L; the pilot gives the skewness of L).
    pub for_mean_target: Option<f64>,
    /// For Var L's target (from the pilot's kurtosis).
    pub for_variance_target: Option<f64>,
    /// For [`MIN_NONZERO`] nonzero values (from the pilot's fraction).
    pub for_nonzero: Option<f64>,
    /// For [`MIN_EFFECTIVE_COUNT`] values carrying the spread (M/κ grows
    /// like M).
    pub for_effective_count: Option<f64>,
    /// For one value's influence on a z to fall to half of
    /// [`MAX_INFLUENCE`] (from the pilot's, falling like 1/√M; half, since
    /// larger values come with more samples).
    pub for_influence: Option<f64>,
    /// The pilot's kurtosis κ of L.
    pub kurtosis: Option<f64>,
    /// Caveats and what could not be estimated.
    pub notes: Vec<String>,
    /// The pilot's own check: a pilot that already fails shows a bug before
    /// the long run.
    pub pilot: Verdict,
}

/// Plans a check: from the pilot's values, about how many samples meet the
/// targets of `options` (from the prediction and the pilot's skewness,
/// kurtosis and sixth moment) and the resolution rules (nonzero values, one
/// value's influence). An estimate: a pilot of heavy-tailed values tends to
/// under-state the kurtosis, so render a little more than planned; the
/// check itself decides.
///
/// ```
/// use mcrt_noise::{check, predict, CheckOptions, Samples, Scene};
/// use mcrt_noise::check::plan;
///
/// let scene = Scene::builder()
///     .medium(1.0, 0.8)
///     .point_light([1.0, 0.0, 1.0], 1.0)
///     .camera([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
///     .estimator(0.2, 0.5, 20, 4)
///     .build()?;
/// # let tracer = mcrt_noise::reference::Tracer::new(&scene)?;
/// # let render_pixel = |i: u64| tracer.trial(8, i, mcrt_noise::reference::HitMethod::Sorted).0;
/// let prediction = predict(&scene)?;
/// let options = CheckOptions::default();
/// let mut pilot = Samples::new();
/// for i in 0..10_000 { pilot.push(render_pixel(i))?; }
/// let needed = plan(&prediction, &pilot, &options).samples.expect("a count");
/// let mut samples = pilot.clone();
/// for i in 10_000..(needed * 1.2) as u64 { samples.push(render_pixel(i))?; }
/// check(&prediction, &samples, &options).assert_pass();
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn plan(prediction: &Prediction, pilot: &Samples, options: &CheckOptions) -> Plan {
    let verdict = check(prediction, pilot, options);
    // The limit for the pilot's correlation of the z-scores, as its check used.
    let (z_limit, z_power) = (verdict.z_limit, options.z_power());
    let null = Null::new(prediction, pilot.rounding_bounds());
    let (target_mean, target_variance) = options.targets();
    let mut notes = Vec::new();
    let shape = verdict.shape;
    let for_mean_target = shape.and_then(|s| {
        let m = statistics::samples_for_mean(target_mean, &s, &null, z_limit, z_power);
        if m.is_none() {
            notes.push(format!("the mean's bars alone exceed its target {target_mean}: no number of samples meets it"));
        }
        m
    });
    let kurtosis = shape.map(|s| s.kurtosis);
    let for_variance_target = shape.and_then(|s| {
        let m = statistics::samples_for_variance(target_variance, &s, &null, z_limit, z_power);
        if m.is_none() {
            notes
                .push(format!("Var L's bars alone exceed its target {target_variance}: no number of samples meets it"));
        }
        m
    });
    if shape.is_none() {
        notes.push(
            "the pilot has no usable spread (fewer than 4 values, all equal, or beyond a double): the targets' \
             requirements need a pilot with hits"
                .into(),
        );
    }
    let n = pilot.count() as f64;
    let for_nonzero = match pilot.nonzero() {
        Some(0) => {
            notes.push(format!("no nonzero value among the pilot's {}: render a larger pilot", pilot.count()));
            None
        }
        Some(k) => Some((n * MIN_NONZERO as f64 / k as f64).ceil()),
        None => {
            notes.push("the pilot's power sums came without the nonzero count: sparsity not planned for".into());
            None
        }
    };
    // One value's influence falls like 1/√M for values of a given size;
    // aim at half the bound, as larger values come with more samples.
    let for_influence = largest_influence(pilot, &null)
        .filter(|i| i.is_finite())
        .map(|i| (n * (i / (0.5 * MAX_INFLUENCE)).powi(2)).ceil());
    // M/κ grows like M for a given distribution.
    let for_effective_count = shape.map(|s| (n * MIN_EFFECTIVE_COUNT / s.effective_count()).ceil());
    if kurtosis.is_some() {
        notes.push(
            "a pilot of heavy-tailed values tends to under-state the kurtosis, and larger values come with more \
             samples: render somewhat more than planned (the check itself decides)"
                .into(),
        );
    }
    let parts = [for_mean_target, for_variance_target, for_nonzero, for_effective_count, for_influence];
    let complete = for_mean_target.is_some() && for_variance_target.is_some();
    let samples = complete.then(|| parts.iter().flatten().copied().fold(n, f64::max));
    Plan {
        pilot_samples: pilot.count(),
        targets: options.targets(),
        samples,
        for_mean_target,
        for_variance_target,
        for_nonzero,
        for_effective_count,
        for_influence,
        kurtosis,
        notes,
        pilot: verdict,
    }
}

impl fmt::Display for Plan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let count = |x: Option<f64>| x.map_or("—".to_string(), count_text);
        match self.samples {
            Some(m) => writeln!(
                f,
                "PLAN: {} samples to resolve {:.3} % of the mean and {:.3} % of Var L (from a pilot of {})",
                count_text(m),
                self.targets.0 * 100.0,
                self.targets.1 * 100.0,
                self.pilot_samples
            )?,
            None => writeln!(f, "PLAN: no sample count could be estimated from a pilot of {}", self.pilot_samples)?,
        }
        writeln!(f, "  mean's target                  {}", count(self.for_mean_target))?;
        writeln!(
            f,
            "  Var L's target                 {}{}",
            count(self.for_variance_target),
            self.kurtosis.map_or(String::new(), |k| format!("   (pilot's kurtosis {k:.4e})"))
        )?;
        writeln!(f, "  {MIN_NONZERO} nonzero values             {}", count(self.for_nonzero))?;
        writeln!(f, "  {MIN_EFFECTIVE_COUNT} values carrying the spread {}", count(self.for_effective_count))?;
        writeln!(f, "  one value's influence ≤ {:.1}    {}", 0.5 * MAX_INFLUENCE, count(self.for_influence))?;
        for note in &self.notes {
            writeln!(f, "  note: {note}")?;
        }
        let pilot = match self.pilot.status {
            Status::Fail => "the pilot already FAILS: fix the renderer before the long run",
            Status::Pass => "the pilot already passes",
            Status::NotResolved => "the pilot is not resolved yet, as expected of a pilot",
        };
        write!(f, "  pilot's verdict: {pilot}\n{}", self.pilot)
    }
}
