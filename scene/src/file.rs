//! The scene file as written: a serde image of the TOML with no validation.
//!
//! Unknown keys are rejected here (`deny_unknown_fields`). Numbers that have a
//! range are read in a wider type (`i64`, `f64`) so that the validator, not the
//! decoder, reports them with the field name and the allowed range.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SceneFile {
    pub medium: MediumFile,
    pub lights: Vec<LightFile>,
    pub camera: CameraFile,
    pub estimator: EstimatorFile,
    #[serde(default)]
    pub effects: EffectsFile,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MediumFile {
    pub sigma_ext: f64,
    pub albedo: f64,
    #[serde(default)]
    pub phase: PhaseFile,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PhaseFile {
    pub kind: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub g: Option<f64>,
}

impl Default for PhaseFile {
    fn default() -> Self {
        PhaseFile { kind: "isotropic".into(), g: None }
    }
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct LightFile {
    pub kind: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    pub flux: f64,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct CameraFile {
    pub origin: [f64; 3],
    pub direction: [f64; 3],
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct EstimatorFile {
    pub radius: f64,
    pub q: f64,
    pub forward_rays: i64,
    pub camera_rays: i64,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct EffectsFile {
    #[serde(default = "default_orders")]
    pub scattering_orders: OrdersFile,
}

impl Default for EffectsFile {
    fn default() -> Self {
        EffectsFile { scattering_orders: default_orders() }
    }
}

fn default_orders() -> OrdersFile {
    OrdersFile::Count(0)
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(untagged)]
pub(crate) enum OrdersFile {
    Count(i64),
    Word(String),
}
