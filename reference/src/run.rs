//! Runs over trial ranges, in parallel, and shards that merge exactly.
//!
//! Trial i of a run seeded with S always uses the stream (S, i) and its L
//! enters exact sums (`moments`), so a run over a range gives bit-identical
//! numbers for any thread count, and shards over a split of the range merge
//! into exactly the single run's numbers.

use crate::estimator::{Counters, HitMethod, Tracer};
use crate::moments::{Estimates, PowerSums, Summary};
use mcrt_scene::Scene;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::ops::Range;

/// Largest number of trials per work item: progress is reported and sums
/// are merged per chunk. Chunks of heavy trials are smaller (down to one
/// trial), so that progress shows every ~2²⁰ units of expected work.
const CHUNK: u64 = 4096;
/// Expected work (rays + segments + spheres) per chunk, where trials are heavy.
const CHUNK_WORK: f64 = 1048576.0;

/// The outcome of tracing some trials of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    /// The scene as normalised TOML (shards merge only for the same scene).
    pub scene: String,
    pub seed: u64,
    /// Disjoint trial ranges covered, sorted.
    pub ranges: Vec<Range<u64>>,
    pub counters: Counters,
    pub sums: PowerSums,
}

/// Trials with L > 0 a run of 4 trials or more needs before its mean and
/// variance are reported as resolved (below, `Run::estimates` gives the
/// reason instead, and `trace`, `merge` exit 1, `compare` says NOT
/// RESOLVED). The standard errors rest on a normal approximation that
/// needs many nonzero values: with k trials of M having L > 0, the
/// relative standard error of the mean is ≈ 1/√k (the count k itself is
/// the dominant noise), so at k = 100 the mean is known to ~10 % and the
/// count's Poisson skewness 1/√k is 0.1; the variance's standard error,
/// from the fourth moment, is dominated by the few largest values and is
/// itself unreliable for few nonzero values (a run of `point-hg-forward`
/// with 1 hit in 300 trials gave Var L ± 1 % and z = −160 against an
/// oracle it agrees with).
pub const MIN_NONZERO_TRIALS: u64 = 100;

impl Run {
    /// Mean and variance of L with standard errors (`None` below 4 trials),
    /// whatever the number of nonzero trials ([`Run::estimates`] checks it).
    pub fn summary(&self) -> Option<Summary> {
        self.sums.summary()
    }

    /// The mean and the variance, each with its standard error or the
    /// reason it is not given: from 4 trials on, fewer than
    /// [`MIN_NONZERO_TRIALS`] trials with L > 0 (no hits at all, or too
    /// few); otherwise as [`PowerSums::estimates`] (fewer than 4 trials, no
    /// spread, beyond the range of a double).
    pub fn estimates(&self) -> Estimates {
        let c = &self.counters;
        if c.trials >= 4 && c.nonzero_trials < MIN_NONZERO_TRIALS {
            let need = format!(
                "at least {MIN_NONZERO_TRIALS} trials with hits are needed for the standard errors to mean anything"
            );
            let why = if c.hits == 0 {
                format!(
                    "no hits in {} trials: the mean and variance are not resolved (no forward segment passed within \
                     R of a sphere; {need}: run more trials or take a larger estimator.radius)",
                    c.trials
                )
            } else if c.nonzero_trials == 0 {
                format!(
                    "L = 0 in all {} trials ({} hits added no light: the medium scatters none, medium.albedo = 0): \
                     the mean and variance are not resolved ({need})",
                    c.trials, c.hits
                )
            } else {
                format!(
                    "only {} of {} trials had hits: the mean and variance are not resolved ({need}: run more trials, \
                     merge shards, or take a larger estimator.radius)",
                    c.nonzero_trials, c.trials
                )
            };
            return Estimates { mean: Err(why.clone()), variance: Err(why) };
        }
        self.sums.estimates()
    }
}

/// Traces trials `range` of the run seeded with `seed`, in parallel on the
/// current rayon pool; `progress` is called with the number of trials done
/// after each chunk (from any thread). Nothing is allocated per trial or
/// chunk up front, and the range may end anywhere up to `u64::MAX`. A run
/// beyond `limits::MAX_RUN_WORK` should be refused first
/// ([`Tracer::check_trials`]): its counters could overflow.
pub fn trace(tracer: &Tracer, seed: u64, range: Range<u64>, method: HitMethod, progress: &(dyn Fn(u64) + Sync)) -> Run {
    let len = range.end.saturating_sub(range.start);
    let chunk = chunk_size(tracer);
    let exp = tracer.scale_exponent();
    let (counters, sums) = (0..len.div_ceil(chunk))
        .into_par_iter()
        .map(|k| {
            // k·chunk < len: no overflow; the end saturates and is clipped.
            let start = range.start + k * chunk;
            let end = start.saturating_add(chunk).min(range.end);
            let mut counters = Counters::default();
            let mut scaled = PowerSums::default();
            for i in start..end {
                let (l, c) = tracer.trial_scaled(seed, i, method);
                scaled.push(l);
                counters.add(&c);
            }
            progress(end - start);
            (counters, scaled.scaled(exp))
        })
        .reduce(
            || (Counters::default(), PowerSums::default()),
            |(mut ca, sa), (cb, sb)| {
                ca.add(&cb);
                (ca, sa.merge(&sb))
            },
        );
    let ranges = if range.is_empty() { Vec::new() } else { vec![range] };
    Run { scene: tracer.scene().to_toml_string(), seed, ranges, counters, sums }
}

/// Trials per chunk: [`CHUNK`], or fewer for heavy trials.
fn chunk_size(tracer: &Tracer) -> u64 {
    (CHUNK_WORK / tracer.work().total()).clamp(1.0, CHUNK as f64) as u64
}

/// A run as stored in a shard file.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Shard {
    pub format: String,
    pub scene: String,
    pub seed: u64,
    pub ranges: Vec<[u64; 2]>,
    pub counters: Counters,
    /// Exact Σ L, Σ L², Σ L³, Σ L⁴ in hexadecimal.
    pub sums: [String; 4],
}

/// The shard format this version writes and reads. Format 2 added
/// `counters.nonzero_trials`.
pub const SHARD_FORMAT: &str = "mcrt-noise trace shard 2";

/// The `format` field of a shard (`None`: missing or not a string) against
/// [`SHARD_FORMAT`], checked before the rest of the shard is read: a shard
/// of format 1 was refused as "missing field `nonzero_trials`", which named
/// neither format.
pub fn check_shard_format(found: Option<&str>) -> Result<(), String> {
    match found {
        Some(SHARD_FORMAT) => Ok(()),
        Some(f @ "mcrt-noise trace shard 1") => Err(format!(
            "format: expected \"{SHARD_FORMAT}\", found \"{f}\" (format 1, from an earlier version, has no \
             counters.nonzero_trials, which the sparsity check needs and cannot be recovered from its sums: trace \
             its trial ranges again with `trace --out`)"
        )),
        Some(f) => Err(format!("format: expected \"{SHARD_FORMAT}\", found \"{f}\"")),
        None => Err(format!("format: missing (a shard file has \"format\": \"{SHARD_FORMAT}\"); not a shard")),
    }
}

impl Run {
    pub fn to_shard(&self) -> Shard {
        Shard {
            format: SHARD_FORMAT.into(),
            scene: self.scene.clone(),
            seed: self.seed,
            ranges: self.ranges.iter().map(|r| [r.start, r.end]).collect(),
            counters: self.counters,
            sums: self.sums.to_hex(),
        }
    }

    /// The run of a shard, every field checked: the format; the scene
    /// through the scene validation and the tracer's bounds (stored
    /// normalised); the ranges non-empty, ascending and disjoint; the
    /// counters consistent with them and with the scene; the sums finite,
    /// exact and those of real numbers. The error names the field.
    pub fn from_shard(shard: &Shard) -> Result<Run, String> {
        check_shard_format(Some(&shard.format))?;
        let scene = Scene::from_toml_str(&shard.scene).map_err(|e| format!("scene: {e}"))?;
        let tracer = Tracer::new(&scene).map_err(|e| format!("scene: {e}"))?;
        let ranges: Vec<Range<u64>> = shard.ranges.iter().map(|r| r[0]..r[1]).collect();
        let mut count = 0u64;
        for (i, r) in ranges.iter().enumerate() {
            if r.start >= r.end {
                return Err(format!("ranges[{i}] = {r:?}: must be non-empty (start < end)"));
            }
            if i > 0 && r.start < ranges[i - 1].end {
                return Err(format!(
                    "ranges[{i}] = {r:?}: must start at or after the end of ranges[{}] = {:?} (ascending, disjoint)",
                    i - 1,
                    ranges[i - 1]
                ));
            }
            count += r.end - r.start; // disjoint ranges within u64: no overflow
        }
        check_counters(&shard.counters, count, &tracer)?;
        let sums = PowerSums::from_hex(count, &shard.sums)?;
        if shard.counters.hits == 0 && !sums.is_zero() {
            return Err("sums: must be 0 when counters.hits = 0 (no trial hit a sphere)".into());
        }
        check_nonzero_trials(&shard.counters, &sums, &tracer)?;
        sums.check_non_negative(shard.counters.nonzero_trials)?;
        Ok(Run { scene: scene.to_toml_string(), seed: shard.seed, ranges, counters: shard.counters, sums })
    }
}

/// The counters of a shard against its ranges (`trials` in all) and scene.
fn check_counters(c: &Counters, trials: u64, tracer: &Tracer) -> Result<(), String> {
    let est = &tracer.scene().estimator;
    let d = &c.draws;
    let bad = |field: &str, value: u64, want: String| Err(format!("counters.{field} = {value}: must be {want}"));
    if c.trials != trials {
        return bad("trials", c.trials, format!("{trials}, the trials the ranges cover"));
    }
    if Some(c.forward_rays) != trials.checked_mul(est.forward_rays) {
        return bad(
            "forward_rays",
            c.forward_rays,
            format!("trials × estimator.forward_rays = {trials} × {}", est.forward_rays),
        );
    }
    if c.forward_segments < c.forward_rays {
        return bad("forward_segments", c.forward_segments, "at least counters.forward_rays".into());
    }
    if d.free_path != c.forward_segments {
        return bad("draws.free_path", d.free_path, "counters.forward_segments (one free path per segment)".into());
    }
    if trials.checked_mul(est.camera_rays).is_none_or(|n| c.sphere_placements < n) {
        return bad("sphere_placements", c.sphere_placements, "at least trials × estimator.camera_rays".into());
    }
    if d.sub_step != c.sphere_placements {
        return bad("draws.sub_step", d.sub_step, "counters.sphere_placements (one sub-step per sphere)".into());
    }
    if c.hits > 0 && c.candidate_tests == 0 {
        return bad("candidate_tests", c.candidate_tests, "at least 1 when counters.hits > 0".into());
    }
    Ok(())
}

/// `counters.nonzero_trials` of a shard against its other counters, its
/// sums and its scene: at most the trials and the hits (a trial with L > 0
/// has a hit); 0 exactly when the sums are 0; at medium.albedo > 0 (every
/// hit adds light) 0 exactly when there are no hits, at albedo 0 always 0.
fn check_nonzero_trials(c: &Counters, sums: &PowerSums, tracer: &Tracer) -> Result<(), String> {
    let k = c.nonzero_trials;
    let bad = |want: String| Err(format!("counters.nonzero_trials = {k}: must be {want}"));
    if k > c.trials {
        return bad(format!("at most counters.trials = {}", c.trials));
    }
    if k > c.hits {
        return bad(format!("at most counters.hits = {} (a trial with L > 0 has a hit)", c.hits));
    }
    if (k == 0) != sums.is_zero() {
        return bad(if k == 0 {
            "at least 1 when the sums are not 0 (some L > 0)".into()
        } else {
            "0 when the sums are 0 (every L = 0)".into()
        });
    }
    let albedo = tracer.scene().medium.albedo;
    if albedo > 0.0 && (k == 0) != (c.hits == 0) {
        return bad(format!(
            "at least 1 when counters.hits = {} > 0 (at medium.albedo = {albedo} every hit adds light)",
            c.hits
        ));
    }
    if albedo == 0.0 && k != 0 {
        return bad("0 at medium.albedo = 0 (no light is scattered: L = 0 in every trial)".into());
    }
    Ok(())
}

/// Merges runs of the same scene and seed over disjoint trial ranges.
pub fn merge(runs: &[Run]) -> Result<Run, String> {
    let first = runs.first().ok_or("nothing to merge")?;
    let mut ranges = Vec::new();
    let mut counters = Counters::default();
    let mut sums = PowerSums::default();
    for (i, r) in runs.iter().enumerate() {
        if r.scene != first.scene {
            return Err(format!("shard {} traced a different scene than shard 1", i + 1));
        }
        if r.seed != first.seed {
            return Err(format!("shard {} has seed {}, shard 1 has seed {}", i + 1, r.seed, first.seed));
        }
        ranges.extend(r.ranges.iter().cloned());
        counters = counters.checked_sum(&r.counters).ok_or(format!(
            "shard {}: the merged counters would overflow a u64 (too many trials for one run)",
            i + 1
        ))?;
        sums = sums.merge(&r.sums);
    }
    ranges.sort_by_key(|r| r.start);
    for w in ranges.windows(2) {
        if w[1].start < w[0].end {
            return Err(format!("trial ranges {:?} and {:?} overlap", w[0], w[1]));
        }
    }
    // Adjacent ranges are joined: a split of 0..M merges to [0..M].
    let mut joined: Vec<Range<u64>> = Vec::new();
    for r in ranges {
        match joined.last_mut() {
            Some(last) if last.end == r.start => last.end = r.end,
            _ => joined.push(r),
        }
    }
    Ok(Run { scene: first.scene.clone(), seed: first.seed, ranges: joined, counters, sums })
}
