//! A toy renderer of the multiple-integration-spheres estimator (Ershov, Zhdanov & Voloboy 2019),
//! written from `docs/tracer.md` and `docs/conventions.md` only, with bugs that can be planted one at a time.
//!
//! One pixel, one homogeneous medium, one isotropic point light, uncollided light only (scattering order 0).
//! [`render_iteration`] returns one iteration's pixel value L (paper eq. (6)); [`render`] runs many
//! independent iterations, each with its own random stream, so the values do not depend on how a run is split.

#![warn(missing_docs)]

use std::f64::consts::PI;
use std::ops::Range;

use rand::Rng;
use rand_pcg::Pcg64;

/// A scene the toy renderer understands: homogeneous medium, one isotropic point light, one pixel's camera ray,
/// the estimator's parameters. Uncollided light only (scattering order 0).
#[derive(Clone, Debug, PartialEq)]
pub struct ToyScene {
    /// Extinction coefficient σ_ext (1/length), > 0.
    pub sigma_ext: f64,
    /// Single-scattering albedo σ_sc/σ_ext, in [0, 1].
    pub albedo: f64,
    /// Henyey–Greenstein g, in (−1, 1) (0: isotropic).
    pub g: f64,
    /// Position of the point light.
    pub light_position: [f64; 3],
    /// Total flux 𝓕 of the light.
    pub flux: f64,
    /// Origin o of the camera ray.
    pub camera_origin: [f64; 3],
    /// Unit view direction u of the camera ray.
    pub camera_direction: [f64; 3],
    /// Integration sphere radius R.
    pub radius: f64,
    /// Extinction probability q per sub-step, in (0, 1].
    pub q: f64,
    /// Number N_F of forward rays per iteration.
    pub forward_rays: u32,
    /// Number N_B of camera rays through the pixel per iteration.
    pub camera_rays: u32,
}

impl ToyScene {
    /// The scene of the documented bug table (`docs/library.md`): σ_ext = 1,
    /// albedo 0.8, Henyey–Greenstein g = 0.5 (the phase bug needs an
    /// anisotropic medium), a point light at (1, 0, 1), the camera at the
    /// origin along +z, R = 0.2, q = 0.5 (the q bugs need q < 1), N_F = 20,
    /// N_B = 4 (the shared-spheres bug needs several camera rays).
    pub fn example() -> ToyScene {
        ToyScene {
            sigma_ext: 1.0,
            albedo: 0.8,
            g: 0.5,
            light_position: [1.0, 0.0, 1.0],
            flux: 1.0,
            camera_origin: [0.0; 3],
            camera_direction: [0.0, 0.0, 1.0],
            radius: 0.2,
            q: 0.5,
            forward_rays: 20,
            camera_rays: 4,
        }
    }
}

/// A bug planted in the estimator, or none.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bug {
    /// The estimator as documented.
    None,
    /// Weight 𝒞 instead of q·𝒞 per sphere.
    ForgetQ,
    /// 𝒞 divided by R² instead of πR².
    RSquaredArea,
    /// The N_B camera rays of the pixel share one set of spheres (placed once, used N_B times).
    SharedSpheres,
    /// Sub-steps ~ Exp(σ_ext) instead of Exp(σ_ext/q).
    SubStepsAtSigma,
    /// The phase function evaluated at +u·v instead of the scattering-angle cosine −u·v.
    PhaseAtPlusCos,
    /// The albedo left out of 𝒞 (σ_ext in place of σ_sc).
    NoAlbedo,
}

impl Bug {
    /// Every variant, [`Bug::None`] first.
    pub const ALL: [Bug; 7] = [
        Bug::None,
        Bug::ForgetQ,
        Bug::RSquaredArea,
        Bug::SharedSpheres,
        Bug::SubStepsAtSigma,
        Bug::PhaseAtPlusCos,
        Bug::NoAlbedo,
    ];
}

/// Henyey–Greenstein phase function at the cosine `c` of the scattering angle, normalised to 1 over the sphere
/// (1/sr): (1 − g²)/(4π (1 + g² − 2gc)^{3/2}); 1/(4π) at g = 0.
pub fn henyey_greenstein(g: f64, c: f64) -> f64 {
    (1.0 - g * g) / (4.0 * PI * (1.0 + g * g - 2.0 * g * c).powf(1.5))
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// An Exp(rate) distance.
fn exp_step<R: Rng>(rng: &mut R, rate: f64) -> f64 {
    -(1.0 - rng.random::<f64>()).ln() / rate
}

/// Distances along the camera ray of the spheres of one camera ray: sub-steps ~ Exp(rate), a sphere after each,
/// then the segment ends with probability q (no draw at q = 1).
fn place_spheres<R: Rng>(rng: &mut R, rate: f64, q: f64, spheres: &mut Vec<f64>) {
    let mut s = 0.0;
    loop {
        s += exp_step(rng, rate);
        spheres.push(s);
        if q >= 1.0 || rng.random::<f64>() < q {
            return;
        }
    }
}

/// One iteration of the pixel: the estimator's L (paper eq. (6)),
/// L = (1/(N_F N_B)) Σ over forward segments and camera rays of Σ over hit spheres of q·𝒞.
pub fn render_iteration<R: Rng>(scene: &ToyScene, bug: Bug, rng: &mut R) -> f64 {
    let sigma = scene.sigma_ext;
    let q = scene.q;
    let r2 = scene.radius * scene.radius;
    let u = scene.camera_direction;
    let o = scene.camera_origin;

    // Camera: the sphere positions s of all N_B rays (each ray's spheres counted once per ray).
    let step_rate = if bug == Bug::SubStepsAtSigma { sigma } else { sigma / q };
    let mut spheres = Vec::new();
    if bug == Bug::SharedSpheres {
        let mut one = Vec::new();
        place_spheres(rng, step_rate, q, &mut one);
        for _ in 0..scene.camera_rays {
            spheres.extend_from_slice(&one);
        }
    } else {
        for _ in 0..scene.camera_rays {
            place_spheres(rng, step_rate, q, &mut spheres);
        }
    }

    // 𝒞 = (σ_sc/σ_ext) f 𝓕/(πR²), times the sphere weight q.
    let albedo = if bug == Bug::NoAlbedo { 1.0 } else { scene.albedo };
    let area = if bug == Bug::RSquaredArea { r2 } else { PI * r2 };
    let weight = if bug == Bug::ForgetQ { 1.0 } else { q };
    let c_without_f = weight * albedo * scene.flux / area;

    let p0 = scene.light_position;
    let mut sum = 0.0;
    for _ in 0..scene.forward_rays {
        // Isotropic emission; the first (uncollided) segment ends at a free path ~ Exp(σ_ext).
        let z = 1.0 - 2.0 * rng.random::<f64>();
        let phi = 2.0 * PI * rng.random::<f64>();
        let sin = (1.0 - z * z).max(0.0).sqrt();
        let v = [sin * phi.cos(), sin * phi.sin(), z];
        let length = exp_step(rng, sigma);

        let mu = dot(u, v);
        let cos_scattering = if bug == Bug::PhaseAtPlusCos { mu } else { -mu };
        let c = c_without_f * henyey_greenstein(scene.g, cos_scattering);
        for &s in &spheres {
            let d = [o[0] + s * u[0] - p0[0], o[1] + s * u[1] - p0[1], o[2] + s * u[2] - p0[2]];
            let tau = dot(d, v); // closest point of the segment's line to the centre
            if (0.0..=length).contains(&tau) && dot(d, d) - tau * tau <= r2 {
                sum += c;
            }
        }
    }
    sum / (f64::from(scene.forward_rays) * f64::from(scene.camera_rays))
}

/// The random stream of iteration `i` of a run seeded with `seed`: PCG-64 with a state from the seed and the
/// stream selected by `i`.
pub fn iteration_rng(seed: u64, i: u64) -> Pcg64 {
    // SplitMix64 spreads the seed over the 128-bit state.
    let mix = |mut x: u64| {
        x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
        x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        x ^ (x >> 31)
    };
    let state = (u128::from(mix(seed)) << 64) | u128::from(mix(seed ^ 0xD1B5_4A32_D192_ED03));
    Pcg64::new(state, u128::from(i))
}

/// `iterations` independent iterations, iteration i drawing from its own `rand_pcg::Pcg64` stream derived from
/// (seed, i) ([`iteration_rng`]), so the values do not depend on how the loop is split.
pub fn render(scene: &ToyScene, bug: Bug, iterations: u64, seed: u64) -> Vec<f64> {
    render_range(scene, bug, 0..iterations, seed)
}

/// Iterations `range` of the run seeded with `seed`: the same values as the corresponding slice of [`render`].
pub fn render_range(scene: &ToyScene, bug: Bug, range: Range<u64>, seed: u64) -> Vec<f64> {
    range.map(|i| render_iteration(scene, bug, &mut iteration_rng(seed, i))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene() -> ToyScene {
        ToyScene::example()
    }

    #[test]
    fn values_do_not_depend_on_the_split() {
        let whole = render(&scene(), Bug::None, 300, 7);
        let mut parts = render_range(&scene(), Bug::None, 0..120, 7);
        parts.extend(render_range(&scene(), Bug::None, 120..300, 7));
        assert_eq!(whole, parts);
        assert!(whole.iter().any(|&l| l > 0.0));
    }

    #[test]
    fn henyey_greenstein_is_normalised() {
        for g in [0.0, 0.5, -0.5] {
            let n = 100_000;
            let h = 2.0 / n as f64;
            let sum: f64 = (0..n).map(|i| henyey_greenstein(g, -1.0 + h * (i as f64 + 0.5))).sum();
            let integral = 2.0 * PI * h * sum;
            assert!((integral - 1.0).abs() < 1e-6, "g = {g}: {integral}");
        }
    }
}
