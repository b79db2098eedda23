//! An exact accumulator of powers of doubles: a fixed-point integer as wide
//! as the terms need, in 32-bit digits held in 64-bit slots whose carries
//! are propagated lazily (a "superaccumulator"). Adding never rounds, so a
//! sum does not depend on the order of its terms.

use super::dyadic::{decompose, Dyadic};
use num_bigint::{BigInt, BigUint};

/// Digits per slot.
const DIGIT_BITS: i64 = 32;
const DIGIT_MASK: i64 = (1 << DIGIT_BITS) - 1;
/// Each term adds less than 2³² to a slot, so slots stay below 2⁶² for this
/// many terms between carry propagations.
const TERMS_BETWEEN_CARRIES: u32 = 1 << 29;
/// Room kept below the first term for smaller ones, in slots.
const LOW_ROOM: i64 = 4;

/// An exact sum of terms ±m·2^e (m an integer of up to 6 × 64 bits): the
/// value Σ slotᵢ·2^(lsb + 32 i).
///
/// ```
/// use mcrt_reference::exact::{Dyadic, ExactSum};
/// let mut a = ExactSum::default();
/// for x in [1e30, 1.0, -1e30, 1e-30] {
///     a.add_f64(x);
/// }
/// assert_eq!(a.to_dyadic(), &Dyadic::from(1u64) + &Dyadic::from_f64(1e-30).unwrap());
/// ```
#[derive(Debug, Clone, Default)]
pub struct ExactSum {
    slots: Vec<i64>,
    /// The exponent of slot 0's lowest bit.
    lsb: i64,
    /// Terms added since the carries were last propagated.
    pending: u32,
}

impl ExactSum {
    /// Adds ±`magnitude`·2^`exponent` (`magnitude` little-endian 64-bit limbs).
    pub fn add_term(&mut self, magnitude: &[u64], exponent: i64, negative: bool) {
        let Some(top) = magnitude.iter().rposition(|&limb| limb != 0) else { return };
        let magnitude = &magnitude[..=top];
        let bits = 64 * top as i64 + 64 - i64::from(magnitude[top].leading_zeros());
        self.make_room(exponent, exponent + bits);
        let offset = exponent - self.lsb;
        let (first, shift) = ((offset / DIGIT_BITS) as usize, (offset % DIGIT_BITS) as u32);
        let sign = if negative { -1 } else { 1 };
        let mut carry = 0u64;
        let digits = magnitude.iter().flat_map(|&limb| [limb & DIGIT_MASK as u64, limb >> DIGIT_BITS]);
        for (slot, digit) in self.slots[first..].iter_mut().zip(digits) {
            let shifted = (digit << shift) | carry;
            *slot += sign * (shifted & DIGIT_MASK as u64) as i64;
            carry = shifted >> DIGIT_BITS;
        }
        self.slots[first + 2 * magnitude.len()] += sign * carry as i64;
        self.pending += 1;
        if self.pending >= TERMS_BETWEEN_CARRIES {
            self.propagate_carries();
        }
    }

    /// Adds a finite double (a non-finite one is a caller's bug: panics).
    pub fn add_f64(&mut self, x: f64) {
        let (magnitude, exponent, negative) = decompose(x).expect("ExactSum::add_f64 takes finite doubles");
        self.add_term(&[magnitude], exponent, negative);
    }

    /// Adds another sum.
    pub fn merge(&mut self, other: &ExactSum) {
        let mut other = other.clone();
        other.propagate_carries();
        for (i, &slot) in other.slots.iter().enumerate() {
            if slot != 0 {
                self.add_term(&[slot.unsigned_abs()], other.lsb + DIGIT_BITS * i as i64, slot < 0);
            }
        }
    }

    /// The sum times 2^k (exact).
    pub fn mul_pow2(&mut self, k: i64) {
        self.lsb += k;
    }

    /// The sum as a dyadic rational.
    pub fn to_dyadic(&self) -> Dyadic {
        let mut sum = self.clone();
        sum.propagate_carries();
        let Some((&top, digits)) = sum.slots.split_last() else { return Dyadic::zero() };
        let digits: Vec<u32> = digits.iter().map(|&d| d as u32).collect();
        let top = BigInt::from(top) << (DIGIT_BITS as usize * digits.len());
        Dyadic::new(BigInt::from(BigUint::from_slice(&digits)) + top, sum.lsb)
    }

    /// Whether the sum is 0.
    pub fn is_zero(&self) -> bool {
        self.to_dyadic().is_zero()
    }

    /// Slots for bits lo..hi of a term, with room for its carries.
    fn make_room(&mut self, lo: i64, hi: i64) {
        if self.slots.is_empty() {
            self.lsb = lo - LOW_ROOM * DIGIT_BITS;
        } else if lo < self.lsb {
            let extra = (self.lsb - lo + DIGIT_BITS - 1) / DIGIT_BITS + LOW_ROOM;
            self.slots.splice(0..0, std::iter::repeat_n(0, extra as usize));
            self.lsb -= extra * DIGIT_BITS;
        }
        // The term's digits, one more for its shift and one for a carry.
        let needed = ((hi - self.lsb) / DIGIT_BITS + 3) as usize;
        if self.slots.len() < needed {
            self.slots.resize(needed, 0);
        }
    }

    /// Every slot but the last to [0, 2³²), the last to {−1, 0} (the sign).
    fn propagate_carries(&mut self) {
        let mut carry = 0i64;
        for slot in &mut self.slots {
            let v = *slot + carry;
            *slot = v & DIGIT_MASK;
            carry = v >> DIGIT_BITS;
        }
        while carry != 0 && carry != -1 {
            self.slots.push(carry & DIGIT_MASK);
            carry >>= DIGIT_BITS;
        }
        if carry == -1 {
            self.slots.push(-1);
        }
        while self.slots.len() > 1 && self.slots[self.slots.len() - 1] == 0 {
            self.slots.pop();
        }
        if self.slots == [0] {
            self.slots.clear();
        }
        self.pending = 0;
    }
}

impl PartialEq for ExactSum {
    /// Equal values (whatever their layout).
    fn eq(&self, other: &ExactSum) -> bool {
        self.to_dyadic() == other.to_dyadic()
    }
}

/// The exact powers x, x², …, x^K of a double: |x|ᵏ = mᵏ·2^(k e) with m
/// the 53-bit integer mantissa, as 64-bit limbs (m⁶ needs 318 bits).
#[derive(Debug, Clone)]
pub struct Powers<const K: usize> {
    limbs: [[u64; 6]; K],
    lens: [usize; K],
    exponent: i64,
    negative: bool,
}

impl<const K: usize> Powers<K> {
    /// The powers of a finite double (`None` for ±inf, NaN), K ≤ 6.
    pub fn of(x: f64) -> Option<Powers<K>> {
        const { assert!(K >= 1 && K <= 6, "powers 1 to 6") };
        let (m, exponent, negative) = decompose(x)?;
        let mut limbs = [[0u64; 6]; K];
        let mut lens = [0usize; K];
        limbs[0][0] = m;
        lens[0] = 1;
        for k in 1..K {
            let (previous, current) = limbs.split_at_mut(k);
            let mut carry = 0u128;
            for (out, &limb) in current[0].iter_mut().zip(&previous[k - 1][..lens[k - 1]]) {
                let product = u128::from(limb) * u128::from(m) + carry;
                *out = product as u64;
                carry = product >> 64;
            }
            current[0][lens[k - 1]] = carry as u64;
            lens[k] = lens[k - 1] + 1;
        }
        Some(Powers { limbs, lens, exponent, negative })
    }

    /// Adds x^k to `sum` (k in 1..=K).
    pub fn add_to(&self, k: usize, sum: &mut ExactSum) {
        let negative = self.negative && k % 2 == 1;
        sum.add_term(&self.limbs[k - 1][..self.lens[k - 1]], self.exponent * k as i64, negative);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn value(s: &ExactSum) -> Dyadic {
        s.to_dyadic()
    }

    #[test]
    fn sums_of_doubles_of_any_spread_are_exact_and_order_free() {
        let xs = [1e300, -3.5, 5e-324, 1e-300, -1e300, 2.0f64.powi(-1000), 7.25, -0.0, 1e16, 1.0];
        let mut forward = ExactSum::default();
        xs.iter().for_each(|&x| forward.add_f64(x));
        let mut backward = ExactSum::default();
        xs.iter().rev().for_each(|&x| backward.add_f64(x));
        let exact = xs.iter().fold(Dyadic::zero(), |acc, &x| &acc + &Dyadic::from_f64(x).unwrap());
        assert_eq!(value(&forward), exact);
        assert_eq!(forward, backward);
        let mut half = ExactSum::default();
        xs[..4].iter().for_each(|&x| half.add_f64(x));
        let mut rest = ExactSum::default();
        xs[4..].iter().for_each(|&x| rest.add_f64(x));
        half.merge(&rest);
        assert_eq!(half, forward);
    }

    #[test]
    fn negative_sums_and_cancellation_to_zero() {
        let mut s = ExactSum::default();
        s.add_f64(-1.0);
        s.add_f64(-2.0f64.powi(-60));
        let expected = -(&Dyadic::from(1u64) + &Dyadic::from_f64(2.0f64.powi(-60)).unwrap());
        assert_eq!(value(&s), expected);
        s.add_f64(1.0);
        s.add_f64(2.0f64.powi(-60));
        assert!(s.is_zero());
        assert_eq!(s, ExactSum::default());
    }

    #[test]
    fn powers_are_exact() {
        for x in [3.0, -1.5, 1.0 / 3.0, 1e-200, 5e-324, 1e250] {
            let p = Powers::<6>::of(x).unwrap();
            let d = Dyadic::from_f64(x).unwrap();
            for k in 1..=6 {
                let mut s = ExactSum::default();
                p.add_to(k, &mut s);
                assert_eq!(value(&s), d.pow(k as u32), "{x:e}^{k}");
            }
        }
    }

    #[test]
    fn many_terms_through_carry_propagation() {
        let mut s = ExactSum::default();
        let x = f64::from_bits(0x3fef_ffff_ffff_ffff); // 53 ones in the mantissa
        for _ in 0..3000 {
            s.add_f64(x);
        }
        s.pending = TERMS_BETWEEN_CARRIES - 1;
        s.add_f64(-x);
        assert_eq!(value(&s), &Dyadic::from_f64(x).unwrap() * &Dyadic::from(2999u64));
        let mut scaled = s.clone();
        scaled.mul_pow2(-2000);
        assert_eq!(value(&scaled), value(&s).mul_pow2(-2000));
    }
}
