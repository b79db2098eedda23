//! Same seed, same numbers: for any thread count, any split of the trial
//! range into shards, and either way of finding hits.

mod common;

use mcrt_reference::{merge, trace, HitMethod, Run, Tracer};

fn run_on(threads: usize, tracer: &Tracer, seed: u64, range: std::ops::Range<u64>) -> Run {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| trace(tracer, seed, range, HitMethod::Sorted, &|_| {}))
}

#[test]
fn one_and_two_threads_give_bit_identical_results() {
    let tracer = Tracer::new(&common::scene("point-hg-forward", &[("radius = 0.01", "radius = 0.05")])).unwrap();
    let one = run_on(1, &tracer, 11, 0..20_000);
    let two = run_on(2, &tracer, 11, 0..20_000);
    assert_eq!(one, two);
    let (a, b) = (one.summary().unwrap(), two.summary().unwrap());
    assert_eq!(a.mean.value.to_bits(), b.mean.value.to_bits());
    assert_eq!(a.variance.value.to_bits(), b.variance.value.to_bits());
}

#[test]
fn shards_through_their_files_merge_into_the_single_run() {
    let tracer = Tracer::new(&common::scene("beam-isotropic", &[("radius = 0.01", "radius = 0.05")])).unwrap();
    let whole = run_on(2, &tracer, 5, 0..12_345);
    // An uneven split, traced out of order on different thread counts.
    let parts = [(1, 7_000..12_345), (2, 0..1), (1, 1..4_097), (2, 4_097..7_000)];
    let shards: Vec<Run> = parts
        .iter()
        .map(|(threads, range)| {
            let run = run_on(*threads, &tracer, 5, range.clone());
            let text = serde_json::to_string(&run.to_shard()).unwrap();
            Run::from_shard(&serde_json::from_str(&text).unwrap()).unwrap()
        })
        .collect();
    let merged = merge(&shards).unwrap();
    assert_eq!(merged, whole);
    assert_eq!(merged.summary(), whole.summary());
}

#[test]
fn overlapping_or_foreign_shards_are_refused() {
    let tracer = Tracer::new(&common::scene("point-isotropic", &[])).unwrap();
    let a = run_on(1, &tracer, 1, 0..10);
    let b = run_on(1, &tracer, 1, 5..15);
    assert!(merge(&[a.clone(), b]).unwrap_err().contains("overlap"));
    let other_seed = run_on(1, &tracer, 2, 10..20);
    assert!(merge(&[a.clone(), other_seed]).unwrap_err().contains("seed"));
    let other = Tracer::new(&common::scene("point-isotropic", &[("q = 0.5", "q = 0.25")])).unwrap();
    let c = run_on(1, &other, 1, 10..20);
    assert!(merge(&[a, c]).unwrap_err().contains("different scene"));
}

/// The sorted search and the brute-force pair test find the same hits, so
/// every trial's L is the same double, on 10⁴ trials of each kind of scene
/// (point and beam, orders 0 and 1, isotropic and HG; large spheres and
/// many of them, so that hits are frequent).
#[test]
fn sorted_search_and_brute_force_give_identical_luminance() {
    let scenes = [
        common::scene("point-isotropic", &[("radius = 0.01", "radius = 0.1")]),
        common::scene("point-hg-forward", &[("radius = 0.01", "radius = 0.1")]),
        common::scene("point-isotropic-order1", &[("radius = 0.01", "radius = 0.1")]),
        common::scene("beam-isotropic", &[("radius = 0.01", "radius = 0.1"), ("q = 0.5", "q = 0.1")]),
    ];
    for scene in &scenes {
        let tracer = Tracer::new(scene).unwrap();
        let mut hits = 0;
        for i in 0..10_000 {
            let (fast, c_fast) = tracer.trial(3, i, HitMethod::Sorted);
            let (brute, c_brute) = tracer.trial(3, i, HitMethod::BruteForce);
            assert_eq!(fast.to_bits(), brute.to_bits(), "trial {i}: {fast} vs {brute}");
            assert_eq!(c_fast.hits, c_brute.hits);
            hits += c_fast.hits;
        }
        assert!(hits > 10_000, "too few hits ({hits}) to mean anything");
    }
}
