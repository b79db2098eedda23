//! A point light in the finite-sphere model (`docs/model.md` §9.2).
//!
//! The light sits at axial abscissa z on the camera line (absolute s of
//! its foot) and distance b ≥ 0 from it. A forward ray has polar angle ϑ
//! about u and azimuth χ about u, χ = 0 heading straight towards the
//! camera line. Its line passes the camera line at distance b|sin χ|, so it
//! can hit only when b|sin χ| ≤ R; with ρ = √(R² − b² sin²χ) and
//! B = b cos χ the centres within R of the line are s_c ± ρ/sin ϑ,
//! s_c = z + B cot ϑ, where τ(s_c) = B/sin ϑ, and τ = 0 at
//! s_τ = z − B tan ϑ. The hit interval J is
//!
//!   [max(s_c − ρ/sin ϑ, 0, s_τ if μ > 0), min(s_c + ρ/sin ϑ, s_τ if μ < 0)],
//!
//! its length and the path P = a + τ(a) are formed per pair of active
//! bounds so that nothing cancels (below). The kinks in ϑ are where two
//! bounds meet: z sin ϑ + B cos ϑ = ±ρ (the window's ends at the camera),
//! cos ϑ = ±B/ρ (the window's ends at the light), z cos ϑ = B sin ϑ
//! (s_τ = 0) and ϑ = π/2 (the pair orientation); all are roots of
//! A sin ϑ + B cos ϑ = C with discriminants |y − o|² − R², R² − b², or
//! B² + z², given without cancellation ([`super::angles`]).
//!
//! Ray-centric integrals: (1/4π)∫dω = (1/2π)∫₀^π dχ ∫₀^π sin ϑ dϑ (χ ↔ −χ
//! symmetric). For b > R only a window χ ≤ arcsin(R/b) towards the line
//! can hit (the other side would need the closest point behind the light),
//! integrated in η = b sin χ/R ∈ [0, 1], dχ = (R/b) dη/cos χ, ρ = R√(1 − η²);
//! for b ≤ R every χ can, and χ ∈ [0, π] is integrated directly (above 53
//! bits, for a light ahead of the camera, folded about π/2: `FOLD_POWER`).
//!
//! Sphere-centric ⟨𝒞⟩_R(s): a light at distance d from the centre sees the
//! sphere as a cap of half-angle ψ_R = arcsin(R/d) about w = (x(s) − y)/d
//! (the hemisphere ψ ≤ π/2 when d ≤ R, the light inside); the segment must
//! reach the closest point, at d cos ψ:
//!
//!   ⟨𝒞^k⟩_R = (albedo 𝓕/(πR²))^k (Φ/𝓕) ∫_cap f^k e^{−σ d cos ψ} dω/(4π).
//!
//! For an isotropic medium this is closed: (1/2) e^{−σ√(d² − R²)} F₁(σd, h),
//! h = 1 − cos ψ_R = R²/(d(d + √(d² − R²))); otherwise (ψ, χ) about w with
//! the phase function's poles declared (`angular::Frame::around`).

use super::angles::{roots, sum_and_difference};
use super::ray::{functional, Functional, Hit};
use super::{phase_of, FiniteField};
use crate::model::angular::{decades_below, view_direction, Direction, Features, Frame, Halves, Pole};
use crate::model::field::{decay_graded_about, graded_about};
use crate::quad::{integrate_nested, integrate_within_pass, CheckRule, Domain, Estimate, Options, Outcome};
use crate::real::Real;
use crate::special::{exp_segment, hg_ring};
use mcrt_scene::Phase;

/// A point light as the finite-sphere model sees it.
#[derive(Debug, Clone)]
pub struct PointLight<T> {
    /// Axial abscissa of the light's foot on the camera line (absolute s).
    pub z: T,
    /// Distance of the light from the camera line (≥ 0).
    pub b: T,
    /// Flux Φ of the light.
    pub flux: T,
    /// |y − o|² − R² = z² + b² − R².
    disc_camera: T,
    /// b² − R² = (b − R)(b + R).
    b2_minus_r2: T,
}

/// A ray's azimuth as the hit geometry needs it.
#[derive(Debug, Clone)]
pub(super) struct Azimuth<T> {
    /// B = b cos χ (> 0: heading towards the camera line).
    bcos: T,
    /// ρ = √(R² − b² sin²χ), half-width of the window (in the plane ⊥ v).
    rho: T,
    /// B + ρ and B − ρ, without cancellation ((B + ρ)(B − ρ) = b² − R²).
    plus: T,
    minus: T,
}

/// Which bound of the hit interval is active.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Bound {
    /// The window of centres within R of the ray's line.
    Window,
    /// The camera (s ≥ 0), lower bound only.
    Camera,
    /// The light (τ ≥ 0).
    Light,
}

impl<T: CheckRule> PointLight<T> {
    /// From the foot's abscissa `z`, the distance `b` ≥ 0 from the camera
    /// line, the flux and the sphere radius `r` > 0.
    pub fn new(z: T, b: T, flux: T, r: &T) -> Self {
        let disc_camera = z.clone() * z.clone() + (b.clone() - r.clone()) * (b.clone() + r.clone());
        let b2_minus_r2 = (b.clone() - r.clone()) * (b.clone() + r.clone());
        PointLight { z, b, flux, disc_camera, b2_minus_r2 }
    }

    pub(super) fn azimuth(&self, bcos: T, rho: T) -> Azimuth<T> {
        let (plus, minus) = sum_and_difference(&bcos, &rho, &self.b2_minus_r2);
        Azimuth { bcos, rho, plus, minus }
    }

    /// The hit interval of the ray (ϑ, χ), or `None` when it hits nothing.
    pub(super) fn hit(&self, dir: &Direction<T>, az: &Azimuth<T>) -> Option<Hit<T>> {
        self.bounded_hit(dir, az).map(|(hit, _)| hit)
    }

    /// [`PointLight::hit`] with τ at both ends of J, [τ(a), τ(a + L)], each
    /// formed from its active bound — 0 at the light's, B sin ϑ − zμ at the
    /// camera, (B ∓ μρ)/sin ϑ at the window's lower and upper end
    /// ([`window_tau`]) — not as a difference of positions: a chord from
    /// next to the light reaches the spheres with τ ≤ r₁, and r₁ may lie far
    /// below ulp(s) (`cross_segments`).
    pub(super) fn hit_with_ends(&self, dir: &Direction<T>, az: &Azimuth<T>) -> Option<(Hit<T>, [T; 2])> {
        let (hit, (lower, upper)) = self.bounded_hit(dir, az)?;
        let (s, zero) = (&dir.sin, dir.sin.lit(0.0));
        let tau_lo = match lower {
            Bound::Window => window_tau(az, &-dir.mu.clone(), &dir.one_minus_mu) / s.clone(),
            Bound::Camera => hit.path.clone(),
            Bound::Light => zero.clone(),
        };
        let tau_hi = match upper {
            Bound::Window => window_tau(az, &dir.mu, &dir.one_plus_mu) / s.clone(),
            _ => zero,
        };
        Some((hit, [tau_lo, tau_hi]))
    }

    /// The hit interval and its active (lower, upper) bounds.
    fn bounded_hit(&self, dir: &Direction<T>, az: &Azimuth<T>) -> Option<(Hit<T>, (Bound, Bound))> {
        let (s, mu, z) = (&dir.sin, &dir.mu, &self.z);
        let (bb, rho) = (&az.bcos, &az.rho);
        let zero = s.lit(0.0);
        if !(s.clone() > zero) {
            return None;
        }
        // τ is constant at μ = 0: B/sin ϑ, which must be ≥ 0.
        if mu.is_zero() && bb.clone() < zero {
            return None;
        }
        // Bμ − ρ = (B − ρ) − B(1 − μ): no cancellation as ϑ → 0 with B ≈ ρ.
        let window_lo = z.clone() + (az.minus.clone() - bb.clone() * dir.one_minus_mu.clone()) / s.clone();
        let window_hi = z.clone() + (bb.clone() * mu.clone() + rho.clone()) / s.clone();
        let light = z.clone() - bb.clone() * s.clone() / mu.clone(); // s_τ (μ ≠ 0)
        let mut lower = (Bound::Window, window_lo);
        if zero > lower.1 {
            lower = (Bound::Camera, zero.clone());
        }
        if *mu > zero && light > lower.1 {
            lower = (Bound::Light, light.clone());
        }
        let mut upper = (Bound::Window, window_hi);
        if *mu < zero && light < upper.1 {
            upper = (Bound::Light, light);
        }
        // The length from the pair of active bounds (a window narrower than
        // ulp(z) is invisible in the positions themselves); ≤ 0: no hit.
        let len = match (lower.0, upper.0) {
            (Bound::Window, Bound::Window) => s.lit(2.0) * rho.clone() / s.clone(),
            (Bound::Camera, _) => upper.1.clone(),
            (Bound::Light, Bound::Window) => (bb.clone() + rho.clone() * mu.clone()) / (s.clone() * mu.clone()),
            (Bound::Window, Bound::Light) => (rho.clone() * mu.clone() - bb.clone()) / (s.clone() * mu.clone()),
            (Bound::Light, Bound::Light) => unreachable!("the light bounds J below for μ > 0, above for μ < 0"),
            (_, Bound::Camera) => unreachable!("the camera is a lower bound only"),
        };
        if !(len > zero) {
            return None;
        }
        let path = match lower.0 {
            Bound::Window => z.clone() + dir.one_plus_mu.clone() * az.minus.clone() / s.clone(),
            Bound::Camera => bb.clone() * s.clone() - z.clone() * mu.clone(),
            Bound::Light => lower.1.clone(),
        };
        Some((Hit { start: lower.1, len, path }, (lower.0, upper.0)))
    }

    /// The kinks of the ϑ-integrand at azimuth `az` (module doc), plus
    /// decades towards the phase function's poles (Henyey–Greenstein).
    fn kinks(&self, ff: &FiniteField<T>, az: &Azimuth<T>) -> Halves<T> {
        let like = &self.z;
        let mut halves = Halves::new(like);
        let (z, bb) = (&self.z, &az.bcos);
        let r2_minus_b2 = -self.b2_minus_r2.clone();
        let mut found = Vec::new();
        // The window's ends at the camera: z sin ϑ + B cos ϑ = ±ρ.
        found.extend(roots(z, &az.plus, &(-az.minus.clone()), &self.disc_camera));
        found.extend(roots(z, &az.minus, &(-az.plus.clone()), &self.disc_camera));
        // The window's ends at the light: ρ cos ϑ = ±B.
        found.extend(roots(&like.lit(0.0), &az.plus, &az.minus, &r2_minus_b2));
        found.extend(roots(&like.lit(0.0), &(-az.minus.clone()), &(-az.plus.clone()), &r2_minus_b2));
        // s_τ = 0: z cos ϑ − B sin ϑ = 0.
        found.extend(roots(&(-bb.clone()), z, &(-z.clone()), &(bb.clone() * bb.clone() + z.clone() * z.clone())));
        for (t, tc) in found {
            if t <= tc {
                halves.cut_at(t);
            } else {
                halves.cut_before_pi(tc);
            }
        }
        halves.cut_at(like.pi() / like.lit(2.0));
        // No grading towards the poles on the light's angular scale
        // (min(b, R)/|y − o|): the primary rule clusters its nodes at a
        // piece's ends double-exponentially and the check rule bisects,
        // and the decades cost a quarter to a half of every direction
        // integral with no change in any value (`docs/model.md` §9.2).
        let (plus, minus) = ff.phase_floors();
        for d in plus.iter().flat_map(|f| decades_below(&(f.clone() / like.lit(10.0)), &(like.pi() / like.lit(2.0)))) {
            halves.cut_at(d);
        }
        for d in minus.iter().flat_map(|f| decades_below(&(f.clone() / like.lit(10.0)), &(like.pi() / like.lit(2.0)))) {
            halves.cut_before_pi(d);
        }
        halves
    }

    /// The outer variable's kinks: azimuths at which two of the ϑ-kinks of
    /// [`PointLight::kinks`] that move different ends of J cross, or one
    /// crosses ϑ = π/2 where the rates of G₂₃, G₂₄ switch, so that the
    /// ϑ-integral of a pair functional has a jump in its third derivative
    /// there (G₁, a difference of one function at J's ends, has no cross
    /// term and no rate switch: Mean and Second get none). Only for a light
    /// ahead of the camera (z > 0) and only at B = b cos χ > 0 are they
    /// active (at their mirrors J is empty or the moving end is the edge of
    /// the support, where L → 0). For b ≤ R, in χ ∈ (0, π/2), with
    /// s = √(R² − b²):
    /// - the window's lower end at the camera (z sin ϑ + B cos ϑ = ρ) meets
    ///   its upper end at the light (ρ cos ϑ = −B) where 2B² = s(z − s):
    ///   tan χ = √(b² − h)/√h, h = s(z − s)/2 ∈ (0, b²);
    /// - the window's end at the camera reaches ϑ = π/2 (z = ρ) where
    ///   b²sin²χ = R² − z²: tan χ = √((R − z)(R + z))/√((z − s)(z + s)),
    ///   s < z < R.
    ///
    /// For b > R (in η = b sin χ/R ∈ (0, 1)) only the second, at
    /// η = √((R − z)(R + z))/R, z < R. Formed from products and an
    /// arctangent, so that each keeps its accuracy near the ends of the
    /// range. Without them the two quadrature passes of C₂₃ each claimed
    /// ~10⁻¹⁵ and disagreed by ~2·10⁻¹⁰ (lights at (z, b) = (0.22, 0.1),
    /// (0.05, 0.25), (0.18, 0.25), (0.18, 0.4) with R = 0.2 ended NOT
    /// CONVERGED at the default 10⁻¹⁰).
    fn azimuth_kinks(&self, r: &T, which: Functional) -> Vec<T> {
        let (z, like) = (&self.z, &self.z);
        let zero = like.lit(0.0);
        let pair = matches!(which, Functional::Pair23 | Functional::Pair24);
        if !pair || self.b.is_zero() || *z <= zero {
            return Vec::new();
        }
        // (R − z)(R + z): the end at the camera on ϑ = π/2.
        let r2_minus_z2 = (r.clone() - z.clone()) * (r.clone() + z.clone());
        if self.b > *r {
            return if r2_minus_z2 > zero { vec![r2_minus_z2.sqrt() / r.clone()] } else { Vec::new() };
        }
        let s = (-self.b2_minus_r2.clone()).sqrt();
        let mut out = Vec::new();
        let z2_minus_s2 = (z.clone() - s.clone()) * (z.clone() + s.clone());
        if r2_minus_z2 > zero && z2_minus_s2 > zero {
            out.push((r2_minus_z2.sqrt() / z2_minus_s2.sqrt()).atan());
        }
        let h = s.clone() * (z.clone() - s) / like.lit(2.0);
        let rest = self.b.clone() * self.b.clone() - h.clone();
        if h > zero && rest > zero {
            out.push((rest.sqrt() / h.sqrt()).atan());
        }
        out
    }

    /// This light's part of μ (13), M₂ (16), C₂₃ (16), (23) or C₂₄ (18),
    /// (24): (1/2π)∫dχ ∫ sin ϑ f^k G dϑ, a nested integral (outer: the
    /// azimuth window, inner: ϑ in two halves), times the functional's
    /// constant (albedo 𝓕/(πR²))^k Φ/𝓕. Domain: R > 0, σ > 0, any light
    /// position. Deviation: the paper's (13)–(24) take f and the
    /// attenuation at the sphere's centre (§4.3); this is the estimator's
    /// exact moment (`docs/model.md` §9).
    pub fn ray_integral(&self, ff: &FiniteField<T>, which: Functional, opts: &Options) -> Outcome<T> {
        self.ray_integral_in(ff, which, opts, false, &ff.shift)
    }

    /// [`PointLight::ray_integral`] with the shift `shift` in place of the
    /// field's c₀, as a nested integral of its own (`within` false) or as
    /// levels inside a pass of an enclosing one (`within` true: the pass's
    /// rule throughout, checked by the other pass). `opts.abs_tol` applies
    /// to the integral before its constant (albedo 𝓕/(πR²))^k Φ/(2π𝓕).
    /// Used for virtual lights at the interaction points of single
    /// scattering (`virtual_lights`).
    pub(super) fn ray_integral_in(
        &self,
        ff: &FiniteField<T>,
        which: Functional,
        opts: &Options,
        within: bool,
        shift: &T,
    ) -> Outcome<T> {
        let like = &self.z;
        let (zero, one) = (like.lit(0.0), like.lit(1.0));
        let r = &ff.radius;
        let inner = |az: Azimuth<T>, jac: T, o: &Options| -> Outcome<T> {
            let halves = self.kinks(ff, &az);
            let sample = |theta: &T, theta_c: &T, _: &Options| {
                let dir = view_direction(theta, theta_c);
                let value = match self.hit(&dir, &az) {
                    Some(hit) => {
                        phase_power(&ff.phase, &dir, which.power())
                            * dir.sin.clone()
                            * functional(which, &hit, &dir, &ff.sigma, shift)
                    }
                    None => zero.clone(),
                };
                Ok(Estimate::known(value, zero.clone(), 1, o.rule))
            };
            let each = Options { abs_tol: (o.abs_tol / jac.to_f64()).min(f64::MAX), ..o.clone() };
            Ok(halves.integrate(&sample, &each)?.scaled(&jac))
        };
        // The integral's constant: applied to a failure's best guess too.
        let constant = ff.per_hit(which, &self.flux) / (like.pi() * like.lit(2.0));
        let e = if self.b > *r {
            // η = b sin χ/R ∈ [0, 1].
            let ratio = r.clone() / self.b.clone();
            outer_level(
                within,
                |eta: &T, o: &Options| {
                    let sin_chi = eta.clone() * ratio.clone();
                    let cos_chi = ((one.clone() - sin_chi.clone()) * (one.clone() + sin_chi)).sqrt();
                    let rho = r.clone() * ((one.clone() - eta.clone()) * (one.clone() + eta.clone())).sqrt();
                    let jac = ratio.clone() / cos_chi.clone();
                    inner(self.azimuth(self.b.clone() * cos_chi, rho), jac, o)
                },
                &Domain::finite(zero.clone(), one.clone()).with_breakpoints(self.azimuth_kinks(r, which)),
                opts,
            )
        } else if like.prec() > 53 && self.z > zero {
            // χ = π/2 ∓ δ, δ = (π/2)w^k, both halves folded onto w ∈ [0, 1]
            // (`FOLD_POWER`): above 53 bits, for a light ahead.
            let quarter = like.pi() / like.lit(2.0);
            let cuts: Vec<T> = self
                .azimuth_kinks(r, which)
                .into_iter()
                .map(|c| quarter.clone() - c)
                .filter(|d| *d > zero && *d < quarter)
                .map(|d| ((d / quarter.clone()).ln() / like.lit(FOLD_POWER as f64)).exp())
                .collect();
            outer_level(
                within,
                |w: &T, o: &Options| {
                    let w_k1 = (1..FOLD_POWER).fold(one.clone(), |acc, _| acc * w.clone());
                    let delta = quarter.clone() * w_k1.clone() * w.clone();
                    let jac = quarter.clone() * like.lit(FOLD_POWER as f64) * w_k1;
                    if jac.is_zero() {
                        return Ok(Estimate::known(zero.clone(), zero.clone(), 0, o.rule));
                    }
                    let bs = self.b.clone() * delta.cos();
                    let rho = ((r.clone() - bs.clone()) * (r.clone() + bs)).sqrt();
                    let bcos = self.b.clone() * delta.sin();
                    let half = Options { abs_tol: o.abs_tol / 2.0, ..o.clone() };
                    let towards = inner(self.azimuth(bcos.clone(), rho.clone()), jac.clone(), &half)?;
                    let away = inner(self.azimuth(-bcos, rho), jac, &half)?;
                    Ok(towards.plus(away))
                },
                &Domain::finite(zero.clone(), one.clone()).with_breakpoints(cuts),
                opts,
            )
        } else {
            outer_level(
                within,
                |chi: &T, o: &Options| {
                    let bs = self.b.clone() * chi.sin();
                    let rho = ((r.clone() - bs.clone()) * (r.clone() + bs)).sqrt();
                    inner(self.azimuth(self.b.clone() * chi.cos(), rho), one.clone(), o)
                },
                &Domain::finite(zero.clone(), like.pi())
                    .with_breakpoints(self.azimuth_kinks(r, which).into_iter().chain([like.pi() / like.lit(2.0)])),
                opts,
            )
        };
        e.map(|e| e.scaled(&constant)).map_err(|f| f.scaled(&constant))
    }

    /// Distance d from the light and (cos γ, sin γ) of w = (x(s) − y)/d
    /// against u, at s = center + x.
    pub(super) fn seen_from(&self, ff: &FiniteField<T>, x: &T) -> (T, T, T) {
        let (d, dz) = self.distance_to(ff, x);
        (d.clone(), dz / d.clone(), self.b.clone() / d)
    }

    /// (D, s − z): the distance from the light to the sphere's centre at
    /// s = center + x, and its axial part.
    pub(super) fn distance_to(&self, ff: &FiniteField<T>, x: &T) -> (T, T) {
        let dz = (ff.center.clone() - self.z.clone()) + x.clone(); // s − z
        ((dz.clone() * dz.clone() + self.b.clone() * self.b.clone()).sqrt(), dz)
    }

    /// ⟨𝒞^k⟩_R·e^{c₀} at s = center + x in an isotropic medium (f = 1/4π),
    /// closed form (module doc): the finite-R (19) (k = 1) and (20) (k = 2).
    /// Domain: any x; R > 0; isotropic phase only (the caller's choice).
    /// Deviation: exact at R, where (19), (20) take the field at the
    /// sphere's centre; carries the albedo (E7).
    pub fn moment_isotropic(&self, ff: &FiniteField<T>, x: &T, power: i32) -> T {
        let (d, _, _) = self.seen_from(ff, x);
        let r = &ff.radius;
        let (reach, h) = if d > *r {
            let t = ((d.clone() - r.clone()) * (d.clone() + r.clone())).sqrt();
            (t.clone(), r.clone() * r.clone() / (d.clone() * (d.clone() + t)))
        } else {
            (x.lit(0.0), x.lit(1.0))
        };
        let cap = (ff.shift.clone() - ff.sigma.clone() * reach).exp() * exp_segment(&(ff.sigma.clone() * d), Some(&h))
            / x.lit(2.0);
        let f = x.lit(1.0) / (x.pi() * x.lit(4.0));
        ff.per_hit_power(power, &self.flux) * power_of(f, power) * cap
    }

    /// ⟨𝒞^k⟩_R·e^{c₀} at s = center + x in a Henyey–Greenstein medium:
    /// a 1-D quadrature over the cap's polar angle ψ about w, the azimuthal
    /// integral of f^k in closed form. With p̂ = −sgn(g)u the peak direction
    /// and γ its angle from w, 1 + g² − 2g(−u·v) = A − B cos χ with
    /// A ∓ |B| = (1 − |g|)² + 4|g| sin²((ψ ∓ γ)/2), |B| = 2|g| sin ψ sin γ, and
    ///
    /// ∫₀^{2π} (A − B cos χ)^{−3/2} dχ = 4E(m)/((A − |B|)√(A + |B|)), 1 − m = (A − |B|)/(A + |B|),
    /// ∫₀^{2π} (A − B cos χ)^{−3} dχ = π(2A² + B²)/((A − |B|)(A + |B|))^{5/2}
    ///
    /// (E: [`crate::special::complete_elliptic_e`]; [`hg_ring`]). The peak's circle ψ = γ is declared with
    /// decades of width 1 − |g| about it. The finite-R (19) (k = 1) and (20)
    /// (k = 2). Domain: any x; R > 0; |g| < 1. Deviation: exact at R (the
    /// paper takes f at the sphere's centre); carries the albedo (E7).
    pub fn moment_cap(&self, ff: &FiniteField<T>, x: &T, power: i32, opts: &Options) -> Outcome<T> {
        let g = match ff.phase {
            Phase::HenyeyGreenstein { g } if g != 0.0 => g,
            _ => return Ok(Estimate::known(self.moment_isotropic(ff, x, power), x.lit(0.0), 1, opts.rule)),
        };
        self.cap_integral(ff, x, power, opts, &|frame, sin_g, psi, o| {
            let gamma = if g > 0.0 { &frame.psi_mirror } else { &frame.psi_u };
            Ok(Estimate::known(hg_ring(g, psi, gamma, sin_g, power), psi.lit(0.0), 1, o.rule))
        })
    }

    /// ⟨𝒞^k⟩_R·e^{c₀} at s = center + x by a 2-D quadrature over the cap,
    /// (ψ, χ) about w with the phase function's poles declared: an
    /// independent route to [`PointLight::moment_cap`] (tests). Domain: any
    /// x; R > 0.
    pub fn moment_cap_2d(&self, ff: &FiniteField<T>, x: &T, power: i32, opts: &Options) -> Outcome<T> {
        let features = phase_features(ff);
        let g = |dir: &Direction<T>, o: &Options| {
            Ok(Estimate::known(phase_power(&ff.phase, dir, power), dir.mu.lit(0.0), 1, o.rule))
        };
        self.cap_integral(ff, x, power, opts, &|frame, _, psi, o| frame.around(psi, &features, &g, o))
    }

    /// (c^k Φ/𝓕)(1/4π)∫₀^{ψ_R} sin ψ e^{c₀ − σ d cos ψ} Φ_k(ψ) dψ, with the
    /// azimuthal integral Φ_k(ψ) of f^k handed by `azimuthal(frame about w,
    /// sin γ, ψ, options)`, the phase function's peaks declared in ψ.
    fn cap_integral(
        &self,
        ff: &FiniteField<T>,
        x: &T,
        power: i32,
        opts: &Options,
        azimuthal: &Azimuthal<'_, T>,
    ) -> Outcome<T> {
        let (d, cos_g, sin_g) = self.seen_from(ff, x);
        let psi_r = cap_half_angle(&d, &ff.radius);
        let frame = Frame::new(cos_g, sin_g.clone());
        let cuts: Vec<T> = frame.psi_breakpoints(&phase_features(ff)).into_iter().filter(|p| *p < psi_r).collect();
        let front = ff.per_hit_power(power, &self.flux) / (x.pi() * x.lit(4.0));
        let e = integrate_within_pass(
            |psi: &T, o: &Options| {
                let w = cap_weight(ff, &d, psi);
                if w.is_zero() {
                    return Ok(Estimate::known(x.lit(0.0), x.lit(0.0), 0, o.rule));
                }
                let each = Options { abs_tol: (o.abs_tol / w.to_f64()).min(f64::MAX), ..o.clone() };
                Ok(azimuthal(&frame, &sin_g, psi, &each)?.scaled(&w))
            },
            &Domain::finite(x.lit(0.0), psi_r).with_breakpoints(cuts),
            &Options { abs_tol: (opts.abs_tol / front.to_f64()).min(f64::MAX), ..opts.clone() },
        )?;
        Ok(e.scaled(&front))
    }

    /// The points along the camera ray (in x) where d = R, when b < R: the
    /// sphere starts or stops containing the light. Outside them the cap's
    /// half-angle arcsin(R/d) reaches π/2 like √(d − R), so ⟨𝒞⟩_R is an
    /// analytic function of √(±(x − k)) there, with the sign (−1 for the
    /// first, +1 for the second) telling which side is outside.
    pub fn containment_kinks(&self, ff: &FiniteField<T>) -> Vec<(T, i32)> {
        if !(self.b < ff.radius) {
            return Vec::new();
        }
        let a = self.z.clone() - ff.center.clone();
        let inside = (-self.b2_minus_r2.clone()).sqrt();
        vec![(a.clone() - inside.clone(), -1), (a + inside, 1)]
    }

    /// Breakpoints along the camera ray (in x): the foot of the light, the
    /// Lorentzian of width b graded by decades, the same graded from R (the
    /// cap's size), and the two points where d = R ([`PointLight::containment_kinks`]).
    pub fn ray_breakpoints(&self, ff: &FiniteField<T>) -> Vec<T> {
        let a = self.z.clone() - ff.center.clone();
        let scale = a.abs().max_of(a.lit(1.0));
        let mut v = vec![a.clone(), a.clone() + scale.clone()];
        v.extend(graded_about(&a, &self.b, &scale));
        v.extend(graded_about(&a, &ff.radius, &scale));
        v.extend(decay_graded_about(&a, &ff.sigma, &scale));
        v.extend(self.containment_kinks(ff).into_iter().map(|(k, _)| k));
        v
    }
}

/// The power k of the fold χ = π/2 ∓ (π/2)w^k of [`PointLight::ray_integral_in`]
/// (b ≤ R, a light ahead of the camera, above 53 bits). As χ → π/2, B = b cos χ → 0
/// and the ϑ-kinks where the light's end of J meets the window's
/// (ρ cos ϑ = ±B) close in on ϑ = π/2; the χ-integrand is then singular at
/// π/2 (a B ln|B| term, by the sketch in `docs/quadrature.md`, Limits), which
/// tanh–sinh resolves and Gauss–Legendre bisection, the check, only
/// algebraically. In f64 goals that costs a few bisections; at 128 bits it
/// spent the 5·10⁷ budget (a light 10⁻⁶ from the line, 2 ahead, R = 0.01:
/// 6 336 azimuths for the check against 339 for tanh–sinh). The fold makes
/// δ ln δ a w^{2k−1} ln w that one 64-node panel integrates (and a term odd
/// in B cancels between the two halves it adds): there the mean alone took
/// 4.1·10⁶ evaluations and 27 s instead of 4.7·10⁷ and 384 s, the same
/// value, and lights at (0.005, 2) with R = 0.01 and (0.3, 0.5) with R = 0.5,
/// whose means ran past 200 s, converge in 4.5·10⁶ and 3.9·10⁶. Used above 53
/// bits only (in f64 the order-1 pair share at 10⁻³ took 22 % more
/// evaluations with it), virtual lights of single scattering included, and
/// not for a light behind the camera, where the light's end is inactive (at
/// 128 bits its mean took 1.0·10⁶ evaluations with it, 4.6·10⁵ without).
const FOLD_POWER: i32 = 6;

/// The outermost level of a ray integral: nested with its own passes, or
/// one level within an enclosing pass.
fn outer_level<T: CheckRule>(
    within: bool,
    f: impl Fn(&T, &Options) -> Outcome<T> + Sync,
    domain: &Domain<T>,
    opts: &Options,
) -> Outcome<T> {
    if within {
        integrate_within_pass(|x: &T, o: &Options| f(x, o), domain, opts)
    } else {
        integrate_nested(f, domain, opts)
    }
}

/// The structure of f(−μ)^k on the sphere of directions: the phase
/// function's peaks at ±u (width 1 − |g|), for `angular::Frame`.
pub(super) fn phase_features<T: CheckRule>(ff: &FiniteField<T>) -> Features<T> {
    let (plus, minus) = ff.phase_floors();
    Features {
        plus: Pole { floor: plus, marks: Vec::new() },
        minus: Pole { floor: minus, marks: Vec::new() },
        equator_jump: false,
        source_near_0: None,
        source_near_pi: None,
    }
}

/// The azimuthal integral of f^k at polar angle ψ about w: (frame about
/// w, sin γ, ψ, options) → value with bar.
type Azimuthal<'a, T> = dyn Fn(&Frame<T>, &T, &T, &Options) -> Outcome<T> + 'a;

/// B ± μρ (τ·sin ϑ at the window's upper end for +μ, lower end for −μ, with
/// `one_pm` = 1 ± μ), in the better conditioned of two forms: directly,
/// with an absolute error ~ε(|B| + |μ|ρ), or as (B − ρ) + ρ(1 ± μ) with
/// B − ρ from `Azimuth::minus`, ~ε(|B − ρ| + ρ(1 ± μ)). The second is exact
/// to rounding when b ≥ R (both terms ≥ 0) and as the line nears ±u with
/// B ≈ ρ; the first when B and μρ are both small (a chord from next to a
/// light inside the spheres' cylinder, nearly ⊥ u: τ ~ 10⁻¹⁷, where the
/// second form's error ε·ρ decided whether r₁ ~ 10⁻¹⁷ reached at all).
fn window_tau<T: CheckRule>(az: &Azimuth<T>, mu: &T, one_pm: &T) -> T {
    let rho = &az.rho;
    let direct_scale = az.bcos.abs() + mu.abs() * rho.clone();
    let split_scale = az.minus.abs() + rho.clone() * one_pm.clone();
    if direct_scale < split_scale {
        az.bcos.clone() + mu.clone() * rho.clone()
    } else {
        az.minus.clone() + rho.clone() * one_pm.clone()
    }
}

/// The cap's half-angle ψ_R: arcsin(R/d), formed as arctan(R/√(d² − R²))
/// (arcsin near 1 would lose half the digits as the sphere comes to hold
/// the light), or π/2 when d ≤ R (the sphere holds the light; every ray
/// whose closest point lies ahead hits).
pub(super) fn cap_half_angle<T: CheckRule>(d: &T, r: &T) -> T {
    if d > r {
        (r.clone() / ((d.clone() - r.clone()) * (d.clone() + r.clone())).sqrt()).atan()
    } else {
        d.pi() / d.lit(2.0)
    }
}

/// f(−μ)^k for k = 1 or 2.
pub(super) fn phase_power<T: Real>(phase: &Phase, dir: &Direction<T>, power: i32) -> T {
    power_of(phase_of(phase, dir), power)
}

/// x^k for k = 1 or 2.
pub(super) fn power_of<T: Real>(x: T, power: i32) -> T {
    if power == 1 {
        x
    } else {
        x.clone() * x
    }
}

/// sin ψ e^{c₀ − σ d cos ψ}: the polar measure of the cap and the chance
/// that the segment reaches the closest point, at d cos ψ, formed as
/// d − 2d sin²(ψ/2).
fn cap_weight<T: CheckRule>(ff: &FiniteField<T>, d: &T, psi: &T) -> T {
    let two = psi.lit(2.0);
    let half = (psi.clone() / two.clone()).sin();
    let reach = d.clone() - two * d.clone() * half.clone() * half;
    psi.sin() * (ff.shift.clone() - ff.sigma.clone() * reach).exp()
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(feature = "mpfr")]
    use rug::Float;

    /// At each azimuth `azimuth_kinks` declares, the ϑ-kinks it names meet:
    /// the window's lower end at the camera with its upper end at the light
    /// (z sin ϑ + B cos ϑ = ρ at cos ϑ = −B/ρ), or the end at the camera on
    /// ϑ = π/2 (z = ρ); none for a light behind the camera, on the line or
    /// for Mean and Second.
    #[test]
    fn azimuth_kinks_are_where_the_theta_kinks_meet() {
        let r = 0.2f64;
        for (z, b) in [(0.22, 0.1), (0.175, 0.1), (0.19, 0.15), (0.3, 0.19), (0.05, 0.25), (0.18, 0.4)] {
            let light = PointLight::new(z, b, 1.0, &r);
            let kinks = light.azimuth_kinks(&r, Functional::Pair23);
            assert!(!kinks.is_empty(), "({z}, {b})");
            assert_eq!(kinks, light.azimuth_kinks(&r, Functional::Pair24));
            for k in kinks {
                let chi = if b > r { (k * r / b).asin() } else { k };
                assert!(chi > 0.0 && chi < std::f64::consts::FRAC_PI_2, "({z}, {b}): χ = {chi}");
                let (bb, rho) = (b * chi.cos(), (r * r - (b * chi.sin()).powi(2)).sqrt());
                let on_half_pi = (z - rho).abs() <= 1e-14;
                let cos_t = -bb / rho;
                let sin_t = (1.0 - cos_t * cos_t).sqrt();
                let camera_meets_light = b <= r && (z * sin_t + bb * cos_t - rho).abs() <= 1e-14;
                assert!(on_half_pi || camera_meets_light, "({z}, {b}): χ = {chi} is neither crossing");
            }
            for which in [Functional::Mean, Functional::Second] {
                assert!(light.azimuth_kinks(&r, which).is_empty());
            }
            assert!(PointLight::new(-z, b, 1.0, &r).azimuth_kinks(&r, Functional::Pair23).is_empty());
        }
        assert!(PointLight::new(0.1, 0.0, 1.0, &r).azimuth_kinks(&r, Functional::Pair23).is_empty());
    }

    /// Direction (ϑ about u) with 1 ∓ μ from half angles, in the precision
    /// of `like`.
    #[cfg(feature = "mpfr")]
    fn direction<T: CheckRule>(theta: f64, like: &T) -> Direction<T> {
        let (t, two) = (like.lit(theta), like.lit(2.0));
        let (h_sin, h_cos) = ((t.clone() / two.clone()).sin(), (t.clone() / two.clone()).cos());
        Direction {
            mu: t.cos(),
            one_minus_mu: two.clone() * h_sin.clone() * h_sin,
            one_plus_mu: two * h_cos.clone() * h_cos,
            sin: t.sin(),
        }
    }

    /// τ at both ends of J ([`PointLight::hit_with_ends`], from the active
    /// bounds) against τ(s) = μ(s − z) + B sin ϑ at J's ends in 256 bits,
    /// for lights inside, at and outside the spheres' cylinder, directions
    /// near ±u (where B ∓ μρ cancels when formed as (B ± ρ) − ρ(1 ± μ)) and
    /// near ⊥u with B ≈ 0 (where (B − ρ) + ρ(1 ∓ μ) cancels) included:
    /// every τ within 10⁻¹³ of itself when b ≥ R, within the larger of
    /// that and 10³ε(|B| + |μ|ρ)/sin ϑ when b < R (352 ends, 286 of them at
    /// a window's).
    #[test]
    #[cfg(feature = "mpfr")]
    fn tau_at_the_ends_of_j_is_formed_without_cancellation() {
        let r = 0.2f64;
        let hi = Float::with_val(256, 0);
        let (mut checked, mut at_window) = (0, 0);
        for (z, b) in [(1.0f64, 0.1f64), (0.5, 0.2), (1.0, 0.2000001), (0.3, 0.25), (2.0, 1.0)] {
            let half_pi = std::f64::consts::FRAC_PI_2;
            for theta in [
                1e-6,
                1e-3,
                0.3,
                1.2,
                half_pi - 1e-12,
                1.9,
                2.8,
                std::f64::consts::PI - 1e-3,
                std::f64::consts::PI - 1e-6,
            ] {
                for chi_frac in [0.0, 0.3, 0.5 - 1e-12, 0.7, 0.999] {
                    let chi_max = if b > r { (r / b).asin() } else { std::f64::consts::PI };
                    let chi: f64 = chi_frac * chi_max;
                    // B and ρ in 256 bits, the f64 code given their roundings
                    // (ρ near the window's edge is ill-conditioned in χ).
                    let light_hi = PointLight::new(hi.lit(z), hi.lit(b), hi.lit(1.0), &hi.lit(r));
                    let rho_hi = (hi.lit(r) * hi.lit(r) - (hi.lit(b) * hi.lit(chi).sin()).square()).sqrt();
                    let bcos_hi = hi.lit(b) * hi.lit(chi).cos();
                    let (bcos, rho) = (bcos_hi.to_f64(), rho_hi.to_f64());
                    let light = PointLight::new(z, b, 1.0, &r);
                    let Some((hit, [lo, up])) = light.hit_with_ends(&direction(theta, &0.0), &light.azimuth(bcos, rho))
                    else {
                        continue;
                    };
                    let dir = direction(theta, &hi);
                    let az = light_hi.azimuth(bcos_hi, rho_hi);
                    let (h, _) = light_hi.hit_with_ends(&dir, &az).expect("the same hit in 256 bits");
                    let tau = |s: Float| dir.mu.clone() * (s - hi.lit(z)) + az.bcos.clone() * dir.sin.clone();
                    let want = [tau(h.start.clone()), tau(h.start.clone() + h.len.clone())];
                    for (got, want, end) in [(lo, &want[0], "a"), (up, &want[1], "a + L")] {
                        if !hit.len.is_finite() && end == "a + L" {
                            continue;
                        }
                        // b < R: B ∓ μρ may cancel; its error is ~ε(|B| + |μ|ρ) at most.
                        let scale = bcos.abs() + theta.cos().abs() * rho;
                        let floor = if b < r { 1e3 * f64::EPSILON * scale / theta.sin() } else { 0.0 };
                        // A window end: τ ≠ 0 (the light's is 0 to 256 bits) and not the camera.
                        if want.clone().abs() > hi.lit(1e-60) && !(end == "a" && h.start.is_zero()) {
                            at_window += 1;
                        }
                        let want = want.to_f64();
                        let off = (got - want).abs();
                        assert!(
                            off <= (1e-13 * want.abs()).max(floor),
                            "z {z} b {b} ϑ {theta} χ {chi}: τ({end}) {got:e} vs {want:e} (256 bits)"
                        );
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked > 300 && at_window > 200, "only {checked} ends checked, {at_window} at a window's");
    }
}
