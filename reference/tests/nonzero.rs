//! Trials with L > 0: counted, kept through shards and `merge`, and the
//! rule that a run resolves its mean and variance only from
//! `MIN_NONZERO_TRIALS` of them on (the probe: 1 hit in 300 trials of
//! `point-hg-forward` gave Var L ± 1 % and `compare` said DISAGREE, z = −160).

mod common;

use mcrt_reference::moments::PowerSums;
use mcrt_reference::{merge, trace, HitMethod, Run, Shard, Tracer, MIN_NONZERO_TRIALS};

fn run(tracer: &Tracer, seed: u64, range: std::ops::Range<u64>) -> Run {
    trace(tracer, seed, range, HitMethod::Sorted, &|_| {})
}

/// The count against the trials' own L, trial by trial, on scenes with and
/// without scattering; kept by a shard split and `merge`.
#[test]
fn nonzero_trials_counts_the_trials_whose_l_is_positive() {
    for scene in [
        common::scene("point-hg-forward", &[("radius = 0.01", "radius = 0.05")]),
        common::scene("point-isotropic-order1", &[("radius = 0.01", "radius = 0.05")]),
        common::scene("beam-isotropic", &[]),
    ] {
        let tracer = Tracer::new(&scene).unwrap();
        let direct = (0..3000).filter(|&i| tracer.trial(7, i, HitMethod::Sorted).0 > 0.0).count() as u64;
        let whole = run(&tracer, 7, 0..3000);
        assert_eq!(whole.counters.nonzero_trials, direct);
        assert!(direct > 0 && direct < 3000 && direct <= whole.counters.hits, "{direct} of 3000");
        let parts = [run(&tracer, 7, 0..1234), run(&tracer, 7, 1234..3000)];
        assert_eq!(parts[0].counters.nonzero_trials + parts[1].counters.nonzero_trials, direct);
        let through_files: Vec<Run> = parts
            .iter()
            .map(|r| Run::from_shard(&serde_json::from_str(&serde_json::to_string(&r.to_shard()).unwrap()).unwrap()))
            .collect::<Result<_, _>>()
            .unwrap();
        assert_eq!(merge(&through_files).unwrap(), whole);
    }
}

/// The probe's seeds: 300 trials of `point-hg-forward` never have 100 trials
/// with hits, so none is resolved, and the reason states the count.
#[test]
fn the_probes_barely_hit_runs_are_not_resolved() {
    let tracer = Tracer::new(&common::scene("point-hg-forward", &[])).unwrap();
    for seed in 1..=40 {
        let r = run(&tracer, seed, 0..300);
        let k = r.counters.nonzero_trials;
        assert!(k < MIN_NONZERO_TRIALS, "seed {seed}: {k}");
        let e = r.estimates();
        let why = e.variance.unwrap_err();
        let want =
            if k == 0 { "no hits in 300 trials".to_string() } else { format!("only {k} of 300 trials had hits") };
        assert!(why.starts_with(&want) && why.contains("not resolved"), "seed {seed}: {why}");
        assert_eq!(e.mean.unwrap_err(), why);
    }
}

/// 99 trials with hits are not resolved, 100 are: the range ends just
/// before and just after the 100th trial with L > 0.
#[test]
fn the_threshold_is_exactly_min_nonzero_trials() {
    assert_eq!(MIN_NONZERO_TRIALS, 100);
    let tracer = Tracer::new(&common::scene("point-isotropic", &[("radius = 0.01", "radius = 0.05")])).unwrap();
    let mut nonzero = 0;
    let hundredth = (0..)
        .find(|&i| {
            nonzero += u64::from(tracer.trial(3, i, HitMethod::Sorted).0 > 0.0);
            nonzero == MIN_NONZERO_TRIALS
        })
        .unwrap();
    let below = run(&tracer, 3, 0..hundredth);
    assert_eq!(below.counters.nonzero_trials, 99);
    let why = below.estimates().mean.unwrap_err();
    assert!(
        why.starts_with(&format!("only 99 of {hundredth} trials had hits")) && why.contains("at least 100"),
        "{why}"
    );
    let at = run(&tracer, 3, 0..hundredth + 1);
    assert_eq!(at.counters.nonzero_trials, 100);
    let e = at.estimates();
    assert!(e.mean.is_ok() && e.variance.is_ok(), "{e:?}");
    // The raw summary is unaffected by the rule (the statistical tests use it).
    assert!(below.summary().is_some());
}

/// At albedo 0 hits add no light: L = 0 in every trial, said so.
#[test]
fn hits_that_add_no_light_are_not_resolved_either() {
    let tracer = Tracer::new(&common::scene(
        "point-isotropic",
        &[("radius = 0.01", "radius = 0.2"), ("albedo = 0.8", "albedo = 0.0")],
    ))
    .unwrap();
    let r = run(&tracer, 1, 0..500);
    assert!(r.counters.hits > 0);
    assert_eq!(r.counters.nonzero_trials, 0);
    let why = r.estimates().mean.unwrap_err();
    assert!(why.starts_with("L = 0 in all 500 trials") && why.contains("albedo = 0"), "{why}");
    assert!(Run::from_shard(&r.to_shard()).is_ok());
}

/// A shard's sums must be those of non-negative values, `nonzero_trials` of
/// them > 0: checked exactly, the sum or counter named.
#[test]
fn shards_with_sums_no_non_negative_values_have_are_refused() {
    let tracer = Tracer::new(&common::scene("point-isotropic", &[("radius = 0.01", "radius = 0.05")])).unwrap();
    let good = run(&tracer, 2, 0..2000).to_shard();
    assert!(Run::from_shard(&good).is_ok());
    let k = good.counters.nonzero_trials;
    let hex = |sums: [f64; 4]| PowerSums::from_f64_sums(2000, sums).unwrap().to_hex();
    let check = |edit: &dyn Fn(&mut Shard), needle: &str| common::assert_shard_refused(&good, edit, needle);
    check(&|s| s.sums[0] = format!("-{}", s.sums[0]), "sums[0] (Σ L)");
    check(&|s| s.sums[2] = format!("-{}", s.sums[2]), "sums[2] (Σ L³)");
    check(&|s| s.sums = hex([1.0, 2.0, 1.0, 16.0]), "(Σ L²)² <= Σ L · Σ L³");
    check(&|s| s.sums = hex([1.0, 1.0, 2.0, 1.0]), "(Σ L³)² <= Σ L² · Σ L⁴");
    check(&|s| s.sums = hex([0.0, 0.0, 0.0, 1.0]), "all 0 or all > 0");
    // k values > 0 bound the sums too, (Σ L)² ≤ k Σ L²: k + 1 values of 1 are more than k.
    let kf = k as f64;
    assert!(k < 1999, "{k}");
    check(&|s| s.sums = hex([kf + 1.0; 4]), "(Σ L)² <= k Σ L²");
    // k values of 1: accepted.
    let mut equal = good.clone();
    equal.sums = hex([kf, kf, kf, kf]);
    assert!(Run::from_shard(&equal).is_ok());
}

/// `counters.nonzero_trials` against the trials, the hits and the sums; a
/// shard of format 1 (which had no such counter) is refused by its format.
#[test]
fn shards_with_a_wrong_nonzero_count_are_refused() {
    let tracer = Tracer::new(&common::scene("point-isotropic", &[("radius = 0.01", "radius = 0.05")])).unwrap();
    let good = run(&tracer, 2, 0..2000).to_shard();
    assert!(Run::from_shard(&good).is_ok());
    let check = |edit: &dyn Fn(&mut Shard), needle: &str| common::assert_shard_refused(&good, edit, needle);
    check(&|s| s.counters.nonzero_trials = s.counters.trials + 1, "at most counters.trials");
    check(&|s| s.counters.nonzero_trials = s.counters.hits + 1, "at most counters.hits");
    check(&|s| s.counters.nonzero_trials = 0, "counters.nonzero_trials = 0");
    check(&|s| s.format = "mcrt-noise trace shard 1".into(), "format");
    // Sums of 0 with trials that had L > 0, and the converse.
    let zero = ["0".to_string(), "0".to_string(), "0".to_string(), "0".to_string()];
    let mut zero_sums = good.clone();
    zero_sums.sums = zero.clone();
    let err = Run::from_shard(&zero_sums).unwrap_err();
    assert!(err.contains("counters.nonzero_trials") && err.contains("when the sums are 0"), "{err}");
}
