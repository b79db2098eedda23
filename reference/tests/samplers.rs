//! Chi-square tests of every sampler of the tracer.
//!
//! Each test bins fixed-seed samples, pools adjacent cells until every
//! expected count is at least 5, and requires the chi-square p-value to be at
//! least the Šidák-corrected level 1 − (1 − 0.01)^{1/m} for the m tests of
//! this file, so that the family fails by chance with probability 1 %. The
//! expected cell probabilities come from closed-form CDFs written here, not
//! from the samplers' inversions.

mod common;

use glam::DVec3;
use mcrt_reference::rng::{Draw, Stream};
use mcrt_reference::sampling::{disk_point, exponential, hg_cosine, rotate, uniform_direction};
use mcrt_reference::Tracer;
use statrs::distribution::{ChiSquared, ContinuousCDF};
use std::f64::consts::PI;

/// Tests in this file (the Šidák family).
const FAMILY: i32 = 10;
const SAMPLES: usize = 200_000;

fn sidak_level() -> f64 {
    1.0 - (1.0 - 0.01f64).powf(1.0 / f64::from(FAMILY))
}

/// p-value of observed counts against expected probabilities, after pooling.
fn chi_square_p(observed: &[u64], probs: &[f64]) -> f64 {
    let n: u64 = observed.iter().sum();
    let (mut cells, mut obs, mut exp) = (Vec::new(), 0.0, 0.0);
    for (o, p) in observed.iter().zip(probs) {
        obs += *o as f64;
        exp += p * n as f64;
        if exp >= 5.0 {
            cells.push((obs, exp));
            (obs, exp) = (0.0, 0.0);
        }
    }
    if let Some(last) = cells.last_mut() {
        last.0 += obs;
        last.1 += exp;
    }
    assert!(cells.len() >= 5, "too few cells after pooling: {}", cells.len());
    let stat: f64 = cells.iter().map(|(o, e)| (o - e) * (o - e) / e).sum();
    1.0 - ChiSquared::new((cells.len() - 1) as f64).unwrap().cdf(stat)
}

fn assert_fits(name: &str, observed: &[u64], probs: &[f64]) {
    let sum: f64 = probs.iter().sum();
    assert!((sum - 1.0).abs() < 1e-9, "{name}: cell probabilities sum to {sum}");
    let p = chi_square_p(observed, probs);
    assert!(p >= sidak_level(), "{name}: chi-square p = {p:e} below {:e}", sidak_level());
}

/// Counts of values u ∈ [0, 1) in `bins` equal cells.
fn uniform_cells(values: impl Iterator<Item = f64>, bins: usize) -> Vec<u64> {
    let mut counts = vec![0u64; bins];
    for u in values {
        assert!((0.0..=1.0).contains(&u), "{u} outside [0, 1]");
        counts[((u * bins as f64) as usize).min(bins - 1)] += 1;
    }
    counts
}

/// P(cos ≤ μ) for Henyey–Greenstein: (1 − g²)/(2g)·((1 + g² − 2gμ)^{−1/2} − 1/(1 + g)).
fn hg_cdf(g: f64, mu: f64) -> f64 {
    if g == 0.0 {
        return (mu + 1.0) / 2.0;
    }
    (1.0 - g * g) / (2.0 * g) * ((1.0 + g * g - 2.0 * g * mu).powf(-0.5) - 1.0 / (1.0 + g))
}

/// An orthonormal basis about n built here (not the crate's).
fn test_basis(n: DVec3) -> (DVec3, DVec3) {
    let helper = if n.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let e1 = n.cross(helper).normalize();
    (e1, n.cross(e1))
}

fn azimuth(v: DVec3, n: DVec3) -> f64 {
    let (e1, e2) = test_basis(n);
    (v.dot(e2).atan2(v.dot(e1)) / (2.0 * PI)).rem_euclid(1.0)
}

#[test]
fn exponential_steps_follow_their_cdf() {
    let mut s = Stream::new(1, 0);
    let rate = 2.5;
    let cells =
        uniform_cells((0..SAMPLES).map(|_| 1.0 - (-rate * exponential(&mut s, rate, Draw::FreePath)).exp()), 40);
    assert_fits("Exp(2.5)", &cells, &[1.0 / 40.0; 40]);
}

#[test]
fn uniform_directions_cover_the_sphere_evenly() {
    let mut s = Stream::new(2, 0);
    let mut cells = vec![0u64; 10 * 16];
    for _ in 0..SAMPLES {
        let v = uniform_direction(&mut s, Draw::EmissionDirection);
        assert!((v.length() - 1.0).abs() < 1e-12);
        let c = (((v.z + 1.0) / 2.0 * 10.0) as usize).min(9);
        let a = ((azimuth(v, DVec3::Z) * 16.0) as usize).min(15);
        cells[c * 16 + a] += 1;
    }
    assert_fits("uniform direction", &cells, &[1.0 / 160.0; 160]);
}

fn hg_case(g: f64, seed: u64) {
    let mut s = Stream::new(seed, 0);
    let cells = uniform_cells((0..SAMPLES).map(|_| hg_cdf(g, hg_cosine(&mut s, g))), 50);
    assert_fits(&format!("HG g = {g}"), &cells, &[1.0 / 50.0; 50]);
}

#[test]
fn hg_cosines_follow_the_hg_cdf_forward() {
    hg_case(0.9, 3);
}

#[test]
fn hg_cosines_follow_the_hg_cdf_backward() {
    hg_case(-0.5, 4);
}

#[test]
fn hg_cosines_follow_the_hg_cdf_at_g_0_99() {
    hg_case(0.99, 5);
}

#[test]
fn hg_cosines_follow_the_hg_cdf_at_g_minus_0_99() {
    hg_case(-0.99, 6);
}

#[test]
fn hg_cosines_near_g_0_are_isotropic() {
    hg_case(1e-7, 7);
}

#[test]
fn rotation_keeps_the_scattering_angle_and_spreads_the_azimuth() {
    let mut s = Stream::new(8, 0);
    let d = DVec3::new(0.3, -0.5, 0.8).normalize();
    let g = 0.7;
    let mut cells = vec![0u64; 10 * 8];
    for _ in 0..SAMPLES {
        let cos = hg_cosine(&mut s, g);
        let v = rotate(&mut s, d, cos);
        assert!((v.dot(d) - cos).abs() < 1e-9, "angle lost: {} vs {cos}", v.dot(d));
        let c = ((hg_cdf(g, cos) * 10.0) as usize).min(9);
        let a = ((azimuth(v, d) * 8.0) as usize).min(7);
        cells[c * 8 + a] += 1;
    }
    assert_fits("rotated HG directions", &cells, &[1.0 / 80.0; 80]);
}

#[test]
fn beam_points_cover_the_disk_evenly() {
    let mut s = Stream::new(9, 0);
    let (center, normal, radius) = (DVec3::new(1.0, 2.0, 3.0), DVec3::new(1.0, 1.0, 0.0).normalize(), 0.5);
    let mut cells = vec![0u64; 10 * 12];
    for _ in 0..SAMPLES {
        let p = disk_point(&mut s, center, normal, radius) - center;
        assert!(p.dot(normal).abs() < 1e-12 && p.length() <= radius * (1.0 + 1e-12));
        let r2 = ((p.length_squared() / (radius * radius) * 10.0) as usize).min(9);
        let a = ((azimuth(p, normal) * 12.0) as usize).min(11);
        cells[r2 * 12 + a] += 1;
    }
    assert_fits("disk points", &cells, &[1.0 / 120.0; 120]);
}

#[test]
fn lights_are_chosen_in_proportion_to_flux() {
    // The bundled point light (flux 1 at (1, 0, 1)) with a second point
    // light and a beam added.
    let more_lights = r#"[[lights]]
kind = "point"
position = [2.0, 0.0, 1.0]
flux = 2.0

[[lights]]
kind = "beam"
center = [-2.0, 0.0, 1.0]
direction = [1.0, 0.0, 0.0]
radius = 0.5
flux = 5.0

[camera]"#;
    let tracer = Tracer::new(&common::scene("point-isotropic", &[("[camera]", more_lights)])).unwrap();
    let mut s = Stream::new(10, 0);
    let mut cells = vec![0u64; 3];
    for _ in 0..SAMPLES {
        let (p, _) = tracer.emit(&mut s);
        let i = if p == DVec3::new(1.0, 0.0, 1.0) {
            0
        } else if p == DVec3::new(2.0, 0.0, 1.0) {
            1
        } else {
            assert!((p.x + 2.0).abs() < 1e-12, "not on the beam's disk: {p}");
            2
        };
        cells[i] += 1;
    }
    assert_eq!(s.counts.light_choice, SAMPLES as u64);
    // Three cells, each expecting ≥ 25 000: the chi-square on them directly
    // (the pooling helper wants at least five cells).
    let n = SAMPLES as f64;
    let expected = [n / 8.0, 2.0 * n / 8.0, 5.0 * n / 8.0];
    let stat: f64 = cells.iter().zip(expected).map(|(o, e)| (*o as f64 - e).powi(2) / e).sum();
    let p = 1.0 - ChiSquared::new(2.0).unwrap().cdf(stat);
    assert!(p >= sidak_level(), "light choice: p = {p:e}, counts {cells:?}");
}
