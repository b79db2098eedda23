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
#![warn(missing_docs)]

pub mod kernel;
pub mod model;
pub mod oracle;
pub mod prec;
pub mod quad;
pub mod real;
pub mod reports;
pub mod special;

pub use mcrt_scene as scene;
