//! The validated scene. Every value here is in range; construct it with
//! [`Scene::from_toml_str`] or [`Scene::builder`], read it with the
//! accessors (`access.rs`).

use crate::phase::Phase;
use glam::DVec3;

/// A validated scene: one medium filling space, lights, one pixel's camera ray,
/// the estimator's parameters, and the effects to simulate.
///
/// Read it with the accessors ([`Scene::medium`], [`Scene::lights`],
/// [`Scene::camera`], [`Scene::estimator`], [`Scene::effects`],
/// [`Scene::scattering_orders`], [`Scene::cost`]); the fields stay public for
/// existing code, and a scene changed through them is checked again by
/// [`Scene::validated`].
///
/// ```
/// // A renderer reads a scene file and sets up its own parameters.
/// use mcrt_scene::Scene;
/// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/point-isotropic-order1.toml"))?;
/// let scene = Scene::from_toml_str(&text)?;
/// let sigma_t = scene.medium().sigma_ext();
/// let n_lights = scene.lights().len();
/// let eye = (scene.camera().origin(), scene.camera().direction());
/// let (r, n_f) = (scene.estimator().radius(), scene.estimator().forward_rays());
/// let max_bounces = scene.scattering_orders().limit();
/// assert_eq!((sigma_t, n_lights, r, n_f, max_bounces), (1.0, 1, 0.01, 200, Some(1)));
/// assert_eq!(eye.1.z, 1.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// The medium filling space.
    pub medium: Medium,
    /// The lights (at least one).
    pub lights: Vec<Light>,
    /// The pixel's camera ray.
    pub camera: Camera,
    /// The estimator's parameters R, q, N_F, N_B.
    pub estimator: Estimator,
    /// Which effects are simulated.
    pub effects: Effects,
    /// A renderer's per-operation costs (`[cost]`), for choosing parameters
    /// (`mcrt-noise optimize`); the oracle and the tracer ignore them.
    pub cost: Option<Cost>,
}

/// The keys of a `[cost]` table, in the order of [`Cost::ns`]: the fixed
/// cost of an iteration, per forward ray, per camera ray, per forward
/// segment, per integration sphere, per unit of S log₂ S for sorting the S
/// spheres of an iteration, per searching segment and unit of log₂(1 + S),
/// per hit, and per hit in a Henyey–Greenstein medium (its phase function evaluated).
pub const COST_KEYS: [&str; 9] = [
    "trial_ns",
    "forward_ray_ns",
    "camera_ray_ns",
    "segment_ns",
    "sphere_ns",
    "sort_ns",
    "search_ns",
    "hit_ns",
    "hg_ns",
];

/// Per-operation costs of one iteration in nanoseconds (`[cost]`, every key
/// of [`COST_KEYS`] required; `mcrt-noise calibrate` prints such a table),
/// each in [0, 1e12], and optionally their standard errors (`std_errors`,
/// as a calibration gives them).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cost {
    /// The costs in the order of [`COST_KEYS`].
    pub ns: [f64; 9],
    /// Their standard errors (zeros: given by hand).
    pub std_errors: [f64; 9],
}

impl Cost {
    /// The cost named `key` (one of [`COST_KEYS`]).
    pub fn get(&self, key: &str) -> Option<f64> {
        COST_KEYS.iter().position(|k| *k == key).map(|i| self.ns[i])
    }
}

/// Homogeneous medium. Units: 1/length for the coefficients.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Medium {
    /// Extinction coefficient σ_ext > 0.
    pub sigma_ext: f64,
    /// Single-scattering albedo σ_sc/σ_ext ∈ [0, 1].
    pub albedo: f64,
    /// Phase function.
    pub phase: Phase,
}

impl Medium {
    /// Scattering coefficient σ_sc = albedo · σ_ext.
    pub fn sigma_sc(&self) -> f64 {
        self.albedo * self.sigma_ext
    }
}

/// A light source. Flux is the total power it emits (arbitrary power unit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// Isotropic point light.
    Point {
        /// Position.
        position: DVec3,
        /// Total flux 𝓕 (> 0).
        flux: f64,
    },
    /// Collimated beam of uniform irradiance leaving a disk of `radius` at
    /// `center`, perpendicular to the unit vector `direction`, along it.
    Beam {
        /// Centre of the emitting disk.
        center: DVec3,
        /// Unit direction of travel (normal of the disk).
        direction: DVec3,
        /// Disk radius (> 0).
        radius: f64,
        /// Total flux 𝓕 (> 0).
        flux: f64,
    },
}

impl Light {
    /// Total flux emitted by this light.
    pub fn flux(&self) -> f64 {
        match *self {
            Light::Point { flux, .. } | Light::Beam { flux, .. } => flux,
        }
    }
}

/// The camera ray of the pixel (zero footprint): origin and unit direction u.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Origin of the camera ray.
    pub origin: DVec3,
    /// Unit view direction u (the camera looks along +u).
    pub direction: DVec3,
}

/// Parameters of the multiple-integration-spheres estimator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimator {
    /// Integration sphere radius R > 0.
    pub radius: f64,
    /// Extinction probability per sub-step q ∈ (0, 1].
    pub q: f64,
    /// Forward rays per iteration N_F ≥ 1.
    pub forward_rays: u64,
    /// Camera rays through the pixel per iteration N_B ≥ 1.
    pub camera_rays: u64,
}

/// Which light-transport effects are simulated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Effects {
    /// How many scatterings a light path may have.
    pub scattering_orders: ScatteringOrders,
}

/// Forward segments after more scatterings than this are not simulated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScatteringOrders {
    /// At most this many scatterings (0: uncollided light only).
    Limited(u32),
    /// No limit.
    All,
}

impl ScatteringOrders {
    /// As a scene file writes it (`effects.scattering_orders`): `"all"`
    /// quoted, a number bare; for messages that name the field's value.
    ///
    /// ```
    /// use mcrt_scene::ScatteringOrders;
    /// assert_eq!(ScatteringOrders::All.as_toml(), "\"all\"");
    /// assert_eq!(ScatteringOrders::Limited(3).as_toml(), "3");
    /// ```
    pub fn as_toml(&self) -> String {
        match self {
            ScatteringOrders::Limited(n) => n.to_string(),
            ScatteringOrders::All => "\"all\"".into(),
        }
    }
}

/// `all` or the number, unquoted (what a report's field holds).
///
/// ```
/// use mcrt_scene::ScatteringOrders;
/// assert_eq!(ScatteringOrders::All.to_string(), "all");
/// assert_eq!(ScatteringOrders::Limited(2).to_string(), "2");
/// ```
impl std::fmt::Display for ScatteringOrders {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ScatteringOrders::Limited(n) => write!(f, "{n}"),
            ScatteringOrders::All => f.write_str("all"),
        }
    }
}

impl Scene {
    /// Total flux 𝓕 of all lights (paper eq. (5)).
    pub fn total_flux(&self) -> f64 {
        self.lights.iter().map(Light::flux).sum()
    }
}
