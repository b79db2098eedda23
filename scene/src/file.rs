//! The scene file as written: a serde image of the TOML with no validation.
//!
//! Unknown keys are rejected here (`deny_unknown_fields`). Numbers that have a
//! range are read in a wider type (`i64`, `f64`) so that the validator, not the
//! decoder, reports them with the field name and the allowed range.

use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::{Deserialize, Serialize, Serializer};
use std::fmt;

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SceneFile {
    pub medium: MediumFile,
    pub lights: Vec<LightFile>,
    pub camera: CameraFile,
    pub estimator: EstimatorFile,
    #[serde(default)]
    pub effects: EffectsFile,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cost: Option<CostFile>,
}

/// A file holding a `[cost]` table alone (`Cost::from_toml_str`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct CostOnlyFile {
    pub cost: CostFile,
}

/// `[cost]`: a renderer's per-operation costs in nanoseconds (`Cost`,
/// keys `COST_KEYS`).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct CostFile {
    pub trial_ns: f64,
    pub forward_ray_ns: f64,
    pub camera_ray_ns: f64,
    pub segment_ns: f64,
    pub sphere_ns: f64,
    pub sort_ns: f64,
    pub search_ns: f64,
    pub hit_ns: f64,
    pub hg_ns: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub std_errors: Option<Vec<f64>>,
}

impl CostFile {
    /// The costs in `COST_KEYS` order.
    pub fn ns(&self) -> [f64; 9] {
        [
            self.trial_ns,
            self.forward_ray_ns,
            self.camera_ray_ns,
            self.segment_ns,
            self.sphere_ns,
            self.sort_ns,
            self.search_ns,
            self.hit_ns,
            self.hg_ns,
        ]
    }

    /// From costs in `COST_KEYS` order.
    pub fn from_ns(ns: [f64; 9], std_errors: Option<Vec<f64>>) -> CostFile {
        CostFile {
            trial_ns: ns[0],
            forward_ray_ns: ns[1],
            camera_ray_ns: ns[2],
            segment_ns: ns[3],
            sphere_ns: ns[4],
            sort_ns: ns[5],
            search_ns: ns[6],
            hit_ns: ns[7],
            hg_ns: ns[8],
            std_errors,
        }
    }
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
    pub position: Option<Triple>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center: Option<Triple>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<Triple>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    pub flux: f64,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct CameraFile {
    pub origin: Triple,
    pub direction: Triple,
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

/// `effects.scattering_orders` as written: an integer, a word, or anything
/// else TOML allows (kept as text), so that the validator names the field
/// and the allowed values for every wrong value.
#[derive(Debug, Clone)]
pub(crate) enum OrdersFile {
    Count(i64),
    Word(String),
    /// A value of another type (float, boolean, an integer beyond i64), as written.
    Other(String),
}

impl Serialize for OrdersFile {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            OrdersFile::Count(n) => s.serialize_i64(*n),
            OrdersFile::Word(w) | OrdersFile::Other(w) => s.serialize_str(w),
        }
    }
}

impl<'de> Deserialize<'de> for OrdersFile {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = OrdersFile;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an integer in [0, 1000000] or \"all\"")
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<OrdersFile, E> {
                Ok(OrdersFile::Count(v))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<OrdersFile, E> {
                Ok(i64::try_from(v).map_or_else(|_| OrdersFile::Other(v.to_string()), OrdersFile::Count))
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<OrdersFile, E> {
                Ok(OrdersFile::Other(format!("{v:?}")))
            }
            fn visit_bool<E: de::Error>(self, v: bool) -> Result<OrdersFile, E> {
                Ok(OrdersFile::Other(v.to_string()))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<OrdersFile, E> {
                Ok(OrdersFile::Word(v.to_string()))
            }
        }
        d.deserialize_any(V)
    }
}

/// Three numbers as written, with how many the file gave: an array of any
/// other length is read (its extra elements counted, not stored) and
/// refused by the validator with the field named.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Triple {
    /// The first three numbers (zeros where fewer were given).
    pub v: [f64; 3],
    /// How many numbers the array held.
    pub len: usize,
}

impl From<[f64; 3]> for Triple {
    fn from(v: [f64; 3]) -> Self {
        Triple { v, len: 3 }
    }
}

impl Serialize for Triple {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.v.serialize(s)
    }
}

impl<'de> Deserialize<'de> for Triple {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Triple;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an array of 3 numbers")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Triple, A::Error> {
                let mut t = Triple { v: [0.0; 3], len: 0 };
                while let Some(x) = seq.next_element::<f64>()? {
                    if let Some(slot) = t.v.get_mut(t.len) {
                        *slot = x;
                    }
                    t.len += 1;
                }
                Ok(t)
            }
        }
        d.deserialize_seq(V)
    }
}
