//! The periodic trapezoidal rule for ∫₀^{2π} of an even periodic function,
//! after a Möbius map of the circle that moves its two known singularities
//! as far from the real axis as they can both be (the check pass's rule for
//! Λ(ϑ), `docs/quadrature.md`).

use crate::quad::{Estimate, Options, Rule};
use crate::real::Real;

/// Smallest strip half-width (in the mapped variable) for which the check
/// pass tries the periodic trapezoidal rule: N = 512 nodes on the circle
/// reach e^{−512·0.05} ≈ 10⁻¹¹ relative. Below it (ϑ within ~10⁻³ of ψ_u)
/// the adaptive rule with graded cuts takes over, as it does when the
/// trapezoidal rule has not converged by N = 512.
pub(crate) const MIN_STRIP: f64 = 0.05;

/// The Möbius map of the circle φ = 2 arctan(ε tan(τ/2)), which crowds the
/// nodes of a uniform τ-grid towards φ = 0 (ε < 1) or φ = π (ε > 1),
/// dφ/dτ = ε/(cos²(τ/2) + ε² sin²(τ/2)). It is conformal, so an integrand
/// periodic and analytic in a strip stays so in τ: singularities at
/// φ = ±2i·artanh(a) and φ = π ± 2i·artanh(b) move to τ = ±2i·artanh(a/ε)
/// and τ = π ± 2i·artanh(εb). With ε = √(a/b) both lie at
/// 2 artanh(√(ab)), against 2 artanh(min(a, b)) without the map.
pub(crate) struct CircleMap<T> {
    eps: T,
    /// Half-width of the strip of analyticity in τ, 2 artanh(√(ab)).
    pub strip: T,
}

impl<T: Real> CircleMap<T> {
    /// The balanced map for singularities at tan(φ/2) = ±i·a and
    /// cot(φ/2) = ∓i·b (0 < a, b < 1).
    pub fn balanced(a: &T, b: &T) -> Self {
        let one = a.lit(1.0);
        if !(*a > a.lit(0.0) && *b > a.lit(0.0)) {
            return CircleMap { eps: one, strip: a.lit(0.0) };
        }
        let g = (a.clone() * b.clone()).sqrt();
        // 2 artanh(g) = ln((1 + g)/(1 − g)).
        let strip = ((one.clone() + g.clone()) / (one - g)).ln();
        CircleMap { eps: (a.clone() / b.clone()).sqrt(), strip }
    }

    /// (φ, π − φ, dφ/dτ) at τ, given τ and π − τ (each angle from its own
    /// half-angle tangent, so that both are accurate near 0).
    pub fn at(&self, tau: &T, tau_c: &T) -> (T, T, T) {
        let two = tau.lit(2.0);
        // cos(τ/2) = sin((π − τ)/2): accurate near τ = π.
        let (hs, hc) = ((tau.clone() / two.clone()).sin(), (tau_c.clone() / two.clone()).sin());
        // tan(φ/2) = ε·tan(τ/2), tan((π − φ)/2) = tan((π − τ)/2)/ε.
        let atan = |y: T, x: T| -> T {
            // 2·atan(y/x) for y, x ≥ 0, via asin of the normalised sine.
            let r = (y.clone() * y.clone() + x.clone() * x).sqrt();
            two.clone() * (y / r).asin()
        };
        let (y, x) = (self.eps.clone() * hs.clone(), hc.clone());
        let (yc, xc) = (hc.clone(), self.eps.clone() * hs.clone());
        let phi = if y <= x { atan(y.clone(), x.clone()) } else { tau.pi() - atan(yc.clone(), xc.clone()) };
        let phi_c = if yc <= xc { atan(yc, xc) } else { tau.pi() - atan(y, x) };
        let jac = self.eps.clone() / (hc.clone() * hc + self.eps.clone() * self.eps.clone() * hs.clone() * hs);
        (phi, phi_c, jac)
    }
}

/// ∫₀^{2π} f dφ of an even periodic f given on [0, π] as f(φ, π − φ), by the
/// trapezoidal rule with N = 16, 32, … 512 nodes on the circle (nested), its
/// bar |T_N − T_{N/2}| (the error of T_{N/2} when it converges
/// geometrically, so a bound on T_N's), accepted when that is below a
/// quarter of the goal; `None` if it is not by N = 512 (the caller then
/// uses the adaptive rule).
pub(crate) fn periodic_trapezoid<T: Real>(like: &T, f: &dyn Fn(&T, &T) -> T, opts: &Options) -> Option<Estimate<T>> {
    let pi = like.pi();
    // Sum over the nodes φ_j = 2πj/N on [0, π] with half weights at 0 and π.
    let mut n = 8usize; // half the circle's node count
    let node = |j: usize, n: usize| {
        let phi = pi.clone() * like.lit(j as f64) / like.lit(n as f64);
        let phi_c = pi.clone() * like.lit((n - j) as f64) / like.lit(n as f64);
        f(&phi, &phi_c)
    };
    let mut sum = (node(0, n) + node(n, n)) / like.lit(2.0);
    for j in 1..n {
        sum = sum + node(j, n);
    }
    let mut evaluations = (n + 1) as u64;
    let mut value = sum.clone() * like.lit(2.0) * pi.clone() / like.lit(n as f64);
    while n < 256 {
        // Doubling: the new nodes are the odd ones of the finer grid.
        let fine = 2 * n;
        for j in (1..fine).step_by(2) {
            sum = sum + node(j, fine);
        }
        evaluations += n as u64;
        n = fine;
        let next = sum.clone() * like.lit(2.0) * pi.clone() / like.lit(n as f64);
        let diff = (next.clone() - value.clone()).abs();
        value = next;
        let goal = (value.abs() * like.lit(opts.rel_tol)).max_of(like.lit(opts.abs_tol)) / like.lit(4.0);
        if diff <= goal && diff.is_finite() {
            return Some(Estimate::known(value, diff, evaluations, Rule::Check));
        }
    }
    None
}

/// ∫₀^{2π} f dφ of an even periodic f given on [0, π] as f(φ, π − φ), whose
/// singularities near the real axis sit at tan(φ/2) = ±i·a, 0 < a ≤ 1 (a
/// small: the circle passes next to w₀, where the Möbius map's balanced
/// strip 2 artanh(√(ab)) is too thin for [`periodic_trapezoid`]), and any
/// other singularity on the imaginary t-axis, t = tan(φ/2), no nearer to 0
/// (cot(φ/2) = ∓i·b with b ≤ 1, and t = ±i, where φ runs off to i∞, qualify).
/// The substitution t = a·sinh v (dφ = 2a cosh v/(1 + a² sinh² v) dv)
/// moves ±i·a to v = ±iπ/2 and every t = ±iy with y ≥ a onto the lines
/// |Im v| = π/2 (sinh v = iy/a with y/a ≥ 1 lies on them), so the integrand,
/// even in v, is analytic in the strip |Im v| < π/2 whatever a is, and the
/// trapezoidal rule on [0, V] converges like e^{−π²/h} (step h = 1, ½, …,
/// 1/16, nested); its bar is |T_h − T_{2h}| (the coarser one's error, as in
/// [`periodic_trapezoid`]) plus the tail beyond V. For v ≥ asinh(1/a) + 3
/// (φ within 2e^{−3} of π) the weight is 4e^{−v}/a to 1 %, times f near
/// φ = π, which varies little there, so ∫_V^∞ is g(V) (g the integrand in v)
/// to a few per cent: the tail is taken as (2 + h)|g(V)| (also covering the
/// full weight the last node gets), with V = asinh(1/a) + ln(8/rel_tol) + 3,
/// so that it is ~rel_tol/8 of the integral or less. Accepted when the bar
/// is below a quarter of the goal; `None` otherwise (the caller then uses
/// the adaptive rule). The value is twice the one over [0, π].
pub(crate) fn near_pole_trapezoid<T: Real>(a: &T, f: &dyn Fn(&T, &T) -> T, opts: &Options) -> Option<Estimate<T>> {
    let zero = a.lit(0.0);
    let one = a.lit(1.0);
    let two = a.lit(2.0);
    if !(*a > zero && *a <= one && opts.rel_tol > 0.0) {
        return None;
    }
    let pi = a.pi();
    let g = |v: &T| {
        let (sh, ch) = (v.sinh(), v.cosh());
        let t = a.clone() * sh;
        // φ = 2 atan t, π − φ = 2 atan(1/t), each from the smaller argument.
        let (phi, phi_c) = if t <= one {
            let p = two.clone() * t.clone().atan();
            (p.clone(), pi.clone() - p)
        } else {
            let pc = two.clone() * (one.clone() / t.clone()).atan();
            (pi.clone() - pc.clone(), pc)
        };
        f(&phi, &phi_c) * two.clone() * a.clone() * ch / (one.clone() + t.clone() * t)
    };
    let inv = one.clone() / a.clone();
    // asinh(1/a) + ln(8/rel_tol) + 3.
    let reach = (inv.clone() + (inv.clone() * inv + one.clone()).sqrt()).ln() + a.lit((8.0 / opts.rel_tol).ln() + 3.0);
    // h = 1: nodes 0, 1, …, K with K ≥ V.
    let k_max = reach.to_f64().ceil() as usize;
    if k_max > 4096 {
        return None;
    }
    let end = a.lit(k_max as f64);
    let g_end = g(&end);
    let mut sum = g(&zero) / two.clone() + g_end.clone();
    for k in 1..k_max {
        sum = sum + g(&a.lit(k as f64));
    }
    let mut evaluations = (k_max + 1) as u64;
    let mut steps = 1usize; // nodes per unit of v
    let mut value = sum.clone();
    while steps < 16 {
        let fine = 2 * steps;
        for j in (1..fine * k_max).step_by(2) {
            sum = sum + g(&(a.lit(j as f64) / a.lit(fine as f64)));
        }
        evaluations += (steps * k_max) as u64;
        steps = fine;
        let h = a.lit(1.0 / steps as f64);
        let next = sum.clone() * h.clone();
        let tail = g_end.abs() * (two.clone() + h);
        let bar = (next.clone() - value.clone()).abs() + tail;
        value = next;
        let goal = (value.abs() * a.lit(opts.rel_tol)).max_of(a.lit(opts.abs_tol)) / a.lit(4.0);
        if bar <= goal && bar.is_finite() {
            return Some(Estimate::known(value * two.clone(), bar * two, evaluations, Rule::Check));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫₀^{2π} [1/(1 − r cos φ) + 1/(1 + r′ cos φ)] dφ = 2π/√(1 − r²) + 2π/√(1 − r′²):
    /// poles at tan(φ/2) = ±i√((1 − r)/(1 + r)) and cot(φ/2) = ±i√((1 − r′)/(1 + r′)),
    /// the structure of Λ's integrand near w₀ and its antipode.
    fn two_poles(r: f64, r_far: f64) -> (f64, f64, f64, impl Fn(&f64, &f64) -> f64) {
        // 1 − r² as (1 − r)(1 + r): 1 − r is exact in f64.
        let exact = 2.0
            * std::f64::consts::PI
            * (1.0 / ((1.0 - r) * (1.0 + r)).sqrt() + 1.0 / ((1.0 - r_far) * (1.0 + r_far)).sqrt());
        let a = ((1.0 - r) / (1.0 + r)).sqrt();
        let b = ((1.0 - r_far) / (1.0 + r_far)).sqrt();
        // 1 − r cos φ = (1 − r) + 2r sin²(φ/2) and 1 + r′ cos φ = (1 − r′) +
        // 2r′ sin²((π − φ)/2), each without cancellation near its pole.
        let f = move |phi: &f64, phi_c: &f64| {
            let near = (1.0 - r) + 2.0 * r * (phi / 2.0).sin().powi(2);
            let far = (1.0 - r_far) + 2.0 * r_far * (phi_c / 2.0).sin().powi(2);
            1.0 / near + 1.0 / far
        };
        (exact, a, b, f)
    }

    #[test]
    fn circle_map_moves_both_poles_to_the_balanced_strip() {
        let (exact, a, b, f) = two_poles(0.9999, 0.5);
        let map = CircleMap::balanced(&a, &b);
        let predicted = 2.0 * ((a * b).sqrt()).atanh();
        assert!((map.strip - predicted).abs() <= 1e-15 * predicted);
        let mapped = |tau: &f64, tau_c: &f64| {
            let (phi, phi_c, jac) = map.at(tau, tau_c);
            assert!((phi + phi_c - std::f64::consts::PI).abs() <= 4.0 * f64::EPSILON);
            f(&phi, &phi_c) * jac
        };
        let opts = Options::rel(1e-12);
        let e = periodic_trapezoid(&1.0, &mapped, &opts).expect("mapped rule converges by N = 512");
        assert!((e.value - exact).abs() <= e.error + 1e-14 * exact, "{} vs {exact} ± {}", e.value, e.error);
        assert!(e.error <= 1e-12 * exact / 4.0);
        // Without the map the poles sit 2 artanh(a) ≈ 0.014 from the axis:
        // the plain rule has not converged by N = 512 and says so.
        assert!(periodic_trapezoid(&1.0, &f, &opts).is_none());
    }

    /// Poles 7·10⁻⁵ and 10⁻⁸ from the axis (strips of the balanced map
    /// 0.005 and 5·10⁻⁵, far too thin for it), the far pole at b = 0.58:
    /// the sinh substitution converges, within its bar of the closed form.
    #[test]
    fn the_sinh_substitution_takes_a_pole_next_to_the_circle() {
        for r in [1.0 - 1e-8, 1.0 - 2e-16] {
            let (exact, a, b, f) = two_poles(r, 0.5);
            assert!(CircleMap::balanced(&a, &b).strip < MIN_STRIP);
            for tol in [1e-6, 1e-12] {
                let e = near_pole_trapezoid(&a, &f, &Options::rel(tol)).expect("converges");
                assert!((e.value - exact).abs() <= e.error + 1e-14 * exact, "{} vs {exact} ± {}", e.value, e.error);
                assert!(e.error <= tol * exact / 4.0, "{e:?}");
                assert!(e.evaluations <= 600, "{e:?}");
            }
        }
    }

    #[test]
    fn circle_map_is_the_identity_when_the_poles_are_equally_far() {
        let map = CircleMap::balanced(&0.3, &0.3);
        let (phi, phi_c, jac) = map.at(&1.0, &(std::f64::consts::PI - 1.0));
        assert!((phi - 1.0).abs() <= 4.0 * f64::EPSILON && (jac - 1.0).abs() <= 4.0 * f64::EPSILON);
        assert!((phi_c - (std::f64::consts::PI - 1.0)).abs() <= 4.0 * f64::EPSILON);
    }

    /// Next to w₀ (ϑ − ψ_u from 10⁻³ down to 10⁻¹², where the check pass
    /// takes Λ by the sinh substitution, `periodic::near_pole_trapezoid`)
    /// the two passes' rules agree within their bars, with L₁ = 1/sin ψ.
    #[test]
    fn next_to_w0_the_check_rule_agrees_with_tanh_sinh() {
        use super::super::angular::{Features, Pole};
        let features = Features {
            plus: Pole { floor: None, marks: Vec::new() },
            minus: Pole { floor: None, marks: Vec::new() },
            equator_jump: false,
            source_near_0: None,
            source_near_pi: None,
        };
        let l1 = |_: &f64, _: &f64, sin_psi: &f64| 1.0 / sin_psi;
        let frame = super::super::angular::Frame::new(0.6f64, 0.8f64);
        for gap in [1e-3, -1e-5, 1e-8, -1e-12] {
            let theta = frame.psi_u + gap;
            let theta_c = std::f64::consts::PI - theta;
            let o = |rule| Options { rule, abs_tol: 0.0, ..Options::rel(1e-9) };
            let check = frame.azimuthal(&theta, &theta_c, &features, &l1, &o(Rule::Check)).unwrap();
            let primary = frame.azimuthal(&theta, &theta_c, &features, &l1, &o(Rule::TanhSinh)).unwrap();
            let diff = (check.value - primary.value).abs();
            assert!(diff <= check.error + primary.error, "gap {gap}: {check:?} against {primary:?}");
            assert!(check.evaluations <= 600, "gap {gap}: {check:?}");
        }
    }
}
