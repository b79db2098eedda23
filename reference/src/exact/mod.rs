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

/// The largest |e| that [`from_hex`] accepts for 2^e, the unit of a
/// number's last digit, in either text form (2²⁰: any sum of the tracer's or
/// a renderer's powers lies far inside).
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
/// assert!(from_hex("0x1p-9223372036854775808").is_err()); // beyond ±2²⁰
/// assert_eq!(from_hex("1@-262144"), from_hex("0x1p-1048576")); // one bound for both forms
/// assert!(from_hex("1@-262145").is_err());
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
    // The exponent of the last digit's unit, in i128: no input overflows it.
    let (digits, exponent) = if let Some(c99) = body.strip_prefix("0x") {
        let (digits, exp) = c99.split_once('p').ok_or("no binary exponent (`p`)")?;
        (digits, parse_exponent(exp)?)
    } else {
        match body.split_once('@') {
            Some((digits, exp)) => (digits, 4 * parse_exponent(exp)?),
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
    let exponent = exponent - 4 * fraction.len() as i128;
    if exponent.unsigned_abs() > MAX_HEX_EXPONENT as u128 {
        return Err(format!("the last digit's unit is 2^{exponent}: its exponent must be within ±{MAX_HEX_EXPONENT}"));
    }
    let exponent = exponent as i64;
    let m = BigInt::parse_bytes(all.as_bytes(), 16).ok_or("not hexadecimal digits")?;
    Ok(Dyadic::new(if negative { -m } else { m }, exponent))
}

/// An exponent as written (any i64), widened so that scaling it cannot overflow.
fn parse_exponent(text: &str) -> Result<i128, String> {
    let e: i64 = text.parse().map_err(|_| format!("exponent \"{text}\" is not an integer"))?;
    Ok(i128::from(e))
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extreme_exponents_are_refused_not_wrapped() {
        for text in [
            "0x1p-9223372036854775808",
            "0x1.8p-9223372036854775808",
            "0x1p+9223372036854775807",
            "1@-9223372036854775808",
            "1@9223372036854775807",
            "0x1p-1048577",
        ] {
            let err = from_hex(text).unwrap_err();
            assert!(err.contains("within ±1048576"), "{text}: {err}");
        }
        assert!(from_hex("0x1p99999999999999999999").unwrap_err().contains("not an integer"));
        assert_eq!(from_hex("0x1p-1048576").unwrap().exponent(), -1048576);
    }

    #[test]
    fn shard_sums_with_extreme_exponents_are_refused() {
        let hex = ["0x1p-9223372036854775808", "0x1p+0", "0x1p+0", "0x1p+0"].map(String::from);
        let err = crate::moments::PowerSums::from_hex(4, &hex).unwrap_err();
        assert!(err.starts_with("sums[0] = \"0x1p-9223372036854775808\""), "{err}");
    }
}
