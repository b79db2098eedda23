//! A scene read back through its accessors alone and rebuilt with the builder
//! is the same scene (issue 22: a renderer builds its own scene from the
//! oracle's `Scene`, or the reverse). Every bundled scene, and a few written
//! here for what no bundled scene has (several lights, `[cost]`, defaults),
//! goes through; the set is checked to hold every feature of a scene file,
//! so a feature the accessors or the builder drop makes a scene differ.

use mcrt_scene::{Cost, Phase, ScatteringOrders, Scene, SceneBuilder, COST_KEYS};
use std::path::{Path, PathBuf};

/// Several lights of both kinds, unnormalised directions, HG with g = 0
/// (not isotropic), a limited order above 1, costs with standard errors.
const MIXED: &str = r#"
[medium]
sigma_ext = 2.5
albedo = 0.3
[medium.phase]
kind = "henyey-greenstein"
g = 0.0
[[lights]]
kind = "point"
position = [1.0, -0.5, 1.0]
flux = 2.0
[[lights]]
kind = "beam"
center = [0.0, -3.0, 2.0]
direction = [0.0, 3.0, 0.1]
radius = 0.25
flux = 0.75
[[lights]]
kind = "point"
position = [-1.0, 0.25, 3.0]
flux = 1e-3
[camera]
origin = [0.5, 0.0, -1.0]
direction = [0.1, 0.0, 2.0]
[estimator]
radius = 0.03
q = 0.125
forward_rays = 5000
camera_rays = 3
[effects]
scattering_orders = 5
[cost]
trial_ns = 900.0
forward_ray_ns = 40.0
camera_ray_ns = 2000.0
segment_ns = 30.0
sphere_ns = 8.0
sort_ns = 1.5
search_ns = 2.0
hit_ns = 0.0
hg_ns = 9.0
std_errors = [9.0, 1.0, 20.0, 0.5, 0.1, 0.05, 0.1, 0.25, 0.3]
"#;

/// Optional tables left out (isotropic phase, order 0, no cost); costs
/// without standard errors.
const DEFAULTS: &str = r#"
[medium]
sigma_ext = 1e-3
albedo = 1.0
[[lights]]
kind = "beam"
center = [-20.0, 0.0, 10.0]
direction = [1.0, 0.0, 0.0]
radius = 5.0
flux = 1e4
[camera]
origin = [0.0, 0.0, 0.0]
direction = [0.0, 0.0, 1.0]
[estimator]
radius = 1.0
q = 1.0
forward_rays = 1
camera_rays = 1
[cost]
trial_ns = 1.0
forward_ray_ns = 0.0
camera_ray_ns = 0.0
segment_ns = 0.0
sphere_ns = 0.0
sort_ns = 0.0
search_ns = 0.0
hit_ns = 0.0
hg_ns = 0.0
"#;

/// `scene` rebuilt through the builder from what its accessors give, field
/// access nowhere: each light from its kind's accessors, the phase function
/// from its g, the orders from their limit, the costs from their arrays.
fn rebuild(scene: &Scene) -> Scene {
    let medium = scene.medium();
    let camera = scene.camera();
    let e = scene.estimator();
    assert_eq!(scene.effects().scattering_orders(), scene.scattering_orders());
    let phase = match medium.phase().g() {
        None => Phase::Isotropic,
        Some(g) => Phase::HenyeyGreenstein { g },
    };
    let orders = match scene.scattering_orders().limit() {
        Some(n) => ScatteringOrders::Limited(n),
        None => ScatteringOrders::All,
    };
    let mut b = Scene::builder()
        .medium(medium.sigma_ext(), medium.albedo())
        .phase(phase)
        .camera(camera.origin().to_array(), camera.direction().to_array())
        .estimator(e.radius(), e.q(), e.forward_rays(), e.camera_rays())
        .scattering_orders(orders);
    for (i, l) in scene.lights().iter().enumerate() {
        b = match (l.position(), l.center(), l.direction(), l.radius()) {
            (Some(p), None, None, None) if l.is_point() && !l.is_beam() => b.point_light(p.to_array(), l.flux()),
            (None, Some(c), Some(d), Some(a)) if l.is_beam() && !l.is_point() => {
                b.beam(c.to_array(), d.to_array(), a, l.flux())
            }
            other => panic!("lights[{i}]: accessors disagree on its kind: {other:?}"),
        };
    }
    if let Some(k) = scene.cost() {
        for (i, key) in COST_KEYS.iter().enumerate() {
            assert_eq!(k.get(key), Some(k.ns()[i]), "{key}");
            assert_eq!(k.std_error(key), Some(k.std_errors()[i]), "{key}");
        }
        b = b.cost(Cost { ns: k.ns(), std_errors: k.std_errors() });
    }
    b.build().unwrap_or_else(|e| panic!("the rebuilt scene is refused: {e}"))
}

/// The same through [`SceneBuilder::light`], the lights passed whole.
fn rebuild_with_whole_lights(scene: &Scene) -> Scene {
    let (m, c, e) = (scene.medium(), scene.camera(), scene.estimator());
    let mut b: SceneBuilder = Scene::builder()
        .medium(m.sigma_ext(), m.albedo())
        .phase(m.phase())
        .camera(c.origin().to_array(), c.direction().to_array())
        .estimator(e.radius(), e.q(), e.forward_rays(), e.camera_rays())
        .scattering_orders(scene.scattering_orders());
    for &l in scene.lights() {
        b = b.light(l);
    }
    if let Some(&k) = scene.cost() {
        b = b.cost(k);
    }
    b.build().unwrap()
}

fn bundled() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    paths.sort();
    paths
}

/// What of a scene file's features a scene uses.
#[derive(Default, Debug)]
struct Seen {
    isotropic: bool,
    henyey_greenstein: bool,
    point: bool,
    beam: bool,
    several_lights: bool,
    order_zero: bool,
    order_above_zero: bool,
    all_orders: bool,
    no_cost: bool,
    cost_with_std_errors: bool,
    cost_without_std_errors: bool,
}

impl Seen {
    fn add(&mut self, s: &Scene) {
        self.isotropic |= s.medium().phase() == Phase::Isotropic;
        self.henyey_greenstein |= s.medium().phase().g().is_some();
        self.point |= s.lights().iter().any(|l| l.is_point());
        self.beam |= s.lights().iter().any(|l| l.is_beam());
        self.several_lights |= s.lights().len() > 1;
        self.order_zero |= s.scattering_orders() == ScatteringOrders::Limited(0);
        self.order_above_zero |= s.scattering_orders().limit().is_some_and(|n| n > 0);
        self.all_orders |= s.scattering_orders() == ScatteringOrders::All;
        self.no_cost |= s.cost().is_none();
        self.cost_with_std_errors |= s.cost().is_some_and(|k| k.std_errors() != [0.0; 9]);
        self.cost_without_std_errors |= s.cost().is_some_and(|k| k.std_errors() == [0.0; 9]);
    }
}

#[test]
fn every_scene_rebuilt_from_its_accessors_is_the_same_scene() {
    let mut scenes: Vec<(String, String)> =
        bundled().iter().map(|p| (p.display().to_string(), std::fs::read_to_string(p).unwrap())).collect();
    assert!(scenes.len() >= 6, "only {} bundled scenes", scenes.len());
    scenes.push(("MIXED".into(), MIXED.into()));
    scenes.push(("DEFAULTS".into(), DEFAULTS.into()));
    let mut seen = Seen::default();
    for (name, text) in &scenes {
        let original = Scene::from_toml_str(text).unwrap_or_else(|e| panic!("{name}: {e}"));
        seen.add(&original);
        for rebuilt in [rebuild(&original), rebuild_with_whole_lights(&original)] {
            assert_eq!(rebuilt, original, "{name}");
            // Bit for bit, as written (−0.0 and 0.0 compare equal but print apart).
            assert_eq!(rebuilt.to_toml_string(), original.to_toml_string(), "{name}");
            assert_eq!(Scene::from_toml_str(&rebuilt.to_toml_string()).unwrap(), rebuilt, "{name}");
        }
    }
    let Seen {
        isotropic,
        henyey_greenstein,
        point,
        beam,
        several_lights,
        order_zero,
        order_above_zero,
        all_orders,
        no_cost,
        cost_with_std_errors,
        cost_without_std_errors,
    } = seen;
    assert!(
        isotropic
            && henyey_greenstein
            && point
            && beam
            && several_lights
            && order_zero
            && order_above_zero
            && all_orders
            && no_cost
            && cost_with_std_errors
            && cost_without_std_errors,
        "the scenes no longer cover every feature: {seen:?}"
    );
}

#[test]
fn the_accessors_give_the_values_as_written_and_normalised() {
    let s = Scene::from_toml_str(MIXED).unwrap();
    assert_eq!(
        (s.medium().sigma_ext(), s.medium().albedo(), s.medium().phase()),
        (2.5, 0.3, Phase::HenyeyGreenstein { g: 0.0 })
    );
    assert_eq!(s.medium().phase().g(), Some(0.0));
    assert_eq!(s.lights().len(), 3);
    assert_eq!(s.lights()[0].position().unwrap().to_array(), [1.0, -0.5, 1.0]);
    let beam = s.lights()[1];
    assert_eq!((beam.center().unwrap().to_array(), beam.radius(), beam.flux()), ([0.0, -3.0, 2.0], Some(0.25), 0.75));
    approx::assert_relative_eq!(beam.direction().unwrap().length(), 1.0, max_relative = 1e-15);
    approx::assert_relative_eq!(beam.direction().unwrap().y / beam.direction().unwrap().z, 30.0, max_relative = 1e-14);
    assert_eq!(s.lights()[2].flux(), 1e-3);
    assert_eq!(s.camera().origin().to_array(), [0.5, 0.0, -1.0]);
    approx::assert_relative_eq!(s.camera().direction().length(), 1.0, max_relative = 1e-15);
    let e = s.estimator();
    assert_eq!((e.radius(), e.q(), e.forward_rays(), e.camera_rays()), (0.03, 0.125, 5000, 3));
    assert_eq!(s.scattering_orders(), ScatteringOrders::Limited(5));
    assert!(s.scattering_orders().includes(5) && !s.scattering_orders().includes(6));
    assert!(ScatteringOrders::All.includes(u32::MAX) && ScatteringOrders::All.limit().is_none());
    let k = s.cost().unwrap();
    assert_eq!((k.get("hit_ns"), k.std_error("hit_ns"), k.std_error("no_such_ns")), (Some(0.0), Some(0.25), None));
    assert_eq!(s.total_flux(), 2.0 + 0.75 + 1e-3);

    let d = Scene::from_toml_str(DEFAULTS).unwrap();
    assert_eq!(
        (d.medium().phase(), d.scattering_orders(), d.cost().unwrap().std_errors()),
        (Phase::Isotropic, ScatteringOrders::Limited(0), [0.0; 9])
    );
}
