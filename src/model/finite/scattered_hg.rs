//! Single-scattered light of a point light in a Henyey–Greenstein medium,
//! at any R (`docs/model.md` §9.9): ⟨𝒞₁^k⟩(s), the mean k-th power of the
//! contribution of a path's second segment to the sphere at s, the brick
//! of the exact order-1 mean (the isotropic one is `scattered`, whose
//! H(d) no longer serves: the second segment's direction is drawn about
//! the first's, and the score f(−u·ω) depends on it).
//!
//! The second segment starts at x₁, the end of the first (density
//! S₀ = σe^{−σr₁}/(4πr₁²) about the light y, r₁ = |x₁ − y|), along ω with
//! the density p(ω̂₀·ω), ω̂₀ = (x₁ − y)/r₁; it hits the sphere about x when
//! its line passes within R of x, at the closest point x + b (b ⊥ ω), and
//! that point lies ahead of x₁, ℓ ≥ 0 before it, and is reached
//! (e^{−σℓ}) — the tracer's rule (`reference/src/hits.rs`). With
//! x₁ = x + b − ℓω, d³x₁ = d²b dℓ:
//!
//!   ⟨𝒞₁^k⟩(s) = albedo (c^kΦ/𝓕) ∫_{S²} f(−u·ω)^k G(ω) dω,
//!   G(ω) = ∫_{|b|≤R} d²b ∫₀^∞ e^{−σℓ} S₀(x + b − ℓω) p(ω̂₀·ω) dℓ.
//!
//! G depends on ω only through θ, its angle from w = (x − y)/D: about that
//! axis f^k integrates over the azimuth in closed form ([`hg_ring`]). Along
//! the line of one b the light is at p from it (p = |b − b_y|, b_y the
//! light's foot in the disk's plane, δ = |b_y| = D sin θ from its centre)
//! and t = D cos θ behind x's plane; with α the angle between ω and
//! x₁ − y, r₁ = p/sin α, ℓ + r₁ = t + p tan(α/2) and dℓ/r₁² = dα/p, so
//!
//!   ∫₀^∞ … dℓ = (σ/(4πp)) ∫_{α_z}^π e^{−σ(t + p tan(α/2))} p(cos α) dα,  α_z = atan2(p, t),
//!
//! and in polar coordinates about b_y the 1/p cancels against d²b = p dp dφ,
//! the φ-range being the arc Θ(p) of the circle of radius p inside the
//! disk ([`arc_in_disc`]):
//!
//!   G(θ) = (σ/4π) ∫_{(δ−R)⁺}^{δ+R} Θ(p) V(p) dp,  V(p) = ∫_{α_z}^π e^{−σ(t + p tan(α/2))} p(cos α) dα.
//!
//! Three nested levels per s (θ, p, α), all bounded: the √-kinks of Θ at
//! p = |R − δ| and of G at δ = R (θ = arcsin(R/D), π − arcsin(R/D)), the
//! phase function's peak (width 1 − |g|) in α at 0 (g > 0) or π (g < 0),
//! hence in p at |t|(1 − |g|) and in θ near 0 and π, and the peak of f^k
//! at θ = γ (`angular::Frame`), are declared. With p = 1/4π the route is
//! an independent computation of the isotropic I(D) of `scattered`
//! (bipolar coordinates, E₁; no shared geometry): a unit test.

use super::point::PointLight;
use super::FiniteField;
use crate::model::angular::Frame;
use crate::model::field::graded_by;
use crate::model::same_path::{angle, scattering_phase};
use crate::quad::{integrate_within_pass, CheckRule, Domain, Estimate, Options, Outcome};
use crate::special::{arc_in_disc, hg_ring};
use mcrt_scene::Phase;

impl<T: CheckRule> PointLight<T> {
    /// ⟨𝒞₁^k⟩·e^{c₀} at s = center + x, k = `power` ∈ {1, 2}, for a medium
    /// of any phase function the module's route covers (Henyey–Greenstein,
    /// isotropic as g = 0): three nested levels within the caller's pass
    /// (module docs). Domain: any x, R > 0, |g| < 1. Not in the paper: its
    /// §3a takes the single-scattered radiance at the sphere's centre and
    /// its direction at the centre's (E10 for the cross-segment terms).
    pub(super) fn scattered_moment_hg(&self, ff: &FiniteField<T>, x: &T, power: i32, opts: &Options) -> Outcome<T> {
        let g = asymmetry(&ff.phase);
        let (d, mut cos_g, mut sin_g) = self.seen_from(ff, x);
        if d.is_zero() {
            // The light at the sphere's centre: every axis w is one, so u.
            (cos_g, sin_g) = (x.lit(1.0), x.lit(0.0));
        }
        let frame = Frame::new(cos_g, sin_g.clone());
        // The peak of f(−u·ω) lies at −sgn(g)u, γ from w.
        let gamma = if g > 0.0 { frame.psi_mirror.clone() } else { frame.psi_u.clone() };
        let pi = x.pi();
        let front =
            ff.per_hit_power(power, &self.flux) * ff.albedo.clone() * ff.sigma.clone() / (pi.clone() * x.lit(4.0));
        let mut cuts = frame.psi_breakpoints(&super::point::phase_features(ff));
        // G bends where the light's foot crosses the disk's rim (δ = R, at
        // θ_R and π − θ_R: cut there, not graded); near the poles it varies
        // on the scale of the phase function's peak (graded below).
        let theta_r = super::point::cap_half_angle(&d, &ff.radius);
        let half_pi = pi.clone() / x.lit(2.0);
        cuts.push(theta_r.clone());
        cuts.push(pi.clone() - theta_r);
        // The peak of p: forward photons arrive about θ = 0 (g > 0),
        // backward ones about π (g < 0).
        if let Some(w) = peak_width(g) {
            let pole = if g > 0.0 { x.lit(0.0) } else { pi.clone() };
            cuts.extend(graded_by(&pole, &x.lit(w), &half_pi, 4.0, 32));
        }
        cuts.retain(|c| *c > x.lit(0.0) && *c < pi);
        let level = Options { abs_tol: (opts.abs_tol / front.to_f64()).min(f64::MAX), ..opts.clone() };
        let e = integrate_within_pass(
            |theta: &T, o: &Options| {
                let w = theta.sin() * hg_ring(g, theta, &gamma, &sin_g, power);
                if w.is_zero() {
                    return Ok(Estimate::known(x.lit(0.0), x.lit(0.0), 0, o.rule));
                }
                let each = Options { abs_tol: (o.abs_tol / w.to_f64()).min(f64::MAX), ..o.clone() };
                Ok(disk_flux(ff, g, &d, theta, &each)?.scaled(&w))
            },
            &Domain::finite(x.lit(0.0), pi).with_breakpoints(cuts),
            &level,
        )?;
        Ok(e.scaled(&front))
    }
}

/// g of the medium's phase function (0 when isotropic).
pub(super) fn asymmetry(phase: &Phase) -> f64 {
    match *phase {
        Phase::HenyeyGreenstein { g } => g,
        Phase::Isotropic => 0.0,
    }
}

/// The angular width of the phase function's peak, (1 − |g|)/√|g| (the
/// half-width of 1/(1 + g² − 2g cos α)^{3/2}), or `None` for g = 0.
pub(super) fn peak_width(g: f64) -> Option<f64> {
    (g != 0.0).then(|| (1.0 - g.abs()) / g.abs().sqrt())
}

/// ∫_{(δ−R)⁺}^{δ+R} Θ(p) V(p) dp·e^{c₀} (G(θ)·4π/σ, module docs), δ = D sin θ,
/// t = D cos θ.
fn disk_flux<T: CheckRule>(ff: &FiniteField<T>, g: f64, d: &T, theta: &T, opts: &Options) -> Outcome<T> {
    let r = &ff.radius;
    let (delta, t) = (d.clone() * theta.sin(), d.clone() * theta.cos());
    let lo = if delta > *r { delta.clone() - r.clone() } else { d.lit(0.0) };
    let hi = delta.clone() + r.clone();
    let mut cuts = vec![(r.clone() - delta.clone()).abs()];
    if let Some(w) = peak_width(g) {
        cuts.extend(graded_by(&d.lit(0.0), &(t.abs() * d.lit(w)), &hi, 4.0, 12));
    }
    cuts.retain(|c| *c > lo && *c < hi);
    integrate_within_pass(
        |p: &T, o: &Options| {
            let arc = arc_in_disc(p, r, &delta);
            if arc.is_zero() {
                return Ok(Estimate::known(p.lit(0.0), p.lit(0.0), 0, o.rule));
            }
            let each = Options { abs_tol: (o.abs_tol / arc.to_f64()).min(f64::MAX), ..o.clone() };
            Ok(line_flux(ff, g, &t, p, &each)?.scaled(&arc))
        },
        &Domain::finite(lo, hi).with_breakpoints(cuts),
        opts,
    )
}

/// V(p)·e^{c₀} = ∫_{α_z}^π e^{c₀ − σ(t + p tan(α/2))} p(cos α) dα: the light
/// at p from the line, t behind the disk's plane (module docs). The exponent
/// is formed as r_z + p(tan(α/2) − tan(α_z/2)), r_z = √(t² + p²) the
/// distance from the light to where the line crosses the plane. Below π/2
/// the variable is α, above it β = π − α (exact where α nears π: a light
/// just ahead of the plane puts the whole range within 10⁻¹² of π, where
/// α would be quantised by ulp(π)); the difference of tangents is
/// sin((α − α_z)/2)/(cos(α/2) cos(α_z/2)), or in β,
/// sin((β_z − β)/2)/(sin(β/2) sin(β_z/2)).
fn line_flux<T: CheckRule>(ff: &FiniteField<T>, g: f64, t: &T, p: &T, opts: &Options) -> Outcome<T> {
    let (zero, two) = (p.lit(0.0), p.lit(2.0));
    let half_pi = p.pi() / two.clone();
    let r_z = (t.clone() * t.clone() + p.clone() * p.clone()).sqrt();
    let base = ff.shift.clone() - ff.sigma.clone() * r_z.clone();
    let sp = ff.sigma.clone() * p.clone();
    // The peak of p, graded by fours from its width (below π/2).
    let widths = |scale: Option<f64>| -> Vec<T> {
        scale.map_or_else(Vec::new, |w| graded_by(&zero, &p.lit(w), &half_pi, 4.0, 8))
    };
    // p(cos α) from 1 − cos α = 2 sin²(α/2) and 1 + cos α = 2 cos²(α/2).
    let leaf = |sh: &T, ch: &T, rise: T, o: &Options| {
        let attenuation = if p.is_zero() { base.clone().exp() } else { (base.clone() - sp.clone() * rise).exp() };
        let phase =
            scattering_phase(g, &(two.clone() * sh.clone() * sh.clone()), &(two.clone() * ch.clone() * ch.clone()));
        Ok(Estimate::known(attenuation * phase, zero.clone(), 1, o.rule))
    };
    let half = Options { abs_tol: opts.abs_tol / 2.0, ..opts.clone() };
    // β ∈ [0, β_hi]: the backward half (all of it when t < 0).
    let (beta_hi, cot_z) = if *t > zero {
        (half_pi.clone(), None)
    } else if p.is_zero() {
        // On the line through the light with t ≤ 0: the range [α_z, π] is empty.
        return Ok(Estimate::known(zero.clone(), zero, 0, opts.rule));
    } else {
        let beta_z = angle(&t.abs(), p);
        (beta_z.clone(), Some(beta_z))
    };
    if !(beta_hi > zero) {
        return Ok(Estimate::known(zero.clone(), zero, 0, opts.rule));
    }
    // tan(α_z/2) for t > 0: p/(r_z + t).
    let tan_z = if *t > zero { p.clone() / (r_z.clone() + t.clone()) } else { zero.clone() };
    let mut cuts = widths(if g < 0.0 { peak_width(g) } else { None });
    // e^{−σp cot(β/2)} rises from 0 at β ~ 2σp: sharp only when σp is
    // small (graded by fours from there, at most 12 cuts).
    cuts.extend(graded_by(&zero, &(sp.clone() * two.clone()), &p.lit(0.25), 4.0, 12));
    cuts.retain(|c| *c > zero && *c < beta_hi);
    let back = integrate_within_pass(
        |beta: &T, o: &Options| {
            let hb = beta.clone() / two.clone();
            let (sb, cb) = (hb.sin(), hb.cos());
            let rise = match &cot_z {
                None => cb.clone() / sb.clone() - tan_z.clone(),
                Some(bz) => {
                    ((bz.clone() - beta.clone()) / two.clone()).sin() / (sb.clone() * (bz.clone() / two.clone()).sin())
                }
            };
            leaf(&cb, &sb, rise, o)
        },
        &Domain::finite(zero.clone(), beta_hi).with_breakpoints(cuts),
        &half,
    )?;
    if cot_z.is_some() {
        return Ok(back);
    }
    // α ∈ [α_z, π/2]: the forward half (t > 0).
    let alpha_z = angle(t, p);
    if !(alpha_z < half_pi) {
        return Ok(back);
    }
    let cos_z = (alpha_z.clone() / two.clone()).cos();
    let mut cuts = widths(if g > 0.0 { peak_width(g) } else { None });
    cuts.retain(|c| *c > alpha_z && *c < half_pi);
    let front = integrate_within_pass(
        |alpha: &T, o: &Options| {
            let ha = alpha.clone() / two.clone();
            let (sa, ca) = (ha.sin(), ha.cos());
            let rise = ((alpha.clone() - alpha_z.clone()) / two.clone()).sin() / (ca.clone() * cos_z.clone());
            leaf(&sa, &ca, rise, o)
        },
        &Domain::finite(alpha_z.clone(), half_pi).with_breakpoints(cuts),
        &half,
    )?;
    Ok(back.plus(front))
}

#[cfg(test)]
mod tests {
    use super::super::scattered_table::ScatteredTables;
    use super::super::FiniteLight;
    use super::*;
    use crate::model::field::Field;
    use mcrt_scene::Scene;

    use super::super::order1_test_field as field_at;

    /// With p = 1/4π (g = 0) the route of this module — (θ, p, α) about the
    /// light's foot in the disk — is an independent computation of the
    /// isotropic ⟨𝒞₁^k⟩ of `scattered` (I(D) in bipolar coordinates, E₁):
    /// at points on both sides of the light's foot and far, at R = 0.5 and
    /// 0.05, and at R = 1.5, where the sphere holds the light (D < R) at
    /// s = 1 and 1.3, k = 1 and 2, the two agree within their bars.
    #[test]
    fn at_g_zero_the_route_is_the_isotropic_one() {
        for radius in [0.5, 0.05, 1.5] {
            let iso = field_at(radius, Phase::Isotropic);
            let zero = field_at(radius, Phase::HenyeyGreenstein { g: 0.0 });
            let FiniteLight::Point(light) = &iso.lights[0] else { panic!("a point light") };
            let tables = ScatteredTables::default();
            for s in [0.2, 1.0, 1.3, 2.5] {
                let x = s - iso.center;
                for power in [1, 2] {
                    let opts = Options::rel(1e-9).declared();
                    let want = light.scattered_moment(&iso, &tables, &x, power, &opts).unwrap();
                    let got = light.scattered_moment_hg(&zero, &x, power, &Options::rel(1e-7).declared()).unwrap();
                    let (d, _) = light.distance_to(&iso, &x);
                    let off = (got.value / want.value - 1.0).abs();
                    let allowed = (got.error + want.error) / want.value + 1e-12;
                    println!("R {radius}, s {s} (D {d:.4}), k {power}: {:.12e} vs {:.12e}, off {off:.2e}, allowed {allowed:.2e}, {} evaluations", got.value, want.value, got.evaluations);
                    assert!(
                        off <= allowed,
                        "R {radius}, s {s}, k {power}: {} ± {} vs {} ± {}",
                        got.value,
                        got.error,
                        want.value,
                        want.error
                    );
                }
            }
        }
    }

    /// With g ≠ 0 (the forms of p at both peaks, the choice of f^k's peak
    /// direction, the cuts): as R → 0 the route tends at a camera-ray point
    /// to the small-sphere ⟨𝒞₁⟩ of §3a (L₁ integrated over directions at
    /// the centre: another computation), their relative gap of second order
    /// in R — fitted between R = 0.004 and 0.002 within [1.8, 2.2], each gap
    /// at least ten times its bar — at g = 0.9 and −0.5, before and past the
    /// light's foot.
    #[test]
    fn with_g_the_route_tends_to_the_small_sphere_mean_at_second_order() {
        use crate::quad::Rule;
        for g in [0.9, -0.5] {
            for s in [0.5, 2.0] {
                let gaps: Vec<(f64, f64)> = [0.004, 0.002]
                    .iter()
                    .map(|&radius| {
                        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic-order1.toml");
                        let mut scene = Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
                        scene.estimator.radius = radius;
                        scene.medium.phase = Phase::HenyeyGreenstein { g };
                        let field = Field::from_scene(&scene, &1.0f64).unwrap();
                        let ff = FiniteField::of_first_segments(&scene, &field);
                        let FiniteLight::Point(light) = &ff.lights[0] else { panic!("a point light") };
                        let x = s - ff.center;
                        let o = Options { rule: Rule::Kronrod, ..Options::rel(1e-8).declared() };
                        let finite = light.scattered_moment_hg(&ff, &x, 1, &o).unwrap();
                        let small =
                            crate::model::moments::scattered_mean(&field, &(s - field.center), &Options::rel(1e-10))
                                .unwrap();
                        let (f, sm) = (finite.value * (-ff.shift).exp(), small.value * (-field.shift).exp());
                        let bar = finite.error / finite.value + small.error / small.value;
                        (f / sm - 1.0, bar)
                    })
                    .collect();
                let order = (gaps[0].0 / gaps[1].0).log2();
                println!(
                    "g {g}, s {s}: gaps {:.4e} ± {:.1e}, {:.4e} ± {:.1e}: order {order:.3}",
                    gaps[0].0, gaps[0].1, gaps[1].0, gaps[1].1
                );
                assert!(gaps.iter().all(|(gap, bar)| gap.abs() >= 10.0 * bar), "g {g}, s {s}: {gaps:?}");
                assert!((1.8..=2.2).contains(&order), "g {g}, s {s}: order {order}");
            }
        }
    }
}
