//! Where the segments of every scattering order start (isotropic media,
//! point lights; `docs/model.md` §10.1): the radial densities a^j c_j of a
//! point light's j-th interaction points, summed over a range of orders, in
//! closed form up to one non-oscillatory quadrature.
//!
//! In an isotropic medium the rest of a path after a scattering is a fresh
//! isotropic point source, so the j-th interaction points have the density
//! a^j c_j (a the albedo), c_j the j-fold convolution of
//! c₁(r) = σe^{−σr}/(4πr²), whose radial Fourier transform is
//! ĉ₁(k) = arctan(k/σ)/(k/σ). A range of orders first..=last has the
//! transform F(z) = Σ_{j=first}^{last} z^j at z = aĉ₁, and every order from
//! `first` on has F(z) = z^first/(1 − z): resummed, with nothing truncated.
//!
//! Back in space (σ = 1; a density at σ is σ³ times the one at σr), with
//! k f̂(k) odd, r f(r) = (1/(4π²i))∫_ℝ k e^{ikr} f̂(k) dk, and the contour
//! closed in the upper half-plane. F(aĉ₁) is analytic there except for
//! ĉ₁'s branch cut k = iu, u ≥ 1 (arctan's branch point at i), and, for
//! the resummed F, the zero of 1 − aĉ₁ at k = iν, 0 < ν < 1,
//! a·artanh(ν) = ν (the diffusion mode). On the cut
//! ĉ₁(iu ± 0) = (artanh(1/u) ∓ iπ/2)/u, and the two sides' difference gives,
//! with z₊ = aĉ₁(iu − 0),
//!
//!   r C(r) = (1/(2π²))∫₁^∞ u e^{−ur} Im F(z₊(u)) du + ν²e^{−νr}/(2π(a/(1 − ν²) − 1)),
//!
//! z₊ = a(artanh(1/u) + iπ/2)/u, the pole term only for the resummed F
//! (its residue does not depend on `first`: z = 1 there). For F(z) = az the
//! integral is e^{−r}/(4πr)·a, c₁ itself: `tests` check that, and every
//! other order against an independent inverse transform (mpmath's
//! oscillatory quadrature of the sine transform, 20 digits). The tail
//! T(t) = ∫_t^∞ r C(r) dr, which the bipolar integrals of `multiple` read,
//! is the same with u e^{−ur} → e^{−ut} and ν²e^{−νr} → νe^{−νt}.
//!
//! **Conditioning.** Im F on the cut oscillates in sign with a magnitude
//! that grows like (a·artanh(1/u))^last towards u = 1, while the integral
//! is of the order a^last: for finite ranges the cancellation grows like
//! (last/2)^last e^{−last}, 10⁴ at last = 12. Finite ranges are therefore
//! limited to [`MAX_FINITE_ORDER`]; beyond, the resummed form (every order)
//! has no such growth (Im z^first/(1 − z) → −Im z^{first−1} as |z| → ∞,
//! bounded by its logarithm).

use crate::model::OracleError;
use crate::quad::{integrate, CheckRule, Domain, Options, Outcome};
use crate::real::Real;

/// The highest last order of a finite range (module docs, **Conditioning**).
pub const MAX_FINITE_ORDER: u32 = 10;

/// The orders first..=last (`last` `None`: every order from `first` on) of
/// a point light's interaction points in an isotropic medium of albedo a.
#[derive(Debug, Clone)]
pub struct StartDensity<T> {
    albedo: T,
    first: u32,
    last: Option<u32>,
    /// ν and the pole's weight 1/(2π(a/(1 − ν²) − 1)), for every order.
    pole: Option<(T, T)>,
}

/// A complex number at the working precision (only what Im F needs).
#[derive(Debug, Clone)]
struct Complex<T> {
    re: T,
    im: T,
}

impl<T: Real> Complex<T> {
    fn mul(&self, o: &Complex<T>) -> Complex<T> {
        Complex {
            re: self.re.clone() * o.re.clone() - self.im.clone() * o.im.clone(),
            im: self.re.clone() * o.im.clone() + self.im.clone() * o.re.clone(),
        }
    }

    fn powi(&self, n: u32) -> Complex<T> {
        let mut out = Complex { re: self.re.lit(1.0), im: self.re.lit(0.0) };
        for _ in 0..n {
            out = out.mul(self);
        }
        out
    }
}

impl<T: Real> StartDensity<T> {
    /// The orders first..=last (`last` `None`: all from `first` on) at
    /// albedo a. Domain: 1 ≤ first, first ≤ last ≤ [`MAX_FINITE_ORDER`];
    /// 0 ≤ a ≤ 1, and a < 1 for every order (an infinite non-absorbing
    /// medium holds infinite light).
    pub fn new(albedo: &T, first: u32, last: Option<u32>) -> Result<StartDensity<T>, OracleError> {
        let bad = |what: String| Err(OracleError::Unsupported(what));
        if !(albedo.to_f64() >= 0.0 && albedo.to_f64() <= 1.0) {
            return bad(format!("medium albedo = {}: allowed 0 ≤ albedo ≤ 1", albedo.to_f64()));
        }
        if first == 0 {
            return bad("the first order of a start density is 1 or more (order 0 starts at the light)".into());
        }
        let pole = match last {
            Some(last) if last < first || last > MAX_FINITE_ORDER => {
                return bad(format!(
                    "interaction orders {first}..={last}: allowed {first} ≤ last ≤ {MAX_FINITE_ORDER} (beyond, the \
                     cut integral of a finite order loses more than four digits to cancellation; docs/model.md §10.1)"
                ));
            }
            Some(_) => None,
            None if albedo.to_f64() >= 1.0 => {
                return bad("effects.scattering_orders = \"all\" with medium albedo = 1: an infinite medium without \
                     absorption holds infinite light; allowed: albedo < 1, or a finite order"
                    .into());
            }
            None if albedo.is_zero() => None,
            None => Some(diffusion_pole(albedo)),
        };
        Ok(StartDensity { albedo: albedo.clone(), first, last, pole })
    }

    /// The last order of a finite range, `None` for every order.
    pub fn last_order(&self) -> Option<u32> {
        self.last
    }

    /// ∫C d³x = Σ_{j=first}^{last} a^j (a^first/(1 − a) for every order):
    /// the expected number of interactions of these orders per path.
    pub fn mass(&self) -> T {
        let a = &self.albedo;
        let head = a.clone().powi_like(self.first as i32);
        match self.last {
            Some(last) => {
                let mut sum = a.lit(0.0);
                let mut term = head;
                for _ in self.first..=last {
                    sum = sum + term.clone();
                    term = term * a.clone();
                }
                sum
            }
            None => head / (a.lit(1.0) - a.clone()),
        }
    }

    /// ν of the diffusion mode e^{−νσr} (every order, a > 0), else `None`.
    pub fn decay_of_pole(&self) -> Option<T> {
        self.pole.as_ref().map(|(nu, _)| nu.clone())
    }

    /// The slowest decay rate of r C(r), in units of σ: ν with every order,
    /// else 1.
    pub fn decay(&self) -> T {
        self.decay_of_pole().unwrap_or_else(|| self.albedo.lit(1.0))
    }

    /// Im F(z₊(u)) at u = 1 + x (x > 0), without cancellation in
    /// artanh(1/u) = ½ ln(1 + 2/x).
    fn cut_weight(&self, x: &T) -> T {
        let one = x.lit(1.0);
        let u = one.clone() + x.clone();
        let artanh = (x.lit(2.0) / x.clone()).ln_1p() * x.lit(0.5);
        let z = Complex {
            re: self.albedo.clone() * artanh / u.clone(),
            im: self.albedo.clone() * x.pi() / (u * x.lit(2.0)),
        };
        let head = z.powi(self.first);
        let f = match self.last {
            Some(last) => {
                // Σ_{k=0}^{last−first} z^k by Horner, times z^first.
                let mut acc = Complex { re: one.clone(), im: x.lit(0.0) };
                for _ in self.first..last {
                    acc = acc.mul(&z);
                    acc.re = acc.re.clone() + one.clone();
                }
                head.mul(&acc)
            }
            None => {
                // z^first/(1 − z).
                let den = Complex { re: one - z.re.clone(), im: -z.im.clone() };
                let norm = den.re.clone() * den.re.clone() + den.im.clone() * den.im.clone();
                let conj = Complex { re: den.re.clone(), im: -den.im };
                let num = head.mul(&conj);
                Complex { re: num.re / norm.clone(), im: num.im / norm }
            }
        };
        f.im
    }
}

impl<T: CheckRule> StartDensity<T> {
    /// r C(r) at σ = 1 (module docs), r ≥ 0 (r = 0 only for first ≥ 2,
    /// where it is finite).
    pub fn radial(&self, r: &T, opts: &Options) -> Outcome<T> {
        let cut = self.over_cut(r, true, opts)?;
        let pole = match &self.pole {
            Some((nu, w)) => nu.clone() * nu.clone() * (-(nu.clone() * r.clone())).exp() * w.clone(),
            None => r.lit(0.0),
        };
        Ok(cut.plus(crate::quad::Estimate::known(pole, r.lit(0.0), 0, opts.rule)))
    }

    /// T(t) = ∫_t^∞ r C(r) dr at σ = 1 (module docs), t ≥ 0 (t = 0 only
    /// for first ≥ 2).
    pub fn tail(&self, t: &T, opts: &Options) -> Outcome<T> {
        let cut = self.over_cut(t, false, opts)?;
        let pole = match &self.pole {
            Some((nu, w)) => nu.clone() * (-(nu.clone() * t.clone())).exp() * w.clone(),
            None => t.lit(0.0),
        };
        Ok(cut.plus(crate::quad::Estimate::known(pole, t.lit(0.0), 0, opts.rule)))
    }

    /// ln T(t) and its relative bar (as the estimate's error), for t so
    /// large that T itself underflows: the decay e^{−t} (or e^{−νt}) is
    /// kept in the exponent.
    pub fn ln_tail(&self, t: &T, opts: &Options) -> Outcome<T> {
        let unit = t.lit(1.0);
        let cut = self.over_cut_unscaled(t, false, &Options { abs_tol: 0.0, ..opts.clone() })?;
        let scale = unit.clone() / (t.pi() * t.pi() * t.lit(2.0));
        let (ln, rel) = match &self.pole {
            Some((nu, w)) => {
                // T = e^{−νt}(νw + J e^{−(1−ν)t}/(2π²)).
                let damp = (-(unit.clone() - nu.clone()) * t.clone()).exp() * scale;
                let sum = nu.clone() * w.clone() + cut.value.clone() * damp.clone();
                ((sum.clone()).ln() - nu.clone() * t.clone(), cut.error.clone() * damp / sum)
            }
            None => (cut.value.clone().ln() + scale.ln() - t.clone(), cut.error.clone() / cut.value.clone().abs()),
        };
        Ok(crate::quad::Estimate { value: ln, error: rel, ..cut })
    }

    /// (1/(2π²))∫₁^∞ u^{radial} e^{−ut} Im F(z₊(u)) du, in x = u − 1.
    fn over_cut(&self, t: &T, radial: bool, opts: &Options) -> Outcome<T> {
        let scale = (-t.clone()).exp() / (t.pi() * t.pi() * t.lit(2.0));
        let goal = Options { abs_tol: (opts.abs_tol / scale.to_f64()).min(f64::MAX), ..opts.clone() };
        Ok(self.over_cut_unscaled(t, radial, &goal)?.scaled(&scale))
    }

    /// ∫₀^∞ (1 + x)^{radial} e^{−xt} Im F(z₊(1 + x)) dx.
    fn over_cut_unscaled(&self, t: &T, radial: bool, opts: &Options) -> Outcome<T> {
        let f = |x: &T| {
            if x.is_zero() {
                return x.lit(0.0);
            }
            let w = self.cut_weight(x) * (-(x.clone() * t.clone())).exp();
            if radial {
                w * (x.lit(1.0) + x.clone())
            } else {
                w
            }
        };
        let decades = (1..=15).map(|k| t.lit(10f64.powi(-k)));
        let mut domain = Domain::semi_infinite(t.lit(0.0)).with_breakpoints(decades.chain([t.lit(1.0)]));
        if t.to_f64() >= 1.0 {
            domain = domain.with_decay(t.clone());
        }
        integrate(f, &domain, opts)
    }
}

/// ν with a·artanh(ν) = ν, 0 < ν < 1 (0 < a < 1), by bisection to the
/// working precision, and the pole's weight 1/(2π(a/(1 − ν²) − 1)).
/// Both without cancellation as a → 1 (ν² ≈ 3(1 − a)): the equation is
/// solved as g(ν) = (1 − a)/a, g(ν) = artanh(ν)/ν − 1 = Σ_{k≥1} ν^{2k}/(2k + 1)
/// (by its series below ν = ½), and a/(1 − ν²) − 1 = (ν² − a·g(ν))/(1 − ν²)
/// (a − 1 = −a·g(ν)), whose terms do not cancel (a·g ≈ ν²/3).
fn diffusion_pole<T: Real>(albedo: &T) -> (T, T) {
    let one = albedo.lit(1.0);
    let target = (one.clone() - albedo.clone()) / albedo.clone();
    let (mut lo, mut hi) = (albedo.lit(0.0), one.clone());
    // Until lo and hi are neighbours (ν ~ 10⁻⁶ needs ~20 halvings more
    // than the precision); the cap only guards the loop.
    for _ in 0..(albedo.prec() * 4 + 1100) {
        let mid = (lo.clone() + hi.clone()) * albedo.lit(0.5);
        if mid == lo || mid == hi {
            break;
        }
        if excess_of_artanh(&mid) > target {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let nu = (lo + hi) * albedo.lit(0.5);
    let nu2 = nu.clone() * nu.clone();
    let excess = (nu2.clone() - albedo.clone() * excess_of_artanh(&nu)) / (one - nu2);
    let weight = albedo.lit(1.0) / (albedo.pi() * albedo.lit(2.0) * excess);
    (nu, weight)
}

/// g(ν) = artanh(ν)/ν − 1 for 0 < ν < 1: its series Σ_{k≥1} ν^{2k}/(2k + 1)
/// below ν = ½ (terms fall by ν² ≤ ¼), else ½ ln((1 + ν)/(1 − ν))/ν − 1.
fn excess_of_artanh<T: Real>(nu: &T) -> T {
    let one = nu.lit(1.0);
    if nu.to_f64() >= 0.5 {
        let artanh = (nu.lit(2.0) * nu.clone() / (one.clone() - nu.clone())).ln_1p() * nu.lit(0.5);
        return artanh / nu.clone() - one;
    }
    let nu2 = nu.clone() * nu.clone();
    let mut power = nu2.clone();
    let mut sum = nu.lit(0.0);
    for k in 1..=(nu.prec() as usize) {
        let term = power.clone() / nu.lit((2 * k + 1) as f64);
        let next = sum.clone() + term;
        if next == sum {
            break;
        }
        sum = next;
        power = power * nu2.clone();
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::special::exp_int_e1_scaled;

    fn opts() -> Options {
        Options::rel(1e-12).declared()
    }

    /// ν as a → 1 against its expansion ν² = 3ε − (27/5)ε² + O(ε³),
    /// ε = (1 − a)/a, to 10⁻¹⁰ relative at 1 − a = 10⁻¹² (where solving
    /// a·artanh(ν) = ν directly loses half the digits), and the pole's
    /// weight against 1/(2π·(2/3)ν²·(1 + O(ν²))).
    #[test]
    fn the_diffusion_pole_keeps_its_digits_as_the_albedo_tends_to_one() {
        for gap in [1e-6, 1e-9, 1e-12] {
            let a = 1.0 - gap;
            let d = StartDensity::new(&a, 2, None).unwrap();
            let nu = d.decay_of_pole().unwrap();
            let eps = (1.0 - a) / a;
            let want = (3.0 * eps - 5.4 * eps * eps).sqrt();
            assert!((nu / want - 1.0).abs() < 1e-10, "1 − a = {gap:e}: ν {nu:e} vs {want:e}");
            let (_, w) = d.pole.unwrap();
            let approx = 1.0 / (2.0 * std::f64::consts::PI * (2.0 / 3.0) * nu * nu);
            assert!((w / approx - 1.0).abs() < 2.0 * nu * nu, "1 − a = {gap:e}: weight {w:e} vs {approx:e}");
        }
    }

    /// Order 1 alone is c₁: r c₁(r) = a e^{−r}/(4πr), T(t) = (a/4π)E₁(t).
    #[test]
    fn the_first_order_is_the_first_interaction_density() {
        let a = 0.8;
        let one = StartDensity::new(&a, 1, Some(1)).unwrap();
        for r in [0.01, 0.3, 1.0, 3.0, 20.0] {
            let got = one.radial(&r, &opts()).unwrap();
            let want = a * (-r).exp() / (4.0 * std::f64::consts::PI * r);
            assert!((got.value / want - 1.0).abs() <= 1e-11 + got.error / want, "r {r}: {} vs {want}", got.value);
            let tail = one.tail(&r, &opts()).unwrap();
            let want = a / (4.0 * std::f64::consts::PI) * (-r).exp() * exp_int_e1_scaled(&r);
            assert!((tail.value / want - 1.0).abs() <= 1e-11 + tail.error / want, "t {r}: {} vs {want}", tail.value);
        }
    }

    /// r C(r) of the order-2 density and of every order from 2 on, at
    /// a = 0.8, against mpmath's inverse sine transform of (aĉ₁)² and
    /// (aĉ₁)²/(1 − aĉ₁) (quadosc, 20 digits; an independent route: no
    /// contour, no cut): `scripts/cut-check.py`, which prints both routes.
    #[test]
    #[allow(clippy::excessive_precision)] // mpmath's 20 digits, as printed
    fn the_cut_and_the_pole_give_the_inverse_transform() {
        let a = 0.8;
        let two = StartDensity::new(&a, 2, Some(2)).unwrap();
        let all = StartDensity::new(&a, 2, None).unwrap();
        let nu = all.decay_of_pole().unwrap();
        assert!((nu - 0.71041178348787037148).abs() < 4e-16, "ν {nu}");
        let cases = [
            (0.3, 0.064028428457949441629, 0.10184783847912591632),
            (1.0, 0.022104465206658400284, 0.062510139187047714231),
            (3.0, 0.0018012059726638621086, 0.015320356179163207884),
        ];
        for (r, want2, want_all) in cases {
            for (d, want) in [(&two, want2), (&all, want_all)] {
                let got = d.radial(&r, &opts()).unwrap();
                let off = (got.value / want - 1.0).abs();
                assert!(off <= 1e-11 + got.error / want, "r {r}: {} vs {want} ({off:e})", got.value);
            }
        }
    }

    /// Orders 2..=n approach every order from 2 on as n grows, from below,
    /// at t = 0.2, order 10 within 2a^{10} of every order.
    #[test]
    fn finite_orders_approach_every_order() {
        let a = 0.5;
        let all = StartDensity::new(&a, 2, None).unwrap().tail(&0.2, &opts()).unwrap().value;
        let mut last = 0.0;
        for n in 2..=MAX_FINITE_ORDER {
            let got = StartDensity::new(&a, 2, Some(n)).unwrap().tail(&0.2, &opts()).unwrap().value;
            assert!(got > last && got < all, "n {n}: {got} not between {last} and {all}");
            last = got;
        }
        assert!((all - last) / all < 2.0 * a.powi(MAX_FINITE_ORDER as i32), "{last} vs {all}");
    }
}
