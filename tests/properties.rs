//! Property tests (issue 11): random scenes, valid and not, through the
//! scene validation and the oracle (both models); f64 against 128 bits; a
//! mutation fuzzer over the bundled scene files. Nothing may panic or hang;
//! every number is finite with a bar, or there is a refusal naming its field.
//!
//! Case counts: CI runs 2000 builder cases, 1000 oracle cases, 12 f64/128-bit
//! draws (at least 10 compared; ~8 s each at 128 bits, one of the first six
//! took 30 s) and 10 000 mutated files; `PROPTEST_CASES` overrides them all. The
//! long run (10⁵ cases each, ~3 h):
//! `cargo test --release --test properties -- --ignored`.

use mcrt_noise::oracle::{run, run_within, Precision, Report};
use mcrt_noise::quad::Budget;
use mcrt_noise::scene::{Phase, Scene, SceneError};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestRunner};

/// Cases of a test at its CI default, unless `PROPTEST_CASES` is set.
fn config(default_cases: u32) -> Config {
    let cases = std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(default_cases);
    // Seeded, so that CI draws the same scenes every run (with proptest's
    // random default, `f64_and_128_bits_agree_on_random_scenes` compared 9
    // of 12 scenes on one run of an unchanged tree and failed, passing on
    // the runs before); PROPTEST_RNG_SEED draws others.
    let rng_seed = match std::env::var("PROPTEST_RNG_SEED") {
        Ok(_) => Config::default().rng_seed,
        Err(_) => RngSeed::Fixed(PROPERTIES_SEED),
    };
    Config { cases, failure_persistence: None, rng_seed, ..Config::default() }
}

/// The seed of every property here unless PROPTEST_RNG_SEED is set.
const PROPERTIES_SEED: u64 = 20261206;

/// The ignored long run: every property at 10⁵ cases.
#[test]
#[ignore = "10⁵ cases of each property, ~3 h: cargo test --release --test properties -- --ignored"]
fn long_run() {
    const LONG: u32 = 100_000;
    builder_validates_any_values(LONG);
    oracle_on_random_valid_scenes(LONG);
    #[cfg(feature = "mpfr")]
    f64_and_128_bits_agree(LONG);
    mutated_scene_files(LONG);
}

/// Any f64 a user could write, weighted towards the troublesome ones.
fn any_number() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -10.0..10.0f64,
        1 => Just(0.0),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(5e-324),
        1 => Just(1e300),
        1 => Just(-1e-300),
        1 => proptest::num::f64::ANY,
    ]
}

fn any_vec3() -> impl Strategy<Value = [f64; 3]> {
    [any_number(), any_number(), any_number()]
}

fn any_count() -> impl Strategy<Value = u64> {
    prop_oneof![3 => 0u64..300, 1 => Just(u64::MAX), 1 => Just(1u64 << 40), 1 => any::<u64>()]
}

/// A scene from arbitrary values through the builder: valid or refused with
/// every bad field named (never a panic).
#[test]
fn the_builder_validates_any_values() {
    builder_validates_any_values(2000);
}

fn builder_validates_any_values(cases: u32) {
    let strategy = (
        (any_number(), any_number(), any_number()),
        (any_vec3(), any_number()),
        (any_vec3(), any_vec3()),
        (any_number(), any_number(), any_count(), any_count()),
    );
    TestRunner::new(config(cases))
        .run(&strategy, |((sigma, albedo, g), (pos, flux), (origin, dir), (r, q, nf, nb))| {
            let built = Scene::builder()
                .medium(sigma, albedo)
                .phase(Phase::HenyeyGreenstein { g })
                .point_light(pos, flux)
                .camera(origin, dir)
                .estimator(r, q, nf, nb)
                .build();
            match built {
                Ok(scene) => {
                    // A valid scene round-trips through its normalised TOML.
                    let again = Scene::from_toml_str(&scene.to_toml_string()).expect("a valid scene's TOML is valid");
                    prop_assert_eq!(again.to_toml_string(), scene.to_toml_string());
                }
                Err(SceneError::Invalid(errors)) => {
                    prop_assert!(!errors.is_empty());
                    for e in errors {
                        prop_assert!(!e.field.is_empty() && !e.allowed.is_empty(), "{e}");
                    }
                }
                Err(SceneError::Parse(msg)) => prop_assert!(false, "the builder gave a parse error: {msg}"),
            }
            Ok(())
        })
        .unwrap();
}

/// A valid scene the oracle can be asked about: lengths in optical depths
/// up to 20, every estimator parameter in its range, point lights or beams,
/// isotropic or Henyey–Greenstein |g| ≤ 0.95, uncollided light.
fn valid_scene() -> impl Strategy<Value = Scene> {
    let light = prop_oneof![
        ([-5.0..5.0f64, -5.0..5.0f64, -5.0..5.0f64], 0.01..100.0f64).prop_map(|(p, f)| (true, p, [0.0; 3], 0.0, f)),
        // A beam whose axis crosses the camera ray (the z axis) at z = t,
        // from a distance s back along its direction: a beam that misses
        // the ray has L = 0 exactly, which the oracle refuses by design.
        ([-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64], 0.2..5.0f64, 0.3..3.0f64, 0.05..2.0f64, 0.01..100.0f64)
            .prop_filter("a direction", |(d, ..)| d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > 1e-2)
            .prop_map(|(d, t, s, r, f)| {
                let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                let u = [d[0] / n, d[1] / n, d[2] / n];
                ([-s * u[0], -s * u[1], t - s * u[2]], u, r, f)
            })
            .prop_map(|(c, d, r, f)| (false, c, d, r, f)),
    ];
    (
        (0.2..4.0f64, 0.05..1.0f64, prop_oneof![Just(None), (-0.95..0.95f64).prop_map(Some)]),
        proptest::collection::vec(light, 1..3),
        (1e-3..0.5f64, 0.05..1.0f64, 1u64..2000, 1u64..64),
    )
        .prop_filter_map("an invalid draw (zero direction)", |((sigma, albedo, g), lights, (r, q, nf, nb))| {
            let mut b =
                Scene::builder().medium(sigma, albedo).camera([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]).estimator(r, q, nf, nb);
            if let Some(g) = g {
                b = b.phase(Phase::HenyeyGreenstein { g });
            }
            for (point, p, d, radius, flux) in lights {
                b = if point { b.point_light(p, flux) } else { b.beam(p, d, radius, flux) };
            }
            b.build().ok()
        })
}

/// Every number of the prediction finite, bars included; mean > 0, Var ≥ 0.
fn check_report(report: &Report) -> Result<(), TestCaseError> {
    let p = &report.prediction;
    for (name, v) in [("mean", &p.mean), ("Var L", &p.variance), ("relative noise", &p.relative_noise)] {
        prop_assert!(v.value.is_finite() && v.error.is_finite() && v.error >= 0.0, "{name}: {} ± {}", v.value, v.error);
    }
    prop_assert!(p.mean.value > 0.0, "mean {}", p.mean.value);
    prop_assert!(p.variance.value + p.variance.error >= 0.0, "Var L {}", p.variance.value);
    Ok(())
}

fn with_counts(scene: &Scene, nf: u64, nb: u64) -> Scene {
    let mut s = scene.clone();
    s.estimator.forward_rays = nf;
    s.estimator.camera_rays = nb;
    s
}

/// The oracle on random valid scenes: a prediction with finite bars or a
/// NOT CONVERGED within the budget; the relative noise does not grow with
/// N_F or N_B.
#[test]
fn the_oracle_on_random_valid_scenes() {
    oracle_on_random_valid_scenes(1000);
}

fn oracle_on_random_valid_scenes(cases: u32) {
    let (ok, refused) = (std::cell::Cell::new(0u32), std::cell::Cell::new(0u32));
    TestRunner::new(config(cases))
        .run(&valid_scene(), |scene| {
            let budget = Budget::new(50_000_000);
            let report = match run_within(&scene, Precision::F64, Some(1e-6), &budget) {
                Ok(r) => r,
                Err(e) => {
                    // A refusal must say what: never an empty or NaN message.
                    refused.set(refused.get() + 1);
                    let msg = e.to_string();
                    if std::env::var("SHOW_REFUSALS").is_ok() {
                        eprintln!("REFUSAL {}\n{}", msg.chars().take(160).collect::<String>(), scene.to_toml_string());
                    }
                    prop_assert!(!msg.is_empty() && !msg.contains("NaN ±"), "{msg}");
                    return Ok(());
                }
            };
            check_report(&report)?;
            ok.set(ok.get() + 1);
            let (nf, nb) = (scene.estimator.forward_rays, scene.estimator.camera_rays);
            let base = &report.prediction.relative_noise;
            for (more_f, more_b) in [(2 * nf, nb), (nf, 2 * nb)] {
                let Ok(more) = run(&with_counts(&scene, more_f, more_b), Precision::F64, Some(1e-6)) else {
                    continue;
                };
                let m = &more.prediction.relative_noise;
                prop_assert!(
                    m.value <= base.value + base.error + m.error,
                    "relative noise grew from {} ± {:e} (N_F {nf}, N_B {nb}) to {} ± {:e} (N_F {more_f}, N_B {more_b})",
                    base.value,
                    base.error,
                    m.value,
                    m.error
                );
            }
            Ok(())
        })
        .unwrap();
    // Not a vacuous pass: these scenes are all computable, so the oracle
    // must answer nearly all of them (proptest also runs rejected draws'
    // replacements, so count what was run).
    eprintln!("oracle on random scenes: {} predictions, {} refusals", ok.get(), refused.get());
    assert!(
        ok.get() * 50 >= 49 * (ok.get() + refused.get()),
        "{} refusals of {}",
        refused.get(),
        ok.get() + refused.get()
    );
}

/// f64 and 128 bits agree within their bars on at least 10 random scenes.
#[test]
#[cfg(feature = "mpfr")]
fn f64_and_128_bits_agree_on_random_scenes() {
    f64_and_128_bits_agree(12);
}

#[cfg(feature = "mpfr")]
fn f64_and_128_bits_agree(cases: u32) {
    let compared = std::cell::Cell::new(0u32);
    TestRunner::new(config(cases))
        .run(&valid_scene(), |scene| {
            // 128 bits costs ~50× f64 per call; to 10⁻⁹ (the f64 run's bars
            // are ~10⁻¹⁰ relative) a scene takes seconds; a budget of 10⁷
            // calls ends a slow one loudly rather than stalling the test;
            // 12 draws must give at least 10 comparisons.
            let t0 = std::time::Instant::now();
            let big = run_within(&scene, Precision::Bits(128), Some(1e-9), &Budget::new(10_000_000));
            if std::env::var("SHOW_REFUSALS").is_ok() {
                let what = big.as_ref().map_or_else(|e| e.to_string(), |_| "ok".into());
                eprintln!("128 bits: {:.1} s, {what}", t0.elapsed().as_secs_f64());
            }
            let (Ok(a), Ok(b)) = (run(&scene, Precision::F64, None), big) else {
                return Ok(());
            };
            compared.set(compared.get() + 1);
            for (name, x, y) in [
                ("mean", &a.prediction.mean, &b.prediction.mean),
                ("Var L", &a.prediction.variance, &b.prediction.variance),
            ] {
                prop_assert!(
                    (x.value - y.value).abs() <= x.error + y.error,
                    "{name}: f64 {} ± {:e}, 128 bits {} ± {:e}",
                    x.value,
                    x.error,
                    y.value,
                    y.error
                );
            }
            Ok(())
        })
        .unwrap();
    let drawn = config(cases).cases;
    assert!(compared.get() >= drawn * 5 / 6, "only {} of {drawn} scenes compared", compared.get());
}

/// One mutation of a scene file's text: at the byte level (flip, insert,
/// delete) or the token level (a number replaced by an extreme one, a line
/// duplicated or dropped, an array lengthened).
#[derive(Debug, Clone)]
enum Mutation {
    Flip(usize, u8),
    Insert(usize, u8),
    Delete(usize),
    Number(usize, &'static str),
    DuplicateLine(usize),
    DropLine(usize),
    LongerArray(usize),
}

const EXTREMES: [&str; 14] = [
    "0",
    "-0.0",
    "nan",
    "inf",
    "-inf",
    "5e-324",
    "1e300",
    "-1e300",
    "1e-300",
    "18446744073709551615",
    "9223372036854775808",
    "1.0",
    "1e999",
    "\"text\"",
];

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Mutation::Flip(i, b)),
        (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Mutation::Insert(i, b)),
        any::<usize>().prop_map(Mutation::Delete),
        (any::<usize>(), proptest::sample::select(EXTREMES.as_slice())).prop_map(|(i, n)| Mutation::Number(i, n)),
        any::<usize>().prop_map(Mutation::DuplicateLine),
        any::<usize>().prop_map(Mutation::DropLine),
        any::<usize>().prop_map(Mutation::LongerArray),
    ]
}

fn apply(text: &str, m: &Mutation) -> Vec<u8> {
    let mut bytes = text.as_bytes().to_vec();
    let lines: Vec<&str> = text.lines().collect();
    let n = bytes.len();
    match *m {
        Mutation::Flip(i, b) => bytes[i % n] = b,
        Mutation::Insert(i, b) => bytes.insert(i % (n + 1), b),
        Mutation::Delete(i) => {
            bytes.remove(i % n);
        }
        Mutation::Number(i, with) => {
            // The i-th number-looking token.
            let tokens: Vec<(usize, usize)> = text
                .match_indices(|c: char| c.is_ascii_digit())
                .map(|(start, _)| {
                    let end = text[start..]
                        .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == 'e' || c == '-'))
                        .map_or(text.len(), |e| start + e);
                    (start, end)
                })
                .collect();
            if let Some(&(a, b)) = tokens.get(i % tokens.len().max(1)) {
                bytes = format!("{}{}{}", &text[..a], with, &text[b..]).into_bytes();
            }
        }
        Mutation::DuplicateLine(i) => {
            let mut l = lines.clone();
            l.insert(i % l.len(), lines[i % lines.len()]);
            bytes = l.join("\n").into_bytes();
        }
        Mutation::DropLine(i) => {
            let mut l = lines.clone();
            l.remove(i % l.len());
            bytes = l.join("\n").into_bytes();
        }
        Mutation::LongerArray(i) => {
            let arrays: Vec<usize> = text.match_indices(']').map(|(k, _)| k).collect();
            if let Some(&k) = arrays.get(i % arrays.len().max(1)) {
                bytes = format!("{}, 2.0{}", &text[..k], &text[k..]).into_bytes();
            }
        }
    }
    bytes
}

const BUNDLED: [&str; 5] = [
    include_str!("../scenes/point-isotropic.toml"),
    include_str!("../scenes/point-hg-forward.toml"),
    include_str!("../scenes/point-hg-backward.toml"),
    include_str!("../scenes/beam-isotropic.toml"),
    include_str!("../scenes/point-isotropic-order1.toml"),
];

/// Up to three mutations of a bundled scene: parse and validate never panic;
/// a scene that survives validates again from its normalised TOML, and the
/// reference tracer accepts it or refuses it with a reason.
#[test]
fn mutated_scene_files_never_panic() {
    mutated_scene_files(10000);
}

fn mutated_scene_files(cases: u32) {
    let strategy = (0..BUNDLED.len(), proptest::collection::vec(mutation(), 1..4));
    TestRunner::new(config(cases))
        .run(&strategy, |(which, mutations)| {
            let mut text = BUNDLED[which].to_string();
            for m in &mutations {
                text = String::from_utf8_lossy(&apply(&text, m)).into_owned();
            }
            match Scene::from_toml_str(&text) {
                Ok(scene) => {
                    prop_assert!(Scene::from_toml_str(&scene.to_toml_string()).is_ok());
                    let _ = mcrt_noise::reference::Tracer::new(&scene);
                }
                Err(e) => prop_assert!(!e.to_string().is_empty()),
            }
            Ok(())
        })
        .unwrap();
}
