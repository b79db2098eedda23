//! # mcrt-noise
//!
//! A numerics oracle for the noise of the multiple-integration-spheres
//! estimator of Ershov, Zhdanov & Voloboy (2019): special functions and a
//! quadrature engine in f64 and MPFR that report value, error bar, evaluation
//! count and status, never a silently wrong number.
//!
//! Architecture: scene (crate `mcrt-scene`) → field → moments → correlations →
//! noise, beside the independent reference tracer (crate `mcrt-reference`).
//! Units and conventions: `docs/conventions.md`.

// `!(x >= 0)` is how NaN-rejecting range checks are written here, on purpose.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod accuracy;
pub mod compare;
pub mod kernel;
pub mod model;
pub mod model_error;
pub mod oracle;
pub mod prec;
pub mod quad;
pub mod real;
pub mod report;
pub mod special;
pub mod sweep;
pub mod tracer_checks;

pub use mcrt_scene as scene;
