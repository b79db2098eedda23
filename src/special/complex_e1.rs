//! The scaled exponential integral e^{z}E₁(z) of complex argument (Re z ≥ 0)
//! and the θ-integral of single-scattered light in an isotropic medium that
//! it gives in closed form (`model::scattered`, `docs/model.md` §3a).

use crate::real::Real;

/// A complex number over [`Real`] (only what the two routes below need).
#[derive(Debug, Clone)]
struct C<T> {
    re: T,
    im: T,
}

impl<T: Real> C<T> {
    fn add(&self, o: &C<T>) -> C<T> {
        C { re: self.re.clone() + o.re.clone(), im: self.im.clone() + o.im.clone() }
    }
    fn mul(&self, o: &C<T>) -> C<T> {
        C {
            re: self.re.clone() * o.re.clone() - self.im.clone() * o.im.clone(),
            im: self.re.clone() * o.im.clone() + self.im.clone() * o.re.clone(),
        }
    }
    fn scale(&self, k: &T) -> C<T> {
        C { re: self.re.clone() * k.clone(), im: self.im.clone() * k.clone() }
    }
    /// 1/self (Smith's scaling, so that no square over- or underflows).
    fn recip(&self) -> C<T> {
        let one = self.re.lit(1.0);
        if self.re.abs() >= self.im.abs() {
            let r = self.im.clone() / self.re.clone();
            let d = self.re.clone() + self.im.clone() * r.clone();
            C { re: one / d.clone(), im: -r / d }
        } else {
            let r = self.re.clone() / self.im.clone();
            let d = self.re.clone() * r.clone() + self.im.clone();
            C { re: r / d.clone(), im: -one / d }
        }
    }
    fn abs(&self) -> T {
        let (a, b) = (self.re.abs(), self.im.abs());
        let (big, small) = if a >= b { (a, b) } else { (b, a) };
        if big.is_zero() {
            return big;
        }
        let q = small / big.clone();
        big * (q.lit(1.0) + q.clone() * q).sqrt()
    }
}

/// |z| below which e^{z}E₁(z) is summed from its power series, above which
/// from its continued fraction: the series' terms reach e^{|z|}/|z| at most
/// (no more than 4 lost to cancellation at |z| = 2), and the fraction needs
/// ~40 terms on the imaginary axis there in f64.
const SERIES_BELOW: f64 = 2.0;

/// 2∫_{u₀}^∞ e^{−a(u − u₀)}/(1 + u²) du with u₀ = tan(ψ/2), a = ρ cos(ψ/2)
/// (ρ = |z| ≥ 0), i.e. ∫_ψ^π e^{−ρ sin((θ − ψ)/2)/(cos(θ/2) cos(ψ/2))·…} dθ of
/// `model::scattered` (u = tan(θ/2), the exponent's excess σr sin ψ ·
/// (tan(θ/2) − tan(ψ/2)) = a(u − u₀), a = σr sin ψ, ρ = 2σr sin(ψ/2)), and
/// its absolute error bound. With 1/(1 + u²) = Im 1/(u − i) and
/// w = a(u − i), it is 2 Im[e^{z}E₁(z)] at z = a(u₀ − i) = ρe^{−i(π − ψ)/2}
/// (docs/model.md §3a). Given ψ and π − ψ (each exact where small).
/// Domain: 0 ≤ ψ ≤ π, ρ ≥ 0 finite; at ρ = 0 it is π − ψ. `None` where the
/// continued fraction has not converged by 10⁵ terms (never seen; the
/// caller then integrates).
pub fn isotropic_arc<T: Real>(psi: &T, psi_c: &T, rho: &T) -> Option<(T, T)> {
    let zero = psi.lit(0.0);
    if rho.is_zero() || psi_c.is_zero() {
        return Some((psi_c.clone(), zero));
    }
    let two = psi.lit(2.0);
    let eps = psi.eps();
    // z = ρ(sin(ψ/2) − i cos(ψ/2)), cos(ψ/2) = sin((π − ψ)/2).
    let z = C {
        re: rho.clone() * (psi.clone() / two.clone()).sin(),
        im: -(rho.clone() * (psi_c.clone() / two.clone()).sin()),
    };
    let (w, bound) = if rho.to_f64() < SERIES_BELOW {
        // e^{z}[−γ − ln z − Σ_{k≥1} (−z)^k/(k·k!)], ln z = ln ρ − i(π − ψ)/2.
        let minus_z = C { re: -z.re.clone(), im: -z.im.clone() };
        let mut term = C { re: psi.lit(1.0), im: zero.clone() };
        let mut sum = C { re: zero.clone(), im: zero.clone() };
        let mut size = zero.clone();
        let mut k = 1u32;
        loop {
            term = minus_z.mul(&term).scale(&(psi.lit(1.0) / psi.lit(k as f64)));
            let add = term.scale(&(psi.lit(1.0) / psi.lit(k as f64)));
            let mag = add.abs();
            sum = sum.add(&add);
            size = size + mag.clone();
            if mag <= eps.clone() * sum.abs().max_of(psi.lit(1e-300)) || k > 200 {
                break;
            }
            k += 1;
        }
        let e = C {
            re: -(psi.euler_gamma() + rho.ln() + sum.re.clone()),
            im: psi_c.clone() / two.clone() - sum.im.clone(),
        };
        let ez = C { re: z.im.clone().cos(), im: z.im.clone().sin() }.scale(&z.re.clone().exp());
        let w = ez.mul(&e);
        // Im w = e^{x}(cos y·Im E + sin y·Re E), y = Im z. The rounding of
        // Re E is that of its parts (γ, ln ρ, the terms); that of Im E is
        // that of (π − ψ)/2 and of Im S, whose terms' rounding is
        // proportional to |y| (Im of (−z)^k is formed from products with
        // Im z, the real parts' errors reach it multiplied by |y|): at most
        // |y|e^{ρ} times a few ulps, so that the bar stays relative to
        // Im w where z is nearly real (ψ near π, Im w ~ |y|).
        let y = z.im.abs();
        let err_re = eps.clone() * psi.lit(16.0) * (psi.euler_gamma() + rho.ln().abs() + size + psi.lit(1.0));
        let err_im =
            eps.clone() * psi.lit(16.0) * (psi_c.clone() / two.clone() + y.clone() * rho.clone().exp() + e.im.abs());
        let bound = z.re.clone().exp()
            * (err_im + y.clone() * err_re + eps.clone() * psi.lit(8.0) * (e.im.abs() + y.clone() * e.re.abs()));
        (w, bound)
    } else {
        // 1/(z + 1 − 1²/(z + 3 − 2²/(z + 5 − …))) by the modified Lentz method.
        let tiny = psi.lit(1e-300);
        let one = C { re: psi.lit(1.0), im: zero.clone() };
        let mut b = z.add(&one);
        let mut c = C { re: one.re.clone() / tiny.clone(), im: zero.clone() };
        let mut d = b.recip();
        let mut h = d.clone();
        let mut i = 1u32;
        loop {
            let an = psi.lit(-((i * i) as f64));
            b = b.add(&C { re: two.clone(), im: zero.clone() });
            d = d.scale(&an).add(&b);
            if d.abs() < tiny {
                d = C { re: tiny.clone(), im: zero.clone() };
            }
            d = d.recip();
            c = b.add(&c.recip().scale(&an));
            if c.abs() < tiny {
                c = C { re: tiny.clone(), im: zero.clone() };
            }
            let del = c.mul(&d);
            h = h.mul(&del);
            let change = C { re: del.re.clone() - psi.lit(1.0), im: del.im.clone() }.abs();
            if change <= eps {
                // Each step's rounding (a few ulps of h), and the last change.
                let bound = h.abs() * eps.clone() * psi.lit(8.0 + 4.0 * i as f64);
                break (h, bound);
            }
            i += 1;
            if i > 100_000 {
                return None;
            }
        }
    };
    Some((two.clone() * w.im, two * bound))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against the θ-integral by the engine in both rules, over ψ near 0,
    /// inside and near π and ρ on both sides of the switch: equal within
    /// the two bars, and at ρ = 0 the arc π − ψ.
    #[test]
    fn the_arc_integral_matches_its_quadrature() {
        use crate::quad::{integrate, Domain, Options, Rule};
        let pi = std::f64::consts::PI;
        for psi in [1e-9, 1e-3, 0.4, 1.5, 2.9, pi - 1e-4] {
            let psi_c = pi - psi;
            for rho in [0.0, 1e-6, 0.3, 1.999, 2.001, 7.0, 60.0] {
                let (value, bound) = isotropic_arc(&psi, &psi_c, &rho).unwrap();
                // The excess exponent ρ sin(δ/2)/cos(θ/2), θ = ψ + δ (scattered.rs).
                let f = |delta: &f64| {
                    let cos_half_theta = ((psi_c - delta) / 2.0).sin();
                    if cos_half_theta <= 0.0 {
                        return 0.0;
                    }
                    (-(rho * (delta / 2.0).sin() / cos_half_theta)).exp()
                };
                for rule in [Rule::TanhSinh, Rule::Check] {
                    let o = Options { rule, ..Options::rel(1e-12) };
                    let mut cuts = Vec::new();
                    if rho > 0.0 {
                        cuts.extend([2.0 / rho, 20.0 / rho].into_iter().filter(|c| *c < psi_c));
                    }
                    let q = integrate(f, &Domain::finite(0.0, psi_c).with_breakpoints(cuts), &o).unwrap();
                    let gap = (value - q.value).abs();
                    assert!(gap <= bound + q.error, "ψ {psi} ρ {rho} {rule:?}: {value} ± {bound} vs {q:?}");
                    // Near ψ = π (z nearly real) the fraction's bar, relative
                    // to |e^{z}E₁(z)|, is far above Im of it: the caller
                    // integrates there (`model::scattered`).
                    if psi <= 2.9 {
                        assert!(bound <= 1e-11 * value, "ψ {psi} ρ {rho}: {value} ± {bound}");
                    }
                }
            }
        }
    }
}
