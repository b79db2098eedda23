//! The tracer's commands: `trace`, `merge`, `compare`.

use indicatif::{ProgressBar, ProgressStyle};
use mcrt_noise::oracle::Precision;
use mcrt_noise::reports::compare::{Comparison, TraceReport};
use mcrt_noise::scene::Scene;
use mcrt_reference::{merge, trace, HitMethod, Run, Shard, Tracer};
use std::io::IsTerminal;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// `--trials M` (0..M) or `--trials A..B`.
pub fn parse_trials(text: &str) -> Result<Range<u64>, String> {
    let bad = || format!("--trials: \"{text}\" is neither a count M >= 1 nor a range A..B with A < B");
    let range = match text.split_once("..") {
        Some((a, b)) => a.trim().parse::<u64>().map_err(|_| bad())?..b.trim().parse::<u64>().map_err(|_| bad())?,
        None => 0..text.trim().parse::<u64>().map_err(|_| bad())?,
    };
    if range.start >= range.end {
        return Err(bad());
    }
    Ok(range)
}

/// Runs `f` on a pool of `threads` threads (all cores when `None`).
fn with_threads<R: Send>(threads: Option<usize>, f: impl FnOnce() -> R + Send) -> Result<R, String> {
    match threads {
        None => Ok(f()),
        Some(0) => Err("--threads: must be at least 1".into()),
        Some(n) => {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(n).build().map_err(|e| e.to_string())?;
            Ok(pool.install(f))
        }
    }
}

/// The tracer for the scene and the trial count, every bound checked
/// before anything runs (exit 2 with the field or flag named).
fn prepared(scene: &Scene, range: &Range<u64>) -> Result<Tracer, String> {
    let tracer = Tracer::new(scene).map_err(|e| e.to_string())?;
    tracer.check_trials(range.end - range.start).map_err(|e| e.to_string())?;
    Ok(tracer)
}

/// Traces the range with a progress bar on a terminal for long runs
/// (about a second of work or more).
fn traced(tracer: &Tracer, seed: u64, range: Range<u64>, threads: Option<usize>) -> Result<(Run, f64), String> {
    let total = range.end - range.start;
    let bar = if std::io::stderr().is_terminal() && total as f64 * tracer.work().total() >= 3e7 {
        let bar = ProgressBar::new(total);
        bar.set_style(
            ProgressStyle::with_template("{bar:40} {pos}/{len} trials  {per_sec}  eta {eta}")
                .map_err(|e| e.to_string())?,
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

pub fn trace_cmd(
    scene: &Scene,
    trials: &str,
    seed: u64,
    threads: Option<usize>,
    json: bool,
    out: Option<&Path>,
) -> Result<(), String> {
    let range = parse_trials(trials)?;
    let tracer = prepared(scene, &range)?;
    let file = out.map(open_out).transpose()?;
    let (run, seconds) = traced(&tracer, seed, range, threads)?;
    let report = TraceReport::new(&run, seconds);
    write_then_print(&run, file, out, &report, json)
}

pub fn merge_cmd(paths: &[PathBuf], json: bool, out: Option<&Path>) -> Result<(), String> {
    let runs = paths
        .iter()
        .map(|p| {
            let text = std::fs::read_to_string(p).map_err(|e| format!("{}: {e}", p.display()))?;
            let shard: Shard = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", p.display()))?;
            Run::from_shard(&shard).map_err(|e| format!("{}: {e}", p.display()))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let file = out.map(open_out).transpose()?;
    let run = merge(&runs)?;
    write_then_print(&run, file, out, &TraceReport::new(&run, 0.0), json)
}

/// The `--out` file, created (or truncated) before the run, so that a path
/// that cannot be written is refused before any work.
fn open_out(path: &Path) -> Result<std::fs::File, String> {
    std::fs::File::create(path).map_err(|e| format!("--out {}: cannot be written: {e}", path.display()))
}

/// Writes the shard (if asked), then prints the report; if writing fails,
/// the report is printed first, then the error.
fn write_then_print(
    run: &Run,
    file: Option<std::fs::File>,
    path: Option<&Path>,
    report: &TraceReport,
    json: bool,
) -> Result<(), String> {
    let written = match (file, path) {
        (Some(file), Some(path)) => write_shard(run, file, path),
        _ => Ok(()),
    };
    print_report(report, json)?;
    written
}

/// The run as a shard file for `merge`.
fn write_shard(run: &Run, mut file: std::fs::File, path: &Path) -> Result<(), String> {
    use std::io::Write;
    let text = serde_json::to_string_pretty(&run.to_shard()).map_err(|e| e.to_string())?;
    file.write_all(text.as_bytes()).and_then(|()| file.sync_all()).map_err(|e| {
        format!("--out {}: writing the shard failed after the run (result printed above): {e}", path.display())
    })
}

fn print_report(report: &TraceReport, json: bool) -> Result<(), String> {
    if json {
        println!("{}", serde_json::to_string_pretty(report).map_err(|e| e.to_string())?);
    } else {
        print!("{}", report.table());
    }
    Ok(())
}

/// `compare`: prints the comparison (the verdict once, on stdout) and
/// returns whether the two sides agree (`false` for DISAGREE and for NOT
/// RESOLVED: exit 1).
pub fn compare_cmd(scene: &Scene, trials: &str, seed: u64, threads: Option<usize>, json: bool) -> Result<bool, String> {
    let range = parse_trials(trials)?;
    if range.end - range.start < 4 {
        return Err(format!("--trials: \"{trials}\" is fewer than 4 trials; compare needs at least 4"));
    }
    let tracer = prepared(scene, &range)?;
    let oracle = mcrt_noise::oracle::run(scene, Precision::F64, None).map_err(|e| e.to_string())?;
    let (run, _) = traced(&tracer, seed, range, threads)?;
    let cmp = Comparison::new(&oracle, &run.estimates(), run.counters.trials, seed);
    if json {
        println!("{}", serde_json::to_string_pretty(&cmp).map_err(|e| e.to_string())?);
    } else {
        print!("{}", cmp.table());
    }
    Ok(cmp.pass)
}
