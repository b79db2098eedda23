//! Named tolerances, in one place (cf. statrs `prec`).

/// Default relative tolerance of f64 quadrature.
pub const F64_REL_TOL: f64 = 1e-13;
/// Maximum f64 error of a special function, in units in the last place,
/// over its whole domain (measured in `docs/accuracy.md`).
pub const SPECIAL_MAX_ULPS: f64 = 4.0;

/// Radius at which the oracle model's own error is measured against the
/// tracer (`tests/tracer_vs_oracle.rs`, ignored test
/// `model_error_at_the_reference_radius`).
pub const MODEL_ERROR_RADIUS: f64 = 0.1;

/// How the oracle model's own error (the small-sphere assumptions of §4.3:
/// f and the attenuation taken at the sphere's centre, one segment through
/// whole spheres) is carried from [`MODEL_ERROR_RADIUS`] to a smaller R:
/// times R ln(1/R) / (R₀ ln(1/R₀)), the slowest decay derived or observed
/// (single-scattered light has an R ln(1/R) term, `docs/asymptotic-checks.md`;
/// order-0 errors measured O(R) and O(R²)). For R ≥ R₀ it is 1 (the
/// measurement is not extrapolated upwards: callers keep R ≤ R₀).
pub fn model_error_scale(radius: f64) -> f64 {
    let r0 = MODEL_ERROR_RADIUS;
    if radius >= r0 {
        return 1.0;
    }
    radius * (1.0 / radius).ln() / (r0 * (1.0 / r0).ln())
}

/// Default relative tolerance for `bits` of MPFR: 2^{−(bits − 22)}, leaving
/// 22 bits for rounding noise and the inner integrals' tenth (feature `mpfr`).
#[cfg(feature = "mpfr")]
pub fn mpfr_default_tol(bits: u32) -> f64 {
    2f64.powi(-(bits as i32 - 22))
}

/// The small-sphere model's own relative error for single-scattered light
/// at R = [`MODEL_ERROR_RADIUS`] (mean, Var L): the larger of the two
/// measurements of `tests/tracer_vs_oracle.rs` (point-isotropic-order1 with
/// q = 0.5, N_F = 200, N_B = 8 and with q = 0.2, N_F = N_B = 1; each
/// |tracer/oracle − 1| plus two standard errors; re-measured by its ignored
/// test `model_error_at_the_reference_radius`), with the cross-segment terms
/// of (23), (24) in the model (`model::cross_segment`, E10). `check::predict`
/// uses it, scaled by [`model_error_scale`], as the model bar of scenes
/// with scattered light whose (23), (24) carry those terms, and of those
/// with q = 1 and N_B = 1, where (7)–(9) weigh (23), (24) 0 (there the
/// small-sphere model's error is that of μ, M₂ and P alone: against the
/// exact finite-sphere model, isotropic, Var L is 1.75 % high at R = 0.2,
/// `tests/finite_order1.rs`, and 0.67 % at R = 0.1, `oracle --rel-tol 1e-6`).
pub const SMALL_SPHERE_SCATTERED_ALLOWANCE: (f64, f64) = (1.1e-2, 2.1e-2);

/// The loosest relative goal of the finite-sphere correlations of two
/// spheres with single-scattered light (C₂₃, C₂₄ and the model beside
/// them) in the library's prediction (`oracle::Scope::ExactPrediction`):
/// they cost ~10⁹ evaluations at 10⁻³ and grow past minutes below
/// (`docs/model.md` §9.7). The bars the quadrature reports at this goal are
/// one to two orders tighter (Var L ± 3.5·10⁻⁵ relative on
/// `point-isotropic-order1`), and enter the check's tolerance as they are.
pub const FINITE_PAIRS_PREDICTION_TOL: f64 = 1e-3;

/// The loosest relative goal of the finite-sphere mean of single-scattered
/// light in a Henyey–Greenstein medium (`model::finite::scattered_hg`,
/// three nested levels at every camera-ray point, f64 only): it is
/// computed at this goal when the run asks for a tighter one. At 10⁻³ it
/// takes 2·10⁸–4·10⁸ evaluations (12–21 s on two cores; 10⁻⁴ costs twice
/// that, 10⁻⁶ 3·10⁹ and 3.5 minutes), and its bars are one to two orders
/// tighter than the goal (±1.9·10⁻⁵ relative at g = 0.9, R = 0.2, the
/// light 0.3 from the camera line); they are reported as they are.
pub const FINITE_HG_MEAN_TOL: f64 = 1e-3;

/// The evaluation budget of a prediction with the finite-sphere
/// correlations of two spheres ([`FINITE_PAIRS_PREDICTION_TOL`]): three
/// times the 10⁹ default, since the pairs alone need 6.7·10⁸ on
/// `point-isotropic-order1` and 1.4·10⁹ with a light 0.1 from the camera
/// line (a few minutes on two cores at most; spent, the prediction falls
/// back to the small-sphere model with its allowance, or fails).
pub const FINITE_PAIRS_PREDICTION_EVALUATIONS: u64 = 3_000_000_000;

/// The evaluation budget of a prediction of scattering orders ≥ 2 or
/// `"all"` (`oracle::every_order_mean` with Var L, `docs/model.md` §10.3):
/// three times the 10⁹ default, since a finite order n builds a table of
/// the hits of each order 2..n − 1 for its same-path pairs (7 December
/// 2026, two cores, the README scene at albedo 0.5, R = 0.2, N_F = 1:
/// `"all"` 2·10⁸ evaluations and 10 s, order 3 10 s, order 6 34 s, order
/// 9 1.4·10⁹ and 63 s).
pub const EVERY_ORDER_PREDICTION_EVALUATIONS: u64 = 3_000_000_000;

/// The evaluation budget of a prediction of single-scattered light from
/// point lights in a Henyey–Greenstein medium at q = 1 and N_B = 1, exact
/// at any R (`oracle::Scope::ExactPrediction`: μ, M₂ with the same-path
/// term, P, `docs/model.md` §9.10, at [`FINITE_PAIRS_PREDICTION_TOL`]).
/// Measured (6 December 2026, two cores, g = 0.6, albedo 0.9, light at
/// (0.7, 0.4, 1.6), N_F = 20): 4.2·10⁹ evaluations and 4.4 minutes at
/// R = 0.2, 4.1·10⁹ and 5.2 minutes at R = 0.01; 4.1·10⁹ at g = −0.5,
/// R = 0.5; 1.65·10¹⁰ (~30 minutes) at g = 0.9 with the light 0.2 from the
/// camera line (5 December 2026), with the rest of the prediction and a
/// second computation of μ beside it. Spent, the prediction falls back to the
/// small-sphere model with its allowance (R ≤ 0.1), or fails.
pub const FINITE_HG_PREDICTION_EVALUATIONS: u64 = 30_000_000_000;

/// The same measurement without the cross-segment terms (December 2026,
/// before they entered the model: Var L 4.7 % below the tracer at the
/// first point, plus two standard errors): the model bar where they are not
/// added (Henyey–Greenstein media, where they are not derived, or an R
/// outside their R → 0 form's range) and (23), (24) count (q < 1 or
/// N_B > 1). Not re-measurable now that the
/// isotropic model carries them; a measurement on an isotropic scene, not
/// a bound for other media. Checked at g = −0.5, R = 0.1 against the
/// tracer (0.63 % and 4.30 % with two standard errors, 5 December 2026:
/// `tests/tracer_vs_oracle.rs`, ignored); at g = 0.9 the tracer does not
/// resolve Var L there.
pub const SMALL_SPHERE_SCATTERED_ALLOWANCE_WITHOUT_CROSS: (f64, f64) = (1.1e-2, 4.9e-2);
