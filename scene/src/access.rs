//! Read accessors: the documented way to read a [`Scene`] and its parts
//! (the public fields stay for compatibility). Each gives back what a
//! [`SceneBuilder`](crate::SceneBuilder) method took, validated: directions of
//! unit length, every value in its range. The estimator's carry the paper's
//! names (R, q, N_F, N_B).

use crate::model::{Camera, Cost, Effects, Estimator, Light, Medium, ScatteringOrders, Scene, COST_KEYS};
use crate::phase::Phase;
use glam::DVec3;

impl Scene {
    /// The medium filling space.
    ///
    /// ```
    /// // A renderer sets up its medium from a scene file.
    /// use mcrt_scene::Scene;
    /// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/point-hg-forward.toml"))?;
    /// let scene = Scene::from_toml_str(&text)?;
    /// let medium = scene.medium();
    /// let (sigma_t, sigma_s) = (medium.sigma_ext(), medium.sigma_sc());
    /// let g = medium.phase().g().unwrap_or(0.0);
    /// assert_eq!((sigma_t, sigma_s, g), (1.0, 0.8, 0.9));
    /// assert_eq!(medium.albedo(), 0.8);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn medium(&self) -> &Medium {
        &self.medium
    }

    /// The lights (at least one), in the order of the file's `[[lights]]`.
    ///
    /// ```
    /// // A renderer turns the scene's lights into its own emitters.
    /// use mcrt_scene::Scene;
    /// enum Emitter {
    ///     Point { at: [f64; 3], power: f64 },
    ///     Disk { at: [f64; 3], normal: [f64; 3], radius: f64, power: f64 },
    /// }
    /// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/beam-isotropic.toml"))?;
    /// let scene = Scene::from_toml_str(&text)?;
    /// let emitters: Vec<Emitter> = scene
    ///     .lights()
    ///     .iter()
    ///     .map(|l| match (l.position(), l.center(), l.direction(), l.radius()) {
    ///         (Some(p), ..) => Emitter::Point { at: p.to_array(), power: l.flux() },
    ///         (None, Some(c), Some(d), Some(a)) => {
    ///             Emitter::Disk { at: c.to_array(), normal: d.to_array(), radius: a, power: l.flux() }
    ///         }
    ///         _ => unreachable!("a light is a point light or a beam"),
    ///     })
    ///     .collect();
    /// assert!(matches!(emitters[..], [Emitter::Disk { radius: 0.5, power: 1.0, .. }]));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// The pixel's camera ray.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// The estimator's parameters R, q, N_F, N_B.
    pub fn estimator(&self) -> &Estimator {
        &self.estimator
    }

    /// Which effects are simulated (`[effects]`).
    pub fn effects(&self) -> &Effects {
        &self.effects
    }

    /// How many scatterings a light path may have (`effects.scattering_orders`).
    pub fn scattering_orders(&self) -> ScatteringOrders {
        self.effects.scattering_orders
    }

    /// A renderer's per-operation costs (`[cost]`), if the scene gives them.
    ///
    /// ```
    /// use mcrt_scene::Scene;
    /// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/point-isotropic.toml"))?;
    /// assert!(Scene::from_toml_str(&text)?.cost().is_none());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn cost(&self) -> Option<&Cost> {
        self.cost.as_ref()
    }
}

impl Medium {
    /// Extinction coefficient σ_ext (1/length).
    pub fn sigma_ext(&self) -> f64 {
        self.sigma_ext
    }

    /// Single-scattering albedo σ_sc/σ_ext.
    pub fn albedo(&self) -> f64 {
        self.albedo
    }

    /// The phase function.
    pub fn phase(&self) -> Phase {
        self.phase
    }
}

impl Phase {
    /// Henyey–Greenstein's g (`None` for isotropic; unlike
    /// [`Phase::mean_cosine`], this tells isotropic from HG with g = 0).
    ///
    /// ```
    /// // A renderer picks its phase-function sampler.
    /// use mcrt_scene::{Phase, Scene};
    /// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/point-hg-backward.toml"))?;
    /// let scene = Scene::from_toml_str(&text)?;
    /// let sampler = match scene.medium().phase().g() {
    ///     None => "uniform sphere".to_string(),
    ///     Some(g) => format!("Henyey-Greenstein g = {g}"),
    /// };
    /// assert_eq!(sampler, "Henyey-Greenstein g = -0.5");
    /// assert_eq!(Phase::Isotropic.g(), None);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn g(&self) -> Option<f64> {
        match *self {
            Phase::Isotropic => None,
            Phase::HenyeyGreenstein { g } => Some(g),
        }
    }
}

impl Light {
    /// Whether this is an isotropic point light ([`Light::Point`]).
    pub fn is_point(&self) -> bool {
        matches!(self, Light::Point { .. })
    }

    /// Whether this is a collimated beam ([`Light::Beam`]).
    pub fn is_beam(&self) -> bool {
        matches!(self, Light::Beam { .. })
    }

    /// A point light's position (`None` for a beam).
    ///
    /// ```
    /// use mcrt_scene::{DVec3, Scene};
    /// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/point-isotropic.toml"))?;
    /// let scene = Scene::from_toml_str(&text)?;
    /// let light = &scene.lights()[0];
    /// assert!(light.is_point() && !light.is_beam());
    /// assert_eq!(light.position(), Some(DVec3::new(1.0, 0.0, 1.0)));
    /// assert_eq!((light.center(), light.direction(), light.radius()), (None, None, None));
    /// assert_eq!(light.flux(), 1.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn position(&self) -> Option<DVec3> {
        match *self {
            Light::Point { position, .. } => Some(position),
            Light::Beam { .. } => None,
        }
    }

    /// A beam's disk centre (`None` for a point light).
    pub fn center(&self) -> Option<DVec3> {
        match *self {
            Light::Beam { center, .. } => Some(center),
            Light::Point { .. } => None,
        }
    }

    /// A beam's unit direction of travel, the disk's normal (`None` for a point light).
    pub fn direction(&self) -> Option<DVec3> {
        match *self {
            Light::Beam { direction, .. } => Some(direction),
            Light::Point { .. } => None,
        }
    }

    /// A beam's disk radius a (`None` for a point light).
    pub fn radius(&self) -> Option<f64> {
        match *self {
            Light::Beam { radius, .. } => Some(radius),
            Light::Point { .. } => None,
        }
    }
}

impl Camera {
    /// Origin of the camera ray.
    ///
    /// ```
    /// // A renderer places its pixel's primary ray.
    /// use mcrt_scene::Scene;
    /// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/point-isotropic.toml"))?;
    /// let scene = Scene::from_toml_str(&text)?;
    /// let (o, u) = (scene.camera().origin(), scene.camera().direction());
    /// let point_at = |t: f64| o + t * u;
    /// assert_eq!(point_at(2.0).to_array(), [0.0, 0.0, 2.0]);
    /// assert_eq!(u.length(), 1.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn origin(&self) -> DVec3 {
        self.origin
    }

    /// Unit view direction u (the camera looks along +u).
    pub fn direction(&self) -> DVec3 {
        self.direction
    }
}

impl Estimator {
    /// Integration sphere radius R.
    ///
    /// ```
    /// // A renderer takes its estimator's parameters from the scene.
    /// use mcrt_scene::Scene;
    /// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/point-isotropic.toml"))?;
    /// let e = *Scene::from_toml_str(&text)?.estimator();
    /// let (sphere_radius, p_stop) = (e.radius(), e.q());
    /// let (light_paths, eye_paths) = (e.forward_rays(), e.camera_rays());
    /// assert_eq!((sphere_radius, p_stop, light_paths, eye_paths), (0.01, 0.5, 200, 8));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Extinction probability per sub-step q.
    pub fn q(&self) -> f64 {
        self.q
    }

    /// Forward rays per iteration N_F.
    pub fn forward_rays(&self) -> u64 {
        self.forward_rays
    }

    /// Camera rays through the pixel per iteration N_B.
    pub fn camera_rays(&self) -> u64 {
        self.camera_rays
    }
}

impl Effects {
    /// How many scatterings a light path may have.
    ///
    /// ```
    /// use mcrt_scene::{ScatteringOrders, Scene};
    /// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/point-isotropic-order1.toml"))?;
    /// let scene = Scene::from_toml_str(&text)?;
    /// assert_eq!(scene.effects().scattering_orders(), ScatteringOrders::Limited(1));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn scattering_orders(&self) -> ScatteringOrders {
        self.scattering_orders
    }
}

impl ScatteringOrders {
    /// The most scatterings a path may have (`None`: no limit).
    ///
    /// ```
    /// // A renderer sets its bounce limit.
    /// use mcrt_scene::Scene;
    /// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/point-isotropic-all.toml"))?;
    /// let orders = Scene::from_toml_str(&text)?.scattering_orders();
    /// let max_bounces = orders.limit().unwrap_or(u32::MAX);
    /// assert_eq!(max_bounces, u32::MAX);
    /// assert!(orders.includes(7));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn limit(&self) -> Option<u32> {
        match *self {
            ScatteringOrders::Limited(n) => Some(n),
            ScatteringOrders::All => None,
        }
    }

    /// Whether light after `order` scatterings is simulated.
    pub fn includes(&self, order: u32) -> bool {
        self.limit().is_none_or(|n| order <= n)
    }
}

impl Cost {
    /// The costs in nanoseconds, in the order of [`COST_KEYS`].
    ///
    /// ```
    /// // A renderer reports its per-operation costs by name.
    /// use mcrt_scene::{Cost, COST_KEYS};
    /// let cost = Cost::from_toml_str("[cost]\ntrial_ns = 900\nforward_ray_ns = 40\ncamera_ray_ns = 2000\n\
    ///     segment_ns = 30\nsphere_ns = 8\nsort_ns = 1.5\nsearch_ns = 2\nhit_ns = 4\nhg_ns = 9\n\
    ///     std_errors = [9, 1, 20, 0.5, 0.1, 0.05, 0.1, 0.2, 0.3]")?;
    /// let table: Vec<(&str, f64, f64)> =
    ///     COST_KEYS.iter().zip(cost.ns()).zip(cost.std_errors()).map(|((k, ns), se)| (*k, ns, se)).collect();
    /// assert_eq!(table[3], ("segment_ns", 30.0, 0.5));
    /// assert_eq!(cost.std_error("camera_ray_ns"), Some(20.0));
    /// # Ok::<(), mcrt_scene::SceneError>(())
    /// ```
    pub fn ns(&self) -> [f64; 9] {
        self.ns
    }

    /// Their standard errors, in the same order (all 0: none given).
    pub fn std_errors(&self) -> [f64; 9] {
        self.std_errors
    }

    /// The standard error of the cost named `key` (one of [`COST_KEYS`]).
    pub fn std_error(&self, key: &str) -> Option<f64> {
        COST_KEYS.iter().position(|k| *k == key).map(|i| self.std_errors[i])
    }
}
