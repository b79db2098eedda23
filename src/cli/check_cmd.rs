//! `mcrt-noise check SCENE --values FILE`: a renderer's per-iteration values
//! (from any language) checked against the prediction.

use super::{to_json, CliError};
use mcrt_noise::{check, predict, CheckOptions, Samples, Scene};
use serde::de::{DeserializeSeed, Deserializer, SeqAccess, Visitor};
use serde::Deserialize;
use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::Path;

/// What `check` reads besides the scene.
pub struct CheckArgs<'a> {
    /// The values file (`-`: standard input).
    pub values: &'a Path,
    /// Family-wise false-alarm rate.
    pub false_alarm_rate: f64,
    /// Power of the detectable-error figures.
    pub power: f64,
    /// Relative resolution targets (mean, Var L); the defaults where `None`.
    pub targets: (Option<f64>, Option<f64>),
    /// Plan a check from these values (a pilot) instead of checking them.
    pub plan: bool,
    /// One JSON object instead of the text.
    pub json: bool,
}

/// Power sums as JSON: `{"count": M, "sums": [ΣL, ΣL², ΣL³, ΣL⁴, ΣL⁵, ΣL⁶],
/// "min": a, "max": b}` (or `"largest": [b₁, b₂, …]`, the up to 8 largest
/// values), with an optional bound on their relative error and an optional
/// count of the nonzero values (without it the check cannot tell sparse
/// values).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SumsFile {
    count: u64,
    sums: Vec<f64>,
    sums_relative_error: Option<f64>,
    nonzero: Option<u64>,
    min: Option<f64>,
    max: Option<f64>,
    largest: Option<Vec<f64>>,
}

/// Runs the check: `Ok` on pass; a verdict that failed or is not resolved,
/// printed on stdout, is [`CliError::Stated`] (exit 1); bad input is usage
/// (exit 2), and so is a scene the prediction does not support; a
/// prediction that did not converge is computed (exit 1). With `plan`, the
/// plan is printed, and exit 1 means the pilot already fails or no count
/// could be estimated.
pub fn check_cmd(scene: &Scene, args: &CheckArgs) -> Result<(), CliError> {
    let options = options(args).map_err(CliError::Usage)?;
    let samples = read_samples(args.values).map_err(CliError::Usage)?;
    let prediction = predict(scene)?;
    if args.plan {
        let plan = mcrt_noise::check::plan(&prediction, &samples, &options);
        if args.json {
            println!("{}", to_json(&plan)?);
        } else {
            println!("{plan}");
        }
        let usable = plan.samples.is_some() && plan.pilot.status != mcrt_noise::check::Status::Fail;
        return if usable { Ok(()) } else { Err(CliError::Stated) };
    }
    let verdict = check(&prediction, &samples, &options);
    if args.json {
        println!("{}", to_json(&verdict)?);
    } else {
        println!("{verdict}");
    }
    if verdict.pass {
        Ok(())
    } else {
        Err(CliError::Stated)
    }
}

fn options(args: &CheckArgs) -> Result<CheckOptions, String> {
    let flag = |name: &str, e: mcrt_noise::scene::FieldError| format!("--{name} = {}: must be {}", e.value, e.allowed);
    // Refused before anything is read or computed.
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

/// Longest line of a values file, in bytes.
const MAX_LINE: u64 = 4096;

/// Largest power-sums JSON object, in bytes (a pretty-printed one is a few
/// hundred; anything near this is not power sums).
const MAX_SUMS_JSON: u64 = 1 << 20;

/// The values: one number per line, a JSON array, or power sums as JSON.
/// Read as a stream: memory stays bounded whatever the file's size.
fn read_samples(path: &Path) -> Result<Samples, String> {
    let at = path.display().to_string();
    let mut reader: Box<dyn BufRead> = if path == Path::new("-") {
        Box::new(BufReader::new(std::io::stdin()))
    } else {
        Box::new(BufReader::new(File::open(path).map_err(|e| format!("--values {at}: {e}"))?))
    };
    let io = |e: std::io::Error| format!("--values {at}: {e}");
    // The first non-blank byte says which format.
    let first = loop {
        let buf = reader.fill_buf().map_err(io)?;
        match buf.iter().position(|b| !b.is_ascii_whitespace()) {
            Some(i) => break Some(buf[i]),
            None if buf.is_empty() => break None,
            None => {
                let n = buf.len();
                reader.consume(n);
            }
        }
    };
    match first {
        Some(b'{') => read_power_sums(reader, &at),
        Some(b'[') => {
            let mut samples = Samples::new();
            let mut de = serde_json::Deserializer::from_reader(reader);
            PushEach(&mut samples).deserialize(&mut de).map_err(|e| format!("--values {at}: JSON array: {e}"))?;
            de.end().map_err(|e| format!("--values {at}: JSON array: {e}"))?;
            Ok(samples)
        }
        _ => read_lines(reader, &at),
    }
    .and_then(|samples| {
        if samples.count() == 0 {
            Err(format!("--values {at}: no values (one number per line, a JSON array, or power sums)"))
        } else {
            Ok(samples)
        }
    })
}

/// Power sums as JSON ([`SumsFile`]), read whole (anything after the
/// object is an error, not ignored).
fn read_power_sums(reader: Box<dyn BufRead>, at: &str) -> Result<Samples, String> {
    let mut text = String::new();
    reader.take(MAX_SUMS_JSON + 1).read_to_string(&mut text).map_err(|e| format!("--values {at}: {e}"))?;
    if text.len() as u64 > MAX_SUMS_JSON {
        return Err(format!("--values {at}: power sums JSON longer than {MAX_SUMS_JSON} bytes"));
    }
    let f: SumsFile = serde_json::from_str(&text).map_err(|e| format!("--values {at}: power sums JSON: {e}"))?;
    let bad = |e: mcrt_noise::SampleError| format!("--values {at}: {e}");
    let sums: [f64; 6] = f.sums.as_slice().try_into().map_err(|_| {
        format!(
            "--values {at}: power sums JSON: \"sums\" has {} entries: must have 6, [ΣL, ΣL², ΣL³, ΣL⁴, ΣL⁵, ΣL⁶] \
             (Var L's test corrects its skewness with the sixth moment)",
            f.sums.len()
        )
    })?;
    let mut samples = Samples::from_power_sums(f.count, sums, sums_error(&f, at)?).map_err(bad)?;
    if let Some(k) = f.nonzero {
        samples = samples.with_nonzero(k).map_err(bad)?;
    }
    let largest = largest_values(f.max, f.largest, at)?;
    match f.min.filter(|_| !largest.is_empty()) {
        Some(lo) => samples.with_extremes(lo, &largest).map_err(bad),
        None => Err(format!(
            "--values {at}: power sums JSON: \"min\" and \"max\" (the smallest and largest value) are required: \
             without them one value's influence on the verdict cannot be bounded (\"largest\", the up to 8 largest \
             values, bounds a handful's as well)"
        )),
    }
}

/// The sums' relative error: as given, or by default the bound of plain
/// f64 summation of M powers, each formed with at most 3 roundings:
/// (M − 1)·2⁻⁵³ for the additions and 3·2⁻⁵³ for the terms, (M + 2)·2⁻⁵³
/// (the check's inequalities are tight for one nonzero value, where the
/// terms' own rounding matters); past ~10¹³ values that bound exceeds what
/// the check accepts: say so.
fn sums_error(f: &SumsFile, at: &str) -> Result<f64, String> {
    let plain = (f.count as f64 + 2.0) * f64::EPSILON / 2.0;
    match f.sums_relative_error {
        Some(eps) => Ok(eps),
        None if plain < 1e-3 => Ok(plain),
        None => Err(format!(
            "--values {at}: count = {}: plain f64 sums of that many values may be off by more than 10⁻³ relative; \
             give \"sums_relative_error\" (e.g. 4·2⁻⁵³ for compensated sums of powers formed by multiplication)",
            f.count
        )),
    }
}

/// The largest values given: `largest`, or `max` alone (which, given with
/// `largest`, must be its largest); empty when neither is given.
fn largest_values(max: Option<f64>, largest: Option<Vec<f64>>, at: &str) -> Result<Vec<f64>, String> {
    match (max, largest) {
        (_, Some(list)) if list.is_empty() => Err(format!("--values {at}: power sums JSON: \"largest\" is empty")),
        (Some(max), Some(list)) if list.iter().copied().fold(f64::MIN, f64::max) != max => {
            Err(format!("--values {at}: power sums JSON: \"max\" = {max:e} is not the largest of \"largest\" {list:?}"))
        }
        (_, Some(list)) => Ok(list),
        (Some(max), None) => Ok(vec![max]),
        (None, None) => Ok(Vec::new()),
    }
}

/// One number per line (`#` comments and blank lines skipped).
fn read_lines(mut reader: Box<dyn BufRead>, at: &str) -> Result<Samples, String> {
    let mut samples = Samples::new();
    let mut line = Vec::new();
    for number in 1u64.. {
        line.clear();
        let n =
            (&mut reader).take(MAX_LINE + 1).read_until(b'\n', &mut line).map_err(|e| format!("--values {at}: {e}"))?;
        if n == 0 {
            break;
        }
        if n as u64 > MAX_LINE {
            return Err(format!("--values {at}: line {number} is longer than {MAX_LINE} bytes"));
        }
        let text = std::str::from_utf8(&line).map_err(|_| format!("--values {at}: line {number} is not UTF-8"))?.trim();
        if text.is_empty() || text.starts_with('#') {
            continue;
        }
        let l: f64 = text.parse().map_err(|_| format!("--values {at}: line {number}: {text:?} is not a number"))?;
        samples.push(l).map_err(|e| format!("--values {at}: line {number}: {e}"))?;
    }
    Ok(samples)
}

/// Deserialises a JSON array of numbers straight into samples (no vector).
struct PushEach<'a>(&'a mut Samples);

impl<'de> DeserializeSeed<'de> for PushEach<'_> {
    type Value = ();
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for PushEach<'_> {
    type Value = ();
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("an array of numbers")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        while let Some(l) = seq.next_element::<f64>()? {
            self.0.push(l).map_err(serde::de::Error::custom)?;
        }
        Ok(())
    }
}
