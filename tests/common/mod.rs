//! Scenes shared by the test binaries: the bundled ones, and the variations
//! the finite-sphere tests need (a light inside the spheres, a beam edge
//! across them, two lights).

#![allow(dead_code)]

pub mod order1;

use mcrt_scene::{DVec3, Light, Scene};
use std::path::Path;

/// `scenes/NAME.toml`.
pub fn bundled(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(format!("{name}.toml"));
    Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The scene with the sphere radius R set.
pub fn with_radius(mut s: Scene, r: f64) -> Scene {
    s.estimator.radius = r;
    s
}

/// The isotropic point-light scene with the light 0.1 from the camera line.
pub fn near_light() -> Scene {
    let mut s = bundled("point-isotropic");
    s.lights[0] = Light::Point { position: DVec3::new(0.1, 0.0, 1.0), flux: 1.0 };
    s
}

/// The beam scene moved sideways so that the beam's edge crosses the
/// camera line's spheres (axis 0.45 from the line, beam radius 0.5).
pub fn beam_edge() -> Scene {
    let mut s = bundled("beam-isotropic");
    s.lights[0] = Light::Beam { center: DVec3::new(-2.0, 0.45, 1.0), direction: DVec3::X, radius: 0.5, flux: 1.0 };
    s
}

/// A point light and an oblique beam in a backward-scattering medium.
pub fn point_and_beam() -> Scene {
    let mut s = bundled("point-hg-backward");
    s.lights.push(Light::Beam {
        center: DVec3::new(-2.0, 0.3, 1.5),
        direction: DVec3::new(1.0, 0.0, 0.2).normalize(),
        radius: 0.5,
        flux: 2.0,
    });
    s
}

/// A beam travelling towards the camera's side at an angle (μ = −0.8):
/// its rays reach the camera line's spheres only up to a depth, hi₀ < ∞.
pub fn beam_towards_camera() -> Scene {
    let mut s = bundled("beam-isotropic");
    s.lights[0] = Light::Beam {
        center: DVec3::new(-2.0, 0.0, 3.0),
        direction: DVec3::new(0.6, 0.0, -0.8),
        radius: 0.5,
        flux: 1.0,
    };
    s
}

/// A beam travelling away from the camera at an angle (μ = 0.8) whose disk
/// lies beyond the camera: the spheres it reaches start at lo₀ > 0.
pub fn beam_away_from_camera() -> Scene {
    let mut s = bundled("beam-isotropic");
    s.lights[0] = Light::Beam {
        center: DVec3::new(-2.0, 0.0, 2.0),
        direction: DVec3::new(0.6, 0.0, 0.8),
        radius: 0.5,
        flux: 1.0,
    };
    s
}

/// The isotropic point-light scene with the light moved to `position`.
pub fn point_at(position: [f64; 3]) -> Scene {
    let mut s = bundled("point-isotropic");
    s.lights[0] = Light::Point { position: DVec3::from_array(position), flux: 1.0 };
    s
}

/// The report's `finite` object at `digits` significant digits (bars:
/// their decade; integrals not computed: the reason), for snapshots.
pub fn finite_text(r: &mcrt_noise::oracle::Report, digits: usize) -> String {
    let f = r.finite.as_ref().expect("a finite-sphere model");
    let sig = |v: f64| format!("{v:.*e}", digits - 1);
    let decade = |v: f64| if v > 0.0 { format!("<= 1e{}", v.log10().ceil() as i32) } else { "0".into() };
    let mut out = format!("prediction.model {}\n", r.prediction.model);
    for (label, v) in [
        ("mean", Some(f.mean)),
        ("variance", Some(f.variance)),
        ("bias", Some(f.bias)),
        ("relative_noise", Some(f.relative_noise)),
        ("mean_ratio", Some(f.mean_ratio)),
        ("variance_ratio", f.variance_ratio),
        ("m2", Some(f.integral_m2.into())),
        ("p", Some(f.integral_p.into())),
        ("q_pair", f.integral_q.map(Into::into)),
        ("corr23", f.corr23.map(Into::into)),
        ("corr24", f.corr24.map(Into::into)),
    ] {
        let v: Option<mcrt_noise::oracle::ValueWithBar> = v;
        match v {
            Some(v) => out.push_str(&format!("{label} {} ({})\n", sig(v.value), decade(v.error))),
            None => out.push_str(&format!("{label} not computed\n")),
        }
    }
    if f.covers != "uncollided" {
        out.push_str(&format!("covers {}\n", f.covers));
    }
    out
}
