//! What the oracle predicts for a scene, with both of its bars.

use crate::model::OracleError;
use crate::oracle::{self, EveryOrderMean, Precision, Report, ValueWithBar};
use crate::prec::{
    model_error_scale, FINITE_PAIRS_PREDICTION_TOL, MODEL_ERROR_RADIUS, SMALL_SPHERE_SCATTERED_ALLOWANCE,
    SMALL_SPHERE_SCATTERED_ALLOWANCE_WITHOUT_CROSS,
};
use crate::quad::Budget;
use mcrt_scene::{ScatteringOrders, Scene, SceneError};
use serde::Serialize;
use std::fmt;

/// Which model produced a [`Prediction`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Model {
    /// The finite-sphere model (`docs/model.md` §9): the estimator's exact
    /// moments at the scene's R, for uncollided light, and for
    /// single-scattered light in isotropic media (point lights and beams at
    /// any q and N_B, in f64), and for scattering orders 2 to 9 and `"all"`
    /// (point lights and beams in an isotropic medium, q = 1, N_B = 1, in
    /// f64). Its
    /// model bar is 0.
    FiniteSphere,
    /// The paper's small-sphere model (§4.3), exact only as R → 0; used for
    /// the other scenes with single-scattered light, with a measured model
    /// bar (for Var L, and for the mean where the finite-sphere mean is not
    /// computed: where it is, the mean is that exact μ(R), model bar 0).
    SmallSphere,
}

impl fmt::Display for Model {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Model::FiniteSphere => "finite-sphere",
            Model::SmallSphere => "small-sphere",
        })
    }
}

/// A predicted quantity with its two bars, each a bound on a distance from
/// the value, not a standard deviation: the true value of the estimator
/// lies within `value ± (quadrature_bar + model_bar)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Predicted {
    /// The model's value.
    pub value: f64,
    /// Bound on the quadrature's error (the engine's cross-checked bar).
    pub quadrature_bar: f64,
    /// Bound on the model's own error at this R: 0 for the finite-sphere
    /// model; for the small-sphere model the measured allowance
    /// ([`Prediction::model_bar_basis`] says where it comes from).
    pub model_bar: f64,
}

impl Predicted {
    /// Both bars together.
    pub fn total_bar(&self) -> f64 {
        self.quadrature_bar + self.model_bar
    }
}

/// The oracle's prediction for one iteration of one pixel: what a renderer
/// running the estimator on this scene must produce on average.
///
/// ```
/// use mcrt_noise::{predict, Model, Scene};
///
/// let scene = Scene::builder()
///     .medium(1.0, 0.8)
///     .point_light([1.0, 0.0, 1.0], 1.0)
///     .camera([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
///     .estimator(0.2, 0.5, 20, 4)
///     .build()?;
/// let prediction = predict(&scene)?;
/// assert_eq!(prediction.model, Model::FiniteSphere);
/// assert_eq!(prediction.mean.model_bar, 0.0);
/// assert!(prediction.variance.quadrature_bar < 1e-9 * prediction.variance.value);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Serialize)]
pub struct Prediction {
    /// The model that produced the numbers.
    pub model: Model,
    /// ⟨⟨L⟩⟩, the mean of one iteration's L.
    pub mean: Predicted,
    /// Var L of one iteration with the scene's N_F, N_B, q, R.
    pub variance: Predicted,
    /// The estimator's bias b(R) = μ(R) − μ(0) with its quadrature bar,
    /// wherever the finite-sphere mean μ(R) was computed: with the
    /// finite-sphere model, and with the small-sphere model wherever
    /// `report.finite_mean` has it (a scene whose finite-sphere
    /// correlations or M₂, P failed, or in MPFR; point lights in a
    /// Henyey–Greenstein medium), and always for scattering orders ≥ 2 and
    /// `"all"`. There `mean` is that exact μ(R), model
    /// bar 0 (since 5 December 2026; it was the small-sphere μ(0) with its
    /// allowance), so μ(0) = mean − bias. (`report.finite_mean` is
    /// `prediction.report.up_to_order_one()?.finite_mean`.)
    pub bias: Option<ValueWithBar>,
    /// Where the model bar comes from, in words.
    pub model_bar_basis: String,
    /// The oracle's report behind the numbers: for scattering orders 0 and
    /// 1 both models, the integrals and their bars; for every order the
    /// exact mean, Var L, M₂ with its same-path pairs, and P.
    pub report: PredictionReport,
}

/// The oracle's report behind a [`Prediction`], by the scene's scattering
/// orders.
///
/// ```
/// use mcrt_noise::{predict, Scene};
///
/// let scene = Scene::builder()
///     .medium(1.0, 0.8)
///     .point_light([1.0, 0.0, 1.0], 1.0)
///     .camera([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
///     .estimator(0.2, 0.5, 20, 4)
///     .build()?;
/// let prediction = predict(&scene)?;
/// let report = prediction.report.up_to_order_one().expect("uncollided light: orders 0 and 1");
/// assert_eq!(report.finite.as_ref().unwrap().covers, "uncollided");
/// assert!(prediction.report.every_order().is_none());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// Serialized externally tagged: `{"up-to-order-one": {…}}` or
/// `{"every-order": {…}}`.
#[derive(Debug, Clone, Serialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum PredictionReport {
    /// `scattering_orders` 0 or 1: the oracle's [`Report`] (both models,
    /// the integrals, their bars), to the extent the prediction needs
    /// ([`oracle::Scope::Prediction`]: with q = 1 and N_B = 1 the
    /// small-sphere integrals of two spheres, which Var L weighs 0, are not
    /// computed).
    UpToOrderOne(Box<Report>),
    /// `scattering_orders` from 2 to 9 or `"all"` (at q = 1 and one camera
    /// ray, where Var L is modelled): the exact mean, its small-sphere limit, the bias,
    /// Var L, M₂ with its same-path pairs and P ([`oracle::every_order_mean`],
    /// `docs/model.md` §10).
    EveryOrder(Box<EveryOrderMean>),
}

impl PredictionReport {
    /// The report of a scene with scattering orders 0 or 1, if this is one.
    pub fn up_to_order_one(&self) -> Option<&Report> {
        match self {
            PredictionReport::UpToOrderOne(r) => Some(r),
            PredictionReport::EveryOrder(_) => None,
        }
    }

    /// The report of a scene with every scattering order, if this is one.
    pub fn every_order(&self) -> Option<&EveryOrderMean> {
        match self {
            PredictionReport::EveryOrder(r) => Some(r),
            PredictionReport::UpToOrderOne(_) => None,
        }
    }
}

/// Why there is no prediction.
#[derive(Debug, Clone, PartialEq)]
pub enum PredictError {
    /// The scene is invalid (every invalid value named).
    Scene(SceneError),
    /// The oracle cannot compute this scene ([`OracleError::Unsupported`]),
    /// did not converge, or its result is beyond f64: the oracle's error,
    /// its kind kept.
    Oracle(OracleError),
    /// The scene is valid but outside what the oracle can vouch for.
    Unsupported(String),
}

impl fmt::Display for PredictError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PredictError::Scene(e) => write!(f, "{e}"),
            PredictError::Oracle(e) => write!(f, "oracle: {e}"),
            PredictError::Unsupported(e) => write!(f, "unsupported: {e}"),
        }
    }
}

impl std::error::Error for PredictError {}

impl From<SceneError> for PredictError {
    fn from(e: SceneError) -> Self {
        PredictError::Scene(e)
    }
}

impl From<OracleError> for PredictError {
    fn from(e: OracleError) -> Self {
        PredictError::Oracle(e)
    }
}

/// The prediction for `scene` in f64 at the default tolerance (1e-10
/// relative for uncollided light, 1e-6 with scattered light; the
/// finite-sphere correlations of single-scattered light 1e-3,
/// [`crate::prec::FINITE_PAIRS_PREDICTION_TOL`]).
///
/// The scene is validated first (a hand-assembled [`Scene`] gets the scene
/// file's checks). Uncollided light (scattering order 0) is predicted by the
/// finite-sphere model, exact at the scene's R: the model bar is 0.
/// Single-scattered light (order 1) in an isotropic medium is predicted by
/// the finite-sphere model too, exact at any R (model bar 0): point lights
/// and beams with q = 1 and N_B = 1 ([`oracle::finite_sphere_covers`]), and
/// both at any q, N_B in f64 with the correlations of two spheres
/// that the scene's Var L weighs ([`oracle::finite_pairs_cover`],
/// [`oracle::Scope::ExactPrediction`], at a goal no tighter than
/// [`crate::prec::FINITE_PAIRS_PREDICTION_TOL`] with the budget
/// [`crate::prec::FINITE_PAIRS_PREDICTION_EVALUATIONS`]);
/// the oracle computes the small-sphere model beside it all the same, so
/// a failure of that model fails the prediction too (none is known since
/// its (23) was mended for lights near the camera line, `docs/model.md`
/// §9.6). If the finite-sphere
/// computation itself fails, the small-sphere model with its allowance
/// serves for R ≤ 0.1 and the failure is returned beyond (and with a beam,
/// whose small-sphere error was never measured).
/// So is single-scattered light from point lights in a Henyey–Greenstein
/// medium at q = 1 and N_B = 1 in f64 ([`oracle::finite_hg_moments_cover`]:
/// μ, M₂ with the same-path term, P, `docs/model.md` §9.10, at the same
/// goal, with the budget [`crate::prec::FINITE_HG_PREDICTION_EVALUATIONS`]),
/// with the same fallback.
/// In MPFR a beam at q < 1 or N_B > 1 is refused (the finite-sphere
/// correlations run in f64 only, and the small-sphere model, whose pair
/// integrals for a beam's scattered light lack the cross-segment terms,
/// `docs/model.md` §3a, has no measured model error there).
/// Other order-1 scenes (Henyey–Greenstein media at q < 1 or N_B > 1, or in
/// MPFR; in MPFR, point lights with q < 1 or N_B > 1) are predicted by the small-sphere
/// model with its
/// measured allowance as the model bar, for R ≤ 0.1
/// ([`crate::prec::SMALL_SPHERE_SCATTERED_ALLOWANCE`] where its (23), (24)
/// carry the cross-segment terms of erratum E10, isotropic media, or where
/// q = 1 and N_B = 1 weigh (23), (24) 0;
/// [`crate::prec::SMALL_SPHERE_SCATTERED_ALLOWANCE_WITHOUT_CROSS`]
/// elsewhere); larger R there is refused.
/// Scattering orders 2 to 9 and `"all"` are predicted by the finite-sphere
/// model of every order (`docs/model.md` §10.3, f64 only, model bar 0, the
/// bias predicted) for point lights in an isotropic medium at q = 1 and
/// N_B = 1, the only setting whose Var L it has; at other q and N_B they
/// are refused before any integral, naming the fields.
///
/// Cost: milliseconds for uncollided light in a release build; for single
/// scattering ~1.5 s with q = 1 and N_B = 1 (isotropic medium, point
/// lights; the small-sphere integrals of two spheres, weighed 0, are
/// skipped), ~15 s with a beam (its single-scattered light is a 2-D
/// quadrature at every table node, `docs/model.md` §9.8), about a minute
/// with point lights at q < 1 or N_B > 1 (the finite-sphere correlations:
/// ~61 s on `point-isotropic-order1`, minutes with a light near the camera
/// line), about 5 minutes for point lights in a Henyey–Greenstein medium
/// at q = 1 and N_B = 1 (4·10⁹ evaluations, at any R) and ~10–15 s in
/// one at other q and N_B, ~9 s for every order (2.5·10⁸ evaluations on
/// the README scene at R = 0.2; `docs/library.md` gives the profile
/// settings a dependent crate needs for its debug tests).
pub fn predict(scene: &Scene) -> Result<Prediction, PredictError> {
    predict_with(scene, Precision::F64, None)
}

/// [`predict`] at a chosen precision and relative tolerance (default:
/// [`Precision::default_tol_for`]; the finite-sphere correlations of
/// single-scattered light, computed in f64 only, at `rel_tol` or
/// [`crate::prec::FINITE_PAIRS_PREDICTION_TOL`], whichever is looser).
///
/// ```
/// use mcrt_noise::{check::predict_with, oracle::Precision, Scene};
///
/// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic.toml"))?;
/// let scene = Scene::from_toml_str(&text)?;
/// let p = predict_with(&scene, Precision::F64, Some(1e-6))?;
/// assert!(p.mean.quadrature_bar <= 1e-6 * p.mean.value);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn predict_with(scene: &Scene, precision: Precision, rel_tol: Option<f64>) -> Result<Prediction, PredictError> {
    let (_, evaluations) = oracle::prediction_scope(scene, precision);
    predict_within(scene, precision, rel_tol, &Budget::new(evaluations))
}

/// [`predict_with`] within the evaluation budget (and deadline) `budget`,
/// shared by every integral of the prediction, in place of its default
/// ([`Precision::default_evaluations`], or
/// [`crate::prec::FINITE_PAIRS_PREDICTION_EVALUATIONS`] where the
/// finite-sphere correlations of single-scattered light are computed, or
/// [`crate::prec::FINITE_HG_PREDICTION_EVALUATIONS`] where the same-path
/// term of a Henyey–Greenstein medium is, or
/// [`crate::prec::EVERY_ORDER_PREDICTION_EVALUATIONS`] for orders ≥ 2:
/// [`oracle::prediction_scope`]).
/// Those correlations (or that term) run last: if they spend the budget the small-sphere
/// model with its allowance serves for R ≤ 0.1, and beyond the failure is
/// returned ([`PredictError::Oracle`]). With every scattering order there
/// is no fallback: a spent budget fails the prediction
/// ([`PredictError::Oracle`] with the quadrature's error; the default
/// budget, 3·10⁹ evaluations, is ~13 times what the README scene with
/// `"all"` needs and twice what order 9 at N_F = 1 does), and
/// `rel_tol` must lie in [`oracle::EVERY_ORDER_TOL_RANGE`].
///
/// ```
/// use mcrt_noise::{check::predict_within, oracle::Precision, quad::Budget, Scene};
///
/// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic.toml"))?;
/// let scene = Scene::from_toml_str(&text)?;
/// assert!(predict_within(&scene, Precision::F64, None, &Budget::new(100)).is_err());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn predict_within(
    scene: &Scene,
    precision: Precision,
    rel_tol: Option<f64>,
    budget: &Budget,
) -> Result<Prediction, PredictError> {
    let scene = scene.validated()?;
    if let Some(tol) = rel_tol {
        if !(tol > 0.0 && tol < 1.0) {
            return Err(PredictError::Unsupported(format!("rel_tol = {tol:e}: must be in (0, 1)")));
        }
    }
    if oracle::orders_beyond_the_first(&scene) {
        return predict_every_order(&scene, precision, rel_tol, budget);
    }
    let scattered = scene.effects.scattering_orders != ScatteringOrders::Limited(0);
    let radius = scene.estimator.radius;
    let small_sphere_too_large = |why: &str| {
        PredictError::Unsupported(format!(
            "estimator.radius = {radius}: with scattered light (effects.scattering_orders ≥ 1) the prediction here \
             is the small-sphere model ({why}), whose own error is measured only for R ≤ {MODEL_ERROR_RADIUS}; use \
             R ≤ {MODEL_ERROR_RADIUS}, or scattering_orders = 1 in an isotropic medium (the finite-sphere model, \
             exact at any R: point lights and beams at any q and N_B in f64) or with point lights in a \
             Henyey–Greenstein medium at q = 1 and camera_rays = 1 (f64), or scattering_orders = 0"
        ))
    };
    // With a beam, what the finite-sphere model does not cover the oracle
    // refuses at any R, naming the fields (a smaller R would not help).
    let scattered_beam = scattered && scene.lights.iter().any(|l| matches!(l, mcrt_scene::Light::Beam { .. }));
    let (scope, _) = oracle::prediction_scope(&scene, precision);
    let with_pairs = scope == oracle::Scope::ExactPrediction;
    let covered = oracle::finite_sphere_covers(&scene) || with_pairs;
    if scattered && !scattered_beam && radius > MODEL_ERROR_RADIUS && !covered {
        let why = if oracle::finite_pairs_cover(&scene) {
            "in MPFR the finite-sphere correlations of single-scattered light are not computed: f64 gives them"
        } else if oracle::finite_hg_moments_cover(&scene) {
            "in MPFR the finite-sphere model of a Henyey–Greenstein medium is not computed: f64 gives it"
        } else {
            "the finite-sphere model does not cover this scene"
        };
        return Err(small_sphere_too_large(why));
    }
    // A beam's scattered light where (7)–(9) weigh the correlations, in
    // MPFR: the finite-sphere correlations are computed in f64 only, and the
    // small-sphere model's own error was never measured for a beam (it
    // lacks the cross-segment pairs of E10 there, `docs/model.md` §3a), so
    // it cannot serve: refused before the run.
    if scattered_beam && oracle::finite_pairs_cover(&scene) && !with_pairs {
        return Err(PredictError::Unsupported(
            "a beam's single-scattered light with estimator.q < 1 or estimator.camera_rays > 1 is predicted by the \
             finite-sphere model's correlations, computed in f64 only (use precision f64); the small-sphere model, \
             which MPFR would give, has no measured model error for a beam"
                .into(),
        ));
    }
    let report = oracle::run_within_scoped(&scene, precision, rel_tol, budget, scope)?;
    let p = &report.prediction;
    let mut mean = p.mean;
    let (model, (mean_rel, var_rel), basis) = match &report.finite {
        Some(f) if f.covers == "uncollided" => (Model::FiniteSphere, (0.0, 0.0), FINITE_BASIS.to_string()),
        Some(_) if with_pairs && scene.medium.phase != mcrt_scene::Phase::Isotropic => {
            (Model::FiniteSphere, (0.0, 0.0), finite_hg_basis())
        }
        Some(_) if with_pairs => (Model::FiniteSphere, (0.0, 0.0), finite_pairs_basis()),
        Some(_) => (Model::FiniteSphere, (0.0, 0.0), FINITE_ORDER1_BASIS.to_string()),
        // A covered scene whose finite-sphere computation failed: beyond the
        // small-sphere model's measured range that failure is the answer, and
        // so it is with a beam's scattered light, where that model's own
        // error was never measured (the allowance is a point light's).
        None if radius > MODEL_ERROR_RADIUS || scattered_beam => {
            return Err(match &report.finite_error {
                Some(e) => PredictError::Oracle(e.clone()),
                None => small_sphere_too_large(report.finite_not_used.as_deref().unwrap_or("no finite-sphere model")),
            })
        }
        None => {
            let scale = model_error_scale(radius);
            let crossed =
                |c: &Option<crate::oracle::Correlation>| c.as_ref().is_some_and(|c| c.cross_segment.is_some());
            // With q = 1 and N_B = 1, (7)–(9) weigh (23), (24) 0: the
            // model is the same with or without the cross-segment terms.
            let cross = if oracle::pairs_weigh_nothing(&scene) {
                CrossTerms::WeighNothing
            } else if crossed(&report.corr23) && crossed(&report.corr24) {
                CrossTerms::Added
            } else {
                CrossTerms::NotAdded
            };
            let (m, v) = match cross {
                CrossTerms::NotAdded => SMALL_SPHERE_SCATTERED_ALLOWANCE_WITHOUT_CROSS,
                _ => SMALL_SPHERE_SCATTERED_ALLOWANCE,
            };
            let mut basis = small_sphere_basis(radius, (m * scale, v * scale), cross);
            if let Some(why) = &report.finite_not_used {
                basis.push_str(&format!(". Not the finite-sphere model: {why}"));
            }
            // The exact mean, where the oracle has it, replaces the
            // small-sphere μ(0) and its allowance: the renderer's mean at R
            // is μ(R).
            match report.finite_mean.as_ref().and_then(|f| f.mean) {
                Some(exact) => {
                    mean = exact;
                    basis.push_str(EXACT_MEAN_BASIS);
                    (Model::SmallSphere, (0.0, v * scale), basis)
                }
                None => (Model::SmallSphere, (m * scale, v * scale), basis),
            }
        }
    };
    let predicted = |v: ValueWithBar, rel: f64| Predicted {
        value: v.value,
        quadrature_bar: v.error,
        model_bar: rel * v.value.abs(),
    };
    Ok(Prediction {
        model,
        mean: predicted(mean, mean_rel),
        variance: predicted(p.variance, var_rel),
        // On the small-sphere fallback the exact mean may still be there.
        bias: report.finite.as_ref().map(|f| f.bias).or_else(|| report.finite_mean.as_ref().and_then(|m| m.bias)),
        model_bar_basis: basis,
        report: PredictionReport::UpToOrderOne(Box::new(report)),
    })
}

/// The prediction of a scene with scattering orders ≥ 2 or `"all"`: the
/// finite-sphere model of every order (`docs/model.md` §10, f64 only),
/// exact at R, model bar 0, where it has Var L (q = 1 and one camera ray,
/// isotropic medium, point lights and beams); elsewhere refused with the oracle's
/// reason. Var L's integrals that fail (a spent budget) fail the
/// prediction with their error, its kind kept.
fn predict_every_order(
    scene: &Scene,
    precision: Precision,
    rel_tol: Option<f64>,
    budget: &Budget,
) -> Result<Prediction, PredictError> {
    let orders = scene.effects.scattering_orders.as_toml();
    // Refused before any integral: what the model of every order does not
    // cover (its medium, lights) or has no Var L of, then MPFR and a goal
    // outside its range.
    oracle::every_order_variance_refusal(scene)?;
    if let Some(bits) = precision.mpfr_bits() {
        return Err(PredictError::Oracle(OracleError::Unsupported(format!(
            "precision = {bits} bits: with effects.scattering_orders = {orders} the oracle computes in f64 only \
             (allowed: f64)"
        ))));
    }
    if let Some(tol) = rel_tol {
        let (lo, hi) = oracle::EVERY_ORDER_TOL_RANGE;
        if !(lo..=hi).contains(&tol) {
            return Err(PredictError::Unsupported(format!(
                "rel_tol = {tol:e}: with effects.scattering_orders = {orders} must be in [{lo:e}, {hi:e}] (the tables \
                 of every order need goals no finer in f64; Var L's integrals run at {:e} or looser)",
                oracle::EVERY_ORDER_VARIANCE_TOL
            )));
        }
    }
    let (report, variance_error) = oracle::every_order_report(scene, rel_tol, budget)?;
    if let Some(e) = variance_error {
        return Err(PredictError::Oracle(e));
    }
    let Some(variance) = report.variance else {
        return Err(PredictError::Oracle(OracleError::Unsupported(format!(
            "Var L of every order: {}",
            report.variance_missing.as_deref().unwrap_or("not computed")
        ))));
    };
    let exact = |v: ValueWithBar| Predicted { value: v.value, quadrature_bar: v.error, model_bar: 0.0 };
    Ok(Prediction {
        model: Model::FiniteSphere,
        mean: exact(report.mean),
        variance: exact(variance),
        bias: Some(report.bias),
        model_bar_basis: every_order_basis(report.variance_rel_tol.unwrap_or(report.rel_tol)),
        report: PredictionReport::EveryOrder(Box::new(report)),
    })
}

fn every_order_basis(variance_tol: f64) -> String {
    format!(
        "none needed: the finite-sphere model of every scattering order is exact at this R (isotropic medium, \
         point lights and beams, q = 1, N_B = 1; M₂ with the same-path pairs of one forward path; docs/model.md \
         §10.3, §10.6); Var \
         L's integrals are computed to a goal of {variance_tol:e}, within the quadrature bar"
    )
}

/// What the basis adds where the small-sphere prediction takes the
/// finite-sphere model's exact mean.
const EXACT_MEAN_BASIS: &str = ". The mean is not the small-sphere one: it is the finite-sphere model's \
     exact μ(R) (`finite_mean`; docs/model.md §9.5, §9.9), model bar 0; the bar above is Var L's";

const FINITE_BASIS: &str = "none needed: the finite-sphere model is exact at this R for uncollided light";

const FINITE_ORDER1_BASIS: &str = "none needed: the finite-sphere model is exact at this R for uncollided and \
     single-scattered light (isotropic medium, q = 1, N_B = 1; docs/model.md §9.6, §9.8)";

fn finite_pairs_basis() -> String {
    format!(
        "none needed: the finite-sphere model is exact at this R for uncollided and single-scattered light, the \
         correlations of two spheres included (isotropic medium, point lights; docs/model.md §9.6, §9.7); they \
         are computed to a goal no tighter than {FINITE_PAIRS_PREDICTION_TOL:e}, within the quadrature bar"
    )
}

fn finite_hg_basis() -> String {
    format!(
        "none needed: the finite-sphere model is exact at this R for uncollided and single-scattered light (point \
         lights in a Henyey–Greenstein medium at q = 1 and N_B = 1, with the same-path term of M₂; docs/model.md \
         §9.9, §9.10); it is computed to a goal no tighter than {FINITE_PAIRS_PREDICTION_TOL:e}, within the \
         quadrature bar"
    )
}

/// Whether the small-sphere model's (23), (24) carry the cross-segment
/// terms of E10, which picks the measured bar.
#[derive(Debug, Clone, Copy)]
enum CrossTerms {
    /// Added (isotropic media, R in their form's range).
    Added,
    /// Not added (Henyey–Greenstein media, R out of range, a failure).
    NotAdded,
    /// q = 1 and N_B = 1: (7)–(9) weigh (23), (24) 0, so the model is the
    /// same with or without them.
    WeighNothing,
}

fn small_sphere_basis(radius: f64, (mean, variance): (f64, f64), cross: CrossTerms) -> String {
    let which = match cross {
        CrossTerms::Added => "with the cross-segment terms of (23), (24) (E10) in the model",
        CrossTerms::NotAdded => {
            "measured before the cross-segment terms of (23), (24) (E10) entered the model: they are not added for \
             this scene"
        }
        CrossTerms::WeighNothing => {
            "with the cross-segment terms of (23), (24) (E10) in the model; here q = 1 and N_B = 1, where (7)–(9) \
             weigh (23), (24) 0, with those terms or without"
        }
    };
    format!(
        "the small-sphere model's own error, measured with the reference tracer on point-isotropic-order1 at R = \
         {MODEL_ERROR_RADIUS} (the larger of two (q, N_F, N_B) settings, plus two standard errors; {which}) and \
         carried to R = {radius} by R ln(1/R): {:.2} % of the mean, {:.2} % of Var L. A measurement, not a bound: \
         other media and lights may differ (tests/tracer_vs_oracle.rs re-measures it)",
        mean * 100.0,
        variance * 100.0
    )
}
