//! # mcrt-reference
//!
//! The seeded reference tracer of `mcrt-noise`: it runs the estimator of the
//! seed paper (multiple integration spheres on the camera ray, forward rays
//! from the lights) many independent times and measures the pixel's mean and
//! variance with standard errors. It depends on the scene model
//! (`mcrt-scene`) only, never on the oracle's formulas, so that it stays an
//! independent witness.
//!
//! - [`rng`]: per-trial streams keyed by (seed, trial), draws counted by kind;
//! - [`sampling`]: exponential steps, directions, disk points;
//! - [`hits`]: which spheres a forward segment hits (sorted search, brute force);
//! - [`limits`]: the tracer's bounds (lengths, memory and work of a trial, work of a run);
//! - [`estimator`]: one trial (one iteration of one pixel), with counters;
//! - [`exact`]: exact sums of powers of doubles and exact dyadic arithmetic (no GMP/MPFR);
//! - [`moments`]: exact power sums, mean, variance and standard errors;
//! - [`run`]: parallel runs over trial ranges, shards and their exact merge;
//! - [`correlation`]: a direct measurement of ⟨𝒞(s)𝒞(s+t)⟩.

pub mod correlation;
pub mod estimator;
pub mod exact;
pub mod hits;
pub mod limits;
pub mod moments;
pub mod rng;
pub mod run;
pub mod sampling;

pub use estimator::{Counters, HitMethod, TraceError, Tracer};
pub use rng::trial_rng;
pub use run::{merge, trace, Run, Shard, MIN_NONZERO_TRIALS};
