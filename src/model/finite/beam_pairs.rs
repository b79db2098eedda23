//! The order-1 correlations of two spheres for a beam (isotropic media,
//! `docs/model.md` §9.11): what a beam's single-scattered light adds to
//! C₂₃ and C₂₄, by the two routes of point lights (§9.6, §9.7) with the
//! beam's interaction density
//!
//!   n(x₁) = σe^{−σt}/(πa²) inside the beam (depth t ≥ 0, within a of its axis),
//!
//! in place of a point light's σe^{−σr₁}/(4πr₁²), and the beam's ray through
//! x₁ as the first segment in place of the chord from the light.
//!
//! x₁ is integrated in cylindrical coordinates about the camera line, (z, b)
//! outside and the azimuth φ over the ring's arcs inside the beam
//! (`beam_ring`), dz db b dφ:
//! - **one scattered segment meeting both spheres**: the order-0 pair
//!   functional F(z, b) of a virtual point light at x₁ (which depends on
//!   x₁'s foot and distance only) times the ring's density
//!   ρ₂(z, b) = b∫ n dφ over its arcs, times the albedo;
//! - **the two segments of one path meeting one sphere each**: the weight W
//!   of §9.7 (`cross_segments::cross_weight`), with the spheres
//!   [s₀, s₁] that the beam's ray hits before x₁: the sphere at s is hit
//!   when its centre's projection (ξ₀ + s sin ϑ, η₀) lies within R of the
//!   ray's (ξ, η) and 0 ≤ τ(s) = depth₀ + μs ≤ t (closest point between
//!   the disk and x₁, the tracer's rule), and the hit cumulants of x₁.
//!
//! Both are four and three nested levels deep, as for point lights. The
//! first route's check is that ρ₂ integrates to 1 over the half-plane and
//! that the same average of the order-0 *mean* functional is the beam's
//! single-scattered mean of §9.8, which shares no geometry with it
//! (`the_virtual_route_gives_the_beams_scattered_mean`).

use super::beam::BeamLight;
use super::cross_segments::{cross_weight, CrossPair};
use super::hit_cumulants::HitCumulants;
use super::ray::Functional;
use super::virtual_lights::virtual_light_node;
use super::FiniteField;
use crate::model::field::graded_about;
use crate::quad::{integrate_nested, integrate_within_pass, CheckRule, Domain, Estimate, Failure, Options, Outcome};
use std::sync::OnceLock;

/// A ring geometry that could not be certified, as a quadrature failure at z.
fn ring_failure<T: CheckRule>(reason: String, z: &T) -> Failure<T> {
    Failure {
        reason: format!("{reason} (the rings about the camera line at z = {:e})", z.to_f64()),
        best_guess: None,
        error_estimate: None,
        evaluations: 1,
    }
}

/// A node of the half-plane integral: f(z, b, options).
type RingNode<'a, T> = dyn Fn(&T, &T, &Options) -> Outcome<T> + Sync + 'a;

impl<T: CheckRule> BeamLight<T> {
    /// ∫ dz ∫ db node(z, b) over the (z, b) whose rings meet the beam
    /// (`beam_ring`), z outside (nested), each b-integral's absolute goal
    /// at least `b_floor(z)`. Declared in z: the camera's ±R and 0, the
    /// disk's span, the abscissa where the axis passes closest to the camera
    /// line (graded on the scales a and |η₀|); in b: R, the camera's circle
    /// √(R² − z²); both decay at σ where unbounded.
    fn over_rings(
        &self,
        ff: &FiniteField<T>,
        node: &RingNode<'_, T>,
        opts: &Options,
        b_floor: &(dyn Fn(&T) -> f64 + Sync),
    ) -> Outcome<T> {
        let like = &self.radius;
        let (r, sigma) = (&ff.radius, &ff.sigma);
        let zero = like.lit(0.0);
        let b_level = |z: &T, o: &Options| -> Outcome<T> {
            let none = Ok(Estimate::known(zero.clone(), zero.clone(), 0, o.rule));
            let Some(span) = self.ring_span(z).map_err(|reason| ring_failure(reason, z))? else { return none };
            let (b_min, b_max) = (span.lo, span.hi);
            let mut cuts = span.kinks;
            cuts.push(r.clone());
            if z.abs() < *r {
                cuts.push(((r.clone() - z.abs()) * (r.clone() + z.abs())).sqrt());
            }
            let cuts: Vec<T> =
                cuts.into_iter().filter(|b| *b > b_min && b_max.as_ref().is_none_or(|h| b < h)).collect();
            let domain = match b_max {
                Some(h) if h > b_min => Domain::finite(b_min, h),
                Some(_) => return none,
                None => Domain::semi_infinite(b_min).with_decay(sigma.clone()),
            };
            integrate_within_pass(
                |b: &T, o2: &Options| node(z, b, o2),
                &domain.with_breakpoints(cuts),
                &Options { abs_tol: o.abs_tol.max(b_floor(z)), ..o.clone() },
            )
        };
        let (lo, hi) = self.z_support();
        let (mu, sin) = (&self.dir.mu, &self.dir.sin);
        let centre = -(self.xi0.clone() * sin.clone() + self.depth0.clone() * mu.clone());
        let half = self.radius.clone() * sin.clone();
        let mut cuts = vec![-r.clone(), zero.clone(), r.clone(), centre.clone() - half.clone(), centre + half];
        if !sin.is_zero() {
            let closest = -self.xi0.clone() / sin.clone();
            let far = like.lit(8.0) / sigma.clone();
            cuts.extend(graded_about(&closest, &self.radius, &far));
            if !self.eta0.is_zero() {
                cuts.extend(graded_about(&closest, &self.eta0.abs(), &far));
            }
            cuts.push(closest);
        }
        match (lo, hi) {
            (Some(lo), Some(hi)) => {
                let cuts: Vec<T> = cuts.into_iter().filter(|z| *z > lo && *z < hi).collect();
                integrate_nested(b_level, &Domain::finite(lo, hi).with_breakpoints(cuts), opts)
            }
            (Some(lo), None) => {
                let cuts: Vec<T> = cuts.into_iter().filter(|z| *z > lo).collect();
                integrate_nested(
                    b_level,
                    &Domain::semi_infinite(lo).with_decay(sigma.clone()).with_breakpoints(cuts),
                    opts,
                )
            }
            (None, Some(hi)) => {
                // z = hi − w, w ≥ 0.
                let cuts: Vec<T> = cuts.into_iter().filter(|z| *z < hi).map(|z| hi.clone() - z).collect();
                integrate_nested(
                    |w: &T, o: &Options| b_level(&(hi.clone() - w.clone()), o),
                    &Domain::semi_infinite(zero.clone()).with_decay(sigma.clone()).with_breakpoints(cuts),
                    opts,
                )
            }
            // `z_support` bounds at least one end (a beam runs one way along
            // the camera line or across it): an error, not a panic, if not.
            (None, None) => Err(Failure {
                reason: "a beam's interactions have no end along the camera line".into(),
                best_guess: None,
                error_estimate: None,
                evaluations: 0,
            }),
        }
    }

    /// ρ₂(z, b)·e^{σt_lo} = b∫ σe^{−σ(t − t_lo)}/(πa²) dφ over the ring's
    /// arcs inside the beam, t_lo the least depth on them (t = D₀ +
    /// b sin ϑ cos φ is least at φ = π, else at an arc's end; ≥ 0), with
    /// t_lo; relative goal only (the caller scales it). Taken over the arcs,
    /// not the whole ring (D₀ − b sin ϑ), so that e^{−σ(t − t_lo)} does not
    /// underflow on arcs that lie deep in the beam when σa is large.
    /// Declared: φ = π, where e^{−σb sin ϑ cos φ} peaks.
    fn ring_density(
        &self,
        ff: &FiniteField<T>,
        z: &T,
        b: &T,
        arcs: &[[T; 2]],
        opts: &Options,
    ) -> Result<(Estimate<T>, T), Failure<T>> {
        let like = b;
        let sigma = &ff.sigma;
        let zero = like.lit(0.0);
        let pi = like.pi();
        let t_lo = arcs
            .iter()
            .flat_map(|[lo, hi]| {
                let mut at = vec![lo.clone(), hi.clone()];
                if *lo < pi && pi < *hi {
                    at.push(pi.clone());
                }
                at
            })
            .map(|phi| self.ring_depth(z, b, &phi))
            .reduce(|a, c| a.min_of(c))
            .unwrap_or_else(|| zero.clone())
            .max_of(zero.clone());
        let front = sigma.clone() * b.clone() / (pi.clone() * self.radius.clone() * self.radius.clone());
        let o = Options { abs_tol: 0.0, ..opts.clone() };
        let mut total = Estimate::known(zero.clone(), zero.clone(), 0, o.rule);
        for [lo, hi] in arcs {
            let f = |phi: &T, o2: &Options| {
                let t = self.ring_depth(z, b, phi);
                Ok(Estimate::known((-(sigma.clone() * (t - t_lo.clone()))).exp(), zero.clone(), 1, o2.rule))
            };
            let cuts = (pi > *lo && pi < *hi).then_some(pi.clone());
            total = total.plus(integrate_within_pass(
                f,
                &Domain::finite(lo.clone(), hi.clone()).with_breakpoints(cuts),
                &o,
            )?);
        }
        Ok((total.scaled(&front), t_lo))
    }

    /// Absolute floors for the inner integrals of a nested pass that asks
    /// them for a relative goal only (the coarse pass), which values far
    /// out along the beam (10⁻²⁸ at z = 22) could not meet against their
    /// own nodes' floors: `total` spread over the half-plane as the weight
    /// w(z, b) = (σ/2)e^{−σ|z − z_c|}·(σ/2)e^{−σ|b − |η₀||} about the axis's
    /// closest approach to the camera line (z_c = −ξ₀/sin ϑ; 0 for a beam
    /// along it), which integrates to at most 1: (per b-integral at z,
    /// total·(σ/2)e^{−σ|z − z_c|}; per node, total·w). All of them together
    /// add at most `total` to the result.
    #[allow(clippy::type_complexity)]
    fn floors(
        &self,
        ff: &FiniteField<T>,
        total: f64,
    ) -> (Box<dyn Fn(&T) -> f64 + Sync>, Box<dyn Fn(&T, &T) -> f64 + Sync>) {
        let (s, e) = (ff.sigma.to_f64(), self.eta0.abs().to_f64());
        let z_c = if self.dir.sin.is_zero() { 0.0 } else { -(self.xi0.clone() / self.dir.sin.clone()).to_f64() };
        let along = move |z: &T| total * s / 2.0 * (-(s * (z.to_f64() - z_c).abs())).exp();
        let node = move |z: &T, b: &T| along(z) * s / 2.0 * (-(s * (b.to_f64() - e).abs())).exp();
        (Box::new(along), Box::new(node))
    }

    /// The spheres [s₀, s₁] = [s₀, s₀ + ℓ] that the beam's ray through the
    /// ring point (z, b, φ) hits before it reaches it, and that point's
    /// depth t, or `None` (module docs): the window |ξ − ξ₀ − s sin ϑ| ≤
    /// ρ_w = √(R² − b² sin²φ) (all s for a beam along the line, b ≤ R), the
    /// beam's range (s ≥ 0, τ(s) ≥ 0) and τ(s) ≤ t. ℓ is formed as 2ρ_w/sin ϑ
    /// when the window bounds both ends and as t/|μ| when τ does, else as
    /// the difference (the density is bounded: no chord is shorter than its
    /// ends' rounding matters for).
    fn chord_hits(&self, ff: &FiniteField<T>, z: &T, b: &T, phi: &T) -> Option<(T, T, T, T)> {
        let like = b;
        let zero = like.lit(0.0);
        let r = &ff.radius;
        let (lo0, hi0) = self.range.clone()?;
        let (mu, sin) = (&self.dir.mu, &self.dir.sin);
        let t = self.ring_depth(z, b, phi);
        if t < zero {
            return None;
        }
        let across = (b.clone() * phi.sin()).abs();
        if across > *r {
            return None;
        }
        // (value, kind): 0 window, 1 range/τ ≥ 0, 2 camera s ≥ 0, 3 reach τ ≤ t.
        let mut lows: Vec<(T, u8)> = vec![(lo0.clone(), if lo0.is_zero() { 2 } else { 1 })];
        let mut highs: Vec<(T, u8)> = hi0.iter().map(|h| (h.clone(), 1)).collect();
        let rho = ((r.clone() - across.clone()) * (r.clone() + across)).sqrt();
        if sin.is_zero() {
            if *b > *r {
                return None;
            }
        } else {
            let m = z.clone() - b.clone() * mu.clone() * phi.cos() / sin.clone();
            let delta = rho.clone() / sin.clone();
            lows.push((m.clone() - delta.clone(), 0));
            highs.push((m + delta, 0));
        }
        if *mu > zero {
            highs.push(((t.clone() - self.depth0.clone()) / mu.clone(), 3));
        } else if *mu < zero {
            lows.push(((t.clone() - self.depth0.clone()) / mu.clone(), 3));
        } else if self.depth0 > t {
            return None;
        }
        let pick = |v: Vec<(T, u8)>, high: bool| {
            v.into_iter().reduce(|p, q| if (q.0 < p.0) == high { q } else { p }).expect("the range gives a lower end")
        };
        let (s0, k0) = pick(lows, false);
        let Some((s1, k1)) = (!highs.is_empty()).then(|| pick(highs, true)) else {
            return Some((s0, like.lit(f64::INFINITY), like.lit(f64::INFINITY), t));
        };
        let len = match (k0, k1) {
            (0, 0) => like.lit(2.0) * rho / sin.clone(),
            (1, 3) | (3, 1) => t.clone() / mu.abs(),
            _ => s1.clone() - s0.clone(),
        };
        (len > zero).then_some((s0, s1, len, t))
    }

    /// albedo ∫ n(x₁) F(x₁) d³x₁: the order-0 ray functional `which` of a
    /// virtual point light at the interaction point x₁ averaged over the
    /// beam's interactions (module docs), times e^{c₀}. For Mean it is the
    /// beam's single-scattered part of μ by a route that shares no geometry
    /// with §9.8's; for Pair23, Pair24 the one-segment-two-spheres part of
    /// C₂₃, C₂₄. Domain: R > 0, σ > 0, isotropic media.
    pub(super) fn virtual_average(&self, ff: &FiniteField<T>, which: Functional, opts: &Options) -> Outcome<T> {
        let sigma = &ff.sigma;
        let zero = self.radius.lit(0.0);
        // Floors for the inner integrals of the coarse pass (relative goals
        // only), as for the cross part (`floors`): a node's product
        // ρ₂F may stop at rel·scale/100 times the plane's weight there, and
        // each b-integral at that weight's integral over b.
        let scale = self
            .ray_integral(ff, which, &Options { rel_tol: 1e-3, abs_tol: 0.0, ..opts.clone() })?
            .value
            .abs()
            .to_f64();
        let (b_floor, node_floor) = self.floors(ff, opts.rel_tol * scale / 100.0);
        let node = |z: &T, b: &T, o2: &Options| -> Outcome<T> {
            let arcs = self.ring_arcs(z, b).map_err(|reason| ring_failure(reason, z))?;
            if arcs.is_empty() || b.is_zero() {
                return Ok(Estimate::known(zero.clone(), zero.clone(), 1, o2.rule));
            }
            let (dens, t_lo) = self.ring_density(ff, z, b, &arcs, o2)?;
            if dens.value.is_zero() {
                return Ok(Estimate::known(zero.clone(), zero.clone(), dens.evaluations, o2.rule));
            }
            let shift = ff.shift.clone() - sigma.clone() * t_lo;
            let allowed = (o2.abs_tol.max(node_floor(z, b)) / dens.value.to_f64()).min(f64::MAX);
            virtual_light_node(ff, which, &self.flux, [z, b], &dens, &shift, allowed, o2)
        };
        let o = Options { abs_tol: (opts.abs_tol / ff.albedo.to_f64()).min(f64::MAX), ..opts.clone() };
        Ok(self.over_rings(ff, &node, &o, &b_floor)?.scaled(&ff.albedo))
    }

    /// The two segments of one path meeting one sphere each, X₂₃ or X₂₄ of
    /// §9.7 for this beam (module docs), times e^{c₀}. Domain: R > 0,
    /// σ > 0, isotropic media.
    pub(super) fn cross_segments(&self, ff: &FiniteField<T>, pair: CrossPair, opts: &Options) -> Outcome<T> {
        let like = &self.radius;
        let (r, sigma) = (&ff.radius, &ff.sigma);
        let zero = like.lit(0.0);
        let which = match pair {
            CrossPair::C23 => Functional::Pair23,
            CrossPair::C24 => Functional::Pair24,
        };
        let f = like.lit(1.0) / (like.pi() * like.lit(4.0));
        let kappa = ff.per_hit_power(2, &self.flux) * f.clone() * f * ff.albedo.clone();
        let scale =
            (self.ray_integral(ff, which, &Options { rel_tol: 1e-3, abs_tol: 0.0, ..opts.clone() })?.value.abs()
                / kappa.clone())
            .to_f64();
        let (b_floor, node_floor) = self.floors(ff, opts.rel_tol * scale / 100.0);
        let dens = sigma.clone() / (like.pi() * self.radius.clone() * self.radius.clone());
        let node = |z: &T, b: &T, o2: &Options| -> Outcome<T> {
            let nothing = Ok(Estimate::known(zero.clone(), zero.clone(), 1, o2.rule));
            let arcs = self.ring_arcs(z, b).map_err(|reason| ring_failure(reason, z))?;
            if arcs.is_empty() || b.is_zero() {
                return nothing;
            }
            let each = Options { abs_tol: o2.abs_tol.max(node_floor(z, b)).min(f64::MAX), ..o2.clone() };
            let cumulants: OnceLock<Result<HitCumulants<T>, Failure<T>>> = OnceLock::new();
            let density = dens.clone() * b.clone();
            let weight = |phi: &T, o: &Options| -> Outcome<T> {
                let none = Ok(Estimate::known(zero.clone(), zero.clone(), 1, o.rule));
                let Some((s0, s1, len, t)) = self.chord_hits(ff, z, b, phi) else { return none };
                if (ff.shift.clone() - sigma.clone() * (t.clone() + s0.clone())).exp().is_zero() {
                    return none;
                }
                let first = cumulants.get().is_none();
                let c = cumulants.get_or_init(|| HitCumulants::new(sigma, r, z, b));
                let c = c.as_ref().map_err(Failure::clone)?;
                let evaluations = if first { 1 + c.evaluations } else { 1 };
                let (value, error) = cross_weight(ff, pair, c, [&s0, &s1, &len], &t, &density, o.rel_tol, [z, b])?;
                Ok(Estimate::known(value, error, evaluations, o.rule))
            };
            let mut edges = Vec::new();
            if *b > *r {
                let w = (r.clone() / b.clone()).asin();
                let pi = like.pi();
                edges.extend([w.clone(), pi.clone() - w.clone(), pi.clone() + w.clone(), pi * like.lit(2.0) - w]);
            }
            if self.dir.mu.is_zero() {
                let half_pi = like.pi() / like.lit(2.0);
                edges.extend([half_pi.clone(), half_pi * like.lit(3.0)]);
            }
            let share = Options { abs_tol: each.abs_tol / arcs.len() as f64, ..each.clone() };
            let mut total = Estimate::known(zero.clone(), zero.clone(), 0, o2.rule);
            for [lo, hi] in &arcs {
                let cuts: Vec<T> = edges.iter().filter(|p| *p > lo && *p < hi).cloned().collect();
                let domain = Domain::finite(lo.clone(), hi.clone()).with_breakpoints(cuts);
                total = total.plus(integrate_within_pass(&weight, &domain, &share)?);
            }
            Ok(total)
        };
        let o = Options { abs_tol: (opts.abs_tol / kappa.to_f64()).min(f64::MAX), ..opts.clone() };
        let e = self.over_rings(ff, &node, &o, &b_floor).map_err(|f| f.scaled(&kappa))?;
        Ok(e.scaled(&kappa))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::field::Field;
    use crate::model::finite::FiniteLight;
    use mcrt_scene::{DVec3, Light, ScatteringOrders, Scene};

    /// `beam-isotropic` at order 1 with R and the beam's direction and centre.
    fn scene(radius: f64, direction: DVec3, center: DVec3) -> Scene {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/beam-isotropic.toml");
        let mut s = Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        s.effects.scattering_orders = ScatteringOrders::Limited(1);
        s.estimator.radius = radius;
        let Light::Beam { radius: a, flux, .. } = s.lights[0] else { panic!("the scene has a beam") };
        s.lights[0] = Light::Beam { center, direction: direction.normalize(), radius: a, flux };
        s
    }

    fn beam_of(s: &Scene) -> (FiniteField<f64>, BeamLight<f64>) {
        let field = Field::from_scene(s, &1.0f64).unwrap();
        let ff = FiniteField::of_first_segments(s, &field);
        let FiniteLight::Beam(b) = ff.lights[0].clone() else { panic!("a beam") };
        (ff, b)
    }

    /// The geometries the tests run: across the camera ray (the bundled
    /// scene), slanted towards it, and nearly along it from behind.
    fn geometries() -> Vec<(DVec3, DVec3)> {
        vec![
            (DVec3::new(1.0, 0.0, 0.0), DVec3::new(-2.0, 0.0, 1.0)),
            (DVec3::new(1.0, 0.3, 0.6), DVec3::new(-1.5, -0.2, 0.0)),
            (DVec3::new(0.1, 0.05, 1.0), DVec3::new(-0.3, 0.2, -1.0)),
        ]
    }

    /// ∫∫ ρ₂ dz db = ∫ n d³x₁ = 1: the half-plane, the rings' arcs and
    /// the density together hold every interaction of the beam.
    #[test]
    fn ring_density_integrates_to_one() {
        let goal = 1e-6;
        // And a thin beam far from the camera line in a thin medium (a
        // review's counterexample: 14.5 % of its interactions were lost to a
        // tolerance of a's ulps on the section's boundary points).
        let thin = (DVec3::new(1.0, 0.0, 0.5), DVec3::new(-2.0, 1.0, 1.5));
        for (k, (direction, center)) in geometries().into_iter().chain([thin]).enumerate() {
            let t = std::time::Instant::now();
            let mut s = scene(0.2, direction, center);
            if k == 3 {
                let Light::Beam { center, direction, flux, .. } = s.lights[0] else { panic!("a beam") };
                s.lights[0] = Light::Beam { center, direction, radius: 0.01, flux };
                s.medium.sigma_ext = 0.1;
            }
            let (ff, beam) = beam_of(&s);
            let o = Options { rule: crate::quad::Rule::Kronrod, ..Options::rel(goal).declared() };
            let node = |z: &f64, b: &f64, o2: &Options| -> Outcome<f64> {
                let arcs = beam.ring_arcs(z, b).unwrap();
                if arcs.is_empty() {
                    return Ok(Estimate::known(0.0, 0.0, 1, o2.rule));
                }
                let (d, t_lo) = beam.ring_density(&ff, z, b, &arcs, o2)?;
                Ok(d.scaled(&(-ff.sigma * t_lo).exp()))
            };
            let e = beam.over_rings(&ff, &node, &o, &|_: &f64| 0.0).unwrap();
            println!(
                "{direction:?}: ∫ρ₂ = {:.12} ± {:.1e} ({} evaluations) [{:.1?}]",
                e.value,
                e.error,
                e.evaluations,
                t.elapsed()
            );
            assert!((e.value - 1.0).abs() <= e.error + 1e-12 && e.error < 1e-7, "{e:?}");
        }
    }

    /// A ring whose arcs lie deep in a dense beam while its shallowest
    /// point lies outside it (the bundled beam across the camera ray at
    /// σ = 300, the ring b = 3 at its axis's height: arcs at depth ~4.96,
    /// the ring's least depth −1): ρ₂e^{σt_lo} is taken from the arcs'
    /// least depth and equals a midpoint sum of its integrand; from the
    /// whole ring's (t_lo = 0) every sample underflowed (σ·4.96 = 1488).
    #[test]
    fn ring_density_keeps_rings_deep_in_a_dense_beam() {
        let (direction, center) = geometries()[0];
        let mut s = scene(0.2, direction, center);
        s.medium.sigma_ext = 300.0;
        let (ff, beam) = beam_of(&s);
        let (z, b) = (1.0f64, 3.0f64);
        let arcs = beam.ring_arcs(&z, &b).unwrap();
        assert!(!arcs.is_empty());
        let o = Options::rel(1e-10);
        let (d, t_lo) = beam.ring_density(&ff, &z, &b, &arcs, &o).unwrap();
        assert!(t_lo > 4.9 && d.value > 0.0, "t_lo {t_lo}, ρ₂e^(σt_lo) {}", d.value);
        let a = 0.5f64;
        let n = 200_000;
        let brute: f64 = arcs
            .iter()
            .map(|[lo, hi]| {
                let h = (hi - lo) / n as f64;
                (0..n)
                    .map(|i| {
                        let phi = lo + (i as f64 + 0.5) * h;
                        let t = beam.ring_depth(&z, &b, &phi);
                        ff.sigma * b * (-ff.sigma * (t - t_lo)).exp() / (std::f64::consts::PI * a * a) * h
                    })
                    .sum::<f64>()
            })
            .sum();
        assert!((d.value - brute).abs() <= 1e-6 * brute, "{} vs {brute}", d.value);
    }

    /// The virtual-light average of the order-0 mean functional is the
    /// beam's single-scattered mean of §9.8 (sphere-centric, the beam's
    /// volume in spherical shells about each sphere: no shared geometry).
    #[test]
    fn the_virtual_route_gives_the_beams_scattered_mean() {
        for (direction, center) in geometries() {
            let s = scene(0.2, direction, center);
            let (ff, beam) = beam_of(&s);
            let goal = 1e-3;
            let o = Options { rule: crate::quad::Rule::Kronrod, ..Options::rel(goal).declared() };
            let t = std::time::Instant::now();
            let shells = ff.scattered_mean(&o).unwrap();
            let lights = beam.virtual_average(&ff, Functional::Mean, &o).unwrap();
            let gap = (shells.value - lights.value).abs();
            println!(
                "{direction:?}: shells {:.10e} ± {:.1e}, virtual lights {:.10e} ± {:.1e} ({} evaluations), gap {:.1e} [{:.1?}]",
                shells.value,
                shells.error,
                lights.value,
                lights.error,
                lights.evaluations,
                gap / shells.value,
                t.elapsed()
            );
            assert!(gap <= shells.error + lights.error, "the routes disagree");
        }
    }
}
