//! The objective of parameter choice: the relative RMSE of the pixel after
//! a wall-time budget T, bias included,
//!
//! ```text
//! RMSE/μ(0) = √(b(R)² + Var L(q, R, N_F, N_B)/M) / μ(0),   M = T/τ(q, R, N_F, N_B),
//! ```
//!
//! with M iterations (each with fresh forward and camera rays, paper §4:
//! the variance of the average of M iterations is Var L/M), b(R) = μ(R) −
//! μ(0) the bias of the finite spheres and τ the time of one iteration
//! (`cost`). For a fixed R the integrals do not depend on q, N_F, N_B, and
//! Var L is explicit in them ((7)–(9) with (14)–(17)):
//!
//! ```text
//! Var L = [q M₂ + 2(1−q) C₂₃]/(N_F N_B) + (1/N_B − 1/(N_F N_B)) [q P + 2(1−q) Q]
//!       + (1/N_F − 1/(N_F N_B)) C₂₄ + (1/(N_F N_B) − 1/N_B − 1/N_F) μ²
//! ```
//!
//! (the same combination as `model::noise::variance`, here in f64 on the
//! report's unshifted integrals, so that a search costs nothing per point).

use crate::oracle::{Report, ValueWithBar};
use serde::Serialize;

/// What the noise model gives at one radius, in absolute f64 values.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct ModelAtRadius {
    /// The radius R.
    pub radius: f64,
    /// `"finite-sphere"` (exact at R, bias predicted) or `"small-sphere"`
    /// (R → 0 model; the bias predicted only where the oracle has the
    /// finite-sphere mean: single scattering in an isotropic medium, or
    /// from point lights in a Henyey–Greenstein one).
    pub model: &'static str,
    /// μ(R) = ⟨⟨L⟩⟩ at R.
    pub mean: ValueWithBar,
    /// μ(0), the luminance the estimator converges to as R → 0.
    pub mean_at_zero: ValueWithBar,
    /// b(R) = μ(R) − μ(0); `None` where the model does not predict it.
    pub bias: Option<ValueWithBar>,
    /// M₂ of (16).
    pub m2: ValueWithBar,
    /// (23) (C₂₃); `None` where the model does not give it (the
    /// finite-sphere model of single-scattered light, at q = 1, N_B = 1).
    pub c23: Option<ValueWithBar>,
    /// P of (17).
    pub p: ValueWithBar,
    /// Q of (17); `None` as for `c23`.
    pub q_pair: Option<ValueWithBar>,
    /// (24) (C₂₄); `None` as for `c23`.
    pub c24: Option<ValueWithBar>,
    /// The small-sphere model's M₂ at R (∝ 1/R², for the asymptotic rule).
    pub small_sphere_m2: ValueWithBar,
}

impl ModelAtRadius {
    /// The prediction's integrals from an oracle report: the finite-sphere
    /// model's where the report has it (exact at R, bias predicted; without
    /// the pair integrals Q, C₂₃, C₂₄ for single-scattered light, which it
    /// gives at q = 1, N_B = 1 only, where (7)–(9) weigh them 0), else the
    /// small-sphere model's, with the bias b(R) where the report has the
    /// finite-sphere mean (`finite_mean`: single scattering in an isotropic
    /// medium, or from point lights in a Henyey–Greenstein one). A
    /// small-sphere report without its pair integrals (run with
    /// `Scope::Prediction` at q = 1, N_B = 1, or `Scope::ExactPrediction`
    /// with a beam's single-scattered light) cannot predict other settings: that is an
    /// error giving the report's reason (`pairs_not_computed`).
    pub fn from_report(r: &Report) -> Result<ModelAtRadius, crate::model::OracleError> {
        let vb = |i: crate::oracle::Integral| ValueWithBar::from(i);
        if let Some(f) = &r.finite {
            return Ok(ModelAtRadius {
                radius: r.radius,
                model: "finite-sphere",
                mean: f.mean,
                mean_at_zero: r.mean_luminance,
                bias: Some(f.bias),
                m2: vb(f.integral_m2),
                c23: f.corr23.map(vb),
                p: vb(f.integral_p),
                q_pair: f.integral_q.map(vb),
                c24: f.corr24.map(vb),
                small_sphere_m2: vb(r.integral_m2),
            });
        }
        Self::small_sphere_from_report(r)
    }

    /// The finite-sphere model of every scattering order at q = 1 and
    /// N_B = 1 ([`crate::oracle::every_order_mean`] of a scene of orders
    /// 2 to 9 or `"all"` at
    /// `radius`, `docs/model.md` §10.3): μ(R), M₂ with its same-path pairs, P and the
    /// bias, exact at R; no pair integrals (other q and N_B are not
    /// modelled), so [`ModelAtRadius::variance`] is `None` there. The
    /// small-sphere M₂ of the asymptotic rule, ∝ 1/R², is c f μ(0): M₂
    /// less its same-path pairs is c f μ(R) in an isotropic medium (every
    /// hit adds c f), scaled by μ(0)/μ(R). An error where the report has
    /// no Var L, giving its reason.
    ///
    /// ```no_run
    /// use mcrt_noise::{oracle::every_order_mean, quad::Budget, tuning::objective::ModelAtRadius};
    /// let mut scene = mcrt_noise::Scene::from_toml_str(&std::fs::read_to_string("scenes/point-isotropic-all.toml")?)?;
    /// (scene.estimator.q, scene.estimator.camera_rays) = (1.0, 1);
    /// let report = every_order_mean(&scene, Some(1e-4), &Budget::new(1_000_000_000))?;
    /// let model = ModelAtRadius::from_every_order(&report, scene.estimator.radius)?;
    /// assert!(model.bias.is_some() && model.variance(1.0, 20.0, 1.0).is_some());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn from_every_order(
        m: &crate::oracle::EveryOrderMean,
        radius: f64,
    ) -> Result<ModelAtRadius, crate::model::OracleError> {
        let (Some(m2), Some(p), Some(pairs)) = (m.m2, m.p, m.same_path_pairs) else {
            return Err(crate::model::OracleError::Unsupported(format!(
                "Var L of every order: {}",
                m.variance_missing.as_deref().unwrap_or("not computed")
            )));
        };
        let (mu, mu0) = (m.mean, m.small_sphere_mean);
        let single = m2.value - pairs.value;
        let ratio = mu0.value / mu.value;
        let small_sphere_m2 = ValueWithBar {
            value: single * ratio,
            error: (m2.error + pairs.error) * ratio + single * ratio * (mu0.error / mu0.value + mu.error / mu.value),
        };
        Ok(ModelAtRadius {
            radius,
            model: "finite-sphere",
            mean: mu,
            mean_at_zero: mu0,
            bias: Some(m.bias),
            m2,
            c23: None,
            p,
            q_pair: None,
            c24: None,
            small_sphere_m2,
        })
    }

    /// The small-sphere model's integrals from an oracle report, whatever
    /// else it has, with the bias b(R) where the report has the
    /// finite-sphere mean (`finite_mean`) or model; an error where the report lacks
    /// the small-sphere pair integrals (see [`ModelAtRadius::from_report`]).
    ///
    /// ```no_run
    /// use mcrt_noise::oracle::{run, Precision};
    /// use mcrt_noise::tuning::objective::ModelAtRadius;
    /// let mut scene = mcrt_noise::Scene::from_toml_str(&std::fs::read_to_string("scenes/point-isotropic-order1.toml")?)?;
    /// (scene.estimator.q, scene.estimator.camera_rays) = (1.0, 1);
    /// let report = run(&scene, Precision::F64, Some(1e-4))?; // every integral of both models
    /// assert_eq!(ModelAtRadius::from_report(&report)?.model, "finite-sphere");
    /// let small = ModelAtRadius::small_sphere_from_report(&report)?;
    /// assert!(small.model == "small-sphere" && small.has_pairs() && small.bias.is_some());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn small_sphere_from_report(r: &Report) -> Result<ModelAtRadius, crate::model::OracleError> {
        let vb = |i: crate::oracle::Integral| ValueWithBar::from(i);
        // Their failure (at q = 1, N_B = 1, where the report stands without
        // them) is a computed failure, not an unsupported scene.
        if let Some(e) = &r.pairs_error {
            return Err(e.clone());
        }
        let (Some(corr23), Some(integral_q), Some(corr24)) = (&r.corr23, r.integral_q, &r.corr24) else {
            return Err(crate::model::OracleError::Unsupported(format!(
                "the oracle report lacks the small-sphere pair integrals (Q, (23), (24)) that other q and N_B need: {}",
                r.pairs_not_computed.as_deref().unwrap_or("not computed")
            )));
        };
        Ok(ModelAtRadius {
            radius: r.radius,
            model: "small-sphere",
            mean: r.mean_luminance,
            mean_at_zero: r.mean_luminance,
            // b(R) = μ(R) − μ(0) does not depend on q or N_B: the
            // finite-sphere mean's, or the finite-sphere model's own.
            bias: r.finite_mean.as_ref().and_then(|f| f.bias).or(r.finite.as_ref().map(|f| f.bias)),
            m2: vb(r.integral_m2),
            c23: Some(vb(corr23.exact)),
            p: vb(r.integral_p),
            q_pair: Some(vb(integral_q)),
            c24: Some(vb(corr24.exact)),
            small_sphere_m2: vb(r.integral_m2),
        })
    }

    /// Whether the model gives Var L at every (q, N_F, N_B), not only at
    /// q = 1, N_B = 1 ([`ModelAtRadius::variance`] is then never `None`).
    ///
    /// ```no_run
    /// use mcrt_noise::oracle::{run_scoped, Precision, Scope};
    /// use mcrt_noise::tuning::objective::ModelAtRadius;
    /// let mut scene = mcrt_noise::Scene::from_toml_str(&std::fs::read_to_string("scenes/point-isotropic-order1.toml")?)?;
    /// (scene.estimator.q, scene.estimator.camera_rays) = (1.0, 1);
    /// let model = ModelAtRadius::from_report(&run_scoped(&scene, Precision::F64, Some(1e-4), Scope::Prediction)?)?;
    /// assert!(!model.has_pairs()); // single-scattered light: finite-sphere, q = 1 and N_B = 1 only
    /// assert!(model.variance(1.0, 20.0, 1.0).is_some() && model.variance(0.5, 20.0, 1.0).is_none());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn has_pairs(&self) -> bool {
        self.c23.is_some() && self.q_pair.is_some() && self.c24.is_some()
    }

    /// Var L of one iteration with (q, N_F, N_B) (continuous counts
    /// allowed) and its bar, linear in the integrals' bars; `None` where it
    /// needs a pair integral the model does not give (q < 1 needs C₂₃ and,
    /// with N_F > 1, Q; N_B > 1 needs C₂₄), never reading one as 0.
    pub fn variance(&self, q: f64, n_f: f64, n_b: f64) -> Option<ValueWithBar> {
        let nfnb = n_f * n_b;
        let w_a = 1.0 / nfnb;
        let w_b = 1.0 / n_b - 1.0 / nfnb;
        let w_c = 1.0 / n_f - 1.0 / nfnb;
        let w_mu2 = 1.0 / nfnb - 1.0 / n_b - 1.0 / n_f;
        // A pair integral with weight exactly 0 (q = 1; N_B = 1) is not needed.
        let zero = ValueWithBar { value: 0.0, error: 0.0 };
        let needed = |x: Option<ValueWithBar>, weight: f64| if weight == 0.0 { Some(zero) } else { x };
        let b = needed(self.c23, w_a * (1.0 - q))?;
        let q_pair = needed(self.q_pair, w_b * (1.0 - q))?;
        let c = needed(self.c24, w_c)?;
        let (m, a) = (self.mean, self.m2);
        let value = w_a * (q * a.value + 2.0 * (1.0 - q) * b.value)
            + w_b * (q * self.p.value + 2.0 * (1.0 - q) * q_pair.value)
            + w_c * c.value
            + w_mu2 * m.value * m.value;
        let error = w_a * (q * a.error + 2.0 * (1.0 - q) * b.error)
            + w_b.abs() * (q * self.p.error + 2.0 * (1.0 - q) * q_pair.error)
            + w_c.abs() * c.error
            + w_mu2.abs() * 2.0 * m.value.abs() * m.error;
        Some(ValueWithBar { value, error })
    }
}

/// The predicted error after the budget, split into bias and noise.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Rmse {
    /// √(b² + Var/M)/μ(0), the relative RMSE.
    pub relative: f64,
    /// Its bar: the integrals' bars and the time's standard error (the
    /// costs' and the rates') carried through (the cost model's own error,
    /// validated in docs/choosing-parameters.md, is not in it).
    pub error: f64,
    /// |b(R)|/μ(0); `None` where the bias is not predicted.
    pub relative_bias: Option<f64>,
    /// Its bar (the integrals').
    pub relative_bias_error: Option<f64>,
    /// √(Var L/M)/μ(0).
    pub relative_noise: f64,
    /// Its bar: Var L's and the time's.
    pub relative_noise_error: f64,
    /// M = ⌊T/τ⌋, the whole iterations in the budget (≥ 1).
    pub iterations: u64,
    /// τ, predicted seconds per iteration.
    pub seconds_per_iteration: f64,
    /// Its standard error (costs and rates).
    pub seconds_per_iteration_error: f64,
}

impl Rmse {
    /// The RMSE of `model` with Var L = `variance` after `budget` seconds at
    /// `tau` = (seconds per iteration, its standard error); `None` if not
    /// one whole iteration fits.
    pub fn of(model: &ModelAtRadius, variance: ValueWithBar, tau: (f64, f64), budget: f64) -> Option<Rmse> {
        let mu0 = model.mean_at_zero.value;
        let whole = (budget / tau.0).floor();
        if !(whole >= 1.0 && whole.is_finite()) {
            return None;
        }
        let m = whole;
        let b = model.bias.map_or(0.0, |b| b.value);
        let noise2 = variance.value.max(0.0) / m;
        let total = (b * b + noise2).sqrt();
        // d(noise²) = dVar/M + noise²·dτ/τ (M ∝ 1/τ, continuous); d(total²) = 2|b| db + d(noise²).
        let d_noise2 = variance.error / m + noise2 * tau.1 / tau.0;
        let d_total2 = 2.0 * b.abs() * model.bias.map_or(0.0, |b| b.error) + d_noise2;
        let rel_mu = model.mean_at_zero.error / mu0;
        let half = |v: f64, dv: f64| if v > 0.0 { dv / (2.0 * v.sqrt()) } else { dv.sqrt() };
        Some(Rmse {
            relative: total / mu0,
            error: half(total * total, d_total2) / mu0 + total / mu0 * rel_mu,
            relative_bias: model.bias.map(|_| b.abs() / mu0),
            relative_bias_error: model.bias.map(|e| e.error / mu0 + b.abs() / mu0 * rel_mu),
            relative_noise: noise2.sqrt() / mu0,
            relative_noise_error: half(noise2, d_noise2) / mu0 + noise2.sqrt() / mu0 * rel_mu,
            // M ≤ T/τ ≤ 1e9 s / 1 ns = 1e18 < 2⁶⁴ (`cost::MIN_ITERATION_NS`).
            iterations: m as u64,
            seconds_per_iteration: tau.0,
            seconds_per_iteration_error: tau.1,
        })
    }
}
