//! Named tolerances, in one place (cf. statrs `prec`).

/// Default relative tolerance of f64 quadrature.
pub const F64_REL_TOL: f64 = 1e-13;
/// Maximum f64 error of a special function, in units in the last place,
/// over its whole domain (measured in `docs/accuracy.md`).
pub const SPECIAL_MAX_ULPS: f64 = 4.0;
