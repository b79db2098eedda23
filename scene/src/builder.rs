//! Building a [`Scene`] in code, validated exactly as a scene file is.

use crate::error::{FieldError, SceneError};
use crate::file::*;
use crate::model::{Cost, ScatteringOrders, Scene};
use crate::phase::Phase;

/// Builds a [`Scene`] in code. [`SceneBuilder::build`] applies the scene
/// file's validation (`docs/scene-format.md`): the same ranges and the same
/// field-named errors, every invalid value listed.
///
/// Medium, at least one light, camera and estimator must be set; the phase
/// function defaults to isotropic and the scattering orders to 0
/// (uncollided light), as in a scene file.
///
/// ```
/// use mcrt_scene::{Phase, Scene};
///
/// let scene = Scene::builder()
///     .medium(1.0, 0.8)
///     .phase(Phase::HenyeyGreenstein { g: 0.5 })
///     .point_light([1.0, 0.0, 1.0], 1.0)
///     .camera([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
///     .estimator(0.2, 0.5, 20, 4)
///     .build()?;
/// assert_eq!(scene.estimator.camera_rays, 4);
///
/// // An invalid value is named, with its range.
/// let err = Scene::builder()
///     .medium(1.0, 0.8)
///     .point_light([1.0, 0.0, 1.0], 1.0)
///     .camera([0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
///     .estimator(0.2, 1.5, 20, 4)
///     .build()
///     .unwrap_err();
/// assert!(err.to_string().contains("estimator.q = 1.5: must be in (0, 1]"));
/// # Ok::<(), mcrt_scene::SceneError>(())
/// ```
#[derive(Debug, Clone, Default)]
pub struct SceneBuilder {
    medium: Option<(f64, f64)>,
    phase: Option<Phase>,
    lights: Vec<LightFile>,
    camera: Option<([f64; 3], [f64; 3])>,
    estimator: Option<(f64, f64, u64, u64)>,
    orders: Option<ScatteringOrders>,
    cost: Option<Cost>,
}

impl Scene {
    /// A builder for a scene in code (see [`SceneBuilder`]).
    pub fn builder() -> SceneBuilder {
        SceneBuilder::default()
    }

    /// This scene checked as a scene file is: a `Scene` assembled by hand
    /// (its fields are public) passes the same validation before use.
    /// Returns the scene normalised (unit directions).
    ///
    /// ```
    /// use mcrt_scene::Scene;
    /// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/point-isotropic.toml"))?;
    /// let mut scene = Scene::from_toml_str(&text)?;
    /// scene.estimator.q = 0.0;
    /// let err = scene.validated().unwrap_err();
    /// assert!(err.to_string().contains("estimator.q = 0"));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn validated(&self) -> Result<Scene, SceneError> {
        Scene::from_file(self.to_file())
    }
}

impl SceneBuilder {
    /// The homogeneous medium: extinction coefficient σ_ext (1/length, > 0)
    /// and single-scattering albedo (in [0, 1]).
    pub fn medium(mut self, sigma_ext: f64, albedo: f64) -> Self {
        self.medium = Some((sigma_ext, albedo));
        self
    }

    /// The phase function (default: isotropic).
    pub fn phase(mut self, phase: Phase) -> Self {
        self.phase = Some(phase);
        self
    }

    /// Adds an isotropic point light at `position` emitting `flux` (> 0).
    pub fn point_light(mut self, position: [f64; 3], flux: f64) -> Self {
        self.lights.push(LightFile {
            kind: "point".into(),
            position: Some(position.into()),
            center: None,
            direction: None,
            radius: None,
            flux,
        });
        self
    }

    /// Adds a collimated beam: a disk of `radius` at `center`, perpendicular
    /// to `direction` (any non-zero length; normalised), emitting `flux`
    /// uniformly over the disk along `direction`.
    pub fn beam(mut self, center: [f64; 3], direction: [f64; 3], radius: f64, flux: f64) -> Self {
        self.lights.push(LightFile {
            kind: "beam".into(),
            position: None,
            center: Some(center.into()),
            direction: Some(direction.into()),
            radius: Some(radius),
            flux,
        });
        self
    }

    /// The pixel's camera ray: `origin` and view `direction` u (non-zero;
    /// normalised).
    pub fn camera(mut self, origin: [f64; 3], direction: [f64; 3]) -> Self {
        self.camera = Some((origin, direction));
        self
    }

    /// The estimator's parameters: sphere radius R (> 0), extinction
    /// probability per sub-step q (in (0, 1]), forward rays N_F and camera
    /// rays N_B per iteration (≥ 1).
    pub fn estimator(mut self, radius: f64, q: f64, forward_rays: u64, camera_rays: u64) -> Self {
        self.estimator = Some((radius, q, forward_rays, camera_rays));
        self
    }

    /// How many scatterings are simulated (default `Limited(0)`: uncollided
    /// light only).
    pub fn scattering_orders(mut self, orders: ScatteringOrders) -> Self {
        self.orders = Some(orders);
        self
    }

    /// The renderer's per-operation costs (the `[cost]` table), used only
    /// to choose parameters.
    ///
    /// ```
    /// use mcrt_scene::{Cost, Scene};
    /// // trial, forward ray, camera ray, segment, sphere, sort, search, hit, HG (ns; `COST_KEYS`)
    /// let cost = Cost { ns: [900.0, 40.0, 2000.0, 30.0, 8.0, 1.5, 2.0, 4.0, 9.0], std_errors: [0.0; 9] };
    /// let scene = Scene::builder().medium(1.0, 0.8).point_light([1.0, 0.0, 1.0], 1.0)
    ///     .camera([0.0; 3], [0.0, 0.0, 1.0]).estimator(0.05, 0.5, 200, 8).cost(cost).build()?;
    /// assert_eq!(scene.cost, Some(cost));
    /// # Ok::<(), mcrt_scene::SceneError>(())
    /// ```
    pub fn cost(mut self, cost: Cost) -> Self {
        self.cost = Some(cost);
        self
    }

    /// The validated scene, or every invalid or missing value.
    pub fn build(self) -> Result<Scene, SceneError> {
        let mut missing = Vec::new();
        let not_set = |field: &str, how: &str| FieldError {
            field: field.into(),
            value: "(not set)".into(),
            allowed: format!("set with SceneBuilder::{how}"),
        };
        if self.medium.is_none() {
            missing.push(not_set("medium", "medium"));
        }
        if self.camera.is_none() {
            missing.push(not_set("camera", "camera"));
        }
        let count = |field: &str, n: u64, errors: &mut Vec<FieldError>| {
            i64::try_from(n).unwrap_or_else(|_| {
                errors.push(FieldError {
                    field: field.into(),
                    value: n.to_string(),
                    allowed: format!("an integer in [1, {}]", i64::MAX),
                });
                1
            })
        };
        let estimator = match self.estimator {
            Some((radius, q, n_f, n_b)) => EstimatorFile {
                radius,
                q,
                forward_rays: count("estimator.forward_rays", n_f, &mut missing),
                camera_rays: count("estimator.camera_rays", n_b, &mut missing),
            },
            None => {
                missing.push(not_set("estimator", "estimator"));
                EstimatorFile { radius: 1.0, q: 1.0, forward_rays: 1, camera_rays: 1 }
            }
        };
        let (sigma_ext, albedo) = self.medium.unwrap_or((1.0, 1.0));
        let phase = match self.phase.unwrap_or(Phase::Isotropic) {
            Phase::Isotropic => PhaseFile { kind: "isotropic".into(), g: None },
            Phase::HenyeyGreenstein { g } => PhaseFile { kind: "henyey-greenstein".into(), g: Some(g) },
        };
        let (origin, direction) = self.camera.unwrap_or(([0.0; 3], [0.0, 0.0, 1.0]));
        let scattering_orders = match self.orders.unwrap_or(ScatteringOrders::Limited(0)) {
            ScatteringOrders::Limited(n) => OrdersFile::Count(n as i64),
            ScatteringOrders::All => OrdersFile::Word("all".into()),
        };
        let file = SceneFile {
            medium: MediumFile { sigma_ext, albedo, phase },
            lights: self.lights,
            camera: CameraFile { origin: origin.into(), direction: direction.into() },
            estimator,
            effects: EffectsFile { scattering_orders },
            cost: self.cost.map(CostFile::from),
        };
        match Scene::from_file(file) {
            Ok(scene) if missing.is_empty() => Ok(scene),
            Ok(_) => Err(SceneError::Invalid(missing)),
            Err(SceneError::Invalid(mut errors)) => {
                missing.append(&mut errors);
                Err(SceneError::Invalid(missing))
            }
            Err(other) => Err(other),
        }
    }
}
