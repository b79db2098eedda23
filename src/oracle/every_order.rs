//! The exact mean of a scene with every scattering order (orders ≥ 2, or
//! `"all"`), at its R and as R → 0 (`docs/model.md` §10), and at q = 1
//! and N_B = 1 its exact Var L with the same-path pairs in M₂ (§10.3).
//! Other q and N_B need the correlations of two spheres of every order,
//! which the model does not have yet (§10.4).

use super::report::{reported, ValueWithBar};
use crate::model::field::Field;
use crate::model::finite::{FiniteField, Functional};
use crate::model::OracleError;
use crate::quad::Budget;
use crate::quad::{Estimate, Options};
use mcrt_scene::{ScatteringOrders, Scene};
use serde::Serialize;

/// The mean luminance of every simulated order, exact at the scene's R, the
/// small-sphere mean it tends to as R → 0, and the bias between them.
#[derive(Debug, Clone, Serialize)]
pub struct EveryOrderMean {
    /// The scene's `scattering_orders`, as written in its file.
    pub orders: String,
    /// The relative tolerance asked of the mean's integrals.
    pub rel_tol: f64,
    /// The relative tolerance Var L's integrals (P, the same-path pairs)
    /// ran at, where they ran: `rel_tol` or [`EVERY_ORDER_VARIANCE_TOL`],
    /// whichever is looser.
    pub variance_rel_tol: Option<f64>,
    /// μ(R) = μ₀(R) + μ₁(R) + μ_{2..n}(R), with its quadrature bar.
    pub mean: ValueWithBar,
    /// μ(0), the small-sphere mean of every simulated order: the luminance
    /// a renderer converges to as R → 0.
    pub small_sphere_mean: ValueWithBar,
    /// b(R) = μ(R) − μ(0).
    pub bias: ValueWithBar,
    /// The share of μ(R) of segments 2..=n (or all of them).
    pub beyond_first: ValueWithBar,
    /// Var L of one iteration, exact at R, where the model has it
    /// (q = 1, N_B = 1: M₂/N_F + (1 − 1/N_F)P − μ²).
    pub variance: Option<ValueWithBar>,
    /// M₂ behind it (16): Σ_j⟨𝒞_j²⟩ + 2Σ_{j<k}⟨𝒞_j𝒞_k⟩ over one path's
    /// segments at one sphere.
    pub m2: Option<ValueWithBar>,
    /// The same-path pairs 2Σ_{j<k}⟨𝒞_j𝒞_k⟩ in M₂: one forward path hitting
    /// one sphere with two of its segments (not a functional of the
    /// forward field: the part the paper's §3 structure leaves out).
    pub same_path_pairs: Option<ValueWithBar>,
    /// P = ∫σe^{−σs}⟨𝒞⟩² ds.
    pub p: Option<ValueWithBar>,
    /// Integrand evaluations spent.
    pub evaluations: u64,
    /// Why the report has no Var L (and `predict` no prediction), if it has none.
    pub variance_missing: Option<String>,
}

/// Why an every-order report carries the mean only.
pub const VARIANCE_NOT_MODELLED: &str =
    "not modelled for this scene yet: the oracle has it for scattering_orders 2 to 9 or \"all\" at q = 1 and \
     camera_rays = 1 only (allowed); other q and camera_rays need the correlations of two spheres of every order \
     (docs/model.md §10.4). `predict` and `check` refuse the scene (`optimize` searches it at q = 1 and \
     camera_rays = 1); its exact mean and bias: \
     `oracle::every_order_mean` (`mcrt-noise oracle`); its Var L: the tracer (`mcrt-noise trace`)";

/// The default relative tolerance of [`every_order_mean`] (allowed from
/// 10⁻⁸: the tail tables need goals of 1/40000 of it, at least 10⁻¹³ in f64).
pub const EVERY_ORDER_TOL: f64 = 1e-6;

/// The relative tolerances [`every_order_mean`] accepts: from 10⁻⁸ (its
/// tail tables need goals of 1/40000 of it, at least 10⁻¹³ in f64) to 10⁻².
pub const EVERY_ORDER_TOL_RANGE: (f64, f64) = (1e-8, 1e-2);

/// The goal Var L's integrals of every order (P and the same-path pairs)
/// run at when a finer one is asked: 10⁻⁴, where their chained tables meet
/// their goals at every albedo measured (at 10⁻⁶ the cross-section table
/// of K_G could not be built at albedo 0.95, R = 0.3: the bracket of G
/// about d = R is then wider than its samples' goal; at 10⁻³ Var L costs
/// no less) and P and the pairs take ~7 s of one core, beside the mean's
/// integrals (~9 s in all on two cores). The bars reported
/// are those computed, ~10⁻⁶ relative on the README scene.
pub const EVERY_ORDER_VARIANCE_TOL: f64 = 1e-4;

/// Refuses, before any integral, what the model of every order does not
/// cover: a Henyey–Greenstein medium, a point light on the camera line
/// ahead of the camera (the small-sphere mean diverges there like
/// ∫ds/(s − z)²). Beams are covered (their mean, and at q = 1 and N_B = 1
/// their Var L, [`every_order_variance_modelled`]).
pub(crate) fn every_order_scene_covered(scene: &Scene) -> Result<(), OracleError> {
    if scene.medium.phase != mcrt_scene::Phase::Isotropic {
        return Err(crate::model::finite::every_order_phase_refusal(scene.medium.phase));
    }
    let (o, u) = (scene.camera.origin, scene.camera.direction);
    for (i, light) in scene.lights.iter().enumerate() {
        match light {
            mcrt_scene::Light::Beam { .. } => {}
            mcrt_scene::Light::Point { position, .. } => {
                let rel = *position - o;
                let (z, b) = (rel.dot(u), rel.cross(u).length());
                if z >= 0.0 && b <= 1e-12 * z.max(f64::MIN_POSITIVE) {
                    return Err(OracleError::Unsupported(format!(
                        "lights[{i}].position is on the camera ray at or ahead of the camera (distance {b:e} from it; \
                         allowed: more than 1e-12 × its distance along the ray): the small-sphere mean of every order \
                         does not exist there (it diverges like ∫ds/(s − z)²), so neither does the bias"
                    )));
                }
            }
        }
    }
    Ok(())
}

/// Whether `scene` simulates scattering orders beyond the first (2 to 9 or
/// `"all"`), whose model is `docs/model.md` §10.
pub(crate) fn orders_beyond_the_first(scene: &Scene) -> bool {
    !matches!(scene.effects.scattering_orders, ScatteringOrders::Limited(0 | 1))
}

/// Whether the model of every order has Var L for `scene` (orders ≥ 2 or
/// `"all"`): at q = 1 and one camera ray, point lights and beams
/// (`docs/model.md` §10.3, §10.6); other q and N_B need the correlations
/// of two spheres of every order (§10.4).
pub(crate) fn every_order_variance_modelled(scene: &Scene) -> bool {
    let est = &scene.estimator;
    est.q == 1.0 && est.camera_rays == 1
}

/// Why an every-order report of `scene` carries the mean only, if it does.
fn variance_missing_reason(scene: &Scene) -> Option<String> {
    (!every_order_variance_modelled(scene)).then(|| VARIANCE_NOT_MODELLED.to_string())
}

/// Refuses, before any integral, a scene of orders ≥ 2 or `"all"` whose
/// Var L the model of every order does not give: what it does not cover
/// ([`every_order_scene_covered`]: its medium, its lights), then q < 1 or
/// more than one camera ray (`predict`, `check` and `optimize` need Var L).
pub(crate) fn every_order_variance_refusal(scene: &Scene) -> Result<(), OracleError> {
    every_order_scene_covered(scene)?;
    if every_order_variance_modelled(scene) {
        return Ok(());
    }
    Err(OracleError::Unsupported(format!(
        "effects.scattering_orders = {}, estimator.q = {}, estimator.camera_rays = {}: Var L {}",
        scene.effects.scattering_orders.as_toml(),
        scene.estimator.q,
        scene.estimator.camera_rays,
        variance_missing_reason(scene).unwrap_or_default()
    )))
}

/// The mean of `scene` (scattering orders ≥ 2 or `"all"`, an isotropic
/// medium, point lights off the camera line and beams) in f64 to the relative
/// tolerance `rel_tol` (default [`EVERY_ORDER_TOL`]; from 10⁻⁸ to 10⁻²)
/// within `budget` (shared by its integrals: spent, the computation
/// fails with that reason); at q = 1 and one camera ray also Var L, M₂
/// (with its same-path pairs) and P, exact at R (`docs/model.md` §10.3,
/// a beam's §10.6; at a goal no tighter than [`EVERY_ORDER_VARIANCE_TOL`],
/// beside the mean's integrals on a budget of their own charged after;
/// ~9 s in all on two cores for point lights, ~1 minute with a beam,
/// whose order 5 spends ~1.1·10⁹ evaluations: give such scenes
/// [`crate::prec::EVERY_ORDER_PREDICTION_EVALUATIONS`]), else
/// [`EveryOrderMean::variance_missing`] says why not.
///
/// ```no_run
/// use mcrt_noise::{oracle::every_order_mean, Scene};
///
/// let scene = Scene::from_toml_str(&std::fs::read_to_string("scenes/point-isotropic-all.toml")?)?;
/// let m = every_order_mean(&scene, None, &mcrt_noise::quad::Budget::new(2_000_000_000))?;
/// assert!(m.bias.value.abs() < 1e-2 * m.mean.value);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn every_order_mean(scene: &Scene, rel_tol: Option<f64>, budget: &Budget) -> Result<EveryOrderMean, OracleError> {
    every_order_report(scene, rel_tol, budget).map(|(m, _)| m)
}

/// [`every_order_mean`] with the error that ended Var L's integrals, its
/// kind kept (a spent budget is [`OracleError::Quadrature`]), where they
/// ran and failed: `predict` passes it on.
pub(crate) fn every_order_report(
    scene: &Scene,
    rel_tol: Option<f64>,
    budget: &Budget,
) -> Result<(EveryOrderMean, Option<OracleError>), OracleError> {
    let rel_tol = rel_tol.unwrap_or(EVERY_ORDER_TOL);
    let (lo, hi) = EVERY_ORDER_TOL_RANGE;
    if !(lo..=hi).contains(&rel_tol) {
        return Err(OracleError::Unsupported(format!(
            "--rel-tol = {rel_tol:e} (`rel_tol` in the library): with scattering_orders >= 2 allowed from {lo:e} to \
             {hi:e} (the tables of every order need goals no finer in f64)"
        )));
    }
    every_order_scene_covered(scene)?;
    if !orders_beyond_the_first(scene) {
        return Err(OracleError::Unsupported(
            "every_order_mean is for effects.scattering_orders ≥ 2 or \"all\"; orders 0 and 1 have the full oracle"
                .into(),
        ));
    }
    let highest = crate::model::finite::start_density::MAX_FINITE_ORDER - 1;
    if let ScatteringOrders::Limited(n) = scene.effects.scattering_orders {
        if n > highest {
            return Err(OracleError::Unsupported(format!(
                "effects.scattering_orders = {n}: allowed 0 ≤ n ≤ {highest} or \"all\" (beyond, the cut integral of \
                 a finite order loses more than four digits to cancellation, docs/model.md §10.1; \"all\" has no \
                 such limit)"
            )));
        }
    }
    // The small-sphere field of the first two segments carries what the
    // finite-sphere geometry reads (σ, albedo, flux, the along-ray origin).
    let mut first_two = scene.clone();
    first_two.effects.scattering_orders = ScatteringOrders::Limited(1);
    let field = Field::from_scene(&first_two, &0.0f64)?;
    let ff = FiniteField::of_first_segments(scene, &field);
    ff.every_order_covered()?;
    let opts = Options::rel(rel_tol).with_budget(budget.clone()).declared();
    let with_variance = every_order_variance_modelled(scene);
    // Var L's integrals run beside the means (which stand if they fail), on
    // a budget of their own with the same limit and deadline, charged to
    // `budget` after both: where, run after the means, they would have
    // spent its evaluations, they are reported as having spent them, so
    // the outcome does not depend on the threads' timing. (A deadline,
    // `--time-limit`, is wall time and shared: there the two compete for
    // the cores, and the means can miss a deadline they would have met
    // alone.)
    let own = budget.renewed();
    let (means, second) = rayon::join(
        || -> Result<_, OracleError> {
            let uncollided = ff.ray_total(Functional::Mean, &opts)?;
            let small = ff.small_sphere_mean_of_segments(scene.effects.scattering_orders, &opts)?;
            let small = small.plus(beams_small_sphere_low_orders(scene, &ff.shift, &opts)?);
            let (single, beyond) = ff.every_order_means(&opts)?;
            Ok((uncollided, small, single, beyond))
        },
        || {
            with_variance.then(|| {
                // P and the pairs at a goal no tighter than
                // EVERY_ORDER_VARIANCE_TOL, their tables reaching the pairs'
                // distances (a field of their own: the mean's tables need not).
                let mut wide = FiniteField::of_first_segments(scene, &field);
                wide.cover_pair_distances();
                let goal = rel_tol.max(EVERY_ORDER_VARIANCE_TOL);
                wide.every_order_second_moments(&Options::rel(goal).with_budget(own.clone()).declared())
            })
        },
    );
    // Charged before the means' failure, if any, is returned.
    let before = budget.used();
    budget.charge(own.used());
    let (uncollided, small, single, beyond) = means.map_err(|e| e.unshifted(ff.shift))?;
    let second = second.map(|r| spent_after_the_means(r, budget, &own, before));
    let k = (-ff.shift).exp();
    let mut evaluations = uncollided.evaluations + single.evaluations + beyond.evaluations + small.evaluations;
    let exact = uncollided.plus(single).plus(beyond.clone());
    let (mut variance, mut m2_out, mut p_out, mut pairs_out) = (None, None, None, None);
    let mut variance_missing = variance_missing_reason(scene);
    let mut variance_error = None;
    if let Some(Err(e)) = &second {
        let e = e.clone().unshifted(ff.shift);
        variance_missing = Some(format!("not computed: {e} (the mean above stands)"));
        variance_error = Some(e);
    }
    if let Some(Ok((p, pairs))) = second {
        evaluations += pairs.evaluations + p.evaluations;
        // Σ_j⟨𝒞_j²⟩ = c f⟨𝒞⟩ in an isotropic medium: every hit adds c f.
        let cf = ff.per_hit_power(1, &ff.total_flux) / (4.0 * std::f64::consts::PI);
        pairs_out = Some(reported(&(pairs.value * k), &(pairs.error * k)));
        let m2 = Estimate::known(cf * exact.value, cf * exact.error, 0, opts.rule).plus(pairs);
        let n_f = scene.estimator.forward_rays as f64;
        let (mu, mu_e) = (exact.value * k, exact.error * k);
        let (m2v, m2e) = (m2.value * k, m2.error * k);
        let (pv, pe) = (p.value * k, p.error * k);
        let v = m2v / n_f + (1.0 - 1.0 / n_f) * pv - mu * mu;
        let e = m2e / n_f + (1.0 - 1.0 / n_f) * pe + 2.0 * mu.abs() * mu_e + mu_e * mu_e;
        variance = Some(reported(&v, &e));
        m2_out = Some(reported(&m2v, &m2e));
        p_out = Some(reported(&pv, &pe));
    }
    let bias = Estimate::known(exact.value - small.value, exact.error + small.error, 0, opts.rule);
    let report = EveryOrderMean {
        orders: scene.effects.scattering_orders.to_string(),
        rel_tol,
        variance_rel_tol: with_variance.then(|| rel_tol.max(EVERY_ORDER_VARIANCE_TOL)),
        variance_missing,
        variance,
        m2: m2_out,
        same_path_pairs: pairs_out,
        p: p_out,
        mean: reported(&(exact.value * k), &(exact.error * k)),
        small_sphere_mean: reported(&(small.value * k), &(small.error * k)),
        bias: reported(&(bias.value * k), &(bias.error * k)),
        beyond_first: reported(&(beyond.value * k), &(beyond.error * k)),
        evaluations,
    };
    Ok((report, variance_error))
}

/// The small-sphere mean of the beams' orders 0 and 1 (the small-sphere
/// model's, `model::field`, of the scene's beams alone), times e^{c₀} of
/// the every-order field (`shift`): what the finite field's small-sphere
/// mean of segments (`small_sphere_mean_of_segments`, a beam's segments
/// ≥ 2) leaves out of a beam's μ(0). Zero without beams.
fn beams_small_sphere_low_orders(scene: &Scene, shift: &f64, opts: &Options) -> Result<Estimate<f64>, OracleError> {
    let mut beams = scene.clone();
    beams.lights.retain(|l| matches!(l, mcrt_scene::Light::Beam { .. }));
    if beams.lights.is_empty() {
        return Ok(Estimate::known(0.0, 0.0, 0, opts.rule));
    }
    beams.effects.scattering_orders = ScatteringOrders::Limited(1);
    let field = Field::from_scene(&beams, &0.0f64)?;
    let m = crate::model::moments::mean_luminance(&field, opts)?;
    Ok(m.scaled(&(shift - field.shift).exp()))
}

/// Var L's integrals, run beside the means on their own budget `own` and
/// already charged to the computation's `budget` (which had `before` used
/// without them): past its limit, or with their own budget spent, they
/// have spent the computation's (as they would have, run after the means),
/// whatever they returned, and the reason counts both.
fn spent_after_the_means<T>(
    result: Result<T, OracleError>,
    budget: &Budget,
    own: &Budget,
    before: u64,
) -> Result<T, OracleError> {
    // Their own evaluations spent (not a deadline, which is reported as it is).
    let own_spent = own.used() >= own.limit();
    if budget.used() <= budget.limit() && !own_spent {
        return result;
    }
    match result {
        Err(e) if !own_spent => Err(e),
        _ => Err(OracleError::Quadrature {
            what: "Var L's integrals of every order (P, the same-path pairs)",
            reason: format!(
                "the computation's evaluation budget of {} is spent ({} evaluations: the means (and what ran before \
                 them) {before}, Var L's integrals, run beside them, {}{})",
                budget.limit(),
                budget.used(),
                own.used(),
                if own_spent { ", stopped there" } else { "" }
            ),
            guess: None,
            evaluations: own.used(),
        }),
    }
}

impl std::fmt::Display for EveryOrderMean {
    /// The report as the `oracle` command prints it.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let row = |f: &mut std::fmt::Formatter<'_>, what: &str, v: &ValueWithBar| {
            writeln!(f, "  {what:<44} {:.10e} ± {:.1e}", v.value, v.error)
        };
        let what = match (self.variance_missing.is_some(), self.variance_rel_tol) {
            (false, Some(v)) if v != self.rel_tol => format!(" (Var L's integrals at {v:e})"),
            (true, _) => ": the mean only".to_string(),
            _ => String::new(),
        };
        writeln!(f, "mcrt-noise oracle: scattering_orders = {}, f64, rel-tol {:e}{what}", self.orders, self.rel_tol)?;
        row(f, "mean luminance μ(R), exact (finite-sphere)", &self.mean)?;
        row(f, "  of which segments 2 and beyond", &self.beyond_first)?;
        row(f, "small-sphere mean μ(0) (the R → 0 limit)", &self.small_sphere_mean)?;
        row(f, "bias μ(R) − μ(0)", &self.bias)?;
        writeln!(
            f,
            "  relative bias {:+.4} % ± {:.1e} %",
            100.0 * self.bias.value / self.small_sphere_mean.value,
            100.0
                * (self.bias.error / self.small_sphere_mean.value.abs()
                    + (self.bias.value * self.small_sphere_mean.error / self.small_sphere_mean.value.powi(2)).abs())
        )?;
        if let (Some(v), Some(m2), Some(pairs), Some(p)) = (&self.variance, &self.m2, &self.same_path_pairs, &self.p) {
            row(f, "Var L (one iteration), exact (finite-sphere)", v)?;
            row(f, "  M₂ (16)", m2)?;
            row(f, "    of which same-path pairs 2Σ⟨𝒞_j𝒞_k⟩", pairs)?;
            row(f, "  P (17)", p)?;
        }
        writeln!(f, "  evaluations: {}", self.evaluations)?;
        match &self.variance_missing {
            Some(why) => writeln!(f, "Var L: {why}."),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Var L's integrals charged after the means: within the limit their
    /// result stands; past it, or with their own budget spent, they have
    /// spent the computation's, whatever they returned, and the reason
    /// counts both; their other failures stand as they are.
    #[test]
    fn var_l_beside_the_means_spends_the_budget_as_if_run_after_them() {
        let run = |means: u64, var: u64, result: Result<u8, OracleError>| {
            let budget = Budget::new(1000);
            budget.charge(means);
            let own = budget.renewed();
            own.charge(var);
            let _ = own.exhausted();
            let before = budget.used();
            budget.charge(own.used());
            spent_after_the_means(result, &budget, &own, before)
        };
        assert_eq!(run(400, 600, Ok(7)).unwrap(), 7);
        let over = run(400, 601, Ok(7)).unwrap_err().to_string();
        assert!(over.contains("budget of 1000 is spent (1001 evaluations: the means"), "{over}");
        assert!(over.contains("400, Var L's integrals, run beside them, 601)"), "{over}");
        let stopped = run(10, 1000, Err(OracleError::Unsupported("spent".into()))).unwrap_err().to_string();
        assert!(stopped.contains("1000, stopped there") && stopped.contains("(1010 evaluations"), "{stopped}");
        let other = run(600, 600, Err(OracleError::Unsupported("a table failed".into()))).unwrap_err();
        assert_eq!(other, OracleError::Unsupported("a table failed".into()));
    }
}
