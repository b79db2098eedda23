//! Dyadic rationals m·2^e, exactly: sums, differences and products of them
//! never round; quotients and square roots are rounded once, correctly, to a
//! double (or printed in decimal beyond a double's range).

use num_bigint::{BigInt, BigUint, Sign};
use num_traits::{One, Signed, Zero};
use std::cmp::Ordering;
use std::ops::{Add, Mul, Neg, Sub};

/// The number m·2^e for an integer m of any size, exact. Kept canonical (m
/// odd, or m = 0 with e = 0), so that equal numbers compare equal field by
/// field.
///
/// ```
/// use mcrt_reference::exact::Dyadic;
/// let third = Dyadic::from_f64(1.0 / 3.0).unwrap();
/// let sum = &(&third + &third) + &third; // exact: no rounding
/// assert_ne!(sum, Dyadic::from(1u64));
/// assert_eq!(sum.to_f64(), 1.0);
/// assert_eq!(Dyadic::from(2u64).sqrt_div_to_f64(&Dyadic::from(1u64)), 2f64.sqrt());
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Dyadic {
    mantissa: BigInt,
    exponent: i64,
}

impl Dyadic {
    /// 0.
    pub fn zero() -> Dyadic {
        Dyadic { mantissa: BigInt::zero(), exponent: 0 }
    }

    /// m·2^e, made canonical.
    pub fn new(mantissa: BigInt, exponent: i64) -> Dyadic {
        match mantissa.trailing_zeros() {
            None => Dyadic::zero(),
            Some(0) => Dyadic { mantissa, exponent },
            Some(tz) => Dyadic { mantissa: mantissa >> tz, exponent: exponent + tz as i64 },
        }
    }

    /// A finite double, exactly (`None` for ±inf and NaN).
    pub fn from_f64(x: f64) -> Option<Dyadic> {
        let (magnitude, exponent, negative) = decompose(x)?;
        let m = BigInt::from(magnitude);
        Some(Dyadic::new(if negative { -m } else { m }, exponent))
    }

    /// The integer mantissa m (odd, or 0).
    pub fn mantissa(&self) -> &BigInt {
        &self.mantissa
    }

    /// The exponent e.
    pub fn exponent(&self) -> i64 {
        self.exponent
    }

    /// Whether this is 0.
    pub fn is_zero(&self) -> bool {
        self.mantissa.is_zero()
    }

    /// Whether this is < 0.
    pub fn is_negative(&self) -> bool {
        self.mantissa.is_negative()
    }

    /// |x|.
    pub fn abs(&self) -> Dyadic {
        Dyadic { mantissa: self.mantissa.abs(), exponent: self.exponent }
    }

    /// x·2^k, exactly.
    pub fn mul_pow2(&self, k: i64) -> Dyadic {
        if self.is_zero() {
            return Dyadic::zero();
        }
        Dyadic { mantissa: self.mantissa.clone(), exponent: self.exponent + k }
    }

    /// x·k, exactly.
    pub fn mul_u64(&self, k: u64) -> Dyadic {
        Dyadic::new(&self.mantissa * k, self.exponent)
    }

    /// x^k, exactly.
    pub fn pow(&self, k: u32) -> Dyadic {
        Dyadic::new(self.mantissa.pow(k), self.exponent * i64::from(k))
    }

    /// The larger of the two.
    pub fn max(self, other: Dyadic) -> Dyadic {
        if other > self {
            other
        } else {
            self
        }
    }

    /// The nearest double (ties to even); ±inf beyond the largest, a
    /// subnormal or 0 below the smallest normal.
    pub fn to_f64(&self) -> f64 {
        self.div_to_f64(&Dyadic::from(1u64))
    }

    /// self / `den` rounded once to the nearest double (ties to even); `den` > 0.
    pub fn div_to_f64(&self, den: &Dyadic) -> f64 {
        assert!(den.mantissa.is_positive(), "a quotient's denominator must be > 0");
        if self.is_zero() {
            return 0.0;
        }
        let (q, exp, sticky) = truncated_quotient(self.mantissa.magnitude(), den.mantissa.magnitude(), 66);
        round_to_f64(q, exp + self.exponent - den.exponent, sticky, self.is_negative())
    }

    /// √(self / `den`) rounded once to the nearest double; self ≥ 0, `den` > 0.
    pub fn sqrt_div_to_f64(&self, den: &Dyadic) -> f64 {
        assert!(den.mantissa.is_positive(), "a quotient's denominator must be > 0");
        assert!(!self.is_negative(), "the square root of a negative quotient");
        if self.is_zero() {
            return 0.0;
        }
        let (mut num, mut exp) = (self.mantissa.magnitude().clone(), self.exponent - den.exponent);
        if exp.rem_euclid(2) == 1 {
            num <<= 1u32;
            exp -= 1;
        }
        // The radicand ⌊num·2^s/den⌋ with ≥ 134 bits and s even, so that its
        // root has ≥ 67 bits and ⌊√radicand⌋ = ⌊√(num·2^s/den)⌋.
        let den_m = den.mantissa.magnitude();
        let mut shift = 134 + den_m.bits() as i64 - num.bits() as i64;
        shift += shift.rem_euclid(2);
        let (scaled, den_m) =
            if shift >= 0 { (num << shift as u64, den_m.clone()) } else { (num, den_m << (-shift) as u64) };
        let radicand = &scaled / &den_m;
        let root = radicand.sqrt();
        let sticky = &radicand * &den_m != scaled || &root * &root != radicand;
        let rexp = -shift;
        round_to_f64(root, rexp / 2 + exp / 2, sticky, false)
    }

    /// self / `den` in decimal with `digits` digits after the point, like
    /// `format!("{:.6e}")` of a double but at any magnitude (`den` > 0); "0"
    /// for 0.
    pub fn div_to_sci(&self, den: &Dyadic, digits: usize) -> String {
        sci(self, den, digits, false)
    }

    /// √(self / `den`) in decimal, as [`Dyadic::div_to_sci`] (self ≥ 0, `den` > 0).
    pub fn sqrt_div_to_sci(&self, den: &Dyadic, digits: usize) -> String {
        sci(self, den, digits, true)
    }

    /// Bits of |m| (0 for 0).
    fn bits(&self) -> i64 {
        self.mantissa.bits() as i64
    }

    /// A rough base-2 logarithm of |x| (exact to within 1; `None` for 0).
    pub fn log2_floor(&self) -> Option<i64> {
        (!self.is_zero()).then(|| self.bits() - 1 + self.exponent)
    }
}

/// |x| = magnitude·2^exponent for a finite double, with its sign.
pub(crate) fn decompose(x: f64) -> Option<(u64, i64, bool)> {
    if !x.is_finite() {
        return None;
    }
    let bits = x.to_bits();
    let negative = bits >> 63 == 1;
    let biased = ((bits >> 52) & 0x7ff) as i64;
    let fraction = bits & ((1u64 << 52) - 1);
    Some(if biased == 0 { (fraction, -1074, negative) } else { (fraction | (1u64 << 52), biased - 1075, negative) })
}

/// ⌊a·2^s / b⌋ with at least `bits` bits, as (quotient, −s, whether the
/// division left a remainder).
fn truncated_quotient(a: &BigUint, b: &BigUint, bits: i64) -> (BigUint, i64, bool) {
    let shift = bits + b.bits() as i64 - a.bits() as i64;
    let (num, den) = if shift >= 0 { (a << shift as u64, b.clone()) } else { (a.clone(), b << (-shift) as u64) };
    let q = &num / &den;
    let sticky = &q * &den != num;
    (q, -shift, sticky)
}

/// The double nearest to ±(q + δ)·2^exp, 0 ≤ δ < 1 and δ > 0 exactly when
/// `sticky` (q has at least 55 bits, so δ only breaks ties).
fn round_to_f64(q: BigUint, exp: i64, sticky: bool, negative: bool) -> f64 {
    let sign = if negative { -1.0 } else { 1.0 };
    let nbits = q.bits() as i64;
    let top = nbits - 1 + exp;
    if top > 1023 {
        return sign * f64::INFINITY;
    }
    let ulp = if top >= -1022 { top - 52 } else { -1074 };
    let drop = ulp - exp;
    debug_assert!(drop >= 1, "round_to_f64 needs guard bits");
    if drop > nbits {
        return sign * 0.0; // below half the smallest subnormal
    }
    let kept = &q >> drop as u64;
    let rest = &q - (&kept << drop as u64);
    let half = BigUint::one() << (drop - 1) as u64;
    let odd = kept.bit(0);
    let up = match rest.cmp(&half) {
        Ordering::Greater => true,
        Ordering::Equal => sticky || odd,
        Ordering::Less => false,
    };
    let kept = u64::try_from(kept).expect("at most 53 bits kept") + u64::from(up);
    sign * ldexp(kept as f64, ulp)
}

/// x·2^k for an x whose result is a double (no rounding on the way).
fn ldexp(mut x: f64, mut k: i64) -> f64 {
    let pow2 = |j: i64| f64::from_bits(((j + 1023) as u64) << 52);
    while k > 1000 {
        x *= pow2(1000);
        k -= 1000;
    }
    while k < -1000 {
        x *= pow2(-1000);
        k += 1000;
    }
    x * pow2(k)
}

/// ±(n/d)^(1/2 if `root`) in decimal scientific notation at any magnitude.
fn sci(n: &Dyadic, d: &Dyadic, digits: usize, root: bool) -> String {
    if n.is_zero() {
        return "0".into(); // as MPFR printed an exact 0
    }
    let log2 = (n.bits() + n.exponent - d.bits() - d.exponent) as f64 / if root { 2.0 } else { 1.0 };
    let decade = (log2 * std::f64::consts::LOG10_2).floor() as i64;
    // n/d·10^(−decade) (squared for a root), of order 1 at any magnitude.
    let ten = BigInt::from(10u32).pow((decade.unsigned_abs() * if root { 2 } else { 1 }) as u32);
    let (n, d) = if decade >= 0 {
        (n.clone(), Dyadic::new(d.mantissa.clone() * ten, d.exponent))
    } else {
        (Dyadic::new(n.mantissa.clone() * ten, n.exponent), d.clone())
    };
    let scaled = if root { n.sqrt_div_to_f64(&d) } else { n.div_to_f64(&d) };
    let text = format!("{scaled:.digits$e}");
    let (mantissa, exp) = text.split_once('e').expect("a double in scientific notation");
    format!("{mantissa}e{}", exp.parse::<i64>().expect("an exponent") + decade)
}

impl From<u64> for Dyadic {
    fn from(n: u64) -> Dyadic {
        Dyadic::new(BigInt::from(n), 0)
    }
}

impl From<BigInt> for Dyadic {
    fn from(n: BigInt) -> Dyadic {
        Dyadic::new(n, 0)
    }
}

impl Ord for Dyadic {
    fn cmp(&self, other: &Dyadic) -> Ordering {
        match (self - other).mantissa.sign() {
            Sign::Minus => Ordering::Less,
            Sign::NoSign => Ordering::Equal,
            Sign::Plus => Ordering::Greater,
        }
    }
}

impl PartialOrd for Dyadic {
    fn partial_cmp(&self, other: &Dyadic) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Add for &Dyadic {
    type Output = Dyadic;
    fn add(self, other: &Dyadic) -> Dyadic {
        if self.is_zero() {
            return other.clone();
        }
        if other.is_zero() {
            return self.clone();
        }
        let e = self.exponent.min(other.exponent);
        let a = &self.mantissa << (self.exponent - e) as u64;
        let b = &other.mantissa << (other.exponent - e) as u64;
        Dyadic::new(a + b, e)
    }
}

impl Sub for &Dyadic {
    type Output = Dyadic;
    fn sub(self, other: &Dyadic) -> Dyadic {
        self + &(-other)
    }
}

impl Neg for &Dyadic {
    type Output = Dyadic;
    fn neg(self) -> Dyadic {
        Dyadic { mantissa: -&self.mantissa, exponent: self.exponent }
    }
}

impl Mul for &Dyadic {
    type Output = Dyadic;
    fn mul(self, other: &Dyadic) -> Dyadic {
        Dyadic::new(&self.mantissa * &other.mantissa, self.exponent + other.exponent)
    }
}

macro_rules! by_value {
    ($($op:ident $method:ident),*) => {$(
        impl $op for Dyadic {
            type Output = Dyadic;
            fn $method(self, other: Dyadic) -> Dyadic {
                (&self).$method(&other)
            }
        }
        impl $op<&Dyadic> for Dyadic {
            type Output = Dyadic;
            fn $method(self, other: &Dyadic) -> Dyadic {
                (&self).$method(other)
            }
        }
    )*};
}
by_value!(Add add, Sub sub, Mul mul);

impl Neg for Dyadic {
    type Output = Dyadic;
    fn neg(self) -> Dyadic {
        Dyadic { mantissa: -self.mantissa, exponent: self.exponent }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn d(x: f64) -> Dyadic {
        Dyadic::from_f64(x).unwrap()
    }

    #[test]
    fn doubles_round_trip_exactly_including_subnormals() {
        for x in [0.0, 1.0, -2.5, 1e-300, 5e-324, -4.9e-322, f64::MAX, f64::MIN_POSITIVE, 1.0 / 3.0] {
            assert_eq!(d(x).to_f64().to_bits(), if x == 0.0 { 0.0f64.to_bits() } else { x.to_bits() }, "{x:e}");
        }
        assert!(Dyadic::from_f64(f64::NAN).is_none());
    }

    #[test]
    fn quotients_are_correctly_rounded() {
        for (a, b) in [(1.0, 3.0), (2.0, 7.0), (1e300, 1e-10), (1e-300, 1e10), (355.0, 113.0), (-1.0, 49.0)] {
            assert_eq!(d(a).div_to_f64(&d(b)), a / b, "{a:e}/{b:e}");
        }
        for x in [2.0, 3.0, 1e-310, 0.5, 1e300, 7.0] {
            assert_eq!(d(x).sqrt_div_to_f64(&d(1.0)), x.sqrt(), "√{x:e}");
        }
        // Overflow and underflow.
        assert_eq!(d(f64::MAX).div_to_f64(&d(0.5)), f64::INFINITY);
        assert_eq!(d(5e-324).div_to_f64(&d(4.0)), 0.0);
        // Ties: 1 + 2^-53 is halfway between 1 and its successor, and rounds to even (1).
        let tie = &d(1.0) + &d(2f64.powi(-53));
        assert_eq!(tie.to_f64(), 1.0);
        let above = &tie + &d(2f64.powi(-200));
        assert_eq!(above.to_f64(), 1.0 + f64::EPSILON);
    }

    #[test]
    fn decimal_beyond_the_range_of_a_double() {
        let tiny = d(1e-300).pow(2);
        assert_eq!(tiny.div_to_sci(&d(1.0), 6), "1.000000e-600");
        assert_eq!(d(1e300).pow(3).sqrt_div_to_sci(&d(1.0), 3), "1.000e450");
        assert_eq!(d(-2.5).div_to_sci(&d(1.0), 2), "-2.50e0");
        assert_eq!(d(0.0).div_to_sci(&d(1.0), 6), "0");
    }

    #[test]
    fn comparisons_and_canonical_form() {
        assert!(d(1.0) < d(1.5));
        assert!(-d(3.0) < d(-2.0));
        assert_eq!(&d(0.5) + &d(0.5), d(1.0));
        assert_eq!(&d(3.0) * &d(0.25), d(0.75));
        assert_eq!(d(2.0).mul_pow2(-3), d(0.25));
        assert_eq!(&d(1.0) - &d(1.0), Dyadic::zero());
    }
}
