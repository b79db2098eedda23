//! A direct measurement of the correlation the model is built on:
//! ⟨𝒞(s)𝒞(s+t)⟩, the expectation over forward rays of the product of one
//! ray's contributions to a sphere at s and one at s + t (paper §4.3).
//!
//! Only forward rays are traced. A segment hits the spheres whose centres
//! lie in its hit interval [lo, hi] on the camera line (`hits`); if s is in
//! it, the product is 𝒞² for every s + t in it. Each ray therefore adds, to
//! the bin [a, b) of t, 𝒞²·|[lo − s, hi − s] ∩ [a, b)|/(b − a): the exact
//! average of its product over the bin. Sums over segments of a ray are
//! kept (a ray with several segments can hit with more than one), so the
//! estimate is of the real product, whatever the model assumes.

use crate::estimator::{Counters, Tracer};
use crate::hits::hit_interval;
use crate::moments::WithError;
use crate::rng::Stream;
use rayon::prelude::*;
use std::ops::Range;

const CHUNK: u64 = 1 << 14;

/// Bin averages of ⟨𝒞(s)𝒞(s+t)⟩ over the t-bins between consecutive
/// `edges` (increasing, ≥ 0), from forward rays `rays` of the run seeded
/// with `seed`, with standard errors. Deterministic for any thread count.
pub fn pair_correlation(tracer: &Tracer, seed: u64, rays: Range<u64>, s: f64, edges: &[f64]) -> Vec<WithError> {
    let bins = edges.len().saturating_sub(1);
    let chunks: Vec<Range<u64>> =
        (rays.start..rays.end).step_by(CHUNK as usize).map(|a| a..(a + CHUNK).min(rays.end)).collect();
    // Per chunk, sequential sums of x and x² per bin; chunks are added in
    // order afterwards, so the result does not depend on the threads.
    let partial: Vec<Vec<(f64, f64)>> = chunks
        .into_par_iter()
        .map(|chunk| {
            let mut acc = vec![(0.0, 0.0); bins];
            let mut x = vec![0.0; bins];
            let mut counters = Counters::default();
            // (lo − s, hi − s, 𝒞) of a ray's segments, reused across rays.
            let mut hits: Vec<(f64, f64, f64)> = Vec::new();
            for i in chunk {
                x.iter_mut().for_each(|v| *v = 0.0);
                hits.clear();
                let mut stream = Stream::new(seed, i);
                let mut c_at_s = 0.0;
                tracer.walk_forward_ray(&mut stream, &mut counters, &mut |seg, _| {
                    if let Some((lo, hi)) = hit_interval(tracer.line(), seg) {
                        let c = tracer.contribution(seg.dir);
                        if (lo..=hi).contains(&s) {
                            c_at_s += c;
                        }
                        hits.push((lo - s, hi - s, c));
                    }
                });
                if c_at_s == 0.0 {
                    continue;
                }
                for (lo, hi, c) in &hits {
                    for (k, w) in edges.windows(2).enumerate() {
                        let covered = (hi.min(w[1]) - lo.max(w[0])).max(0.0);
                        x[k] += c_at_s * c * covered / (w[1] - w[0]);
                    }
                }
                for (a, v) in acc.iter_mut().zip(&x) {
                    a.0 += v;
                    a.1 += v * v;
                }
            }
            acc
        })
        .collect();
    let n = (rays.end - rays.start) as f64;
    (0..bins)
        .map(|k| {
            let (s1, s2) = partial.iter().fold((0.0, 0.0), |(a, b), p| (a + p[k].0, b + p[k].1));
            let mean = s1 / n;
            let var = ((s2 - n * mean * mean) / (n - 1.0)).max(0.0);
            WithError { value: mean, se: (var / n).sqrt() }
        })
        .collect()
}
