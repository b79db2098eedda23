//! Scene parsing, validation and round-trip.

use mcrt_scene::{Phase, ScatteringOrders, Scene, SceneError};
use std::path::Path;

const BASE: &str = r#"
[medium]
sigma_ext = 1.0
albedo = 0.8
[medium.phase]
kind = "henyey-greenstein"
g = 0.0
[[lights]]
kind = "point"
position = [1.0, 0.0, 1.0]
flux = 1.0
[camera]
origin = [0.0, 0.0, 0.0]
direction = [0.0, 0.0, 1.0]
[estimator]
radius = 0.01
q = 0.5
forward_rays = 200
camera_rays = 8
[effects]
scattering_orders = 0
"#;

fn with(from: &str, to: &str) -> String {
    assert!(BASE.contains(from), "test bug: {from:?} not in base scene");
    BASE.replacen(from, to, 1)
}

/// The single field error of `text`, as (field, message).
fn field_error(text: &str) -> (String, String) {
    match Scene::from_toml_str(text) {
        Err(SceneError::Invalid(errors)) => {
            assert_eq!(errors.len(), 1, "{errors:?}");
            (errors[0].field.clone(), errors[0].to_string())
        }
        other => panic!("expected one field error, got {other:?}"),
    }
}

#[test]
fn issue_example_parses() {
    let s = Scene::from_toml_str(BASE).unwrap();
    assert_eq!(s.medium.phase, Phase::HenyeyGreenstein { g: 0.0 });
    assert_eq!(s.estimator.forward_rays, 200);
    assert_eq!(s.effects.scattering_orders, ScatteringOrders::Limited(0));
    assert_eq!(s.total_flux(), 1.0);
}

#[test]
fn bundled_scenes_parse_and_round_trip_exactly() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let mut n = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let s = Scene::from_toml_str(&std::fs::read_to_string(&path).unwrap())
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let again = Scene::from_toml_str(&s.to_toml_string()).unwrap();
            assert_eq!(s, again, "{}", path.display());
            n += 1;
        }
    }
    assert!(n >= 5, "only {n} bundled scenes");
}

#[test]
fn direction_is_normalised_and_round_trips() {
    let s = Scene::from_toml_str(&with("direction = [0.0, 0.0, 1.0]", "direction = [1.0, 2.0, 3.0]")).unwrap();
    approx::assert_relative_eq!(s.camera.direction.length(), 1.0, max_relative = 1e-15);
    assert_eq!(Scene::from_toml_str(&s.to_toml_string()).unwrap(), s);
}

#[test]
fn defaults_are_filled_in() {
    let text = BASE
        .replace("[effects]\nscattering_orders = 0\n", "")
        .replace("[medium.phase]\nkind = \"henyey-greenstein\"\ng = 0.0\n", "");
    let s = Scene::from_toml_str(&text).unwrap();
    assert_eq!(s.medium.phase, Phase::Isotropic);
    assert_eq!(s.effects.scattering_orders, ScatteringOrders::Limited(0));
    assert!(s.to_toml_string().contains("scattering_orders = 0"));
}

#[test]
fn orders_all() {
    let s = Scene::from_toml_str(&with("scattering_orders = 0", "scattering_orders = \"all\"")).unwrap();
    assert_eq!(s.effects.scattering_orders, ScatteringOrders::All);
}

#[test]
fn each_out_of_range_value_names_field_value_and_range() {
    let cases: &[(&str, &str, &str, &str)] = &[
        ("sigma_ext = 1.0", "sigma_ext = -1.0", "medium.sigma_ext", "> 0"),
        ("sigma_ext = 1.0", "sigma_ext = 0.0", "medium.sigma_ext", "> 0"),
        ("sigma_ext = 1.0", "sigma_ext = nan", "medium.sigma_ext", "finite"),
        ("albedo = 0.8", "albedo = 1.5", "medium.albedo", "[0, 1]"),
        ("albedo = 0.8", "albedo = -0.1", "medium.albedo", "[0, 1]"),
        ("g = 0.0", "g = 1.0", "medium.phase.g", "[-0.999999, 0.999999]"),
        ("g = 0.0", "g = -1.0", "medium.phase.g", "[-0.999999, 0.999999]"),
        ("g = 0.0", "g = nan", "medium.phase.g", "[-0.999999, 0.999999]"),
        ("radius = 0.01", "radius = 0.0", "estimator.radius", "> 0"),
        ("radius = 0.01", "radius = -0.01", "estimator.radius", "> 0"),
        ("radius = 0.01", "radius = inf", "estimator.radius", "finite"),
        ("q = 0.5", "q = 0.0", "estimator.q", "(0, 1]"),
        ("q = 0.5", "q = 1.0000001", "estimator.q", "(0, 1]"),
        ("q = 0.5", "q = nan", "estimator.q", "(0, 1]"),
        ("forward_rays = 200", "forward_rays = 0", "estimator.forward_rays", ">= 1"),
        ("camera_rays = 8", "camera_rays = -3", "estimator.camera_rays", ">= 1"),
        ("flux = 1.0", "flux = 0.0", "lights[0].flux", "> 0"),
        ("position = [1.0, 0.0, 1.0]", "position = [1.0, nan, 1.0]", "lights[0].position[1]", "finite"),
        ("direction = [0.0, 0.0, 1.0]", "direction = [0.0, 0.0, 0.0]", "camera.direction", "non-zero"),
        ("kind = \"point\"", "kind = \"spot\"", "lights[0].kind", "\"point\" or \"beam\""),
        ("kind = \"henyey-greenstein\"", "kind = \"rayleigh\"", "medium.phase.kind", "isotropic"),
        ("scattering_orders = 0", "scattering_orders = -1", "effects.scattering_orders", "\"all\""),
        ("scattering_orders = 0", "scattering_orders = \"many\"", "effects.scattering_orders", "\"all\""),
    ];
    for (from, to, field, range) in cases {
        let (f, msg) = field_error(&with(from, to));
        assert_eq!(&f, field, "{to}: {msg}");
        assert!(msg.contains(range), "{to}: message {msg:?} lacks {range:?}");
        let value = to.split(" = ").nth(1).unwrap().trim_matches('"');
        let value_shown = value.trim_start_matches('-').trim_start_matches('[');
        assert!(msg.contains(&value_shown[..1.min(value_shown.len())]), "{msg}");
    }
}

#[test]
fn all_errors_are_listed_not_only_the_first() {
    let text = with("albedo = 0.8", "albedo = 2.0").replace("q = 0.5", "q = 2.0");
    match Scene::from_toml_str(&text) {
        Err(SceneError::Invalid(e)) => {
            let fields: Vec<_> = e.iter().map(|e| e.field.as_str()).collect();
            assert_eq!(fields, ["medium.albedo", "estimator.q"]);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn unknown_key_is_named() {
    for (from, to, key) in [
        ("albedo = 0.8", "albedo = 0.8\nalbedoo = 0.8", "albedoo"),
        ("q = 0.5", "q = 0.5\nsphere_count = 3", "sphere_count"),
        ("flux = 1.0", "flux = 1.0\ncolour = 3", "colour"),
    ] {
        match Scene::from_toml_str(&with(from, to)) {
            Err(SceneError::Parse(msg)) => assert!(msg.contains(key), "{msg}"),
            other => panic!("{other:?}"),
        }
    }
    match Scene::from_toml_str(&format!("{BASE}\n[extra]\na = 1\n")) {
        Err(SceneError::Parse(msg)) => assert!(msg.contains("extra"), "{msg}"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn point_light_on_camera_ray_in_front_is_rejected() {
    for pos in ["[0.0, 0.0, 2.0]", "[0.0, 0.0, 0.0]", "[0.0, 0.0, 1e-300]"] {
        let (f, msg) = field_error(&with("position = [1.0, 0.0, 1.0]", &format!("position = {pos}")));
        assert_eq!(f, "lights[0].position");
        assert!(msg.contains("infinite"), "{msg}");
    }
    // Oblique camera ray, light on it up to rounding of the input.
    let text = with("direction = [0.0, 0.0, 1.0]", "direction = [1.0, 1.0, 1.0]")
        .replace("position = [1.0, 0.0, 1.0]", "position = [0.3, 0.3, 0.3]");
    assert_eq!(field_error(&text).0, "lights[0].position");
}

#[test]
fn point_light_behind_camera_or_near_the_ray_is_accepted() {
    for pos in ["[0.0, 0.0, -2.0]", "[1e-6, 0.0, 2.0]", "[-1e-6, 0.0, -2.0]"] {
        Scene::from_toml_str(&with("position = [1.0, 0.0, 1.0]", &format!("position = {pos}")))
            .unwrap_or_else(|e| panic!("{pos}: {e}"));
    }
}

#[test]
fn beam_requires_its_fields() {
    let text = with("kind = \"point\"\nposition = [1.0, 0.0, 1.0]", "kind = \"beam\"\ncenter = [1.0, 0.0, 1.0]");
    match Scene::from_toml_str(&text) {
        Err(SceneError::Invalid(e)) => {
            let fields: Vec<_> = e.iter().map(|e| e.field.as_str()).collect();
            assert_eq!(fields, ["lights[0].direction", "lights[0].radius"]);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_built_scene_equals_the_same_scene_read_from_toml() {
    let built = Scene::builder()
        .medium(1.0, 0.8)
        .phase(Phase::HenyeyGreenstein { g: 0.0 })
        .point_light([1.0, 0.0, 1.0], 1.0)
        .camera([0.0; 3], [0.0, 0.0, 2.0])
        .estimator(0.01, 0.5, 200, 8)
        .scattering_orders(ScatteringOrders::Limited(0))
        .build()
        .unwrap();
    assert_eq!(built, Scene::from_toml_str(BASE).unwrap());
    let beam = Scene::builder()
        .medium(2.0, 1.0)
        .beam([0.0, -1.0, 1.0], [0.0, 1.0, 0.0], 0.3, 2.0)
        .point_light([1.0, 0.0, 1.0], 1.0)
        .camera([0.0; 3], [0.0, 0.0, 1.0])
        .estimator(0.1, 1.0, 1, 1)
        .build()
        .unwrap();
    assert_eq!(Scene::from_toml_str(&beam.to_toml_string()).unwrap(), beam);
}

#[test]
fn the_builder_names_every_missing_and_invalid_value() {
    let err = Scene::builder().point_light([1.0, 0.0, f64::NAN], -1.0).build().unwrap_err();
    let SceneError::Invalid(errors) = err else { panic!("expected field errors") };
    let fields: Vec<&str> = errors.iter().map(|e| e.field.as_str()).collect();
    for expected in ["medium", "camera", "estimator", "lights[0].position[2]", "lights[0].flux"] {
        assert!(fields.contains(&expected), "{expected} not named in {fields:?}");
    }
    let err = Scene::builder()
        .medium(1.0, 0.5)
        .point_light([1.0, 0.0, 1.0], 1.0)
        .camera([0.0; 3], [0.0; 3])
        .estimator(-1.0, 0.5, u64::MAX, 0)
        .build()
        .unwrap_err()
        .to_string();
    for expected in [
        "camera.direction = [0.0, 0.0, 0.0]: must be a non-zero vector",
        "estimator.radius = -1: must be finite and > 0",
        "estimator.forward_rays = 18446744073709551615: must be an integer in [1, 9223372036854775807]",
        "estimator.camera_rays = 0: must be an integer >= 1",
    ] {
        assert!(err.contains(expected), "{expected:?} not in {err}");
    }
    let mut scene = Scene::from_toml_str(BASE).unwrap();
    scene.medium.albedo = 2.0;
    assert!(scene.validated().unwrap_err().to_string().contains("medium.albedo = 2"));
}

/// Issue 11: every field error of `text`, as "field = value: must be …" lines.
fn errors_of(text: &str) -> Vec<(String, String)> {
    match Scene::from_toml_str(text) {
        Err(SceneError::Invalid(errors)) => errors.iter().map(|e| (e.field.clone(), e.to_string())).collect(),
        other => panic!("expected field errors, got {other:?}"),
    }
}

#[test]
fn arrays_of_other_than_three_numbers_are_refused_not_truncated() {
    for (from, to, field) in [
        ("position = [1.0, 0.0, 1.0]", "position = [1, 0, 1, 2]", "lights[0].position"),
        ("position = [1.0, 0.0, 1.0]", "position = [1.0, 0.0]", "lights[0].position"),
        ("origin = [0.0, 0.0, 0.0]", "origin = [0.0, 0.0, 0.0, 0.0, 0.0]", "camera.origin"),
        ("direction = [0.0, 0.0, 1.0]", "direction = []", "camera.direction"),
    ] {
        let (f, msg) = field_error(&with(from, to));
        assert_eq!(f, field, "{to}: {msg}");
        assert!(msg.contains("exactly 3 numbers"), "{msg}");
    }
    let (_, msg) = field_error(&with("position = [1.0, 0.0, 1.0]", "position = [1, 0, 1, 2]"));
    assert_eq!(msg, "lights[0].position = an array of 4 numbers: must be an array of exactly 3 numbers [x, y, z]");
}

#[test]
fn huge_directions_normalise_without_overflow_and_huge_lengths_are_refused_by_name() {
    // |d| overflows f64, d itself is fine: normalised, not "zero".
    let s = Scene::from_toml_str(&with("direction = [0.0, 0.0, 1.0]", "direction = [1e300, 1e300, 0]")).unwrap();
    approx::assert_relative_eq!(s.camera.direction.x, std::f64::consts::FRAC_1_SQRT_2, max_relative = 1e-15);
    assert_eq!(Scene::from_toml_str(&s.to_toml_string()).unwrap(), s);
    let s = Scene::from_toml_str(&with("direction = [0.0, 0.0, 1.0]", "direction = [0.0, 1e-320, 1e-320]")).unwrap();
    approx::assert_relative_eq!(s.camera.direction.length(), 1.0, max_relative = 1e-15);
    // A coordinate beyond σ_ext·|x| ≤ 1e6: that coordinate is named, nothing else.
    let (f, msg) = field_error(&with("position = [1.0, 0.0, 1.0]", "position = [1e300, 0.0, 1.0]"));
    assert_eq!(f, "lights[0].position[0]");
    assert!(msg.contains("σ_ext·|x| ≤ 1e6"), "{msg}");
    let (f, msg) = field_error(&with("origin = [0.0, 0.0, 0.0]", "origin = [0.0, -2e6, 0.0]"));
    assert_eq!(f, "camera.origin[1]", "{msg}");
    // A camera so far out that |light − origin|² overflows: only the
    // coordinate is named (the plain lengths were inf, and inf ≤ inf put the
    // light "on the camera ray" as well).
    for origin in ["1e155", "1e200", "1e300"] {
        let (f, msg) = field_error(&with("origin = [0.0, 0.0, 0.0]", &format!("origin = [{origin}, 0.0, 0.0]")));
        assert_eq!(f, "camera.origin[0]", "{origin}: {msg}");
    }
    // A light beyond 600 optical depths: named with its optical distance.
    let (f, msg) = field_error(&with("position = [1.0, 0.0, 1.0]", "position = [800.0, 0.0, 1.0]"));
    assert_eq!(f, "lights[0].position");
    assert!(msg.contains("σ_ext·r ≤ 600") && msg.contains("here 800.0") && msg.contains("underflows"), "{msg}");
    let far =
        with("sigma_ext = 1.0", "sigma_ext = 2.0").replace("position = [1.0, 0.0, 1.0]", "position = [0, 1, 400]");
    assert_eq!(field_error(&far).0, "lights[0].position");
    Scene::from_toml_str(&with("position = [1.0, 0.0, 1.0]", "position = [0.0, 1.0, 599.0]")).unwrap();
    // A beam: its disk's nearest point counts.
    let beam = |center: &str| {
        with(
            "kind = \"point\"\nposition = [1.0, 0.0, 1.0]",
            &format!("kind = \"beam\"\ncenter = {center}\ndirection = [1.0, 0.0, 0.0]\nradius = 0.5"),
        )
    };
    let (f, msg) = field_error(&beam("[-700.0, 0.0, 1.0]"));
    assert_eq!(f, "lights[0].center");
    assert!(msg.contains("nearest point of the beam's disk"), "{msg}");
    Scene::from_toml_str(&beam("[-2.0, 0.0, 1.0]")).unwrap();
    // The builder goes through the same checks.
    let err = Scene::builder()
        .medium(1.0, 0.8)
        .point_light([900.0, 0.0, 1.0], 1.0)
        .camera([0.0; 3], [1e300, 1e300, 0.0])
        .estimator(0.01, 0.5, 10, 1)
        .build()
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("lights[0].position") && err.contains("σ_ext·r ≤ 600") && !err.contains("camera.direction"),
        "{err}"
    );
}

#[test]
fn scattering_orders_of_a_wrong_type_name_the_field_and_the_allowed_values() {
    for v in ["1.0", "true", "18446744073709551615", "-1"] {
        let (f, msg) = field_error(&with("scattering_orders = 0", &format!("scattering_orders = {v}")));
        assert_eq!(f, "effects.scattering_orders", "{v}");
        assert!(msg.contains("an integer in [0, 1000000] or \"all\""), "{v}: {msg}");
        assert!(msg.contains(v), "{v}: {msg}");
    }
}

#[test]
fn scales_counts_and_q_outside_what_downstream_can_compute_are_refused_with_the_bound() {
    let cases: &[(&str, &str, &str, &str)] = &[
        ("q = 0.5", "q = 1e-12", "estimator.q", "at least 1e-6"),
        ("camera_rays = 8", "camera_rays = 1099511627776", "estimator.camera_rays", "[1, 1000000]"),
        ("forward_rays = 200", "forward_rays = 1099511627776", "estimator.forward_rays", "[1, 100000000]"),
        ("radius = 0.01", "radius = 1e-300", "estimator.radius", "σ_ext·radius in [1e-12, 1e3]"),
        ("radius = 0.01", "radius = 1e4", "estimator.radius", "σ_ext·radius in [1e-12, 1e3]"),
        ("flux = 1.0", "flux = 1e300", "lights[0].flux", "[1e-10, 1e10]"),
        ("flux = 1.0", "flux = 1e-300", "lights[0].flux", "[1e-10, 1e10]"),
        ("sigma_ext = 1.0", "sigma_ext = 5e-324", "medium.sigma_ext", "[1e-10, 1e10]"),
        ("sigma_ext = 1.0", "sigma_ext = 1e300", "medium.sigma_ext", "[1e-10, 1e10]"),
        ("g = 0.0", "g = 0.9999999", "medium.phase.g", "[-0.999999, 0.999999]"),
    ];
    for (from, to, field, range) in cases {
        let (f, msg) = field_error(&with(from, to));
        assert_eq!(&f, field, "{to}: {msg}");
        assert!(msg.contains(range), "{to}: message {msg:?} lacks {range:?}");
    }
    // N_B/q bounds the spheres one iteration stores.
    let text = with("q = 0.5", "q = 0.01").replace("camera_rays = 8", "camera_rays = 1000000");
    let errors = errors_of(&text);
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert_eq!(errors[0].0, "estimator.camera_rays / estimator.q");
    assert!(errors[0].1.contains("1e8") && errors[0].1.contains("at most 1e7"), "{}", errors[0].1);
    // σ_ext·R is checked in units of 1/σ_ext, with a few ulps of slack at the bound.
    let dense = with("sigma_ext = 1.0", "sigma_ext = 1e10")
        .replace("position = [1.0, 0.0, 1.0]", "position = [1e-10, 0.0, 1e-10]");
    Scene::from_toml_str(&dense.replace("radius = 0.01", "radius = 1e-22")).unwrap();
    assert_eq!(field_error(&dense).0, "estimator.radius");
    // The builder: the same bounds.
    let err = Scene::builder()
        .medium(5e-324, 0.8)
        .point_light([1.0, 0.0, 1.0], 1e300)
        .camera([0.0; 3], [0.0, 0.0, 1.0])
        .estimator(1e-300, 1e-12, 1 << 40, 1 << 40)
        .build()
        .unwrap_err()
        .to_string();
    for field in
        ["medium.sigma_ext", "lights[0].flux", "estimator.q", "estimator.forward_rays", "estimator.camera_rays"]
    {
        assert!(err.contains(field), "{field} not in {err}");
    }
}

/// `[cost]` (issue 12): a renderer's per-operation costs, every key
/// required, each a time in [0, 1e12] ns named on error; optional standard
/// errors; round-trips; absent means none.
#[test]
fn a_cost_table_is_validated_by_field_and_round_trips() {
    let table = "[cost]\ntrial_ns = 900.0\nforward_ray_ns = 40.0\ncamera_ray_ns = 2000.0\nsegment_ns = 30.0\n\
                 sphere_ns = 8.0\nsort_ns = 1.5\nsearch_ns = 2.0\nhit_ns = 4.0\nhg_ns = 9.0\n";
    let s = Scene::from_toml_str(&format!("{BASE}{table}")).unwrap();
    let k = s.cost.unwrap();
    assert_eq!((k.get("trial_ns"), k.get("hg_ns"), k.std_errors), (Some(900.0), Some(9.0), [0.0; 9]));
    assert_eq!(Scene::from_toml_str(&s.to_toml_string()).unwrap(), s);
    assert_eq!(Scene::from_toml_str(BASE).unwrap().cost, None);
    let with_errors = format!("{BASE}{table}std_errors = [1, 2, 3, 4, 5, 6, 7, 8, 9]\n");
    let s = Scene::from_toml_str(&with_errors).unwrap();
    assert_eq!(s.cost.unwrap().std_errors[8], 9.0);
    let (f, msg) = field_error(&format!("{BASE}{table}std_errors = [1, 2]\n"));
    assert!(f == "cost.std_errors" && msg.contains("9 numbers"), "{msg}");
    assert_eq!(Scene::from_toml_str(&s.to_toml_string()).unwrap(), s);
    let (f, msg) = field_error(&format!("{BASE}{}", table.replace("hit_ns = 4.0", "hit_ns = -4.0")));
    assert_eq!(f, "cost.hit_ns");
    assert!(msg.contains("[0, 1e12]"), "{msg}");
    let (f, _) = field_error(&format!("{BASE}{}", table.replace("sort_ns = 1.5", "sort_ns = nan")));
    assert_eq!(f, "cost.sort_ns");
    // A missing key or an unknown one is a parse error naming it.
    for bad in [table.replace("camera_ray_ns = 2000.0\n", ""), format!("{table}bogus_ns = 1.0\n")] {
        match Scene::from_toml_str(&format!("{BASE}{bad}")) {
            Err(SceneError::Parse(m)) => assert!(m.contains("camera_ray_ns") || m.contains("bogus_ns"), "{m}"),
            other => panic!("expected a parse error, got {other:?}"),
        }
    }
}
