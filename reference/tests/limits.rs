//! Issue 11: the tracer never panics, hangs or allocates without bound on a
//! valid scene, and its run arithmetic is overflow-safe.

mod common;

use mcrt_reference::moments::PowerSums;
use mcrt_reference::{merge, trace, HitMethod, Run, Shard, Tracer};

fn run(tracer: &Tracer, range: std::ops::Range<u64>) -> Run {
    trace(tracer, 9, range, HitMethod::Sorted, &|_| {})
}

#[test]
fn scenes_beyond_the_tracers_bounds_are_refused_with_the_field_named() {
    let base = common::scene("point-isotropic", &[]);
    type Edit = Box<dyn Fn(&mut mcrt_scene::Scene)>;
    let cases: Vec<(Edit, &str)> = vec![
        (Box::new(|s| s.estimator.camera_rays = 1 << 40), "estimator.camera_rays"),
        (Box::new(|s| s.estimator.q = 1e-12), "estimator.q"),
        (Box::new(|s| s.estimator.forward_rays = 1 << 40), "estimator.forward_rays"),
        (
            Box::new(|s| {
                s.medium.albedo = 1.0;
                s.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(1_000_000);
            }),
            "effects.scattering_orders",
        ),
        (Box::new(|s| s.medium.sigma_ext = 5e-324), "medium.sigma_ext"),
        (Box::new(|s| s.estimator.radius = 1e-300), "estimator.radius"),
        (Box::new(|s| s.camera.origin.y = 1e130), "camera.origin[1]"),
        // Built in code past the scene's own validation: validated here too.
        (Box::new(|s| s.medium.albedo = 7.0), "medium.albedo"),
        (Box::new(|s| s.estimator.q = 0.0), "estimator.q"),
    ];
    for (edit, field) in cases {
        let mut scene = base.clone();
        edit(&mut scene);
        let err = Tracer::new(&scene).unwrap_err().to_string();
        assert!(err.contains(field), "{field}: {err}");
    }
    let tracer = Tracer::new(&base).unwrap();
    assert!(tracer.check_trials(1 << 40).is_ok());
    let err = tracer.check_trials(u64::MAX).unwrap_err().to_string();
    assert!(err.contains("--trials") && err.contains("at most"), "{err}");
}

#[test]
fn ranges_near_the_end_of_u64_are_traced_in_full() {
    let tracer = Tracer::new(&common::scene("point-isotropic", &[("radius = 0.01", "radius = 0.2")])).unwrap();
    for range in [u64::MAX - 5..u64::MAX, u64::MAX - 5000..u64::MAX, 18446744073709550000..u64::MAX] {
        let r = run(&tracer, range.clone());
        assert_eq!(r.counters.trials, range.end - range.start, "{range:?}");
        assert_eq!(r.sums.count, range.end - range.start);
        assert_eq!(r.ranges, vec![range]);
    }
    // A split at the end merges into the single run.
    let whole = run(&tracer, u64::MAX - 9000..u64::MAX);
    let parts = [run(&tracer, u64::MAX - 9000..u64::MAX - 4097), run(&tracer, u64::MAX - 4097..u64::MAX)];
    assert_eq!(merge(&parts).unwrap(), whole);
    assert_eq!(run(&tracer, 5..5).counters.trials, 0);
}

#[test]
fn l_is_scaled_exactly_by_powers_of_two_of_the_flux() {
    let one = Tracer::new(&common::scene("point-isotropic", &[("radius = 0.01", "radius = 0.2")])).unwrap();
    let base = run(&one, 0..3000).estimates();
    let (m, v) = (base.mean.unwrap(), base.variance.unwrap());
    // Fluxes within the scene's bounds ([1e−10, 1e10], `mcrt_scene::limits`):
    // the scaling is exact; beyond a double's range the sums give a reason
    // instead (tests/moments.rs).
    for k in [33, 17, -17, -33] {
        let mut scene = one.scene().clone();
        scene.lights[0] = mcrt_scene::Light::Point {
            position: glam::DVec3::new(1.0, 0.0, 1.0),
            flux: 2f64.powi(k / 2) * 2f64.powi(k - k / 2),
        };
        let tracer = Tracer::new(&scene).unwrap();
        let e = run(&tracer, 0..3000).estimates();
        let scale = |x: f64, n: i32| x * 2f64.powi(n / 2) * 2f64.powi(n - n / 2);
        let mean = e.mean.as_ref().unwrap_or_else(|why| panic!("2^{k}: {why}"));
        assert_eq!((mean.value, mean.se), (scale(m.value, k), scale(m.se, k)), "2^{k}");
        let var = e.variance.as_ref().unwrap_or_else(|why| panic!("2^{k}: {why}"));
        assert_eq!((var.value, var.se), (scale(v.value, 2 * k), scale(v.se, 2 * k)), "2^{k}");
    }
}

#[test]
fn a_run_without_hits_resolves_neither_mean_nor_variance() {
    let far = Tracer::new(&common::scene(
        "point-isotropic",
        &[("position = [1.0, 0.0, 1.0]", "position = [40.0, 0.0, 1.0]")],
    ))
    .unwrap();
    let r = run(&far, 0..5000);
    assert_eq!(r.counters.hits, 0);
    let e = r.estimates();
    for why in [e.mean.unwrap_err(), e.variance.unwrap_err()] {
        assert!(why.starts_with("no hits in 5000 trials: the mean and variance are not resolved"), "{why}");
    }
    // Equal values (no spread): standard errors of 0 are never given.
    let mut s = PowerSums::default();
    (0..10).for_each(|_| s.push(0.25));
    assert!(s.estimates().mean.unwrap_err().contains("all 10 values are equal"));
}

#[test]
fn shards_are_validated_field_by_field() {
    let tracer = Tracer::new(&common::scene("point-isotropic", &[("radius = 0.01", "radius = 0.2")])).unwrap();
    let good = run(&tracer, 0..100).to_shard();
    assert!(Run::from_shard(&good).is_ok());
    let check = |edit: &dyn Fn(&mut Shard), needle: &str| common::assert_shard_refused(&good, edit, needle);
    check(&|s| s.sums[0] = "@inf@".into(), "sums[0]");
    check(&|s| s.sums[2] = "@nan@".into(), "sums[2]");
    check(&|s| s.sums[1] = "0".into(), "sums: not the power sums");
    check(&|s| s.scene = "not a scene".into(), "scene");
    check(&|s| s.scene = s.scene.replace("albedo = 0.8", "albedo = 7.0"), "medium.albedo");
    check(&|s| s.ranges = vec![[0, 60], [40, 80]], "ranges[1]");
    check(&|s| s.ranges = vec![[50, 100], [0, 50]], "ranges[1]");
    check(&|s| s.ranges = vec![[u64::MAX - 10, u64::MAX], [0, 90]], "ranges[1]");
    check(&|s| s.counters.forward_rays += 1, "counters.forward_rays");
    check(&|s| s.counters.draws.free_path += 1, "counters.draws.free_path");
    check(&|s| s.counters.trials += 1, "counters.trials");
}
