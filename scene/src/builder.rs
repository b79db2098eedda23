//! Building a [`Scene`] in code, validated exactly as a scene file is.

use crate::error::{FieldError, SceneError};
use crate::file::*;
use crate::model::{Cost, Light, ScatteringOrders, Scene};
use crate::phase::Phase;
use glam::DVec3;

/// Builds a [`Scene`] in code. [`SceneBuilder::build`] applies the scene
/// file's validation (`docs/scene-format.md`): the same ranges and the same
/// field-named errors, every invalid value listed.
///
/// Medium, at least one light, camera and estimator must be set; the phase
/// function defaults to isotropic and the scattering orders to 0
/// (uncollided light), as in a scene file. Each part of a scene file has its
/// method: `[medium]` [`medium`](Self::medium), `[medium.phase]`
/// [`phase`](Self::phase), each `[[lights]]` [`point_light`](Self::point_light),
/// [`beam`](Self::beam) or [`light`](Self::light), `[camera]`
/// [`camera`](Self::camera), `[estimator]` [`estimator`](Self::estimator),
/// `[effects]` [`scattering_orders`](Self::scattering_orders), `[cost]`
/// [`cost`](Self::cost). A [`Scene`]'s accessors give back what each took, so
/// a scene read from a file can be rebuilt, or changed, in code.
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
/// assert_eq!(scene.estimator().camera_rays(), 4);
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
    /// The homogeneous medium: extinction coefficient σ_ext (1/length) in
    /// [1e-10, 1e10] ([`limits::MIN_SIGMA_EXT`](crate::limits::MIN_SIGMA_EXT), [`limits::MAX_SIGMA_EXT`](crate::limits::MAX_SIGMA_EXT))
    /// and single-scattering albedo σ_sc/σ_ext in [0, 1]. Required.
    ///
    /// ```
    /// use mcrt_scene::Scene;
    /// let scene = Scene::builder()
    ///     .medium(2.0, 0.5)
    ///     .point_light([1.0, 0.0, 1.0], 1.0)
    ///     .camera([0.0; 3], [0.0, 0.0, 1.0])
    ///     .estimator(0.01, 0.5, 200, 8)
    ///     .build()?;
    /// assert_eq!(scene.medium().sigma_sc(), 1.0);
    /// assert!(Scene::builder().medium(2.0, 1.5).build().unwrap_err().to_string().contains("medium.albedo = 1.5"));
    /// # Ok::<(), mcrt_scene::SceneError>(())
    /// ```
    pub fn medium(mut self, sigma_ext: f64, albedo: f64) -> Self {
        self.medium = Some((sigma_ext, albedo));
        self
    }

    /// The medium's phase function (default [`Phase::Isotropic`], as a scene
    /// file without `[medium.phase]`). Henyey–Greenstein's g in
    /// [−0.999999, 0.999999] (±[`limits::MAX_ABS_G`](crate::limits::MAX_ABS_G)).
    ///
    /// ```
    /// use mcrt_scene::{Phase, Scene};
    /// let scene = Scene::builder()
    ///     .medium(1.0, 0.8)
    ///     .phase(Phase::HenyeyGreenstein { g: 0.9 })
    ///     .point_light([1.0, 0.0, 1.0], 1.0)
    ///     .camera([0.0; 3], [0.0, 0.0, 1.0])
    ///     .estimator(0.01, 0.5, 200, 8)
    ///     .build()?;
    /// assert_eq!(scene.medium().phase().g(), Some(0.9));
    /// # Ok::<(), mcrt_scene::SceneError>(())
    /// ```
    pub fn phase(mut self, phase: Phase) -> Self {
        self.phase = Some(phase);
        self
    }

    /// Adds an isotropic point light at `position` emitting `flux` in
    /// [1e-10, 1e10] ([`limits::MIN_FLUX`](crate::limits::MIN_FLUX), [`limits::MAX_FLUX`](crate::limits::MAX_FLUX)). Every
    /// coordinate finite with σ_ext·|x| ≤ 1e6
    /// ([`limits::MAX_OPTICAL_COORDINATE`](crate::limits::MAX_OPTICAL_COORDINATE)); σ_ext·|position − camera origin|
    /// ≤ 600 ([`limits::MAX_OPTICAL_DISTANCE`](crate::limits::MAX_OPTICAL_DISTANCE)); not on the camera ray at or in
    /// front of the camera. Call it (or [`beam`](Self::beam),
    /// [`light`](Self::light)) once per light: at least one is required.
    ///
    /// ```
    /// use mcrt_scene::Scene;
    /// let scene = Scene::builder()
    ///     .medium(1.0, 0.8)
    ///     .point_light([1.0, 0.0, 1.0], 1.0)
    ///     .point_light([-1.0, 0.0, 2.0], 3.0)
    ///     .camera([0.0; 3], [0.0, 0.0, 1.0])
    ///     .estimator(0.01, 0.5, 200, 8)
    ///     .build()?;
    /// assert_eq!(scene.lights().len(), 2);
    /// assert_eq!(scene.lights()[1].position().map(|p| p.to_array()), Some([-1.0, 0.0, 2.0]));
    /// assert_eq!(scene.total_flux(), 4.0);
    /// # Ok::<(), mcrt_scene::SceneError>(())
    /// ```
    pub fn point_light(self, position: impl Into<DVec3>, flux: f64) -> Self {
        self.light(Light::Point { position: position.into(), flux })
    }

    /// Adds a collimated beam: a disk of `radius` a at `center`, perpendicular
    /// to `direction`, emitting `flux` uniformly over the disk along
    /// `direction`. `direction` finite and non-zero, of any length
    /// (normalised); σ_ext·a in [1e-10, 1e6] ([`limits::MIN_OPTICAL_BEAM_RADIUS`](crate::limits::MIN_OPTICAL_BEAM_RADIUS),
    /// [`limits::MAX_OPTICAL_COORDINATE`](crate::limits::MAX_OPTICAL_COORDINATE)); `center`'s coordinates finite
    /// with σ_ext·|x| ≤ 1e6; σ_ext × the distance from the camera origin to
    /// the disk ≤ 600 ([`limits::MAX_OPTICAL_DISTANCE`](crate::limits::MAX_OPTICAL_DISTANCE)); `flux` in
    /// [1e-10, 1e10].
    ///
    /// ```
    /// use mcrt_scene::Scene;
    /// let scene = Scene::builder()
    ///     .medium(1.0, 0.8)
    ///     .beam([-2.0, 0.0, 1.0], [3.0, 0.0, 0.0], 0.5, 1.0)
    ///     .camera([0.0; 3], [0.0, 0.0, 1.0])
    ///     .estimator(0.01, 0.5, 200, 8)
    ///     .build()?;
    /// let beam = &scene.lights()[0];
    /// assert!(beam.is_beam());
    /// assert_eq!(beam.direction().map(|d| d.to_array()), Some([1.0, 0.0, 0.0]));
    /// assert_eq!(beam.radius(), Some(0.5));
    /// # Ok::<(), mcrt_scene::SceneError>(())
    /// ```
    pub fn beam(self, center: impl Into<DVec3>, direction: impl Into<DVec3>, radius: f64, flux: f64) -> Self {
        self.light(Light::Beam { center: center.into(), direction: direction.into(), radius, flux })
    }

    /// Adds a light given as a [`Light`] (one of another scene's
    /// [`Scene::lights`], say), with the ranges of
    /// [`point_light`](Self::point_light) and [`beam`](Self::beam) (a beam's
    /// direction is normalised).
    ///
    /// ```
    /// use mcrt_scene::Scene;
    /// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/beam-isotropic.toml"))?;
    /// let scene = Scene::from_toml_str(&text)?;
    /// // The scene's beam beside a point light of our own.
    /// let mut builder = Scene::builder()
    ///     .medium(1.0, 0.8)
    ///     .point_light([1.0, 0.0, 1.0], 1.0)
    ///     .camera([0.0; 3], [0.0, 0.0, 1.0])
    ///     .estimator(0.01, 0.5, 200, 8);
    /// for &light in scene.lights() {
    ///     builder = builder.light(light);
    /// }
    /// let both = builder.build()?;
    /// assert_eq!(both.lights()[1], scene.lights()[0]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn light(mut self, light: Light) -> Self {
        self.lights.push(light.into());
        self
    }

    /// The pixel's camera ray: `origin` (coordinates finite, σ_ext·|x| ≤ 1e6,
    /// [`limits::MAX_OPTICAL_COORDINATE`](crate::limits::MAX_OPTICAL_COORDINATE)) and view direction u (finite,
    /// non-zero, any length: normalised). Required.
    ///
    /// ```
    /// use mcrt_scene::Scene;
    /// let scene = Scene::builder()
    ///     .medium(1.0, 0.8)
    ///     .point_light([1.0, 0.0, 1.0], 1.0)
    ///     .camera([0.0, 0.0, -1.0], [0.0, 0.0, 2.0])
    ///     .estimator(0.01, 0.5, 200, 8)
    ///     .build()?;
    /// assert_eq!(scene.camera().direction().to_array(), [0.0, 0.0, 1.0]);
    /// // Positions and directions are arrays or glam's `DVec3`, as the accessors give them.
    /// let again = Scene::builder()
    ///     .medium(1.0, 0.8)
    ///     .point_light(scene.lights()[0].position().unwrap(), 1.0)
    ///     .camera(scene.camera().origin(), scene.camera().direction())
    ///     .estimator(0.01, 0.5, 200, 8)
    ///     .build()?;
    /// assert_eq!(again, scene);
    /// # Ok::<(), mcrt_scene::SceneError>(())
    /// ```
    pub fn camera(mut self, origin: impl Into<DVec3>, direction: impl Into<DVec3>) -> Self {
        self.camera = Some((origin.into().to_array(), direction.into().to_array()));
        self
    }

    /// The estimator's parameters: sphere radius R with σ_ext·R in
    /// [1e-12, 1e3] ([`limits::MIN_OPTICAL_RADIUS`](crate::limits::MIN_OPTICAL_RADIUS),
    /// [`limits::MAX_OPTICAL_RADIUS`](crate::limits::MAX_OPTICAL_RADIUS)); extinction probability per sub-step q
    /// in [1e-6, 1] ([`limits::MIN_Q`](crate::limits::MIN_Q)); forward rays N_F per iteration, an
    /// integer in [1, 10⁸] ([`limits::MAX_FORWARD_RAYS`](crate::limits::MAX_FORWARD_RAYS)); camera rays N_B per
    /// iteration, an integer in [1, 10⁶] ([`limits::MAX_CAMERA_RAYS`](crate::limits::MAX_CAMERA_RAYS)), with
    /// N_B/q ≤ 10⁷ ([`limits::MAX_SPHERES_PER_ITERATION`](crate::limits::MAX_SPHERES_PER_ITERATION)). Required.
    ///
    /// ```
    /// use mcrt_scene::Scene;
    /// let scene = Scene::builder()
    ///     .medium(1.0, 0.8)
    ///     .point_light([1.0, 0.0, 1.0], 1.0)
    ///     .camera([0.0; 3], [0.0, 0.0, 1.0])
    ///     .estimator(0.05, 0.25, 1000, 4)
    ///     .build()?;
    /// let e = scene.estimator();
    /// assert_eq!((e.radius(), e.q(), e.forward_rays(), e.camera_rays()), (0.05, 0.25, 1000, 4));
    /// # Ok::<(), mcrt_scene::SceneError>(())
    /// ```
    pub fn estimator(mut self, radius: f64, q: f64, forward_rays: u64, camera_rays: u64) -> Self {
        self.estimator = Some((radius, q, forward_rays, camera_rays));
        self
    }

    /// How many scatterings a light path may have (`effects.scattering_orders`):
    /// [`ScatteringOrders::Limited`] with n in [0, 10⁶] ([`limits::MAX_ORDERS`](crate::limits::MAX_ORDERS))
    /// or [`ScatteringOrders::All`]. Default `Limited(0)`: uncollided light
    /// only, as in a scene file.
    ///
    /// ```
    /// use mcrt_scene::{ScatteringOrders, Scene};
    /// let scene = Scene::builder()
    ///     .medium(1.0, 0.8)
    ///     .point_light([1.0, 0.0, 1.0], 1.0)
    ///     .camera([0.0; 3], [0.0, 0.0, 1.0])
    ///     .estimator(0.1, 0.5, 200, 8)
    ///     .scattering_orders(ScatteringOrders::All)
    ///     .build()?;
    /// assert_eq!(scene.scattering_orders(), ScatteringOrders::All);
    /// # Ok::<(), mcrt_scene::SceneError>(())
    /// ```
    pub fn scattering_orders(mut self, orders: ScatteringOrders) -> Self {
        self.orders = Some(orders);
        self
    }

    /// The renderer's per-operation costs (the `[cost]` table), used only
    /// to choose parameters: each cost and standard error in [0, 1e12]
    /// nanoseconds (standard errors all 0: none given, none written).
    /// Optional.
    ///
    /// ```
    /// use mcrt_scene::{Cost, Scene};
    /// // trial, forward ray, camera ray, segment, sphere, sort, search, hit, HG (ns; `COST_KEYS`)
    /// let cost = Cost { ns: [900.0, 40.0, 2000.0, 30.0, 8.0, 1.5, 2.0, 4.0, 9.0], std_errors: [0.0; 9] };
    /// let scene = Scene::builder().medium(1.0, 0.8).point_light([1.0, 0.0, 1.0], 1.0)
    ///     .camera([0.0; 3], [0.0, 0.0, 1.0]).estimator(0.05, 0.5, 200, 8).cost(cost).build()?;
    /// assert_eq!(scene.cost(), Some(&cost));
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
        let phase = self.phase.unwrap_or(Phase::Isotropic).into();
        let (origin, direction) = self.camera.unwrap_or(([0.0; 3], [0.0, 0.0, 1.0]));
        let scattering_orders = self.orders.unwrap_or(ScatteringOrders::Limited(0)).into();
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
