//! `Scene`: from a file, from TOML, or from keywords; every field readable.

use crate::errors::{scene_error, SceneError};
use mcrt_noise::{Phase, ScatteringOrders, Scene as RustScene};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// A scene: medium, lights, camera, estimator, scattering orders.
///
/// Made by `Scene.from_file`, `Scene.from_toml` or the keyword builder
/// `Scene.build`; all three validate alike and name every invalid value.
#[pyclass(module = "mcrt_noise", frozen)]
#[derive(Clone)]
pub struct Scene {
    pub(crate) inner: RustScene,
}

fn shape_error(name: &str, shape: &str, e: PyErr) -> PyErr {
    Python::attach(|py| SceneError::new_err(format!("{name}: {}: must be {shape}", e.value(py))))
}

/// A keyword's sequence of lights (None: none).
fn items<'py>(value: Option<&Bound<'py, PyAny>>, name: &str) -> PyResult<Vec<Bound<'py, PyAny>>> {
    let Some(value) = value else { return Ok(Vec::new()) };
    if value.is_instance_of::<pyo3::types::PyString>() {
        return Err(SceneError::new_err(format!("{name} = {value}: must be a sequence of lights")));
    }
    value.try_iter().and_then(|it| it.collect()).map_err(|e| shape_error(name, "a sequence of lights", e))
}

/// A 3-vector of real numbers.
fn vector(value: &Bound<'_, PyAny>, name: &str) -> PyResult<[f64; 3]> {
    value.extract::<[f64; 3]>().map_err(|e| shape_error(name, "three real numbers (x, y, z)", e))
}

/// A count >= 1 (`forward_rays`, `camera_rays`); a bool is not a count.
fn count(value: &Bound<'_, PyAny>, name: &str) -> PyResult<u64> {
    let n = if value.is_instance_of::<pyo3::types::PyBool>() { None } else { value.extract::<i128>().ok() };
    n.and_then(|n| u64::try_from(n).ok())
        .ok_or_else(|| SceneError::new_err(format!("estimator.{name} = {value}: must be an integer >= 1")))
}

fn orders_from_py(orders: &Bound<'_, PyAny>) -> PyResult<ScatteringOrders> {
    if orders.is_instance_of::<pyo3::types::PyBool>() {
        return Err(SceneError::new_err(format!("scattering_orders = {orders}: must be an integer >= 0 or \"all\"")));
    }
    if let Ok(text) = orders.extract::<String>() {
        return match text.as_str() {
            "all" => Ok(ScatteringOrders::All),
            _ => Err(SceneError::new_err(format!("scattering_orders = {text:?}: must be an integer >= 0 or \"all\""))),
        };
    }
    let n: i64 = orders.extract().map_err(|_| {
        SceneError::new_err(format!("scattering_orders = {orders}: must be an integer >= 0 or \"all\""))
    })?;
    u32::try_from(n)
        .map(ScatteringOrders::Limited)
        .map_err(|_| SceneError::new_err(format!("scattering_orders = {n}: must be an integer >= 0 or \"all\"")))
}

fn phase_from_py(phase: &str, g: Option<f64>) -> PyResult<Phase> {
    match (phase, g) {
        ("isotropic", None) => Ok(Phase::Isotropic),
        ("isotropic", Some(g)) => Err(SceneError::new_err(format!(
            "g = {g}: only a Henyey–Greenstein phase has g (phase = \"henyey-greenstein\")"
        ))),
        ("henyey-greenstein", Some(g)) => Ok(Phase::HenyeyGreenstein { g }),
        ("henyey-greenstein", None) => {
            Err(SceneError::new_err("g: missing; phase = \"henyey-greenstein\" needs g in (-1, 1)"))
        }
        (other, _) => {
            Err(SceneError::new_err(format!("phase = {other:?}: must be \"isotropic\" or \"henyey-greenstein\"")))
        }
    }
}

#[pymethods]
impl Scene {
    /// Reads and validates a scene file (TOML, `docs/scene-format.md`; at most 1 MiB).
    #[staticmethod]
    fn from_file(path: std::path::PathBuf) -> PyResult<Scene> {
        let text = mcrt_noise::scene::limits::read_scene_text(&path).map_err(SceneError::new_err)?;
        let inner =
            RustScene::from_toml_str(&text).map_err(|e| SceneError::new_err(format!("{}: {e}", path.display())))?;
        Ok(Scene { inner })
    }

    /// Validates a scene given as TOML text.
    #[staticmethod]
    fn from_toml(text: &str) -> PyResult<Scene> {
        RustScene::from_toml_str(text).map(|inner| Scene { inner }).map_err(scene_error)
    }

    /// Builds a scene from keywords, validated as a scene file is.
    ///
    /// `point_lights`: a sequence of ((x, y, z), flux); `beams`: of
    /// ((x, y, z) centre, (x, y, z) direction, radius, flux); `phase`:
    /// "isotropic" or "henyey-greenstein" (with `g`); `scattering_orders`:
    /// an integer >= 0 or "all".
    #[staticmethod]
    #[pyo3(signature = (
        *, sigma_ext, albedo, radius, q, forward_rays, camera_rays,
        point_lights = None, beams = None,
        camera_origin = None, camera_direction = None,
        phase = "isotropic", g = None, scattering_orders = None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn build(
        sigma_ext: f64,
        albedo: f64,
        radius: f64,
        q: f64,
        forward_rays: &Bound<'_, PyAny>,
        camera_rays: &Bound<'_, PyAny>,
        point_lights: Option<&Bound<'_, PyAny>>,
        beams: Option<&Bound<'_, PyAny>>,
        camera_origin: Option<&Bound<'_, PyAny>>,
        camera_direction: Option<&Bound<'_, PyAny>>,
        phase: &str,
        g: Option<f64>,
        scattering_orders: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Scene> {
        let origin = camera_origin.map(|v| vector(v, "camera_origin")).transpose()?.unwrap_or([0.0; 3]);
        let direction = camera_direction.map(|v| vector(v, "camera_direction")).transpose()?.unwrap_or([0.0, 0.0, 1.0]);
        let mut builder = RustScene::builder()
            .medium(sigma_ext, albedo)
            .phase(phase_from_py(phase, g)?)
            .camera(origin, direction)
            .estimator(radius, q, count(forward_rays, "forward_rays")?, count(camera_rays, "camera_rays")?);
        for (i, light) in items(point_lights, "point_lights")?.iter().enumerate() {
            let name = format!("point_lights[{i}]");
            let (position, flux) =
                light.extract::<(Bound<'_, PyAny>, f64)>().map_err(|e| shape_error(&name, "((x, y, z), flux)", e))?;
            builder = builder.point_light(vector(&position, &format!("{name} position"))?, flux);
        }
        for (i, beam) in items(beams, "beams")?.iter().enumerate() {
            let name = format!("beams[{i}]");
            let (center, direction, beam_radius, flux) = beam
                .extract::<(Bound<'_, PyAny>, Bound<'_, PyAny>, f64, f64)>()
                .map_err(|e| shape_error(&name, "((x, y, z) centre, (x, y, z) direction, radius, flux)", e))?;
            let (center, direction) =
                (vector(&center, &format!("{name} centre"))?, vector(&direction, &format!("{name} direction"))?);
            builder = builder.beam(center, direction, beam_radius, flux);
        }
        if let Some(orders) = scattering_orders {
            builder = builder.scattering_orders(orders_from_py(orders)?);
        }
        builder.build().map(|inner| Scene { inner }).map_err(scene_error)
    }

    /// The scene as a scene file writes it (normalised: defaults filled in).
    fn to_toml(&self) -> String {
        self.inner.to_toml_string()
    }

    /// Every field, as a dict of plain Python values.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = &self.inner;
        let d = PyDict::new(py);
        d.set_item("sigma_ext", s.medium.sigma_ext)?;
        d.set_item("albedo", s.medium.albedo)?;
        match s.medium.phase {
            Phase::Isotropic => d.set_item("phase", "isotropic")?,
            Phase::HenyeyGreenstein { g } => {
                d.set_item("phase", "henyey-greenstein")?;
                d.set_item("g", g)?;
            }
        }
        let lights = PyList::empty(py);
        for light in &s.lights {
            let l = PyDict::new(py);
            match light {
                mcrt_noise::scene::Light::Point { position, flux } => {
                    l.set_item("kind", "point")?;
                    l.set_item("position", position.to_array())?;
                    l.set_item("flux", flux)?;
                }
                mcrt_noise::scene::Light::Beam { center, direction, radius, flux } => {
                    l.set_item("kind", "beam")?;
                    l.set_item("center", center.to_array())?;
                    l.set_item("direction", direction.to_array())?;
                    l.set_item("radius", radius)?;
                    l.set_item("flux", flux)?;
                }
            }
            lights.append(l)?;
        }
        d.set_item("lights", lights)?;
        d.set_item("camera_origin", s.camera.origin.to_array())?;
        d.set_item("camera_direction", s.camera.direction.to_array())?;
        d.set_item("radius", s.estimator.radius)?;
        d.set_item("q", s.estimator.q)?;
        d.set_item("forward_rays", s.estimator.forward_rays)?;
        d.set_item("camera_rays", s.estimator.camera_rays)?;
        match s.effects.scattering_orders {
            ScatteringOrders::All => d.set_item("scattering_orders", "all")?,
            ScatteringOrders::Limited(n) => d.set_item("scattering_orders", n)?,
        }
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!("Scene.from_toml({:?})", self.inner.to_toml_string())
    }
}
