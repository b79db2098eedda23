//! The oracle end to end: scene → field → integrals → variance, at a chosen
//! precision, as a serialisable report (`mcrt-noise oracle SCENE --json`).
//!
//! Two models are computed side by side: the small-sphere model of §4.3
//! (exact only as R → 0; its exact (23), (24), their R → 0 forms and the
//! §4.4 formula) and the finite-sphere model (`model::finite`, exact at
//! the scene's R) for uncollided light and, in isotropic media, for
//! single-scattered light (point lights and beams at q = 1 and N_B = 1;
//! point lights at any q and N_B with [`Scope::FinitePairs`] or
//! [`Scope::ExactPrediction`], which add the correlations of two spheres;
//! with these scopes also point lights in Henyey–Greenstein media at q = 1
//! and N_B = 1).
//! The report's `prediction` is the finite-sphere model where it exists,
//! the small-sphere one otherwise, and says which (and, with scattered
//! light, why in `finite_not_used`).

use crate::model::field::{beam_interval, Field};
use crate::model::finite::{FiniteField, FiniteIntegrals, Functional, Weighed};
use crate::model::noise::{
    d_constants, d_errors, relative_from_d, relative_from_d_error, variance, Counts, Integrals, Valued,
};
use crate::model::OracleError;
use crate::prec::FINITE_PAIRS_PREDICTION_TOL;
use crate::quad::{Budget, CheckRule, Estimate, Options};
use crate::real::Real;
use mcrt_scene::{Light, Scene};
use serde::Serialize;
use std::time::Instant;

mod every_order;
mod order_one;
mod report;
pub use every_order::{
    every_order_mean, EveryOrderMean, EVERY_ORDER_TOL, EVERY_ORDER_TOL_RANGE, EVERY_ORDER_VARIANCE_TOL,
    VARIANCE_NOT_MODELLED,
};
pub(crate) use every_order::{
    every_order_report, every_order_scene_covered, every_order_variance_refusal, orders_beyond_the_first,
};
pub(crate) use order_one::pairs_weigh_nothing;
pub use order_one::{
    finite_hg_moments_cover, finite_pairs_cover, finite_sphere_covers, finite_sphere_covers_the_standard_method,
};
use order_one::{
    finite_mean_report, finite_not_used, not_weighed, order_one, scattered_covered, scattered_mean_field,
    with_finite_pairs, with_hg_moments, OrderOne,
};
use report::{correlation, reported, scaled};
pub use report::{
    Asymptotic, Correlation, FiniteMean, FiniteReport, Integral, Report, ReportPrediction, ValueWithBar, Variance,
    FINITE_NOTE, FINITE_ORDER1_HG_NOTE, FINITE_ORDER1_NOTE, PAIRS_NOT_NEEDED, SMALL_SPHERE_NOTE,
    SMALL_SPHERE_PAIRS_FAILED, SMALL_SPHERE_PAIRS_NOT_NEEDED,
};

/// How much of the small-sphere model a run computes.
///
/// ```
/// use mcrt_noise::oracle::{run_scoped, Precision, Scope};
/// use mcrt_noise::Scene;
///
/// let scene = Scene::builder()
///     .medium(1.0, 0.8)
///     .point_light([1.0, 0.0, 1.0], 1.0)
///     .camera([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
///     .estimator(0.2, 1.0, 20, 1)
///     .build()?;
/// let report = run_scoped(&scene, Precision::F64, None, Scope::Prediction)?;
/// assert!(report.corr23.is_none() && report.pairs_not_computed.is_some());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Scope {
    /// Every integral of both models (`mcrt-noise oracle`): D₁…D₅ and
    /// (23), (24) with their R → 0 forms whatever the scene's q and N_B
    /// (at q = 1 and N_B = 1, where Var L weighs them 0, their failure is
    /// reported in [`Report::pairs_not_computed`] and
    /// [`Report::pairs_error`] instead of failing the run).
    Everything,
    /// What the scene's Var L needs: with q = 1 and N_B = 1, (7)–(9) weigh
    /// the small-sphere integrals of two spheres (Q, (23), (24)) 0, and
    /// they and their R → 0 forms are skipped ([`Report::pairs_not_computed`];
    /// with single-scattered light they are ~97 % of the work). The
    /// library's `predict` where the finite-sphere correlations of two
    /// spheres are not needed or not covered.
    Prediction,
    /// [`Scope::Everything`] and, for single-scattered light (isotropic
    /// media, point lights and beams) with q < 1 or N_B > 1, the finite-sphere
    /// model's Q and the correlations Var L weighs — C₂₃ where q < 1, C₂₄
    /// where N_B > 1, the other named in `FiniteReport::not_computed`
    /// (`docs/model.md` §9.7, §9.11; with a beam the small-sphere model
    /// has no pair integrals, and [`Report::variance`] is `None`) — so that the prediction
    /// is the exact finite-sphere model at any R (`mcrt-noise oracle
    /// --finite-pairs`). A minute or more where [`Scope::Everything`] takes
    /// seconds: ~7·10⁸ evaluations at 10⁻³ on `point-isotropic-order1` at
    /// R = 0.05 (51 s on two cores with the Gauss–Kronrod pair of rules;
    /// 5 % more evaluations since the nested engine's inner share,
    /// `docs/quadrature.md`),
    /// 1.4·10⁹ with a light 0.1 from the camera line at R = 0.2 (141 s),
    /// beyond the default budget of 10⁹, and more at tighter goals: give
    /// it a goal and a budget. Their failure (the budget spent among them) is
    /// reported, and the prediction is then the small-sphere one; they are
    /// computed after everything else, so that the rest of the report
    /// stands when they spend the budget. For point lights in a
    /// Henyey–Greenstein medium at q = 1 and N_B = 1 it computes μ, M₂ and
    /// P of the order-1 model (M₂ with the same-path term of
    /// `docs/model.md` §9.10, 4·10⁹ evaluations and ~5 minutes at 10⁻³ at
    /// g = −0.5), so that the prediction is exact there too.
    FinitePairs,
    /// [`Scope::Prediction`] and, for single-scattered light (isotropic
    /// media, point lights and beams) with q < 1 or N_B > 1 in f64, the finite-sphere
    /// model with the correlations that the scene's Var L weighs
    /// (`model::finite::Weighed`) at a goal no tighter than
    /// [`crate::prec::FINITE_PAIRS_PREDICTION_TOL`]: the library's
    /// `predict`, exact at any R (model bar 0). About a minute on two cores
    /// (`point-isotropic-order1`: ~61 s). For point lights in a
    /// Henyey–Greenstein medium at q = 1 and N_B = 1 (f64), μ, M₂ and P of
    /// the order-1 model at the same goal, as [`Scope::FinitePairs`] computes
    /// them (~4·10⁹ evaluations, about 5 minutes). Their failure is reported as with
    /// [`Scope::FinitePairs`], and a failure of the finite-sphere mean in
    /// [`Report::finite_error`] too. In MPFR it is [`Scope::Prediction`]:
    /// the correlations would take hours there.
    ExactPrediction,
}

/// The largest MPFR precision a run accepts: its default tolerance
/// 2^{−(bits − 22)} is then 2^{−1002} ≈ 2.3·10⁻³⁰², still a normal double
/// (tolerances are f64; past ~1044 bits the default underflowed to 0 and
/// every integral was refused).
#[cfg(feature = "mpfr")]
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
///
/// MPFR precisions (`Precision::Bits`) exist with the `mpfr` feature (on
/// by default) only; without it every run is in f64. The enum is
/// `#[non_exhaustive]` so that a dependent crate's `match` compiles with
/// and without the feature (another crate in the build may turn it on).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Precision {
    /// IEEE double precision.
    F64,
    /// MPFR with this many bits of mantissa (32 to [`MAX_BITS`]; feature
    /// `mpfr`).
    #[cfg(feature = "mpfr")]
    Bits(u32),
}

impl Precision {
    /// Parses `f64` or (feature `mpfr`) a number of bits in [32,
    /// `MAX_BITS`]. Without the feature a number of bits is refused,
    /// naming the feature.
    pub fn parse(text: &str) -> Result<Precision, String> {
        if text == "f64" {
            return Ok(Precision::F64);
        }
        #[cfg(feature = "mpfr")]
        {
            match text.parse::<u32>() {
                Ok(b) if (32..=MAX_BITS).contains(&b) => Ok(Precision::Bits(b)),
                _ => Err(format!(
                    "--precision {text:?}: must be `f64` or a number of bits in [32, {MAX_BITS}] (tolerances are \
                     doubles, so the tightest is ~1e-300: more bits would only be guard digits)"
                )),
            }
        }
        #[cfg(not(feature = "mpfr"))]
        {
            Err(format!(
                "precision {text:?}: must be `f64` (MPFR precisions, a number of bits, need mcrt-noise's `mpfr` \
                 feature, which this build leaves out)"
            ))
        }
    }

    /// The bits of an MPFR precision; `None` for f64 (and always without
    /// the `mpfr` feature).
    pub fn mpfr_bits(self) -> Option<u32> {
        match self {
            Precision::F64 => None,
            #[cfg(feature = "mpfr")]
            Precision::Bits(b) => Some(b),
        }
    }

    /// Default evaluation budget of a run: [`crate::quad::DEFAULT_EVALUATIONS`]
    /// (10⁹, ~20 s) in f64; in MPFR, whose evaluations cost ~300 times
    /// more at 128 bits and grow roughly with the square of the precision
    /// beyond, `quad::DEFAULT_EVALUATIONS_MPFR` (5·10⁷, a few
    /// minutes) up to 128 bits and 5·10⁷·(128/bits)² above (7.8·10⁵ at 1024
    /// bits), so that the default never means hours.
    pub fn default_evaluations(self) -> u64 {
        match self {
            Precision::F64 => crate::quad::DEFAULT_EVALUATIONS,
            #[cfg(feature = "mpfr")]
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
            #[cfg(feature = "mpfr")]
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
            #[cfg(feature = "mpfr")]
            (Precision::Bits(_), true) => self.default_tol().max(1e-10),
        }
    }
}

/// Runs the oracle on `scene` at the precision of `like` with `rel_tol`,
/// every integral of both models charged to the one `budget`
/// ([`Scope::Everything`]).
pub fn run_with<T: CheckRule>(
    scene: &Scene,
    like: &T,
    rel_tol: f64,
    label: String,
    budget: &Budget,
) -> Result<Report, OracleError> {
    run_with_scoped(scene, like, rel_tol, label, budget, Scope::Everything)
}

/// [`run_with`], the small-sphere model to the extent `scope`.
pub fn run_with_scoped<T: CheckRule>(
    scene: &Scene,
    like: &T,
    rel_tol: f64,
    label: String,
    budget: &Budget,
    scope: Scope,
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
    let scattered_field = scattered_mean_field(scene, &field);
    // The whole order-1 model (μ, M₂, P) where the pairs weigh nothing; in a
    // Henyey–Greenstein medium the mean alone.
    let whole_model = scattered_field.is_some() && scattered_covered(scene);
    let unpaired = whole_model && pairs_weigh_nothing(scene);
    // Point lights in a Henyey–Greenstein medium at q = 1 and N_B = 1: μ, M₂
    // and P with the same-path term's four-level nest (`docs/model.md`
    // §9.10), minutes at 10⁻³: with `--finite-pairs` and the library's
    // `predict` (f64) only, after everything else (as the pairs), so that a
    // spent budget leaves the report.
    let predicting = matches!(scope, Scope::Prediction | Scope::ExactPrediction);
    // The finite-sphere correlations (and the same-path term of a
    // Henyey–Greenstein medium) in the prediction: f64 only.
    let exact = scope == Scope::ExactPrediction && like.prec() <= 53;
    let hg_unpaired =
        (scope == Scope::FinitePairs || exact) && scattered_field.is_some() && finite_hg_moments_cover(scene);
    // The prediction's goal for either is no tighter than 1e-3.
    let pairs_opts = Options {
        rel_tol: if exact { opts.rel_tol.max(FINITE_PAIRS_PREDICTION_TOL) } else { opts.rel_tol },
        ..opts.clone()
    };
    // A beam's single-scattered light: the small-sphere pairs from its
    // radiance by direction (`docs/model.md` §3a), the finite-sphere ones
    // (§9.11) when asked for them (`--finite-pairs`, or `predict` in f64).
    let beam_scattered = !field.scattered_beams.is_empty();
    let small_unpaired = (predicting || beam_scattered) && pairs_weigh_nothing(scene);
    let ((ints, finite), scattered) = rayon::join(
        || {
            rayon::join(
                || {
                    // With a beam the prediction's exact scope skips the
                    // small-sphere pairs too: it never falls back to them
                    // (their model error for a beam was never measured).
                    if small_unpaired || (beam_scattered && exact) {
                        Integrals::compute_single_sphere(&field, &r, &opts).map(|i| (i, None))
                    } else if pairs_weigh_nothing(scene) {
                        // Reported, not needed: their failure does not fail the run.
                        Integrals::compute_with_optional_pairs(&field, &r, &opts)
                    } else {
                        Integrals::compute(&field, &r, &opts).map(|i| (i, None))
                    }
                },
                || finite_field.as_ref().map(|ff| ff.integrals(&opts)).transpose(),
            )
        },
        || scattered_field.as_ref().map(|ff| order_one(ff, unpaired, &opts)).transpose(),
    );
    // The finite-sphere pairs when asked for, after everything else, so that
    // if they spend the budget the rest of the report stands.
    let scattered = match (scattered, &scattered_field) {
        (Ok(Some(OrderOne::Mean(mean, None))), Some(ff)) if whole_model && (scope == Scope::FinitePairs || exact) => {
            let weighed = Weighed::of(scene.estimator.q, scene.estimator.camera_rays);
            Ok(Some(with_finite_pairs(ff, mean, &pairs_opts, weighed)))
        }
        (Ok(Some(OrderOne::Mean(mean, None))), Some(ff)) if hg_unpaired => {
            Ok(Some(with_hg_moments(ff, mean, &pairs_opts)))
        }
        (other, _) => other,
    };
    // A failure's best guess carries its field's e^{c₀}: in the report's units.
    let (ints, pairs_failed) = ints.map_err(|e| e.unshifted(field.shift.to_f64()))?;
    let pairs_failed = pairs_failed.map(|e| e.unshifted(field.shift.to_f64()));
    let finite = finite.map_err(|e| e.unshifted(finite_field.as_ref().map_or(0.0, |ff| ff.shift.to_f64())))?;
    // The exact order-1 model is an addition to the small-sphere report:
    // its failure is reported, with the reason, and does not fail the run.
    let shift = scattered_field.as_ref().map_or(0.0, |ff| ff.shift.to_f64());
    let scattered = scattered.map_err(|e| e.unshifted(shift)).map(|one| {
        one.map(|one| match one {
            OrderOne::Mean(m, failed) => OrderOne::Mean(m, failed.map(|e| e.unshifted(shift))),
            whole => whole,
        })
    });
    let finite_not_used = finite_not_used(scene, &scattered);
    let (order1_finite, scattered, finite_error) = match scattered {
        Ok(Some(OrderOne::Integrals(f))) => (Some(f), Ok(None), None),
        Ok(Some(OrderOne::Mean(m, failed))) => (None, Ok(Some(m)), failed),
        Ok(None) => (None, Ok(None), None),
        Err(e) => (None, Err(e.clone()), (pairs_weigh_nothing(scene) || exact).then_some(e)),
    };
    if ints.mean.value.is_zero() {
        return Err(OracleError::Unsupported(
            "the mean luminance is exactly 0 (no light reaches the camera ray): Var L = 0 and the relative noise is undefined".into(),
        ));
    }
    // The small-sphere Var L needs the pairs wherever (7)–(9) weigh them.
    let small_formed = pairs_weigh_nothing(scene) || ints.pairs.is_some();
    let counts = Counts {
        q: like.lit(scene.estimator.q),
        n_f: like.lit(scene.estimator.forward_rays as f64),
        n_b: like.lit(scene.estimator.camera_rays as f64),
    };
    // The field carries W·e^{c₀}; k = e^{−c₀} restores absolute values.
    let k = (-field.shift.clone()).exp();
    let inv_k = field.shift.exp();
    let mean = Valued::from(&ints.mean);
    // Without the pair integrals (q = 1, N_B = 1) (7)–(9) weigh them 0.
    let pairs = ints.pairs.as_ref();
    let var = variance(
        &mean,
        &Valued::from(&ints.m2),
        &or_zero(pairs.map(|p| &p.c23), &r),
        &Valued::from(&ints.p),
        &or_zero(pairs.map(|p| &p.q), &r),
        &or_zero(pairs.map(|p| &p.c24), &r),
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
    let d_error = d.as_ref().and_then(|d| d_errors(&ints, d));
    let asymptotic = d.as_ref().map(|d| relative_from_d(d, &r, &field.sigma_ext, &counts));
    let relative_asymptotic = asymptotic.as_ref().map(Real::to_f64);
    // The bars as the report gives them: the value's rounding to f64 included.
    let relative_asymptotic_error = asymptotic
        .as_ref()
        .zip(d_error.as_ref())
        .map(|(v, e)| reported(v, &relative_from_d_error(e, &r, &field.sigma_ext, &counts)).error);
    let d_error_reported = d.as_ref().zip(d_error.as_ref()).map(|(d, e)| {
        let mut out = [0.0; 5];
        for (o, (v, e)) in out.iter_mut().zip(d.iter().zip(e)) {
            *o = reported(v, e).error;
        }
        out
    });
    let small_mean = reported(&(ints.mean.value.clone() * k.clone()), &(ints.mean.error.clone() * k.clone()));
    let small_variance = reported(&(var.value.clone() * k.clone()), &(var.error.clone() * k.clone()));
    let small_relative = reported(&relative, &relative_error);
    let small = (&mean, small_formed.then_some(&var), &field.shift);
    let finite_report = match (&finite, &finite_field, &order1_finite, &scattered_field) {
        (Some(f), Some(ff), _, _) => Some(finite_report(f, ff, &counts, small, "uncollided")),
        (_, _, Some(f), Some(ff)) => Some(finite_report(f, ff, &counts, small, "uncollided and single-scattered")),
        _ => None,
    };
    if finite_report.is_none() && !small_formed {
        // No model gives Var L: the finite-sphere one failed (or, above 53
        // bits, was not run) and the small-sphere one cannot form it.
        return Err(finite_error.clone().unwrap_or_else(|| {
            OracleError::Unsupported(
                "neither model formed Var L: the small-sphere pair integrals were not computed and the \
                 finite-sphere model was not run"
                    .into(),
            )
        }));
    }
    let prediction = match &finite_report {
        Some(f) => ReportPrediction {
            model: "finite-sphere",
            mean: f.mean,
            variance: f.variance,
            relative_noise: f.relative_noise,
            note: match &order1_finite {
                None => FINITE_NOTE,
                Some(_) if scene.medium.phase == mcrt_scene::Phase::Isotropic => FINITE_ORDER1_NOTE,
                Some(_) => FINITE_ORDER1_HG_NOTE,
            }
            .into(),
        },
        None => ReportPrediction {
            model: "small-sphere",
            mean: small_mean,
            variance: small_variance,
            relative_noise: small_relative,
            note: match &finite_not_used {
                Some(why) => format!("{SMALL_SPHERE_NOTE}. Not the finite-sphere model: {why}"),
                None => SMALL_SPHERE_NOTE.into(),
            },
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
        corr23: pairs.map(|p| correlation(&p.c23, p.c23_cross.as_ref(), &p.c23_asym, &k)),
        corr24: pairs.map(|p| correlation(&p.c24, p.c24_cross.as_ref(), &p.c24_asym, &k)),
        variance: small_formed.then(|| Variance {
            exact: small_variance,
            log10: log10(&var.value) - shift_log10,
            log10_error: log10_bar(&var.value, &var.error),
            relative: small_relative.value,
            relative_error: small_relative.error,
            relative_asymptotic,
            relative_asymptotic_error,
        }),
        integral_m2: scaled(&ints.m2, &k),
        integral_m2_same_path: field.is_smooth().then(|| scaled(&ints.m2_same_path, &k)),
        finite_mean: finite_mean_report(scattered, scattered_field.as_ref(), &ints.mean, &k),
        finite_not_used,
        finite_error,
        pairs_error: pairs_failed.clone(),
        integral_p: scaled(&ints.p, &k),
        integral_q: pairs.map(|p| scaled(&p.q, &k)),
        pairs_not_computed: pairs.is_none().then(|| match &pairs_failed {
            Some(e) => format!("{e}: {SMALL_SPHERE_PAIRS_FAILED}"),
            None => SMALL_SPHERE_PAIRS_NOT_NEEDED.to_string(),
        }),
        attenuation_shift: field.shift.to_f64(),
        d: d.map(|d| d.map(|v| v.to_f64())),
        d_error: d_error_reported,
        evaluations: ints.evaluations(),
        finite: finite_report,
        prediction,
        wall_time_ms: t0.elapsed().as_secs_f64() * 1e3,
    };
    report.check_representable(scene, field.uncollided_light_meets_the_camera_ray())?;
    Ok(report)
}

/// A pair integral for (7)–(9), or 0 ± 0 where it was not computed (q = 1
/// and N_B = 1 weigh it 0); `like` gives the precision.
fn or_zero<T: Real>(e: Option<&Estimate<T>>, like: &T) -> Valued<T> {
    e.map_or_else(|| Valued { value: like.lit(0.0), error: like.lit(0.0) }, Valued::from)
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
    let grazing = ff.filter(|_| reach).map(|ff| {
        let mean = ff.ray_total(Functional::Mean, opts).map_err(|e| e.unshifted(ff.shift.to_f64()));
        (mean, (-ff.shift.clone()).exp())
    });
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
    small: (&Valued<T>, Option<&Valued<T>>, &T),
    covers: &'static str,
) -> FiniteReport {
    let k = (-ff.shift.clone()).exp();
    let mean_t = Valued::from(&f.mean);
    // Q, C₂₃, C₂₄ are missing only where (7)–(9) weigh them 0 (all three
    // at q = 1 and N_B = 1, C₂₃ at q = 1, C₂₄ at N_B = 1: `Weighed`): they
    // enter as exact zeros.
    debug_assert!(f.c23.is_some() || counts.q.to_f64() == 1.0, "C₂₃ missing at q = {}", counts.q.to_f64());
    debug_assert!(f.c24.is_some() || counts.n_b.to_f64() == 1.0, "C₂₄ missing at N_B = {}", counts.n_b.to_f64());
    let var = variance(
        &mean_t,
        &Valued::from(&f.m2),
        &or_zero(f.c23.as_ref(), &k),
        &Valued::from(&f.p),
        &or_zero(f.q.as_ref(), &k),
        &or_zero(f.c24.as_ref(), &k),
        counts,
        &k,
    );
    let to = |v: &T, e: &T| reported(&(v.clone() * k.clone()), &(e.clone() * k.clone()));
    // finite/small of two shifted values: (a e^{−c₀}) / (b e^{−c₀′}).
    let (small_mean, small_var, small_shift) = small;
    let rescale = (small_shift.clone() - ff.shift.clone()).exp();
    let ratio = |a: &Valued<T>, b: &Valued<T>| {
        let value = a.value.clone() / b.value.clone() * rescale.clone();
        let rel = a.error.clone() / a.value.abs() + b.error.clone() / b.value.abs();
        reported(&value, &(value.abs() * rel))
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
        bias: reported(&bias, &bias_error),
        relative_noise: reported(&rel, &rel_err),
        mean_ratio: ratio(&mean_t, small_mean),
        variance_ratio: small_var.map(|v| ratio(&var, v)),
        integral_m2: scaled(&f.m2, &k),
        integral_p: scaled(&f.p, &k),
        integral_q: f.q.as_ref().map(|e| scaled(e, &k)),
        corr23: f.c23.as_ref().map(|e| scaled(e, &k)),
        corr24: f.c24.as_ref().map(|e| scaled(e, &k)),
        not_computed: not_weighed(f, counts).map(|why| {
            if ff.phase == mcrt_scene::Phase::Isotropic {
                why
            } else {
                format!("{why}; in a Henyey–Greenstein medium they are derived but not computed (docs/model.md §9.12: not yet affordable)")
            }
        }),
        covers,
        attenuation_shift: ff.shift.to_f64(),
        evaluations: f.evaluations(),
    }
}

/// The scope and evaluation budget of the library's prediction of `scene`
/// at `precision`: [`Scope::ExactPrediction`] with
/// [`crate::prec::FINITE_PAIRS_PREDICTION_EVALUATIONS`] where the
/// finite-sphere correlations of single-scattered light cover it in f64
/// ([`finite_pairs_cover`]), or with
/// [`crate::prec::FINITE_HG_PREDICTION_EVALUATIONS`] where the same-path
/// term of a Henyey–Greenstein medium does at q = 1 and N_B = 1
/// ([`finite_hg_moments_cover`]); [`Scope::Prediction`] with
/// [`crate::prec::EVERY_ORDER_PREDICTION_EVALUATIONS`] for scattering
/// orders ≥ 2 or `"all"` in f64 (the model of every order,
/// [`every_order_mean`]), else with [`Precision::default_evaluations`].
/// `check::predict` and
/// `mcrt-noise compare` both use it.
///
/// ```
/// use mcrt_noise::oracle::{prediction_scope, Precision, Scope};
/// use mcrt_noise::Scene;
///
/// let mut scene = Scene::builder()
///     .medium(1.0, 0.8)
///     .point_light([1.0, 0.0, 1.0], 1.0)
///     .camera([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
///     .estimator(0.2, 0.5, 20, 4)
///     .build()?;
/// assert_eq!(prediction_scope(&scene, Precision::F64), (Scope::Prediction, 1_000_000_000));
/// scene.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(1);
/// assert_eq!(prediction_scope(&scene, Precision::F64), (Scope::ExactPrediction, 3_000_000_000));
/// # #[cfg(feature = "mpfr")]
/// assert_eq!(prediction_scope(&scene, Precision::Bits(128)).0, Scope::Prediction);
/// (scene.estimator.q, scene.estimator.camera_rays) = (1.0, 1);
/// scene.medium.phase = mcrt_scene::Phase::HenyeyGreenstein { g: 0.6 };
/// assert_eq!(prediction_scope(&scene, Precision::F64), (Scope::ExactPrediction, 30_000_000_000));
/// scene.medium.phase = mcrt_scene::Phase::Isotropic;
/// scene.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(5);
/// assert_eq!(prediction_scope(&scene, Precision::F64), (Scope::Prediction, 3_000_000_000));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn prediction_scope(scene: &Scene, precision: Precision) -> (Scope, u64) {
    if precision == Precision::F64 && orders_beyond_the_first(scene) {
        (Scope::Prediction, crate::prec::EVERY_ORDER_PREDICTION_EVALUATIONS)
    } else if precision == Precision::F64 && finite_pairs_cover(scene) {
        (Scope::ExactPrediction, crate::prec::FINITE_PAIRS_PREDICTION_EVALUATIONS)
    } else if precision == Precision::F64 && finite_hg_moments_cover(scene) {
        (Scope::ExactPrediction, crate::prec::FINITE_HG_PREDICTION_EVALUATIONS)
    } else {
        (Scope::Prediction, precision.default_evaluations())
    }
}

/// Runs the oracle at `precision` with its default tolerance (or `rel_tol`)
/// and the default evaluation budget ([`Precision::default_evaluations`]):
/// every integral of both models ([`Scope::Everything`]).
pub fn run(scene: &Scene, precision: Precision, rel_tol: Option<f64>) -> Result<Report, OracleError> {
    run_scoped(scene, precision, rel_tol, Scope::Everything)
}

/// [`run`] to the extent `scope` (example at [`Scope`]).
pub fn run_scoped(
    scene: &Scene,
    precision: Precision,
    rel_tol: Option<f64>,
    scope: Scope,
) -> Result<Report, OracleError> {
    run_within_scoped(scene, precision, rel_tol, &Budget::new(precision.default_evaluations()), scope)
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
    run_within_scoped(scene, precision, rel_tol, budget, Scope::Everything)
}

/// [`run_within`] to the extent `scope`.
pub fn run_within_scoped(
    scene: &Scene,
    precision: Precision,
    rel_tol: Option<f64>,
    budget: &Budget,
    scope: Scope,
) -> Result<Report, OracleError> {
    let tol = rel_tol.unwrap_or(precision.default_tol_for(scene));
    match precision {
        Precision::F64 => run_with_scoped(scene, &0.0f64, tol, "f64".into(), budget, scope),
        #[cfg(feature = "mpfr")]
        Precision::Bits(b) => {
            run_with_scoped(scene, &rug::Float::with_val(b, 0), tol, format!("{b} bits"), budget, scope)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Precision;

    /// `f64` parses in every build; a number of bits only with the `mpfr`
    /// feature, and is refused naming it without.
    #[test]
    fn precision_parses_bits_only_with_mpfr() {
        assert_eq!(Precision::parse("f64"), Ok(Precision::F64));
        assert_eq!(Precision::F64.mpfr_bits(), None);
        #[cfg(feature = "mpfr")]
        {
            assert_eq!(Precision::parse("128"), Ok(Precision::Bits(128)));
            assert_eq!(Precision::Bits(128).mpfr_bits(), Some(128));
            assert!(Precision::parse("31").is_err());
        }
        #[cfg(not(feature = "mpfr"))]
        {
            let err = Precision::parse("128").unwrap_err();
            assert!(err.contains("`mpfr` feature"), "{err}");
        }
    }
}
