//! The oracle's report: values with their bars in f64 as the report gives
//! them, the report's types, and the check that every number it prints is
//! representable.

use super::*;
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
    /// The integral at the scene's R: exact for the one-segment part (the
    /// paper's (23), (24), corrected), plus `cross_segment`, an R → 0 form.
    pub exact: Integral,
    /// The part of `exact` from the two segments of one forward path meeting
    /// one sphere each (single-scattered light in isotropic media; erratum
    /// E10, its R → 0 form, `docs/model.md` §3c); absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cross_segment: Option<Integral>,
    /// Why the cross-segment term was computed but not added (its R → 0
    /// form is out of range); absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cross_segment_not_added: Option<String>,
    /// Its R → 0 form, (25) or (26).
    pub asymptotic: Asymptotic,
    /// (exact − cross_segment) / asymptotic (→ 1 as R → 0): the one-segment
    /// part of the integral, the paper's, against its R → 0 form.
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
    /// finite/small-sphere ratio of Var L; `None` (JSON `null`) where the
    /// small-sphere Var L cannot be formed ([`Report::variance`]).
    pub variance_ratio: Option<ValueWithBar>,
    /// M₂ = ∫σe^{−σs}⟨𝒞²⟩_R ds of (16).
    pub integral_m2: Integral,
    /// P = ∫σe^{−σs}⟨𝒞⟩_R² ds of (17).
    pub integral_p: Integral,
    /// Q = ∫∫ σ²e^{−σ(s+s′)}⟨𝒞⟩_R(s)⟨𝒞⟩_R(s′) ds ds′ of (17); `None`
    /// (JSON `null`) where not computed ([`FiniteReport::not_computed`]
    /// says why).
    pub integral_q: Option<Integral>,
    /// C₂₃, the finite-sphere form of integral (23); `None` where not
    /// computed (also when q = 1 alone: [`FiniteReport::not_computed`]).
    pub corr23: Option<Integral>,
    /// C₂₄, the finite-sphere form of integral (24); `None` where not
    /// computed (also when N_B = 1 alone: [`FiniteReport::not_computed`]).
    pub corr24: Option<Integral>,
    /// Why some of Q, C₂₃ and C₂₄ are missing, if any is: each is computed
    /// only where Var L weighs it (all three missing at q = 1 and N_B = 1,
    /// C₂₃ alone at q = 1, C₂₄ alone at N_B = 1).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub not_computed: Option<String>,
    /// The light the model covers: `"uncollided"` (scattering order 0) or
    /// `"uncollided and single-scattered"` (order 1).
    pub covers: &'static str,
    /// This model's c₀ (`FiniteField::shift`).
    pub attenuation_shift: f64,
    /// Integrand evaluations of this model's integrals.
    pub evaluations: u64,
}

/// [`Report::pairs_not_computed`] of a prediction with q = 1 and N_B = 1.
pub const SMALL_SPHERE_PAIRS_NOT_NEEDED: &str = "Q, (23), (24) and their R → 0 forms enter Var L with weight 0 at \
     q = 1 and N_B = 1 (one sphere per camera ray, one camera ray) and a prediction does not compute them; \
     `mcrt-noise oracle` does (they give D₁…D₅ and the other settings' noise)";

/// Follows the failure in [`Report::pairs_not_computed`] where the
/// small-sphere pair integrals failed at q = 1 and N_B = 1.
pub const SMALL_SPHERE_PAIRS_FAILED: &str = "the small-sphere Q, (23), (24) and their R → 0 forms failed; they \
     enter Var L with weight 0 at q = 1 and N_B = 1 (one sphere per camera ray, one camera ray), so the report \
     stands without them (no D₁…D₅, no noise at other settings)";

/// [`FiniteReport::not_computed`] of an order-1 scene with q = 1, N_B = 1.
pub const PAIRS_NOT_NEEDED: &str = "Q, C₂₃ and C₂₄ enter Var L with weight 0 at q = 1 and N_B = 1 (one sphere per \
     camera ray, one camera ray) and are not computed; with single-scattered light they take about a minute \
     (docs/model.md §9.7)";

/// The finite-sphere mean of a scene with single-scattered light.
#[derive(Debug, Clone, Serialize)]
pub struct FiniteMean {
    /// μ(R) = μ₀(R) + μ₁(R), exact at the scene's R, with its quadrature
    /// bar; `None` when it could not be computed (`missing` says why).
    pub mean: Option<ValueWithBar>,
    /// b(R) = μ(R) − μ(0), μ(0) the small-sphere mean (formed in the
    /// working precision).
    pub bias: Option<ValueWithBar>,
    /// Why the mean is missing (its quadrature's failure), if it is.
    pub missing: Option<String>,
    /// Integrand evaluations spent on it.
    pub evaluations: u64,
}

/// What the oracle predicts for the scene, and from which model.
#[derive(Debug, Clone, Serialize)]
pub struct ReportPrediction {
    /// `"finite-sphere"` (exact at the scene's R: uncollided light, and
    /// single-scattered light in isotropic media with q = 1, N_B = 1, or
    /// at any q, N_B with [`super::Scope::FinitePairs`] or
    /// [`super::Scope::ExactPrediction`], and with these scopes
    /// single-scattered light from point lights in Henyey–Greenstein media
    /// with q = 1, N_B = 1) or
    /// `"small-sphere"` (§4.3, exact as R → 0; the other
    /// scenes with scattered light).
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
     model's own error at this R (the finite-sphere model covers uncollided light; in isotropic media \
     it covers single-scattered light at q = 1 and N_B = 1, and of other order-1 scenes it gives the mean, \
     `finite_mean`); measured with the tracer on \
     point-isotropic-order1 at R = 0.1: Var L within 1.2 % and 2.0 % (two standard errors included) with the \
     cross-segment terms of (23), (24) (E10; 4.7 % off without them, as where they are not added), falling like \
     R ln(1/R) \
     (tests/tracer_vs_oracle.rs); its mean is 0.33 % low there, as `finite_mean` computes)";

/// The note of a finite-sphere prediction for uncollided light.
pub const FINITE_NOTE: &str = "exact at this R for uncollided light; the bars are the quadrature's (the model \
     approximates nothing)";

/// The note of a finite-sphere prediction with single-scattered light.
pub const FINITE_ORDER1_NOTE: &str = "exact at this R for uncollided and single-scattered light (isotropic medium); \
     the bars are the quadrature's (the model approximates nothing)";

/// The note of a finite-sphere prediction with single-scattered light in a
/// Henyey–Greenstein medium (`oracle --finite-pairs` and the library's
/// `predict`, q = 1 and N_B = 1).
pub const FINITE_ORDER1_HG_NOTE: &str = "exact at this R for uncollided and single-scattered light (point lights \
     in a Henyey–Greenstein medium at q = 1 and N_B = 1, docs/model.md §9.10); the bars are the quadrature's (the \
     model approximates nothing)";

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
    /// Integral (23), exact at R and its R → 0 form (small-sphere model);
    /// `None` (JSON `null`) where not computed ([`Report::pairs_not_computed`]
    /// says why).
    pub corr23: Option<Correlation>,
    /// Integral (24), likewise.
    pub corr24: Option<Correlation>,
    /// Var L of the small-sphere model, and the §4.4 formula; `None` (JSON
    /// `null`) where that model cannot form it: its integrals of two
    /// spheres, which (7)–(9) weigh (q < 1 or N_B > 1), failed
    /// ([`Report::pairs_error`] and [`Report::pairs_not_computed`] say
    /// why). The prediction is then the finite-sphere model's, if it has
    /// one.
    pub variance: Option<Variance>,
    /// M₂ = ∫σe^{−σs}⟨𝒞²⟩ ds, the rest of (16) beside (23) (with the
    /// same-path double hits of scattered light, `integral_m2_same_path`).
    pub integral_m2: Integral,
    /// M₂ₓ, the part of `integral_m2` from one forward path hitting a sphere
    /// with two segments (E9, `docs/model.md` §3b); present for scenes with
    /// scattered light only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub integral_m2_same_path: Option<Integral>,
    /// The exact mean at R of an order-1 scene (isotropic medium;
    /// `docs/model.md` §9.5) whose Var L is still the small-sphere
    /// model's (q < 1 or N_B > 1; with q = 1 and N_B = 1 [`Report::finite`]
    /// has the whole order-1 model).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub finite_mean: Option<FiniteMean>,
    /// Why the prediction of a scene with scattered light is not the
    /// finite-sphere model (what it does not cover yet, or its failure).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub finite_not_used: Option<String>,
    /// The finite-sphere model's failure on a scene it covers (its
    /// quadrature did not converge), kept for the library's `predict`.
    #[serde(skip)]
    pub finite_error: Option<crate::model::OracleError>,
    /// The failure of the small-sphere pair integrals at q = 1 and N_B = 1,
    /// where Var L weighs them 0 and the report stands without them
    /// ([`Report::pairs_not_computed`] gives it as text), kept for callers
    /// that need them (`sweep`, the optimiser's small-sphere comparison).
    #[serde(skip)]
    pub pairs_error: Option<crate::model::OracleError>,
    /// P = ∫σe^{−σs}⟨𝒞⟩² ds of (17).
    pub integral_p: Integral,
    /// Q = ∫∫σ²e^{−σ(s+s′)}⟨𝒞⟩(s)⟨𝒞⟩(s′) ds ds′ of (17); `None` as
    /// `corr23`.
    pub integral_q: Option<Integral>,
    /// Why the small-sphere model's integrals of two spheres (Q, (23),
    /// (24), (25), (26)) are missing, if they are: a prediction
    /// ([`Scope::Prediction`]) with q = 1 and N_B = 1, whose Var L weighs
    /// them 0, or their failure (the failure, then
    /// [`SMALL_SPHERE_PAIRS_FAILED`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pairs_not_computed: Option<String>,
    /// c₀ = σ_ext × shortest light path to the camera ray: integrals are
    /// computed with W·e^{c₀} and scaled back for this report.
    pub attenuation_shift: f64,
    /// D₁…D₅ of §4.4, if the asymptotic forms exist (and were computed).
    pub d: Option<[f64; 5]>,
    /// Their bars.
    pub d_error: Option<[f64; 5]>,
    /// Evaluations of the small-sphere model's integrals.
    pub evaluations: u64,
    /// The finite-sphere model: for uncollided light, and for
    /// single-scattered light in isotropic media with q = 1, N_B = 1 (point
    /// lights and beams) or, with [`super::Scope::FinitePairs`] or
    /// [`super::Scope::ExactPrediction`], any q and N_B (point lights and
    /// beams), and with these scopes point lights in Henyey–Greenstein media
    /// with q = 1, N_B = 1; `None` elsewhere ([`Report::finite_not_used`]
    /// says why).
    pub finite: Option<FiniteReport>,
    /// The prediction to test a renderer against: the finite-sphere model
    /// where it exists, else the small-sphere one.
    pub prediction: ReportPrediction,
    /// Wall time of the run.
    pub wall_time_ms: f64,
}

/// A value of the working precision as the report gives it, in f64: the
/// bar bounds the distance of the *reported* value to the exact one, so it
/// is the working bar plus the value's rounding to f64, rounded up (in
/// MPFR a bar of 1e-400 was reported as 0, and a bar of 1e-300 on a value
/// rounded to 53 bits claimed more than f64 holds).
pub(super) fn reported<T: Real>(value: &T, error: &T) -> ValueWithBar {
    let v = value.to_f64();
    let rounding = (value.clone() - value.lit(v)).abs();
    ValueWithBar { value: v, error: (error.abs() + rounding).to_f64_up() }
}

/// An estimate of the shifted field scaled back by `factor` (e^{−c₀} for
/// quantities linear in W, e^{−2c₀} for quadratic ones), for the report.
pub(super) fn scaled<T: Real>(e: &Estimate<T>, factor: &T) -> Integral {
    let r = reported(&(e.value.clone() * factor.clone()), &(e.error.clone() * factor.clone()));
    Integral { value: r.value, error: r.error, evaluations: e.evaluations }
}

pub(super) fn correlation<T: Real>(
    exact: &Estimate<T>,
    cross: Option<&Result<Estimate<T>, String>>,
    asym: &Result<Estimate<T>, String>,
    k: &T,
) -> Correlation {
    let scaled = |e: &Estimate<T>| scaled(e, k);
    let added = cross.and_then(|c| c.as_ref().ok());
    let cross_segment = added.map(scaled);
    let cross_segment_not_added = cross.and_then(|c| c.as_ref().err()).cloned();
    // The ratio is of the one-segment part, whose R → 0 form (25), (26) is.
    let (one, one_error) = match added {
        Some(x) => (exact.value.clone() - x.value.clone(), exact.error.clone() + x.error.clone()),
        None => (exact.value.clone(), exact.error.clone()),
    };
    match asym {
        Ok(a) => {
            let ratio = one.clone() / a.value.clone();
            let rel = one_error / one.abs() + a.error.clone() / a.value.abs();
            let asymptotic = reported(&(a.value.clone() * k.clone()), &(a.error.clone() * k.clone()));
            let ratio = reported(&ratio, &(ratio.abs() * rel));
            Correlation {
                exact: scaled(exact),
                cross_segment,
                cross_segment_not_added,
                asymptotic: Asymptotic { value: Some(asymptotic.value), error: Some(asymptotic.error), missing: None },
                ratio: Some(ratio.value),
                ratio_error: Some(ratio.error),
            }
        }
        Err(why) => Correlation {
            exact: scaled(exact),
            cross_segment,
            cross_segment_not_added,
            asymptotic: Asymptotic { value: None, error: None, missing: Some(why.clone()) },
            ratio: None,
            ratio_error: None,
        },
    }
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
        if let Some(v) = &self.variance {
            bar("Var L (small-sphere)", &v.exact);
        }
        bar("prediction: mean", &self.prediction.mean);
        bar("prediction: Var L", &self.prediction.variance);
        bar("prediction: relative noise", &self.prediction.relative_noise);
        if let Some(f) = &self.finite {
            bar("finite-sphere mean", &f.mean);
            bar("finite-sphere Var L", &f.variance);
            bar("finite-sphere bias", &f.bias);
            bar("finite-sphere relative noise", &f.relative_noise);
            bar("finite/small mean ratio", &f.mean_ratio);
            if let Some(r) = &f.variance_ratio {
                bar("finite/small Var L ratio", r);
            }
        }
        if let Some(f) = &self.finite_mean {
            if let (Some(m), Some(b)) = (&f.mean, &f.bias) {
                bar("finite-sphere mean (single scattering)", m);
                bar("finite-sphere bias (single scattering)", b);
            }
        }
        if let Some(m) = &self.integral_m2_same_path {
            bar("M₂ same-path hits", &ValueWithBar { value: m.value, error: m.error });
        }
        if let Some(v) = &self.variance {
            out.push(("relative noise (small-sphere)".into(), v.relative));
            out.push(("relative noise (small-sphere, bar)".into(), v.relative_error));
        }
        for (name, c) in [("(23)", &self.corr23), ("(24)", &self.corr24)] {
            let Some(c) = c else { continue };
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
        let small = self.variance.as_ref();
        for (what, v) in [
            ("Var/L², §4.4 formula", small.and_then(|v| v.relative_asymptotic)),
            ("Var/L², §4.4 formula (bar)", small.and_then(|v| v.relative_asymptotic_error)),
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
    /// of a positive integrand): printed as 0, they have underflowed. The
    /// same-path hits only where uncollided light meets the camera ray
    /// (`same_path_lit`); elsewhere they are exactly 0 (a beam beside the
    /// camera ray, whose scattered light alone reaches it).
    fn positive_numbers(&self, same_path_lit: bool) -> Vec<(&'static str, ValueWithBar)> {
        let int = |i: &Integral| ValueWithBar { value: i.value, error: i.error };
        let mut out =
            vec![("mean luminance (small-sphere)", self.mean_luminance), ("prediction: mean", self.prediction.mean)];
        if let Some(v) = &self.variance {
            out.push(("Var L (small-sphere)", v.exact));
        }
        out.push(("prediction: Var L", self.prediction.variance));
        for (name, c) in [("(23) exact", &self.corr23), ("(24) exact", &self.corr24)] {
            if let Some(c) = c {
                out.push((name, int(&c.exact)));
            }
        }
        if let Some(f) = &self.finite {
            out.push(("finite-sphere Var L", f.variance));
        }
        if let Some(m) = self.finite_mean.as_ref().and_then(|f| f.mean) {
            out.push(("finite-sphere mean (single scattering)", m));
        }
        if let Some(m) = self.integral_m2_same_path.as_ref().filter(|_| same_path_lit) {
            out.push(("M₂ same-path hits", int(m)));
        }
        out
    }

    /// Fails when a printed number is not finite, or a quantity that is
    /// positive for every lit scene (the mean, which the ratios and the
    /// relative noise divide by; Var L; (23), (24); the same-path hits where
    /// uncollided light meets the camera ray, `same_path_lit`) has
    /// underflowed to 0.
    pub(super) fn check_representable(&self, scene: &Scene, same_path_lit: bool) -> Result<(), OracleError> {
        let fluxes: Vec<String> = scene.lights.iter().map(|l| format!("{:e}", l.flux())).collect();
        let advice = format!(
            "the mean scales with the lights' flux ({}) and Var L with its square, the relative noise not at all: \
             rescale the fluxes (or bring the lights nearer: e^(−σ_ext·distance) underflows beyond ~700)",
            fluxes.join(", ")
        );
        for (name, v) in self.positive_numbers(same_path_lit) {
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

#[cfg(all(test, feature = "mpfr"))]
mod tests {
    use super::reported;
    use rug::Float;

    /// A 1024-bit value and bar as the report gives them in f64: the bar
    /// (1e-502, below the smallest double) must stay positive and bound
    /// the distance of the f64 value to the working one, its rounding.
    #[test]
    fn a_bar_below_f64_is_a_positive_bound_on_the_reported_value() {
        let value = decimal("1.234567890123456789012345678901234567890e-200");
        let bar = decimal("1e-502");
        let r = reported(&value, &bar);
        assert!(r.error > 0.0, "{r:?}");
        let off = Float::with_val(1024, &value - r.value).abs();
        assert!(off <= r.error, "off by {off:e}, bar {:e}", r.error);
        // f64 itself adds nothing.
        let exact = reported(&0.5f64, &1e-20);
        assert_eq!((exact.value, exact.error), (0.5, 1e-20));
    }

    fn decimal(text: &str) -> Float {
        crate::kernel::parse_decimal(text, 1024).expect("a decimal")
    }
}
