//! A beam's single-scattered light as the small-sphere field sees it
//! (isotropic media, `docs/model.md` §3a): where along the camera ray it
//! bends, and its fluence there, the volume integral of
//! `model::beam_source` with the small-sphere kernel e^{−σd}/d².

#[cfg(test)]
use super::beam_source::BeamFrame;
use super::beam_source::BeamPoint;
use crate::quad::{CheckRule, Estimate, Options, Outcome};
use crate::real::Real;
#[cfg(test)]
use mcrt_scene::DVec3;

/// A beam's single-scattered light as the small-sphere field sees it
/// (isotropic media): its fluence ∫L₁dω at the camera-ray points, from the
/// beam's frame (as `finite::beam`: the camera origin at (ξ₀, η₀) across,
/// depth₀ along; the ray at angle ϑ to v_b, cos ϑ = μ).
#[derive(Debug, Clone)]
pub struct ScatteredBeam<T> {
    /// Disk radius a.
    pub radius: T,
    /// Flux Φ.
    pub flux: T,
    /// μ = u·v_b.
    pub mu: T,
    /// sin ϑ = |u × v_b|.
    pub sin: T,
    /// The camera origin across the beam, along e_m = v_b × e_n (e_n ∥ u × v_b).
    pub xi0: T,
    /// The camera origin across the beam, along e_n.
    pub eta0: T,
    /// The camera origin's depth past the disk.
    pub depth0: T,
    /// The scale c_b of its fluence ([`super::field::Field::beams_shift`]).
    pub shift: T,
    /// The field's [`super::field::Field::center`].
    pub center: T,
}

#[cfg(test)]
impl ScatteredBeam<f64> {
    /// The tests' beam: radius `a`, flux 1, from `center` along
    /// `direction`, seen from the camera ray from the origin along +z
    /// (scale c_b = 0, field centre 0).
    pub(crate) fn seen_along_z(center: DVec3, direction: DVec3, a: f64) -> ScatteredBeam<f64> {
        let frame = BeamFrame::new(DVec3::ZERO, DVec3::Z, center, direction.normalize());
        ScatteredBeam {
            radius: a,
            flux: 1.0,
            mu: frame.mu,
            sin: frame.sin,
            xi0: frame.xi0,
            eta0: frame.eta0,
            depth0: frame.depth0,
            shift: 0.0,
            center: 0.0,
        }
    }
}

impl<T: Real> ScatteredBeam<T> {
    /// Where the camera-ray point s = center + x sits against the beam.
    fn point(&self, x: &T, sigma: &T) -> BeamPoint<T> {
        let s = self.center.clone() + x.clone();
        let across = self.xi0.clone() + s.clone() * self.sin.clone();
        BeamPoint {
            a: self.radius.clone(),
            p: (across.clone() * across + self.eta0.clone() * self.eta0.clone()).sqrt(),
            tau: self.depth0.clone() + self.mu.clone() * s,
            sigma: sigma.clone(),
        }
    }

    /// An upper bound of [`ScatteredBeam::fluence`] at x: every path from
    /// the disk to x through a first interaction is at least
    /// ℓ = max(dist(x, beam), τ⁺) long (`beam_scattered_path`), and
    /// ∫ n/d² over the beam is at most 8σ/a (the ball of radius a about x
    /// gives ≤ 4πa·σ/(πa²), the rest, at d ≥ max(a, |t − τ|), ≤ 4πa·σ/(πa²)
    /// too), with e^{−σ(t + d)} ≤ e^{−σℓ}: albedo Φ f e^{c_b − σℓ}·8σ/a
    /// (c_b this light's `shift`, the scale of [`ScatteredBeam::fluence`]).
    pub fn fluence_bound(&self, x: &T, sigma: &T, albedo: &T) -> T {
        let at = self.point(x, sigma);
        let zero = x.lit(0.0);
        let across = (at.p.clone() - at.a.clone()).max_of(zero.clone());
        let before = (-at.tau.clone()).max_of(zero.clone());
        let dist2 = across.clone() * across + before.clone() * before;
        let path = dist2.clone().sqrt().max_of(at.tau.clone());
        let volume = x.lit(8.0) * sigma.clone() / at.a.clone();
        let front = albedo.clone() * self.flux.clone() / (x.pi() * x.lit(4.0));
        front * volume * (self.shift.clone() - sigma.clone() * path).exp()
    }

    /// Where along the camera ray (in x) the fluence bends: the ray
    /// crossing the disk's plane (τ = 0) and the beam's surface (p = a).
    pub fn ray_breakpoints(&self) -> Vec<T> {
        let mut out = self.surface_crossings();
        if !self.mu.is_zero() {
            let s = -self.depth0.clone() / self.mu.clone();
            if s > self.radius.lit(0.0) {
                out.push(s - self.center.clone());
            }
        }
        out
    }

    /// Decades (in x) about the camera ray's closest approach to the beam's
    /// axis, s* = −ξ₀/sin ϑ, from the width max(4a, |η₀|)/sin ϑ out to
    /// 1/(σ sin ϑ): seen from outside a thin beam the fluence falls like a
    /// line source's, ~1/p in the distance p from the axis, out to about a
    /// decay length, and along the ray p grows as sin ϑ·|s − s*| (a near
    /// miss, |η₀| > a, peaks there as a Lorentzian of width |η₀|/sin ϑ). A
    /// piece spanning ln p over several decades cost the along-ray tables
    /// their samples: with the surface crossings' decades alone (out to
    /// 4a), a beam of radius 10⁻³ crossing the ray needed 1 200–1 328
    /// fluence samples per table, and one of 10⁻⁵ spent the oracle's 10⁹
    /// evaluations at 10⁻⁴. Empty for a beam parallel to the ray, or whose
    /// axis passes closest behind the camera.
    pub fn line_source_grading(&self, sigma: &T) -> Vec<T> {
        let zero = self.radius.lit(0.0);
        if !(self.sin > zero) {
            return Vec::new();
        }
        let closest = -self.xi0.clone() / self.sin.clone();
        if !(closest > zero) {
            return Vec::new();
        }
        let near = (self.radius.clone() * self.radius.lit(4.0)).max_of(self.eta0.clone().abs());
        let width = near / self.sin.clone();
        let scale = self.radius.lit(1.0) / (sigma.clone() * self.sin.clone());
        crate::model::field::graded_about(&(closest - self.center.clone()), &width, &scale)
    }

    /// Where (in x) the plane through the camera-ray point normal to u
    /// touches the disk's rim, s = (c − o)·u ± a sin ϑ (c the disk's
    /// centre): there the rim's directions, where the beam's radiance by
    /// direction bends (`beam_angular`), cross the equator μ = 0, where the
    /// pair integrals' g jumps, so their integrand along the ray bends
    /// (for a beam across the ray, μ = 0, these are also where that plane
    /// touches the cylinder). Ahead of the camera only.
    pub fn equator_crossings(&self) -> Vec<T> {
        let zero = self.radius.lit(0.0);
        let centre = -(self.xi0.clone() * self.sin.clone() + self.depth0.clone() * self.mu.clone());
        let half = self.radius.clone() * self.sin.clone();
        [centre.clone() - half.clone(), centre + half]
            .into_iter()
            .filter(|s| *s > zero)
            .map(|s| s - self.center.clone())
            .collect()
    }

    /// Where (in x) the camera ray crosses the beam's cylindrical surface
    /// p = a, ahead of the camera.
    pub fn surface_crossings(&self) -> Vec<T> {
        let zero = self.radius.lit(0.0);
        let mut s_points = Vec::new();
        if !self.sin.is_zero() {
            let a = &self.radius;
            let h2 = (a.clone() - self.eta0.clone()) * (a.clone() + self.eta0.clone());
            // (h2 = 0: the ray touches the surface; graded there too.)
            if h2 >= zero {
                let h = h2.sqrt();
                s_points.push((-self.xi0.clone() - h.clone()) / self.sin.clone());
                s_points.push((h - self.xi0.clone()) / self.sin.clone());
            }
        }
        s_points.into_iter().filter(|s| *s > zero).map(|s| s - self.center.clone()).collect()
    }
}

impl<T: CheckRule> ScatteredBeam<T> {
    /// ∫L₁dω·e^{c_b} at s = center + x (c_b this light's `shift`), one level inside a pass: the
    /// single-scattered fluence σ_sc f ∫E(x′)e^{−σ|x − x′|}/|x − x′|² d³x′
    /// of the beam's irradiance E (f = 1/4π), = albedo Φ f ∫ n(x₁)
    /// e^{−σd}/d² d³x₁ (module docs). Domain: any x; σ > 0. Deviation: the
    /// paper's §3a has no beams at order 1.
    pub fn fluence(&self, x: &T, sigma: &T, albedo: &T, opts: &Options) -> Outcome<T> {
        let front = albedo.clone() * self.flux.clone() / (x.pi() * x.lit(4.0));
        if front.is_zero() {
            return Ok(Estimate::known(x.lit(0.0), x.lit(0.0), 0, opts.rule));
        }
        let o = Options { abs_tol: (opts.abs_tol / front.to_f64()).min(f64::MAX), ..opts.clone() };
        // d²·σe^{c₀ − σt}e^{−σd}/d².
        let kernel =
            |t: &T, d: &T| sigma.clone() * (self.shift.clone() - sigma.clone() * (t.clone() + d.clone())).exp();
        Ok(self.point(x, sigma).integral(&kernel, None, &o, true)?.scaled(&front))
    }
}
