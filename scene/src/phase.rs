//! Phase functions, normalised over the sphere: ∫ f dω = 1 (units 1/sr).
//!
//! The argument is the cosine of the *scattering angle*, the angle between the
//! direction the light travelled before the event and the one after it
//! (`docs/conventions.md`). Paper eq. (5) writes f(−u, v) for light travelling
//! along v scattered towards the camera, i.e. along −u: `cos = dot(−u, v)`.

use std::f64::consts::PI;

/// A phase function of the medium.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Phase {
    /// f = 1/(4π).
    Isotropic,
    /// Henyey–Greenstein, f = (1 − g²) / (4π (1 + g² − 2g cos)^{3/2}), |g| < 1.
    HenyeyGreenstein {
        /// Mean cosine of the scattering angle, in (−1, 1).
        g: f64,
    },
}

impl Phase {
    /// Phase function value at the scattering-angle cosine `cos_theta` ∈ [−1, 1].
    ///
    /// The HG denominator is evaluated as (1 − g)² + 2g(1 − cos), which keeps its
    /// relative accuracy when g → ±1 and cos → ±1 (forward and backward peaks).
    pub fn eval(&self, cos_theta: f64) -> f64 {
        match *self {
            Phase::Isotropic => 1.0 / (4.0 * PI),
            Phase::HenyeyGreenstein { g } => {
                let denom = if g >= 0.0 {
                    (1.0 - g) * (1.0 - g) + 2.0 * g * (1.0 - cos_theta)
                } else {
                    (1.0 + g) * (1.0 + g) - 2.0 * g * (1.0 + cos_theta)
                };
                (1.0 - g) * (1.0 + g) / (4.0 * PI * denom * denom.sqrt())
            }
        }
    }

    /// Mean cosine of the scattering angle (0 for isotropic).
    pub fn mean_cosine(&self) -> f64 {
        match *self {
            Phase::Isotropic => 0.0,
            Phase::HenyeyGreenstein { g } => g,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ f dω = 2π ∫_{-1}^{1} f(μ) dμ by composite Simpson on a graded grid.
    fn integrate_mu(phase: Phase, moment: i32) -> f64 {
        // Substitution μ = 1 − 2 y², dense near μ = 1 where HG peaks.
        let n = 200_000;
        let h = 1.0 / n as f64;
        let mut sum = 0.0;
        for i in 0..=n {
            let y = i as f64 * h;
            let mu = 1.0 - 2.0 * y * y;
            let w = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            sum += w * phase.eval(mu) * mu.powi(moment) * 4.0 * y;
        }
        2.0 * PI * sum * h / 3.0
    }

    #[test]
    fn phase_functions_are_normalised_and_have_mean_cosine_g() {
        for phase in [
            Phase::Isotropic,
            Phase::HenyeyGreenstein { g: 0.0 },
            Phase::HenyeyGreenstein { g: 0.5 },
            Phase::HenyeyGreenstein { g: -0.5 },
            Phase::HenyeyGreenstein { g: 0.9 },
        ] {
            approx::assert_relative_eq!(integrate_mu(phase, 0), 1.0, max_relative = 1e-8);
            approx::assert_abs_diff_eq!(integrate_mu(phase, 1), phase.mean_cosine(), epsilon = 1e-8);
        }
    }

    #[test]
    fn hg_is_finite_near_the_limits() {
        for g in [0.999999, -0.999999] {
            let p = Phase::HenyeyGreenstein { g };
            for mu in [-1.0, -0.999999, 0.0, 0.999999, 1.0] {
                let v = p.eval(mu);
                assert!(v.is_finite() && v > 0.0, "g={g} mu={mu} f={v}");
            }
            // Peak value (1 + g) / (4π (1 − g)²) in the direction of g.
            let peak = (1.0 + g.abs()) / (4.0 * PI * (1.0 - g.abs()).powi(2));
            approx::assert_relative_eq!(p.eval(g.signum()), peak, max_relative = 1e-9);
        }
    }
}
