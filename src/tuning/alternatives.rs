//! The alternatives beside the optimum: q = 1 (the standard method),
//! several spheres per camera ray (q ≤ 1/2), the cylinder limit q → 0, the
//! scene's own parameters, the R of the asymptotic rule (bias ∝ R², noise ∝
//! 1/R²) and N_B = 1, each with the other parameters optimised (or, for
//! the rule, the optimum's). Beside the standard method's optimum of
//! single-scattered light ([`super::Searched::StandardMethod`]) other
//! comparisons: `beside_the_standard_method`.

use super::cost::Parameters;
use super::radii::RadiusCache;
use super::search::{Constraints, Scored};
use super::{best_over_radii, Alternative, Options, TuningError};
use crate::quad::Budget;
use mcrt_scene::Scene;

/// The comparisons: q = 1, the cylinder limit, the scene's own parameters,
/// the asymptotic rule's R, N_B = 1.
pub(crate) fn alternatives(
    scene: &Scene,
    opts: &Options,
    cache: &mut RadiusCache,
    best: &Scored,
    range: (f64, f64),
    bias_predicted: bool,
) -> Result<Vec<Alternative>, TuningError> {
    let free = Constraints::free(opts.budget, opts.max_spheres);
    let fixed_r = |cache: &mut RadiusCache, c: &Constraints| -> Result<Option<Scored>, TuningError> {
        if bias_predicted {
            best_over_radii(scene, opts, cache, c, range).map(Some).or_else(|e| match e {
                TuningError::Infeasible(_) => Ok(None),
                e => Err(e),
            })
        } else {
            Ok(cache.at(scene.estimator.radius)?.best(scene, &opts.costs, c))
        }
    };
    let none = |what: &str| format!("no {what} parameters fit the budget");
    let mut out = Vec::new();
    let q1 = fixed_r(cache, &Constraints { q: Some(1.0), ..free })?;
    out.push(Alternative {
        name: "q = 1 (one sphere per camera ray, the standard method)".into(),
        scored: q1.ok_or_else(|| none("q = 1")),
        note: "R, N_F, N_B optimised with q held at 1".into(),
    });
    let several = fixed_r(cache, &Constraints { q_max: Some(0.5), ..free })?;
    out.push(Alternative {
        name: "several spheres per camera ray (q ≤ 1/2)".into(),
        scored: several.ok_or_else(|| none("q ≤ 1/2")),
        note: "R, q, N_F, N_B optimised with q at most 1/2 (at least two spheres per camera ray on average)".into(),
    });
    let cyl = fixed_r(cache, &Constraints { cylinder: true, ..free })?;
    out.push(Alternative {
        name: "q → 0 (the cylinder limit)".into(),
        scored: cyl.ok_or_else(|| none("cylinder")),
        note: "Var L at q = 0 in closed form ((7)–(9) with q = 0); cost of one integration volume per camera \
               ray and one contribution per crossing segment (the sphere method itself would need 1/q → ∞ \
               spheres); R, N_F, N_B optimised"
            .into(),
    });
    let own = Parameters::of(scene);
    let at_own = cache.at(own.radius)?;
    out.push(Alternative {
        name: "the scene's own parameters".into(),
        scored: at_own
            .scored_at(scene, &opts.costs, &free, &own)
            .ok_or_else(|| "the scene's own parameters do not fit the budget".to_string()),
        note: format!("q = {}, R = {}, N_F = {}, N_B = {}", own.q, own.radius, own.forward_rays, own.camera_rays),
    });
    if bias_predicted {
        out.push(asymptotic_rule(scene, opts, cache, best, range)?);
    }
    let nb1 = fixed_r(cache, &Constraints { camera_rays: Some(1), ..free })?;
    out.push(Alternative {
        name: "N_B = 1 (one camera ray per iteration)".into(),
        scored: nb1.ok_or_else(|| none("N_B = 1")),
        note: "R, q, N_F optimised with N_B held at 1".into(),
    });
    Ok(out)
}

/// The note of an alternative that the small-sphere model scores beside
/// the standard method (the reports tell its predictions from the exact
/// model's by it).
pub(crate) const SMALL_SPHERE_NOTE: &str = "Var L from the small-sphere model, exact only as R → 0: its own error at \
                                            this R is not in the bar (docs/model-error.md); the bias b(R) from the \
                                            finite-sphere mean; R held at the scene's";

/// The comparisons beside the standard method's optimum of single-scattered
/// light (q = 1, N_B = 1, R and N_F searched by the finite-sphere model):
/// the scene's own parameters, the asymptotic rule's R, and q, N_F, N_B
/// chosen at the scene's R by the small-sphere model (its Var L exact only
/// as R → 0; the bias b(R) from the finite-sphere mean), which may predict
/// less noise with q < 1 or N_B > 1 than the standard method has, at the
/// price of a model error its bar does not hold. q < 1 and N_B > 1 are
/// not scored by the finite-sphere model: one entry says why.
pub(crate) fn beside_the_standard_method(
    scene: &Scene,
    opts: &Options,
    cache: &mut RadiusCache,
    best: &Scored,
    range: (f64, f64),
) -> Result<Vec<Alternative>, TuningError> {
    let free = Constraints::free(opts.budget, opts.max_spheres);
    let own = Parameters::of(scene);
    // The small-sphere model at the scene's R, with the scene's q and N_B
    // (its pair integrals), under a budget of its own (it alone can cost
    // as much as the whole search over R; for a beam's scattered light its
    // pairs lack the cross-segment terms, docs/model.md §3a); a refusal or a
    // failure is that alternative's answer, not the optimum's.
    let budget = Budget::new(opts.evaluations);
    let small = RadiusCache::small_sphere(scene, budget).at(own.radius).map_err(|e| e.to_string());
    let small_note = SMALL_SPHERE_NOTE;
    let mut out = Vec::new();
    let standard = own.q == 1.0 && own.camera_rays == 1;
    // Every order: the small-sphere model has no Var L of it, and the
    // finite-sphere model none at q < 1 or N_B > 1.
    let small = match (super::every_order(scene), small) {
        (true, _) if !standard => Err(format!(
            "not scored: Var L of every scattering order is modelled at q = 1 and N_B = 1 only (docs/model.md \
             §10.4), and the small-sphere model has none (the paper's is of orders 0 and 1); the tracer measures \
             it (q = {}, N_B = {} here)",
            own.q, own.camera_rays
        )),
        (_, small) => small,
    };
    let (scored, note) = if standard {
        let at = cache.at(own.radius)?;
        (at.scored_at(scene, &opts.costs, &Constraints { q: Some(1.0), camera_rays: Some(1), ..free }, &own), "")
    } else {
        (small.as_ref().ok().and_then(|at| at.scored_at(scene, &opts.costs, &free, &own)), small_note)
    };
    out.push(Alternative {
        name: "the scene's own parameters".into(),
        scored: match (&small, standard) {
            (Err(why), false) => Err(why.clone()),
            _ => scored.ok_or_else(|| "the scene's own parameters do not fit the budget".to_string()),
        },
        note: format!(
            "q = {}, R = {}, N_F = {}, N_B = {}{}{note}",
            own.q,
            own.radius,
            own.forward_rays,
            own.camera_rays,
            if note.is_empty() { "" } else { "; " }
        ),
    });
    out.push(asymptotic_rule(scene, opts, cache, best, range)?);
    out.push(Alternative {
        name: "q, N_F, N_B free at the scene's R (small-sphere model)".into(),
        scored: small.and_then(|at| {
            at.best(scene, &opts.costs, &free).ok_or_else(|| "no parameters fit the budget at the scene's R".into())
        }),
        note: small_note.into(),
    });
    let why = if super::every_order(scene) {
        "not scored: the correlations of two spheres of every scattering order (C₂₃, Q, C₂₄), which several \
         spheres per camera ray, the cylinder limit and N_B > 1 need, are not modelled yet (docs/model.md §10.4)"
    } else {
        "not scored: the finite-sphere correlations of two spheres of single-scattered light (C₂₃, Q, C₂₄), which \
         several spheres per camera ray, the cylinder limit and N_B > 1 need, take minutes at 10⁻³ (docs/model.md \
         §9.7; `oracle --finite-pairs`), too long to score alternatives with"
    };
    out.push(Alternative {
        name: "q < 1 or N_B > 1 by the finite-sphere model".into(),
        scored: Err(why.into()),
        note: String::new(),
    });
    Ok(out)
}

/// The R an asymptotic rule picks (bias ≈ b₂R², noise ≈ V₂/R²): with b₂ =
/// b(R_lo)/R_lo² at the smallest radius evaluated whose bias is resolved
/// and V₂ = q M₂R²/(N_F N_B)
/// (the small-sphere M₂ ∝ 1/R²) at the optimum's q, N_F, N_B, τ and T,
/// RMSE² ≈ b₂²R⁴ + V₂τ/(R²T) is least at R⁶ = V₂τ/(2b₂²T). Scored by the
/// exact model with the optimum's other parameters.
fn asymptotic_rule(
    scene: &Scene,
    opts: &Options,
    cache: &mut RadiusCache,
    best: &Scored,
    range: (f64, f64),
) -> Result<Alternative, TuningError> {
    let name = "R of the asymptotic rule (bias ∝ R², noise ∝ 1/R²)".to_string();
    // b₂ at the smallest radius evaluated (the range's low end first) whose
    // bias is resolved (three times its bar): at 10⁻³ the bias of
    // single-scattered light is ~10⁻⁷ of μ, below the bars of the oracle's
    // 10⁻⁴ there.
    cache.at(range.0)?;
    let resolved = |b: &crate::oracle::ValueWithBar| b.value.abs() > 3.0 * b.error;
    let Some((r_lo, bias)) =
        cache.all().into_iter().find_map(|x| x.model.bias.filter(resolved).map(|b| (x.model.radius, b)))
    else {
        let why = "no radius evaluated has its bias b(R) resolved (|b| > 3 bars), so no b₂".to_string();
        return Ok(Alternative { name, scored: Err(why), note: String::new() });
    };
    let b2 = bias.value / (r_lo * r_lo);
    let p = best.parameters;
    // The small-sphere M₂ ∝ 1/R²: M₂R² is the same at every radius.
    let m2_r2 = cache.at(r_lo)?.model.small_sphere_m2.value * r_lo * r_lo;
    let v2 = p.q * m2_r2 / (p.forward_rays as f64 * p.camera_rays as f64);
    let r6 = v2 * best.rmse.seconds_per_iteration / (2.0 * b2 * b2 * opts.budget);
    let r = r6.powf(1.0 / 6.0);
    if !(r.is_finite() && r > 0.0) {
        return Ok(Alternative { name, scored: Err(format!("b₂ = {b2:e}: no finite R")), note: String::new() });
    }
    // A failure at the rule's R (beyond the scene's bounds of σR, or its
    // oracle run not converging) is this alternative's answer, not the
    // optimum's: the optimisation goes on.
    let at = match cache.at(r) {
        Ok(at) => at,
        Err(TuningError::Radius(_, why)) => {
            return Ok(Alternative { name, scored: Err(format!("R = {r:.4e}: {why}")), note: String::new() })
        }
        Err(e) => return Ok(Alternative { name, scored: Err(format!("R = {r:.4e}: {e}")), note: String::new() }),
    };
    let params = Parameters { radius: r, ..p };
    Ok(Alternative {
        name,
        scored: at
            .scored_at(scene, &opts.costs, &Constraints::free(opts.budget, opts.max_spheres), &params)
            .ok_or_else(|| format!("R = {r:e} does not fit the budget")),
        note: format!(
            "R = (V₂τ/(2b₂²T))^(1/6) = {r:.4e} with b₂ = {b2:.4e} (b(R)/R² at R = {:.1e}) and V₂ = {v2:.4e}; \
             q, N_F, N_B the optimum's",
            r_lo
        ),
    })
}
