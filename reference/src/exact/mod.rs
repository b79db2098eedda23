//! Exact arithmetic for the power sums: [`ExactSum`] accumulates powers of
//! doubles without rounding (an integer superaccumulator), [`Dyadic`]
//! combines the sums exactly (products, differences) and rounds a quotient
//! or its square root once, correctly, to a double. Written here rather than
//! on MPFR so that neither the tracer nor the check needs GMP/MPFR; the big
//! integers are `num-bigint`'s.
//!
//! Text form (shard files): C99's hexadecimal floating point with as many
//! digits as the number has, `0x1.8p+1` = 3 ([`to_hex`]); [`from_hex`] also
//! reads the MPFR radix-16 form of earlier shard files (`3.`, `ff.8`,
//! `1.99a@-1` = 0x1.99a·16⁻¹).

mod dyadic;
mod sum;

pub use dyadic::Dyadic;
pub use sum::{ExactSum, Powers};

use num_bigint::{BigInt, BigUint};

/// The largest binary exponent, in magnitude, that [`from_hex`] accepts
/// (2²⁰: any sum of the tracer's or a renderer's powers lies far inside).
pub const MAX_HEX_EXPONENT: i64 = 1 << 20;

/// The largest number of hexadecimal digits [`from_hex`] accepts.
pub const MAX_HEX_DIGITS: usize = 1 << 14;

/// `x` in C99 hexadecimal floating point, exactly: `0x0p+0`, `0x1p-3`,
/// `-0x1.8p+1`.
///
/// ```
/// use mcrt_reference::exact::{from_hex, to_hex, Dyadic};
/// let x = Dyadic::from_f64(-3.0).unwrap();
/// assert_eq!(to_hex(&x), "-0x1.8p+1");
/// assert_eq!(from_hex(&to_hex(&x)), Ok(x));
/// assert_eq!(from_hex("ff.8"), Ok(Dyadic::from_f64(255.5).unwrap())); // MPFR's form
/// ```
pub fn to_hex(x: &Dyadic) -> String {
    if x.is_zero() {
        return "0x0p+0".into();
    }
    let sign = if x.is_negative() { "-" } else { "" };
    let m = x.mantissa().magnitude();
    let fraction_bits = m.bits() - 1;
    let exponent = x.exponent() + fraction_bits as i64;
    if fraction_bits == 0 {
        return format!("{sign}0x1p{exponent:+}");
    }
    let pad = (4 - fraction_bits % 4) % 4;
    let fraction = (m - (BigUint::from(1u32) << fraction_bits)) << pad;
    let digits = ((fraction_bits + pad) / 4) as usize;
    let text = format!("{fraction:0digits$x}");
    format!("{sign}0x1.{}p{exponent:+}", text.trim_end_matches('0'))
}

/// A number read from [`to_hex`]'s form or MPFR's radix-16 form (digits
/// with an optional point, then `@e` for ·16^e); the error says what is wrong.
pub fn from_hex(text: &str) -> Result<Dyadic, String> {
    let (negative, body) = match text.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, text),
    };
    let (digits, exponent) = if let Some(c99) = body.strip_prefix("0x") {
        let (digits, exp) = c99.split_once('p').ok_or("no binary exponent (`p`)")?;
        (digits, parse_exponent(exp)?)
    } else {
        match body.split_once('@') {
            Some((digits, exp)) => (digits, parse_exponent(exp)?.checked_mul(4).ok_or("exponent out of range")?),
            None => (body, 0),
        }
    };
    let (whole, fraction) = digits.split_once('.').unwrap_or((digits, ""));
    let all = format!("{whole}{fraction}");
    if all.is_empty() || !all.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err("not hexadecimal digits".into());
    }
    if all.len() > MAX_HEX_DIGITS {
        return Err(format!("{} hexadecimal digits: at most {MAX_HEX_DIGITS}", all.len()));
    }
    let exponent = exponent - 4 * fraction.len() as i64;
    if exponent.abs() > MAX_HEX_EXPONENT + 4 * MAX_HEX_DIGITS as i64 {
        return Err(format!("binary exponent {exponent}: must be within ±{MAX_HEX_EXPONENT}"));
    }
    let m = BigInt::parse_bytes(all.as_bytes(), 16).ok_or("not hexadecimal digits")?;
    Ok(Dyadic::new(if negative { -m } else { m }, exponent))
}

fn parse_exponent(text: &str) -> Result<i64, String> {
    let e: i64 = text.parse().map_err(|_| format!("exponent \"{text}\" is not an integer"))?;
    if e.abs() > MAX_HEX_EXPONENT {
        return Err(format!("exponent {e}: must be within ±{MAX_HEX_EXPONENT}"));
    }
    Ok(e)
}

impl ExactSum {
    /// The sum holding exactly `x`.
    pub fn from_dyadic(x: &Dyadic) -> ExactSum {
        let mut sum = ExactSum::default();
        let (sign, limbs) = x.mantissa().to_u64_digits();
        sum.add_term(&limbs, x.exponent(), sign == num_bigint::Sign::Minus);
        sum
    }
}
