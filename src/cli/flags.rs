//! The numeric flags' ranges, in one place: clap value parsers that refuse
//! a value outside its range with the value and the range named (clap adds
//! the flag and exits 2). Ranges: `docs/scene-format.md`, "Command-line flags".

/// `--rel-tol` in [1e-30, 0.1]: looser than 10 % is no error bar; 1e-30
/// is about 100 bits of MPFR (a tolerance tighter than the working
/// precision's rounding is attempted and reported as NOT CONVERGED).
pub const REL_TOL: (f64, f64) = (1e-30, 0.1);
/// `kernel --radius` (R in units of 1/σ_ext): the kernel is computed at any R (its far edge by analysis, `kernel.rs`); below 1e-200 its value ~R falls under the engine's absolute floor.
pub const KERNEL_RADIUS: (f64, f64) = (1e-200, 1e300);
/// `--max-evals` in [1, 10¹⁵] (a whole number).
pub const MAX_EVALS: (f64, f64) = (1.0, 1e15);
/// `--time-limit` in (0, 10⁶] seconds.
pub const TIME_LIMIT: (f64, f64) = (0.0, 1e6);
/// `--threads` in [1, 1024].
pub const THREADS: (usize, usize) = (1, 1024);
/// `accuracy --points` in [1, 10⁷].
pub const POINTS: (usize, usize) = (1, 10_000_000);
/// `cost --repeats` in [1, 10⁴].
pub const REPEATS: (usize, usize) = (1, 10_000);

/// `x` in its shorter form, plain or with an exponent (`1e-300`, `0.5`).
fn short(x: f64) -> String {
    let (plain, exp) = (format!("{x}"), format!("{x:e}"));
    if exp.len() < plain.len() {
        exp
    } else {
        plain
    }
}

fn closed(text: &str, (lo, hi): (f64, f64)) -> Result<f64, String> {
    let v: f64 = text.trim().parse().map_err(|_| format!("{text:?} is not a number"))?;
    if (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(format!("{} is outside [{}, {}]", text.trim(), short(lo), short(hi)))
    }
}

fn count(text: &str, (lo, hi): (usize, usize)) -> Result<usize, String> {
    let v: usize = text.trim().parse().map_err(|_| format!("{text:?} is not an integer in [{lo}, {hi}]"))?;
    if (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(format!("{v} is outside [{lo}, {hi}]"))
    }
}

/// `--rel-tol`.
pub fn rel_tol(text: &str) -> Result<f64, String> {
    closed(text, REL_TOL)
}

/// `--max-evals`: a whole number of evaluations in [1, 1e15].
pub fn max_evals(text: &str) -> Result<u64, String> {
    let v = closed(text, MAX_EVALS)?;
    if v.fract() != 0.0 {
        return Err(format!("{} is not a whole number in [1, 1e15]", text.trim()));
    }
    Ok(v as u64)
}

/// `--time-limit`: seconds in (0, 1e6].
pub fn time_limit(text: &str) -> Result<f64, String> {
    match closed(text, TIME_LIMIT) {
        Ok(v) if v > 0.0 => Ok(v),
        Ok(_) | Err(_) if text.trim().parse::<f64>().is_ok() => {
            Err(format!("{} is outside (0, 1e6] seconds", text.trim()))
        }
        other => other,
    }
}

/// `optimize --budget`: seconds in (0, 1e9].
pub fn budget_seconds(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v > 0.0 && v <= 1e9 => Ok(v),
        Ok(_) => Err(format!("{} is outside (0, 1e9] seconds", text.trim())),
        Err(_) => Err(format!("{text:?} is not a number of seconds")),
    }
}

/// `optimize --max-spheres`: a count in [1, 1e7] (the scene's bound on N_B/q).
pub fn max_spheres(text: &str) -> Result<f64, String> {
    closed(text, (1.0, mcrt_scene::limits::MAX_SPHERES_PER_ITERATION))
}

/// `optimize --radius-range LO,HI`: two radii in one argument (so that a
/// negative `-1,2` is named with the flag, not taken for a flag itself),
/// LO < HI, both finite and > 0. Their bound, σ_ext·R in [1e-12, 1e3], is
/// the scene's (`tuning::optimize` checks it with the scene).
pub fn radius_range(text: &str) -> Result<(f64, f64), String> {
    let bad = |why: &str| format!("{} {why}; give LO,HI with 0 < LO < HI, e.g. 1e-3,0.5", text.trim());
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let [lo, hi] = parts[..] else {
        return Err(bad(&format!("is {} value(s), not two radii", parts.len())));
    };
    let number = |t: &str| t.parse::<f64>().map_err(|_| bad(&format!("has {t:?}, not a number")));
    let (lo, hi) = (number(lo)?, number(hi)?);
    if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && lo < hi) {
        return Err(bad("is not a range of radii"));
    }
    Ok((lo, hi))
}

/// `--threads`.
pub fn threads(text: &str) -> Result<usize, String> {
    count(text, THREADS)
}

/// `trace --seed`, `compare --seed`: any u64.
pub fn seed(text: &str) -> Result<u64, String> {
    text.trim().parse().map_err(|_| format!("{text:?} is not an integer in [0, {}]", u64::MAX))
}

/// `accuracy --points`.
pub fn points(text: &str) -> Result<usize, String> {
    count(text, POINTS)
}

/// `cost --repeats`.
pub fn repeats(text: &str) -> Result<usize, String> {
    count(text, REPEATS)
}

/// `trace --radius`, `compare --radius`: finite and > 0 here; its bound in
/// units of 1/σ_ext is the scene's (`estimator.radius`), checked with the scene.
pub fn positive(text: &str) -> Result<f64, String> {
    let v: f64 = text.trim().parse().map_err(|_| format!("{text:?} is not a number"))?;
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(format!("{} is outside (0, ∞): must be finite and > 0", text.trim()))
    }
}

/// Plain decimal syntax: an optional sign, digits with at most one point
/// (at least one digit), an optional exponent `e`/`E` with an optional sign
/// and digits. MPFR's parser, which reads the kernel's flags at the working
/// precision, also takes `8@0` (exponent `@`), `7_0` (separators),
/// `0x1p3` and the like: a value written so was computed without any range
/// check (`--theta 8@0` ran at ϑ = 8).
pub fn is_plain_decimal(text: &str) -> bool {
    let t = text.trim();
    let t = t.strip_prefix(['+', '-']).unwrap_or(t);
    let (mantissa, exponent) = match t.find(['e', 'E']) {
        Some(i) => (&t[..i], Some(&t[i + 1..])),
        None => (t, None),
    };
    let digits = |s: &str| s.bytes().all(|b| b.is_ascii_digit());
    let (int, frac) = mantissa.split_once('.').unwrap_or((mantissa, ""));
    let mantissa_ok = digits(int) && digits(frac) && !(int.is_empty() && frac.is_empty());
    let exponent_ok = exponent.is_none_or(|e| {
        let e = e.strip_prefix(['+', '-']).unwrap_or(e);
        !e.is_empty() && digits(e)
    });
    mantissa_ok && exponent_ok
}

/// `kernel --theta` (`pi`, `pi/2` or a plain decimal), ϑ in (0, π] at the
/// working precision `bits` (`None`: f64); the kernel needs sin ϑ > 0.
pub fn check_theta(text: &str, bits: Option<u32>) -> Result<(), String> {
    let t = text.trim();
    if t == "pi" || t == "pi/2" {
        return Ok(());
    }
    let bad = || format!("--theta: {t} is outside (0, π] (radians; at ϑ = 0 the kernel has no edge)");
    let theta = decimal_at(text, "--theta", "0.5, pi/2 or pi", bits)?;
    let pi = rug::Float::with_val(theta.prec(), rug::float::Constant::Pi);
    if theta > 0 && theta <= pi {
        Ok(())
    } else {
        Err(bad())
    }
}

/// `kernel --radius` (a plain decimal), R in [1e-200, 1e300] at the
/// working precision `bits` (`None`: f64).
pub fn check_kernel_radius(text: &str, bits: Option<u32>) -> Result<(), String> {
    let (lo, hi) = KERNEL_RADIUS;
    let r = decimal_at(text, "--radius", "0.001 or 1e-3", bits)?;
    let at = |x: f64| mcrt_noise::kernel::parse_decimal(&short(x), r.prec()).expect("a bound parses");
    if r >= at(lo) && r <= at(hi) {
        Ok(())
    } else {
        Err(format!(
            "--radius: {} is outside [{}, {}] (R in units of 1/σ_ext; I(ϑ, R) ~ R as R → 0, and below 1e-200 it falls under the engine's absolute floor of ~3e-290)",
            text.trim(),
            short(lo),
            short(hi)
        ))
    }
}

/// A plain decimal `text` read at `bits` (53 for f64: rounded as `f64`'s
/// parser rounds), or why it is refused, naming `flag` with `examples`.
fn decimal_at(text: &str, flag: &str, examples: &str, bits: Option<u32>) -> Result<rug::Float, String> {
    let t = text.trim();
    if !is_plain_decimal(t) {
        return Err(format!(
            "{flag}: {t:?} is not a plain decimal number (digits with an optional point and exponent, e.g. {examples})"
        ));
    }
    mcrt_noise::kernel::parse_decimal(t, bits.unwrap_or(53)).map_err(|e| format!("{flag}: {e}"))
}
