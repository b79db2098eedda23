//! One numeric interface for f64 and MPFR (`rug::Float`, feature `mpfr`) so
//! that every special function and quadrature rule is written once and runs
//! at any precision.
//!
//! A `rug::Float` carries its precision; constants are made "like" an existing
//! value ([`Real::lit`], [`Real::pi`]) so that they inherit it.

#[cfg(feature = "mpfr")]
use rug::float::Constant;
#[cfg(feature = "mpfr")]
use rug::Float;
use std::fmt::Debug;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// A real number type: f64, or `rug::Float` at its own precision (feature
/// `mpfr`).
pub trait Real:
    'static
    + Clone
    + Debug
    + PartialOrd
    + Send
    + Sync
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// Significand bits (53 for f64).
    fn prec(&self) -> u32;
    /// Whether [`Real::raised`] adds guard bits (MPFR) or is the identity (f64).
    const CAN_RAISE_PRECISION: bool;
    /// The value `v` at this value's precision.
    fn lit(&self, v: f64) -> Self;
    /// Machine epsilon 2^(1−prec) (2⁻⁵² for f64; twice the unit roundoff).
    fn eps(&self) -> Self {
        self.lit(2f64).powi_like(1 - self.prec() as i32)
    }
    /// 2^k at this precision.
    fn powi_like(&self, k: i32) -> Self;
    /// π at this precision.
    fn pi(&self) -> Self;
    /// Euler–Mascheroni constant γ.
    fn euler_gamma(&self) -> Self;
    /// Nearest f64 (MPFR: rounded to nearest).
    fn to_f64(&self) -> f64;
    /// The f64 at or above this value (MPFR: rounded up), for error bars:
    /// a bar below the smallest double stays a positive bound, never 0.
    fn to_f64_up(&self) -> f64 {
        self.to_f64()
    }
    /// Neither infinite nor NaN.
    fn is_finite(&self) -> bool;
    /// |x|.
    fn abs(&self) -> Self;
    /// √x (NaN for x < 0).
    fn sqrt(&self) -> Self;
    /// eˣ.
    fn exp(&self) -> Self;
    /// Natural logarithm ln x (x > 0).
    fn ln(&self) -> Self;
    /// ln(1 + x), accurate for small x.
    fn ln_1p(&self) -> Self;
    /// eˣ − 1, accurate for small x.
    fn exp_m1(&self) -> Self;
    /// arctan x ∈ (−π/2, π/2).
    fn atan(&self) -> Self;
    /// sin x (x in radians).
    fn sin(&self) -> Self;
    /// cos x (x in radians).
    fn cos(&self) -> Self;
    /// arcsin x ∈ [−π/2, π/2], for x ∈ [−1, 1].
    fn asin(&self) -> Self;
    /// arccos x ∈ [0, π], for x ∈ [−1, 1].
    fn acos(&self) -> Self;
    /// sinh x.
    fn sinh(&self) -> Self;
    /// cosh x.
    fn cosh(&self) -> Self;
    /// tanh x.
    fn tanh(&self) -> Self;
    /// Whether the value is exactly zero (±0).
    fn is_zero(&self) -> bool {
        self.to_f64() == 0.0 && self.is_finite()
    }
    /// This value carried at `extra` more bits (MPFR), or unchanged (f64,
    /// which cannot; see [`Real::CAN_RAISE_PRECISION`]).
    fn raised(&self, _extra: u32) -> Self {
        self.clone()
    }
    /// This value rounded to `prec` bits (identity for f64).
    fn rounded_to(&self, _prec: u32) -> Self {
        self.clone()
    }
    /// Magnitude below which values lose relative precision to underflow
    /// (f64: 2⁻¹⁰²² / eps ≈ 1.0·10⁻²⁹²; MPFR: 0, its exponent range is vast).
    fn underflow_floor(&self) -> Self {
        self.lit(0.0)
    }
    /// The larger of the two; `self` when they are equal or `other` is NaN.
    fn max_of(self, other: Self) -> Self {
        if other > self {
            other
        } else {
            self
        }
    }
    /// The smaller of the two; `self` when they are equal or `other` is NaN.
    fn min_of(self, other: Self) -> Self {
        if other < self {
            other
        } else {
            self
        }
    }
}

impl Real for f64 {
    const CAN_RAISE_PRECISION: bool = false;
    fn prec(&self) -> u32 {
        f64::MANTISSA_DIGITS
    }
    fn lit(&self, v: f64) -> Self {
        v
    }
    fn underflow_floor(&self) -> Self {
        f64::MIN_POSITIVE / f64::EPSILON
    }
    fn powi_like(&self, k: i32) -> Self {
        2f64.powi(k)
    }
    fn pi(&self) -> Self {
        std::f64::consts::PI
    }
    fn euler_gamma(&self) -> Self {
        0.577_215_664_901_532_9
    }
    fn to_f64(&self) -> f64 {
        *self
    }
    fn is_finite(&self) -> bool {
        f64::is_finite(*self)
    }
    fn abs(&self) -> Self {
        f64::abs(*self)
    }
    fn sqrt(&self) -> Self {
        f64::sqrt(*self)
    }
    fn exp(&self) -> Self {
        f64::exp(*self)
    }
    fn ln(&self) -> Self {
        f64::ln(*self)
    }
    fn ln_1p(&self) -> Self {
        f64::ln_1p(*self)
    }
    fn exp_m1(&self) -> Self {
        f64::exp_m1(*self)
    }
    fn atan(&self) -> Self {
        f64::atan(*self)
    }
    fn sin(&self) -> Self {
        f64::sin(*self)
    }
    fn cos(&self) -> Self {
        f64::cos(*self)
    }
    fn asin(&self) -> Self {
        f64::asin(*self)
    }
    fn acos(&self) -> Self {
        f64::acos(*self)
    }
    fn sinh(&self) -> Self {
        f64::sinh(*self)
    }
    fn cosh(&self) -> Self {
        f64::cosh(*self)
    }
    fn tanh(&self) -> Self {
        f64::tanh(*self)
    }
}

#[cfg(feature = "mpfr")]
impl Real for Float {
    const CAN_RAISE_PRECISION: bool = true;
    fn raised(&self, extra: u32) -> Self {
        Float::with_val(Float::prec(self) + extra, self)
    }
    fn rounded_to(&self, prec: u32) -> Self {
        Float::with_val(prec, self)
    }
    fn prec(&self) -> u32 {
        Float::prec(self)
    }
    fn lit(&self, v: f64) -> Self {
        Float::with_val(Float::prec(self), v)
    }
    fn powi_like(&self, k: i32) -> Self {
        Float::with_val(Float::prec(self), Float::i_exp(1, k))
    }
    fn pi(&self) -> Self {
        Float::with_val(Float::prec(self), Constant::Pi)
    }
    fn euler_gamma(&self) -> Self {
        Float::with_val(Float::prec(self), Constant::Euler)
    }
    fn to_f64(&self) -> f64 {
        Float::to_f64(self)
    }
    fn to_f64_up(&self) -> f64 {
        Float::to_f64_round(self, rug::float::Round::Up)
    }
    fn is_finite(&self) -> bool {
        Float::is_finite(self)
    }
    fn abs(&self) -> Self {
        self.clone().abs()
    }
    fn sqrt(&self) -> Self {
        self.clone().sqrt()
    }
    fn exp(&self) -> Self {
        self.clone().exp()
    }
    fn ln(&self) -> Self {
        self.clone().ln()
    }
    fn ln_1p(&self) -> Self {
        self.clone().ln_1p()
    }
    fn exp_m1(&self) -> Self {
        self.clone().exp_m1()
    }
    fn atan(&self) -> Self {
        self.clone().atan()
    }
    fn sin(&self) -> Self {
        self.clone().sin()
    }
    fn cos(&self) -> Self {
        self.clone().cos()
    }
    fn asin(&self) -> Self {
        self.clone().asin()
    }
    fn acos(&self) -> Self {
        self.clone().acos()
    }
    fn sinh(&self) -> Self {
        self.clone().sinh()
    }
    fn cosh(&self) -> Self {
        self.clone().cosh()
    }
    fn tanh(&self) -> Self {
        self.clone().tanh()
    }
    fn is_zero(&self) -> bool {
        Float::is_zero(self)
    }
}
