//! The oracle: consistency of the model, convergence of the R → 0 forms,
//! f64 against MPFR, hard cases.
//!
//! Tolerance policy: agreement between precisions is judged against the sum
//! of the two error bars (nothing wider); convergence tests use the first-order
//! behaviour the derivation predicts (`docs/model.md`): |1 − ratio| shrinks by
//! a factor 10 ± 2 per decade of R.

use mcrt_noise::model::correlations::pointwise;
use mcrt_noise::model::field::Field;
use mcrt_noise::model::moments::second_moment;
use mcrt_noise::oracle::{run, Precision, Report};
use mcrt_scene::Scene;
use std::path::Path;

/// (23) of a report of every integral (`run`).
fn c23(r: &Report) -> &mcrt_noise::oracle::Correlation {
    r.corr23.as_ref().expect("a run of every integral has (23)")
}

/// (24) of a report of every integral (`run`).
fn c24(r: &Report) -> &mcrt_noise::oracle::Correlation {
    r.corr24.as_ref().expect("a run of every integral has (24)")
}

const ORDER0_SCENES: [&str; 4] = ["point-isotropic", "point-hg-forward", "point-hg-backward", "beam-isotropic"];

fn scene(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(format!("{name}.toml"));
    Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn with_radius(mut s: Scene, r: f64) -> Scene {
    s.estimator.radius = r;
    s
}

fn oracle(s: &Scene) -> Report {
    run(s, Precision::F64, None).unwrap_or_else(|e| panic!("{e}"))
}

/// A prediction-scoped run (the library's `predict`) skips the
/// small-sphere integrals of two spheres only where (7)–(9) weigh them 0
/// (q = 1, N_B = 1), and its prediction, small-sphere Var L and
/// finite-sphere object are then the full run's to the bit (the skipped
/// terms enter with weights that are exactly 0); with q < 1 or N_B > 1 it
/// computes everything.
#[test]
fn a_prediction_skips_only_what_var_l_weighs_0() {
    use mcrt_noise::oracle::{run_scoped, Scope};
    // Single scattering at 10⁻³ (the full run ~1.3·10⁸ evaluations, where
    // the skip saves most), uncollided light at the default goal.
    for (name, tol) in [
        ("point-isotropic", None),
        ("point-hg-forward", None),
        ("beam-isotropic", None),
        ("point-isotropic-order1", Some(1e-3)),
    ] {
        let mut s = with_radius(scene(name), 0.2);
        s.estimator.q = 1.0;
        s.estimator.camera_rays = 1;
        let full = run(&s, Precision::F64, tol).unwrap();
        let lean = run_scoped(&s, Precision::F64, tol, Scope::Prediction).unwrap();
        assert!(full.corr23.is_some() && full.integral_q.is_some() && full.pairs_not_computed.is_none());
        assert!(lean.corr23.is_none() && lean.corr24.is_none() && lean.integral_q.is_none() && lean.d.is_none());
        assert!(lean.pairs_not_computed.as_deref().is_some_and(|w| w.contains("weight 0")), "{name}");
        let json = |r: &Report| serde_json::to_value(r).unwrap();
        for key in ["prediction", "finite", "mean_luminance", "integral_m2", "integral_p"] {
            let (a, b) = (&json(&full)[key], &json(&lean)[key]);
            assert_eq!(a, b, "{name}: {key}");
        }
        assert_eq!(
            full.variance.as_ref().unwrap().exact,
            lean.variance.as_ref().unwrap().exact,
            "{name}: small-sphere Var L"
        );
        assert!(lean.evaluations < full.evaluations, "{name}: {} vs {}", lean.evaluations, full.evaluations);
        let text = mcrt_noise::reports::tables::oracle_table(&lean);
        assert!(text.contains("not computed: ") && !text.contains("NaN"), "{name}:\n{text}");
        // Two spheres per camera ray: the pairs enter Var L, and are computed.
        if tol.is_none() {
            s.estimator.camera_rays = 2;
            let lean = run_scoped(&s, Precision::F64, None, Scope::Prediction).unwrap();
            assert!(lean.corr23.is_some() && lean.integral_q.is_some() && lean.pairs_not_computed.is_none());
        }
    }
}

#[test]
fn correlation_at_zero_separation_is_the_second_moment() {
    for name in ORDER0_SCENES {
        let s = scene(name);
        let field = Field::from_scene(&s, &0.0f64).unwrap();
        let r = s.estimator.radius;
        // x = s − field.center; the identity holds at every point.
        for x in [-0.9, -0.5, 0.0, 0.1, 0.3, 1.0, 5.0] {
            let (c, m) = (pointwise(&field, &x, &0.0, &r), second_moment(&field, &x, &r));
            assert!((c - m).abs() <= 1e-14 * m.abs(), "{name} s={x}: {c} vs {m}");
        }
    }
}

#[test]
fn asymptotic_forms_converge_at_first_order() {
    for name in ORDER0_SCENES {
        let gaps: Vec<[f64; 2]> = [1e-2, 1e-3, 1e-4]
            .iter()
            .map(|&r| {
                let rep = oracle(&with_radius(scene(name), r));
                [1.0 - c23(&rep).ratio.unwrap(), 1.0 - c24(&rep).ratio.unwrap()]
            })
            .collect();
        for k in 0..2 {
            for w in gaps.windows(2) {
                let factor = w[0][k] / w[1][k];
                assert!((8.0..=12.0).contains(&factor), "{name} ({}) gap {:e} -> {:e}", 23 + k, w[0][k], w[1][k]);
            }
            assert!(gaps[2][k].abs() <= 4e-4, "{name}: |1 - ratio| = {:e} at R = 1e-4", gaps[2][k]);
        }
    }
}

/// Issue 3's convergence point as restated (issue 9): at R = 10⁻⁴ every
/// bundled scene, single-scattered light included, has |1 − ratio| ≤ 4·10⁻⁴
/// for (23) and (24) (the per-scene remainder coefficients are fitted in
/// `docs/asymptotic-checks.md`). The order-0 scenes are checked above; this
/// is the order-1 scene (~10 s).
#[test]
fn single_scattered_light_converges_to_4e_4_at_r_1e_4() {
    let r = oracle(&with_radius(scene("point-isotropic-order1"), 1e-4));
    for (label, c) in [("(23)", c23(&r)), ("(24)", c24(&r))] {
        let (ratio, bar) = (c.ratio.unwrap(), c.ratio_error.unwrap());
        assert!((1.0 - ratio).abs() + bar <= 4e-4, "{label}: ratio {ratio} ± {bar:e} at R = 1e-4");
    }
}

/// f64 and 128 bits on the order-0 scenes. The README's scene runs at the
/// 128-bit default goal (~10⁻³²); the other three at 10⁻²⁰, whose bars are
/// still 10¹² below f64's, so the comparison is as sharp, in half the time
/// (the four at the default goal took ~200 s of CI on two cores).
#[test]
fn f64_and_128_bits_agree_within_their_bars() {
    for name in ORDER0_SCENES {
        let s = scene(name);
        let a = oracle(&s);
        let goal = if name == "point-isotropic" { None } else { Some(1e-20) };
        let b = run(&s, Precision::Bits(128), goal).unwrap_or_else(|e| panic!("{name} at 128 bits: {e}"));
        let close = |x: f64, ex: f64, y: f64, ey: f64, what: &str| {
            assert!((x - y).abs() <= ex + ey, "{name} {what}: f64 {x:e} ± {ex:e} vs 128-bit {y:e} ± {ey:e}");
        };
        close(a.mean_luminance.value, a.mean_luminance.error, b.mean_luminance.value, b.mean_luminance.error, "mean");
        close(c23(&a).exact.value, c23(&a).exact.error, c23(&b).exact.value, c23(&b).exact.error, "(23)");
        close(c24(&a).exact.value, c24(&a).exact.error, c24(&b).exact.value, c24(&b).exact.error, "(24)");
        close(
            a.variance.as_ref().unwrap().exact.value,
            a.variance.as_ref().unwrap().exact.error,
            b.variance.as_ref().unwrap().exact.value,
            b.variance.as_ref().unwrap().exact.error,
            "Var",
        );
        let (fa, fb) = (a.finite.as_ref().unwrap(), b.finite.as_ref().unwrap());
        for (what, x, y) in [
            ("finite mean", fa.mean, fb.mean),
            ("finite Var", fa.variance, fb.variance),
            ("finite (23)", fa.corr23.unwrap().into(), fb.corr23.unwrap().into()),
            ("finite (24)", fa.corr24.unwrap().into(), fb.corr24.unwrap().into()),
            ("finite P", fa.integral_p.into(), fb.integral_p.into()),
            ("finite Q", fa.integral_q.unwrap().into(), fb.integral_q.unwrap().into()),
        ] {
            let (x, y): (mcrt_noise::oracle::ValueWithBar, mcrt_noise::oracle::ValueWithBar) = (x, y);
            close(x.value, x.error, y.value, y.error, what);
        }
    }
}

/// Every hard case converges to finite numbers with finite bars.
fn assert_sane(rep: &Report, what: &str) {
    let finite = [
        rep.mean_luminance.value,
        c23(rep).exact.value,
        c24(rep).exact.value,
        rep.variance.as_ref().unwrap().exact.value,
        rep.variance.as_ref().unwrap().relative,
        rep.variance.as_ref().unwrap().relative_error,
    ];
    assert!(finite.iter().all(|v| v.is_finite()), "{what}: {finite:?}");
    assert!(
        rep.variance.as_ref().unwrap().relative > 0.0,
        "{what}: relative noise {}",
        rep.variance.as_ref().unwrap().relative
    );
    assert!(
        rep.variance.as_ref().unwrap().relative_error <= 1e-6 * rep.variance.as_ref().unwrap().relative,
        "{what}: bar {}",
        rep.variance.as_ref().unwrap().relative_error
    );
}

#[test]
fn hard_cases_stay_finite_and_converged() {
    let base = scene("point-isotropic");
    assert_sane(&oracle(&with_radius(base.clone(), 1e-10)), "R = 1e-10");
    for q in [1e-3, 1.0] {
        let mut s = base.clone();
        s.estimator.q = q;
        assert_sane(&oracle(&s), &format!("q = {q}"));
    }
    let mut s = base.clone();
    s.estimator.forward_rays = 1;
    s.estimator.camera_rays = 1;
    assert_sane(&oracle(&s), "N_F = N_B = 1");
    for g in [0.99, -0.99] {
        let mut s = base.clone();
        s.medium.phase = mcrt_scene::Phase::HenyeyGreenstein { g };
        assert_sane(&oracle(&s), &format!("g = {g}"));
    }
    // σ_ext × (light–camera distance) = 700: e^{-σr} and its square underflow f64.
    let mut s = base.clone();
    s.medium.sigma_ext = 700.0 / 2f64.sqrt();
    let rep = oracle(&s);
    assert!(
        rep.variance.as_ref().unwrap().relative.is_finite() && rep.variance.as_ref().unwrap().relative > 1e290,
        "σr = 700: {}",
        rep.variance.as_ref().unwrap().relative
    );
    assert!(rep.mean_luminance_log10 < -290.0 && rep.mean_luminance_log10.is_finite());
}

/// A light 10⁻⁶ from the camera line: its irradiance is a Lorentzian of
/// width 10⁻⁶ and height 10¹² along the ray, well inside one sphere radius.
/// At the default 1e-10 the two rules disagree by ~5e-10 there (the engine
/// says NOT CONVERGED); at 1e-9 both the value and its bar are sound: the
/// correlation integrals agree with runs at 1e-4…1e-7 to their bars.
#[test]
fn light_nearly_on_the_camera_line() {
    for (pos, label) in [([1e-6, 0.0, 2.0], "ahead (θ → π)"), ([1e-6, 0.0, -2.0], "behind (θ → 0)")] {
        let mut s = scene("point-isotropic");
        s.lights[0] = mcrt_scene::Light::Point { position: mcrt_scene::DVec3::from_array(pos), flux: 1.0 };
        let fine = run(&s, Precision::F64, Some(1e-9)).unwrap_or_else(|e| panic!("{label}: {e}"));
        assert_sane(&fine, label);
        let coarse = run(&s, Precision::F64, Some(1e-6)).unwrap_or_else(|e| panic!("{label}: {e}"));
        let (a, b) = (&c23(&fine).exact, &c23(&coarse).exact);
        assert!(
            (a.value - b.value).abs() <= a.error + b.error,
            "{label}: {} ± {} vs {} ± {}",
            a.value,
            a.error,
            b.value,
            b.error
        );
    }
}

#[test]
fn light_on_the_line_behind_the_camera_has_no_asymptotic_form() {
    let mut s = scene("point-isotropic");
    s.lights[0] = mcrt_scene::Light::Point { position: mcrt_scene::DVec3::new(0.0, 0.0, -2.0), flux: 1.0 };
    let rep = oracle(&s);
    assert!(c23(&rep).asymptotic.missing.as_deref().unwrap_or("").contains("does not exist"));
    assert!(rep.variance.as_ref().unwrap().relative_asymptotic.is_none());
    assert_sane(&rep, "light on the line behind");
}

#[test]
fn orders_beyond_one_and_what_a_scattered_beam_lacks_are_refused_clearly() {
    let mut s = scene("point-isotropic-order1");
    s.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(2);
    let err = run(&s, Precision::F64, None).unwrap_err().to_string();
    assert!(err.contains("scattering_orders = 2") && err.contains("allowed: 0 or 1"), "{err}");
    s.effects.scattering_orders = mcrt_scene::ScatteringOrders::All;
    let err = run(&s, Precision::F64, None).unwrap_err().to_string();
    assert!(err.contains("scattering_orders = \"all\""), "{err}");
    // A beam at order 1 in a Henyey–Greenstein medium is refused, naming
    // the field (in an isotropic medium it is predicted, q < 1 and N_B > 1
    // included: `a_beams_small_sphere_pairs_form_var_l`).
    let mut b = scene("beam-isotropic");
    b.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(1);
    b.medium.phase = mcrt_scene::Phase::HenyeyGreenstein { g: 0.5 };
    let err = run(&b, Precision::F64, None).unwrap_err().to_string();
    assert!(err.contains("beam") && err.contains("medium.phase") && err.contains("isotropic"), "{err}");
}

/// The `oracle --json` numbers of every order-0 bundled scene, pinned at
/// 8 significant digits (error bars: their decade). Evaluation counts and
/// times are left out: they follow engine tuning, not the model.
#[test]
fn oracle_reports_are_pinned() {
    for name in ORDER0_SCENES {
        let text = report_text(&oracle(&scene(name)), 8);
        insta::with_settings!({snapshot_path => "../snapshots", prepend_module_to_snapshot => false}, {
            insta::assert_snapshot!(format!("oracle_{name}"), text);
        });
    }
}

/// The report's numbers at `digits` significant digits (error bars: their decade).
fn report_text(r: &Report, digits: usize) -> String {
    let sig = |v: f64| format!("{v:.*e}", digits - 1);
    let decade = |v: f64| if v > 0.0 { format!("<= 1e{}", v.log10().ceil() as i32) } else { "0".into() };
    let mut out = String::new();
    out.push_str(&format!("mean_luminance {} ({})\n", sig(r.mean_luminance.value), decade(r.mean_luminance.error)));
    for (label, c) in [("corr23", c23(r)), ("corr24", c24(r))] {
        out.push_str(&format!("{label}.exact {} ({})\n", sig(c.exact.value), decade(c.exact.error)));
        out.push_str(&format!("{label}.asymptotic {}\n", c.asymptotic.value.map_or("none".into(), sig)));
        out.push_str(&format!("{label}.ratio {}\n", c.ratio.map_or("none".into(), sig)));
    }
    out.push_str(&format!(
        "variance.exact {} ({})\n",
        sig(r.variance.as_ref().unwrap().exact.value),
        decade(r.variance.as_ref().unwrap().exact.error)
    ));
    out.push_str(&format!("variance.relative {}\n", sig(r.variance.as_ref().unwrap().relative)));
    out.push_str(&format!(
        "variance.relative_asymptotic {}\n",
        r.variance.as_ref().unwrap().relative_asymptotic.map_or("none".into(), sig)
    ));
    if let Some(d) = r.d {
        out.push_str(&format!("D1..D5 {}\n", d.iter().map(|v| sig(*v)).collect::<Vec<_>>().join(" ")));
    }
    if let Some(f) = &r.finite_mean {
        let (m, b) = (f.mean.expect("the finite mean"), f.bias.expect("its bias"));
        out.push_str(&format!("finite_mean {} ({})\n", sig(m.value), decade(m.error)));
        out.push_str(&format!("finite_bias {} ({})\n", sig(b.value), decade(b.error)));
    }
    if let Some(m) = &r.integral_m2_same_path {
        out.push_str(&format!("integral_m2_same_path {} ({})\n", sig(m.value), decade(m.error)));
    }
    out
}

/// The order-1 scene at its default tolerance (1e-6 in f64): converged,
/// every bar within the goal, the scattered light adding to the uncollided
/// mean, the ratios below 1 and close to it at R = 0.01 (first order in R,
/// as for order 0), pinned at 6 significant digits (the bars are ~10⁻⁸
/// relative). About a minute in release mode on two cores.
#[test]
fn order_one_report_is_consistent_and_pinned() {
    let s = scene("point-isotropic-order1");
    let r = oracle(&s);
    assert_eq!(r.rel_tol, 1e-6);
    let mut direct = s.clone();
    direct.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(0);
    let r0 = oracle(&direct);
    assert!(r.mean_luminance.value > r0.mean_luminance.value, "scattered light adds to the mean");
    for (label, v, e) in [
        ("mean", r.mean_luminance.value, r.mean_luminance.error),
        ("corr23", c23(&r).exact.value, c23(&r).exact.error),
        ("corr24", c24(&r).exact.value, c24(&r).exact.error),
        ("variance", r.variance.as_ref().unwrap().exact.value, r.variance.as_ref().unwrap().exact.error),
    ] {
        assert!(v.is_finite() && v > 0.0 && e <= 1e-6 * v, "{label}: {v} ± {e}");
    }
    for c in [c23(&r), c24(&r)] {
        let ratio = c.ratio.unwrap();
        assert!(ratio < 1.0 && ratio > 0.95, "ratio {ratio}");
    }
    insta::with_settings!({snapshot_path => "../snapshots", prepend_module_to_snapshot => false}, {
        insta::assert_snapshot!("oracle_point-isotropic-order1", report_text(&r, 6));
    });
}

/// The R → 0 sweep tables (ratios at 9 significant digits, fitted orders at
/// 4), pinned for every order-0 bundled scene.
#[test]
fn sweep_tables_are_pinned() {
    use mcrt_noise::model::correlations::Which;
    use mcrt_noise::reports::sweep::{fit_order, sweep, DOC_RADII};
    for name in ORDER0_SCENES {
        let rows = sweep(&scene(name), &DOC_RADII).unwrap();
        let mut out = String::from("R | ratio (23) | ratio (24)\n");
        for r in &rows {
            out.push_str(&format!("{:.0e} | {:.8e} | {:.8e}\n", r.radius, r.ratio23, r.ratio24));
        }
        for (label, which) in [("order (23)", Which::Eq23), ("order (24)", Which::Eq24)] {
            let o = fit_order(&rows, which).unwrap();
            out.push_str(&format!("{label} {:.4}\n", o.order));
        }
        insta::with_settings!({snapshot_path => "../snapshots", prepend_module_to_snapshot => false}, {
            insta::assert_snapshot!(format!("sweep_{name}"), out);
        });
    }
}

/// A beam crossing the camera ray at right angles has μ = 0 and a constant
/// irradiance W on [s_in, s_out], so every integral has a closed form, with
/// the inner separation integral J = ∫₀^{2R} A(t/2R) e^{−σt} dt from the
/// quadrature-free series (`kernel_series_reference`, c = 1):
/// mean = albedo f W (e^{−s_in} − e^{−s_out}), (23) = K f² W (e^{−s_in} − e^{−s_out}) J,
/// (24) = K f² W (e^{−2s_in} − e^{−2s_out}) J, (25) = 8 albedo² 𝓕 f² W (e^{−s_in} − e^{−s_out})/(3π²R),
/// with σ = 1, f = 1/4π, K = 2 albedo² 𝓕/(π²R²). Tolerance: the oracle's own bars.
#[test]
fn beam_at_right_angles_matches_closed_forms() {
    use mcrt_noise::kernel::kernel_series_reference;
    use rug::Float;
    use std::f64::consts::PI;
    let s = scene("beam-isotropic");
    let rep = oracle(&s);
    let (albedo, flux, r) = (s.medium.albedo, s.total_flux(), s.estimator.radius);
    let f = 1.0 / (4.0 * PI);
    let w = flux / (PI * 0.5 * 0.5) * (-2.0f64).exp(); // depth 2 inside the beam
    let (s_in, s_out) = (0.5f64, 1.5f64);
    let k = 2.0 * albedo * albedo * flux / (PI * PI * r * r);
    let j = kernel_series_reference(&Float::with_val(256, 1), &Float::with_val(256, 0), &Float::with_val(256, r), 256)
        .to_f64();
    let e1 = (-s_in).exp() - (-s_out).exp();
    let e2 = (-2.0 * s_in).exp() - (-2.0 * s_out).exp();
    let check = |what: &str, got: f64, bar: f64, want: f64| {
        assert!(
            (got - want).abs() <= bar + 4.0 * f64::EPSILON * want.abs(),
            "{what}: {got:e} ± {bar:e} vs closed form {want:e}"
        );
    };
    check("mean", rep.mean_luminance.value, rep.mean_luminance.error, albedo * f * w * e1);
    check("(23)", c23(&rep).exact.value, c23(&rep).exact.error, k * f * f * w * e1 * j);
    check("(24)", c24(&rep).exact.value, c24(&rep).exact.error, k * f * f * w * e2 * j);
    let asym = 8.0 * albedo * albedo * flux * f * f * w * e1 / (3.0 * PI * PI * r);
    check("(25)", c23(&rep).asymptotic.value.unwrap(), c23(&rep).asymptotic.error.unwrap(), asym);
}

#[test]
fn a_beam_that_misses_the_camera_ray_gets_a_clear_answer() {
    let mut s = scene("beam-isotropic");
    s.lights[0] = mcrt_scene::Light::Beam {
        center: mcrt_scene::DVec3::new(-2.0, 3.0, 1.0),
        direction: mcrt_scene::DVec3::X,
        radius: 0.5,
        flux: 1.0,
    };
    let err = run(&s, Precision::F64, None).unwrap_err().to_string();
    assert!(err.contains("meets no light"), "{err}");
}

#[test]
fn a_dark_pixel_is_said_to_be_dark_not_nan() {
    let mut s = scene("point-isotropic");
    s.medium.albedo = 0.0;
    let err = run(&s, Precision::F64, None).unwrap_err().to_string();
    assert!(err.contains("albedo = 0") && err.contains("undefined"), "{err}");
}

/// Long (~2 min in release on two cores; run with
/// `cargo test --release --test oracle -- --ignored order_one_remainder`):
/// for single-scattered light, which is non-zero along the view direction,
/// |1 − ratio| = R (a + b ln(1/R)) with b > 0, the logarithmic term the
/// derivation predicts (`docs/asymptotic-checks.md`); for the uncollided
/// scene b is zero within its fit error. Judged by the fits' own standard
/// errors (b > 10 σ_b for order 1, |b| < 3 σ_b + 10⁻³ |a| for order 0).
#[test]
#[ignore]
fn order_one_remainder_has_a_log_term() {
    use mcrt_noise::model::correlations::Which;
    use mcrt_noise::reports::sweep::{fit_log_term, sweep};
    // Radii where 1 − ratio is resolved at the default tolerance (> 100 bars).
    let radii = [1e-1, 1e-2, 1e-3, 1e-4];
    let rows = sweep(&scene("point-isotropic-order1"), &radii).unwrap();
    let (_, _, b, be) = fit_log_term(&rows, Which::Eq23).unwrap();
    assert!(b > 10.0 * be && b > 0.0, "order 1: b = {b} ± {be}");
    let rows = sweep(&scene("point-isotropic"), &radii).unwrap();
    let (a, _, b, be) = fit_log_term(&rows, Which::Eq23).unwrap();
    assert!(b.abs() < 3.0 * be + 1e-3 * a.abs(), "order 0: b = {b} ± {be}, a = {a}");
}

/// Hard cases of the single-scattered field (~40 s in release): a
/// strongly forward phase function (g = 0.99, whose f² peak of width
/// 1 − g = R makes the R → 0 form far off at R = 0.01: ratio ≈ 0.13) and
/// R = 10⁻¹⁰ (ratio within 10⁻⁸ of 1): converged, every bar within the
/// goal, nothing NaN. The slower ones (g = −0.99, σ_ext = 50: ~35–45 s
/// each) are in `order_one_slow_hard_cases`, ignored by default.
#[test]
fn order_one_hard_cases() {
    let mut hg = scene("point-isotropic-order1");
    hg.medium.phase = mcrt_scene::Phase::HenyeyGreenstein { g: 0.99 };
    let r = oracle(&hg);
    assert_order_one_sane(&r, "g = 0.99");
    let ratio = c23(&r).ratio.unwrap();
    assert!(ratio > 0.05 && ratio < 0.5, "g = 0.99: ratio {ratio}");
    let r = oracle(&with_radius(scene("point-isotropic-order1"), 1e-10));
    assert_order_one_sane(&r, "R = 1e-10");
    for c in [c23(&r), c24(&r)] {
        assert!((1.0 - c.ratio.unwrap()).abs() < 1e-8, "R = 1e-10: ratio {:?}", c.ratio);
    }
}

/// `cargo test --release --test oracle -- --ignored order_one_slow_hard_cases` (~80 s).
#[test]
#[ignore]
fn order_one_slow_hard_cases() {
    let mut hg = scene("point-isotropic-order1");
    hg.medium.phase = mcrt_scene::Phase::HenyeyGreenstein { g: -0.99 };
    assert_order_one_sane(&oracle(&hg), "g = -0.99");
    let mut dense = scene("point-isotropic-order1");
    dense.medium.sigma_ext = 50.0;
    assert_order_one_sane(&oracle(&dense), "sigma_ext = 50");
}

fn assert_order_one_sane(r: &Report, what: &str) {
    for (label, v, e) in [
        ("mean", r.mean_luminance.value, r.mean_luminance.error),
        ("corr23", c23(r).exact.value, c23(r).exact.error),
        ("corr24", c24(r).exact.value, c24(r).exact.error),
        ("variance", r.variance.as_ref().unwrap().exact.value, r.variance.as_ref().unwrap().exact.error),
    ] {
        assert!(v.is_finite() && v > 0.0 && e.is_finite() && e <= r.rel_tol * v, "{what}: {label} {v} ± {e}");
    }
    // The ratio is of the one-segment part (without the cross-segment term
    // of E10), which lies below its R → 0 form.
    for c in [c23(r), c24(r)] {
        let ratio = c.ratio.unwrap();
        assert!(ratio > 0.0 && ratio <= 1.0, "{what}: ratio {ratio}");
    }
}

/// A beam beside the camera ray, along it at distance 1 (farther than its
/// radius 0.5 plus R = 0.2): no uncollided ray reaches a sphere, only its
/// single-scattered light does. The small-sphere same-path hits (E9) are
/// then exactly 0 — not an underflow — and the oracle predicts the scene
/// (it refused it as "not representable: M₂ same-path hits is 0 ± 7e-293"
/// until 6 December 2026).
#[test]
fn a_beam_beside_the_camera_ray_has_no_same_path_hits() {
    use mcrt_scene::{DVec3, Light, ScatteringOrders};
    let mut s = with_radius(scene("beam-isotropic"), 0.2);
    let Light::Beam { radius, flux, .. } = s.lights[0] else { panic!("a beam") };
    s.lights[0] =
        Light::Beam { center: DVec3::new(1.0, 0.0, -1.0), direction: DVec3::new(0.0, 0.0, 1.0), radius, flux };
    s.effects.scattering_orders = ScatteringOrders::Limited(1);
    (s.estimator.q, s.estimator.camera_rays) = (1.0, 1);
    let rep =
        mcrt_noise::oracle::run_within(&s, Precision::F64, Some(1e-4), &mcrt_noise::quad::Budget::new(2_000_000_000))
            .unwrap();
    let same_path = rep.integral_m2_same_path.as_ref().unwrap();
    assert_eq!(same_path.value, 0.0);
    assert_eq!(rep.prediction.model, "finite-sphere");
    assert!(
        rep.prediction.variance.value > 0.0 && rep.prediction.variance.error < 1e-4 * rep.prediction.variance.value
    );
}

/// A beam's single-scattered light with q < 1 and N_B > 1: the small-sphere
/// model forms Var L with its pair integrals (23), (24) from the beam's
/// radiance by direction (`docs/model.md` §3a), without the cross-segment
/// terms of E10, which are derived for point lights only (the report says
/// so). `beam-isotropic` at order 1, R = 0.2, q = 0.5, N_F = 20, N_B = 8
/// at 10⁻³ (~10 s): the finite-sphere model is 4.210253·10⁻⁵, of which its
/// two-segment pairs 3.61·10⁻⁶ (§9.11); without them it is 3.849·10⁻⁵, and
/// the small-sphere Var L must lie within 1 % of that (the O(R) of the
/// one-segment terms: 0.3 % measured, and their R → 0 limit in
/// `tests/finite_order1_beams.rs`).
#[test]
fn a_beams_small_sphere_pairs_form_var_l() {
    use mcrt_scene::ScatteringOrders;
    let mut s = with_radius(scene("beam-isotropic"), 0.2);
    s.effects.scattering_orders = ScatteringOrders::Limited(1);
    s.estimator.forward_rays = 20;
    let rep =
        mcrt_noise::oracle::run_within(&s, Precision::F64, Some(1e-3), &mcrt_noise::quad::Budget::new(2_000_000_000))
            .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(rep.prediction.model, "small-sphere");
    let var = rep.variance.as_ref().expect("the small-sphere Var L");
    assert!(var.exact.error < 1e-3 * var.exact.value, "{:?}", var.exact);
    for c in [c23(&rep), c24(&rep)] {
        let why = c.cross_segment_not_added.as_deref().unwrap_or("");
        assert!(why.contains("point lights only"), "{why}");
    }
    let finite_without_cross = 4.210253e-5 - 3.61e-6;
    let gap = var.exact.value / finite_without_cross - 1.0;
    assert!(gap.abs() < 1e-2, "small-sphere Var L {:e} against {finite_without_cross:e}", var.exact.value);
}
