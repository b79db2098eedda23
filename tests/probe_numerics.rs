//! The numerical items of issue 11's adversarial probe, re-run through the
//! CLI: each ends in a correct result with a bar, or a clear error and a
//! non-zero exit with nothing on standard output; none hangs (each command
//! here finishes in seconds; the old behaviour is in each test's comment).

use std::process::{Command, Output};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mcrt-noise")).args(args).output().expect("the binary runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The value printed after `= ` on the first line of `kernel`'s output, and its bar.
fn kernel_value(args: &[&str]) -> (f64, f64) {
    let out = run(&[&["kernel"], args].concat());
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    let text = stdout(&out);
    let value: f64 = text.lines().next().unwrap().rsplit("= ").next().unwrap().trim().parse().unwrap();
    let bar: f64 = text.lines().nth(1).unwrap().split_whitespace().nth(2).unwrap().parse().unwrap();
    (value, bar)
}

/// Was `I = 0 ± 2.9e−290` (exit 0) for ϑ = 1e−100, 1e−200, 1e−300 and at
/// 128 bits; the limit is π/(2c) with c = 1 + |cos ϑ|.
#[test]
fn kernel_near_the_pole_is_pi_over_4() {
    for theta in ["1e-100", "1e-200", "1e-300"] {
        let (v, bar) = kernel_value(&["--theta", theta, "--radius", "0.001"]);
        assert!((v - std::f64::consts::FRAC_PI_4).abs() <= bar + 1e-15, "ϑ = {theta}: {v} ± {bar:e}");
    }
    let (v, bar) = kernel_value(&["--theta", "1e-100", "--radius", "0.001", "--precision", "128"]);
    assert!((v - std::f64::consts::FRAC_PI_4).abs() <= bar + 1e-16, "128 bits: {v} ± {bar:e}");
}

/// Was `I = 0` for R = 1e100; the limit is π/(2(1 + cos 1)) = 1.0198.
#[test]
fn kernel_with_a_huge_radius_is_pi_over_2c() {
    let (v, bar) = kernel_value(&["--theta", "1", "--radius", "1e100"]);
    let limit = std::f64::consts::PI / (2.0 * (1.0 + 1f64.cos()));
    assert!((v - limit).abs() <= bar + 1e-15, "{v} ± {bar:e} vs {limit}");
}

/// Each of these hung (refinement loop of the check rule at 50–53 bits; the
/// kernel at π in 128 bits sampled e^{−ct} out to t ~ 10³⁶).
#[test]
fn the_precisions_that_hung_finish() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic.toml");
    for bits in ["50", "51", "52", "53"] {
        let out = run(&["oracle", scene, "--precision", bits]);
        assert!(out.status.success(), "{bits} bits: {}", String::from_utf8_lossy(&out.stderr));
        assert!(stdout(&out).contains("mean luminance"));
    }
    kernel_value(&["--theta", "1", "--radius", "0.001", "--precision", "53", "--rel-tol", "1e-6"]);
    let (v, bar) = kernel_value(&["--theta", "pi", "--radius", "0.001", "--precision", "128"]);
    assert!((v - std::f64::consts::FRAC_PI_4).abs() <= bar + 1e-16, "{v} ± {bar:e}");
}

fn scene_with(replace: &str, with: &str) -> std::path::PathBuf {
    let text = include_str!("../scenes/point-isotropic.toml");
    assert!(text.contains(replace));
    let dir = std::env::temp_dir().join(format!("mcrt-noise-probe-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{:x}.toml", text.len() + with.len() * 31 + replace.len() * 7));
    std::fs::write(&path, text.replace(replace, with)).unwrap();
    path
}

/// Was `mean 0 ± 0`, `relative noise inf`, `ratio NaN ± NaN` with exit 0.
/// These three are now outside the scene's bounds: refused by validation,
/// the field named, exit 2.
#[test]
fn results_outside_f64_are_refused_not_printed() {
    for (replace, with, field) in [
        ("position = [1.0, 0.0, 1.0]", "position = [800.0, 0.0, 1.0]", "lights[0].position"),
        ("flux = 1.0", "flux = 1e-300", "lights[0].flux"),
        ("radius = 0.01", "radius = 1e300", "estimator.radius"),
    ] {
        let path = scene_with(replace, with);
        let out = run(&["oracle", path.to_str().unwrap()]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{with}: {}{err}", stdout(&out));
        assert!(out.stdout.is_empty(), "{with}: printed {}", stdout(&out));
        assert!(!err.contains("NaN ±") && err.contains(field), "{with}: {err}");
    }
}

/// A scene inside every bound (σ_ext = 1e-10, flux 1e-10, the light at
/// optical distance 599 of the allowed 600) whose Var L, ≈ 7e-330, is below
/// the smallest double. Printed `Var L 0 ± 0`, `(23) exact 0 ± 0`, the §4.4
/// relative noise `± NaN` and `D4 0 ± NaN` with exit 0 until this test; now
/// refused as not representable in f64, a computed failure: exit 1.
#[test]
fn a_variance_that_underflows_is_not_representable_exit_1() {
    let text = include_str!("../scenes/point-isotropic.toml")
        .replace("position = [1.0, 0.0, 1.0]", "position = [5.99e12, 0.0, 5.99e10]")
        .replace("sigma_ext = 1.0", "sigma_ext = 1e-10")
        .replace("flux = 1.0", "flux = 1e-10")
        .replace("radius = 0.01", "radius = 1e8");
    let path = std::env::temp_dir().join(format!("mcrt-noise-probe-underflow-{}.toml", std::process::id()));
    std::fs::write(&path, text).unwrap();
    let out = run(&["oracle", path.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{}{err}", stdout(&out));
    assert!(out.stdout.is_empty(), "printed {}", stdout(&out));
    assert!(err.contains("not representable in f64: Var L (small-sphere) is 0e0") && err.contains("flux"), "{err}");
}

/// A budget of 1000 evaluations: NOT CONVERGED naming the budget, a computed
/// failure (exit 1; it was exit 2, the code of a typo); the budget's flags
/// out of range are usage (exit 2).
#[test]
fn an_oracle_run_over_its_budget_says_so() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic.toml");
    let out = run(&["oracle", scene, "--max-evals", "1000"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("NOT CONVERGED") && err.contains("evaluation budget of 1000"), "{err}");
    let out = run(&["oracle", scene, "--max-evals=-5"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--max-evals"));
    let out = run(&["oracle", scene, "--time-limit", "0"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--time-limit"));
}

/// `scenes/point-isotropic-order1.toml` (single-scattered light) with 50
/// point lights on a spiral around the camera ray instead of one, written
/// to a temporary file named with `tag`.
fn fifty_lights_order_one(tag: &str) -> std::path::PathBuf {
    let text = include_str!("../scenes/point-isotropic-order1.toml");
    let (head, rest) = text.split_at(text.find("[[lights]]").unwrap());
    let tail = &rest[rest.find("[camera]").unwrap()..];
    let mut lights = String::new();
    for i in 0..50 {
        let a = 2.0 * std::f64::consts::PI * f64::from(i) / 50.0;
        let rho = 0.5 + 0.02 * f64::from(i);
        let (x, y, z) = (a.cos() * rho, a.sin() * rho, 0.5 + 0.05 * f64::from(i));
        lights.push_str(&format!("[[lights]]\nkind = \"point\"\nposition = [{x:.6}, {y:.6}, {z:.6}]\nflux = 1.0\n\n"));
    }
    let path = std::env::temp_dir().join(format!("mcrt-noise-probe-fifty-{tag}-{}.toml", std::process::id()));
    std::fs::write(&path, format!("{head}{lights}{tail}")).unwrap();
    path
}

/// Runs the binary, killing it after `seconds`; `None` if it was still running.
fn run_within(args: &[&str], seconds: f64) -> Option<(Output, f64)> {
    use std::process::Stdio;
    let start = std::time::Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_mcrt-noise"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    while child.try_wait().unwrap().is_none() {
        if start.elapsed().as_secs_f64() >= seconds {
            child.kill().ok();
            child.wait().ok();
            return None;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let secs = start.elapsed().as_secs_f64();
    Some((child.wait_with_output().unwrap(), secs))
}

/// A result with bars (exit 0), or NOT CONVERGED naming `limit` (exit 1) and nothing on stdout.
fn assert_result_or_not_converged(out: &Output, limit: &str) {
    let (text, err) = (stdout(out), String::from_utf8_lossy(&out.stderr));
    match out.status.code() {
        Some(0) => assert!(text.contains("mean luminance") && text.contains(" ± "), "{text}"),
        Some(1) => {
            assert!(out.stdout.is_empty(), "printed {text}");
            assert!(err.contains("NOT CONVERGED") && err.contains(limit), "{limit:?} not in {err}");
        }
        code => panic!("exit {code:?}: {text}{err}"),
    }
}

/// 50 point lights with single scattering: ran past 120 s with no progress
/// or estimate (the probe's stall: every nested level had its own budget).
/// Now the run's one budget ends it loudly. With the old default budget
/// (2·10⁹ evaluations) it ended as NOT CONVERGED after 57 s on 2 idle
/// cores in a release build (112 s of CPU), 90–98 s on a shared machine:
/// past the 60 s, hence today's default of 10⁹. This test gives it a
/// budget and a deadline of its own, each ending it within about two
/// seconds; the default budget is the ignored test below.
#[test]
fn fifty_point_lights_with_single_scattering_end_within_the_budget() {
    let scene = fifty_lights_order_one("limits");
    let scene = scene.to_str().unwrap();
    for (flags, limit) in
        [(["--max-evals", "20000000"], "evaluation budget of 20000000"), (["--time-limit", "2"], "time limit of 2 s")]
    {
        let (out, secs) = run_within(&[&["oracle", scene][..], &flags[..]].concat(), 60.0)
            .unwrap_or_else(|| panic!("{flags:?}: still running after 60 s"));
        assert_result_or_not_converged(&out, limit);
        assert!(secs < 30.0, "{flags:?}: {secs:.1} s");
    }
}

/// CPU seconds (user + system) of every child process ended so far.
#[cfg(unix)]
fn children_cpu_seconds() -> f64 {
    // SAFETY: getrusage writes one plain struct, which we own.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage) };
    let secs = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    secs(usage.ru_utime) + secs(usage.ru_stime)
}

/// The same scene with the default budget (10⁹ evaluations): a result with
/// bars or NOT CONVERGED naming the budget, in the time its evaluations
/// take. The budget is a count, so its time is the machine's: the README
/// said "within 60 s, ~30 s on 2 cores (1 CPU-min)", and the outside probe
/// (item 16) measured 68 s wall, 131 CPU-s on its machine. Measured here
/// (2 cores shared with another engineer's runs, load ~3.4): 45–49 s wall,
/// 51–53 CPU-s, before and after the budget checks within a step; 10⁸
/// evaluations 5.3 s, 3·10⁸ 15.2 s: linear in the evaluations. So the
/// bound is derived from a run of a tenth of the budget on the same
/// machine: 10 times its time, with a factor 1.5 for the cost per
/// evaluation varying between the integrals and for the machine's load
/// changing between the two runs.
#[test]
#[ignore = "about a minute on 2 cores; run by name (README.md, Tests)"]
fn fifty_point_lights_with_single_scattering_default_budget() {
    let scene = fifty_lights_order_one("default");
    let scene = scene.to_str().unwrap();
    let timed = |args: &[&str]| {
        let cpu0 = children_cpu_seconds();
        let (out, secs) = run_within(args, 600.0).unwrap_or_else(|| panic!("{args:?}: still running after 600 s"));
        (out, secs, children_cpu_seconds() - cpu0)
    };
    let (tenth, tenth_secs, tenth_cpu) = timed(&["oracle", scene, "--max-evals", "100000000"]);
    assert_result_or_not_converged(&tenth, "evaluation budget of 100000000");
    let (out, secs, cpu) = timed(&["oracle", scene]);
    eprintln!(
        "10⁸ evaluations: {tenth_secs:.1} s wall, {tenth_cpu:.1} CPU-s; the default 10⁹: {secs:.1} s wall, {cpu:.1} CPU-s"
    );
    assert_result_or_not_converged(&out, "evaluation budget of 1000000000");
    assert!(secs <= 1.5 * 10.0 * tenth_secs, "{secs:.1} s for 10⁹ evaluations, {tenth_secs:.1} s for 10⁸");
}

/// Issue 11's re-probe. `kernel --precision 1000` ran past 70 s, even at
/// `--rel-tol 1e-6`: the tanh–sinh table was built to level 7 + (p − 53)/48
/// = 26 in advance (2²⁶ nodes per panel). Levels are now built on first
/// use, capped at 8 + ⌈log₂(p/53)⌉; both runs end in seconds and agree
/// with the 1100-bit series reference within their bars.
#[test]
fn the_kernel_at_1000_and_1024_bits_ends_and_is_right() {
    use mcrt_noise::kernel::{kernel_series_reference, parse_decimal};
    use rug::Float;
    let theta = Float::with_val(1100, 1);
    let reference =
        kernel_series_reference(&theta.clone().sin(), &theta.cos().abs(), &parse_decimal("1e-3", 1100).unwrap(), 1100);
    for args in [&["--precision", "1000"][..], &["--precision", "1000", "--rel-tol", "1e-6"], &["--precision", "1024"]]
    {
        let all = [&["kernel", "--theta", "1", "--radius", "0.001"][..], args].concat();
        let (out, secs) = run_within(&all, 60.0).unwrap_or_else(|| panic!("{args:?}: still running after 60 s"));
        assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
        let text = stdout(&out);
        let value = Float::with_val(
            1100,
            Float::parse(text.lines().next().unwrap().rsplit("= ").next().unwrap().trim()).unwrap(),
        );
        let bar: f64 = text.lines().nth(1).unwrap().split_whitespace().nth(2).unwrap().parse().unwrap();
        let off = Float::with_val(1100, &value - &reference).abs().to_f64();
        assert!(off <= bar && bar <= 1e-6 * 1.6e-3, "{args:?}: off by {off:e}, bar {bar:e} ({secs:.1} s)");
    }
}

/// Beyond 1024 bits the default tolerance 2^{−(bits−22)} underflowed f64
/// and every integral was refused as "NOT CONVERGED: tolerances rel 0"
/// (exit 1, at 2048 and 4096 bits): such precisions are now usage, named
/// with the range and the reason.
#[test]
fn precisions_beyond_1024_bits_are_refused_as_usage() {
    for cmd in [&["kernel", "--theta", "1", "--radius", "0.001"][..], &["oracle", "scenes/point-isotropic.toml"]] {
        let out = Command::new(env!("CARGO_BIN_EXE_mcrt-noise"))
            .args([cmd, &["--precision", "2048"]].concat())
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{cmd:?}: {err}");
        assert!(err.contains("--precision") && err.contains("[32, 1024]"), "{err}");
    }
}

/// `sweep` had no budget: on the order-1 scene it ran 112 s before
/// printing. Its radii now share one budget; a small one ends it loudly
/// (exit 1, naming the budget, nothing on standard output).
#[test]
fn a_sweep_shares_one_budget_over_its_radii() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic-order1.toml");
    let (out, secs) = run_within(&["sweep", scene, "--max-evals", "10000000"], 60.0)
        .unwrap_or_else(|| panic!("still running after 60 s"));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{}{err}", stdout(&out));
    assert!(out.stdout.is_empty() && err.contains("evaluation budget of 10000000"), "{err}");
    assert!(secs < 30.0, "{secs:.1} s");
}

/// Negative or fractional budget flags were clap's "unexpected argument
/// '-1' found" for `--max-evals -1` (no flag, no range); now every budget
/// flag of `oracle`, `kernel` and `sweep` names itself and its range.
#[test]
fn budget_flags_out_of_range_name_the_flag_and_the_range() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic.toml");
    let kernel = ["kernel", "--theta", "1", "--radius", "0.001"];
    for cmd in [&["oracle", scene][..], &kernel, &["sweep", scene]] {
        for (flag, value, range) in [
            ("--max-evals", "-1", "[1, 1e15]"),
            ("--max-evals", "1.5", "whole number"),
            ("--time-limit", "-1", "(0, 1e6]"),
            ("--time-limit", "0", "(0, 1e6]"),
        ] {
            let out = run(&[cmd, &[flag, value]].concat());
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{cmd:?} {flag} {value}: {err}");
            assert!(err.contains(flag) && err.contains(range), "{cmd:?} {flag} {value}: {err}");
        }
    }
}

/// 200 000 point lights (which the tracer traces in a second) ran the
/// oracle past its deadline by 40 s: its cost grows as the square of the
/// light count, which no evaluation count bounds. Refused up front, naming
/// `lights` and the bound (exit 2).
#[test]
fn more_lights_than_the_oracle_takes_are_refused_by_name() {
    let text = include_str!("../scenes/point-isotropic.toml");
    let (head, rest) = text.split_at(text.find("[[lights]]").unwrap());
    let tail = &rest[rest.find("[camera]").unwrap()..];
    let lights: String = (0..=mcrt_noise::oracle::MAX_LIGHTS)
        .map(|i| format!("[[lights]]\nkind = \"point\"\nposition = [1.0, {:.3}, 1.0]\nflux = 1.0\n\n", i as f64 * 0.01))
        .collect();
    let path = std::env::temp_dir().join(format!("mcrt-noise-probe-many-lights-{}.toml", std::process::id()));
    std::fs::write(&path, format!("{head}{lights}{tail}")).unwrap();
    let (out, _) = run_within(&["oracle", path.to_str().unwrap()], 60.0).expect("refused at once");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(out.stdout.is_empty() && err.contains("lights: 101 lights") && err.contains("at most 100"), "{err}");
}

/// The outside probe, item 6: `kernel --theta 1 --radius 0.001 --max-evals 1`
/// printed I (exit 0) after 128 evaluations: the series path's quadrature
/// met its goal at its first step, where the budget was never looked at.
/// A result that needed more than its budget is a computed failure naming
/// the budget (exit 1, nothing on standard output); the same computation
/// with the evaluations it needs (128) prints its value.
#[test]
fn the_kernel_honours_its_evaluation_budget_on_every_path() {
    let base = ["kernel", "--theta", "1", "--radius", "0.001"];
    for (path, budget) in [(&[][..], "1"), (&[][..], "127"), (&["--nested"][..], "1")] {
        let out = run(&[&base[..], path, &["--max-evals", budget]].concat());
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{path:?} {budget}: {}{err}", stdout(&out));
        assert!(out.stdout.is_empty(), "{path:?}: printed {}", stdout(&out));
        assert!(err.contains("NOT CONVERGED") && err.contains(&format!("evaluation budget of {budget} ")), "{err}");
    }
    let out = run(&[&base[..], &["--max-evals", "128"]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout(&out).contains("evaluations 128 "), "{}", stdout(&out));
}

/// The outside probe, item 3: `oracle --precision 1024 --time-limit 5` ran
/// 48 s (90 s on a busier machine) before saying the limit was spent: the
/// deadline was looked at between refinement steps only, and one step of
/// the check rule (512 nodes per panel at 1024 bits, each an inner
/// integral) takes tens of seconds. Now every level looks every 256 calls
/// (7.1 s wall for a 5 s limit on the shared 2-core machine, 2.2 s for 1 s).
/// The bound: the limit, plus one batch of 256 calls at each level and the
/// Gauss–Legendre nodes (~0.5 s at 1024 bits) being built when it passed,
/// with a factor 3 for a loaded machine: 2 s + 3 × 2 s.
#[test]
fn the_oracle_at_1024_bits_ends_near_its_deadline() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic.toml");
    let (out, secs) = run_within(&["oracle", scene, "--precision", "1024", "--time-limit", "2"], 60.0)
        .unwrap_or_else(|| panic!("still running after 60 s"));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{}{err}", stdout(&out));
    assert!(out.stdout.is_empty() && err.contains("time limit of 2 s"), "{err}");
    assert!(secs <= 2.0 + 3.0 * 2.0, "{secs:.1} s");
}

/// The outside probe, item 7: `kernel --theta 1 --radius 1e-200 --precision
/// 1024` printed `error bar 0.000e0`: the bar, 2.8e-507 (a relative 2^-1018
/// of I ≈ 1.6e-200), was converted to f64, where it underflows. It is now
/// printed at the working precision: positive, and a bound on the distance
/// to the 1100-bit series reference.
#[test]
fn the_kernel_bar_at_1024_bits_is_positive_and_bounds_the_error() {
    use mcrt_noise::kernel::{kernel_series_reference, parse_decimal};
    use rug::Float;
    let theta = Float::with_val(1100, 1);
    let r = parse_decimal("1e-200", 1100).unwrap();
    let reference = kernel_series_reference(&theta.clone().sin(), &theta.cos().abs(), &r, 1100);
    let out = run(&["kernel", "--theta", "1", "--radius", "1e-200", "--precision", "1024"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = stdout(&out);
    let value = text.lines().next().unwrap().rsplit("= ").next().unwrap().trim();
    let bar = text.lines().nth(1).unwrap().split_whitespace().nth(2).unwrap();
    let parse = |s: &str| Float::with_val(1100, Float::parse(s).unwrap_or_else(|e| panic!("{s:?}: {e}")));
    let (value, bar) = (parse(value), parse(bar));
    assert!(bar > 0, "error bar {bar} in\n{text}");
    let off = Float::with_val(1100, &value - &reference).abs();
    assert!(off <= bar, "off by {off:e}, bar {bar:e}");
}

/// The "unreliable best guess V ± E" of an oracle failure message.
fn best_guess(err: &str) -> (f64, f64) {
    let tail = err.split("unreliable best guess ").nth(1).unwrap_or_else(|| panic!("no best guess in {err}"));
    let mut words = tail.split_whitespace();
    let value: f64 = words.next().unwrap().parse().unwrap();
    assert_eq!(words.next(), Some("±"), "{err}");
    let error: f64 = words.next().unwrap().trim_end_matches(')').parse().unwrap();
    (value, error)
}

/// The outside probe, item 8: NOT CONVERGED messages printed the best guess
/// of the model's internal scaling, times e^{c₀} (c₀ = σ_ext × the shortest
/// light path via the camera ray): 4.57e-3 for a mean of 1.11e-3 on the
/// README scene, 5.6e-8 for 2.9e-138 with the light 300 mean free paths
/// away. The guess is now in the report's units: with a budget too small
/// to finish, it lies within its own error estimate (plus the converged
/// bar and the 7 printed digits) of the converged small-sphere mean.
#[test]
fn a_not_converged_best_guess_is_in_the_reports_units() {
    let far = scene_with("position = [1.0, 0.0, 1.0]", "position = [300.0, 0.0, 1.0]");
    let readme = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic.toml");
    for (scene, budget) in [(readme, "1000"), (far.to_str().unwrap(), "1")] {
        let out = run(&["oracle", scene, "--json"]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let mean = v.pointer("/mean_luminance/value").and_then(|x| x.as_f64()).unwrap();
        let bar = v.pointer("/mean_luminance/error").and_then(|x| x.as_f64()).unwrap();
        let out = run(&["oracle", scene, "--max-evals", budget]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert!(err.contains("mean luminance (15): NOT CONVERGED"), "{err}");
        let (guess, estimate) = best_guess(&err);
        let printed = 5e-7 * guess.abs();
        assert!(
            (guess - mean).abs() <= estimate + bar + printed,
            "{scene}: guess {guess:e} ± {estimate:e}, mean {mean:e}"
        );
    }
}

/// The outside probe, item 4: a beam of radius 1e-10 or 1e-9 whose axis
/// crosses the camera ray at right angles (`scenes/beam-isotropic.toml`
/// with `radius` changed): `oracle` said the camera ray passes outside
/// every light (exit 2, after 11–37 s) while the tracer measures L = 0.200
/// ± 0.004. The ray–beam chord was found from a quadratic whose constant
/// |w|² − a² rounded to |w|² = 1 (`model::field::beam_interval`). The beam
/// is now met: the oracle computes, here ending as NOT CONVERGED (the
/// small-sphere model's W = Φ/(πa²) on a chord of 2a is a spike it does
/// not resolve within the budget; exit 1), never "no light".
#[test]
fn a_thin_beam_crossing_the_camera_ray_is_not_declared_dark() {
    for radius in ["1e-10", "1e-9"] {
        let text = include_str!("../scenes/beam-isotropic.toml").replace("radius = 0.5", &format!("radius = {radius}"));
        let path =
            std::env::temp_dir().join(format!("mcrt-noise-probe-thin-beam-{radius}-{}.toml", std::process::id()));
        std::fs::write(&path, text).unwrap();
        let scene = path.to_str().unwrap();
        let out = run(&["trace", scene, "--trials", "20000", "--json"]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let mean = v.pointer("/mean/value").and_then(|x| x.as_f64()).unwrap();
        assert!(mean > 0.0, "the tracer measures light: {mean}");
        let out = run(&["oracle", scene, "--max-evals", "10000000"]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("outside every light") && !err.contains("meets no light"), "{radius}: {err}");
        assert_result_or_not_converged(&out, "evaluation budget of 10000000");
    }
}
