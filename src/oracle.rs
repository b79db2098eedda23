//! The oracle end to end: scene → field → integrals → variance, at a chosen
//! precision, as a serialisable report (`mcrt-noise oracle SCENE --json`).
//!
//! Two models are computed side by side: the small-sphere model of §4.3
//! (exact only as R → 0; its exact (23), (24), their R → 0 forms and the
//! §4.4 formula) and, for uncollided light, the finite-sphere model
//! (`model::finite`, exact at the scene's R). The report's `prediction` is
//! the finite-sphere model where it exists, the small-sphere one otherwise,
//! and says which.

use crate::model::field::{beam_interval, Field};
use crate::model::finite::{FiniteField, FiniteIntegrals, Functional};
use crate::model::noise::{
    d_constants, d_errors, relative_from_d, relative_from_d_error, variance, Counts, Integrals, Valued,
};
use crate::model::OracleError;
use crate::quad::{Budget, CheckRule, Estimate, Options};
use crate::real::Real;
use mcrt_scene::{Light, Scene};
use serde::Serialize;
use std::time::Instant;

/// The largest MPFR precision a run accepts: its default tolerance
/// 2^{−(bits − 22)} is then 2^{−1002} ≈ 2.3·10⁻³⁰², still a normal double
/// (tolerances are f64; past ~1044 bits the default underflowed to 0 and
/// every integral was refused).
pub const MAX_BITS: u32 = 1024;

/// The most lights a scene may have for the oracle. Integrals that sum
/// over the lights inside their integrand (P, Q and the finite-sphere
/// model's) cost about the square of the light count, which no evaluation
/// count bounds: 10 point lights take 0.3 s, 100 take 13 s and 1000 would
/// take ~20 min (measured on two cores; 200 000 lights, which the tracer
/// traces in a second, ran past their deadline by 40 s). Refused beyond,
/// naming `lights`, before any work.
pub const MAX_LIGHTS: usize = 100;

/// Working precision of an oracle run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Precision {
    /// IEEE double precision.
    F64,
    /// MPFR with this many bits of mantissa (32 to [`MAX_BITS`]).
    Bits(u32),
}

impl Precision {
    /// Parses `f64` or a number of bits in [32, [`MAX_BITS`]].
    pub fn parse(text: &str) -> Result<Precision, String> {
        if text == "f64" {
            return Ok(Precision::F64);
        }
        match text.parse::<u32>() {
            Ok(b) if (32..=MAX_BITS).contains(&b) => Ok(Precision::Bits(b)),
            _ => Err(format!(
                "--precision {text:?}: must be `f64` or a number of bits in [32, {MAX_BITS}] (tolerances are \
                 doubles, so the tightest is ~1e-300: more bits would only be guard digits)"
            )),
        }
    }

    /// Default evaluation budget of a run: [`crate::quad::DEFAULT_EVALUATIONS`]
    /// (10⁹, ~20 s) in f64; in MPFR, whose evaluations cost ~300 times
    /// more at 128 bits and grow roughly with the square of the precision
    /// beyond, [`crate::quad::DEFAULT_EVALUATIONS_MPFR`] (5·10⁷, a few
    /// minutes) up to 128 bits and 5·10⁷·(128/bits)² above (7.8·10⁵ at 1024
    /// bits), so that the default never means hours.
    pub fn default_evaluations(self) -> u64 {
        match self {
            Precision::F64 => crate::quad::DEFAULT_EVALUATIONS,
            Precision::Bits(b) => {
                let scale = (128.0 / f64::from(b.max(128))).powi(2);
                (crate::quad::DEFAULT_EVALUATIONS_MPFR as f64 * scale) as u64
            }
        }
    }

    /// Default relative tolerance: 1e-10 in f64, 2^{−(bits − 22)} in MPFR.
    pub fn default_tol(self) -> f64 {
        match self {
            Precision::F64 => 1e-10,
            Precision::Bits(b) => crate::prec::mpfr_default_tol(b),
        }
    }

    /// Default relative tolerance for `scene`: [`Precision::default_tol`]
    /// for uncollided light; with single-scattered light (order 1), whose
    /// integrals are three levels deeper and cost minutes at 1e-10, 1e-6 in
    /// f64 and at most 1e-10 in MPFR (`docs/accuracy-cost.md`).
    pub fn default_tol_for(self, scene: &Scene) -> f64 {
        let scattered = scene.effects.scattering_orders != mcrt_scene::ScatteringOrders::Limited(0);
        match (self, scattered) {
            (_, false) => self.default_tol(),
            (Precision::F64, true) => 1e-6,
            (Precision::Bits(_), true) => self.default_tol().max(1e-10),
        }
    }
}

/// A computed value and its error bar (a bound on |value − exact|), in f64
/// for reports. In JSON: `{"value": …, "error": …}`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ValueWithBar {
    /// The value.
    pub value: f64,
    /// Its error bar: a bound on the distance to the exact value.
    pub error: f64,
}

impl ValueWithBar {
    /// This value over `other`, the bar propagated (relative bars add).
    pub fn ratio(self, other: ValueWithBar) -> ValueWithBar {
        let value = self.value / other.value;
        ValueWithBar { value, error: value.abs() * (self.error / self.value.abs() + other.error / other.value.abs()) }
    }
}

/// A quadrature result for reports.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Integral {
    /// The integral's value.
    pub value: f64,
    /// Its error bar (the engine's cross-checked bound).
    pub error: f64,
    /// Integrand evaluations spent on it.
    pub evaluations: u64,
}

impl From<Integral> for ValueWithBar {
    fn from(i: Integral) -> Self {
        ValueWithBar { value: i.value, error: i.error }
    }
}

/// An asymptotic form: its value, or why it does not exist.
#[derive(Debug, Clone, Serialize)]
pub struct Asymptotic {
    /// The R → 0 form's value.
    pub value: Option<f64>,
    /// Its quadrature bar.
    pub error: Option<f64>,
    /// Set when the form does not exist for the scene.
    pub missing: Option<String>,
}

/// Exact and asymptotic forms of a correlation integral and their ratio.
#[derive(Debug, Clone, Serialize)]
pub struct Correlation {
    /// The integral at the scene's R.
    pub exact: Integral,
    /// Its R → 0 form, (25) or (26).
    pub asymptotic: Asymptotic,
    /// exact / asymptotic (→ 1 as R → 0).
    pub ratio: Option<f64>,
    /// The ratio's bar (the relative bars added).
    pub ratio_error: Option<f64>,
}

/// The variance of one iteration.
#[derive(Debug, Clone, Serialize)]
pub struct Variance {
    /// Var L for one iteration with the scene's N_F, N_B, q, R.
    pub exact: ValueWithBar,
    /// log₁₀ Var L (meaningful where `exact.value` underflows f64).
    pub log10: f64,
    /// Its bar, −log₁₀(1 − bar/|Var L|) ≥ the distance to the exact log₁₀
    /// (the relative bar carried through the logarithm; `None` when the bar
    /// is not below the value).
    pub log10_error: Option<f64>,
    /// Var L / ⟨⟨L⟩⟩².
    pub relative: f64,
    /// Its bar.
    pub relative_error: f64,
    /// The §4.4 formula with D₁…D₅ (corrected constant term), if (25), (26) exist.
    pub relative_asymptotic: Option<f64>,
    /// Its bar from the integrals' bars (not its asymptotic error, the O(R)
    /// gap of the R → 0 forms, which `corr23.ratio` and `corr24.ratio` show).
    pub relative_asymptotic_error: Option<f64>,
}

/// The finite-sphere model's numbers (`model::finite`), exact at the scene's R.
#[derive(Debug, Clone, Serialize)]
pub struct FiniteReport {
    /// ⟨⟨L⟩⟩ at the scene's R.
    pub mean: ValueWithBar,
    /// Var L of one iteration with the scene's N_F, N_B, q, R.
    pub variance: ValueWithBar,
    /// b(R) = ⟨⟨L⟩⟩(R) − ⟨⟨L⟩⟩(0), the estimator's bias (⟨⟨L⟩⟩(0): the
    /// small-sphere mean, the luminance of the simulated orders).
    pub bias: ValueWithBar,
    /// Var L/⟨⟨L⟩⟩².
    pub relative_noise: ValueWithBar,
    /// finite/small-sphere ratio of the mean.
    pub mean_ratio: ValueWithBar,
    /// finite/small-sphere ratio of Var L.
    pub variance_ratio: ValueWithBar,
    /// M₂ = ∫σe^{−σs}⟨𝒞²⟩_R ds of (16).
    pub integral_m2: Integral,
    /// P = ∫σe^{−σs}⟨𝒞⟩_R² ds of (17).
    pub integral_p: Integral,
    /// Q = ∫∫ σ²e^{−σ(s+s′)}⟨𝒞⟩_R(s)⟨𝒞⟩_R(s′) ds ds′ of (17).
    pub integral_q: Integral,
    /// C₂₃, the finite-sphere form of integral (23).
    pub corr23: Integral,
    /// C₂₄, the finite-sphere form of integral (24).
    pub corr24: Integral,
    /// This model's c₀ (`FiniteField::shift`).
    pub attenuation_shift: f64,
    /// Integrand evaluations of this model's integrals.
    pub evaluations: u64,
}

/// What the oracle predicts for the scene, and from which model.
#[derive(Debug, Clone, Serialize)]
pub struct ReportPrediction {
    /// `"finite-sphere"` (exact at the scene's R; uncollided light) or
    /// `"small-sphere"` (§4.3, exact as R → 0; scenes with scattered light).
    pub model: &'static str,
    /// ⟨⟨L⟩⟩ with its quadrature bar.
    pub mean: ValueWithBar,
    /// Var L of one iteration with its quadrature bar.
    pub variance: ValueWithBar,
    /// Var L/⟨⟨L⟩⟩² with its bar.
    pub relative_noise: ValueWithBar,
    /// What the bars cover.
    pub note: String,
}

/// The note of a small-sphere prediction: its own error is not in the bars.
pub const SMALL_SPHERE_NOTE: &str = "exact only as R → 0; the bars are the quadrature's and do not include the \
     model's own error at this R (the finite-sphere model covers uncollided light only; measured with the tracer on \
     point-isotropic-order1 at R = 0.1: Var L 6.7 % and the mean 0.3 % off, falling like R ln(1/R); \
     docs/tracer-checks.md)";

/// The note of a finite-sphere prediction.
pub const FINITE_NOTE: &str = "exact at this R for uncollided light; the bars are the quadrature's (the model \
     approximates nothing)";

/// Everything the oracle says about one scene.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// `"f64"` or `"N bits"`.
    pub precision: String,
    /// Relative tolerance asked of every integral.
    pub rel_tol: f64,
    /// The scene's sphere radius R.
    pub radius: f64,
    /// The scene's extinction probability per sub-step q (a parameter; the
    /// integral Q of (17) is [`Report::integral_q`]).
    pub q: f64,
    /// N_F.
    pub forward_rays: u64,
    /// N_B.
    pub camera_rays: u64,
    /// ⟨⟨L⟩⟩ of the small-sphere model, μ(0).
    pub mean_luminance: ValueWithBar,
    /// log₁₀ of the mean luminance (meaningful where `value` underflows f64).
    pub mean_luminance_log10: f64,
    /// Its bar, as [`Variance::log10_error`].
    pub mean_luminance_log10_error: Option<f64>,
    /// Integral (23), exact at R and its R → 0 form (small-sphere model).
    pub corr23: Correlation,
    /// Integral (24), likewise.
    pub corr24: Correlation,
    /// Var L of the small-sphere model, and the §4.4 formula.
    pub variance: Variance,
    /// M₂ = ∫σe^{−σs}⟨𝒞²⟩ ds, the rest of (16) beside (23).
    pub integral_m2: Integral,
    /// P = ∫σe^{−σs}⟨𝒞⟩² ds of (17).
    pub integral_p: Integral,
    /// Q = ∫∫σ²e^{−σ(s+s′)}⟨𝒞⟩(s)⟨𝒞⟩(s′) ds ds′ of (17).
    pub integral_q: Integral,
    /// c₀ = σ_ext × shortest light path to the camera ray: integrals are
    /// computed with W·e^{c₀} and scaled back for this report.
    pub attenuation_shift: f64,
    /// D₁…D₅ of §4.4, if the asymptotic forms exist.
    pub d: Option<[f64; 5]>,
    /// Their bars.
    pub d_error: Option<[f64; 5]>,
    /// Evaluations of the small-sphere model's integrals.
    pub evaluations: u64,
    /// The finite-sphere model, for uncollided light (`None` with scattered light).
    pub finite: Option<FiniteReport>,
    /// The prediction to test a renderer against: the finite-sphere model
    /// where it exists, else the small-sphere one.
    pub prediction: ReportPrediction,
    /// Wall time of the run.
    pub wall_time_ms: f64,
}

/// An estimate of the shifted field scaled back by `factor` (e^{−c₀} for
/// quantities linear in W, e^{−2c₀} for quadratic ones), for the report.
fn scaled<T: Real>(e: &Estimate<T>, factor: &T) -> Integral {
    Integral {
        value: (e.value.clone() * factor.clone()).to_f64(),
        error: (e.error.clone() * factor.clone()).to_f64(),
        evaluations: e.evaluations,
    }
}

fn correlation<T: Real>(exact: &Estimate<T>, asym: &Result<Estimate<T>, String>, k: &T) -> Correlation {
    let scaled = |e: &Estimate<T>| scaled(e, k);
    match asym {
        Ok(a) => {
            let ratio = exact.value.clone() / a.value.clone();
            let rel = exact.error.clone() / exact.value.abs() + a.error.clone() / a.value.abs();
            Correlation {
                exact: scaled(exact),
                asymptotic: Asymptotic {
                    value: Some((a.value.clone() * k.clone()).to_f64()),
                    error: Some((a.error.clone() * k.clone()).to_f64()),
                    missing: None,
                },
                ratio: Some(ratio.to_f64()),
                ratio_error: Some((ratio.abs() * rel).to_f64()),
            }
        }
        Err(why) => Correlation {
            exact: scaled(exact),
            asymptotic: Asymptotic { value: None, error: None, missing: Some(why.clone()) },
            ratio: None,
            ratio_error: None,
        },
    }
}

/// Runs the oracle on `scene` at the precision of `like` with `rel_tol`,
/// every integral of both models charged to the one `budget`.
pub fn run_with<T: CheckRule>(
    scene: &Scene,
    like: &T,
    rel_tol: f64,
    label: String,
    budget: &Budget,
) -> Result<Report, OracleError> {
    let t0 = Instant::now();
    if scene.lights.len() > MAX_LIGHTS {
        return Err(OracleError::Unsupported(format!(
            "lights: {} lights; the oracle takes at most {MAX_LIGHTS} (its cost grows as the square of the \
             light count: 100 point lights take ~13 s on two cores); the tracer has no such bound",
            scene.lights.len()
        )));
    }
    let field = Field::from_scene(scene, like)?;
    let r = like.lit(scene.estimator.radius);
    if field.albedo.is_zero() {
        return Err(OracleError::Unsupported(
            "medium.albedo = 0: nothing is scattered towards the camera, the pixel is exactly dark (L = 0, Var L = 0) and the relative noise is undefined".into(),
        ));
    }
    let finite_field = FiniteField::from_scene(scene, &field);
    // Every integral of the run, both models, charged to the one budget.
    let opts = Options::rel(rel_tol).with_budget(budget.clone());
    if !field.lights_the_camera_ray() {
        return Err(no_light_on_the_camera_ray(scene, finite_field.as_ref(), &opts));
    }
    let (ints, finite) = rayon::join(
        || Integrals::compute(&field, &r, &opts),
        || finite_field.as_ref().map(|ff| ff.integrals(&opts)).transpose(),
    );
    let (ints, finite) = (ints?, finite?);
    if ints.mean.value.is_zero() {
        return Err(OracleError::Unsupported(
            "the mean luminance is exactly 0 (no light reaches the camera ray): Var L = 0 and the relative noise is undefined".into(),
        ));
    }
    let counts = Counts {
        q: like.lit(scene.estimator.q),
        n_f: like.lit(scene.estimator.forward_rays as f64),
        n_b: like.lit(scene.estimator.camera_rays as f64),
    };
    // The field carries W·e^{c₀}; k = e^{−c₀} restores absolute values.
    let k = (-field.shift.clone()).exp();
    let inv_k = field.shift.exp();
    let mean = Valued::from(&ints.mean);
    let var = variance(
        &mean,
        &Valued::from(&ints.m2),
        &Valued::from(&ints.c23),
        &Valued::from(&ints.p),
        &Valued::from(&ints.q),
        &Valued::from(&ints.c24),
        &counts,
        &k,
    );
    // Var/μ² = (Var e^{c₀}) e^{c₀} / μ_shifted².
    let mu2 = mean.value.clone() * mean.value.clone();
    let relative = var.value.clone() * inv_k.clone() / mu2.clone();
    let relative_error = var.error.clone() * inv_k.clone() / mu2.clone()
        + relative.abs() * like.lit(2.0) * mean.error.clone() / mean.value.abs();
    let d = d_constants(&ints, &r, &field.sigma_ext, &inv_k);
    let log10 = |v: &T| v.abs().ln().to_f64() / std::f64::consts::LN_10;
    // |log₁₀(v ± e) − log₁₀ v| ≤ −log₁₀(1 − e/v) for e < v.
    let log10_bar = |v: &T, e: &T| {
        let rel = (e.clone() / v.abs()).to_f64();
        (rel < 1.0).then(|| -(-rel).ln_1p() / std::f64::consts::LN_10)
    };
    let shift_log10 = field.shift.to_f64() / std::f64::consts::LN_10;
    let relative_asymptotic = d.as_ref().map(|d| relative_from_d(d, &r, &field.sigma_ext, &counts).to_f64());
    let d_error = d.as_ref().and_then(|d| d_errors(&ints, d));
    let relative_asymptotic_error =
        d_error.as_ref().map(|e| relative_from_d_error(e, &r, &field.sigma_ext, &counts).to_f64());
    let small_mean = ValueWithBar {
        value: (ints.mean.value.clone() * k.clone()).to_f64(),
        error: (ints.mean.error.clone() * k.clone()).to_f64(),
    };
    let small_variance = ValueWithBar {
        value: (var.value.clone() * k.clone()).to_f64(),
        error: (var.error.clone() * k.clone()).to_f64(),
    };
    let small_relative = ValueWithBar { value: relative.to_f64(), error: relative_error.to_f64() };
    let finite_report = match (&finite, &finite_field) {
        (Some(f), Some(ff)) => Some(finite_report(f, ff, &counts, (&mean, &var, &field.shift))),
        _ => None,
    };
    let prediction = match &finite_report {
        Some(f) => ReportPrediction {
            model: "finite-sphere",
            mean: f.mean,
            variance: f.variance,
            relative_noise: f.relative_noise,
            note: FINITE_NOTE.into(),
        },
        None => ReportPrediction {
            model: "small-sphere",
            mean: small_mean,
            variance: small_variance,
            relative_noise: small_relative,
            note: SMALL_SPHERE_NOTE.into(),
        },
    };
    let report = Report {
        precision: label,
        rel_tol,
        radius: scene.estimator.radius,
        q: scene.estimator.q,
        forward_rays: scene.estimator.forward_rays,
        camera_rays: scene.estimator.camera_rays,
        mean_luminance: small_mean,
        mean_luminance_log10: log10(&ints.mean.value) - shift_log10,
        mean_luminance_log10_error: log10_bar(&ints.mean.value, &ints.mean.error),
        corr23: correlation(&ints.c23, &ints.c23_asym, &k),
        corr24: correlation(&ints.c24, &ints.c24_asym, &k),
        variance: Variance {
            exact: small_variance,
            log10: log10(&var.value) - shift_log10,
            log10_error: log10_bar(&var.value, &var.error),
            relative: relative.to_f64(),
            relative_error: relative_error.to_f64(),
            relative_asymptotic,
            relative_asymptotic_error,
        },
        integral_m2: scaled(&ints.m2, &k),
        integral_p: scaled(&ints.p, &k),
        integral_q: scaled(&ints.q, &k),
        attenuation_shift: field.shift.to_f64(),
        d: d.map(|d| d.map(|v| v.to_f64())),
        d_error: d_error.map(|d| d.map(|v| v.to_f64())),
        evaluations: ints.evaluations(),
        finite: finite_report,
        prediction,
        wall_time_ms: t0.elapsed().as_secs_f64() * 1e3,
    };
    report.check_representable(scene)?;
    Ok(report)
}

impl Report {
    /// Every number the report prints as a result, by name.
    fn reported_numbers(&self) -> Vec<(String, f64)> {
        let mut out = Vec::new();
        let mut bar = |name: &str, v: &ValueWithBar| {
            out.push((name.to_string(), v.value));
            out.push((format!("{name} (bar)"), v.error));
        };
        bar("mean luminance (small-sphere)", &self.mean_luminance);
        bar("Var L (small-sphere)", &self.variance.exact);
        bar("prediction: mean", &self.prediction.mean);
        bar("prediction: Var L", &self.prediction.variance);
        bar("prediction: relative noise", &self.prediction.relative_noise);
        if let Some(f) = &self.finite {
            bar("finite-sphere mean", &f.mean);
            bar("finite-sphere Var L", &f.variance);
            bar("finite-sphere bias", &f.bias);
            bar("finite-sphere relative noise", &f.relative_noise);
            bar("finite/small mean ratio", &f.mean_ratio);
            bar("finite/small Var L ratio", &f.variance_ratio);
        }
        out.push(("relative noise (small-sphere)".into(), self.variance.relative));
        out.push(("relative noise (small-sphere, bar)".into(), self.variance.relative_error));
        for (name, c) in [("(23)", &self.corr23), ("(24)", &self.corr24)] {
            out.push((format!("{name} exact"), c.exact.value));
            out.push((format!("{name} exact (bar)"), c.exact.error));
            for (what, v) in [
                ("R→0 form", c.asymptotic.value),
                ("R→0 form bar", c.asymptotic.error),
                ("exact/R→0 ratio", c.ratio),
                ("exact/R→0 ratio bar", c.ratio_error),
            ] {
                if let Some(v) = v {
                    out.push((format!("{name} {what}"), v));
                }
            }
        }
        for (what, v) in [
            ("Var/L², §4.4 formula", self.variance.relative_asymptotic),
            ("Var/L², §4.4 formula (bar)", self.variance.relative_asymptotic_error),
        ] {
            if let Some(v) = v {
                out.push((what.into(), v));
            }
        }
        for (what, d) in [("D", &self.d), ("D bar", &self.d_error)] {
            for (k, v) in d.iter().flatten().enumerate() {
                out.push((format!("{what} {}", k + 1), *v));
            }
        }
        out
    }

    /// The numbers that are positive for every lit scene (each an integral
    /// of a positive integrand): printed as 0, they have underflowed.
    fn positive_numbers(&self) -> Vec<(&'static str, ValueWithBar)> {
        let int = |i: &Integral| ValueWithBar { value: i.value, error: i.error };
        let mut out = vec![
            ("mean luminance (small-sphere)", self.mean_luminance),
            ("prediction: mean", self.prediction.mean),
            ("Var L (small-sphere)", self.variance.exact),
            ("prediction: Var L", self.prediction.variance),
            ("(23) exact", int(&self.corr23.exact)),
            ("(24) exact", int(&self.corr24.exact)),
        ];
        if let Some(f) = &self.finite {
            out.push(("finite-sphere Var L", f.variance));
        }
        out
    }

    /// Fails when a printed number is not finite, or a quantity that is
    /// positive for every lit scene (the mean, which the ratios and the
    /// relative noise divide by; Var L; (23), (24)) has underflowed to 0.
    fn check_representable(&self, scene: &Scene) -> Result<(), OracleError> {
        let fluxes: Vec<String> = scene.lights.iter().map(|l| format!("{:e}", l.flux())).collect();
        let advice = format!(
            "the mean scales with the lights' flux ({}) and Var L with its square, the relative noise not at all: \
             rescale the fluxes (or bring the lights nearer: e^(−σ_ext·distance) underflows beyond ~700)",
            fluxes.join(", ")
        );
        for (name, v) in self.positive_numbers() {
            if !(v.value > 0.0) {
                return Err(OracleError::NotRepresentable(format!(
                    "{name} is {:e} ± {:e}: it underflows f64; {advice}",
                    v.value, v.error
                )));
            }
        }
        if let Some((name, v)) = self.reported_numbers().into_iter().find(|(_, v)| !v.is_finite()) {
            return Err(OracleError::NotRepresentable(format!("{name} is {v}; {advice}")));
        }
        Ok(())
    }
}

/// Why the oracle refuses a scene whose camera ray (its line) meets no
/// light: the small-sphere model's mean is then exactly 0, and every ratio
/// of the report is undefined. Spheres of radius R grazing a beam still
/// receive light (the tracer measures it): then the finite-sphere model's
/// mean is computed and named, so the message does not claim a dark pixel.
fn no_light_on_the_camera_ray<T: CheckRule>(scene: &Scene, ff: Option<&FiniteField<T>>, opts: &Options) -> OracleError {
    let r = scene.estimator.radius;
    // A sphere at x(s), s ≥ 0, receives a beam's rays when its centre is within
    // a_b + R of the axis, in front of the disk (a ray's closest point to the
    // centre lies at the centre's depth): the beam widened by R.
    let (o, u) = (scene.camera.origin, scene.camera.direction);
    let reach = scene.lights.iter().any(|l| match *l {
        Light::Beam { center, direction, radius, .. } => {
            let (mu, depth0) = (u.dot(direction), (o - center).dot(direction));
            let (s_in, s_out) = beam_interval(o - center, u, direction, radius + r, depth0, mu);
            s_out != Some(s_in)
        }
        Light::Point { .. } => true,
    });
    let grazing = ff.filter(|_| reach).map(|ff| (ff.ray_total(Functional::Mean, opts), (-ff.shift.clone()).exp()));
    let msg = match grazing {
        Some((Ok(m), k)) if !m.value.is_zero() => format!(
            "the camera ray passes outside every light (no beam crosses it in front of its disk), so the \
             small-sphere model (R → 0) predicts L = 0; but its spheres of radius R = {r} graze a beam and receive \
             light: the finite-sphere model's mean luminance at this R is {:.6e} ± {:.1e} (the tracer measures it \
             too). The oracle reports a scene only where the camera ray itself meets light (its report compares the \
             two models); move the beam onto the camera ray, or use `trace`",
            (m.value * k.clone()).to_f64(),
            (m.error * k).to_f64()
        ),
        Some((Err(e), _)) => format!(
            "the camera ray passes outside every light (no beam crosses it in front of its disk), so the \
             small-sphere model (R → 0) predicts L = 0; whether its spheres of radius R = {r} graze a beam is \
             unknown: {e}"
        ),
        _ => format!(
            "the camera ray meets no light, nor do its spheres of radius R = {r}: the pixel is exactly dark (L = 0, \
             Var L = 0) and the relative noise is undefined"
        ),
    };
    OracleError::Unsupported(msg)
}

/// The finite-sphere model's report from its integrals, beside the
/// small-sphere mean and variance (shifted by e^{c₀} of their own field:
/// `small` = (mean, variance, c₀)) for the bias and the ratios, which are
/// formed in the working precision (they stay finite where the values
/// underflow f64).
fn finite_report<T: CheckRule>(
    f: &FiniteIntegrals<T>,
    ff: &FiniteField<T>,
    counts: &Counts<T>,
    small: (&Valued<T>, &Valued<T>, &T),
) -> FiniteReport {
    let k = (-ff.shift.clone()).exp();
    let mean_t = Valued::from(&f.mean);
    let var = variance(
        &mean_t,
        &Valued::from(&f.m2),
        &Valued::from(&f.c23),
        &Valued::from(&f.p),
        &Valued::from(&f.q),
        &Valued::from(&f.c24),
        counts,
        &k,
    );
    let to = |v: &T, e: &T| ValueWithBar {
        value: (v.clone() * k.clone()).to_f64(),
        error: (e.clone() * k.clone()).to_f64(),
    };
    // finite/small of two shifted values: (a e^{−c₀}) / (b e^{−c₀′}).
    let (small_mean, small_var, small_shift) = small;
    let rescale = (small_shift.clone() - ff.shift.clone()).exp();
    let ratio = |a: &Valued<T>, b: &Valued<T>| {
        let value = a.value.clone() / b.value.clone() * rescale.clone();
        let rel = a.error.clone() / a.value.abs() + b.error.clone() / b.value.abs();
        ValueWithBar { value: value.to_f64(), error: (value.abs() * rel).to_f64() }
    };
    let small_k = (-small_shift.clone()).exp();
    let bias = mean_t.value.clone() * k.clone() - small_mean.value.clone() * small_k.clone();
    let bias_error = mean_t.error.clone() * k.clone() + small_mean.error.clone() * small_k;
    // Var/μ² = (Var e^{c₀}) e^{c₀}/μ_shifted², formed in the working precision.
    let inv_k = ff.shift.exp();
    let mu2 = mean_t.value.clone() * mean_t.value.clone();
    let rel = var.value.clone() * inv_k.clone() / mu2.clone();
    let rel_err =
        var.error.clone() * inv_k / mu2 + rel.abs() * rel.lit(2.0) * mean_t.error.clone() / mean_t.value.abs();
    FiniteReport {
        mean: to(&f.mean.value, &f.mean.error),
        variance: to(&var.value, &var.error),
        bias: ValueWithBar { value: bias.to_f64(), error: bias_error.to_f64() },
        relative_noise: ValueWithBar { value: rel.to_f64(), error: rel_err.to_f64() },
        mean_ratio: ratio(&mean_t, small_mean),
        variance_ratio: ratio(&var, small_var),
        integral_m2: scaled(&f.m2, &k),
        integral_p: scaled(&f.p, &k),
        integral_q: scaled(&f.q, &k),
        corr23: scaled(&f.c23, &k),
        corr24: scaled(&f.c24, &k),
        attenuation_shift: ff.shift.to_f64(),
        evaluations: f.evaluations(),
    }
}

/// Runs the oracle at `precision` with its default tolerance (or `rel_tol`)
/// and the default evaluation budget ([`Precision::default_evaluations`]).
pub fn run(scene: &Scene, precision: Precision, rel_tol: Option<f64>) -> Result<Report, OracleError> {
    run_within(scene, precision, rel_tol, &Budget::new(precision.default_evaluations()))
}

/// [`run`] with the evaluation budget (and deadline) `budget`, shared by
/// every integral of the run; a run that needs more fails with
/// `NOT CONVERGED` naming the budget.
pub fn run_within(
    scene: &Scene,
    precision: Precision,
    rel_tol: Option<f64>,
    budget: &Budget,
) -> Result<Report, OracleError> {
    let tol = rel_tol.unwrap_or(precision.default_tol_for(scene));
    match precision {
        Precision::F64 => run_with(scene, &0.0f64, tol, "f64".into(), budget),
        Precision::Bits(b) => run_with(scene, &rug::Float::with_val(b, 0), tol, format!("{b} bits"), budget),
    }
}
