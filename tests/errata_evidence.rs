//! The reference tracer decides between the paper's formulas and the
//! corrected ones (`docs/errata.md`). For each erratum with a numerical
//! consequence, the paper's version of the prediction is formed from the
//! oracle's integrals (the only change being the erratum), and the tracer's
//! measurement must reject it while agreeing with the corrected prediction.
//!
//! Agreement: |tracer − prediction| ≤ 4 se + ε·|prediction|, ε the oracle
//! model's own error measured for this scene at R = 0.1 (q = 0.5, N_F = 200,
//! N_B = 8: mean 0.43 %, variance 1.75 %, plus two standard errors;
//! `docs/tracer-checks.md`), carried to R by `prec::model_error_scale`.
//! Rejection: even after the whole model allowance, the paper's version is
//! more than 6 standard errors away, (|tracer − paper| − ε·|paper|)/se > 6
//! (a normal tail of 10⁻⁹).
//!
//! E9 (same-path double hits, scattered light) is checked with no
//! allowance on a scene where nothing but M₂ enters Var L (see its test).
//!
//! Run with `cargo test --release --test errata_evidence -- --nocapture` to
//! see the table quoted in `docs/errata.md`.

use mcrt_noise::oracle::{run, Precision, Report};
use mcrt_noise::prec::model_error_scale;
use mcrt_reference::moments::WithError;
use mcrt_reference::{trace, HitMethod, Tracer};
use mcrt_scene::{DVec3, Light, Phase, Scene};
use std::path::Path;

/// (23) of a report of every integral (`run`).
fn c23(r: &Report) -> &mcrt_noise::oracle::Correlation {
    r.corr23.as_ref().expect("a run of every integral has (23)")
}

/// (24) of a report of every integral (`run`).
fn c24(r: &Report) -> &mcrt_noise::oracle::Correlation {
    r.corr24.as_ref().expect("a run of every integral has (24)")
}

/// Model error of `point-isotropic` at R = 0.1 (|ratio − 1| + 2 se): mean, variance.
const MODEL_AT_R0: (f64, f64) = (0.0056, 0.020);

fn scene(radius: f64) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/point-isotropic.toml");
    let mut s = Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    s.estimator.radius = radius;
    s
}

/// Var L from (7)–(9) with the report's integrals, C₂₃ and C₂₄ scaled by
/// `corr`, every integral by `albedo_power` (the paper's (19), (20) without
/// the albedo) and the −μ² terms as given by `mu2_weight`.
fn variance(r: &Report, corr: f64, mu2_weight: Option<f64>, inflate: f64) -> f64 {
    let (q, nf, nb) = (r.q, r.forward_rays as f64, r.camera_rays as f64);
    let w_a = 1.0 / (nf * nb);
    let w_b = 1.0 / nb - w_a;
    let w_c = 1.0 / nf - w_a;
    let w_mu2 = mu2_weight.unwrap_or(w_a - 1.0 / nb - 1.0 / nf);
    let a = q * r.integral_m2.value + 2.0 * (1.0 - q) * corr * c23(r).exact.value;
    let b = q * r.integral_p.value + 2.0 * (1.0 - q) * r.integral_q.unwrap().value;
    let c = corr * c24(r).exact.value;
    let mu = r.mean_luminance.value;
    inflate * (w_a * a + w_b * b + w_c * c + w_mu2 * mu * mu)
}

struct Verdict {
    name: &'static str,
    corrected: f64,
    paper: f64,
    tracer: WithError,
    model: f64,
}

impl Verdict {
    fn check(&self) {
        let (dc, dp) = ((self.tracer.value - self.corrected).abs(), (self.tracer.value - self.paper).abs());
        println!(
            "{:<44} corrected {:.5e} (tracer/it {:.4}), paper {:.5e} (tracer/it {:.4}), tracer {:.5e} ± {:.1e}, \
             allowance {:.1e}",
            self.name,
            self.corrected,
            self.tracer.value / self.corrected,
            self.paper,
            self.tracer.value / self.paper,
            self.tracer.value,
            self.tracer.se,
            self.model * self.corrected
        );
        let z_paper = (dp - self.model * self.paper.abs()) / self.tracer.se;
        println!("{:<44} paper rejected at {z_paper:.1} se beyond the model allowance", "");
        assert!(
            dc <= 4.0 * self.tracer.se + self.model * self.corrected.abs(),
            "{}: the corrected prediction disagrees",
            self.name
        );
        assert!(z_paper > 6.0, "{}: the tracer does not reject the paper's version", self.name);
    }
}

fn measure(radius: f64, trials: u64) -> (Report, WithError, WithError) {
    let s = scene(radius);
    let report = run(&s, Precision::F64, None).unwrap();
    let summary = trace(&Tracer::new(&s).unwrap(), 77, 0..trials, HitMethod::Sorted, &|_| {}).summary().unwrap();
    (report, summary.mean, summary.variance)
}

#[test]
fn tracer_rejects_the_papers_formulas_and_accepts_the_corrected_ones() {
    // R = 0.01 (the bundled scene): correlations and the albedo.
    let (r, mean, var) = measure(0.01, 4_000_000);
    let scale = model_error_scale(0.01);
    let (em, ev) = (MODEL_AT_R0.0 * scale, MODEL_AT_R0.1 * scale);
    let albedo = 0.8;
    let mu = r.mean_luminance.value;
    let exact = variance(&r, 1.0, None, 1.0);
    assert!((exact - r.variance.as_ref().unwrap().exact.value).abs() <= 1e-12 * exact, "variance recomposed: {exact}");
    let verdicts = [
        Verdict { name: "E1 (10): mean squared", corrected: mu, paper: mu * mu, tracer: mean, model: em },
        Verdict {
            name: "E7 (19): mean without the albedo",
            corrected: mu,
            paper: mu / albedo,
            tracer: mean,
            model: em,
        },
        Verdict {
            name: "E7 (19), (20): Var without the albedo",
            corrected: exact,
            paper: variance(&r, 1.0, None, 1.0 / (albedo * albedo)),
            tracer: var,
            model: ev,
        },
        Verdict {
            name: "E2+E3 (21) as printed: correlations / 4",
            corrected: exact,
            paper: variance(&r, 0.25, None, 1.0),
            tracer: var,
            model: ev,
        },
        Verdict {
            name: "E6 (25), (26) as printed: correlations / 2",
            corrected: exact,
            paper: variance(&r, 0.5, None, 1.0),
            tracer: var,
            model: ev,
        },
    ];
    verdicts.iter().for_each(Verdict::check);

    // R = 0.1, where μ² is a larger part of Var: the −μ² terms of §4.4.
    let (r, _, var) = measure(0.1, 2_000_000);
    let (nf, nb) = (r.forward_rays as f64, r.camera_rays as f64);
    Verdict {
        name: "E8 §4.4: only −μ²/(N_F N_B) kept",
        corrected: variance(&r, 1.0, None, 1.0),
        paper: variance(&r, 1.0, Some(-1.0 / (nf * nb)), 1.0),
        tracer: var,
        model: MODEL_AT_R0.1,
    }
    .check();
}

/// `point-isotropic-order1` (uncollided plus single-scattered light) at
/// R = 0.1 with q = 1 and N_F = N_B = 1, so that Var L = M₂ − μ²: no
/// correlation integral enters, and the same-path double hits of E9 are
/// 5 % of Var L.
fn order1_scene() -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/point-isotropic-order1.toml");
    let mut s = Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    s.estimator.radius = 0.1;
    s.estimator.q = 1.0;
    s.estimator.forward_rays = 1;
    s.estimator.camera_rays = 1;
    s
}

/// The prediction with E9's term (corrected), without it (the paper's
/// (20)), and the tracer's Var L.
fn same_path_verdict(name: &'static str, s: &Scene, trials: u64) -> Verdict {
    let r = run(s, Precision::F64, None).unwrap();
    let tracer = trace(&Tracer::new(s).unwrap(), 77, 0..trials, HitMethod::Sorted, &|_| {}).summary().unwrap().variance;
    let same = r.integral_m2_same_path.expect("order-1 scenes report M₂ₓ").value;
    let corrected = r.variance.as_ref().unwrap().exact.value;
    Verdict { name, corrected, paper: corrected - same, tracer, model: 0.0 }
}

/// E9: one forward path can hit a sphere with two segments (the first
/// passes it and scatters close by, the second comes back through it); the
/// paper's (20) counts one segment per hit. No model allowance: at R = 0.1
/// the small-sphere model's remaining error in M₂ is O(R²), below these
/// standard errors (`docs/model.md` §3b).
#[test]
fn tracer_finds_the_same_path_double_hits() {
    same_path_verdict("E9 (20): no same-path double hits", &order1_scene(), 50_000_000).check();
}

/// E9 in a backward-peaked Henyey–Greenstein medium (g = −0.5, albedo 0.9,
/// the light off the camera's plane), where the kernel K weights
/// backscatter: 10⁸ trials, ~1 min in release mode. Agreement only: the
/// term is 5.8 % of Var L here, but the small-sphere model's O(R²) error
/// is of the order of 1 % at R = 0.1 in this medium (its mean is 1 % below
/// the tracer's), too close to separate the two at feasible trial counts;
/// the kernel itself is checked by quadrature (`tests/same_path.rs`), the
/// finite-sphere model will settle the rest.
#[test]
#[ignore = "E9 with a Henyey–Greenstein kernel, ~1 min in release mode"]
fn same_path_double_hits_in_a_backward_peaked_medium_agree() {
    let mut s = order1_scene();
    s.medium.phase = Phase::HenyeyGreenstein { g: -0.5 };
    s.medium.albedo = 0.9;
    s.lights[0] = Light::Point { position: DVec3::new(0.7, 0.4, 1.6), flux: 1.0 };
    let v = same_path_verdict("E9 (20), HG g = −0.5", &s, 100_000_000);
    let z = (v.tracer.value - v.corrected) / v.tracer.se;
    let z_paper = (v.tracer.value - v.paper) / v.tracer.se;
    println!(
        "E9, HG g = −0.5: corrected {:.5e}, paper {:.5e}, tracer {:.5e} ± {:.1e}: z = {z:.2}, paper z = {z_paper:.2}",
        v.corrected, v.paper, v.tracer.value, v.tracer.se
    );
    assert!(z.abs() <= 4.0, "E9 with HG g = −0.5: the corrected prediction disagrees, z = {z}");
}
