//! Runs over trial ranges, in parallel, and shards that merge exactly.
//!
//! Trial i of a run seeded with S always uses the stream (S, i) and its L
//! enters exact sums (`moments`), so a run over a range gives bit-identical
//! numbers for any thread count, and shards over a split of the range merge
//! into exactly the single run's numbers.

use crate::estimator::{Counters, HitMethod, Tracer};
use crate::moments::{PowerSums, Summary};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::ops::Range;

/// Trials per work item: progress is reported and sums are merged per chunk.
const CHUNK: u64 = 4096;

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

impl Run {
    /// Mean and variance of L with standard errors (`None` below 4 trials).
    pub fn summary(&self) -> Option<Summary> {
        self.sums.summary()
    }
}

/// Traces trials `range` of the run seeded with `seed`, in parallel on the
/// current rayon pool; `progress` is called with the number of trials done
/// after each chunk (from any thread).
pub fn trace(tracer: &Tracer, seed: u64, range: Range<u64>, method: HitMethod, progress: &(dyn Fn(u64) + Sync)) -> Run {
    let chunks: Vec<Range<u64>> =
        (range.start..range.end).step_by(CHUNK as usize).map(|a| a..(a + CHUNK).min(range.end)).collect();
    let (counters, sums) = chunks
        .into_par_iter()
        .map(|chunk| {
            let n = chunk.end - chunk.start;
            let mut counters = Counters::default();
            let mut sums = PowerSums::default();
            for i in chunk {
                let (l, c) = tracer.trial(seed, i, method);
                sums.push(l);
                counters.add(&c);
            }
            progress(n);
            (counters, sums)
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

const SHARD_FORMAT: &str = "mcrt-noise trace shard 1";

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

    pub fn from_shard(shard: &Shard) -> Result<Run, String> {
        if shard.format != SHARD_FORMAT {
            return Err(format!("format: expected \"{SHARD_FORMAT}\", found \"{}\"", shard.format));
        }
        let ranges: Vec<Range<u64>> = shard.ranges.iter().map(|r| r[0]..r[1]).collect();
        if ranges.iter().any(|r| r.start >= r.end) {
            return Err("ranges: every range must be non-empty (start < end)".into());
        }
        let count: u64 = ranges.iter().map(|r| r.end - r.start).sum();
        if count != shard.counters.trials {
            return Err(format!("ranges cover {count} trials but counters.trials = {}", shard.counters.trials));
        }
        let sums = PowerSums::from_hex(count, &shard.sums)?;
        Ok(Run { scene: shard.scene.clone(), seed: shard.seed, ranges, counters: shard.counters, sums })
    }
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
        counters.add(&r.counters);
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
