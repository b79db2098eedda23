//! The single-scattered field (scattering order 1) against a closed form.
//!
//! Furnace check: with negligible extinction (σ_ext = 10⁻⁹, albedo 1,
//! isotropic phase function) the single-scattered fluence of a point light of
//! flux Φ at distance r is
//!
//!   φ₁ = ∫ L₁ dω = σ_sc Φ/(16π²) ∫ d³y /(|y|² |y − x|²) = σ_sc Φ π/(16 r),
//!
//! with a relative correction from the attenuation of the far field: the
//! integrand falls like 4π/y² at distances y ≫ r, where e^{−2σy} cuts it,
//! so δ ≈ −(8/π²) σ r ln(1/(σ r)) ≈ −2·10⁻⁸ here (measured 1.3–1.6·10⁻⁵ at
//! σ = 10⁻⁶, as this predicts). Tolerance: 10⁻⁷ relative (five times that
//! correction, far above the quadrature bars, which are checked
//! separately), for each of the two rules on its own, so the test also
//! cross-checks the rules against each other through the closed form.

use mcrt_noise::model::angular::{Direction, Features, Pole};
use mcrt_noise::model::field::Field;
use mcrt_noise::model::moments::mean_contribution_estimate;
use mcrt_noise::quad::{Estimate, Options, Rule};
use mcrt_scene::Scene;

const FURNACE: &str = r#"
[medium]
sigma_ext = 1e-9
albedo = 1.0
[medium.phase]
kind = "isotropic"
[[lights]]
kind = "point"
position = [1.0, 0.0, 1.0]
flux = 2.0
[camera]
origin = [0.0, 0.0, 0.0]
direction = [0.0, 0.0, 1.0]
[estimator]
radius = 0.01
q = 0.5
forward_rays = 10
camera_rays = 2
[effects]
scattering_orders = 1
"#;

fn smooth_features() -> Features<f64> {
    let none = || Pole { floor: None, marks: Vec::new() };
    Features { plus: none(), minus: none(), equator_jump: false, source_near_0: None, source_near_pi: None }
}

fn options(rule: Rule) -> Options {
    Options { rule, cross_check: false, zero_guard: false, ..Options::rel(1e-10).declared() }
}

#[test]
fn single_scattered_fluence_matches_the_closed_form() {
    let scene = Scene::from_toml_str(FURNACE).unwrap();
    let field: Field<f64> = Field::from_scene(&scene, &0.0).unwrap();
    let sc = &field.scattered[0];
    let one = |d: &Direction<f64>, o: &Options| Ok(Estimate::known(1.0 + 0.0 * d.mu, 0.0, 1, o.rule));
    // x is measured from the light's closest approach s = 1 (distance 1).
    for x in [-0.9, 0.0, 0.5, 3.0] {
        let at = sc.at(&x, &field.sigma_ext, &field.sigma_sc);
        // φ₁ with the field's attenuation shift undone.
        let expect = field.sigma_sc * 2.0 * std::f64::consts::PI / (16.0 * at.r) * field.shift.exp();
        for rule in [Rule::TanhSinh, Rule::Check] {
            let e = at.integral(&field.sigma_ext, &field.phase, &smooth_features(), &one, &options(rule)).unwrap();
            let rel = (e.value / expect - 1.0).abs();
            assert!(rel < 1e-7, "x = {x} {rule:?}: {} vs {expect} (rel {rel:e})", e.value);
            assert!(e.error < 1e-9 * e.value, "x = {x} {rule:?}: bar {:e}", e.error);
        }
    }
}

#[test]
fn mean_contribution_adds_the_scattered_part() {
    let scene = Scene::from_toml_str(FURNACE).unwrap();
    let field: Field<f64> = Field::from_scene(&scene, &0.0).unwrap();
    let mut direct_only = scene.clone();
    direct_only.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(0);
    let direct: Field<f64> = Field::from_scene(&direct_only, &0.0).unwrap();
    for x in [-0.5, 0.0, 2.0] {
        let with = mean_contribution_estimate(&field, &x, &options(Rule::TanhSinh)).unwrap();
        let without = mean_contribution_estimate(&direct, &x, &options(Rule::TanhSinh)).unwrap();
        let r = field.scattered[0].at(&x, &field.sigma_ext, &field.sigma_sc).r;
        // albedo · f · φ₁ with f = 1/(4π).
        let phi1 = field.sigma_sc * 2.0 * std::f64::consts::PI / (16.0 * r) * field.shift.exp();
        let expect = phi1 / (4.0 * std::f64::consts::PI);
        let rel = ((with.value - without.value) / expect - 1.0).abs();
        assert!(rel < 1e-7, "x = {x}: {} vs {expect} (rel {rel:e})", with.value - without.value);
    }
}

/// The two angular frames are independent computations of the same
/// integral: polar about w₀ (ψ, χ: `AtPoint::integral`, the source by
/// quadrature at every ψ) and polar about the view direction (ϑ, φ:
/// `AtPoint::view`, the source from its Chebyshev table). They must agree
/// within the sum of their bars, for both rules, on the bundled phase
/// functions (the HG peaks sit at opposite poles for g > 0 and g < 0).
#[test]
fn the_two_angular_frames_agree() {
    use mcrt_noise::model::angular::Measure;
    for (g_text, g) in [("isotropic", None), ("forward", Some(0.9)), ("backward", Some(-0.5))] {
        let phase = match g {
            None => "kind = \"isotropic\"".to_string(),
            Some(g) => format!("kind = \"henyey-greenstein\"\ng = {g}"),
        };
        let text = FURNACE.replace("sigma_ext = 1e-9", "sigma_ext = 1.0").replace("kind = \"isotropic\"", &phase);
        let scene = Scene::from_toml_str(&text).unwrap();
        let field: Field<f64> = Field::from_scene(&scene, &0.0).unwrap();
        let sc = &field.scattered[0];
        let (near_0, near_pi) = mcrt_noise::model::scattered::source_features(&field.phase, &0.0);
        let (plus, minus) = mcrt_noise::model::moments::phase_poles(&field);
        let features = Features {
            plus: Pole { floor: plus, marks: Vec::new() },
            minus: Pole { floor: minus, marks: Vec::new() },
            equator_jump: false,
            source_near_0: near_0,
            source_near_pi: near_pi,
        };
        let f = |d: &Direction<f64>, o: &Options| Ok(Estimate::known(field.phase_at(&d.mu), 0.0, 1, o.rule));
        for x in [-0.9, 0.0, 2.0] {
            let at = sc.at(&x, &field.sigma_ext, &field.sigma_sc);
            for rule in [Rule::TanhSinh, Rule::Check] {
                let o = options(rule);
                let a = at.integral(&field.sigma_ext, &field.phase, &features, &f, &o).unwrap();
                let b = at.view(&field.sigma_ext, &field.phase, &features, Measure::Solid, &f, &o).unwrap();
                let diff = (a.value - b.value).abs();
                assert!(
                    diff <= a.error + b.error,
                    "{g_text} x = {x} {rule:?}: {} ± {:e} vs {} ± {:e}",
                    a.value,
                    a.error,
                    b.value,
                    b.error
                );
                assert!(a.error < 1e-9 * a.value && b.error < 1e-9 * b.value, "{g_text} x = {x} {rule:?}: bars");
            }
        }
    }
}

/// f64 and MPFR (128 bits) agree within their bars on the order-1
/// machinery at one camera-ray point of the bundled scene (σ_ext = 1): the
/// mean's angular integral in the frame about w₀ and the pair integral's in
/// the frame about u, with the tables, both rules. (The whole order-1
/// oracle at 128 bits takes longer than 25 min; this checks its parts, at
/// 128 bits to 1e−12, in about 50 s.)
#[test]
#[cfg(feature = "mpfr")]
fn order_one_parts_agree_between_f64_and_128_bits() {
    use mcrt_noise::model::angular::Measure;
    use rug::Float;
    let text = FURNACE.replace("sigma_ext = 1e-9", "sigma_ext = 1.0");
    let scene = Scene::from_toml_str(&text).unwrap();
    let f64_field: Field<f64> = Field::from_scene(&scene, &0.0).unwrap();
    let mp_field: Field<Float> = Field::from_scene(&scene, &Float::with_val(128, 0)).unwrap();
    let features_of = |plus: Option<f64>| Features {
        plus: Pole { floor: plus, marks: Vec::new() },
        minus: Pole { floor: plus, marks: Vec::new() },
        equator_jump: plus.is_some(),
        source_near_0: None,
        source_near_pi: None,
    };
    for rule in [Rule::TanhSinh, Rule::Check] {
        for (measure, floor) in [(None, None), (Some(Measure::Solid), Some(1e-3))] {
            let x = 0.5;
            let a = {
                let at = f64_field.scattered[0].at(&x, &f64_field.sigma_ext, &f64_field.sigma_sc);
                let f =
                    |d: &Direction<f64>, o: &Options| Ok(Estimate::known(f64_field.phase_at(&d.mu), 0.0, 1, o.rule));
                let o = options(rule);
                match measure {
                    None => at.integral(&f64_field.sigma_ext, &f64_field.phase, &features_of(floor), &f, &o),
                    Some(m) => at.view(&f64_field.sigma_ext, &f64_field.phase, &features_of(floor), m, &f, &o),
                }
                .unwrap()
            };
            let b = {
                let xm = Float::with_val(128, x);
                let at = mp_field.scattered[0].at(&xm, &mp_field.sigma_ext, &mp_field.sigma_sc);
                let f = |d: &Direction<Float>, o: &Options| {
                    Ok(Estimate::known(mp_field.phase_at(&d.mu), Float::with_val(128, 0), 1, o.rule))
                };
                let o = Options { rel_tol: 1e-12, ..options(rule) };
                let pf = features_of(floor);
                let features = Features {
                    plus: Pole { floor: pf.plus.floor.map(|v| Float::with_val(128, v)), marks: Vec::new() },
                    minus: Pole { floor: pf.minus.floor.map(|v| Float::with_val(128, v)), marks: Vec::new() },
                    equator_jump: pf.equator_jump,
                    source_near_0: None,
                    source_near_pi: None,
                };
                match measure {
                    None => at.integral(&mp_field.sigma_ext, &mp_field.phase, &features, &f, &o),
                    Some(m) => at.view(&mp_field.sigma_ext, &mp_field.phase, &features, m, &f, &o),
                }
                .unwrap()
            };
            let diff = (a.value - b.value.to_f64()).abs();
            assert!(
                diff <= a.error + b.error.to_f64() + 4.0 * f64::EPSILON * a.value,
                "{rule:?} {measure:?}: f64 {} ± {:e}, 128 bits {} ± {:e}",
                a.value,
                a.error,
                b.value.to_f64(),
                b.error.to_f64()
            );
        }
    }
}
