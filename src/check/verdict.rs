//! The check of a renderer's samples against a prediction: which tests
//! run, what makes a quantity resolved, and the verdict's three outcomes.

use super::display::z_text;
use super::family::{family_rate, z_correlation};
use super::influence::{influence, without_largest, Influence};
use super::options::{CheckOptions, MAX_INFLUENCE, MIN_EFFECTIVE_COUNT};
use super::predict::{Model, Predicted, Prediction};
use super::samples::{Measured, Samples};
use super::shape::Shape;
use super::statistics::{self, Null};
use serde::Serialize;

/// What a check concluded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Status {
    /// Every quantity resolved, within its limit, and able to detect its
    /// target: the renderer agrees with the prediction to the stated
    /// detectable errors.
    Pass,
    /// Evidence of a bug: a resolved quantity beyond its z limit, or a value
    /// larger than any correct renderer produces at the tail test's rate.
    Fail,
    /// The samples cannot tell: too few, too sparse, without spread, carried
    /// by a few values, or unable to detect a target. The reasons say what
    /// would resolve it.
    NotResolved,
}

impl Status {
    /// `PASS`, `FAIL` or `NOT RESOLVED`.
    pub fn label(self) -> &'static str {
        match self {
            Status::Pass => "PASS",
            Status::Fail => "FAIL",
            Status::NotResolved => "NOT RESOLVED",
        }
    }
}

/// One quantity checked: prediction, measurement, z, the influence of one
/// value on it, and what it could detect.
#[derive(Debug, Clone, Serialize)]
pub struct QuantityCheck {
    /// `"mean L"` or `"Var L"`.
    pub name: &'static str,
    /// The oracle's value with its bars.
    pub predicted: Predicted,
    /// The renderer's value with its own standard error (√(s²/M) for the
    /// mean, s²·a for Var L); `None` when it has none a test can use (all
    /// values equal, or beyond the range of a double: `not_resolved` says
    /// which).
    pub measured: Option<Measured>,
    /// Bound on the measurement's error from inexact power sums (0 when
    /// the samples were accumulated exactly).
    pub rounding_bar: f64,
    /// The z-score (mean: null-scaled by the predicted Var L; Var L: the
    /// studentised s²; each through Hall's skewness correction, the bars
    /// taken off first);
    /// `None` when the quantity is not resolved, or when |z| is beyond the
    /// range of a double (the quantity then fails, its reason saying so).
    pub z: Option<f64>,
    /// measured/predicted with its standard error and bar (`None` when
    /// the measurement is not resolved, or when the ratio is beyond the
    /// range of a double: the row and the failure's reason say so).
    pub ratio: Option<Ratio>,
    /// The largest change of z when one value in the samples' range is
    /// deleted (`None` when there is no z, or when deleting one value
    /// removes nearly all of the spread: `not_resolved` says so); above
    /// [`MAX_INFLUENCE`](super::MAX_INFLUENCE) the quantity is not resolved.
    pub influence: Option<f64>,
    /// The smallest relative error of the renderer in this quantity, either
    /// way, that fails the check with probability ≥ the stated power (for a
    /// bug that scales L). Stated for resolved quantities within their
    /// limit only: for a failing one it would describe a renderer already
    /// shown wrong. `None` also when no error is certain to be caught
    /// (`undetectable` says why).
    pub detectable_relative_error: Option<f64>,
    /// Why the quantity is not resolved (has no usable z), or `None`.
    pub not_resolved: Option<String>,
    /// Why a resolved quantity within its limit has no detectable error.
    pub undetectable: Option<String>,
    /// The resolution target (the default's unless one was stated).
    pub target_relative_error: f64,
    /// About how many samples would make the detectable error meet the
    /// target (`None` when the bars alone exceed it, or no estimate).
    pub samples_for_target: Option<f64>,
    /// Resolved, within its limit, and meeting its target.
    pub pass: bool,
}

/// The tail test: the largest value against the bound on its probability
/// for a correct renderer (Markov and Cantelli with the predicted mean and
/// variance; any distribution).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct TailCheck {
    /// The largest value, or a lower bound of it from the power sums.
    pub largest: f64,
    /// Whether `largest` is the exact largest value.
    pub largest_exact: bool,
    /// Bound on the probability that a correct renderer's largest of these
    /// M values is as large.
    pub probability_bound: f64,
    /// The rate the bound is tested at.
    pub rate: f64,
    /// The bound above the rate.
    pub pass: bool,
}

/// measured/predicted, with the measurement's standard error and the
/// prediction's bars carried to it.
///
/// With P the prediction, b its bars (quadrature + model, bounds), m the
/// measurement, se its standard error and r its rounding bar (a bound):
/// the ratio m/P differs from m_true/P_true by (m/P − m/P_true) + (m −
/// m_true)/P_true. The first part is at most |m|·b/(|P|(|P| − b)) and the
/// rounding's share of the second at most r/(|P| − b): together `bar`. The
/// statistical share is se/|P| to first order: `standard_error`.
///
/// ```
/// use mcrt_noise::check::Ratio;
/// let r = Ratio::new(2.0, 0.1, 4.0, 0.04, 0.0).unwrap();
/// assert_eq!((r.value, r.standard_error), (0.5, 0.025));
/// assert!((r.bar - 0.5 * 0.01 / 0.99).abs() < 1e-15);
/// assert!(Ratio::new(2.0, 0.1, 4.0, 4.0, 0.0).is_none()); // bars as large as the prediction
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Ratio {
    /// measured/predicted.
    pub value: f64,
    /// The measurement's standard error over |predicted| (a standard
    /// deviation, like the measurement's).
    pub standard_error: f64,
    /// Bound on the ratio's error from the prediction's bars and the
    /// measurement's rounding bar, (|m|·b/|P| + r)/(|P| − b).
    pub bar: f64,
}

impl Ratio {
    /// The ratio of `measured` (standard error `se`, rounding bar
    /// `rounding_bar`) to `predicted` (bars `bars`); `None` unless the bars
    /// are below |predicted| and every number is a normal double or 0 (a
    /// ratio beyond the range of a double is not given as a number).
    pub fn new(measured: f64, se: f64, predicted: f64, bars: f64, rounding_bar: f64) -> Option<Ratio> {
        let p = predicted.abs();
        let r = Ratio {
            value: measured / predicted,
            standard_error: se / p,
            bar: (measured.abs() * bars / p + rounding_bar) / (p - bars),
        };
        let representable = |x: f64| x == 0.0 || x.is_normal();
        (bars < p && [r.value, r.standard_error, r.bar].into_iter().all(representable)).then_some(r)
    }
}

/// The outcome of [`check`]: pass, fail or not resolved, each quantity's
/// numbers, and what the samples showed.
#[derive(Debug, Clone, Serialize)]
pub struct Verdict {
    /// Pass, fail or not resolved.
    pub status: Status,
    /// `status == Status::Pass`.
    pub pass: bool,
    /// The model the prediction came from.
    pub model: Model,
    /// How many samples.
    pub samples: u64,
    /// How many of them are nonzero (`None`: power sums given without the
    /// count, so sparsity was not checked; the statement says so).
    pub nonzero: Option<u64>,
    /// The family-wise false-alarm rate.
    pub false_alarm_rate: f64,
    /// The estimated correlation of the two z-scores under the null
    /// hypothesis, γ/√(κ − 1) from the samples' skewness and kurtosis (0
    /// without a shape).
    pub z_correlation: f64,
    /// The rate of each z-test alone: Šidák's split of the family-wise rate
    /// less the tail test's share.
    pub per_check_rate: f64,
    /// The rate the two z-tests spend together at their limit for
    /// z-scores correlated by `z_correlation` (at most the family-wise rate
    /// less the tail test's share; less, the more they are correlated);
    /// `None` if its integral did not converge.
    pub z_tests_spend: Option<f64>,
    /// |z| limit of each quantity (Šidák's, fixed by the stated rate).
    pub z_limit: f64,
    /// Power of the detectable-error figures.
    pub power: f64,
    /// The samples' shape (mean, standard deviation, skewness, kurtosis;
    /// `None` without spread or beyond the range of a double).
    pub shape: Option<Shape>,
    /// M/κ: about how many values carry the spread.
    pub effective_count: Option<f64>,
    /// The tail test (`None` below 4 samples).
    pub tail: Option<TailCheck>,
    /// How many of the largest values the check knew (up to
    /// [`TOP_VALUES`](super::TOP_VALUES)): a handful's joint influence is
    /// bounded over these (power sums may come with fewer).
    pub largest_values_known: usize,
    /// Mean and Var L (empty below 4 samples).
    pub checks: Vec<QuantityCheck>,
    /// Why it failed, one sentence each (empty unless it failed).
    pub failures: Vec<String>,
    /// What is not resolved, and what would resolve it, one sentence each
    /// (empty on a pass; beside the failures on a fail).
    pub unresolved: Vec<String>,
    /// What the check shows, in words.
    pub statement: String,
}

/// Fewest samples for which the mean, the variance and their standard
/// errors exist.
pub const MIN_SAMPLES: u64 = 4;

/// Fewest nonzero values for which the z-tests mean anything; below it both
/// quantities are not resolved. A renderer's L is mostly 0 where hits are
/// rare, and then the k nonzero values carry the whole measurement: the
/// relative standard error of the mean is ≈ 1/√k, and the variance's
/// standard error comes from the fourth moment, which a handful of values
/// does not pin down. The same rule as the reference tracer's (`compare`
/// and `trace`), defined once there.
pub const MIN_NONZERO: u64 = mcrt_reference::MIN_NONZERO_TRIALS;

/// Checks a renderer's per-iteration values of one pixel against the
/// prediction.
///
/// Three tests at the family-wise false-alarm rate α of `options`:
/// - the **tail test** ([`TAIL_SHARE`](super::TAIL_SHARE) of α): a largest
///   value no correct renderer reaches but with probability below that
///   share (Markov and Cantelli bounds: no assumption on the distribution)
///   fails;
/// - the **mean's z**, scaled by the predicted Var L (null-scaled);
/// - **Var L's z**, Wilson–Hilferty's cube root of s²/Var L with the
///   samples' kurtosis;
///
/// each z through Hall's skewness correction; the two z-tests share the
/// rest of α at a limit set for their estimated correlation, the
/// prediction's bars taken off before dividing. A quantity is *resolved*
/// when it has a measurement with spread, at least [`MIN_NONZERO`] nonzero
/// values, at least [`MIN_EFFECTIVE_COUNT`] values carrying the spread, the
/// values' extremes known, and its verdict does not rest on one value or a
/// handful (`undecided`: a pass must survive the deletion of any one value
/// and of its largest few). The verdict FAILS on a failed tail test or a
/// resolved quantity beyond its limit; it is NOT RESOLVED when a quantity
/// is not resolved or cannot detect its target (the reasons say what would
/// resolve it); otherwise it PASSES, and states the relative errors it
/// would have caught.
///
/// ```
/// use mcrt_noise::{check, predict, CheckOptions, Samples, Scene};
/// use mcrt_noise::check::Status;
///
/// let scene = Scene::builder()
///     .medium(1.0, 0.8)
///     .point_light([1.0, 0.0, 1.0], 1.0)
///     .camera([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
///     .estimator(0.2, 0.5, 20, 4)
///     .build()?;
/// let prediction = predict(&scene)?;
/// // A "renderer" that returns the mean every time: right mean, no variance.
/// let mut samples = Samples::new();
/// samples.extend(std::iter::repeat(prediction.mean.value).take(1000))?;
/// let verdict = check(&prediction, &samples, &CheckOptions::default());
/// assert_eq!(verdict.status, Status::NotResolved);
/// assert!(verdict.unresolved.iter().any(|r| r.starts_with("mean L and Var L: all 1000 values are equal")));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn check(prediction: &Prediction, samples: &Samples, options: &CheckOptions) -> Verdict {
    let shape = samples.shape();
    let z_correlation = shape.map_or(0.0, |s| z_correlation(&s));
    let z_limit = options.z_limit();
    let mut verdict = Verdict {
        status: Status::NotResolved,
        pass: false,
        model: prediction.model,
        samples: samples.count(),
        nonzero: samples.nonzero(),
        false_alarm_rate: options.false_alarm_rate(),
        z_correlation,
        per_check_rate: options.per_check_rate(),
        z_tests_spend: family_rate(z_limit, z_correlation),
        z_limit,
        power: options.power(),
        shape: None,
        effective_count: None,
        tail: None,
        largest_values_known: samples.largest_values().len(),
        checks: Vec::new(),
        failures: Vec::new(),
        unresolved: Vec::new(),
        statement: String::new(),
    };
    let Some((mean, variance)) = samples.estimates() else {
        verdict.unresolved.push(format!(
            "{} samples: at least {MIN_SAMPLES} are needed for the variance and its standard error",
            samples.count()
        ));
        verdict.statement = "nothing: too few samples".into();
        return verdict;
    };
    let (round_mean, round_var) = samples.rounding_bounds();
    let null = Null::new(prediction, (round_mean, round_var));
    verdict.shape = shape;
    verdict.effective_count = shape.map(|s| s.effective_count());
    let tail = tail_check(samples, &null, options.tail_rate());
    verdict.tail = Some(tail);
    let sparse = samples.nonzero().filter(|k| *k < MIN_NONZERO).map(|k| sparse_reason(k, samples.count()));
    let z_power = options.z_power();
    let unbounded = samples.range().is_none().then(|| {
        "the values' smallest and largest were not given (Samples::with_range, or \"min\" and \"max\" in the \
         power-sums file): the power sums alone allow one value to carry the whole spread, so one value's influence \
         on the verdict cannot be bounded"
            .to_string()
    });
    let dominated = shape.filter(|s| s.effective_count() < MIN_EFFECTIVE_COUNT).map(|s| dominated_reason(&s));
    let context = Context {
        z_limit,
        z_power,
        null,
        shape,
        range: samples.range(),
        largest: samples.largest_values().to_vec(),
        sparse: sparse.or(dominated).or(unbounded),
    };
    let quantities = [
        (Quantity::Mean, prediction.mean, mean, round_mean, options.targets().0),
        (Quantity::Variance, prediction.variance, variance, round_var, options.targets().1),
    ];
    verdict.checks =
        quantities.into_iter().map(|(which, p, m, r, target)| quantity(which, p, m, r, target, &context)).collect();
    decide(&mut verdict, &null);
    verdict
}

/// The largest change one value's deletion makes to either z-score of
/// `samples` (their shape and range, whatever else resolves them), `None`
/// without a shape or a range: what [`super::plan`] extrapolates.
pub(crate) fn largest_influence(samples: &Samples, null: &Null) -> Option<f64> {
    let (shape, range) = (samples.shape()?, samples.range()?);
    let change = |q: Quantity| influence(&shape, range, |s| q.z(s, null)).largest_change;
    Some(change(Quantity::Mean).max(change(Quantity::Variance)))
}

/// The two quantities tested.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Quantity {
    Mean,
    Variance,
}

impl Quantity {
    fn name(self) -> &'static str {
        match self {
            Quantity::Mean => "mean L",
            Quantity::Variance => "Var L",
        }
    }

    fn z(self, shape: &Shape, null: &Null) -> f64 {
        match self {
            Quantity::Mean => statistics::z_mean(shape, null),
            Quantity::Variance => statistics::z_variance(shape, null),
        }
    }
}

/// What every quantity's check needs besides its own numbers.
struct Context {
    /// The |z| limit (for the estimated correlation of the z-scores).
    z_limit: f64,
    /// Φ⁻¹(power).
    z_power: f64,
    null: Null,
    shape: Option<Shape>,
    /// The smallest and largest value (every value lies between).
    range: Option<(f64, f64)>,
    /// The largest values, descending (for their joint influence).
    largest: Vec<f64>,
    /// Why nothing is resolved whatever the z-scores: the values are sparse,
    /// or their extremes unknown.
    sparse: Option<String>,
}

fn tail_check(samples: &Samples, null: &Null, rate: f64) -> TailCheck {
    let (largest, largest_exact) = samples.largest();
    let probability_bound = statistics::tail_probability(samples.count(), largest, null);
    TailCheck { largest, largest_exact, probability_bound, rate, pass: probability_bound > rate }
}

fn quantity(
    which: Quantity,
    predicted: Predicted,
    measured: Result<Measured, String>,
    rounding_bar: f64,
    target: f64,
    cx: &Context,
) -> QuantityCheck {
    let bars = predicted.total_bar() + rounding_bar;
    let (measured, mut not_resolved) = match measured {
        Ok(m) => (Some(m), None),
        Err(why) => (None, Some(why)),
    };
    let ratio = measured
        .and_then(|m| Ratio::new(m.value, m.standard_error, predicted.value, predicted.total_bar(), rounding_bar));
    if measured.is_some() {
        not_resolved = cx.sparse.clone();
    }
    if measured.is_some() && bars >= predicted.value.abs() {
        not_resolved = Some(format!(
            "the bars ({bars:.2e}) are not below the predicted value ({:.6e}): there is nothing to check against",
            predicted.value
        ));
    }
    let shape = cx.shape.filter(|_| measured.is_some() && not_resolved.is_none());
    let (z_limit, z_power) = (cx.z_limit, cx.z_power);
    let z_of = |s: &Shape| which.z(s, &cx.null);
    let z = shape.map(|s| z_of(&s));
    let influence = shape.zip(cx.range).map(|(s, range)| influence(&s, range, z_of));
    if let (Some(s), Some(z), Some(i)) = (shape, z, influence) {
        let groups = without_largest(&s, &cx.largest, z_of);
        not_resolved = undecided(z, &i, &groups, z_limit, &s);
    }
    let resolved = not_resolved.is_none() && z.is_some();
    // A z beyond the range of a double is left out; `disagreement` states
    // the failure instead.
    let z = z.filter(|z| z.is_finite() && resolved);
    let within = resolved && z.is_some_and(|z| z.abs() <= z_limit);
    let detectable = shape.filter(|_| within).map(|s| match which {
        Quantity::Mean => statistics::detectable_mean(&s, &cx.null, z_limit, z_power),
        Quantity::Variance => statistics::detectable_variance(&s, &cx.null, z_limit, z_power),
    });
    let undetectable = match detectable {
        Some(None) => Some(
            "no error of any size is certain to be caught: the standard error is as large as the prediction".into(),
        ),
        _ => None,
    };
    let detectable_relative_error = detectable.flatten();
    let samples_for_target = shape.and_then(|s| match which {
        Quantity::Mean => statistics::samples_for_mean(target, &s, &cx.null, z_limit, z_power),
        Quantity::Variance => statistics::samples_for_variance(target, &s, &cx.null, z_limit, z_power),
    });
    let target_met = detectable_relative_error.is_some_and(|d| d <= target);
    QuantityCheck {
        name: which.name(),
        predicted,
        measured,
        rounding_bar,
        z,
        ratio,
        influence: influence.map(|i| i.largest_change).filter(|i| i.is_finite()),
        detectable_relative_error,
        not_resolved,
        undetectable,
        target_relative_error: target,
        samples_for_target,
        pass: within && target_met,
    }
}

/// Why a quantity with z-score `z` is not decided by its samples, if it
/// is not.
/// - Within the limit, a pass must survive the deletion of any one value
///   (every such z within the limit too), no one value may move z by more
///   than [`MAX_INFLUENCE`], and the k largest values together (k ≤
///   [`TOP_VALUES`](super::TOP_VALUES)) by no more than k times that:
///   otherwise the pass would rest on one value, or a handful.
/// - Beyond the limit, the failure stands if those influences are within
///   their bounds, or if it survives every such deletion (on the same side);
///   otherwise it would rest on them.
/// - A z that is not a number decides nothing; an infinite one fails.
fn undecided(z: f64, one: &Influence, groups: &[(usize, Option<f64>)], z_limit: f64, shape: &Shape) -> Option<String> {
    if z.is_nan() {
        return Some("its z is not a number: the values lie beyond the range of a double".into());
    }
    let group_excess = groups.iter().find(|(k, zk)| !zk.is_some_and(|zk| (zk - z).abs() <= *k as f64 * MAX_INFLUENCE));
    let small = one.largest_change <= MAX_INFLUENCE && group_excess.is_none();
    if z.abs() <= z_limit {
        if one.lowest < -z_limit || one.highest > z_limit {
            let crossed = if one.highest > z_limit { one.highest } else { one.lowest };
            return Some(format!(
                "deleting one value would take its z from {} to {} (beyond the limit ±{z_limit:.2}): a pass would \
                 rest on that value",
                z_text(z),
                z_text(crossed)
            ));
        }
        return (!small).then(|| influence_reason(one.largest_change, group_excess.copied(), z, shape, false));
    }
    let same_side = |v: f64| v.signum() == z.signum() && v.abs() > z_limit;
    let robust = z.is_infinite()
        || (same_side(one.lowest) && same_side(one.highest) && groups.iter().all(|(_, zk)| zk.is_some_and(same_side)));
    (!(small || robust)).then(|| influence_reason(one.largest_change, group_excess.copied(), z, shape, true))
}

/// Why a quantity whose z one value moves by `one`, or its k largest values
/// together by more than k (`group`: k and the z without them), is not
/// resolved; `beyond`: its z is beyond the limit.
fn influence_reason(one: f64, group: Option<(usize, Option<f64>)>, z: f64, shape: &Shape, beyond: bool) -> String {
    let moved = match (one.is_finite(), group) {
        (false, _) => "deleting one value removes nearly all of the spread".to_string(),
        (true, Some((k, Some(zk)))) if one <= MAX_INFLUENCE => format!(
            "deleting its {k} largest values moves its z from {} to {}, more than {k} × {MAX_INFLUENCE}",
            z_text(z),
            z_text(zk)
        ),
        (true, Some((k, None))) if one <= MAX_INFLUENCE => {
            format!("deleting its {k} largest values removes nearly all of the spread")
        }
        (true, _) => format!(
            "deleting one value moves its z by {}, more than {MAX_INFLUENCE}",
            z_text(one).trim_start_matches('+')
        ),
    };
    let what = if beyond { "the failure" } else { "the verdict" };
    let more = if one.is_finite() {
        let needed = shape.count as f64 * (one / MAX_INFLUENCE).max(1.0).powi(2);
        format!(
            "; if the large values are the renderer's rare but legitimate ones, {} samples would bring their \
             influence within bounds (it falls like 1/√M for values of a given size)",
            count_text(needed.ceil())
        )
    } else {
        String::new()
    };
    format!(
        "{moved}: {what} would rest on a few values (fireflies, or a tail these samples do not resolve: about {:.0} \
         of the {} values carry the spread, M/kurtosis){more}",
        shape.effective_count(),
        shape.count
    )
}

/// Why values whose spread a few of them carry (M/κ below
/// [`MIN_EFFECTIVE_COUNT`]) resolve nothing.
fn dominated_reason(shape: &Shape) -> String {
    let effective = shape.effective_count();
    format!(
        "about {effective:.1} of the {} values carry the spread (M/kurtosis, fewer than {MIN_EFFECTIVE_COUNT}): the \
         moments are dominated by a few values (fireflies, or a tail these samples do not resolve), so Var L's \
         standard error is itself unreliable; if the large values are the renderer's rare but legitimate ones, {} \
         samples would give {MIN_EFFECTIVE_COUNT}",
        shape.count,
        count_text((shape.count as f64 * MIN_EFFECTIVE_COUNT / effective).ceil())
    )
}

/// Why values with only `nonzero` of `count` nonzero (fewer than
/// [`MIN_NONZERO`]) resolve nothing.
fn sparse_reason(nonzero: u64, count: u64) -> String {
    let needed = (count as f64 * MIN_NONZERO as f64 / nonzero.max(1) as f64).ceil();
    format!(
        "only {nonzero} of the {count} values {} nonzero (fewer than {MIN_NONZERO}): the mean's relative standard \
         error is then ≈ 1/√{nonzero} ({:.0} %) and the variance's, from the fourth moment, is unreliable, so the normal \
         approximation behind the z-tests does not hold{}",
        if nonzero == 1 { "is" } else { "are" },
        100.0 / (nonzero.max(1) as f64).sqrt(),
        if nonzero == 0 {
            " (render a larger pilot: no value had a hit)".to_string()
        } else {
            format!(" ({} samples would give {MIN_NONZERO} nonzero values)", count_text(needed))
        }
    )
}

/// A sample count, with its "about": "about 1234", "about 1.23e7", or
/// "more than 1.8e308" (beyond a double).
pub(crate) fn count_text(n: f64) -> String {
    if n < 1e6 {
        format!("about {n:.0}")
    } else if n.is_finite() {
        format!("about {n:.2e}")
    } else {
        format!("more than {:.1e}", f64::MAX)
    }
}

/// Whether `q` is resolved and its z lies beyond the limit (or beyond the
/// range of a double).
pub(crate) fn disagrees(q: &QuantityCheck, z_limit: f64) -> bool {
    q.not_resolved.is_none() && q.measured.is_some() && q.z.is_none_or(|z| z.abs() > z_limit)
}

/// The status, the reasons and the statement, from the quantities and the
/// tail test.
fn decide(verdict: &mut Verdict, null: &Null) {
    use super::display::{disagreement, statement, tail_failure, unmet_target, unresolved};
    let z_limit = verdict.z_limit;
    let tail = verdict.tail.expect("the tail test runs whenever the quantities do");
    if !tail.pass {
        verdict.failures.push(tail_failure(&tail, verdict.samples, null));
    }
    let variance_ratio = verdict.checks[1].ratio.map(|r| r.value);
    for q in &verdict.checks {
        verdict.failures.extend(disagreement(q, z_limit, variance_ratio));
    }
    verdict.unresolved.extend(unresolved(&verdict.checks));
    // Unmet targets matter only when nothing else is wrong: they stop a weak pass.
    if verdict.failures.is_empty() && verdict.unresolved.is_empty() {
        verdict.unresolved.extend(verdict.checks.iter().filter_map(|q| unmet_target(q, verdict.samples)));
    }
    verdict.status = if !verdict.failures.is_empty() {
        Status::Fail
    } else if !verdict.unresolved.is_empty() {
        Status::NotResolved
    } else {
        Status::Pass
    };
    verdict.pass = verdict.status == Status::Pass;
    verdict.statement = statement(verdict);
}
