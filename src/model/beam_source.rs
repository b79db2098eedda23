//! A beam's first interactions as a volume source of single-scattered
//! light (isotropic media), for both models (`docs/model.md` §3a, §9.8).
//!
//! A ray of a collimated disk beam (uniform over the disk of radius a,
//! along v_b) interacts first at depth t past the disk with density
//! σe^{−σt}; over the beam's rays the first interactions have the density
//! n(x₁) = σe^{−σt}/(πa²) inside the semi-infinite cylinder. Scattered
//! isotropically there, a path's second segment reaches a point x with a
//! chance that depends on d = |x₁ − x| only (the kernel k: e^{−σd}/d² for
//! the small-sphere field, the hit chance H(d) of a sphere of radius R for
//! the finite-sphere model). In spherical coordinates about x, polar axis
//! v_b (c = cos of the polar angle), with x at depth τ past the disk and
//! distance p from the beam's axis, the point x₁ lies at depth τ + dc and
//! on the circle of radius d√(1 − c²) about x's foot in the disk's plane,
//! of which the angle Θ lies inside the disk ([`arc_in_disc_gaps`]), so
//!
//!   ∫ n(x₁) k(|x₁ − x|) d³x₁ = (1/πa²) ∫₀^∞ d² k(d) ∫_{τ + dc ≥ 0} Θ(d√(1 − c²)) σe^{−σ(τ + dc)} dc dd.
//!
//! d²k(d) is bounded (e^{−σd} for the small-sphere kernel: the 1/d² of a
//! point inside the beam is gone), H has a √-kink at d = R. For fixed d
//! the c-integrand has √-kinks where the circle touches the disk's rim
//! from inside or outside, d²(1 − c²) = (a ∓ p)², and ends at the disk's
//! plane, c = −τ/d; the d-integrand has kinks where these appear, at
//! d = |a − p|, a + p, |τ| and √(τ² + (a ∓ p)²), all declared. The shell
//! is integrated in the polar angle θ (c = cos θ) over the circle's
//! support only: for a beam much thinner than d the support is a band
//! ~a/d wide at θ ≈ p/d, which c = cos θ would squeeze against ±1
//! (`BeamPoint::shell`).

use crate::quad::{integrate_nested, integrate_within_pass, CheckRule, Domain, Estimate, Options, Outcome};
use crate::real::Real;
use crate::special::arc_in_disc_gaps;
use mcrt_scene::DVec3;

pub use super::beam_fluence::ScatteredBeam;

/// The camera ray in a beam's frame (`docs/model.md` §9.3): e_n ∥ u × v_b,
/// e_m = v_b × e_n; the camera origin at (ξ₀, η₀) across the beam and
/// depth₀ past its disk, the ray at cos ϑ = μ = u·v_b, sin ϑ = |u × v_b|
/// (for a ray along the beam, ξ₀ is the origin's distance from the axis).
pub(crate) struct BeamFrame {
    pub mu: f64,
    pub sin: f64,
    pub xi0: f64,
    pub eta0: f64,
    pub depth0: f64,
}

impl BeamFrame {
    /// The frame of the beam (disk `center`, `direction`) for the camera
    /// ray o + s u.
    pub(crate) fn new(o: DVec3, u: DVec3, center: DVec3, direction: DVec3) -> BeamFrame {
        let rel = o - center;
        let n = u.cross(direction);
        let sin = n.length();
        let (xi0, eta0) = if sin > 0.0 {
            let e_n = n / sin;
            let e_m = direction.cross(e_n);
            (rel.dot(e_m), rel.dot(e_n))
        } else {
            ((rel - direction * rel.dot(direction)).length(), 0.0)
        };
        BeamFrame { mu: u.dot(direction), sin, xi0, eta0, depth0: rel.dot(direction) }
    }
}

/// A lower bound of t₁ + |x₁ − o| over the points x₁ of a beam's volume
/// (depth t₁ ≥ 0 past its disk, within `radius` of its axis): the path
/// light → first interaction → any camera-ray point → camera of its
/// single-scattered light, by the triangle inequality. It is the larger of
/// the camera's distance from that volume and its depth t_o when t_o ≥ 0
/// (t₁ + |t₁ − t_o| ≥ t_o).
pub(crate) fn beam_scattered_path(o: DVec3, center: DVec3, direction: DVec3, radius: f64) -> f64 {
    let rel = o - center;
    let depth = rel.dot(direction);
    let across = ((rel - direction * depth).length() - radius).max(0.0);
    let distance = if depth >= 0.0 { across } else { across.hypot(depth) };
    distance.max(depth)
}

/// Where x sits against a beam: its depth τ past the disk and distance p
/// from the axis, with the disk radius a and σ.
#[derive(Debug, Clone)]
pub(crate) struct BeamPoint<T> {
    /// Disk radius a > 0.
    pub a: T,
    /// Distance p ≥ 0 of x from the beam's axis.
    pub p: T,
    /// Depth τ of x past the disk (any sign).
    pub tau: T,
    /// σ = σ_ext > 0.
    pub sigma: T,
}

/// A factor of a shell kernel that depends on the shell's radius d alone,
/// e^{ln}·rest with a relative bar ([`BeamPoint::integral_over_shells`]).
#[derive(Debug, Clone)]
pub(crate) struct ShellFactor<T> {
    /// Its exponent (kept apart so that the kernel can fold it into its own).
    pub ln: T,
    /// The rest.
    pub rest: T,
    /// Its relative bar.
    pub rel: T,
}

impl<T: Real> ShellFactor<T> {
    /// The factor 1 (no bar).
    pub fn one(like: &T) -> Self {
        ShellFactor { ln: like.lit(0.0), rest: like.lit(1.0), rel: like.lit(0.0) }
    }
}

/// A shell kernel (t, d, the shell's factor) ↦ σe^{−σt}·d²k(d)
/// ([`BeamPoint::integral_over_shells`]).
pub(crate) type ShellKernel<'a, T> = dyn Fn(&T, &T, &ShellFactor<T>) -> T + Sync + 'a;

/// The shell factor of a radius d, computed with the options it is handed.
pub(crate) type ShellFactorFn<'a, T> =
    dyn Fn(&T, &Options) -> Result<ShellFactor<T>, crate::quad::Failure<T>> + Sync + 'a;

/// How [`BeamPoint::integral_over_shells`] runs over the shells' radii.
pub(crate) struct Shells<'a, T> {
    /// R where the kernel has a √-kink at d = R.
    pub knee: Option<&'a T>,
    /// The rate the integrand decays at in d (the quadrature's hint).
    pub decay: T,
    /// The kernel's factor of d alone, if any.
    pub factor: Option<&'a ShellFactorFn<'a, T>>,
    /// The largest radius integrated (the caller bounds the rest).
    pub cut: Option<T>,
}

impl<T: CheckRule> BeamPoint<T> {
    /// ∫ n(x₁) k(|x₁ − x|) d³x₁ (module docs). `kernel(t, d)` gives
    /// σe^{−σt}·d²k(d) at depth t (with whatever shift the caller carries,
    /// in one exponent): the kernel times the shell's d², which the caller
    /// forms without a 1/d² (the small-sphere d²k = e^{−σd}); `knee` is R
    /// where the kernel has a √-kink at d = R (the finite-sphere H), `None`
    /// for the small-sphere e^{−σd}/d².
    /// Computed as one level inside a pass of a nested integral (`within`:
    /// the pass's rule, checked by the other pass) or on its own
    /// (cross-checked). Domain: a > 0, σ > 0, any τ, p ≥ 0.
    pub fn integral(
        &self,
        kernel: &(dyn Fn(&T, &T) -> T + Sync),
        knee: Option<&T>,
        opts: &Options,
        within: bool,
    ) -> Outcome<T> {
        let plain = |t: &T, d: &T, _: &ShellFactor<T>| kernel(t, d);
        let shells = Shells { knee, decay: self.sigma.clone(), factor: None, cut: None };
        self.integral_over_shells(&plain, &shells, opts, within)
    }

    /// The distance from x to the nearest point of the beam's volume (0
    /// inside it).
    pub fn nearest(&self) -> T {
        let zero = self.a.lit(0.0);
        let across = (self.p.clone() - self.a.clone()).max_of(zero.clone());
        let before = (-self.tau.clone()).max_of(zero);
        (across.clone() * across + before.clone() * before).sqrt()
    }

    /// The distance from x to the farthest point of the beam's disk,
    /// √(τ² + (p + a)²): every point of the volume within depth t of the
    /// disk lies within this + t of x.
    pub fn farthest_on_disk(&self) -> T {
        let across = self.p.clone() + self.a.clone();
        (self.tau.clone() * self.tau.clone() + across.clone() * across).sqrt()
    }

    /// [`BeamPoint::integral`] with a factor of the kernel that depends on
    /// d alone, computed once per shell with its relative bar
    /// (`shells.factor`: a radial function the caller reads from tables or
    /// integrates, such as the hits of a fresh path of every order), handed
    /// to `kernel(t, d, factor)`; each shell's value bears the factor's
    /// relative bar. The shells run out to `shells.cut` when given (the
    /// caller bounds the rest) and decay at `shells.decay` beyond the
    /// volume's kinks (the quadrature's hint: νσ for a kernel of every
    /// order, which falls off more slowly than σ).
    pub fn integral_over_shells(
        &self,
        kernel: &ShellKernel<'_, T>,
        shells: &Shells<'_, T>,
        opts: &Options,
        within: bool,
    ) -> Outcome<T> {
        let knee = shells.knee;
        let zero = self.a.lit(0.0);
        let (near, far) = ((self.a.clone() - self.p.clone()).abs(), self.a.clone() + self.p.clone());
        let lo = self.nearest();
        let tau2 = self.tau.clone() * self.tau.clone();
        let mut cuts = vec![
            near.clone(),
            far.clone(),
            self.tau.clone().abs(),
            (tau2.clone() + near.clone() * near).sqrt(),
            (tau2 + far.clone() * far).sqrt(),
        ];
        if let Some(r) = knee {
            cuts.push(r.clone());
        }
        // Well outside the cylinder (p ≥ 2a, so d ≥ p/2) the shells run in
        // v = d − p: a thin beam fills the shells with |d − p| ≲ a, where it
        // is grazed (the shell's content peaks as 1/√(d − p) smoothed over
        // a, a fraction ~√(a/p) of the whole), and absolute nodes d would
        // carry ulp(p), a relative εp/a of that band: ε√(p/a) in the
        // fluence (2·10⁻¹² at a = 10⁻⁸, p = 0.7). The kinks d = p ∓ a are
        // then v = ∓a exactly.
        let offset = self.p >= self.a.lit(2.0) * self.a.clone();
        let (lo, cuts) = if offset {
            let shifted = cuts[2..].iter().map(|c| c.clone() - self.p.clone());
            let cuts: Vec<T> = [-self.a.clone(), self.a.clone()].into_iter().chain(shifted).collect();
            (lo - self.p.clone(), cuts)
        } else {
            (lo, cuts)
        };
        let cuts: Vec<T> = cuts.into_iter().filter(|c| *c > lo).collect();
        let domain = match &shells.cut {
            None => Domain::semi_infinite(lo).with_breakpoints(cuts),
            Some(cut) => {
                let end = if offset { cut.clone() - self.p.clone() } else { cut.clone() };
                if !(end > lo) {
                    return Ok(Estimate::known(zero.clone(), zero, 0, opts.rule));
                }
                let inner: Vec<T> = cuts.into_iter().filter(|c| *c < end).collect();
                Domain::finite(lo, end).with_breakpoints(inner)
            }
        }
        .with_decay(shells.decay.clone());
        let area = zero.pi() * self.a.clone() * self.a.clone();
        // The shells' values are 1/(πa²) times what `shell` integrates, so
        // their absolute goal is πa² times the one asked of their sum's
        // samples (without it a beam of radius 10⁻³ got bars 3·10⁵ times
        // its goal's, and none thinner converged).
        let area_f64 = area.to_f64();
        let f = |v: &T, o: &Options| {
            let o = &Options { abs_tol: o.abs_tol * area_f64, ..o.clone() };
            let (d, d_less_p) =
                if offset { (self.p.clone() + v.clone(), v.clone()) } else { (v.clone(), v.clone() - self.p.clone()) };
            let factor = match shells.factor {
                Some(weigh) => weigh(&d, o)?,
                None => ShellFactor::one(&d),
            };
            let k = |t: &T, d: &T| kernel(t, d, &factor);
            let e = self.shell(&d, &d_less_p, &k, o)?.scaled(&(v.lit(1.0) / area.clone()));
            let error = e.error.clone() + e.value.abs() * factor.rel.clone();
            Ok(Estimate { error, ..e })
        };
        if !within {
            return integrate_nested(f, &domain, opts);
        }
        if opts.abs_tol > 0.0 {
            return integrate_within_pass(f, &domain, opts);
        }
        // A purely relative goal (a table's sample): the shells get an
        // absolute goal from the integral's scale, found at 10⁻³ first (as
        // `integrate_nested` does for goals of 10⁻⁴ and tighter): shells that meet the beam in a sliver,
        // next to a corner of its volume, are at their rounding's level and
        // cannot meet a relative goal of their own (without it, a beam behind
        // a light at the camera bisected such a shell into 2000 panels).
        let coarse = Options { rel_tol: opts.rel_tol.max(1e-3), ..opts.clone() };
        let scale = integrate_within_pass(f, &domain, &coarse)?;
        let fine = Options { abs_tol: scale.value.abs().to_f64() * opts.rel_tol / 10.0, ..opts.clone() };
        match integrate_within_pass(f, &domain, &fine) {
            Ok(e) => Ok(Estimate { evaluations: e.evaluations + scale.evaluations, ..e }),
            Err(mut fail) => {
                fail.evaluations += scale.evaluations;
                Err(fail)
            }
        }
    }

    /// The circle's kinks against the disk on the shell of radius d:
    /// m = |a − p| (near) and a + p (far), with d − m formed from d − p
    /// (exact by Sterbenz where d ≈ p, as on a thin beam's band, where
    /// a ± p rounds to ulp(p), a relative ~εp/a of the band).
    fn kinks(&self, d: &T, d_less_p: &T) -> [Kink<T>; 2] {
        let (a, p) = (&self.a, &self.p);
        let near = if p >= a {
            Kink::new(d, p.clone() - a.clone(), d_less_p.clone() + a.clone())
        } else {
            Kink::new(d, a.clone() - p.clone(), d.clone() - (a.clone() - p.clone()))
        };
        [near, Kink::new(d, a.clone() + p.clone(), d_less_p.clone() - a.clone())]
    }

    /// ∫ Θ(d√(1 − c²)) kernel(τ + dc, d) dc over the sphere of radius d
    /// about x, where its points lie past the disk (τ + dc ≥ 0).
    ///
    /// Taken per hemisphere in the angle ψ ∈ [0, π/2] from the axis (c =
    /// ±cos ψ, |dc| = sin ψ dψ, the circle's radius ρ = d sin ψ): the circle
    /// meets the disk for ρ ∈ [(p − a)⁺, a + p] (fully inside it below
    /// a − p), so the support is ψ ∈ [ψ_near, ψ_far] with ψ_m = asin(m/d)
    /// for m = |a − p|, a + p < d (from 0 inside the cylinder, to π/2 where
    /// m ≥ d), √-kinks at its ends and at ψ_near inside the cylinder; the
    /// disk's plane clips the hemisphere towards it at ψ = acos(|τ|/d)
    /// (τ > 0), or removes the one towards the disk and clips the other
    /// (τ < 0). Both hemispheres are formed from ψ itself, never as π − θ,
    /// whose rounding (half an ulp of π) against a band ~2a/d wide was a
    /// relative 10⁻⁹ at a = 10⁻⁶ (a reviewer's float64 port against mpmath);
    /// each piece runs in the offset δ = ψ − ψ_lo from its start, and the
    /// distances ρ − m of a node from the kinks are formed from δ as
    /// 2d cos((ψ + ψ_m)/2) sin((ψ − ψ_m)/2), exact next to the kink, and
    /// as (m − d) + 2d sin²((π/2 − ψ)/2) where m ≥ d (the circle's largest
    /// ρ at ψ = π/2, an end of every piece): ψ − ψ_near and ψ_end − ψ from
    /// δ and the band's width ([`band_width`]), π/2 − ψ from ψ_end's own
    /// complement, the half-angle cosines as sines of those, d − m from
    /// `d_less_p` = d − p, which the caller forms exactly where it matters
    /// ([`BeamPoint::integral`]), and the plane's angle as
    /// 2 asin(√((d − |τ|)/2d)). Nodes in absolute ψ carried ulp(ψ), a
    /// relative ~εp/a of a thin beam's band (2.8·10⁻¹⁰ high at a = 10⁻⁶
    /// against an mpmath line source), and the other forms missed single
    /// shells by 10⁻¹³–7·10⁻⁸ (module tests). Measured against the c-form it
    /// replaced: the same values where that converged, 2.5× fewer
    /// evaluations (the parts off the support are skipped); a thin beam's
    /// band sits within ~a·p/d² of c = ±1, where c's own rounding limited
    /// the c-form to a relative ~2·10⁻⁹ at a = 10⁻⁶.
    fn shell(&self, d: &T, d_less_p: &T, kernel: &(dyn Fn(&T, &T) -> T + Sync), o: &Options) -> Outcome<T> {
        let zero = d.lit(0.0);
        let one = d.lit(1.0);
        if d.is_zero() {
            // The shell shrinks to x itself: all of it past the disk or none.
            // c ∈ [−1, 1] when τ > 0, [0, 1] when τ = 0, nothing when τ < 0.
            let span = if self.tau > zero {
                d.lit(2.0)
            } else if self.tau.is_zero() {
                d.lit(1.0)
            } else {
                zero.clone()
            };
            let v = if span.is_zero() {
                span
            } else {
                span * crate::special::arc_in_disc(d, &self.a, &self.p) * kernel(&self.tau, d)
            };
            return Ok(Estimate::known(v, zero, 1, o.rule));
        }
        // An absolute goal just above the engine's floor of resolvable
        // values (f64: 1024 underflow floors, ~10⁻²⁸⁹, `quad::goal`): a shell
        // far from a beam behind a brighter light can be ~10⁻²⁸¹, where the
        // panels' floors alone reach its relative goal (they did, at
        // σ·distance 539 behind a light at the camera); 16 times that floor
        // is negligible against every value these integrals take where they
        // matter (a table's, carried times its light's own shift, ≥ 10⁻¹²⁰;
        // the finite model's fallback quadrature at the common c₀ meets a far
        // beam's value only beside a brighter light's).
        let o = &Options { abs_tol: o.abs_tol.max((d.underflow_floor() * d.lit(16.0 * 1024.0)).to_f64()), ..o.clone() };
        let half_pi = d.pi() / d.lit(2.0);
        let inside = self.p < self.a;
        let [near, far] = self.kinks(d, d_less_p);
        let (psi_near, psi_far) = (near.psi.clone(), far.psi.clone());
        // The support in ψ, the same in both hemispheres.
        let support_lo = match (&psi_near, inside) {
            (_, true) => zero.clone(),
            (Some(t), false) => t.clone(),
            // ρ ≤ d ≤ p − a: the circle never reaches the disk.
            (None, false) => return Ok(Estimate::known(zero.clone(), zero, 0, o.rule)),
        };
        let support_hi = psi_far.clone().unwrap_or_else(|| half_pi.clone());
        // ψ from where the plane clips (acos(|τ|/d), 0 when |τ| ≥ d).
        let clip = || {
            if self.tau.clone().abs() >= *d {
                zero.clone()
            } else {
                // acos(|τ|/d) = 2 asin(√((d − |τ|)/2d)), accurate where |τ| ≈ d.
                let half = ((d.clone() - self.tau.clone().abs()) / (d.lit(2.0) * d.clone())).sqrt();
                d.lit(2.0) * half.min_of(one.clone()).asin()
            }
        };
        // (sign of c, ψ-range): the hemisphere away from the disk (c ≥ 0)
        // is whole when τ ≥ 0 and, when τ < 0, past the plane for
        // ψ ≤ acos(|τ|/d) only; the one towards the disk (c < 0) is past it
        // for τ > 0 only, from ψ = acos(τ/d).
        let mut pieces: Vec<(T, T, T)> = Vec::new();
        let mut push = |sign: T, lo: T, hi: T| {
            if lo < hi {
                pieces.push((sign, lo, hi));
            }
        };
        if self.tau >= zero {
            push(one.clone(), support_lo.clone(), support_hi.clone());
        } else {
            // c = cos ψ ≥ |τ|/d: ψ ≤ acos(|τ|/d).
            if -self.tau.clone() < *d {
                push(one.clone(), support_lo.clone(), support_hi.clone().min_of(clip()));
            }
        }
        if self.tau > zero {
            push(-one.clone(), support_lo.clone().max_of(clip()), support_hi.clone());
        }
        if pieces.is_empty() {
            return Ok(Estimate::known(zero.clone(), zero, 0, o.rule));
        }
        // Each piece aims at half the relative goal and its share of half
        // the absolute one: the sum of their bars stays within the shell's
        // goal (the integrand is non-negative).
        let share = Options { abs_tol: o.abs_tol / (2.0 * pieces.len() as f64), rel_tol: o.rel_tol / 2.0, ..o.clone() };
        // The support's width, support_hi − support_lo, formed without ψ's
        // rounding where the support starts at ψ_near (outside the cylinder).
        let reach =
            if inside { support_hi.clone() - support_lo.clone() } else { band_width(d, &near, &far, &self.a, &self.p) };
        let two_d = d.lit(2.0) * d.clone();
        // π/2 − ψ_end for the support's end ψ_end: atan2(S_far, a + p) where
        // the circle reaches a + p, else 0.
        let c_end = if psi_far.is_some() { angle_of(far.s.clone(), far.m.clone()) } else { zero.clone() };
        let mut total = Estimate::known(zero.clone(), zero.clone(), 0, o.rule);
        for (sign, lo, hi) in pieces {
            // The piece in δ = ψ − lo ∈ [0, width]; its nodes' distances from
            // the kinks are formed from δ and the piece's own offsets
            // (ψ − ψ_near = off_near + δ, ψ_end − ψ = rem − δ with ψ_end =
            // ψ_far or π/2), not from ψ = lo + δ: a thin beam's band is
            // ~2a/d wide at ψ ≈ p/d, where ψ's rounding is a relative
            // ~εp/a of the band (at a = 10⁻⁶ the fluence came out 2.8·10⁻¹⁰
            // high against a bar of 10⁻¹³, `thin_beams_fluence_is_the_line_source`).
            let starts_the_support = lo == support_lo;
            let rem = if starts_the_support { reach.clone() } else { support_hi.clone() - lo.clone() };
            let width = if hi == support_hi { rem.clone() } else { hi.clone() - lo.clone() };
            // 0 exactly where the piece starts at ψ_near.
            let off_near = psi_near.as_ref().map(|t| lo.clone() - t.clone());
            let f = |delta: &T, o2: &Options| {
                // e = π/2 − ψ = (π/2 − ψ_end) + (ψ_end − ψ): a thin beam's
                // band lies next to π/2 on the shells that do not reach a + p
                // (~√(a/p) wide there), where ψ's own rounding, ulp(π/2), is
                // a relative ~ε√(p/a) of cos ψ and of the half-angle cosines.
                let left = rem.clone() - delta.clone();
                let e = c_end.clone() + left.clone();
                // sin ψ and cos ψ from the smaller of ψ and e (either's
                // rounding is a relative ε/ψ of the sine of the other).
                let psi = lo.clone() + delta.clone();
                let (sin, cos) =
                    if psi <= e { (psi.clone().sin(), psi.cos()) } else { (e.clone().cos(), e.clone().sin()) };
                let rho = d.clone() * sin.clone();
                // ρ − m_near = 2d cos((ψ + ψ_near)/2) sin((ψ − ψ_near)/2) and
                // m_far − ρ = 2d cos((ψ + ψ_far)/2) sin((ψ_far − ψ)/2), the
                // cosines as sin(e + (ψ − ψ_near)/2) and sin(c_end + (ψ_far − ψ)/2).
                let half = |x: T| x / d.lit(2.0);
                let to_near = match &off_near {
                    Some(off) => {
                        let since = off.clone() + delta.clone();
                        two_d.clone() * (e.clone() + half(since.clone())).sin() * half(since).sin()
                    }
                    // Inside the cylinder with the whole circle in the disk
                    // (a − p ≥ d): ρ − (a − p) < 0.
                    None => {
                        let h = half(e.clone()).sin();
                        near.d_less_m.clone() - two_d.clone() * h.clone() * h
                    }
                };
                let to_far = match &psi_far {
                    Some(_) => two_d.clone() * (c_end.clone() + half(left.clone())).sin() * half(left).sin(),
                    None => {
                        let h = half(left).sin();
                        two_d.clone() * h.clone() * h - far.d_less_m.clone()
                    }
                };
                let angle = arc_in_disc_gaps(&rho, &self.a, &self.p, &to_near, &to_far);
                let v = if angle.is_zero() {
                    angle
                } else {
                    angle * kernel(&(self.tau.clone() + sign.clone() * d.clone() * cos), d) * sin
                };
                Ok(Estimate::known(v, delta.lit(0.0), 1, o2.rule))
            };
            let cuts: Vec<T> = [&psi_near]
                .into_iter()
                .flatten()
                .filter(|t| inside && **t > lo && **t < hi)
                .map(|t| t.clone() - lo.clone())
                .collect();
            let domain = Domain::finite(zero.clone(), width).with_breakpoints(cuts);
            total = total.plus(integrate_within_pass(f, &domain, &share)?);
        }
        Ok(total)
    }
}

/// A kink of a shell's circle against the disk: the circle of radius
/// ρ = d sin ψ touches the disk's rim from inside or outside at ρ = m.
struct Kink<T> {
    /// m = |a − p| or a + p.
    m: T,
    /// d − m, formed by the caller from d − p.
    d_less_m: T,
    /// S_m = √((d − m)(d + m)) (0 where m ≥ d).
    s: T,
    /// ψ_m = asin(m/d) = atan2(m, S_m) where m < d.
    psi: Option<T>,
}

impl<T: Real> Kink<T> {
    fn new(d: &T, m: T, d_less_m: T) -> Kink<T> {
        let zero = d.lit(0.0);
        let s = (d_less_m.clone() * (d.clone() + m.clone())).max_of(zero.clone()).sqrt();
        let psi = (d_less_m > zero).then(|| angle_of(m.clone(), s.clone()));
        Kink { m, d_less_m, s, psi }
    }
}

/// atan2(v, u) for u, v ≥ 0, not both 0, through the smaller ratio.
fn angle_of<T: Real>(v: T, u: T) -> T {
    if v <= u {
        (v / u).atan()
    } else {
        u.pi() / u.lit(2.0) - (u / v).atan()
    }
}

/// The width of a shell's support in ψ for x outside the cylinder (p > a):
/// ψ_far − ψ_near, or π/2 − ψ_near where the circle's largest radius d
/// does not reach a + p. With X = a + p, Y = p − a (the kinks' m) and
/// their S: sin Δ = 4ap/(X S_Y + Y S_X), cos Δ = (S_X S_Y + XY)/d², and
/// π/2 − ψ_near = atan2(S_Y, Y): no difference of two rounded angles,
/// whose rounding (ulp(ψ) ~ εp/d) is a relative ~εp/a of a thin beam's
/// band.
fn band_width<T: Real>(d: &T, near: &Kink<T>, far: &Kink<T>, a: &T, p: &T) -> T {
    let (x, y) = (&far.m, &near.m);
    if far.psi.is_none() {
        return angle_of(near.s.clone(), y.clone());
    }
    // X² − Y² = 4ap.
    let sin = d.lit(4.0) * a.clone() * p.clone() * d.clone() * d.clone();
    let cos = (x.clone() * near.s.clone() + y.clone() * far.s.clone())
        * (far.s.clone() * near.s.clone() + x.clone() * y.clone());
    angle_of(sin, cos)
}

#[cfg(test)]
#[path = "beam_source_tests.rs"]
mod tests;
