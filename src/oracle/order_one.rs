//! What the finite-sphere model covers of an order-1 scene (uncollided
//! plus single-scattered light) and what the oracle computes of it: the
//! exact mean always, μ, M₂ and P where q = 1 and N_B = 1, the correlations
//! of two spheres when asked ([`Scope::FinitePairs`](super::Scope::FinitePairs),
//! [`Scope::ExactPrediction`](super::Scope::ExactPrediction)), and why the prediction is not this
//! model where it is not.

use super::report::{reported, FiniteMean, PAIRS_NOT_NEEDED};
use crate::model::field::Field;
use crate::model::finite::{FiniteField, FiniteIntegrals, Functional, Weighed};
use crate::model::noise::Counts;
use crate::model::OracleError;
use crate::prec::FINITE_HG_MEAN_TOL;
use crate::quad::{CheckRule, Estimate, Options};
use mcrt_scene::{Light, Scene};

/// The finite-sphere field of an order-1 scene whose exact mean the model
/// covers (isotropic medium, `model::finite::scattered`,
/// `model::finite::scattered_beam`; point lights in a Henyey–Greenstein
/// medium, `model::finite::scattered_hg`), or `None`.
pub(super) fn scattered_mean_field<T: CheckRule>(scene: &Scene, field: &Field<T>) -> Option<FiniteField<T>> {
    // The Henyey–Greenstein route's nest is affordable with the f64
    // Gauss–Kronrod pair only.
    let affordable = scene.medium.phase == mcrt_scene::Phase::Isotropic || field.sigma_ext.prec() <= 53;
    (scattered_mean_covered(scene) && affordable).then(|| FiniteField::of_first_segments(scene, field))
}

/// An order-1 scene whose exact mean the finite-sphere model covers: an
/// isotropic medium (point lights and beams), or point lights only in a
/// Henyey–Greenstein medium (its Var L there at q = 1 and N_B = 1 with
/// [`Scope::FinitePairs`](super::Scope::FinitePairs) and, in f64,
/// [`Scope::ExactPrediction`](super::Scope::ExactPrediction) only,
/// `docs/model.md` §9.10; the correlations of two spheres are not computed
/// there, §9.12).
fn scattered_mean_covered(scene: &Scene) -> bool {
    scene.effects.scattering_orders == mcrt_scene::ScatteringOrders::Limited(1)
        && (scene.medium.phase == mcrt_scene::Phase::Isotropic
            || scene.lights.iter().all(|l| matches!(l, Light::Point { .. })))
}

/// Whether the oracle's prediction for `scene` is the finite-sphere model
/// (exact at the scene's R; when its computation succeeds): uncollided
/// light, and single-scattered light in an isotropic medium (point lights
/// and beams) with q = 1 and N_B = 1: what every scope covers. (With
/// [`Scope::FinitePairs`](super::Scope::FinitePairs) and
/// [`Scope::ExactPrediction`](super::Scope::ExactPrediction), the library's
/// `predict`, the oracle gives it at other q and N_B too, for point lights:
/// [`finite_pairs_cover`].)
///
/// ```
/// use mcrt_noise::{oracle::finite_sphere_covers, Scene};
///
/// let mut scene = Scene::builder()
///     .medium(1.0, 0.8)
///     .point_light([1.0, 0.0, 1.0], 1.0)
///     .camera([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
///     .estimator(0.2, 1.0, 20, 1)
///     .build()?;
/// assert!(finite_sphere_covers(&scene));
/// scene.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(1);
/// assert!(finite_sphere_covers(&scene));
/// scene.estimator.camera_rays = 4;
/// assert!(!finite_sphere_covers(&scene));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn finite_sphere_covers(scene: &Scene) -> bool {
    use mcrt_scene::ScatteringOrders::Limited;
    match scene.effects.scattering_orders {
        Limited(0) => true,
        Limited(1) => scattered_covered(scene) && pairs_weigh_nothing(scene),
        _ => false,
    }
}

/// Whether [`Scope::ExactPrediction`](super::Scope::ExactPrediction) (and [`Scope::FinitePairs`](super::Scope::FinitePairs)) give
/// the finite-sphere model of `scene` with the correlations of two spheres
/// (exact at any R, q, N_B; when their computation succeeds): single-scattered
/// light in an isotropic medium, point lights and beams (`docs/model.md`
/// §9.7, §9.11), q < 1 or N_B > 1 (at q = 1 and N_B = 1
/// [`finite_sphere_covers`] covers it without them).
///
/// ```
/// use mcrt_noise::oracle::finite_pairs_cover;
/// use mcrt_noise::Scene;
///
/// let mut scene = Scene::builder()
///     .medium(1.0, 0.8)
///     .point_light([1.0, 0.0, 1.0], 1.0)
///     .camera([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
///     .estimator(0.2, 0.5, 20, 4)
///     .build()?;
/// assert!(!finite_pairs_cover(&scene)); // uncollided light needs no pairs model
/// scene.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(1);
/// assert!(finite_pairs_cover(&scene));
/// scene.medium.phase = mcrt_scene::Phase::HenyeyGreenstein { g: 0.5 };
/// assert!(!finite_pairs_cover(&scene));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn finite_pairs_cover(scene: &Scene) -> bool {
    scattered_covered(scene) && !pairs_weigh_nothing(scene)
}

/// Whether [`Scope::ExactPrediction`](super::Scope::ExactPrediction) (and
/// [`Scope::FinitePairs`](super::Scope::FinitePairs)) give the finite-sphere
/// model of `scene` through the same-path term of a Henyey–Greenstein
/// medium (exact at any R; when its computation succeeds, f64 only):
/// single-scattered light from point lights in a Henyey–Greenstein medium
/// at q = 1 and N_B = 1, where Var L needs μ, M₂ and P only
/// (`docs/model.md` §9.10; minutes: 4·10⁹ evaluations at 10⁻³). At q < 1
/// or N_B > 1 its correlations of two spheres are derived but not computed
/// (§9.12).
///
/// ```
/// use mcrt_noise::oracle::finite_hg_moments_cover;
/// use mcrt_noise::Scene;
///
/// let mut scene = Scene::builder()
///     .medium(1.0, 0.8)
///     .point_light([1.0, 0.0, 1.0], 1.0)
///     .camera([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
///     .estimator(0.2, 1.0, 20, 1)
///     .build()?;
/// scene.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(1);
/// assert!(!finite_hg_moments_cover(&scene)); // isotropic: `finite_sphere_covers`
/// scene.medium.phase = mcrt_scene::Phase::HenyeyGreenstein { g: 0.6 };
/// assert!(finite_hg_moments_cover(&scene));
/// scene.estimator.q = 0.5;
/// assert!(!finite_hg_moments_cover(&scene));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn finite_hg_moments_cover(scene: &Scene) -> bool {
    scattered_mean_covered(scene) && !scattered_covered(scene) && pairs_weigh_nothing(scene)
}

/// Whether the finite-sphere model covers `scene` once q = 1 and N_B = 1
/// (the standard method: one sphere per camera ray, one camera ray) at any
/// R: uncollided light, single-scattered light in an isotropic medium
/// (point lights and beams), and scattering orders 2 to 9 and `"all"`
/// (point lights off the camera line and beams in an isotropic medium,
/// albedo > 0, below 1 for `"all"`; `docs/model.md` §10.3, §10.6).
/// `tuning::optimize`
/// searches R there.
///
/// ```
/// use mcrt_noise::{oracle::finite_sphere_covers_the_standard_method, Scene};
///
/// let mut scene = Scene::builder()
///     .medium(1.0, 0.8)
///     .point_light([1.0, 0.0, 1.0], 1.0)
///     .camera([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
///     .estimator(0.2, 0.5, 20, 4)
///     .build()?;
/// scene.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(1);
/// assert!(finite_sphere_covers_the_standard_method(&scene));
/// scene.medium.phase = mcrt_scene::Phase::HenyeyGreenstein { g: 0.5 };
/// assert!(!finite_sphere_covers_the_standard_method(&scene));
/// scene.effects.scattering_orders = mcrt_scene::ScatteringOrders::All;
/// assert!(!finite_sphere_covers_the_standard_method(&scene));
/// scene.medium.phase = mcrt_scene::Phase::Isotropic;
/// assert!(finite_sphere_covers_the_standard_method(&scene));
/// scene.medium.albedo = 1.0;
/// assert!(!finite_sphere_covers_the_standard_method(&scene)); // the orders never end
/// scene.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(3);
/// assert!(finite_sphere_covers_the_standard_method(&scene)); // a finite order ends
/// scene.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(12);
/// assert!(!finite_sphere_covers_the_standard_method(&scene)); // beyond the cut integral's reach
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn finite_sphere_covers_the_standard_method(scene: &Scene) -> bool {
    use mcrt_scene::ScatteringOrders::{All, Limited};
    match scene.effects.scattering_orders {
        Limited(0) => true,
        Limited(1) => scattered_covered(scene),
        orders => {
            let a = scene.medium.albedo;
            // "all" at albedo 1 never ends; a finite order n needs the
            // cut integrals of orders up to n + 1 (`MAX_FINITE_ORDER`).
            let ends = match orders {
                All => a < 1.0,
                Limited(n) => n < crate::model::finite::start_density::MAX_FINITE_ORDER,
            };
            a > 0.0 && ends && super::every_order::every_order_scene_covered(scene).is_ok()
        }
    }
}

/// An order-1 scene whose medium the finite-sphere model of single
/// scattering covers whole (mean and Var L): isotropic (point lights and
/// beams).
pub(super) fn scattered_covered(scene: &Scene) -> bool {
    scene.effects.scattering_orders == mcrt_scene::ScatteringOrders::Limited(1)
        && scene.medium.phase == mcrt_scene::Phase::Isotropic
}

/// Whether (7)–(9) weigh Q, C₂₃ and C₂₄ 0: q = 1 (one sphere per camera
/// ray) and N_B = 1 (one camera ray), where [`Weighed::of`] weighs neither
/// correlation (Q's weight has the factor 1 − q of C₂₃'s).
pub(crate) fn pairs_weigh_nothing(scene: &Scene) -> bool {
    Weighed::of(scene.estimator.q, scene.estimator.camera_rays) == Weighed::NONE
}

/// What the finite-sphere model gives of an order-1 scene.
pub(super) enum OrderOne<T> {
    /// μ, M₂, P: the whole model where the pairs weigh nothing; with Q and
    /// the correlations Var L weighs where they were asked for
    /// ([`Scope::FinitePairs`](super::Scope::FinitePairs),
    /// [`Scope::ExactPrediction`](super::Scope::ExactPrediction)).
    Integrals(FiniteIntegrals<T>),
    /// μ(R)·e^{c₀} alone: the pairs are not affordable yet, or (the
    /// error) the whole model was asked for and failed.
    Mean(Estimate<T>, Option<OracleError>),
}

/// The finite-sphere model of an order-1 scene: its μ, M₂ and P when
/// `unpaired` (q = 1, N_B = 1: all its Var L needs), else — or when M₂ or P
/// fails (none is known to; the fallback keeps the exact mean) — μ(R)·e^{c₀} =
/// μ₀(R) + μ₁(R) alone, the uncollided mean (ray-centric) plus the
/// single-scattered one (`finite::scattered`), computed once either way.
pub(super) fn order_one<T: CheckRule>(
    ff: &FiniteField<T>,
    unpaired: bool,
    opts: &Options,
) -> Result<OrderOne<T>, OracleError> {
    if unpaired {
        let parts = ff.order1_unpaired_parts(opts)?;
        let mean = parts.mean?;
        return Ok(match (parts.m2, parts.p) {
            (Ok(m2), Ok(p)) => OrderOne::Integrals(FiniteIntegrals { mean, m2, p, q: None, c23: None, c24: None }),
            (Err(e), _) | (_, Err(e)) => OrderOne::Mean(mean, Some(e)),
        });
    }
    let o = opts.clone().declared();
    // A Henyey–Greenstein medium's mean at a goal no tighter than
    // `FINITE_HG_MEAN_TOL` (its cost), with the bars it reaches, and with a
    // budget of its own (the run's size): it runs beside the small-sphere
    // integrals, and spending theirs would fail the run, where its own
    // failure is only reported (`finite_mean.missing`).
    let hg = Options { rel_tol: o.rel_tol.max(FINITE_HG_MEAN_TOL), budget: o.budget.renewed(), ..o.clone() };
    let so = if ff.phase == mcrt_scene::Phase::Isotropic { &o } else { &hg };
    let (uncollided, scattered) = rayon::join(|| ff.ray_total(Functional::Mean, &o), || ff.scattered_mean(so));
    Ok(OrderOne::Mean(uncollided?.plus(scattered?), None))
}

/// Every integral of the order-1 finite-sphere model, Q and the
/// correlations `weighed` included ([`Scope::FinitePairs`](super::Scope::FinitePairs),
/// [`Scope::ExactPrediction`](super::Scope::ExactPrediction)), or, where that fails, the exact mean
/// `mean` computed before with the failure: the mean survives a budget the
/// pairs spent. Of the two means (`mean`, computed at the run's goal, and
/// the one computed beside the pairs, at theirs) the one with the smaller
/// bar is kept: two computations of one μ by different routes, each within
/// its bar (its evaluations count both).
pub(super) fn with_finite_pairs<T: CheckRule>(
    ff: &FiniteField<T>,
    mean: Estimate<T>,
    opts: &Options,
    weighed: Weighed,
) -> OrderOne<T> {
    match ff.order1_integrals_weighed(opts, weighed) {
        Ok(mut whole) => {
            // Both computations are charged, whichever is kept.
            let evaluations = whole.mean.evaluations + mean.evaluations;
            if mean.error < whole.mean.error {
                whole.mean = mean;
            }
            whole.mean.evaluations = evaluations;
            OrderOne::Integrals(whole)
        }
        Err(failed) => OrderOne::Mean(mean, Some(failed)),
    }
}

/// μ, M₂ and P of an order-1 scene with point lights in a Henyey–Greenstein
/// medium at q = 1 and N_B = 1 (`docs/model.md` §9.10; [`Scope::FinitePairs`](super::Scope::FinitePairs)
/// and, in f64, [`Scope::ExactPrediction`](super::Scope::ExactPrediction) only: 10⁹–10¹⁰
/// evaluations at 10⁻³), computed after everything else with `opts` (the
/// run's budget; the run's goal, or no tighter than 10⁻³ in the
/// prediction), or, where they fail, the exact mean `mean`
/// computed before (at its own goal and budget) with the failure. Of the two
/// means the one with the smaller bar is kept, as in [`with_finite_pairs`].
pub(super) fn with_hg_moments<T: CheckRule>(ff: &FiniteField<T>, mean: Estimate<T>, opts: &Options) -> OrderOne<T> {
    let parts = match ff.order1_unpaired_parts(opts) {
        Ok(parts) => parts,
        Err(failed) => return OrderOne::Mean(mean, Some(failed)),
    };
    match (parts.mean, parts.m2, parts.p) {
        (Ok(own), Ok(m2), Ok(p)) => {
            let evaluations = own.evaluations + mean.evaluations;
            let mut kept = if mean.error < own.error { mean } else { own };
            kept.evaluations = evaluations;
            OrderOne::Integrals(FiniteIntegrals { mean: kept, m2, p, q: None, c23: None, c24: None })
        }
        (Err(e), _, _) | (_, Err(e), _) | (_, _, Err(e)) => OrderOne::Mean(mean, Some(e)),
    }
}

/// Why an order-1 scene's prediction is not the finite-sphere model: what
/// the model does not cover yet, or its failure (`None` for order 0, or
/// when it is the prediction).
pub(super) fn finite_not_used<T>(scene: &Scene, run: &Result<Option<OrderOne<T>>, OracleError>) -> Option<String> {
    if scene.effects.scattering_orders == mcrt_scene::ScatteringOrders::Limited(0) {
        return None;
    }
    let e = &scene.estimator;
    let needed = match (e.q < 1.0, e.camera_rays > 1) {
        (true, true) => "C₂₃, Q and C₂₄",
        (true, false) => "C₂₃ and Q (q < 1: several spheres per camera ray)",
        _ => "C₂₄ (N_B > 1: several camera rays)",
    };
    match run {
        Ok(Some(OrderOne::Integrals(_))) => None,
        Ok(Some(OrderOne::Mean(_, Some(err)))) => {
            Some(format!("its computation failed (its exact mean is still `finite_mean`): {err}"))
        }
        // The mean itself failed (before any pairs were tried): that is
        // the reason, whatever the scene's q and N_B.
        Err(err) => Some(format!("its computation failed: {err}")),
        Ok(Some(OrderOne::Mean(_, None))) if scene.medium.phase != mcrt_scene::Phase::Isotropic => {
            Some(if pairs_weigh_nothing(scene) {
                "in a Henyey–Greenstein medium it gives the exact mean (`finite_mean`, docs/model.md §9.9); its Var L \
                 (here q = 1 and N_B = 1: μ, M₂ and P, with the same-path term ⟨𝒞₀𝒞₁⟩ of §9.10) takes ~4·10⁹ \
                 evaluations and minutes at 10⁻³, so the library's `predict` (f64) and `mcrt-noise oracle \
                 --finite-pairs` (give it --rel-tol and --max-evals) compute it, not this run"
                    .into()
            } else {
                format!(
                    "in a Henyey–Greenstein medium it gives the exact mean (`finite_mean`, docs/model.md §9.9) but not \
                     Var L at q = {}, N_B = {}: the correlations of two spheres ({needed}) are derived for isotropic \
                     media only (at q = 1 and N_B = 1 the library's `predict` and `mcrt-noise oracle --finite-pairs` compute \
                     Var L, §9.10)",
                    e.q, e.camera_rays
                )
            })
        }
        Ok(Some(OrderOne::Mean(_, None))) => Some(format!(
            "with single-scattered light it covers q = 1 and N_B = 1 only (here q = {}, N_B = {}), where (7)–(9) \
             weigh the correlations of two spheres 0; this scene needs {needed}, which take about a minute at \
             10⁻³ (docs/model.md §9.7): the library's `predict` computes them (point lights and beams, f64), and so does \
             `mcrt-noise oracle --finite-pairs` (give it --rel-tol and --max-evals); its exact mean is \
             `finite_mean`",
            e.q, e.camera_rays
        )),
        Ok(None) => Some(
            "the finite-sphere model of single-scattered light covers isotropic media, and for the mean point \
             lights (no beam) in a Henyey–Greenstein medium, in f64"
                .into(),
        ),
    }
}

/// The report's `finite_mean` from the order-1 mean μ(R)·e^{c₀} (or its
/// failure, reported as missing), with the small-sphere mean μ(0)·e^{c₀}
/// (`small`, restored by `k` = e^{−c₀}) for the bias, formed in the working
/// precision.
pub(super) fn finite_mean_report<T: CheckRule>(
    scattered: Result<Option<Estimate<T>>, OracleError>,
    ff: Option<&FiniteField<T>>,
    small: &Estimate<T>,
    k: &T,
) -> Option<FiniteMean> {
    match (scattered, ff) {
        (Ok(Some(m)), Some(ff)) => {
            let kf = (-ff.shift.clone()).exp();
            let (value, error) = (m.value.clone() * kf.clone(), m.error.clone() * kf);
            let bias = value.clone() - small.value.clone() * k.clone();
            let bias_error = error.clone() + small.error.clone() * k.clone();
            Some(FiniteMean {
                mean: Some(reported(&value, &error)),
                bias: Some(reported(&bias, &bias_error)),
                missing: None,
                evaluations: m.evaluations,
            })
        }
        (Err(e), _) => Some(FiniteMean { mean: None, bias: None, missing: Some(e.to_string()), evaluations: 0 }),
        _ => None,
    }
}

/// Why some of Q, C₂₃, C₂₄ are missing from a finite-sphere report: all
/// three at q = 1 and N_B = 1 ([`PAIRS_NOT_NEEDED`]), C₂₃ alone at q = 1,
/// C₂₄ alone at N_B = 1 (`Weighed`); `None` when none is.
pub(super) fn not_weighed<T: CheckRule>(f: &FiniteIntegrals<T>, counts: &Counts<T>) -> Option<String> {
    match (f.q.is_some(), f.c23.is_some(), f.c24.is_some()) {
        (true, true, true) => None,
        (false, _, _) => Some(PAIRS_NOT_NEEDED.to_string()),
        (true, false, true) => Some(format!(
            "C₂₃ enters Var L with weight 2(1 − q)/(N_F N_B) = 0 at q = {} (one \
             sphere per camera ray) and is not computed",
            counts.q.to_f64()
        )),
        (true, true, false) => Some(format!(
            "C₂₄ enters Var L with weight (1 − 1/N_B)/N_F = 0 at N_B = {} (one \
             camera ray) and is not computed",
            counts.n_b.to_f64()
        )),
        (true, false, false) => Some(
            "C₂₃ and C₂₄ enter Var L with weight 0 at q = 1 and N_B = 1 and are not \
             computed"
                .to_string(),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An order-1 scene with several spheres per camera ray gets the
    /// small-sphere prediction by default, and the reason names the flag
    /// that computes the finite-sphere pairs.
    #[test]
    fn the_reason_for_the_small_sphere_prediction_names_the_flag() {
        let scene = Scene::builder()
            .medium(1.0, 0.8)
            .point_light([1.0, 0.0, 1.0], 1.0)
            .camera([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
            .estimator(0.2, 0.5, 20, 8)
            .build()
            .unwrap();
        let mut scene = scene;
        scene.effects.scattering_orders = mcrt_scene::ScatteringOrders::Limited(1);
        let mean = Estimate::known(1.0f64, 1e-9, 1, crate::quad::Rule::TanhSinh);
        let why = finite_not_used(&scene, &Ok(Some(OrderOne::Mean(mean, None)))).unwrap();
        assert!(why.contains("--finite-pairs") && why.contains("C₂₃, Q and C₂₄"), "{why}");
        // Where the mean itself failed, the failure is the reason: the flag
        // would not help (it computes the pairs after the mean).
        let failed = OracleError::Quadrature {
            what: "finite-sphere mean luminance",
            reason: "budget spent".into(),
            guess: None,
            evaluations: 7,
        };
        let why = finite_not_used::<f64>(&scene, &Err(failed)).unwrap();
        assert!(why.contains("its computation failed") && why.contains("budget spent"), "{why}");
        assert!(!why.contains("--finite-pairs"), "{why}");
    }

    /// The reason a finite-sphere report lacks a correlation names it and
    /// the parameter that weighs it 0.
    #[test]
    fn a_correlation_weighed_zero_is_named() {
        let e = |v: f64| Some(Estimate::known(v, 1e-12, 1, crate::quad::Rule::TanhSinh));
        let known = |v: f64| e(v).unwrap();
        let with = |q, c23, c24| FiniteIntegrals { mean: known(1.0), m2: known(2.0), p: known(3.0), q, c23, c24 };
        let counts = |q: f64, n_b: f64| Counts { q, n_f: 20.0, n_b };
        assert_eq!(not_weighed(&with(e(4.0), e(5.0), e(6.0)), &counts(0.5, 8.0)), None);
        let c24 = not_weighed(&with(e(4.0), e(5.0), None), &counts(0.5, 1.0)).unwrap();
        assert!(c24.contains("C₂₄") && c24.contains("N_B = 1") && !c24.contains("C₂₃"), "{c24}");
        let c23 = not_weighed(&with(e(4.0), None, e(6.0)), &counts(1.0, 8.0)).unwrap();
        assert!(c23.contains("C₂₃") && c23.contains("q = 1") && !c23.contains("C₂₄"), "{c23}");
        let all = not_weighed(&with(None, None, None), &counts(1.0, 1.0)).unwrap();
        assert_eq!(all, PAIRS_NOT_NEEDED);
    }
}
