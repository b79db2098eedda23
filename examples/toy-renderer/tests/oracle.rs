//! The toy renderer against the oracle, as a renderer's own test would be:
//! the correct estimator passes, each planted bug fails, with
//! `ITERATIONS` iterations and resolution targets these iterations must
//! meet (so a pass is not a pass by noise). Every verdict is printed
//! (`cargo test --release -p toy-renderer -- --nocapture`).

use mcrt_noise::{check, predict, CheckOptions, Phase, Prediction, Samples, Scene, Verdict};
use toy_renderer::{render, Bug, ToyScene};

/// Iterations per check (documented in docs/library.md).
const ITERATIONS: u64 = 200_000;
/// Relative errors of the mean and of Var L these iterations must be able to detect.
const TARGETS: (f64, f64) = (0.05, 0.10);

/// The documented scene (`ToyScene::example`: g = 0.5, q = 0.5, N_B = 4, which the bugs need).
fn toy_scene() -> ToyScene {
    ToyScene::example()
}

/// The same scene for the oracle.
fn oracle_scene(t: &ToyScene) -> Scene {
    Scene::builder()
        .medium(t.sigma_ext, t.albedo)
        .phase(Phase::HenyeyGreenstein { g: t.g })
        .point_light(t.light_position, t.flux)
        .camera(t.camera_origin, t.camera_direction)
        .estimator(t.radius, t.q, t.forward_rays.into(), t.camera_rays.into())
        .build()
        .unwrap()
}

fn verdict(prediction: &Prediction, bug: Bug) -> Verdict {
    let mut samples = Samples::new();
    samples.extend(render(&toy_scene(), bug, ITERATIONS, 42)).unwrap();
    let options = CheckOptions::default().with_targets(TARGETS.0, TARGETS.1).unwrap();
    let v = check(prediction, &samples, &options);
    println!("--- {bug:?}\n{v}\n");
    v
}

#[test]
fn the_correct_renderer_passes_and_each_planted_bug_fails() {
    let prediction = predict(&oracle_scene(&toy_scene())).unwrap();
    verdict(&prediction, Bug::None).assert_pass();
    for bug in Bug::ALL.into_iter().filter(|b| *b != Bug::None) {
        let v = verdict(&prediction, bug);
        assert!(!v.pass, "{bug:?} passed:\n{v}");
        // Caught by a z-test: a failure, not a verdict that could not tell.
        assert_eq!(v.status, mcrt_noise::check::Status::Fail, "{bug:?}:\n{v}");
        assert!(v.failures.iter().all(|r| r.contains("beyond the limit")), "{bug:?}:\n{v}");
    }
}
