//! Testing a renderer against the oracle: [`predict`] what one iteration of
//! the pixel must give, accumulate the renderer's values in [`Samples`],
//! and [`check`] them, with a [`Verdict`] that says what a pass proves.
//!
//! The check is two z-tests (mean and Var L), the prediction's bars
//! (quadrature, and for the small-sphere model its measured model error)
//! subtracted before dividing by the standard error, at a family-wise
//! false-alarm rate split between them by Šidák's correction. Beside
//! pass/fail it reports the smallest relative error in each quantity that
//! would have failed with the stated power: a pass with a detectable error
//! of 30 % proves little, and a stated target turns that into a failure.
//! Calibration: `tests/check.rs` runs it 400 times on the reference tracer
//! where the model is exact. Details and the profile settings a dependent
//! crate needs: `docs/library.md`.

mod predict;
mod samples;
mod verdict;

pub use predict::{predict, predict_with, Model, PredictError, Predicted, Prediction};
pub use samples::{Measured, SampleError, Samples, SumsInequality};
pub use verdict::{check, CheckOptions, QuantityCheck, Ratio, Verdict, CHECKS, MIN_NONZERO, MIN_SAMPLES};
