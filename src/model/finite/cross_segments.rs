//! Order-1 correlations of the two segments of one path (`docs/model.md`
//! §9.7): the uncollided segment hits the sphere at s, the scattered one
//! the sphere at s′ (and the mirror pair). Isotropic media, point lights.
//!
//! Given the interaction point x₁ (density σe^{−σr₁}/(4πr₁²), r₁ = |x₁ − y|)
//! the first segment is the chord y → x₁: it hits exactly the spheres of
//! its hit interval J (§9.2) whose closest points it reaches, τ(s) ≤ r₁,
//! an interval [s₀, s₁] of the camera line. The second segment, isotropic
//! from x₁, hits the sphere at s′ with the chance H(|x₁ − x(s′)|) (§9.5)
//! whatever the first did. With the weights of §9.1 the pair adds
//!
//!   X₂₄ = 2∫∫σ²e^{−σ(s+s′)}⟨𝒞₀(s)𝒞₁(s′)⟩ = 2κ ∫ρ(x₁) σe^{−σs₀}F₁(σ, s₁ − s₀) · σB(∞) d³x₁,
//!   X₂₃ = ∫∫σ²e^{−σ max(s,s′)}⟨𝒞₀(s)𝒞₁(s′)⟩ = κ ∫ρ(x₁) [𝒦(s₁) − 𝒦(s₀)] d³x₁,
//!
//! κ = albedo c²f² Φ/𝓕 (f = 1/4π), to C₂₄ and C₂₃, where with the
//! cumulants A, B, C of H along the camera line from x₁
//! (`hit_cumulants`) and E(s) = σ(B(∞) − B(s)),
//!
//!   K(s) = ∫σ²e^{−σ max(s,s′)}H(s′)ds′ = σ²e^{−σs}A(s) + σE(s),
//!   𝒦(s) = ∫₀^s K = −σe^{−σs}A(s) + σB(s) + σsE(s) + σ²C(s)
//!
//! (by parts; the unit test `big_k_is_the_weighted_hit_count` checks
//! 𝒦(s₁) − 𝒦(s₀) against a direct quadrature). x₁ is
//! integrated in cylindrical coordinates about the camera line: the
//! half-plane (z, b) by `PointLight::over_half_plane` and the azimuth φ
//! about the line, measured from the light's, here.

use super::hit_cumulants::HitCumulants;
use super::point::PointLight;
use super::ray::Functional;
use super::virtual_lights::Offset;
use super::{FiniteField, FiniteLight};
use crate::model::angular::Direction;
use crate::model::field::graded_by;
use crate::quad::{integrate_within_pass, CheckRule, Domain, Estimate, Failure, Options, Outcome};
use crate::special::exp_segment;
use std::sync::OnceLock;

/// Which correlation the pair feeds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CrossPair {
    /// C₂₃ (16): the later sphere's attenuation, σ²e^{−σ max(s, s′)}.
    C23,
    /// C₂₄ (18): both spheres', σ²e^{−σ(s + s′)}.
    C24,
}

/// The first segment y → x₁ as the hit geometry of §9.2 sees it.
struct Chord<T> {
    dir: Direction<T>,
    /// B = b_y cos χ and the window half-width √(R² − q²) (`None`: the
    /// chord's line passes farther than R from the camera line, or runs
    /// along it).
    window: Option<(T, T)>,
    r1: T,
}

impl<T: CheckRule> PointLight<T> {
    /// X₂₃ or X₂₄ of this light (module docs), times e^{c₀}.
    pub(super) fn cross_segments(&self, ff: &FiniteField<T>, pair: CrossPair, opts: &Options) -> Outcome<T> {
        let like = &self.z;
        let sigma = &ff.sigma;
        // Floors for inner integrals asked for a relative goal only (the
        // coarse pass): a hundredth of their goal of the light's own
        // order-0 pair functional, spread as σ²m e^{−σm}/2π over the plane.
        let which = match pair {
            CrossPair::C23 => Functional::Pair23,
            CrossPair::C24 => Functional::Pair24,
        };
        let kappa = self.cross_constant(ff);
        let scale =
            (self.ray_integral(ff, which, &Options { rel_tol: 1e-3, abs_tol: 0.0, ..opts.clone() })?.value.abs()
                / kappa.clone())
            .to_f64();
        let node = |at: &Offset<T>, o2: &Options| -> Outcome<T> {
            let (m, b) = (&at.m, &at.b);
            if b.is_zero() || m.is_zero() {
                return Ok(Estimate::known(like.lit(0.0), like.lit(0.0), 1, o2.rule));
            }
            let spread = sigma.to_f64().powi(2) * m.to_f64() * (-(sigma.to_f64() * m.to_f64())).exp()
                / (2.0 * std::f64::consts::PI);
            let floor = o2.rel_tol * scale / 100.0 * spread;
            let each = Options { abs_tol: o2.abs_tol.max(floor).min(f64::MAX), ..o2.clone() };
            self.around_line(ff, pair, at, &each)
        };
        let o = Options { abs_tol: (opts.abs_tol / kappa.to_f64()).min(f64::MAX), ..opts.clone() };
        // The m-integral at each outer angle γ gets a floor too, a hundredth
        // of the goal of the scale spread evenly over γ ∈ [0, 2π): the
        // nested integral's scale pass asks its inner levels for a relative
        // goal only, which an m-integral far from where the mass lies (a
        // light 300/σ from the camera line: ~e^{−300} of the total, its
        // nodes carrying errors at their own floors) could not meet.
        let m_floor = opts.rel_tol * scale / 100.0 / (2.0 * std::f64::consts::PI);
        let e = self.over_half_plane(ff, &node, &o, m_floor).map_err(|f| f.scaled(&kappa))?;
        Ok(e.scaled(&kappa))
    }

    /// κ = albedo c²f²Φ/𝓕 with f = 1/4π.
    pub(super) fn cross_constant(&self, ff: &FiniteField<T>) -> T {
        let f = self.z.lit(1.0) / (self.z.pi() * self.z.lit(4.0));
        ff.per_hit_power(2, &self.flux) * f.clone() * f * ff.albedo.clone()
    }

    /// m b ∫₀^{2π} ρ(x₁) W(x₁) dφ at the ring (z, b), m from the light (W:
    /// 2σe^{−σs₀}F₁σB(∞) or 𝒦(s₁) − 𝒦(s₀)), times e^{c₀}; φ ↔ −φ
    /// symmetric. ρ's 1/r₁² is formed as (m/r₁)/r₁ (r₁ ≥ m), which neither
    /// overflows nor underflows as x₁ nears the light. The cumulants of x₁
    /// are built at the first φ whose chord hits.
    fn around_line(&self, ff: &FiniteField<T>, pair: CrossPair, at: &Offset<T>, opts: &Options) -> Outcome<T> {
        let like = &self.z;
        let (m, z, b) = (&at.m, &at.z, &at.b);
        let (sigma, r) = (&ff.sigma, &ff.radius);
        let zero = like.lit(0.0);
        let cumulants: OnceLock<Result<HitCumulants<T>, Failure<T>>> = OnceLock::new();
        let f = |phi: &T, o: &Options| -> Outcome<T> {
            let nothing = Ok(Estimate::known(zero.clone(), zero.clone(), 1, o.rule));
            let chord = self.chord(r, at, phi);
            let Some((bcos, rho)) = chord.window.clone() else { return nothing };
            let Some((hit, taus)) = self.hit_with_ends(&chord.dir, &self.azimuth(bcos, rho)) else { return nothing };
            let Some((s0, s1, len)) = reached(&hit, &taus, &chord.dir.mu, &chord.r1) else { return nothing };
            // Both weights carry e^{c₀ − σ(r₁ + s₀)} (W ≤ 2σ² up to it).
            if (ff.shift.clone() - sigma.clone() * (chord.r1.clone() + s0.clone())).exp().is_zero() {
                return nothing;
            }
            // The build's evaluations are charged to the sample that needs it.
            let first = cumulants.get().is_none();
            let c = cumulants.get_or_init(|| HitCumulants::new(sigma, r, z, b));
            let c = c.as_ref().map_err(Failure::clone)?;
            let evaluations = if first { 1 + c.evaluations } else { 1 };
            let r1 = &chord.r1;
            let density = (m.clone() / r1.clone()).min_of(like.lit(1.0)) / r1.clone() * sigma.clone() * b.clone()
                / (like.pi() * like.lit(4.0));
            let (value, error) = cross_weight(ff, pair, c, [&s0, &s1, &len], r1, &density, o.rel_tol, [z, b])?;
            Ok(Estimate::known(value, error, evaluations, o.rule))
        };
        let mut cuts = self.window_edges(r, b);
        // ρ's 1/r₁², r₁² = m² + 4bb_y sin²(φ/2), peaks at φ = 0 with the
        // width m/√(bb_y): graded by decades from it (at m = 10⁻³⁰ C₂₃ took
        // 9·10³ evaluations so, 2.7·10⁴ without).
        let bby = b.clone() * self.b.clone();
        if bby > zero && *m > zero {
            let width = m.clone() / bby.sqrt();
            cuts.extend(graded_by(&zero, &width, &like.pi(), 10.0, 40).into_iter().filter(|c| *c > zero));
        }
        let e = integrate_within_pass(f, &Domain::finite(like.lit(0.0), like.pi()).with_breakpoints(cuts), opts)?;
        Ok(e.scaled(&like.lit(2.0)))
    }

    /// The chord y → x₁ for x₁ at foot z, distance b, azimuth φ from the
    /// light's about the camera line, in the light's frame (ϑ about u, χ = 0
    /// towards the line), its quantities formed without cancellation.
    fn chord(&self, r: &T, at: &Offset<T>, phi: &T) -> Chord<T> {
        let like = &self.z;
        let (by, two) = (&self.b, like.lit(2.0));
        let b = &at.b;
        let half = (phi.clone() / two.clone()).sin();
        // |d_⊥|² = (b − b_y)² + 4 b b_y sin²(φ/2), b − b_y and z − z_y as
        // formed from m (`Offset`).
        let db = at.db.clone();
        let across = two.clone() * (b.clone() * by.clone()).sqrt() * half.abs();
        let dz = at.dz.clone();
        // Scaled, so that nothing underflows as x₁ nears the light.
        let big = db.abs().max_of(across.clone()).max_of(dz.abs());
        if big.is_zero() {
            let dir = Direction {
                mu: like.lit(0.0),
                one_minus_mu: like.lit(1.0),
                one_plus_mu: like.lit(1.0),
                sin: like.lit(0.0),
            };
            return Chord { dir, window: None, r1: big };
        }
        let (u, v, w) = (db.clone() / big.clone(), across / big.clone(), dz / big.clone());
        // Normalised by `big`: p2 = |d_⊥|²/big², rn = r₁/big.
        let p2 = u.clone() * u + v.clone() * v;
        let rn = (p2.clone() + w.clone() * w.clone()).sqrt();
        let (perp, r1) = (p2.clone().sqrt() * big.clone(), rn.clone() * big.clone());
        let mu = w.clone() / rn.clone();
        let (one_minus_mu, one_plus_mu) = if w >= like.lit(0.0) {
            (p2.clone() / (rn.clone() * (rn.clone() + w.clone())), (rn.clone() + w) / rn.clone())
        } else {
            ((rn.clone() - w.clone()) / rn.clone(), p2.clone() / (rn.clone() * (rn.clone() - w)))
        };
        let dir = Direction { mu, one_minus_mu, one_plus_mu, sin: p2.sqrt() / rn };
        if perp.is_zero() {
            return Chord { dir, window: None, r1 };
        }
        // cos χ = (b_y − b cos φ)/|d_⊥|, b_y − b cos φ = (b_y − b) + 2b sin²(φ/2);
        // the line's distance from the camera line is b_y b |sin φ|/|d_⊥|.
        let towards = -db + two * b.clone() * half.clone() * half;
        let bcos = by.clone() * towards / perp.clone();
        let q = by.clone() * b.clone() * phi.sin().abs() / perp;
        let window = if q > *r { None } else { Some((bcos, ((r.clone() - q.clone()) * (r.clone() + q)).sqrt())) };
        Chord { dir, window, r1 }
    }

    /// The azimuths φ ∈ (0, π) where the chord's line passes exactly R from
    /// the camera line: cos φ = (R² ± √((b² − R²)(b_y² − R²)))/(b b_y).
    fn window_edges(&self, r: &T, b: &T) -> Vec<T> {
        let by = &self.b;
        let one = r.lit(1.0);
        let prod =
            ((b.clone() - r.clone()) * (b.clone() + r.clone())) * ((by.clone() - r.clone()) * (by.clone() + r.clone()));
        if b.is_zero() || by.is_zero() || prod < r.lit(0.0) {
            return Vec::new();
        }
        let root = prod.sqrt();
        let r2 = r.clone() * r.clone();
        [r2.clone() - root.clone(), r2 + root]
            .into_iter()
            .map(|t| t / (b.clone() * by.clone()))
            .filter(|c| *c > -one.clone() && *c < one)
            .map(|c| c.acos())
            .collect()
    }
}

/// The weight W of one path (module docs) times `density`, times e^{c₀},
/// and its bar: the first segment reaches x₁ over `path` (e^{−σ·path}) and
/// hits the spheres [s₀, s₁] = [s₀, s₀ + ℓ] on the way (`reach`, ℓ formed
/// without cancellation, ∞ allowed), the second starts at x₁ with the
/// cumulants `c`. Shared by point lights (path r₁, the chord from the
/// light) and beams (path t, the depth of x₁ in the beam,
/// `beam_pairs`). Fails where the weight is not finite (`at`: x₁'s foot
/// and distance, for the message).
#[allow(clippy::too_many_arguments)]
pub(super) fn cross_weight<T: CheckRule>(
    ff: &FiniteField<T>,
    pair: CrossPair,
    c: &HitCumulants<T>,
    [s0, s1, len]: [&T; 3],
    path: &T,
    density: &T,
    rel_tol: f64,
    [z, b]: [&T; 2],
) -> Result<(T, T), Failure<T>> {
    let like = path;
    let sigma = &ff.sigma;
    let (value, error) = match pair {
        CrossPair::C24 => {
            let finite_len = if len.is_finite() { Some(len.clone()) } else { None };
            // e^{−σt₀} of B's scaling in the same exponent.
            let u = sigma.clone()
                * (ff.shift.clone() - sigma.clone() * (path.clone() + s0.clone() + c.t0.clone())).exp()
                * exp_segment(sigma, finite_len.as_ref());
            let v = sigma.clone() * c.b_total();
            let k = like.lit(2.0) * u * density.clone();
            (k.clone() * v, k * sigma.clone() * c.error[1].clone())
        }
        CrossPair::C23 => {
            let lambda = ff.shift.clone() - sigma.clone() * (path.clone() + c.t0.clone());
            let (k1, e1) = big_k(sigma, c, s1, &lambda);
            let (k0, e0) = big_k(sigma, c, s0, &lambda);
            // The difference carries both cumulants' whole bars;
            // a short interval (a chord from near the light) is
            // taken as one slice instead, whichever bar is smaller.
            let (mut k, mut e) = (k1 - k0, e1 + e0);
            if len.is_finite() {
                let (short, short_error) = short_k(sigma, c, s0, len, &lambda);
                // The differences span s₁ − s₀ as rounded, not ℓ:
                // K(s₀) ≈ short/ℓ times the gap joins their bars.
                let gap = ((s1.clone() - s0.clone()) - len.clone()).abs();
                let slip = gap * (short.abs() + short_error.clone()) / len.clone();
                e = e + slip.clone();
                // The increments' form (a Gauss–Legendre sum of the
                // cumulants' interpolants: dearer) where the cheaper
                // bars are not far below this integral's relative aim.
                let fine = short_error.clone().min_of(e.clone());
                if fine > k.abs() * like.lit(rel_tol / 64.0) {
                    let (local, local_error) = k_between(sigma, c, s0, s1, &lambda);
                    if local_error.clone() + slip.clone() < e {
                        (k, e) = (local, local_error + slip);
                    }
                }
                if short_error < e {
                    (k, e) = (short, short_error);
                }
            }
            (k * density.clone(), e * density.clone())
        }
    };
    if !value.is_finite() || !error.is_finite() {
        return Err(Failure {
            reason: format!("cross-segment weight not finite at z {:e}, b {:e}", z.to_f64(), b.to_f64()),
            best_guess: None,
            error_estimate: None,
            evaluations: 1,
        });
    }
    Ok((value, error))
}

/// The spheres [s₀, s₀ + ℓ] of J whose closest points a chord of length
/// r₁ reaches (0 ≤ τ(s) ≤ r₁; τ(s) = τ(a) + μ(s − a)), as (s₀, s₁, ℓ), or
/// `None`. The length ℓ is formed from τ at J's ends (`taus`, each from its
/// active bound): min(L, (r₁ − τ(a))/μ) for μ > 0, min(L, (r₁ − τ(a + L))/|μ|)
/// for μ < 0, never as a difference of positions — a chord from next to the
/// light (r₁ ~ 10⁻²⁷) reaches spheres over ~r₁, far below ulp(s), and
/// s₁ − s₀ formed from positions was rounding (10⁻¹³ where ℓ was 10⁻²⁷).
fn reached<T: CheckRule>(hit: &super::ray::Hit<T>, [tau_lo, tau_hi]: &[T; 2], mu: &T, r1: &T) -> Option<(T, T, T)> {
    let zero = mu.lit(0.0);
    let (a, len) = (&hit.start, &hit.len);
    // τ ≥ 0 on J; a window bound chosen by rounding over the light's (their
    // positions within an ulp) gives a τ below 0 by as much, which would
    // lengthen ℓ by |τ|/|μ| ≫ r₁/|μ| for the shortest chords.
    let (tau_lo, tau_hi) = (tau_lo.clone().max_of(zero.clone()), tau_hi.clone().max_of(zero.clone()));
    let (s0, l) = if *mu > zero {
        if !(tau_lo < *r1) {
            return None;
        }
        (a.clone(), ((r1.clone() - tau_lo) / mu.clone()).min_of(len.clone()))
    } else if *mu < zero {
        if !(tau_hi < *r1) {
            return None;
        }
        let l = ((r1.clone() - tau_hi) / (-mu.clone())).min_of(len.clone());
        // J is bounded above for μ < 0 (by the window or the light).
        (a.clone() + (len.clone() - l.clone()), l)
    } else if tau_lo <= *r1 {
        (a.clone(), len.clone())
    } else {
        return None;
    };
    (l > zero).then(|| (s0.clone(), s0 + l.clone(), l))
}

/// e^{λ}·e^{σt₀}𝒦(s) and its bar from the cumulants (module docs; B, C
/// come scaled by e^{σt₀}, and e^{−σs}A becomes e^{−σ(s − t₀)}A, formed in
/// one exponent with ln A and its bar's with λ, so that nothing overflows
/// where s lies far below the start's foot).
fn big_k<T: CheckRule>(sigma: &T, c: &HitCumulants<T>, s: &T, lambda: &T) -> (T, T) {
    let [a, b, cc] = c.at(s);
    let [ea, eb, ec] = c.error.clone();
    let shifted = sigma.clone() * (s.clone() - c.t0.clone());
    let front = lambda.clone().exp();
    // (A ≤ 0 only by rounding at a piece's start, where it is 0.)
    let decay_a = if a > s.lit(0.0) { (lambda.clone() + a.ln() - shifted.clone()).exp() } else { s.lit(0.0) };
    let s = if s.is_finite() { s.clone() } else { s.lit(0.0) };
    let e = sigma.clone() * (c.b_total() - b.clone());
    let rest = sigma.clone() * b + sigma.clone() * s.clone() * e + sigma.clone() * sigma.clone() * cc;
    let value = -(sigma.clone() * decay_a) + rest * front.clone();
    let error = sigma.clone() * (lambda.clone() - shifted).exp() * ea
        + (sigma.clone() * eb * (s.lit(1.0) + s.lit(2.0) * sigma.clone() * s.clone())
            + sigma.clone() * sigma.clone() * ec)
            * front;
    (value, error)
}

/// e^{λ}·e^{σt₀}(𝒦(s₁) − 𝒦(s₀)) and its bar from the cumulants'
/// increments over [s₀, s₁] (0 ≤ s₀ ≤ s₁ < ∞; [`HitCumulants::between`]),
/// whose bars shrink with s₁ − s₀ where [`big_k`]'s difference bears both
/// cumulants' whole bars. With ℓ = s₁ − s₀, ΔA, ΔB, ΔC the increments
/// (B, C scaled by e^{σt₀}) and E = σ(B(∞) − B),
///
///   𝒦(s₁) − 𝒦(s₀) = σe^{−σs₀}(A(s₀)(1 − e^{−σℓ}) − e^{−σℓ}ΔA) + σΔB
///                  + σℓE(s₁) + σ²(ΔC − s₀ΔB),
///
/// (from 𝒦 = −σe^{−σs}A + σB + σsE + σ²C, with sE(s) differenced as
/// ℓE(s₁) + s₀(E(s₁) − E(s₀)) and E(s₁) − E(s₀) = −σΔB), so every bar
/// but the rounding carries a factor ℓ: the whole bar of A(s₀) and of
/// E(s₁) times σℓ-sized weights, the increments' own ones. At a chord
/// reaching the spheres over ℓ = 10⁻⁶ next to a light 10⁻⁶ from the camera
/// line the bar fell from 2·10⁻⁷ of the value ([`big_k`] and [`short_k`],
/// whose rest is ℓ²K′/2) to ~10⁻¹², and the azimuthal integral that
/// could not meet 5·10⁻⁸ at 10⁻⁵ converges.
fn k_between<T: CheckRule>(sigma: &T, c: &HitCumulants<T>, s0: &T, s1: &T, lambda: &T) -> (T, T) {
    let zero = s0.lit(0.0);
    let len = s1.clone() - s0.clone();
    let ([da, db, dc], [ea_local, eb_local, ec_local]) = c.between(s0, s1);
    let [a0, _, _] = c.at(s0);
    let [ea, eb, _] = c.error.clone();
    let [_, b1, _] = c.at(s1);
    let decay = (-(sigma.clone() * len.clone())).exp();
    let rise = -(-(sigma.clone() * len.clone())).exp_m1();
    // e^{λ − σ(s₀ − t₀)} in one exponent, so that neither factor overflows
    // alone (big_k also folds ln A into its own).
    let argument = lambda.clone() - sigma.clone() * (s0.clone() - c.t0.clone());
    let near = argument.clone().exp();
    let front = lambda.clone().exp();
    let e1 = sigma.clone() * (c.b_total() - b1);
    let first = sigma.clone() * near.clone() * (a0.max_of(zero.clone()) * rise.clone() - decay.clone() * da);
    let second = sigma.clone() * db.clone();
    let third = sigma.clone() * len.clone() * e1;
    let fourth = sigma.clone() * sigma.clone() * (dc - s0.clone() * db);
    let value = first.clone() + (second.clone() + third.clone() + fourth.clone()) * front.clone();
    let sigma2 = sigma.clone() * sigma.clone();
    let error = sigma.clone() * near * (ea * rise + decay * ea_local)
        + (sigma.clone() * eb_local.clone()
            + sigma.clone() * len * sigma.clone() * eb.clone() * s0.lit(2.0)
            + sigma2 * (ec_local + s0.clone() * eb_local))
            * front.clone()
        // Rounding: of the sums, and of each exponent's argument (a relative
        // error ε·|argument| in its exponential).
        + (first.abs() * (s0.lit(8.0) + argument.abs())
            + (second.abs() + third.abs() + fourth.abs()) * front * (s0.lit(8.0) + lambda.abs()))
            * s0.eps();
    (value, error)
}

/// e^{λ}·e^{σt₀}(𝒦(s₁) − 𝒦(s₀)) and its bar as one slice, ℓ·K(s₀), for
/// s₁ = s₀ + ℓ (finite ℓ = `len` > 0, formed as [`reached`] does): K =
/// σ²e^{−σs}A + σE has K′ = −σ³e^{−σs}A (E′ = −σ²e^{−σs}H cancels the H of
/// the first term's derivative), so the rest is at most
/// ℓ²/2·σ³e^{−σs₀}A(s₁) in size. Its bar grows with ℓ where
/// [`big_k`]'s difference carries both cumulants' whole bars: for a chord
/// from near the light (length ~m, the distance of x₁ from it, down to
/// 10⁻²⁴ at the nodes next to the light) the difference's bar was 10¹⁰
/// times its value and the azimuthal integral never met its goal.
fn short_k<T: CheckRule>(sigma: &T, c: &HitCumulants<T>, s0: &T, len: &T, lambda: &T) -> (T, T) {
    let zero = s0.lit(0.0);
    let ([a0, b0, _], [a1, _, _]) = (c.at(s0), c.at(&(s0.clone() + len.clone())));
    let [ea, eb, _] = c.error.clone();
    let sigma2 = sigma.clone() * sigma.clone();
    // e^{λ − σ(s₀ − t₀)} times A, formed in one exponent (as big_k).
    let exponent = lambda.clone() - sigma.clone() * (s0.clone() - c.t0.clone());
    let times = |v: T| if v > zero { (exponent.clone() + v.ln()).exp() } else { zero.clone() };
    let front = lambda.clone().exp();
    let k0 = sigma2.clone() * times(a0) + sigma2.clone() * front.clone() * (c.b_total() - b0);
    let k0_error = sigma2.clone() * exponent.clone().exp() * ea.clone() + sigma2.clone() * front * eb * s0.lit(2.0);
    let slope = sigma2 * sigma.clone() * times(a1 + ea);
    let rest = len.clone() * len.clone() / s0.lit(2.0) * slope;
    (len.clone() * k0, len.clone() * k0_error + rest)
}

impl<T: CheckRule> FiniteField<T> {
    /// Σ over the lights of X₂₃ or X₂₄ (`cross_segments`), times e^{c₀}.
    pub fn order1_cross(&self, pair: CrossPair, opts: &Options) -> Result<Estimate<T>, crate::model::OracleError> {
        let opts = &self.pair_options(opts);
        self.order1_light_sum("finite-sphere cross-segment pairs", opts, |light, o| match light {
            FiniteLight::Point(p) => p.cross_segments(self, pair, o),
            FiniteLight::Beam(b) => b.cross_segments(self, pair, o),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::finite::scattered::hit_chance;
    use crate::quad::integrate;

    /// 𝒦(s₁) − 𝒦(s₀) against ∫ds′ H(s′) σ²∫_{s₀}^{s₁}e^{−σ max(s, s′)} ds by
    /// direct quadrature (the inner s-integral in closed form), for starts
    /// inside, at and outside the cylinder and intervals before, around and
    /// after the start's foot.
    #[test]
    fn big_k_is_the_weighted_hit_count() {
        let (sigma, r) = (0.9f64, 0.25f64);
        for (z, b) in [(1.0, 0.1), (0.6, 0.25), (2.0, 0.8), (0.2, 1.5)] {
            let c = HitCumulants::new(&sigma, &r, &z, &b).unwrap();
            for (s0, s1) in [
                (0.1, 0.4),
                (0.8, 1.3),
                (1.9, 2.05),
                (0.0, 6.0),
                (3.0, 3.0001),
                (0.95, 0.95 + 1e-9),
                (0.95, 0.95 + 1e-6),
                (0.5, 150.0),
            ] {
                let lambda = -sigma * c.t0;
                let (k1, e1) = big_k(&sigma, &c, &s1, &lambda);
                let (k0, e0) = big_k(&sigma, &c, &s0, &lambda);
                // σ²∫_{s₀}^{s₁} e^{−σ max(s, s′)} ds, piecewise in s′ (the
                // differences of exponentials by expm1: free of cancellation
                // on short intervals).
                let fall = |from: f64, to: f64| -(-sigma * from).exp() * (-sigma * (to - from)).exp_m1() / sigma;
                let weight = |sp: f64| {
                    let inner = if sp <= s0 {
                        fall(s0, s1)
                    } else if sp >= s1 {
                        (s1 - s0) * (-sigma * sp).exp()
                    } else {
                        (sp - s0) * (-sigma * sp).exp() + fall(sp, s1)
                    };
                    sigma * sigma * inner
                };
                let f = |sp: &f64| {
                    let d = ((sp - z) * (sp - z) + b * b).sqrt();
                    hit_chance(&sigma, &r, &d) * weight(*sp)
                };
                let mut bps = vec![z, s0, s1];
                if b < r {
                    let h = (r * r - b * b).sqrt();
                    bps.extend([z - h, z + h]);
                }
                let bps: Vec<f64> = bps.into_iter().filter(|x| *x > 0.0).collect();
                let q = integrate(
                    f,
                    &Domain::semi_infinite(0.0).with_breakpoints(bps).with_decay(sigma),
                    &Options::rel(1e-12),
                )
                .unwrap();
                let got = k1 - k0;
                let bar = e1 + e0 + q.error + 1e-14 * q.value.abs();
                assert!(
                    (got - q.value).abs() <= bar,
                    "z {z} b {b} [{s0}, {s1}]: {got:e} vs {:e} (bar {bar:e})",
                    q.value
                );
                // The one-slice form, within its own bar, whatever the length.
                let (short, short_error) = short_k(&sigma, &c, &s0, &(s1 - s0), &lambda);
                let bar = short_error + q.error + 1e-14 * q.value.abs();
                assert!(
                    (short - q.value).abs() <= bar,
                    "z {z} b {b} [{s0}, {s1}], one slice: {short:e} vs {:e} (bar {bar:e})",
                    q.value
                );
                if s1 - s0 < 1e-6 {
                    assert!(short_error < e1 + e0, "z {z} b {b} [{s0}, {s1}]: the slice's bar is no better");
                }
                // The increments' form, within its own bar, which shrinks
                // with the interval where the difference's does not.
                let (local, local_error) = k_between(&sigma, &c, &s0, &s1, &lambda);
                let bar = local_error + q.error;
                assert!(
                    (local - q.value).abs() <= bar,
                    "z {z} b {b} [{s0}, {s1}], increments: {local:e} vs {:e} (bar {bar:e})",
                    q.value
                );
                // (Below ~10⁻⁸ the sums' rounding, not ℓ, sets it: the
                // slice serves there.)
                if (1e-7..1e-3).contains(&(s1 - s0)) {
                    assert!(
                        local_error < 1e-3 * (e1 + e0),
                        "z {z} b {b} [{s0}, {s1}]: {local_error:e} vs {:e}",
                        e1 + e0
                    );
                }
            }
        }
    }
}

#[cfg(test)]
mod near_the_light {
    use super::*;
    use crate::model::field::Field;
    use crate::model::finite::virtual_lights::Offset;
    use crate::model::finite::FiniteLight;
    use mcrt_scene::{DVec3, Light, Scene};

    /// The azimuthal integral of the cross-segment weight at the virtual
    /// light's nodes next to the light (m down to 10⁻³⁰, where the chord's
    /// reached spheres span ~m): the light 0.1 from the camera line of
    /// `docs/model.md` §9.7 (inside the spheres' cylinder, R = 0.2), at the
    /// outer angle where the order-1 runs ran out of budget. Before the
    /// one-slice form ([`short_k`]) C₂₃ exhausted 2·10⁶ evaluations at
    /// m = 2.7·10⁻²⁴ at 10⁻⁴ (the difference of two cumulants bore their
    /// whole bars); before the φ-grading about the density's peak, at
    /// m = 10⁻³⁰.
    #[test]
    fn the_cross_weight_converges_next_to_the_light() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic-order1.toml");
        let mut s = Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        s.estimator.radius = 0.2;
        let Light::Point { flux, .. } = s.lights[0] else { panic!("the scene has a point light") };
        s.lights[0] = Light::Point { position: DVec3::new(0.1, 0.0, 1.0), flux };
        let field = Field::from_scene(&s, &1.0f64).unwrap();
        let ff = FiniteField::of_first_segments(&s, &field);
        let FiniteLight::Point(p) = &ff.lights[0] else { panic!("a point light") };
        // The weight of both pairs at the node (γ, m) from the light.
        let weights = |gamma: f64, m: f64| {
            let (dz, db) = (m * gamma.cos(), m * gamma.sin());
            let at = Offset { z: p.z + dz, b: p.b + db, m, dz, db };
            [CrossPair::C23, CrossPair::C24].map(|pair| {
                let e = p
                    .around_line(&ff, pair, &at, &Options::rel(1e-4))
                    .unwrap_or_else(|f| panic!("γ {gamma}, m {m:e}, {pair:?}: {}", f.reason));
                assert!(e.value > 0.0 && e.error <= 1e-4 * e.value, "m {m:e}, {pair:?}: {} ± {}", e.value, e.error);
                (pair, e)
            })
        };
        let mut scaled: Vec<(f64, f64, CrossPair, f64)> = Vec::new();
        for m in [1.0201501971762524e-30f64, 2.6892457956968588e-24, 1e-16, 1e-8] {
            for (pair, e) in weights(2.305856318423849, m) {
                scaled.push((m, e.value / m.sqrt(), pair, e.error / m.sqrt()));
            }
        }
        // The node of the fourth run, where the chord nearly ⊥ u meets the
        // window with τ ≈ r₁/2 ~ 10⁻¹⁷ (τ formed as (B − ρ) + ρ(1 − μ) had an
        // error ~ερ, and whether it reached was decided by rounding).
        weights(std::f64::consts::FRAC_PI_4, 1.3947335811447094e-34);
        // The light lies inside the spheres' cylinder: a chord of length
        // r₁ ≈ √(m² + bb_yφ²) reaches the spheres over ℓ ≈ r₁²/(m|cos γ|)
        // until ℓ fills the window, at φ* ∝ √m, so the weight is ∝ √m
        // (∫₀^{φ*} const dφ + ∫_{φ*} m/φ² dφ). A length formed from rounded
        // positions (10⁻¹³ for ℓ = 10⁻²⁷) broke this by orders of magnitude.
        for pair in [CrossPair::C23, CrossPair::C24] {
            let v: Vec<_> = scaled.iter().filter(|x| x.2 == pair && x.0 < 1e-10).collect();
            for w in v.windows(2) {
                let (a, b) = (w[0], w[1]);
                assert!(
                    (a.1 - b.1).abs() <= a.3 + b.3,
                    "{pair:?}: weight/√m {:e} at m {:e} vs {:e} at m {:e}",
                    a.1,
                    a.0,
                    b.1,
                    b.0
                );
            }
        }
    }

    /// The light 10⁻⁶ from the camera line (R = 0.2; a hard case of issue
    /// 20, `docs/model.md` §9.7, "At bars ≤ 10⁻⁶") at the node where C₂₃'s run at 10⁻⁵ failed: the samples'
    /// bars (the cumulants' whole bars in the difference, ℓ²K′/2 in the
    /// slice, 2·10⁻⁷ of the value for chords reaching the spheres over
    /// ℓ ≈ 10⁻⁶) filled the azimuthal integral's goal of 5·10⁻⁸, which 2000
    /// panels could not meet. With the increments' bars
    /// ([`k_between`]) it converges at 10⁻⁹ and agrees with 10⁻⁴.
    #[test]
    fn the_cross_weight_converges_next_to_a_light_by_the_line() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic-order1.toml");
        let mut s = Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        s.estimator.radius = 0.2;
        let Light::Point { flux, .. } = s.lights[0] else { panic!("the scene has a point light") };
        s.lights[0] = Light::Point { position: DVec3::new(1e-6, 0.0, 1.0), flux };
        let field = Field::from_scene(&s, &1.0f64).unwrap();
        let ff = FiniteField::of_first_segments(&s, &field);
        let FiniteLight::Point(p) = &ff.lights[0] else { panic!("a point light") };
        let (gamma, m) = (7.074235761210583e-5f64, 9.999549640164e-7f64);
        let (dz, db) = (m * gamma.cos(), m * gamma.sin());
        let at = Offset { z: p.z + dz, b: p.b + db, m, dz, db };
        let weight = |rel: f64| {
            let o = Options { rule: crate::quad::Rule::Kronrod, ..Options::rel(rel) };
            p.around_line(&ff, CrossPair::C23, &at, &o).unwrap_or_else(|f| panic!("at {rel:e}: {}", f.reason))
        };
        let (coarse, fine) = (weight(1e-4), weight(1e-9));
        assert!(fine.error <= 1e-9 * fine.value, "{} ± {}", fine.value, fine.error);
        assert!(
            (coarse.value - fine.value).abs() <= coarse.error + fine.error,
            "{} ± {} at 1e-4 vs {} ± {} at 1e-9",
            coarse.value,
            coarse.error,
            fine.value,
            fine.error
        );
    }
}
