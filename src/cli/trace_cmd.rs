//! The tracer's commands: `trace`, `merge`, `compare`.

use super::{to_json, CliError};
use indicatif::{ProgressBar, ProgressStyle};
use mcrt_noise::oracle::Precision;
use mcrt_noise::reports::compare::{Comparison, TraceReport, MERGED_TIME};
use mcrt_noise::scene::Scene;
use mcrt_reference::run::check_shard_format;
use mcrt_reference::{merge, trace, HitMethod, Run, Shard, Tracer};
use std::io::IsTerminal;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// `--trials M` (0..M) or `--trials A..B`.
pub fn parse_trials(text: &str) -> Result<Range<u64>, CliError> {
    let bad = || {
        CliError::usage(format!(
            "--trials: \"{text}\" is neither a count M in [1, {max}] nor a range A..B of trial indices with \
             0 <= A < B <= {max}",
            max = u64::MAX
        ))
    };
    let range = match text.split_once("..") {
        Some((a, b)) => a.trim().parse::<u64>().map_err(|_| bad())?..b.trim().parse::<u64>().map_err(|_| bad())?,
        None => 0..text.trim().parse::<u64>().map_err(|_| bad())?,
    };
    if range.start >= range.end {
        return Err(bad());
    }
    Ok(range)
}

/// Runs `f` on a pool of `threads` threads (all cores when `None`); a pool
/// the system cannot start is a failure of the run (exit 1).
fn with_threads<R: Send>(threads: Option<usize>, f: impl FnOnce() -> R + Send) -> Result<R, CliError> {
    match threads {
        None => Ok(f()),
        Some(0) => Err(CliError::usage("--threads: must be at least 1")),
        Some(n) => {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| CliError::computed(format!("--threads {n}: the thread pool did not start: {e}")))?;
            Ok(pool.install(f))
        }
    }
}

/// The tracer for the scene and the trial count, every bound checked
/// before anything runs (exit 2 with the field or flag named).
fn prepared(scene: &Scene, range: &Range<u64>) -> Result<Tracer, CliError> {
    let tracer = Tracer::new(scene)?;
    tracer.check_trials(range.end - range.start)?;
    Ok(tracer)
}

/// Traces the range with a progress bar on a terminal for long runs
/// (about a second of work or more).
fn traced(tracer: &Tracer, seed: u64, range: Range<u64>, threads: Option<usize>) -> Result<(Run, f64), CliError> {
    let total = range.end - range.start;
    let bar = if std::io::stderr().is_terminal() && total as f64 * tracer.work().total() >= 3e7 {
        let bar = ProgressBar::new(total);
        bar.set_style(
            ProgressStyle::with_template("{bar:40} {pos}/{len} trials  {per_sec}  eta {eta}")
                .map_err(CliError::computed)?,
        );
        bar
    } else {
        ProgressBar::hidden()
    };
    let start = Instant::now();
    let run = with_threads(threads, || trace(tracer, seed, range, HitMethod::Sorted, &|n| bar.inc(n)))?;
    bar.finish_and_clear();
    Ok((run, start.elapsed().as_secs_f64()))
}

/// `trace`; `scene_path` is the scene file the scene was read from (an
/// `--out` naming it is refused).
pub fn trace_cmd(
    scene: &Scene,
    scene_path: &Path,
    trials: &str,
    seed: u64,
    threads: Option<usize>,
    json: bool,
    out: Option<&Path>,
) -> Result<(), CliError> {
    let range = parse_trials(trials)?;
    let tracer = prepared(scene, &range)?;
    if let Some(out) = out {
        not_an_input(out, "the scene file", scene_path)?;
    }
    out.map(check_out).transpose()?;
    let (run, seconds) = traced(&tracer, seed, range, threads)?;
    let report = TraceReport::new(&run, Ok(seconds));
    write_then_print(&run, out, &report, json)?;
    resolved(&run, &report)
}

/// `merge`: every shard read and validated (exit 2 naming the file), then
/// reported as `trace` reports a run.
pub fn merge_cmd(paths: &[PathBuf], json: bool, out: Option<&Path>) -> Result<(), CliError> {
    let runs = paths
        .iter()
        .map(|p| {
            let at = |e: String| CliError::Usage(format!("{}: {e}", p.display()));
            let text = std::fs::read_to_string(p).map_err(|e| at(e.to_string()))?;
            // The format first: another format's fields are not this one's.
            let head: serde_json::Value = serde_json::from_str(&text).map_err(|e| at(e.to_string()))?;
            check_shard_format(head.get("format").and_then(|f| f.as_str())).map_err(at)?;
            let shard: Shard = serde_json::from_str(&text).map_err(|e| at(e.to_string()))?;
            Run::from_shard(&shard).map_err(at)
        })
        .collect::<Result<Vec<_>, _>>()?;
    if let Some(out) = out {
        for p in paths {
            not_an_input(out, "the shard", p)?;
        }
    }
    out.map(check_out).transpose()?;
    let run = merge(&runs).map_err(CliError::Usage)?;
    let report = TraceReport::new(&run, Err(MERGED_TIME.to_string()));
    write_then_print(&run, out, &report, json)?;
    resolved(&run, &report)
}

/// A run of 4 trials or more whose mean or variance is not resolved (fewer
/// than `mcrt_reference::MIN_NONZERO_TRIALS` trials with hits, no spread,
/// beyond a double; the reason is in the report just printed) is a computed
/// failure, exit 1. Below 4 trials the variance's error is not defined by
/// construction: such a run is a shard to merge, exit 0.
fn resolved(run: &Run, report: &TraceReport) -> Result<(), CliError> {
    if report.not_resolved.is_some() && run.counters.trials >= 4 {
        Err(CliError::Stated)
    } else {
        Ok(())
    }
}

/// Refuses an `--out` path that is the same file as an input (exit 2,
/// before the run): creating it would truncate the input, and the shard
/// would replace it. Same file: same device and inode (Unix; hard links and
/// symbolic links included), else the same canonical path. A path that does
/// not exist yet is no input.
fn not_an_input(out: &Path, what: &str, input: &Path) -> Result<(), CliError> {
    if same_file(out, input) {
        return Err(CliError::usage(format!(
            "--out {}: is {what} {} (an input of this command); writing there would replace it: give another path",
            out.display(),
            input.display()
        )));
    }
    Ok(())
}

fn same_file(a: &Path, b: &Path) -> bool {
    let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        ma.dev() == mb.dev() && ma.ino() == mb.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = (ma, mb);
        matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y)
    }
}

/// The `--out` file can be written, checked before any work without
/// changing it (it used to be truncated at once: a run that failed or was
/// interrupted left an existing shard empty); it is written after the run.
fn check_out(path: &Path) -> Result<(), CliError> {
    super::paths::writable_file("--out", path)
}

/// Writes the shard (if asked), then prints the report; if writing fails,
/// the report is printed first, then the error (exit 2: the path).
fn write_then_print(run: &Run, path: Option<&Path>, report: &TraceReport, json: bool) -> Result<(), CliError> {
    let written = path.map_or(Ok(()), |path| write_shard(run, path));
    print_report(report, json)?;
    written
}

/// The run as a shard file for `merge`.
fn write_shard(run: &Run, path: &Path) -> Result<(), CliError> {
    use std::io::Write;
    let text = to_json(&run.to_shard())?;
    let write = || {
        std::fs::File::create(path).and_then(|mut file| file.write_all(text.as_bytes()).and_then(|()| file.sync_all()))
    };
    write().map_err(|e| {
        CliError::usage(format!(
            "--out {}: writing the shard failed after the run (result printed above): {e}",
            path.display()
        ))
    })
}

fn print_report(report: &TraceReport, json: bool) -> Result<(), CliError> {
    if json {
        println!("{}", to_json(report)?);
    } else {
        print!("{}", report.table());
    }
    Ok(())
}

/// `compare`: prints the comparison (the verdict once, on stdout); DISAGREE
/// and NOT RESOLVED are [`CliError::Stated`] (exit 1).
pub fn compare_cmd(scene: &Scene, trials: &str, seed: u64, threads: Option<usize>, json: bool) -> Result<(), CliError> {
    let range = parse_trials(trials)?;
    if range.end - range.start < 4 {
        return Err(CliError::usage(format!(
            "--trials: \"{trials}\" is fewer than 4 trials; compare needs at least 4"
        )));
    }
    let tracer = prepared(scene, &range)?;
    // The comparison reads the oracle's report of orders 0 and 1 (every
    // order is refused here; `check` takes orders 2–9 and "all" at q = 1,
    // N_B = 1), mean
    // and Var L alone: the library's, the finite-sphere correlations of single-scattered light
    // included where they cover the scene (about a minute), and the
    // same-path term of a Henyey–Greenstein medium at q = 1 and N_B = 1
    // (about 5 minutes).
    let (scope, evaluations) = mcrt_noise::oracle::prediction_scope(scene, Precision::F64);
    let budget = mcrt_noise::quad::Budget::new(evaluations);
    let oracle = mcrt_noise::oracle::run_within_scoped(scene, Precision::F64, None, &budget, scope)?;
    let (run, _) = traced(&tracer, seed, range, threads)?;
    let cmp = Comparison::new(&oracle, &run.estimates(), run.counters.trials, seed);
    if json {
        println!("{}", to_json(&cmp)?);
    } else {
        print!("{}", cmp.table());
    }
    if cmp.pass {
        Ok(())
    } else {
        Err(CliError::Stated)
    }
}
