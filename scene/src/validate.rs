//! Parsing and validation: `SceneFile` (as written) ⇄ `Scene` (validated).

use crate::error::{FieldError, SceneError};
use crate::file::*;
use crate::limits::*;
use crate::model::*;
use crate::phase::Phase;
use glam::DVec3;

/// Relative distance below which a point light counts as lying on the camera
/// ray: |rel × u| ≤ ON_RAY_REL · |rel|, a few ulps of the cross product's rounding.
const ON_RAY_REL: f64 = 16.0 * f64::EPSILON;

/// Collects field errors while converting.
#[derive(Default)]
struct Checker {
    errors: Vec<FieldError>,
    /// σ_ext when it is valid: lengths are bounded in units of 1/σ_ext.
    sigma: Option<f64>,
}

/// `x` in the shortest form that reads back exactly (`1e-12`, `0.5`).
fn g(x: f64) -> String {
    let plain = format!("{x}");
    let exp = format!("{x:e}");
    if exp.len() < plain.len() {
        exp
    } else {
        plain
    }
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

    /// A positive scale in [lo, hi] (flux, σ_ext): non-positive values get
    /// the plain "finite and > 0", tiny or huge ones the bound and why.
    fn scale(&mut self, field: &str, v: f64, (lo, hi): (f64, f64), why: &str) -> f64 {
        if !(v.is_finite() && v > 0.0) {
            self.push(field, v, &format!("finite and > 0, in [{}, {}]", g(lo), g(hi)));
        } else if !(lo..=hi).contains(&v) {
            self.push(field, g(v), &format!("in [{}, {}] ({why})", g(lo), g(hi)));
        }
        v
    }

    /// A length: finite, > 0, and σ_ext·v in [lo, hi] (checked when σ_ext is valid).
    fn length(&mut self, field: &str, v: f64, (lo, hi): (f64, f64), why: &str) -> f64 {
        if !(v.is_finite() && v > 0.0) {
            self.push(field, v, "finite and > 0");
        } else if let Some(sigma) = self.sigma {
            let optical = sigma * v;
            // A few ulps of slack: σ_ext·R rounds (1e10 · 1e-20 = 9.999999999999999e-11).
            let slack = 1.0 + 4.0 * f64::EPSILON;
            if !(lo / slack..=hi * slack).contains(&optical) {
                self.push(
                    field,
                    g(v),
                    &format!(
                        "finite and > 0 with σ_ext·{} in [{}, {}] (here {}; {why})",
                        field.rsplit('.').next().unwrap_or(field),
                        g(lo),
                        g(hi),
                        g(optical)
                    ),
                );
            }
        }
        v
    }

    /// Exactly three numbers, or `None` (with the error recorded).
    fn triple(&mut self, field: &str, t: Triple) -> Option<[f64; 3]> {
        if t.len != 3 {
            self.push(field, format!("an array of {} numbers", t.len), "an array of exactly 3 numbers [x, y, z]");
            return None;
        }
        Some(t.v)
    }

    /// A point: three finite numbers, each within σ_ext·|x| ≤ MAX_OPTICAL_COORDINATE.
    fn vector(&mut self, field: &str, t: Triple) -> DVec3 {
        let Some(v) = self.triple(field, t) else { return DVec3::ZERO };
        for (i, c) in v.iter().enumerate() {
            let at = format!("{field}[{i}]");
            if self.finite(&at, *c) {
                if let Some(sigma) = self.sigma {
                    if sigma * c.abs() > MAX_OPTICAL_COORDINATE * (1.0 + 4.0 * f64::EPSILON) {
                        self.push(
                            &at,
                            g(*c),
                            &format!(
                                "within σ_ext·|x| ≤ {} (here {}): coordinates are bounded in mean free paths so that \
                                 distances never overflow",
                                g(MAX_OPTICAL_COORDINATE),
                                g(sigma * c.abs())
                            ),
                        );
                    }
                }
            }
        }
        DVec3::from_array(v)
    }

    /// A direction: three finite numbers, not all 0; returned normalised,
    /// overflow- and underflow-safe (scaled by its largest component first).
    /// Normalising is idempotent (a vector already of unit length to 4 ulps
    /// is kept as is), so a scene round-trips bit for bit.
    fn direction(&mut self, field: &str, t: Triple) -> DVec3 {
        let Some(v) = self.triple(field, t) else { return DVec3::Z };
        let mut finite = true;
        for (i, c) in v.iter().enumerate() {
            finite &= self.finite(&format!("{field}[{i}]"), *c);
        }
        if !finite {
            return DVec3::Z;
        }
        let d = DVec3::from_array(v);
        let m = d.abs().max_element();
        if m == 0.0 {
            self.push(field, format!("{v:?}"), "a non-zero vector");
            return DVec3::Z;
        }
        let scaled = d / m;
        let len = scaled.length();
        if (m * len - 1.0).abs() <= 4.0 * f64::EPSILON {
            d
        } else {
            scaled / len
        }
    }

    /// An integer count in [1, max].
    fn count(&mut self, field: &str, v: i64, max: i64, why: &str) -> u64 {
        if v < 1 {
            self.push(field, v, "an integer >= 1");
            return 1;
        }
        if v > max {
            self.push(field, v, &format!("an integer in [1, {max}] ({why})"));
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
        let camera_ok = !c.errors.iter().any(|e| e.field.starts_with("camera."));
        let mut lights = Vec::with_capacity(file.lights.len());
        for (i, l) in file.lights.iter().enumerate() {
            let errors = c.errors.len();
            if let Some(l) = light(&mut c, &format!("lights[{i}]"), l) {
                let at = format!("lights[{i}].position");
                if !c.errors[errors..].iter().any(|e| e.field.starts_with(&at)) {
                    check_light_off_camera_ray(&mut c, i, &l, &camera);
                }
                if camera_ok && c.errors.len() == errors {
                    check_optical_distance(&mut c, i, &l, &camera);
                }
                lights.push(l);
            }
        }
        let estimator = estimator(&mut c, &file.estimator);
        let effects = Effects { scattering_orders: orders(&mut c, &file.effects.scattering_orders) };
        let cost = file.cost.map(|k| cost(&mut c, &k));
        if c.errors.is_empty() {
            Ok(Scene { medium, lights, camera, estimator, effects, cost })
        } else {
            Err(SceneError::Invalid(c.errors))
        }
    }

    pub(crate) fn to_file(&self) -> SceneFile {
        SceneFile {
            medium: MediumFile {
                sigma_ext: self.medium.sigma_ext,
                albedo: self.medium.albedo,
                phase: self.medium.phase.into(),
            },
            lights: self.lights.iter().map(|&l| l.into()).collect(),
            camera: CameraFile {
                origin: self.camera.origin.to_array().into(),
                direction: self.camera.direction.to_array().into(),
            },
            estimator: EstimatorFile {
                radius: self.estimator.radius,
                q: self.estimator.q,
                forward_rays: self.estimator.forward_rays as i64,
                camera_rays: self.estimator.camera_rays as i64,
            },
            effects: EffectsFile { scattering_orders: self.effects.scattering_orders.into() },
            cost: self.cost.map(CostFile::from),
        }
    }
}

impl From<Phase> for PhaseFile {
    fn from(phase: Phase) -> PhaseFile {
        match phase {
            Phase::Isotropic => PhaseFile { kind: "isotropic".into(), g: None },
            Phase::HenyeyGreenstein { g } => PhaseFile { kind: "henyey-greenstein".into(), g: Some(g) },
        }
    }
}

impl From<Light> for LightFile {
    fn from(light: Light) -> LightFile {
        match light {
            Light::Point { position, flux } => LightFile {
                kind: "point".into(),
                position: Some(position.to_array().into()),
                center: None,
                direction: None,
                radius: None,
                flux,
            },
            Light::Beam { center, direction, radius, flux } => LightFile {
                kind: "beam".into(),
                position: None,
                center: Some(center.to_array().into()),
                direction: Some(direction.to_array().into()),
                radius: Some(radius),
                flux,
            },
        }
    }
}

impl From<ScatteringOrders> for OrdersFile {
    fn from(orders: ScatteringOrders) -> OrdersFile {
        match orders {
            ScatteringOrders::Limited(n) => OrdersFile::Count(i64::from(n)),
            ScatteringOrders::All => OrdersFile::Word("all".into()),
        }
    }
}

fn medium(c: &mut Checker, m: &MediumFile) -> Medium {
    let sigma_ext = c.scale(
        "medium.sigma_ext",
        m.sigma_ext,
        (MIN_SIGMA_EXT, MAX_SIGMA_EXT),
        "1/length: choose the length unit to bring it into range; outside it L ∝ 𝓕σ² overflows or underflows f64",
    );
    if sigma_ext.is_finite() && (MIN_SIGMA_EXT..=MAX_SIGMA_EXT).contains(&sigma_ext) {
        c.sigma = Some(sigma_ext);
    }
    let albedo = c.range("medium.albedo", m.albedo, (0.0, true), (1.0, true), "in [0, 1]");
    let phase = match (m.phase.kind.as_str(), m.phase.g) {
        ("isotropic", None) => Phase::Isotropic,
        ("isotropic", Some(g)) => {
            c.push("medium.phase.g", g, "absent for kind = \"isotropic\"");
            Phase::Isotropic
        }
        ("henyey-greenstein", Some(g)) => {
            // One message for every g outside the bound, NaN and ±1 included.
            if g.is_nan() || g.abs() > MAX_ABS_G {
                c.push(
                    "medium.phase.g",
                    g,
                    &format!(
                        "in [-{MAX_ABS_G}, {MAX_ABS_G}] (f peaks at (1 + |g|)/(4π(1 − |g|)²), 1.6e11 at the bound: \
                         closer to ±1 a single hit's contribution overflows the tracer's moments)"
                    ),
                );
            }
            Phase::HenyeyGreenstein { g }
        }
        ("henyey-greenstein", None) => {
            c.push(
                "medium.phase.g",
                "(missing)",
                &format!("given, in [-{MAX_ABS_G}, {MAX_ABS_G}], for kind = \"henyey-greenstein\""),
            );
            Phase::Isotropic
        }
        (kind, _) => {
            c.push("medium.phase.kind", format!("{kind:?}"), "\"isotropic\" or \"henyey-greenstein\"");
            Phase::Isotropic
        }
    };
    Medium { sigma_ext, albedo, phase }
}

fn estimator(c: &mut Checker, e: &EstimatorFile) -> Estimator {
    let radius = c.length(
        "estimator.radius",
        e.radius,
        (MIN_OPTICAL_RADIUS, MAX_OPTICAL_RADIUS),
        "R in mean free paths; a hit contributes 1/(πR²)",
    );
    let q = c.range("estimator.q", e.q, (0.0, false), (1.0, true), "in (0, 1]");
    if q > 0.0 && q < MIN_Q {
        c.push(
            "estimator.q",
            g(q),
            &format!(
                "at least {} (a camera ray places on average 1/q integration spheres, stored by the tracer: at most \
                 {} per camera ray; q = {} would place {})",
                g(MIN_Q),
                g(1.0 / MIN_Q),
                g(q),
                g(1.0 / q)
            ),
        );
    }
    let forward_rays = c.count(
        "estimator.forward_rays",
        e.forward_rays,
        MAX_FORWARD_RAYS,
        "one iteration traces N_F forward rays: bounded work per iteration",
    );
    let camera_rays = c.count(
        "estimator.camera_rays",
        e.camera_rays,
        MAX_CAMERA_RAYS,
        "one iteration stores the spheres of all N_B camera rays",
    );
    let spheres = camera_rays as f64 / q;
    if (MIN_Q..=1.0).contains(&q) && spheres > MAX_SPHERES_PER_ITERATION {
        c.push(
            "estimator.camera_rays / estimator.q",
            format!("{camera_rays} / {} = {}", g(q), g(spheres)),
            &format!(
                "at most {} (the expected number of integration spheres of one iteration, all stored at once, 8 \
                 bytes each)",
                g(MAX_SPHERES_PER_ITERATION)
            ),
        );
    }
    Estimator { radius, q, forward_rays, camera_rays }
}

/// The light, or `None` (with an error recorded) when its kind is unknown.
fn light(c: &mut Checker, at: &str, l: &LightFile) -> Option<Light> {
    let flux = c.scale(
        &format!("{at}.flux"),
        l.flux,
        (MIN_FLUX, MAX_FLUX),
        "a power in any unit: rescale all fluxes together; outside it a trial's L⁴ overflows or L underflows f64",
    );
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
                .map(|r| {
                    c.length(
                        &format!("{at}.radius"),
                        r,
                        (MIN_OPTICAL_BEAM_RADIUS, MAX_OPTICAL_COORDINATE),
                        "the disk's irradiance is 𝓕/(πa²)",
                    )
                })
                .unwrap_or(1.0);
            Some(Light::Beam { center, direction, radius, flux })
        }
        kind => {
            c.push(&format!("{at}.kind"), format!("{kind:?}"), "\"point\" or \"beam\"");
            None
        }
    }
}

/// σ_ext × the distance from the camera origin to the light's nearest point
/// (the point light; the nearest point of a beam's disk): every path from the
/// light via the camera ray to the camera is at least this long, so beyond
/// [`MAX_OPTICAL_DISTANCE`] the light underflows f64 (`limits`).
fn check_optical_distance(c: &mut Checker, i: usize, light: &Light, camera: &Camera) {
    let Some(sigma) = c.sigma else { return };
    let (field, distance) = match *light {
        Light::Point { position, .. } => ("position", (position - camera.origin).length()),
        Light::Beam { center, direction, radius, .. } => {
            let rel = camera.origin - center;
            let along = rel.dot(direction);
            let across = (rel - direction * along).length();
            ("center", along.hypot((across - radius).max(0.0)))
        }
    };
    let tau = sigma * distance;
    if tau > MAX_OPTICAL_DISTANCE {
        let to = if field == "center" { "the camera to the nearest point of the beam's disk" } else { "the camera" };
        c.push(
            &format!("lights[{i}].{field}"),
            format!(
                "{:?}",
                match *light {
                    Light::Point { position, .. } => position.to_array(),
                    Light::Beam { center, .. } => center.to_array(),
                }
            ),
            &format!(
                "at an optical distance σ_ext·r ≤ {} from {to} (here {}): every path of its light to the camera is \
                 attenuated by e^(-{}) or more, so its light underflows f64",
                g(MAX_OPTICAL_DISTANCE),
                if tau < 1e6 { format!("{tau:.1}") } else { g(tau) },
                g(tau.floor())
            ),
        );
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
    // Scaled by its largest component, so that no square overflows (at
    // |origin| = 1e155 the plain lengths were inf and inf ≤ inf put every
    // light "on the camera ray"). The difference itself cannot overflow:
    // coordinates beyond the bound are reported on their own.
    let rel = position - camera.origin;
    let scale = rel.abs().max_element();
    if !scale.is_finite() {
        return;
    }
    let rel = if scale > 0.0 { rel / scale } else { rel };
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

impl Cost {
    /// A file holding only a `[cost]` table (as `mcrt-noise calibrate --out`
    /// writes it), with the checks of a scene's `[cost]` table.
    ///
    /// ```
    /// let k = mcrt_scene::Cost::from_toml_str("[cost]\ntrial_ns = 900\nforward_ray_ns = 40\n\
    ///     camera_ray_ns = 2000\nsegment_ns = 30\nsphere_ns = 8\nsort_ns = 1.5\nsearch_ns = 2\nhit_ns = 4\nhg_ns = 9\n")?;
    /// assert_eq!(k.get("segment_ns"), Some(30.0));
    /// assert!(mcrt_scene::Cost::from_toml_str("[cost]\ntrial_ns = -1").is_err());
    /// # Ok::<(), mcrt_scene::SceneError>(())
    /// ```
    pub fn from_toml_str(text: &str) -> Result<Cost, SceneError> {
        let file: CostOnlyFile = toml::from_str(text).map_err(|e| SceneError::Parse(e.to_string()))?;
        let mut c = Checker::default();
        let k = cost(&mut c, &file.cost);
        if c.errors.is_empty() {
            Ok(k)
        } else {
            Err(SceneError::Invalid(c.errors))
        }
    }
}

impl From<Cost> for CostFile {
    fn from(k: Cost) -> CostFile {
        CostFile::from_ns(k.ns, (k.std_errors != [0.0; 9]).then(|| k.std_errors.to_vec()))
    }
}

/// `[cost]`: every cost and standard error a time in nanoseconds in [0, 1e12].
fn cost(c: &mut Checker, k: &CostFile) -> Cost {
    let allowed = "in [0, 1e12] (nanoseconds)";
    let ns = k.ns();
    for (key, v) in COST_KEYS.iter().zip(ns) {
        c.range(&format!("cost.{key}"), v, (0.0, true), (1e12, true), allowed);
    }
    let mut std_errors = [0.0; 9];
    match &k.std_errors {
        None => {}
        Some(e) if e.len() == 9 => {
            for (i, v) in e.iter().enumerate() {
                std_errors[i] = c.range("cost.std_errors", *v, (0.0, true), (1e12, true), allowed);
            }
        }
        Some(e) => c.push(
            "cost.std_errors",
            format!("{} numbers", e.len()),
            "9 numbers, one per cost, in the order of the keys",
        ),
    }
    Cost { ns, std_errors }
}

fn orders(c: &mut Checker, o: &OrdersFile) -> ScatteringOrders {
    let allowed = format!("an integer in [0, {MAX_ORDERS}] or \"all\"");
    match o {
        OrdersFile::Count(n) if (0..=MAX_ORDERS).contains(n) => ScatteringOrders::Limited(*n as u32),
        OrdersFile::Word(w) if w == "all" => ScatteringOrders::All,
        OrdersFile::Count(n) => {
            c.push("effects.scattering_orders", n, &allowed);
            ScatteringOrders::All
        }
        OrdersFile::Word(w) => {
            c.push("effects.scattering_orders", format!("{w:?}"), &allowed);
            ScatteringOrders::All
        }
        OrdersFile::Other(v) => {
            c.push("effects.scattering_orders", v, &allowed);
            ScatteringOrders::All
        }
    }
}
