//! Single-scattered light at any R (isotropic media, point lights; a beam's
//! is `scattered_beam`): the
//! sphere-centric mean contribution of a forward path's second segment,
//! the first brick of the finite-sphere model for order 1 (`docs/model.md`
//! §9.5); its ⟨𝒞₁²⟩ serves the variance (`order1`, §9.6, which lists what
//! is still to come).
//!
//! A point light's first segment ends at x₁ with density
//! σe^{−σr₁}/(4πr₁²) (r₁ = |x₁ − y|); with probability albedo the path
//! scatters there, isotropically, and its second segment is an order-0 ray
//! of a point light at x₁: it hits the sphere at distance d with
//! probability H(d) = (1/4π)∫_cap e^{−σ d cos ψ} dω (§9.2), so
//!
//!   ⟨𝒞^k⟩₁(s) = albedo (c^k Φ/𝓕)(4π)^{−k} ∫ σe^{−σr₁}/(4πr₁²) H(|x₁ − x(s)|) d³x₁.
//!
//! In bipolar coordinates about the light and the sphere's centre (D apart)
//! the r₁-integral is closed, ∫_{|D−d|}^{D+d} σe^{−σr}/r dr =
//! σ[E₁(σ|D − d|) − E₁(σ(D + d))], leaving
//!
//!   I(D) = (σ/(2D)) ∫₀^∞ d H(d) [E₁(σ|D − d|) − E₁(σ(D + d))] dd,
//!
//! H(d) = ½ e^{−σ d c_R} F₁(σd, 1 − c_R), c_R = √(1 − R²/d²) beyond R and 0
//! within it (the sphere holds x₁: every ray whose closest point lies ahead
//! hits); declared structure: d = R (√-kink), d = D (logarithmic), graded
//! about each other when D is near R. I(D) depends on σ, R and D only:
//! the moments read it from one table per quadrature pass
//! (`scattered_table`).

use super::point::PointLight;
use super::scattered_table::ScatteredTables;
use super::{FiniteField, FiniteLight};
use crate::model::OracleError;
use crate::quad::{integrate, integrate_within_pass, CheckRule, Domain, Estimate, Options, Outcome};
use crate::real::Real;
use crate::special::{exp_int_e1_scaled, exp_segment};
use mcrt_scene::Phase;

/// H(d): the chance that an isotropic ray from distance d, with a free
/// path ~ Exp(σ), hits a sphere of radius R (its closest point ahead,
/// within R, and reached). Domain: d ≥ 0, R > 0.
pub fn hit_chance<T: Real>(sigma: &T, r: &T, d: &T) -> T {
    let (reach, rest) = hit_chance_parts(sigma, r, d);
    if reach.is_zero() {
        return rest;
    }
    rest * (-(sigma.clone() * reach)).exp()
}

/// H(d) = e^{−σ·reach}·rest: (reach, rest), reach = √(d² − R²) the path to
/// the sphere's surface along the cap's rim (0 when d ≤ R) and rest =
/// ½F₁(σd, 1 − c_R), so that a caller can put the attenuation into one
/// exponent with others.
pub(super) fn hit_chance_parts<T: Real>(sigma: &T, r: &T, d: &T) -> (T, T) {
    let half = d.lit(0.5);
    if d <= r {
        return (d.lit(0.0), half * exp_segment(&(sigma.clone() * d.clone()), Some(&d.lit(1.0))));
    }
    let root = ((d.clone() - r.clone()) * (d.clone() + r.clone())).sqrt();
    // 1 − c_R = R²/(d(d + √(d² − R²))), without cancellation.
    let h = r.clone() * r.clone() / (d.clone() * (d.clone() + root.clone()));
    (root, half * exp_segment(&(sigma.clone() * d.clone()), Some(&h)))
}

/// I(D) = ∫ σe^{−σr₁}/(4πr₁²) H(|x₁ − x|) d³x₁ for a sphere whose centre
/// is D > 0 from the light (module docs), by quadrature in d with its
/// kinks declared. Domain: D > 0, σ > 0, R > 0.
pub fn scattered_hits<T: CheckRule>(sigma: &T, r: &T, big_d: &T, opts: &Options) -> Outcome<T> {
    hits_over_distance(sigma, r, big_d, &sigma.lit(0.0), opts, false)
}

/// [`scattered_hits`], cross-checked on its own (`within` false) or as one
/// level inside a pass of a nested integral (`within` true: the pass's rule,
/// checked by the other pass), times e^{shift}: the attenuation of both
/// segments, e^{−σ(reach + |D − d|)} and e^{−σ(reach + D + d)}, goes into
/// one exponent with the shift (E₁ = e^{−x}·[`exp_int_e1_scaled`]), so that
/// a shift c₀ near the scene's bound (σ·distance ~ 700) neither overflows
/// nor meets E₁ underflowed to 0.
pub(super) fn hits_over_distance<T: CheckRule>(
    sigma: &T,
    r: &T,
    big_d: &T,
    shift: &T,
    opts: &Options,
    within: bool,
) -> Outcome<T> {
    let f = |d: &T| {
        if d.is_zero() {
            return d.lit(0.0);
        }
        let near = (big_d.clone() - d.clone()).abs() * sigma.clone();
        let far = (big_d.clone() + d.clone()) * sigma.clone();
        if near.is_zero() {
            return d.lit(0.0);
        }
        let (reach, rest) = hit_chance_parts(sigma, r, d);
        let base = shift.clone() - sigma.clone() * reach;
        let near_part = (base.clone() - near.clone()).exp() * exp_int_e1_scaled(&near);
        let far_part = (base - far.clone()).exp() * exp_int_e1_scaled(&far);
        d.clone() * rest * (near_part - far_part)
    };
    let domain =
        Domain::semi_infinite(big_d.lit(0.0)).with_breakpoints(bipolar_cuts(big_d, r)).with_decay(sigma.clone());
    // The result is the integral times σ/(2D): its absolute goal, before.
    let factor = sigma.clone() / (big_d.lit(2.0) * big_d.clone());
    let opts = &Options { abs_tol: (opts.abs_tol / factor.to_f64()).min(f64::MAX), ..opts.clone() };
    let e = if within {
        integrate_within_pass(|d: &T, o: &Options| Ok(Estimate::known(f(d), d.lit(0.0), 1, o.rule)), &domain, opts)?
    } else {
        integrate(f, &domain, opts)?
    };
    Ok(e.scaled(&factor))
}

/// The breakpoints in d of a bipolar integral ∫ d F(d) K(D, d) dd of a
/// sphere's radial function F (kinked at d = R like H) against a kernel
/// that turns at d = D ([`hits_over_distance`], `multiple::convolved`):
/// d = D, d = R, and R·10^k up to D, where H falls like R²/d² over as many
/// decades. With D near R the two points nearly meet and each is a
/// near-singularity of the pieces at the other, graded by decades of
/// their gap (without, I(D) at D = R(1 − 10⁻⁶) and 10⁻¹⁰ failed its
/// cross-check, 10× apart from its bars).
pub(super) fn bipolar_cuts<T: Real>(big_d: &T, r: &T) -> Vec<T> {
    let mut cuts = vec![big_d.clone()];
    if r != big_d {
        cuts.push(r.clone());
        let gap = (big_d.clone() - r.clone()).abs();
        if gap < *r {
            cuts.extend(crate::model::field::graded_about(big_d, &gap, r).into_iter().filter(|c| *c > gap.lit(0.0)));
            cuts.extend(crate::model::field::graded_about(r, &gap, r).into_iter().filter(|c| *c > gap.lit(0.0)));
        }
    }
    cuts.extend(crate::model::field::graded_about(&big_d.lit(0.0), r, big_d).into_iter().filter(|c| c > r));
    cuts
}

impl<T: CheckRule> PointLight<T> {
    /// ⟨𝒞^k⟩₁·e^{c₀} at s = center + x: the mean k-th power of the
    /// contribution of the light's paths' second segments to the sphere
    /// there (module docs). I(D) comes from the pass's table in `tables`
    /// ([`super::scattered_table`], its relative bar in the value's; the
    /// caller charges the tables' evaluations once, at its end) where it
    /// reaches, else from the quadrature, with the pass's rule either way.
    /// In a Henyey–Greenstein medium it is [`PointLight::scattered_moment_hg`]
    /// (§9.9; `tables` unused). Not in the paper: exact at R where its §3a
    /// takes the field at the centre.
    pub(super) fn scattered_moment(
        &self,
        ff: &FiniteField<T>,
        tables: &ScatteredTables<T>,
        x: &T,
        power: i32,
        opts: &Options,
    ) -> Outcome<T> {
        if ff.phase != Phase::Isotropic {
            return self.scattered_moment_hg(ff, x, power, opts);
        }
        let (big_d, _) = self.distance_to(ff, x);
        let f = x.lit(1.0) / (x.pi() * x.lit(4.0));
        let front =
            ff.per_hit_power(power, &self.flux) * if power == 1 { f } else { f.clone() * f } * ff.albedo.clone();
        let table = tables.for_pass(ff, opts);
        if let Some((v, rel)) = table.and_then(|t| t.hits(&ff.sigma, &ff.radius, &big_d, &ff.shift)) {
            let bar = v.abs() * rel;
            return Ok(Estimate::known(v, bar, 1, opts.rule).scaled(&front));
        }
        let o = Options { abs_tol: (opts.abs_tol / front.to_f64()).min(f64::MAX), ..opts.clone() };
        Ok(hits_over_distance(&ff.sigma, &ff.radius, &big_d, &ff.shift, &o, true)?.scaled(&front))
    }
}

impl<T: CheckRule> FiniteField<T> {
    /// μ₁(R)·e^{c₀} = ∫σe^{−σs}⟨𝒞⟩₁ ds: the single-scattered part of the
    /// mean luminance at the field's R: an isotropic medium (point lights
    /// and beams), or point lights in a Henyey–Greenstein one (§9.9, with
    /// the Gauss–Kronrod pair of rules where the goal allows; a beam there
    /// is refused). The uncollided part is [`FiniteField::ray_total`] of the mean.
    pub fn scattered_mean(&self, opts: &Options) -> Result<Estimate<T>, OracleError> {
        let tables = ScatteredTables::default();
        tables.charge(self.scattered_mean_with(&tables, opts))
    }

    /// [`FiniteField::scattered_mean`] reading (and building) `tables`,
    /// whose evaluations the caller charges.
    pub(super) fn scattered_mean_with(
        &self,
        tables: &ScatteredTables<T>,
        opts: &Options,
    ) -> Result<Estimate<T>, OracleError> {
        self.order1_covered()?;
        // A Henyey–Greenstein medium nests three levels per camera-ray
        // point (`scattered_hg`): the Gauss–Kronrod pair's floor per piece
        // (15 and 21) is what makes it affordable at loose goals, as for
        // the pairs (`order1::pair_rule`).
        let hg = Options { rule: super::order1::pair_rule(&self.radius, opts), ..opts.clone() };
        let opts = if self.phase == Phase::Isotropic { opts } else { &hg };
        self.with_line(|line| {
            line.integral_nested("finite-sphere ∫⟨𝒞⟩₁, single-scattered", opts, |x, o| {
                let share = Options { abs_tol: o.abs_tol / self.lights.len() as f64, ..o.clone() };
                self.sum_over_lights(x, o, |i, light| match light {
                    FiniteLight::Point(p) => p.scattered_moment(self, tables, x, 1, &share),
                    FiniteLight::Beam(b) => b.scattered_moment(self, tables, i, x, 1, &share),
                })
            })
        })
    }
}
