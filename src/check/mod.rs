//! Testing a renderer against the oracle: [`predict`] what one iteration of
//! the pixel must give, accumulate the renderer's values in [`Samples`],
//! [`check`] them, and get a [`Verdict`] that passes, fails or says it
//! cannot tell yet ([`Status`]); [`plan`] how many values a check needs
//! from a pilot run.
//!
//! The verdict runs three tests at a family-wise false-alarm rate: the
//! largest value against bounds that hold for any distribution, the mean
//! with the *predicted* Var L as its scale, and Var L by the
//! studentised s², both through Hall's skewness correction, at a limit set
//! for their correlation. A quantity is resolved only when its verdict
//! rests neither on one value nor on a handful ([`MAX_INFLUENCE`],
//! [`TOP_VALUES`]), enough values are nonzero ([`MIN_NONZERO`]) and enough
//! carry the spread ([`MIN_EFFECTIVE_COUNT`]); a pass must detect the
//! resolution targets (default 10 % of the mean, 20 % of Var L), else the
//! samples are NOT RESOLVED with what would resolve them. Calibration and
//! derivations: `docs/library.md`.
//!
//! Modules, in the order a check flows: `predict` (the prediction and its
//! bars), `samples` (exact power sums to the sixth; `extremes`: the
//! smallest value and the largest few;
//! `realisable`: which sums real values can have), `shape` (standardised
//! moments, and with one value deleted), `options` (rates, power, targets,
//! named constants), `statistics` (the z-scores, detectable errors, tail
//! bound), `family` (the limit for correlated z-scores), `influence` (of
//! one value), `verdict` (the decision), `display` (the verdict in words),
//! `plan` (samples needed).

mod display;
pub mod extremes;
mod family;
mod influence;
mod options;
mod plan;
mod predict;
mod realisable;
mod samples;
mod shape;
mod statistics;
mod verdict;

pub use extremes::TOP_VALUES;
pub use options::{
    CheckOptions, CHECKS, DEFAULT_TARGET_MEAN, DEFAULT_TARGET_VARIANCE, MAX_INFLUENCE, MIN_EFFECTIVE_COUNT,
    MIN_FALSE_ALARM_RATE, TAIL_SHARE,
};
pub use plan::{plan, Plan};
pub use predict::{
    predict, predict_with, predict_within, Model, PredictError, Predicted, Prediction, PredictionReport,
};
pub use realisable::SumsInequality;
pub use samples::{Measured, SampleError, Samples};
pub use shape::Shape;
pub use statistics::{Normaliser, Null};
pub use verdict::{check, QuantityCheck, Ratio, Status, TailCheck, Verdict, MIN_NONZERO, MIN_SAMPLES};
