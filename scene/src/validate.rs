//! Parsing and validation: `SceneFile` (as written) ⇄ `Scene` (validated).

use crate::error::{FieldError, SceneError};
use crate::file::*;
use crate::model::*;
use crate::phase::Phase;
use glam::DVec3;

/// Largest number of scattering orders accepted as a number (beyond, use "all").
const MAX_ORDERS: i64 = 1_000_000;

/// Relative distance below which a point light counts as lying on the camera
/// ray: |rel × u| ≤ ON_RAY_REL · |rel|, a few ulps of the cross product's rounding.
const ON_RAY_REL: f64 = 16.0 * f64::EPSILON;

/// Collects field errors while converting.
#[derive(Default)]
struct Checker {
    errors: Vec<FieldError>,
}

impl Checker {
    fn push(&mut self, field: &str, value: impl std::fmt::Display, allowed: &str) {
        self.errors.push(FieldError { field: field.into(), value: value.to_string(), allowed: allowed.into() });
    }

    fn finite(&mut self, field: &str, v: f64) -> bool {
        if !v.is_finite() {
            self.push(field, v, "a finite number");
        }
        v.is_finite()
    }

    /// `v` finite and `lo < v` (open) or `lo <= v` (closed), and `v <= hi` / `< hi`.
    fn range(&mut self, field: &str, v: f64, lo: (f64, bool), hi: (f64, bool), allowed: &str) -> f64 {
        let ok = v.is_finite() && if lo.1 { v >= lo.0 } else { v > lo.0 } && if hi.1 { v <= hi.0 } else { v < hi.0 };
        if !ok {
            self.push(field, v, allowed);
        }
        v
    }

    fn vector(&mut self, field: &str, v: [f64; 3]) -> DVec3 {
        for (i, c) in v.iter().enumerate() {
            self.finite(&format!("{field}[{i}]"), *c);
        }
        DVec3::from_array(v)
    }

    /// A direction: finite, non-zero; returned normalised. Normalising is
    /// idempotent (a vector already of unit length to 4 ulps is kept as is), so
    /// a scene round-trips bit for bit.
    fn direction(&mut self, field: &str, v: [f64; 3]) -> DVec3 {
        let d = self.vector(field, v);
        let len = d.length();
        if !d.is_finite() {
            return DVec3::Z;
        }
        if len == 0.0 || !len.is_normal() {
            self.push(field, format!("{v:?}"), "a non-zero vector");
            return DVec3::Z;
        }
        if (len - 1.0).abs() <= 4.0 * f64::EPSILON {
            d
        } else {
            d / len
        }
    }

    fn count(&mut self, field: &str, v: i64) -> u64 {
        if v < 1 {
            self.push(field, v, "an integer >= 1");
            return 1;
        }
        v as u64
    }
}

impl Scene {
    /// Parses and validates a scene from TOML text.
    pub fn from_toml_str(text: &str) -> Result<Scene, SceneError> {
        let file: SceneFile = toml::from_str(text).map_err(|e| SceneError::Parse(e.to_string()))?;
        Scene::from_file(file)
    }

    /// The scene as normalised TOML (unit directions, defaults filled in).
    /// `Scene::from_toml_str(&s.to_toml_string())` gives back `s` exactly.
    pub fn to_toml_string(&self) -> String {
        toml::to_string(&self.to_file()).expect("a validated scene always serialises")
    }

    pub(crate) fn from_file(file: SceneFile) -> Result<Scene, SceneError> {
        let mut c = Checker::default();
        let medium = medium(&mut c, &file.medium);
        let camera = Camera {
            origin: c.vector("camera.origin", file.camera.origin),
            direction: c.direction("camera.direction", file.camera.direction),
        };
        if file.lights.is_empty() {
            c.push("lights", "[]", "at least one light");
        }
        let mut lights = Vec::with_capacity(file.lights.len());
        for (i, l) in file.lights.iter().enumerate() {
            if let Some(l) = light(&mut c, &format!("lights[{i}]"), l) {
                check_light_off_camera_ray(&mut c, i, &l, &camera);
                lights.push(l);
            }
        }
        let e = &file.estimator;
        let estimator = Estimator {
            radius: c.range("estimator.radius", e.radius, (0.0, false), (f64::INFINITY, false), "finite and > 0"),
            q: c.range("estimator.q", e.q, (0.0, false), (1.0, true), "in (0, 1]"),
            forward_rays: c.count("estimator.forward_rays", e.forward_rays),
            camera_rays: c.count("estimator.camera_rays", e.camera_rays),
        };
        let effects = Effects { scattering_orders: orders(&mut c, &file.effects.scattering_orders) };
        if c.errors.is_empty() {
            Ok(Scene { medium, lights, camera, estimator, effects })
        } else {
            Err(SceneError::Invalid(c.errors))
        }
    }

    pub(crate) fn to_file(&self) -> SceneFile {
        let phase = match self.medium.phase {
            Phase::Isotropic => PhaseFile { kind: "isotropic".into(), g: None },
            Phase::HenyeyGreenstein { g } => PhaseFile { kind: "henyey-greenstein".into(), g: Some(g) },
        };
        let lights = self
            .lights
            .iter()
            .map(|l| match *l {
                Light::Point { position, flux } => LightFile {
                    kind: "point".into(),
                    position: Some(position.to_array()),
                    center: None,
                    direction: None,
                    radius: None,
                    flux,
                },
                Light::Beam { center, direction, radius, flux } => LightFile {
                    kind: "beam".into(),
                    position: None,
                    center: Some(center.to_array()),
                    direction: Some(direction.to_array()),
                    radius: Some(radius),
                    flux,
                },
            })
            .collect();
        let orders = match self.effects.scattering_orders {
            ScatteringOrders::Limited(n) => OrdersFile::Count(n as i64),
            ScatteringOrders::All => OrdersFile::Word("all".into()),
        };
        SceneFile {
            medium: MediumFile { sigma_ext: self.medium.sigma_ext, albedo: self.medium.albedo, phase },
            lights,
            camera: CameraFile { origin: self.camera.origin.to_array(), direction: self.camera.direction.to_array() },
            estimator: EstimatorFile {
                radius: self.estimator.radius,
                q: self.estimator.q,
                forward_rays: self.estimator.forward_rays as i64,
                camera_rays: self.estimator.camera_rays as i64,
            },
            effects: EffectsFile { scattering_orders: orders },
        }
    }
}

fn medium(c: &mut Checker, m: &MediumFile) -> Medium {
    let sigma_ext = c.range("medium.sigma_ext", m.sigma_ext, (0.0, false), (f64::INFINITY, false), "finite and > 0");
    let albedo = c.range("medium.albedo", m.albedo, (0.0, true), (1.0, true), "in [0, 1]");
    let phase = match (m.phase.kind.as_str(), m.phase.g) {
        ("isotropic", None) => Phase::Isotropic,
        ("isotropic", Some(g)) => {
            c.push("medium.phase.g", g, "absent for kind = \"isotropic\"");
            Phase::Isotropic
        }
        ("henyey-greenstein", Some(g)) => {
            Phase::HenyeyGreenstein { g: c.range("medium.phase.g", g, (-1.0, false), (1.0, false), "in (-1, 1)") }
        }
        ("henyey-greenstein", None) => {
            c.push("medium.phase.g", "(missing)", "given, in (-1, 1), for kind = \"henyey-greenstein\"");
            Phase::Isotropic
        }
        (kind, _) => {
            c.push("medium.phase.kind", format!("{kind:?}"), "\"isotropic\" or \"henyey-greenstein\"");
            Phase::Isotropic
        }
    };
    Medium { sigma_ext, albedo, phase }
}

/// The light, or `None` (with an error recorded) when its kind is unknown.
fn light(c: &mut Checker, at: &str, l: &LightFile) -> Option<Light> {
    let flux = c.range(&format!("{at}.flux"), l.flux, (0.0, false), (f64::INFINITY, false), "finite and > 0");
    let forbid = |c: &mut Checker, name: &str, present: bool, kind: &str| {
        if present {
            c.push(&format!("{at}.{name}"), "(given)", &format!("absent for kind = \"{kind}\""));
        }
    };
    let require = |c: &mut Checker, name: &str, present: bool, kind: &str| {
        if !present {
            c.push(&format!("{at}.{name}"), "(missing)", &format!("given for kind = \"{kind}\""));
        }
    };
    match l.kind.as_str() {
        "point" => {
            require(c, "position", l.position.is_some(), "point");
            for (name, present) in
                [("center", l.center.is_some()), ("direction", l.direction.is_some()), ("radius", l.radius.is_some())]
            {
                forbid(c, name, present, "point");
            }
            let position = l.position.map(|p| c.vector(&format!("{at}.position"), p)).unwrap_or(DVec3::ZERO);
            Some(Light::Point { position, flux })
        }
        "beam" => {
            forbid(c, "position", l.position.is_some(), "beam");
            for (name, present) in
                [("center", l.center.is_some()), ("direction", l.direction.is_some()), ("radius", l.radius.is_some())]
            {
                require(c, name, present, "beam");
            }
            let center = l.center.map(|p| c.vector(&format!("{at}.center"), p)).unwrap_or(DVec3::ZERO);
            let direction = l.direction.map(|d| c.direction(&format!("{at}.direction"), d)).unwrap_or(DVec3::Z);
            let radius = l
                .radius
                .map(|r| c.range(&format!("{at}.radius"), r, (0.0, false), (f64::INFINITY, false), "finite and > 0"))
                .unwrap_or(1.0);
            Some(Light::Beam { center, direction, radius, flux })
        }
        kind => {
            c.push(&format!("{at}.kind"), format!("{kind:?}"), "\"point\" or \"beam\"");
            None
        }
    }
}

/// A point light on the camera ray at or in front of the camera makes the mean
/// luminance itself infinite (∫ ds / (s − s₀)² diverges), so no noise exists to
/// estimate. Behind the camera the luminance is finite and the scene is valid.
fn check_light_off_camera_ray(c: &mut Checker, i: usize, light: &Light, camera: &Camera) {
    let Light::Point { position, .. } = *light else { return };
    if !position.is_finite() || !camera.origin.is_finite() || !camera.direction.is_finite() {
        return;
    }
    let rel = position - camera.origin;
    let along = rel.dot(camera.direction);
    let perp = rel.cross(camera.direction).length();
    if along >= 0.0 && perp <= ON_RAY_REL * rel.length() {
        c.push(
            &format!("lights[{i}].position"),
            format!("{:?}", position.to_array()),
            "off the camera ray in front of the camera (a point light on it makes the mean luminance infinite)",
        );
    }
}

fn orders(c: &mut Checker, o: &OrdersFile) -> ScatteringOrders {
    match o {
        OrdersFile::Count(n) if (0..=MAX_ORDERS).contains(n) => ScatteringOrders::Limited(*n as u32),
        OrdersFile::Word(w) if w == "all" => ScatteringOrders::All,
        OrdersFile::Count(n) => {
            c.push("effects.scattering_orders", n, &format!("an integer in [0, {MAX_ORDERS}] or \"all\""));
            ScatteringOrders::All
        }
        OrdersFile::Word(w) => {
            c.push(
                "effects.scattering_orders",
                format!("{w:?}"),
                &format!("an integer in [0, {MAX_ORDERS}] or \"all\""),
            );
            ScatteringOrders::All
        }
    }
}
