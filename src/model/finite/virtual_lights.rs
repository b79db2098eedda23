//! Single-scattered light through virtual point lights (`docs/model.md`
//! §9.6): the second segment of a forward path is an uncollided ray of a
//! point light at its start, the interaction point x₁ of the first, so
//! any order-0 ray functional of §9.1 (μ, M₂, C₂₃, C₂₄) has a
//! single-scattered counterpart that is its average over x₁ with the
//! density albedo·σe^{−σr₁}/(4πr₁²) (r₁ = |x₁ − y|, isotropic scattering)
//! (`PointLight::virtual_average`).
//!
//! The functional depends on x₁ through its foot z and distance b from the
//! camera line only, so the average is over the half-plane (z, b) with the
//! density integrated around the line (`ring_density`), in polar
//! coordinates (m, γ) about the light's own (z_y, b_y), whose dz db = m dm dγ
//! absorbs the density's 1/m there. Four nested levels: γ, m, and the
//! functional's own two; a virtual light whose functional is bounded below
//! its goal without them (`functional_bound`: far from the camera) skips
//! the inner two.
//!
//! For μ this is a second route to §9.5's I(D), sharing no geometry with it
//! (the hit intervals of §9.2 against the cap of §9.5):
//! `tests/finite_order1.rs` (ignored: ~3 minutes on two cores at 10⁻⁴,
//! 2.8·10⁹ evaluations).
//! For C₂₃, C₂₄ it is the one-segment-two-spheres part of order 1 (§9.7),
//! run with the Gauss–Kronrod pair of rules at loose goals
//! (`order1::pair_rule`): ~15 s at 10⁻³ on two cores.

use super::point::{power_of, PointLight};
use super::ray::Functional;
use super::{FiniteField, FiniteLight};
use crate::model::field::graded_about;
use crate::quad::{integrate_nested, integrate_within_pass, CheckRule, Domain, Estimate, Options, Outcome};
use mcrt_scene::Phase;

/// m·ρ₂(z, b): the interaction density of a light's first segments,
/// σe^{−σr}/(4πr²), integrated around the camera line on the circle of
/// radius b at abscissa z, times m, the distance in the (z, b) half-plane
/// from the light's own (z_y, b_y). With k = 4 b b_y,
/// r² = m² + k sin²(φ/2) and
///
///   m ρ₂ = (m b σ/2π) ∫₀^π e^{−σ(r − m)}/r² dφ · e^{−σm},
///
/// returned without the e^{−σm} (the caller carries it in its shift),
/// r − m = k sin²(φ/2)/(r + m) formed without cancellation; the kernel's
/// width near φ = 0, 2m/√k, is graded by decades. At m = 0 the limit
/// σb/(2√k). Domain: m, b, b_y ≥ 0 with |b − b_y| ≤ m (a point of the
/// half-plane at distance m from the light's; so b = 0 when m = b_y = 0).
pub(crate) fn ring_density<T: CheckRule>(sigma: &T, m: &T, b: &T, b_y: &T, opts: &Options) -> Outcome<T> {
    let k = b.lit(4.0) * b.clone() * b_y.clone();
    let known = |v: T| Ok(Estimate::known(v, m.lit(0.0), 1, opts.rule));
    if b.is_zero() {
        return known(m.lit(0.0));
    }
    if k.is_zero() {
        return known(b.clone() * sigma.clone() / (m.lit(2.0) * m.clone()));
    }
    if m.is_zero() {
        return known(sigma.clone() * b.clone() / (m.lit(2.0) * k.sqrt()));
    }
    let f = |phi: &T, o: &Options| {
        let h = (phi.clone() / phi.lit(2.0)).sin();
        let ks = k.clone() * h.clone() * h;
        let r2 = m.clone() * m.clone() + ks.clone();
        let excess = ks / (r2.sqrt() + m.clone());
        Ok(Estimate::known((-(sigma.clone() * excess)).exp() / r2, phi.lit(0.0), 1, o.rule))
    };
    let width = m.lit(2.0) * m.clone() / k.sqrt();
    let zero = m.lit(0.0);
    let cuts: Vec<T> = graded_about(&zero, &width, &m.pi()).into_iter().filter(|c| *c > zero).collect();
    let front = m.clone() * b.clone() * sigma.clone() / (m.pi() * m.lit(2.0));
    let o = Options { abs_tol: (opts.abs_tol / front.to_f64()).min(f64::MAX), ..opts.clone() };
    Ok(integrate_within_pass(f, &Domain::finite(zero, m.pi()).with_breakpoints(cuts), &o)?.scaled(&front))
}

/// An upper bound of the order-0 ray functional `which` of a point light
/// of flux `flux` at x₁ = (z, b) (foot and distance from the camera line),
/// times e^{shift}, as `PointLight::ray_integral_in` computes it — without
/// a direction integral, so that virtual lights far from the camera, which
/// cannot matter to the average, cost nothing (at R = 0.5 and 10⁻³ the
/// virtual lights beyond m = 50 from the light took 29 % of C₂₃'s
/// 2.65·10⁹ evaluations, three quarters of those at m > 745 where e^{−σm}
/// underflows).
///
/// Every G of `ray::functional` integrates e^{−σ(s + τ(s))} over the hit
/// interval J, and s + τ(s) ≥ P_min = max(|x₁ − o| − R, 0) on J (the ray's
/// closest point to x(s) lies within R of it; triangle inequality). Halving
/// the exponent, e^{−σ(s + τ)} ≤ e^{−σP_min/2} e^{−σs/2}, leaves integrals
/// over s ≥ 0 alone: ∫σe^{−σs/2} = 2 for G₁; ∫∫_{s<s′}σ²e^{−σs′/2} = 4 for
/// G₂₃ (max τ ≥ τ(s′)); ∫∫σ²e^{−σs/2}e^{−σs′} = 2 for G₂₄ (max τ ≥ τ(s)).
/// So G ≤ 4e^{shift − σP_min/2} for every direction, and the functional,
/// per_hit · ∫ f^k G dω/4π, is at most per_hit · f_max^k · 4e^{shift −
/// σP_min/2} (f_max = 1/4π, or (1 + |g|)/(4π(1 − |g|)²) for
/// Henyey–Greenstein). Domain: any x₁, σ > 0; +∞ where the exponential
/// overflows (no bound). `far_functionals_stay_within_their_bound` checks
/// it against the direction integral.
pub(super) fn functional_bound<T: CheckRule>(
    ff: &FiniteField<T>,
    which: Functional,
    flux: &T,
    z: &T,
    b: &T,
    shift: &T,
) -> T {
    let like = z;
    let reach = ((z.clone() * z.clone() + b.clone() * b.clone()).sqrt() - ff.radius.clone()).max_of(like.lit(0.0));
    let f_max = match ff.phase {
        Phase::Isotropic => like.lit(1.0) / (like.pi() * like.lit(4.0)),
        Phase::HenyeyGreenstein { g } => {
            let a = g.abs();
            like.lit((1.0 + a) / ((1.0 - a) * (1.0 - a))) / (like.pi() * like.lit(4.0))
        }
    };
    let exponent = shift.clone() - ff.sigma.clone() * reach / like.lit(2.0);
    ff.per_hit(which, flux) * power_of(f_max, which.power()) * like.lit(4.0) * exponent.exp()
}

/// One virtual-light node of the average albedo ∫ n F d³x₁ (point lights
/// and beams alike): `dens` (the density integrated around the ring at
/// (z, b), its attenuation factored into `shift`) times the order-0 functional
/// `which` of a light of flux `flux` at (z, b) with the shift `shift`, the
/// functional to the absolute goal `allowed` (before its constant). Where
/// [`functional_bound`] is within that goal — far from the camera — the
/// functional is [0, bound] and needs no direction integral.
#[allow(clippy::too_many_arguments)]
pub(super) fn virtual_light_node<T: CheckRule>(
    ff: &FiniteField<T>,
    which: Functional,
    flux: &T,
    [z, b]: [&T; 2],
    dens: &Estimate<T>,
    shift: &T,
    allowed: f64,
    opts: &Options,
) -> Outcome<T> {
    let bound = functional_bound(ff, which, flux, z, b, shift);
    if bound.to_f64() <= allowed {
        let half = bound / z.lit(2.0);
        let error = dens.value.abs() * half.clone() + half.clone() * dens.error.clone();
        return Ok(Estimate::known(dens.value.clone() * half, error, dens.evaluations, opts.rule));
    }
    let unit = ff.per_hit(which, flux).to_f64() / (2.0 * std::f64::consts::PI);
    let light = PointLight::new(z.clone(), b.clone(), flux.clone(), &ff.radius);
    let each = Options { abs_tol: (allowed / unit).min(f64::MAX), ..opts.clone() };
    let v = light.ray_integral_in(ff, which, &each, true, shift)?;
    let error = dens.value.abs() * v.error.clone() + v.value.abs() * dens.error.clone();
    Ok(Estimate::known(dens.value.clone() * v.value, error, dens.evaluations + v.evaluations, opts.rule))
}

/// A point of the half-plane (z, b) about the camera line, m from the
/// light's own (z_y, b_y): z = z_y + dz, b = b_y + db ≥ 0, the offsets as
/// formed from m and γ (exact where z and b round them away).
#[derive(Debug, Clone)]
pub(super) struct Offset<T> {
    pub z: T,
    pub b: T,
    pub m: T,
    pub dz: T,
    pub db: T,
}

impl<T: CheckRule> PointLight<T> {
    /// albedo ∫ σe^{−σr₁}/(4πr₁²) F(x₁) d³x₁: the order-0 ray functional
    /// `which` of a virtual point light at the interaction point x₁,
    /// averaged over x₁ (module docs), times e^{c₀}. For Mean and Second
    /// it is the single-scattered part of μ and of ∫σe^{−σs}⟨𝒞₁²⟩ again,
    /// by a route that shares no geometry with [`super::scattered`]; for
    /// Pair23, Pair24 the one-segment-two-spheres part of C₂₃, C₂₄.
    /// Domain: R > 0, σ > 0, isotropic media.
    pub(super) fn virtual_average(&self, ff: &FiniteField<T>, which: Functional, opts: &Options) -> Outcome<T> {
        let sigma = &ff.sigma;
        let zero = self.z.lit(0.0);
        // The scale of the functional, from the light itself: every inner
        // functional gets an absolute floor of a hundredth of its relative
        // goal of it, times e^{−σm} (the functional carries that factor in
        // its shift, and ∫ e^{−σm}·mρ₂ dm dγ = 1), so that inner integrals
        // asked for a relative goal only (the coarse pass) end, and all of
        // them together add at most that floor to the total.
        let scale = self
            .ray_integral(ff, which, &Options { rel_tol: 1e-3, abs_tol: 0.0, ..opts.clone() })?
            .value
            .abs()
            .to_f64();
        let node = |at: &Offset<T>, o2: &Options| {
            let (m, z, b) = (&at.m, &at.z, &at.b);
            let dens = ring_density(sigma, m, b, &self.b, &Options { abs_tol: 0.0, ..o2.clone() })?;
            if dens.value.is_zero() {
                return Ok(Estimate::known(zero.clone(), zero.clone(), dens.evaluations, o2.rule));
            }
            let shift = ff.shift.clone() - sigma.clone() * m.clone();
            let floor = o2.rel_tol * scale / 100.0 * (-(sigma.to_f64() * m.to_f64())).exp();
            // The functional's goal: ray_integral_in's abs_tol applies before its constant.
            let allowed = (o2.abs_tol / dens.value.to_f64()).max(floor);
            virtual_light_node(ff, which, &self.flux, [z, b], &dens, &shift, allowed, o2)
        };
        let e = self.over_half_plane(
            ff,
            &node,
            &Options { abs_tol: (opts.abs_tol / ff.albedo.to_f64()).min(f64::MAX), ..opts.clone() },
            0.0,
        )?;
        Ok(e.scaled(&ff.albedo))
    }

    /// ∫₀^{2π} dγ ∫ dm node(m, z, b) over the half-plane (z, b) of points
    /// about the camera line, in polar coordinates (m, γ) about the light's
    /// own (z_y, b_y): z = z_y + m cos γ, b = b_y + m sin γ ≥ 0 (`node`
    /// carries the Jacobian m). Declared: the axes, the rays from the light
    /// tangent to the camera's circle z² + b² = R² and its crossings, the
    /// line b = R, gradings about m = 0 on the scales R and b_y, the edge
    /// b = 0 and the decay rate σ. Each m-integral's absolute goal is at
    /// least `m_floor` (0: none), in the pass's as in the scale pass, which
    /// asks inner levels for a relative goal only.
    pub(super) fn over_half_plane(
        &self,
        ff: &FiniteField<T>,
        node: &(dyn Fn(&Offset<T>, &Options) -> Outcome<T> + Sync),
        opts: &Options,
        m_floor: f64,
    ) -> Outcome<T> {
        let like = &self.z;
        let (r, sigma) = (&ff.radius, &ff.sigma);
        let (zy, by) = (self.z.clone(), self.b.clone());
        let zero = like.lit(0.0);
        let two_pi = like.pi() * like.lit(2.0);
        // Angles at which the ray from (z_y, b_y) is tangent to the camera's
        // circle z² + b² = R² (x₁ within R of the camera), and the axes.
        let mut gamma_cuts = vec![like.pi() / like.lit(2.0), like.pi(), like.pi() * like.lit(1.5)];
        let dist = (zy.clone() * zy.clone() + by.clone() * by.clone()).sqrt();
        if dist > *r {
            // The direction (−z_y, −b_y) towards the camera: π + angle of (z_y, b_y), b_y ≥ 0.
            let towards = like.pi() + (zy.clone() / dist.clone()).acos();
            let half = (r.clone() / dist.clone()).asin();
            for g in [towards.clone() - half.clone(), towards.clone(), towards + half] {
                let g = if g > two_pi { g - two_pi.clone() } else { g };
                gamma_cuts.push(g);
            }
        }
        integrate_nested(
            |gamma: &T, o: &Options| {
                let (c, s) = (gamma.cos(), gamma.sin());
                let m_max = if s < zero { Some(by.clone() / (-s.clone())) } else { None };
                if m_max.as_ref().is_some_and(|m| m.is_zero()) {
                    return Ok(Estimate::known(zero.clone(), zero.clone(), 0, o.rule));
                }
                let mut cuts = Vec::new();
                if !s.is_zero() {
                    cuts.push((r.clone() - by.clone()) / s.clone());
                }
                // The camera's circle: m² + 2m(z_y c + b_y s) + |y − o|² − R² = 0.
                let half_b = zy.clone() * c.clone() + by.clone() * s.clone();
                let disc = half_b.clone() * half_b.clone() - (dist.clone() - r.clone()) * (dist.clone() + r.clone());
                if disc > zero {
                    let root = disc.sqrt();
                    cuts.push(-half_b.clone() - root.clone());
                    cuts.push(-half_b.clone() + root);
                    cuts.push(-half_b);
                }
                let far = like.lit(4.0) / sigma.clone();
                // mρ₂ changes on the scale b_y (σ/4 at m = 0 to σb/2m), F on R.
                cuts.extend(graded_about(&zero, r, &far));
                if by > zero {
                    cuts.extend(graded_about(&zero, &by.clone().min_of(r.clone()), &far));
                }
                if let Some(m) = &m_max {
                    cuts.extend(graded_about(m, &(r.clone() / like.lit(10.0)), m));
                }
                let cuts: Vec<T> =
                    cuts.into_iter().filter(|m| *m > zero && m_max.as_ref().is_none_or(|x| m < x)).collect();
                let domain = match &m_max {
                    Some(m) => Domain::finite(zero.clone(), m.clone()).with_decay(sigma.clone()),
                    None => Domain::semi_infinite(zero.clone()).with_decay(sigma.clone()),
                }
                .with_breakpoints(cuts);
                integrate_within_pass(
                    |m: &T, o2: &Options| {
                        let (dz, db) = (m.clone() * c.clone(), (m.clone() * s.clone()).max_of(-by.clone()));
                        let at =
                            Offset { z: zy.clone() + dz.clone(), b: by.clone() + db.clone(), m: m.clone(), dz, db };
                        node(&at, o2)
                    },
                    &domain,
                    &Options { abs_tol: o.abs_tol.max(m_floor), ..o.clone() },
                )
            },
            &Domain::finite(zero.clone(), two_pi.clone()).with_breakpoints(gamma_cuts),
            opts,
        )
    }
}

impl<T: CheckRule> FiniteField<T> {
    /// The single-scattered part of μ (Mean) or of ∫σe^{−σs}⟨𝒞₁²⟩ (Second)
    /// by the virtual-light route: a check of [`FiniteField::scattered_mean`]
    /// and of the ⟨𝒞₁²⟩ in [`FiniteField::order1_second_added`] that shares
    /// no geometry with them; of C₂₃ (Pair23) or C₂₄ (Pair24), the share of
    /// one scattered segment meeting both spheres
    /// ([`FiniteField::order1_pair_added`]), with the pair options
    /// (`pair_options`) whoever calls it.
    pub fn order1_virtual(&self, which: Functional, opts: &Options) -> Result<Estimate<T>, crate::model::OracleError> {
        let opts = &match which {
            Functional::Pair23 | Functional::Pair24 => self.pair_options(opts),
            _ => opts.clone(),
        };
        self.order1_light_sum(which.name(), opts, |light, o| match light {
            FiniteLight::Point(p) => p.virtual_average(self, which, o),
            FiniteLight::Beam(b) => b.virtual_average(self, which, o),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `functional_bound` holds: for lights near the camera, on the camera
    /// line, inside and outside the spheres' cylinder, behind the camera and
    /// far away, at R = 0.5 and 0.05, in an isotropic medium and with
    /// g = 0.9, every functional's direction integral (goal 10⁻⁸), plus its
    /// bar, is at most the bound. Each at its own shift σ(|x₁ − o| − R)⁺, so
    /// that the values are of order 1 (the bound scales with e^{shift} as the
    /// functional does). The largest ratio is printed: the bound is far
    /// from tight (the halved exponent), as it need only be where it is used.
    #[test]
    fn far_functionals_stay_within_their_bound() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic-order1.toml");
        let base = mcrt_scene::Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        let mut largest = 0.0f64;
        for (radius, phase) in
            [(0.5, Phase::Isotropic), (0.05, Phase::Isotropic), (0.5, Phase::HenyeyGreenstein { g: 0.9 })]
        {
            let mut s = base.clone();
            s.estimator.radius = radius;
            s.medium.phase = phase;
            let field = crate::model::field::Field::from_scene(&s, &1.0f64).unwrap();
            let ff = FiniteField::of_first_segments(&s, &field);
            for (z, b) in [(0.05, 0.04), (0.3, 0.0), (1.0, 1.0), (3.0, 0.1), (-0.5, 0.3), (5.0, 2.0), (0.0, 0.6)] {
                let shift = (ff.sigma * (f64::hypot(z, b) - radius)).max(0.0);
                let light = PointLight::new(z, b, 1.0, &radius);
                for which in [Functional::Mean, Functional::Second, Functional::Pair23, Functional::Pair24] {
                    let v = light.ray_integral_in(&ff, which, &Options::rel(1e-8).declared(), false, &shift).unwrap();
                    let bound = functional_bound(&ff, which, &1.0, &z, &b, &shift);
                    assert!(
                        v.value + v.error <= bound,
                        "R {radius}, {phase:?}, (z, b) = ({z}, {b}), {which:?}: {} ± {} above the bound {bound}",
                        v.value,
                        v.error
                    );
                    largest = largest.max(v.value / bound);
                }
            }
        }
        println!("largest functional/bound: {largest:.3e}");
        assert!(largest > 0.0);
    }

    /// The ring density integrates to 1 over the half-plane (every first
    /// segment interacts somewhere): ∫dγ ∫ e^{−σm}·mρ₂ dm, for a light off
    /// the camera line (the φ-quadrature) and on it (the closed form).
    #[test]
    fn ring_density_integrates_to_one() {
        let sigma = 1.3f64;
        for (zy, by) in [(1.0f64, 1.0f64), (0.5, 0.0), (2.0, 0.03)] {
            let o = Options::rel(1e-9).declared();
            let total = integrate_nested(
                |gamma: &f64, o: &Options| {
                    let (c, s) = (gamma.cos(), gamma.sin());
                    let m_max = if s < 0.0 { by / -s } else { f64::INFINITY };
                    if m_max == 0.0 {
                        return Ok(Estimate::known(0.0, 0.0, 0, o.rule));
                    }
                    let cuts: Vec<f64> =
                        graded_about(&0.0, &by.max(1e-3), &(4.0 / sigma)).into_iter().filter(|m| *m > 0.0).collect();
                    let domain =
                        if m_max.is_finite() { Domain::finite(0.0, m_max) } else { Domain::semi_infinite(0.0) };
                    integrate_within_pass(
                        |m: &f64, o2: &Options| {
                            let b = (by + m * s).max(0.0);
                            let _ = zy + m * c;
                            Ok(ring_density(&sigma, m, &b, &by, o2)?.scaled(&(-sigma * m).exp()))
                        },
                        &domain.with_decay(sigma).with_breakpoints(cuts),
                        o,
                    )
                },
                &Domain::finite(0.0, 2.0 * std::f64::consts::PI)
                    .with_breakpoints([std::f64::consts::PI, 1.5 * std::f64::consts::PI]),
                &o,
            )
            .unwrap();
            assert!(
                (total.value - 1.0).abs() <= 1e-8 + total.error,
                "(z_y, b_y) = ({zy}, {by}): {} ± {}",
                total.value,
                total.error
            );
        }
    }
}
