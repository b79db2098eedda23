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
/// Now the run's one budget ends it loudly. With the default budget (2·10⁹
/// evaluations) it ends as NOT CONVERGED after 57 s on 2 idle cores in a
/// release build (112 s of CPU), 90 s on a shared machine, 14.5 min in an
/// unoptimised `cargo build`: past the 60 s. So this test gives it a
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

/// The same scene with the default budget: a result with bars or NOT
/// CONVERGED naming the budget, within 120 s (57–90 s measured on 2 cores;
/// the issue asks for 60 s, which this budget meets only on idle cores).
#[test]
#[ignore = "about a minute on 2 cores; run by name (README.md, Tests)"]
fn fifty_point_lights_with_single_scattering_default_budget() {
    let scene = fifty_lights_order_one("default");
    let (out, secs) =
        run_within(&["oracle", scene.to_str().unwrap()], 120.0).unwrap_or_else(|| panic!("still running after 120 s"));
    eprintln!("ended in {secs:.1} s");
    assert_result_or_not_converged(&out, "evaluation budget of 2000000000");
}
