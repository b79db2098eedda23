//! Node tables computed at the working precision, cached per (type, precision).

use crate::real::Real;
use std::any::{Any, TypeId};
use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::Arc;

type Cache = RefCell<HashMap<(TypeId, u32, u32, usize), Arc<dyn Any + Send + Sync>>>;

thread_local! {
    /// Per-thread, so that look-ups in inner loops take no lock.
    static CACHE: Cache = RefCell::new(HashMap::new());
}

/// Value `make()` cached under (type, precision, kind, n), per thread.
pub(crate) fn cached<T: Real + 'static, V: Send + Sync + 'static>(
    kind: u32,
    like: &T,
    n: usize,
    make: impl FnOnce() -> V,
) -> Arc<V> {
    let key = (TypeId::of::<T>(), like.prec(), kind, n);
    if let Some(v) = CACHE.with(|c| c.borrow().get(&key).cloned()) {
        return v.downcast::<V>().expect("node cache type");
    }
    let v = Arc::new(make());
    CACHE.with(|c| c.borrow_mut().insert(key, v.clone()));
    v
}

/// One tanh–sinh node: x = ±(1 − comp) on [−1, 1], weight w = (π/2) cosh t / cosh²((π/2) sinh t).
#[derive(Debug, Clone)]
pub(crate) struct TsNode<T> {
    /// 1 − |x| = 2/(e^{2u} + 1), u = (π/2) sinh t: exact near the ends.
    pub comp: T,
    pub weight: T,
}

/// The tanh–sinh nodes of one level: level 0 holds t = 0, 1, 2, … (t = 0
/// first), level k ≥ 1 the odd multiples of 2^{−k}. Nodes stop where the
/// weight falls below eps², beyond any contribution at this precision.
/// Each level is built when a panel first needs it and cached per (type,
/// precision, level): a level holds ~2^k·t_max nodes (t_max ≈ 3.5 in f64,
/// ≈ 8 at 4096 bits), so building every level up to the cap in advance
/// would cost seconds at high precision for integrals that stop at level 3.
pub(crate) fn tanh_sinh_level<T: Real + 'static>(like: &T, level: usize) -> Arc<Vec<TsNode<T>>> {
    cached(0, like, level, || {
        let eps = like.eps();
        let tiny = eps.clone() * eps;
        let half_pi = like.pi() / like.lit(2.0);
        let node = |t: T| -> TsNode<T> {
            let u = half_pi.clone() * t.sinh();
            let e2u = (u.clone() * like.lit(2.0)).exp();
            let comp = like.lit(2.0) / (e2u + like.lit(1.0));
            let c = u.cosh();
            let weight = half_pi.clone() * t.cosh() / (c.clone() * c);
            TsNode { comp, weight }
        };
        let h = like.powi_like(-(level as i32));
        let (start, step) = if level == 0 { (0usize, 1usize) } else { (1, 2) };
        let mut nodes = Vec::new();
        let mut m = start;
        loop {
            let n = node(h.clone() * like.lit(m as f64));
            if n.weight < tiny && m > 0 {
                break;
            }
            nodes.push(n);
            m += step;
        }
        nodes
    })
}

/// Gauss–Legendre nodes and weights on [−1, 1] (x ≥ 0 half; the rule is
/// symmetric), by Newton's method on P_n at the working precision.
pub(crate) fn gauss_legendre<T: Real + 'static>(like: &T, n: usize) -> Arc<Vec<(T, T)>> {
    cached(1, like, n, || {
        let one = like.lit(1.0);
        let tol = like.eps() * like.lit(4.0);
        let mut out = Vec::with_capacity(n.div_ceil(2));
        for i in 1..=n.div_ceil(2) {
            if n % 2 == 1 && i == n.div_ceil(2) {
                // The centre node of an odd rule is exactly 0 (P_n is odd).
                // Newton from cos(π/2) ≈ 6e−17 may stop at a tiny non-zero
                // x, which the rule would then count twice (±x).
                let (_, pm1) = legendre(&like.lit(0.0), n);
                let dp = like.lit(n as f64) * pm1;
                out.push((like.lit(0.0), like.lit(2.0) / (dp.clone() * dp)));
                continue;
            }
            let guess = (std::f64::consts::PI * (i as f64 - 0.25) / (n as f64 + 0.5)).cos();
            let mut x = seeded_root(like, n, guess);
            let mut dp = one.clone();
            for _ in 0..200 {
                let (p, pm1) = legendre(&x, n);
                dp = like.lit(n as f64) * (x.clone() * p.clone() - pm1) / (x.clone() * x.clone() - one.clone());
                let dx = p / dp.clone();
                x = x - dx.clone();
                if dx.abs() <= tol.clone() {
                    let (p, pm1) = legendre(&x, n);
                    dp = like.lit(n as f64) * (x.clone() * p - pm1) / (x.clone() * x.clone() - one.clone());
                    break;
                }
            }
            let w = like.lit(2.0) / ((one.clone() - x.clone() * x.clone()) * dp.clone() * dp);
            out.push((x, w));
        }
        out
    })
}

/// One Newton step towards a root of P_n from `x`, at `x`'s precision.
fn newton_step<T: Real>(x: &T, n: usize) -> T {
    let (p, pm1) = legendre(x, n);
    let one = x.lit(1.0);
    let dp = x.lit(n as f64) * (x.clone() * p.clone() - pm1) / (x.clone() * x.clone() - one);
    x.clone() - p / dp
}

/// A start for the Newton iteration at the working precision, near the
/// root of P_n from `guess`: converged in f64 first, then one step at each
/// doubled precision up to half the working one (MPFR). Newton doubles the
/// correct bits per step, so the iteration at the working precision needs
/// two steps, not the ~8 from `guess` (at 1024 bits, 512 nodes took 0.6 s
/// per thread, within no budget check).
fn seeded_root<T: Real>(like: &T, n: usize, guess: f64) -> T {
    let mut x = guess;
    for _ in 0..100 {
        let next = newton_step(&x, n);
        let done = (next - x).abs() <= 4.0 * f64::EPSILON;
        x = next;
        if done {
            break;
        }
    }
    let target = like.prec();
    let mut bits = 53;
    let mut x = like.lit(x);
    while T::CAN_RAISE_PRECISION && 2 * bits < target {
        bits *= 2;
        x = newton_step(&x.rounded_to(bits), n);
    }
    x.rounded_to(target)
}

/// (P_n(x), P_{n−1}(x)) by the three-term recurrence.
fn legendre<T: Real>(x: &T, n: usize) -> (T, T) {
    let mut p0 = x.lit(1.0);
    let mut p1 = x.clone();
    for k in 2..=n {
        let kf = k as f64;
        let p2 = (x.lit(2.0 * kf - 1.0) * x.clone() * p1.clone() - x.lit(kf - 1.0) * p0) / x.lit(kf);
        p0 = p1;
        p1 = p2;
    }
    (p1, p0)
}

#[cfg(all(test, feature = "mpfr"))]
mod tests {
    use super::*;
    use rug::Float;

    /// Σ w f(x) over the symmetric rule.
    fn apply(nodes: &[(Float, Float)], f: impl Fn(&Float) -> Float) -> Float {
        let mut sum = Float::with_val(nodes[0].0.prec(), 0);
        for (x, w) in nodes {
            sum += Float::with_val(x.prec(), w * f(x));
            if !x.is_zero() {
                sum += Float::with_val(x.prec(), w * f(&Float::with_val(x.prec(), -x)));
            }
        }
        sum
    }

    /// Every precision the check rule can be asked for uses n = prec/2 and
    /// n/2 points, odd and even: both must integrate x^{2k} exactly
    /// (weights sum to 2, the centre node of an odd rule counted once).
    #[test]
    fn gauss_legendre_is_exact_at_every_precision() {
        for prec in 32u32..=256 {
            let like = Float::with_val(prec, 0);
            let n = (prec as usize / 2).clamp(20, 600);
            for m in [n, n / 2] {
                let nodes = gauss_legendre(&like, m);
                for k in [0u32, 2, 2 * m as u32 - 2] {
                    let got = apply(&nodes, |x| Float::with_val(prec, rug::ops::Pow::pow(x, k)));
                    let want = Float::with_val(prec, 2) / (k + 1);
                    let rel = Float::with_val(prec, (got - &want) / &want).abs().to_f64();
                    assert!(rel < 1e3 * like.eps().to_f64(), "prec {prec} n {m} x^{k}: rel error {rel:e}");
                }
            }
        }
    }
}
