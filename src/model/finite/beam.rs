//! A collimated disk beam in the finite-sphere model (`docs/model.md` §9.3).
//!
//! Every ray of the beam travels along v_b; it starts at a point of the
//! emitting disk (radius a_b, centre c_b, normal v_b), uniformly. In the
//! disk's plane take e_n ∥ u × v_b and e_m = v_b × e_n: the sphere at x(s)
//! projects to P(s) = (ξ₀ + s sin ϑ, η₀) (ξ₀, η₀ the camera origin's
//! coordinates), and the closest point of every ray to it lies at the
//! depth τ(s) = depth₀ + μ s past the disk, the same for all rays. A ray
//! through (ξ, η) = (ξ₀ + m sin ϑ, η₀ + Rζ) hits the sphere at s when
//! |m − s| ≤ δ = ρ/sin ϑ, ρ = R√(1 − ζ²), with s ≥ 0 and τ(s) ≥ 0 (the
//! interval [lo₀, hi₀]): its hit interval is
//! J = [max(m − δ, lo₀), min(m + δ, hi₀)], and dξ dη = R sin ϑ dm dζ.
//!
//! Ray-centric integrals: (1/πa_b²)∫∫ over the disk, outer ζ ∈ [−1, 1]
//! (cut by the disk's extent in η), inner m over the rays of the disk at
//! that ζ, with kinks at lo₀ ± δ, hi₀ ± δ; the outer integrand has kinks
//! where those meet the disk's rim (the circles of radius R about P(lo₀)
//! and P(hi₀) cross the rim) and where 2δ = hi₀ − lo₀.
//!
//! Sphere-centric: ⟨𝒞^k⟩_R(s) = (albedo 𝓕/(πR²))^k (Φ/𝓕) f(−μ)^k e^{−στ(s)}
//! · area(disc(P(s), R) ∩ beam)/(πa_b²), closed form ([`disc_overlap`]).
//!
//! A beam parallel to the camera line (sin ϑ = 0) projects every sphere to
//! one point: then the hit probability is that overlap for all s, and the
//! hit interval is [lo₀, hi₀] for every ray that hits, in closed form.

use super::point::phase_power;
use super::ray::{functional, Functional, Hit};
use super::FiniteField;
use crate::model::angular::Direction;
use crate::quad::{
    decay_lengths, integrate_nested, integrate_within_pass, CheckRule, Domain, Estimate, Options, Outcome,
};
use crate::special::disc_overlap;

/// A beam as the finite-sphere model sees it.
#[derive(Debug, Clone)]
pub struct BeamLight<T> {
    /// Flux Φ of the beam.
    pub flux: T,
    /// Disk radius a_b.
    pub radius: T,
    /// The direction against u: μ = u·v_b, 1 ± μ and sin ϑ = |u × v_b|.
    pub dir: Direction<T>,
    /// The camera origin in the disk's frame: (ξ₀, η₀) across, depth₀ along.
    /// ξ₀ = (o − c_b)·e_m.
    pub xi0: T,
    /// η₀ = (o − c_b)·e_n.
    pub eta0: T,
    /// depth₀ = (o − c_b)·v_b.
    pub depth0: T,
    /// Where on the camera line the depth is ≥ 0 (and s ≥ 0): [lo₀, hi₀]
    /// (hi₀ = `None`: ∞); `None` when nowhere.
    pub range: Option<(T, Option<T>)>,
}

impl<T: CheckRule> BeamLight<T> {
    /// From the beam's direction cosine μ with u, sin ϑ, the camera
    /// origin's coordinates in the disk's frame, the disk radius and flux.
    pub fn new(mu: T, sin: T, xi0: T, eta0: T, depth0: T, radius: T, flux: T) -> Self {
        // 1 ∓ μ: the one that can be small as sin²/(1 ± μ), which keeps a
        // beam nearly along the camera line (μ → ±1) accurate.
        let one = mu.lit(1.0);
        let sin2 = sin.clone() * sin.clone();
        let (one_minus_mu, one_plus_mu) = if mu >= mu.lit(0.0) {
            (sin2 / (one.clone() + mu.clone()), one + mu.clone())
        } else {
            (one.clone() - mu.clone(), sin2 / (one - mu.clone()))
        };
        let dir = Direction { one_minus_mu, one_plus_mu, mu: mu.clone(), sin };
        let zero = mu.lit(0.0);
        let range = if mu > zero {
            Some(((-depth0.clone() / mu.clone()).max_of(zero), None))
        } else if mu < zero {
            let hi = -depth0.clone() / mu.clone();
            (hi > zero).then_some((zero, Some(hi)))
        } else {
            (depth0 >= zero).then_some((zero, None))
        };
        BeamLight { flux, radius, dir, xi0, eta0, depth0, range }
    }

    fn weight(&self, ff: &FiniteField<T>, which: Functional) -> T {
        let fk = phase_power(&ff.phase, &self.dir, which.power());
        ff.per_hit(which, &self.flux) * fk / (self.radius.pi() * self.radius.clone() * self.radius.clone())
    }

    /// The hit interval of the ray crossing at m (window half-length δ).
    fn hit(&self, m: &T, delta: &T) -> Option<Hit<T>> {
        let (lo0, hi0) = self.range.as_ref()?;
        let win_lo = m.clone() - delta.clone();
        let win_hi = m.clone() + delta.clone();
        let clipped_lo = win_lo < *lo0;
        let start = if clipped_lo { lo0.clone() } else { win_lo };
        let clipped_hi = hi0.as_ref().is_some_and(|h| win_hi > *h);
        let len = match (clipped_lo, clipped_hi, hi0) {
            (false, false, _) => m.lit(2.0) * delta.clone(),
            (true, false, _) => (m.clone() - lo0.clone()) + delta.clone(),
            (false, true, Some(h)) => (h.clone() - m.clone()) + delta.clone(),
            (true, true, Some(h)) => h.clone() - lo0.clone(),
            (_, true, None) => unreachable!("no upper clip without an upper end"),
        };
        if !(len > m.lit(0.0)) {
            return None;
        }
        let path = self.depth0.clone() + self.dir.one_plus_mu.clone() * start.clone();
        Some(Hit { start, len, path })
    }

    /// This beam's part of μ (13), M₂ (16), C₂₃ (16), (23) or C₂₄ (18), (24):
    /// ∫∫ over the disk (1/πa_b²) of G, times the functional's constant and
    /// f^k, a nested integral (outer ζ, inner m), or the closed form of a
    /// beam parallel to the camera line. Domain: R > 0, σ > 0, any beam.
    /// Deviation: exact at R, where the paper takes the field at the
    /// sphere's centre (§4.3; `docs/model.md` §9).
    pub fn ray_integral(&self, ff: &FiniteField<T>, which: Functional, opts: &Options) -> Outcome<T> {
        let like = &self.radius;
        let zero = like.lit(0.0);
        let none = || Ok(Estimate::known(zero.clone(), zero.clone(), 0, opts.rule));
        let Some((lo0, hi0)) = self.range.clone() else { return none() };
        let r = &ff.radius;
        let weight = self.weight(ff, which);
        if self.dir.sin.is_zero() {
            let distance = (self.xi0.clone() * self.xi0.clone() + self.eta0.clone() * self.eta0.clone()).sqrt();
            let share = disc_overlap(r, &self.radius, &distance);
            let len = hi0.map_or(like.lit(f64::INFINITY), |h| h - lo0.clone());
            let path = self.depth0.clone() + self.dir.one_plus_mu.clone() * lo0.clone();
            let g = functional(which, &Hit { start: lo0, len, path }, &self.dir, &ff.sigma, &ff.shift);
            let value = weight * share * g;
            // A closed form of a few special functions (each within 8 ulps,
            // `docs/accuracy.md`): its rounding is the bar.
            let bar = value.abs() * value.eps() * value.lit(32.0);
            return Ok(Estimate::known(value, bar, 1, opts.rule));
        }
        let (zeta_lo, zeta_hi) = match self.zeta_range(r) {
            Some(z) => z,
            None => return none(),
        };
        let sin = self.dir.sin.clone();
        // The integral's constant: applied to a failure's best guess too.
        let constant = weight.clone() * r.clone() * sin.clone();
        integrate_nested(
            |zeta: &T, o: &Options| {
                let one = zeta.lit(1.0);
                let rho = r.clone() * ((one.clone() - zeta.clone()) * (one + zeta.clone())).sqrt();
                let delta = rho / sin.clone();
                let eta = self.eta0.clone() + r.clone() * zeta.clone();
                let w2 = (self.radius.clone() - eta.clone()) * (self.radius.clone() + eta);
                if !(w2 > zero) {
                    return Ok(Estimate::known(zero.clone(), zero.clone(), 0, o.rule));
                }
                let w = w2.sqrt();
                let m_min = (-w.clone() - self.xi0.clone()) / sin.clone();
                let m_max = (w - self.xi0.clone()) / sin.clone();
                let lo = m_min.max_of(lo0.clone() - delta.clone());
                let hi = match &hi0 {
                    Some(h) => m_max.min_of(h.clone() + delta.clone()),
                    None => m_max,
                };
                if !(hi > lo) {
                    return Ok(Estimate::known(zero.clone(), zero.clone(), 0, o.rule));
                }
                let mut cuts = vec![lo0.clone() + delta.clone()];
                cuts.extend(hi0.iter().map(|h| h.clone() - delta.clone()));
                // G varies on the scale 1/(σ(1 + μ)) in m after each kink
                // (and the domain's start): with a window much longer than
                // that (a beam nearly along the camera ray), its content
                // would sit in a sliver at a piece's start.
                let scale = one_over(&(ff.sigma.clone() * self.dir.one_plus_mu.clone()));
                let starts = [lo.clone(), lo0.clone() - delta.clone(), lo0.clone() + delta.clone()];
                for start in starts {
                    for k in decay_lengths(&start) {
                        cuts.push(start.clone() + start.lit(k) * scale.clone());
                    }
                }
                let e = integrate_within_pass(
                    |m: &T, oi: &Options| {
                        let value = match self.hit(m, &delta) {
                            Some(hit) => functional(which, &hit, &self.dir, &ff.sigma, &ff.shift),
                            None => zero.clone(),
                        };
                        Ok(Estimate::known(value, zero.clone(), 1, oi.rule))
                    },
                    &Domain::finite(lo, hi).with_breakpoints(cuts),
                    o,
                )?;
                Ok(e)
            },
            &Domain::finite(zeta_lo, zeta_hi).with_breakpoints(self.zeta_kinks(r)),
            &Options {
                abs_tol: (opts.abs_tol / (weight.to_f64() * r.to_f64() * sin.to_f64())).min(f64::MAX),
                ..opts.clone()
            },
        )
        .map(|e| e.scaled(&constant))
        .map_err(|f| f.scaled(&constant))
    }

    /// ζ over the rays of the disk within R of the camera line's projection.
    fn zeta_range(&self, r: &T) -> Option<(T, T)> {
        let one = r.lit(1.0);
        let lo = ((-self.radius.clone() - self.eta0.clone()) / r.clone()).max_of(-one.clone());
        let hi = ((self.radius.clone() - self.eta0.clone()) / r.clone()).min_of(one);
        (hi > lo).then_some((lo, hi))
    }

    /// The outer kinks (module doc): ζ where the circle of radius R about
    /// P(lo₀) or P(hi₀) crosses the disk's rim, and where 2δ = hi₀ − lo₀.
    fn zeta_kinks(&self, r: &T) -> Vec<T> {
        let Some((lo0, hi0)) = &self.range else { return Vec::new() };
        let like = r;
        let mut out = Vec::new();
        let mut ends = vec![lo0.clone()];
        ends.extend(hi0.iter().cloned());
        for s in ends {
            // (X + R cos t)² + (η₀ + R sin t)² = a_b²: X cos t + η₀ sin t = K,
            // K = ((a_b − D)(a_b + D)/R − R)/2, D = |P(s)|; the discriminant
            // D² − K² as (D − K)(D + K): the rim crossings keep their
            // position when R ≪ a_b.
            let x = self.xi0.clone() + s * self.dir.sin.clone();
            let d2 = x.clone() * x.clone() + self.eta0.clone() * self.eta0.clone();
            let d = d2.sqrt();
            let a = self.radius.clone();
            let k = ((a.clone() - d.clone()) * (a + d.clone()) / r.clone() - r.clone()) / like.lit(2.0);
            let disc = (d.clone() - k.clone()) * (d + k.clone());
            if disc > like.lit(0.0) && d2 > like.lit(0.0) {
                let root = disc.sqrt();
                for sign in [-1.0, 1.0] {
                    // sin t = (η₀K ± X√(X² + η₀² − K²))/(X² + η₀²).
                    out.push((self.eta0.clone() * k.clone() + like.lit(sign) * x.clone() * root.clone()) / d2.clone());
                }
            }
        }
        if let Some(h) = hi0 {
            let half = (h.clone() - lo0.clone()) * self.dir.sin.clone() / (like.lit(2.0) * r.clone());
            if half < like.lit(1.0) {
                let z = ((like.lit(1.0) - half.clone()) * (like.lit(1.0) + half)).sqrt();
                out.push(z.clone());
                out.push(-z);
            }
        }
        out
    }

    /// The projection distance D(s) = |P(s)| of the sphere at s from the
    /// beam's axis.
    pub(super) fn axis_distance(&self, s: &T) -> T {
        let x = self.xi0.clone() + s.clone() * self.dir.sin.clone();
        (x.clone() * x + self.eta0.clone() * self.eta0.clone()).sqrt()
    }

    /// ⟨𝒞^k⟩_R·e^{c₀} at s = center + x (module doc): the finite-R (19)
    /// (k = 1) and (20) (k = 2). Domain: any x, R > 0. Deviation: exact at R
    /// (the paper takes the field at the sphere's centre); carries the
    /// albedo (E7).
    pub fn moment(&self, ff: &FiniteField<T>, x: &T, power: i32) -> T {
        let zero = x.lit(0.0);
        let s = ff.center.clone() + x.clone();
        let Some((lo0, hi0)) = &self.range else { return zero };
        if s < *lo0 || hi0.as_ref().is_some_and(|h| s > *h) || s < zero {
            return zero;
        }
        let depth = self.depth0.clone() + self.dir.mu.clone() * s.clone();
        let share = disc_overlap(&ff.radius, &self.radius, &self.axis_distance(&s))
            / (x.pi() * self.radius.clone() * self.radius.clone());
        let fk = phase_power(&ff.phase, &self.dir, power);
        ff.per_hit_power(power, &self.flux) * fk * share * (ff.shift.clone() - ff.sigma.clone() * depth).exp()
    }

    /// Breakpoints along the camera ray (in x): the ends of [lo₀, hi₀] and
    /// where D(s) = a_b ± R (the sphere's projection starts and stops
    /// overlapping the beam, and becomes wholly inside or outside it).
    pub fn ray_breakpoints(&self, ff: &FiniteField<T>) -> Vec<T> {
        let Some((lo0, hi0)) = &self.range else { return Vec::new() };
        let mut s_points = vec![lo0.clone()];
        s_points.extend(hi0.iter().cloned());
        let sin = &self.dir.sin;
        if !sin.is_zero() {
            for edge in [self.radius.clone() + ff.radius.clone(), (self.radius.clone() - ff.radius.clone()).abs()] {
                let h2 = (edge.clone() - self.eta0.clone()) * (edge + self.eta0.clone());
                if h2 > sin.lit(0.0) {
                    let h = h2.sqrt();
                    s_points.push((-self.xi0.clone() - h.clone()) / sin.clone());
                    s_points.push((h - self.xi0.clone()) / sin.clone());
                }
            }
        }
        s_points.into_iter().map(|s| s - ff.center.clone()).collect()
    }
}

/// 1/x, or 0 for x = 0 (no scale).
fn one_over<T: CheckRule>(x: &T) -> T {
    if x.is_zero() {
        x.lit(0.0)
    } else {
        x.lit(1.0) / x.clone()
    }
}
