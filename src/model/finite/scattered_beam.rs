//! Single-scattered light of a beam at any R (isotropic media,
//! `docs/model.md` §9.8): the finite-sphere moments of a forward path whose
//! first segment is a beam ray.
//!
//! The first segment interacts at depth t with density σe^{−σt} over the
//! beam's rays, n(x₁) = σe^{−σt}/(πa²) inside its cylinder; with probability
//! albedo the path scatters there, isotropically, and its second segment
//! hits the sphere at s with the chance H(|x₁ − x(s)|) of §9.5, so
//!
//!   ⟨𝒞^k⟩₁(s) = albedo (c^k Φ/𝓕)(4π)^{−k} ∫ n(x₁) H(|x₁ − x(s)|) d³x₁,
//!
//! the volume integral of `model::beam_source` (spherical shells about x(s)).
//! One path hits the sphere with both segments when its first passes the
//! centre at ρ ≤ R, reaches its closest point at the depth τ(s) (e^{−στ})
//! and its second hits again (K(w), w = √(R² − ρ²), §9.6):
//!
//!   ⟨𝒞₀𝒞₁⟩(s) = albedo (c²Φ/𝓕)(4π)^{−2} e^{−στ(s)} ∫₀^R Θ(ρ(w)) w K(w) dw/(πa²),
//!
//! Θ the angle of the circle of radius ρ about the sphere's foot P(s) that
//! lies inside the beam's disk ([`arc_in_disc_gaps`]).

use super::beam::BeamLight;
use super::scattered::hit_chance_parts;
use super::scattered_table::ScatteredTables;
use super::second_hit::{weighted_second_hit, with_table_bar, SecondHitTable};
use super::{FiniteField, FiniteLight};
use crate::model::beam_source::BeamPoint;
use crate::model::chebyshev::{sample_options, Piecewise};
use crate::model::field::graded_about;
use crate::quad::{decay_lengths, integrate_within_pass, CheckRule, Domain, Estimate, Options, Outcome};
use crate::special::arc_in_disc_gaps;

impl<T: CheckRule> BeamLight<T> {
    /// The sphere at s = center + x against the beam: its depth τ(s) and
    /// the distance p = |P(s)| of its centre from the axis.
    pub(super) fn seen_at(&self, ff: &FiniteField<T>, x: &T) -> BeamPoint<T> {
        let s = ff.center.clone() + x.clone();
        BeamPoint {
            a: self.radius.clone(),
            p: self.axis_distance(&s),
            tau: self.depth0.clone() + self.dir.mu.clone() * s,
            sigma: ff.sigma.clone(),
        }
    }

    /// A lower bound of the path light → second segment's closest point
    /// to a sphere → camera of this beam's single-scattered light, times σ:
    /// σ·(max(dist(o, beam), depth₀) − R)⁺ (as `beam_source::beam_scattered_path`,
    /// from the camera's coordinates in the beam's frame). ≥ c₀; its own
    /// along-ray table is scaled by it, so that a beam far behind a light
    /// near the camera does not underflow there.
    pub(super) fn scattered_shift(&self, ff: &FiniteField<T>) -> T {
        let zero = ff.radius.lit(0.0);
        let across = ((self.xi0.clone() * self.xi0.clone() + self.eta0.clone() * self.eta0.clone()).sqrt()
            - self.radius.clone())
        .max_of(zero.clone());
        let before = (-self.depth0.clone()).max_of(zero.clone());
        let path = (across.clone() * across + before.clone() * before).sqrt().max_of(self.depth0.clone());
        ff.sigma.clone() * (path - ff.radius.clone()).max_of(zero)
    }

    /// ∫ n(x₁) H(|x₁ − x(s)|) d³x₁·e^{shift} at s = center + x (module
    /// docs), as one level inside a pass, or as a table's sample with its
    /// options.
    fn volume_integral(&self, ff: &FiniteField<T>, x: &T, shift: &T, opts: &Options) -> Outcome<T> {
        let sigma = &ff.sigma;
        // d²·σe^{shift − σt}H(d), the attenuation of both segments in one exponent.
        let kernel = |t: &T, d: &T| {
            let (reach, rest) = hit_chance_parts(sigma, &ff.radius, d);
            d.clone() * d.clone() * sigma.clone() * rest * (shift.clone() - sigma.clone() * (t.clone() + reach)).exp()
        };
        self.seen_at(ff, x).integral(&kernel, Some(&ff.radius), opts, true)
    }

    /// ⟨𝒞^k⟩₁·e^{c₀} at s = center + x: the mean k-th power of the
    /// contribution of the beam's paths' second segments to the sphere
    /// there (module docs), the volume integral from the pass's along-ray
    /// table in `tables` (light `index`; its relative bar in the value's)
    /// where it reaches, else by quadrature inside the pass. Isotropic
    /// media only (the caller's check). Not in the paper: exact at R where
    /// its §3a takes the field at the centre (and has no beams at order 1).
    pub(super) fn scattered_moment(
        &self,
        ff: &FiniteField<T>,
        tables: &ScatteredTables<T>,
        index: usize,
        x: &T,
        power: i32,
        opts: &Options,
    ) -> Outcome<T> {
        let f = x.lit(1.0) / (x.pi() * x.lit(4.0));
        let front =
            ff.per_hit_power(power, &self.flux) * if power == 1 { f } else { f.clone() * f } * ff.albedo.clone();
        if let Some((v, rel)) = tables.beams_for_pass(ff, opts).and_then(|t| t.value(ff, index, x)) {
            let bar = v.abs() * rel;
            return Ok(Estimate::known(v, bar, 1, opts.rule).scaled(&front));
        }
        let o = Options { abs_tol: (opts.abs_tol / front.to_f64()).min(f64::MAX), ..opts.clone() };
        Ok(self.volume_integral(ff, x, &ff.shift, &o)?.scaled(&front))
    }

    /// ⟨𝒞₀𝒞₁⟩·e^{c₀} at s = center + x: one path hitting the sphere there
    /// with both its segments (module docs), K from the pass's table when
    /// there is one (its relative bar added), else by quadrature. Domain:
    /// any x, R > 0; isotropic media. Deviation: the paper has no such term
    /// (E9).
    pub(super) fn same_path_moment(
        &self,
        ff: &FiniteField<T>,
        x: &T,
        table: Option<&SecondHitTable<T>>,
        opts: &Options,
    ) -> Outcome<T> {
        self.ray_revisits(ff, x, table, &ff.albedo, opts)
    }

    /// The beam ray's pairs with every later segment of its path at the
    /// sphere at s = center + x, ·e^{c₀}: [`BeamLight::same_path_moment`]
    /// with the K_G table of every order (`multiple_pairs`, `docs/model.md`
    /// §10.6), which carries the albedo (so the front does not). Never K of
    /// order 1 in its place: the table is required.
    pub(super) fn ray_pairs_every_order(
        &self,
        ff: &FiniteField<T>,
        x: &T,
        k_g: &SecondHitTable<T>,
        opts: &Options,
    ) -> Outcome<T> {
        self.ray_revisits(ff, x, Some(k_g), &x.lit(1.0), opts)
    }

    /// ⟨𝒞₀ Σ_k 𝒞_k⟩·e^{c₀}: the beam ray crossing the sphere then hitting it
    /// again as `table` (or order 1's K by quadrature) says, `albedo` in
    /// front (module docs).
    fn ray_revisits(
        &self,
        ff: &FiniteField<T>,
        x: &T,
        table: Option<&SecondHitTable<T>>,
        albedo: &T,
        opts: &Options,
    ) -> Outcome<T> {
        let zero = x.lit(0.0);
        let nothing = || Ok(Estimate::known(zero.clone(), zero.clone(), 0, opts.rule));
        let s = ff.center.clone() + x.clone();
        let Some((lo0, hi0)) = &self.range else { return nothing() };
        if s < *lo0 || hi0.as_ref().is_some_and(|h| s > *h) || s < zero {
            return nothing();
        }
        let at = self.seen_at(ff, x);
        let (r, a, p) = (&ff.radius, &self.radius, &at.p);
        let f = x.lit(1.0) / (x.pi() * x.lit(4.0));
        let front = ff.per_hit_power(2, &self.flux) * f.clone() * f * albedo.clone() / (x.pi() * a.clone() * a.clone())
            * (ff.shift.clone() - ff.sigma.clone() * at.tau.clone()).exp();
        if front.is_zero() {
            return nothing();
        }
        let o = Options { abs_tol: (opts.abs_tol / front.to_f64()).min(f64::MAX), ..opts.clone() };
        // The kinks m = |a − p|, a + p of Θ where m < R, at w_m = √(R² − m²);
        // there ρ − m = (w_m − w)(w_m + w)/(ρ + m), exact near the kink.
        let kinks: Vec<(T, Option<T>)> = [(a.clone() - p.clone()).abs(), a.clone() + p.clone()]
            .into_iter()
            .map(|m| {
                let w_m = (m < *r).then(|| ((r.clone() - m.clone()) * (r.clone() + m.clone())).sqrt());
                (m, w_m)
            })
            .collect();
        let cuts: Vec<T> = kinks.iter().filter_map(|(_, w_m)| w_m.clone()).filter(|w| *w > zero && *w < *r).collect();
        let domain = Domain::finite(zero.clone(), r.clone()).with_breakpoints(cuts);
        let integrand = |w: &T, inner: &Options| {
            let rho = ((r.clone() - w.clone()) * (r.clone() + w.clone())).sqrt();
            let gap = |(m, w_m): &(T, Option<T>)| match w_m {
                Some(w_m) => (w_m.clone() - w.clone()) * (w_m.clone() + w.clone()) / (rho.clone() + m.clone()),
                None => rho.clone() - m.clone(),
            };
            let angle = arc_in_disc_gaps(&rho, a, p, &gap(&kinks[0]), &-gap(&kinks[1]));
            weighted_second_hit(&ff.sigma, r, w, angle * w.clone(), table, inner)
        };
        let e = integrate_within_pass(integrand, &domain, &o)?;
        Ok(with_table_bar(e, table, opts).scaled(&front))
    }

    /// Where along the camera ray (in x) the single-scattered moments bend
    /// beyond the uncollided ones' breakpoints: the sphere's surface
    /// touching the disk's plane (τ(s) = ±R) and the beam's surface
    /// crossing the sphere's centre (|P(s)| = a).
    pub(super) fn scattered_breakpoints(&self, ff: &FiniteField<T>) -> Vec<T> {
        let zero = ff.radius.lit(0.0);
        let mut s_points = Vec::new();
        let mu = &self.dir.mu;
        if !mu.is_zero() {
            for depth in [-ff.radius.clone(), zero.clone(), ff.radius.clone()] {
                s_points.push((depth - self.depth0.clone()) / mu.clone());
            }
        }
        let mut out: Vec<T> = s_points.into_iter().filter(|s| *s > zero).map(|s| s - ff.center.clone()).collect();
        out.extend(self.surface_crossings(ff));
        out
    }

    /// Where (in x) the camera ray crosses the disk's plane (τ(s) = 0), ahead
    /// of the camera.
    fn face_crossing(&self, ff: &FiniteField<T>) -> Option<T> {
        let s = (!self.dir.mu.is_zero()).then(|| -self.depth0.clone() / self.dir.mu.clone())?;
        (s > ff.radius.lit(0.0)).then(|| s - ff.center.clone())
    }

    /// Where (in x) the camera ray crosses the beam's surface (|P(s)| = a),
    /// ahead of the camera.
    pub(super) fn surface_crossings(&self, ff: &FiniteField<T>) -> Vec<T> {
        let zero = ff.radius.lit(0.0);
        let mut s_points = Vec::new();
        let sin = &self.dir.sin;
        if !sin.is_zero() {
            let a = &self.radius;
            let h2 = (a.clone() - self.eta0.clone()) * (a.clone() + self.eta0.clone());
            // (h2 = 0: the ray touches the surface; graded there too.)
            if h2 >= zero {
                let h = h2.sqrt();
                s_points.push((-self.xi0.clone() - h.clone()) / sin.clone());
                s_points.push((h - self.xi0.clone()) / sin.clone());
            }
        }
        s_points.into_iter().filter(|s| *s > zero).map(|s| s - ff.center.clone()).collect()
    }
}

/// Goals finer than this get no along-ray table (MPFR): the quadrature
/// serves.
const FINEST_GOAL: f64 = 1e-13;

/// The beams' volume integrals ∫ n H d³x₁ along the camera ray (each times
/// e^{its own shift}, [`BeamLight::scattered_shift`]) for
/// one quadrature pass: a piecewise Chebyshev interpolant (of the
/// logarithm) per beam over the table range ([`FiniteField::table_range`]),
/// cut at every along-ray breakpoint and the tail's decay lengths, to a
/// tenth of the pass's tolerance from samples at the pass's rule
/// (`chebyshev::sample_options`). μ₁, the ⟨𝒞₁²⟩ of M₂ and P read it at
/// every node instead of a 2-D quadrature there (on `beam-isotropic` at
/// order 1, R = 0.2, the oracle at 10⁻⁶ spent its 10⁹ evaluations without
/// it).
pub(super) struct BeamAlongRay<T> {
    /// Per light in scene order: the beam's interpolant of the volume
    /// integral times e^{shift} with its own shift
    /// ([`BeamLight::scattered_shift`]) (`None` for a point light, or where
    /// interpolation failed and the quadrature serves).
    tables: Vec<Option<(Piecewise<T>, T)>>,
    lo: T,
    hi: T,
}

impl<T: CheckRule> BeamAlongRay<T> {
    /// The tables of `ff`'s beams for the pass with `opts`, or `None` (no
    /// beam, or a goal finer than [`FINEST_GOAL`]), and the evaluations
    /// spent either way.
    pub(super) fn build(ff: &FiniteField<T>, opts: &Options) -> (Option<BeamAlongRay<T>>, u64) {
        let goal = opts.rel_tol / 10.0;
        if goal < FINEST_GOAL || !ff.lights.iter().any(|l| matches!(l, FiniteLight::Beam(_))) {
            return (None, 0);
        }
        let (lo, hi) = ff.table_range();
        let cuts = along_ray_cuts(ff);
        let samples = sample_options(&lo, goal, opts.rule, &opts.budget);
        let mut evaluations = 0;
        let tables = ff
            .lights
            .iter()
            .map(|light| {
                let FiniteLight::Beam(b) = light else { return None };
                let shift = b.scattered_shift(ff);
                match Piecewise::build(|x: &T| b.volume_integral(ff, x, &shift, &samples), &cuts, goal) {
                    Ok(t) => {
                        evaluations += t.evaluations;
                        Some((t, shift))
                    }
                    Err(f) => {
                        evaluations += f.evaluations;
                        None
                    }
                }
            })
            .collect();
        (Some(BeamAlongRay { tables, lo, hi }), evaluations)
    }

    /// The volume integral of light `index` at x times e^{c₀} and its
    /// relative bar (the table's plus the rounding of the exponent c₀ −
    /// shift, 4ε(1 + |c₀| + |shift|)), or `None` where no table reaches.
    fn value(&self, ff: &FiniteField<T>, index: usize, x: &T) -> Option<(T, T)> {
        if *x < self.lo || *x > self.hi {
            return None;
        }
        let (t, shift) = self.tables.get(index)?.as_ref()?;
        let rounding = x.eps() * x.lit(4.0) * (x.lit(1.0) + ff.shift.abs() + shift.abs());
        Some((t.eval(x) * (ff.shift.clone() - shift.clone()).exp(), t.rel_error.clone() + rounding))
    }
}

/// Where the beams' volume integrals along the camera ray bend, over the
/// table range ([`FiniteField::table_range`], its ends included): every
/// along-ray breakpoint, the tail's decay lengths, and pieces graded by
/// decades towards where the camera ray crosses a beam's surface or its
/// disk's face.
pub(super) fn along_ray_cuts<T: CheckRule>(ff: &FiniteField<T>) -> Vec<T> {
    let (lo, hi) = ff.table_range();
    let mut cuts: Vec<T> = ff.ray_domain(&lo, None).breakpoints.into_iter().filter(|b| *b > lo && *b < hi).collect();
    let last = cuts.iter().cloned().fold(lo.clone(), |m, b| m.max_of(b));
    for k in decay_lengths(&lo) {
        let c = last.clone() + lo.lit(k) / ff.sigma.clone();
        if c < hi {
            cuts.push(c);
        }
    }
    // Where the camera ray crosses a beam's surface the volume integral
    // bends like the fluence of a uniform source at its boundary (δ ln δ),
    // smoothed over R: pieces graded by decades towards the crossings
    // from R, so that each sees the bend a decade off (without them
    // R = 10⁻⁸ spent the 10⁹ evaluations of the default budget).
    // (The disk's face likewise.)
    for light in &ff.lights {
        if let FiniteLight::Beam(b) = light {
            let width = ff.radius.clone().max_of(lo.lit(1e-10) / ff.sigma.clone());
            let scale = b.radius.clone() * b.radius.lit(4.0);
            for k in b.surface_crossings(ff).into_iter().chain(b.face_crossing(ff)) {
                cuts.extend(graded_about(&k, &width, &scale).into_iter().filter(|c| *c > lo && *c < hi));
            }
        }
    }
    cuts.push(lo.clone());
    cuts.push(hi.clone());
    cuts
}
