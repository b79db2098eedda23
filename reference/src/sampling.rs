//! The samplers of the estimator: exponential steps, directions (uniform,
//! Henyey–Greenstein about a direction), points on a beam's disk. Each takes
//! its uniforms from a counted [`Stream`]; each is tested by a chi-square
//! test (`tests/samplers.rs`).

use crate::rng::{Draw, Stream};
use glam::DVec3;
use std::f64::consts::PI;

/// ζ ~ Exp(rate): −ln(1 − U)/rate, U ∈ [0, 1) (so 1 − U ∈ (0, 1] and ζ is finite).
pub fn exponential(stream: &mut Stream, rate: f64, kind: Draw) -> f64 {
    -(-stream.uniform(kind)).ln_1p() / rate
}

/// A direction uniform on the unit sphere: cos = 1 − 2U₁, azimuth 2πU₂.
pub fn uniform_direction(stream: &mut Stream, kind: Draw) -> DVec3 {
    let cos = 1.0 - 2.0 * stream.uniform(kind);
    let phi = 2.0 * PI * stream.uniform(kind);
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    DVec3::new(sin * phi.cos(), sin * phi.sin(), cos)
}

/// The cosine of the scattering angle drawn from Henyey–Greenstein with
/// mean cosine g, by inverting its CDF: cos θ = (1 + g² − ((1 − g²)/(1 − g +
/// 2gU))²)/(2g); for |g| < 10⁻⁵ the isotropic 1 − 2U (the inversion's
/// cancellation would cost more than the O(g) difference). Clamped to
/// [−1, 1] against rounding at g → ±1.
pub fn hg_cosine(stream: &mut Stream, g: f64) -> f64 {
    let u = stream.uniform(Draw::Phase);
    if g.abs() < 1e-5 {
        return 1.0 - 2.0 * u;
    }
    let k = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
    ((1.0 + g * g - k * k) / (2.0 * g)).clamp(-1.0, 1.0)
}

/// Two unit vectors completing `n` (unit) to a right-handed orthonormal
/// basis (Duff et al. 2017, branchless, no degenerate direction).
pub fn basis(n: DVec3) -> (DVec3, DVec3) {
    let sign = 1f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), DVec3::new(b, sign + n.y * n.y * a, -n.y))
}

/// The direction at scattering angle arccos(`cos`) from `d`, azimuth 2πU.
pub fn rotate(stream: &mut Stream, d: DVec3, cos: f64) -> DVec3 {
    let phi = 2.0 * PI * stream.uniform(Draw::Phase);
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let (e1, e2) = basis(d);
    (d * cos + (e1 * phi.cos() + e2 * phi.sin()) * sin).normalize()
}

/// A point uniform on the disk of `radius` about `center` perpendicular to
/// the unit `normal`: radius·√U₁ at azimuth 2πU₂.
pub fn disk_point(stream: &mut Stream, center: DVec3, normal: DVec3, radius: f64) -> DVec3 {
    let r = radius * stream.uniform(Draw::EmissionPosition).sqrt();
    let phi = 2.0 * PI * stream.uniform(Draw::EmissionPosition);
    let (e1, e2) = basis(normal);
    center + (e1 * phi.cos() + e2 * phi.sin()) * r
}
