//! # mcrt-noise
//!
//! How noisy is a bi-directional Monte Carlo ray tracer with photon maps in a
//! scattering medium, using multiple integration spheres on the camera ray
//! (Ershov, Zhdanov & Voloboy 2019)? This crate predicts one pixel's mean
//! and variance exactly, with error bars, and checks a renderer against
//! them.
//!
//! ## Testing a renderer
//! [`predict`] what one iteration of the pixel must give, push the
//! renderer's values into [`Samples`], and [`check()`] them: the [`Verdict`]
//! passes or fails at a stated false-alarm rate and says what a pass proves
//! (the smallest error the samples could have caught).
//!
//! ```
//! use mcrt_noise::{check, predict, CheckOptions, Samples, Scene};
//!
//! let scene = Scene::builder()
//!     .medium(1.0, 0.8)                           // σ_ext, albedo
//!     .point_light([1.0, 0.0, 1.0], 1.0)          // position, flux
//!     .camera([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])   // origin, view direction u
//!     .estimator(0.2, 0.5, 20, 4)                 // R, q, N_F, N_B
//!     .build()?;
//! # let tracer = mcrt_noise::reference::Tracer::new(&scene)?;
//! # let render_pixel = |i: u64| tracer.trial(3, i, mcrt_noise::reference::HitMethod::Sorted).0;
//! let prediction = predict(&scene)?;
//! let mut samples = Samples::new();
//! for i in 0..100_000 { samples.push(render_pixel(i))?; }   // your renderer's L
//! let verdict = check(&prediction, &samples, &CheckOptions::default());
//! verdict.assert_pass();
//! println!("{}", verdict.statement);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! `docs/library.md` has the details (what z means with the bars, the
//! calibration, the profile settings a dependent crate needs);
//! `mcrt-noise check` does the same for renderers in other languages.
//!
//! ## The rest of the crate
//! - [`oracle`]: the full report, both models side by side
//!   (`mcrt-noise oracle SCENE`);
//! - [`model`]: the noise model, scene → field → moments → correlations →
//!   noise (small-sphere model of the paper) and [`model::finite`] (exact at
//!   any R for uncollided light);
//! - [`quad`], [`special`], [`real`]: the quadrature engine and special
//!   functions, in f64 and (feature `mpfr`, on by default) MPFR, never
//!   silently wrong;
//! - `reports` (feature `cli`, on by default): the CLI's tables and the
//!   generated documents (uses the library; the library never uses it);
//! - [`scene`] (crate `mcrt-scene`) and [`reference`](mod@crate::reference) (crate
//!   `mcrt-reference`, the independent reference tracer), re-exported.
//!
//! Units and conventions: `docs/conventions.md`.

// `!(x >= 0)` is how NaN-rejecting range checks are written here, on purpose.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
#![warn(missing_docs)]

// The public API of a renderer's test, first.
pub use check::{
    check, predict, CheckOptions, Model, PredictError, Predicted, Prediction, PredictionReport, SampleError, Samples,
    SumsInequality, Verdict,
};
pub use mcrt_scene::{Phase, ScatteringOrders, Scene, SceneBuilder, SceneError};

pub mod check;
pub mod kernel;
pub mod model;
pub mod oracle;
pub mod prec;
pub mod quad;
pub mod real;
#[cfg(feature = "cli")]
pub mod reports;
pub mod special;
pub mod tuning;

pub use mcrt_reference as reference;
pub use mcrt_scene as scene;

/// The README's code blocks, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;

/// The code blocks of `docs/library.md`, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../docs/library.md")]
pub struct LibraryDocDoctests;
