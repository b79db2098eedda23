//! Scene model shared by the `mcrt-noise` oracle and the `mcrt-reference` tracer.
//!
//! A scene is a TOML file (format: `docs/scene-format.md`, conventions:
//! `docs/conventions.md`). [`Scene::from_toml_str`] parses *and* validates it (and
//! [`Scene::builder`] builds one in code with the same validation):
//! every invalid value is reported as a [`FieldError`] naming the field, the
//! value and the allowed range, and no partially valid scene is ever returned.
//! The accessors ([`Scene::medium`], [`Scene::lights`], [`Scene::camera`],
//! [`Scene::estimator`], [`Scene::scattering_orders`], [`Scene::cost`] and
//! those of each part) read every value back, so a renderer can set itself
//! up from a scene, or rebuild one, through these methods alone.
//!
//! This crate holds only the scene and the physics primitives both crates need
//! (the phase functions). The oracle's formulas live in `mcrt-noise`; the tracer
//! must not depend on them, so that it stays an independent witness.

#![warn(missing_docs)]

mod access;
mod builder;
mod error;
mod file;
pub mod limits;
mod model;
mod phase;
mod validate;

pub use builder::SceneBuilder;
pub use error::{FieldError, SceneError};
pub use glam::DVec3;
pub use model::{Camera, Cost, Effects, Estimator, Light, Medium, ScatteringOrders, Scene, COST_KEYS};
pub use phase::Phase;
