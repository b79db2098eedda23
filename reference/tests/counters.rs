//! The tracer simulates only what the scene calls for: the counters show
//! zero draws and evaluations for every effect the scene does not have.

mod common;

use mcrt_reference::{trace, Counters, HitMethod, Tracer};

fn counters(scene: &mcrt_scene::Scene, trials: u64) -> Counters {
    let tracer = Tracer::new(scene).unwrap();
    trace(&tracer, 9, 0..trials, HitMethod::Sorted, &|_| {}).counters
}

#[test]
fn order_zero_draws_no_phase_sample_and_no_roulette() {
    let c = counters(&common::scene("point-hg-forward", &[]), 2_000);
    assert_eq!((c.draws.phase, c.draws.roulette), (0, 0));
    // One segment per forward ray, one free path each.
    assert_eq!(c.forward_segments, c.forward_rays);
    assert_eq!(c.draws.free_path, c.forward_rays);
    assert_eq!(c.forward_rays, 2_000 * 200);
}

#[test]
fn albedo_one_draws_no_roulette_numbers() {
    let c = counters(&common::scene("point-isotropic-order1", &[("albedo = 0.8", "albedo = 1.0")]), 2_000);
    assert_eq!(c.draws.roulette, 0);
    // Every first interaction scatters: two segments per ray.
    assert_eq!(c.forward_segments, 2 * c.forward_rays);
    let with_roulette = counters(&common::scene("point-isotropic-order1", &[]), 2_000);
    assert_eq!(with_roulette.draws.roulette, with_roulette.forward_rays);
}

#[test]
fn isotropic_medium_never_evaluates_henyey_greenstein() {
    let c = counters(&common::scene("point-isotropic-order1", &[("radius = 0.01", "radius = 0.1")]), 2_000);
    assert!(c.hits > 0);
    assert_eq!(c.hg_evaluations, 0);
    let hg = counters(&common::scene("point-hg-forward", &[("radius = 0.01", "radius = 0.1")]), 2_000);
    assert!(hg.hg_evaluations > 0);
}

#[test]
fn the_camera_ray_ends_at_its_first_extinction() {
    // q = 1: one sphere per camera ray and no extinction draws.
    let c = counters(&common::scene("point-isotropic", &[("q = 0.5", "q = 1.0")]), 1_000);
    assert_eq!(c.sphere_placements, 1_000 * 8);
    assert_eq!(c.draws.extinction, 0);
    assert_eq!(c.draws.sub_step, c.sphere_placements);
    // q < 1: one extinction draw per sphere, the last of each camera ray ending it.
    let c = counters(&common::scene("point-isotropic", &[]), 1_000);
    assert_eq!(c.draws.extinction, c.sphere_placements);
}

#[test]
fn single_light_draws_no_light_choice_and_a_beam_no_direction() {
    let c = counters(&common::scene("beam-isotropic", &[]), 1_000);
    assert_eq!((c.draws.light_choice, c.draws.emission_direction), (0, 0));
    assert_eq!(c.draws.emission_position, 2 * c.forward_rays);
    let p = counters(&common::scene("point-isotropic", &[]), 1_000);
    assert_eq!((p.draws.light_choice, p.draws.emission_position), (0, 0));
    assert_eq!(p.draws.emission_direction, 2 * p.forward_rays);
}

#[test]
fn endless_paths_are_refused_with_the_fields_named() {
    let scene = common::scene(
        "point-isotropic",
        &[("albedo = 0.8", "albedo = 1.0"), ("scattering_orders = 0", "scattering_orders = \"all\"")],
    );
    let err = Tracer::new(&scene).unwrap_err().to_string();
    assert!(err.contains("effects.scattering_orders") && err.contains("medium.albedo"), "{err}");
}
