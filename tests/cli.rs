//! The command-line interface: exit codes and messages.

use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_mcrt-noise"))
}

/// The command with `args`, run from the repository's root (so that the
/// bundled scenes are at `scenes/…`), and its output.
fn run_in_repo(args: &[&str]) -> std::process::Output {
    bin().args(args).current_dir(env!("CARGO_MANIFEST_DIR")).output().unwrap()
}

#[test]
fn validate_prints_normalised_scene_for_every_bundled_scene() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let out = bin().arg("validate").arg(&path).output().unwrap();
        assert!(out.status.success(), "{}: {}", path.display(), String::from_utf8_lossy(&out.stderr));
        let text = String::from_utf8(out.stdout).unwrap();
        assert!(text.contains("scattering_orders"), "{text}");
        assert!(mcrt_noise::scene::Scene::from_toml_str(&text).is_ok());
    }
}

#[test]
fn validate_reports_every_bad_field_and_exits_non_zero() {
    let dir = std::env::temp_dir().join(format!("mcrt-noise-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.toml");
    let good =
        std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/point-isotropic.toml"))
            .unwrap();
    std::fs::write(&path, good.replace("q = 0.5", "q = 1.5").replace("albedo = 0.8", "albedo = nan")).unwrap();
    let out = bin().arg("validate").arg(&path).output().unwrap();
    assert!(!out.status.success());
    assert!(out.stdout.is_empty(), "nothing but the error on bad input");
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("estimator.q = 1.5: must be in (0, 1]"), "{err}");
    assert!(err.contains("medium.albedo = NaN: must be in [0, 1]"), "{err}");
}

#[test]
fn kernel_command_reports_value_bar_and_cost() {
    let out = bin().args(["kernel", "--theta", "1", "--radius", "1e-3"]).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    let value: f64 = text.lines().next().unwrap().strip_prefix("I(1, 1e-3) = ").expect("value line").parse().unwrap();
    let reference: f64 = "1.5828197124289608462e-3".parse().unwrap(); // the issue's 20-digit reference
    assert!(((value - reference) / reference).abs() <= 1e-13, "{text}");
    assert!(text.contains("error bar") && text.contains("evaluations"), "{text}");
}

#[test]
fn unconverged_kernel_is_loud() {
    // A tolerance far below f64's rounding: the command must fail (a computed
    // failure, exit 1), not print a number.
    let out = bin().args(["kernel", "--theta", "1", "--radius", "1e-3", "--rel-tol", "1e-30"]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty());
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("NOT CONVERGED"), "{err}");
}

/// `--finite-pairs` takes minutes at a goal it must be given: without
/// `--rel-tol` it is refused (exit 2), naming both flags, before any work.
#[test]
fn finite_pairs_need_a_tolerance() {
    let out = run_in_repo(&["oracle", "scenes/point-isotropic-order1.toml", "--finite-pairs"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("--rel-tol") && err.contains("--finite-pairs"), "{err}");
}

#[test]
fn oracle_json_has_the_documented_keys() {
    let out = run_in_repo(&["oracle", "scenes/point-isotropic.toml", "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for path in [
        "/mean_luminance/value",
        "/mean_luminance/error",
        "/corr23/exact/value",
        "/corr23/exact/error",
        "/corr23/exact/evaluations",
        "/corr23/asymptotic/value",
        "/corr23/asymptotic/error",
        "/corr23/ratio",
        "/corr24/exact/value",
        "/corr24/asymptotic/value",
        "/corr24/ratio",
        "/variance/exact/value",
        "/variance/exact/error",
        "/variance/relative",
        "/variance/relative_asymptotic",
        "/variance/relative_asymptotic_error",
        "/d_error/0",
        "/evaluations",
        "/wall_time_ms",
        "/finite/mean/value",
        "/finite/mean/error",
        "/finite/variance/value",
        "/finite/variance/error",
        "/finite/bias/value",
        "/finite/bias/error",
        "/finite/relative_noise/value",
        "/finite/relative_noise/error",
        "/finite/mean_ratio/value",
        "/finite/variance_ratio/value",
        "/prediction/mean/value",
        "/prediction/variance/error",
    ] {
        let x = v.pointer(path).unwrap_or_else(|| panic!("missing {path}"));
        assert!(x.as_f64().is_some_and(f64::is_finite), "{path} = {x}");
    }
    assert_eq!(v.pointer("/prediction/model").and_then(|m| m.as_str()), Some("finite-sphere"));
}

/// `oracle --json` on an order-1 scene (uncollided plus single-scattered
/// light). At q = 1 and N_B = 1 the `finite` object is the whole
/// finite-sphere model, and it is the prediction ("finite-sphere"), with
/// Q, C₂₃, C₂₄ `null` and the reason in `finite.not_computed`. At the
/// bundled scene's own q = 0.5 and N_B = 8 (no `--finite-pairs`) `finite`
/// is `null`, the exact mean and bias are in `finite_mean`, the prediction
/// is the small-sphere model, and `finite_not_used` names the flag that
/// would make it exact.
#[test]
fn oracle_json_of_an_order1_scene() {
    let number = |v: &serde_json::Value, path: &str| -> f64 {
        let x = v.pointer(path).unwrap_or_else(|| panic!("missing {path} in {v}"));
        x.as_f64().filter(|x| x.is_finite()).unwrap_or_else(|| panic!("{path} = {x}"))
    };
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic-order1.toml")).unwrap();
    let unpaired = text
        .replace("radius = 0.01", "radius = 0.2")
        .replace("q = 0.5", "q = 1.0")
        .replace("forward_rays = 200", "forward_rays = 20")
        .replace("camera_rays = 8", "camera_rays = 1");
    assert_ne!(unpaired, text);
    let path = std::env::temp_dir().join(format!("mcrt-noise-order1-q1-{}.toml", std::process::id()));
    std::fs::write(&path, unpaired).unwrap();
    let out = run_in_repo(&["oracle", path.to_str().unwrap(), "--json", "--rel-tol", "1e-4"]);
    std::fs::remove_file(&path).ok();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v.pointer("/finite/covers").and_then(|c| c.as_str()), Some("uncollided and single-scattered"));
    assert_eq!(v.pointer("/prediction/model").and_then(|m| m.as_str()), Some("finite-sphere"), "{v}");
    // Each within the goal, compounded as the report forms it: the bias, a
    // difference of two means, within both means' goals; Var/μ², within
    // Var L's and twice the mean's; the ratios, within both models'.
    let mean = number(&v, "/finite/mean/value");
    for (key, goals) in [
        ("mean", 1.0),
        ("variance", 1.0),
        ("integral_m2", 1.0),
        ("integral_p", 1.0),
        ("bias", 2.0),
        ("relative_noise", 3.0),
        ("mean_ratio", 2.0),
        ("variance_ratio", 2.0),
    ] {
        let (value, error) = (number(&v, &format!("/finite/{key}/value")), number(&v, &format!("/finite/{key}/error")));
        let scale = if key == "bias" { mean } else { value.abs() };
        assert!(error > 0.0 && error <= goals * 1e-4 * scale, "{key}: {value} ± {error}");
    }
    for key in ["mean", "variance"] {
        assert_eq!(number(&v, &format!("/prediction/{key}/value")), number(&v, &format!("/finite/{key}/value")));
        assert_eq!(number(&v, &format!("/prediction/{key}/error")), number(&v, &format!("/finite/{key}/error")));
    }
    for key in ["integral_q", "corr23", "corr24"] {
        assert!(v.pointer(&format!("/finite/{key}")).is_some_and(|x| x.is_null()), "finite.{key}: {v}");
    }
    let why = v.pointer("/finite/not_computed").and_then(|w| w.as_str()).unwrap();
    assert!(why.contains("weight 0") && why.contains("q = 1 and N_B = 1"), "{why}");
    assert!(v.pointer("/finite_not_used").is_none_or(|x| x.is_null()), "{v}");

    let out = run_in_repo(&["oracle", "scenes/point-isotropic-order1.toml", "--json", "--rel-tol", "1e-4"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(v.pointer("/finite").is_some_and(|x| x.is_null()), "{v}");
    assert_eq!(v.pointer("/prediction/model").and_then(|m| m.as_str()), Some("small-sphere"));
    let (mean, bar) = (number(&v, "/finite_mean/mean/value"), number(&v, "/finite_mean/mean/error"));
    assert!(bar <= 1e-4 * mean, "{mean} ± {bar}");
    number(&v, "/finite_mean/bias/value");
    number(&v, "/finite_mean/bias/error");
    let why = v.pointer("/finite_not_used").and_then(|w| w.as_str()).unwrap();
    assert!(why.contains("--finite-pairs") && why.contains("q = 0.5, N_B = 8"), "{why}");
}

/// The README scene with every order at q = 1, one camera ray, N_F 20 and
/// R 0.2 (where the oracle computes Var L of every order), written to a
/// temporary file named after `tag`; the caller removes it.
fn every_order_q1_scene(tag: &str) -> std::path::PathBuf {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic.toml"))
        .unwrap()
        .replace("scattering_orders = 0", "scattering_orders = \"all\"")
        .replace("radius = 0.01", "radius = 0.2")
        .replace("q = 0.5", "q = 1.0")
        .replace("forward_rays = 200", "forward_rays = 20")
        .replace("camera_rays = 8", "camera_rays = 1");
    let path = std::env::temp_dir().join(format!("mcrt-noise-{tag}-{}.toml", std::process::id()));
    std::fs::write(&path, &text).unwrap();
    path
}

/// With every order at q = 1 and one camera ray the oracle gives Var L
/// exact at R (docs/model.md §10.3) with M₂'s same-path pairs and P, each
/// with a bar, and no `variance_missing`; the text report prints them.
#[test]
fn oracle_gives_the_variance_of_every_order_at_q_one() {
    let path = every_order_q1_scene("all-q1");
    let out = bin().args(["oracle", path.to_str().unwrap(), "--json", "--rel-tol", "1e-3"]).output().unwrap();
    let text_out = bin().args(["oracle", path.to_str().unwrap(), "--rel-tol", "1e-3"]).output().unwrap();
    std::fs::remove_file(&path).ok();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let get = |p: &str| v.pointer(p).and_then(|x| x.as_f64()).unwrap_or_else(|| panic!("{p} in {v}"));
    let (var, bar) = (get("/variance/value"), get("/variance/error"));
    assert!(var > 0.0 && bar > 0.0 && bar <= 1e-3 * var, "{v}");
    let (m2, pairs, p) = (get("/m2/value"), get("/same_path_pairs/value"), get("/p/value"));
    assert!(pairs > 0.0 && pairs < m2 && p > 0.0, "{v}");
    assert!(v["variance_missing"].is_null(), "{v}");
    let shown = String::from_utf8(text_out.stdout).unwrap();
    assert!(shown.contains("Var L (one iteration), exact") && shown.contains("same-path pairs"), "{shown}");
    assert!(!shown.contains("the mean only"), "{shown}");
}

/// `check` on every order (`"all"` at q = 1 and one camera ray): the
/// tracer's values pass against the exact prediction (finite-sphere model,
/// no model bar), and the same values scaled by 1.1 (mean 10 % high, Var L
/// 21 %) fail, exit 1.
#[test]
fn check_of_every_order_passes_the_tracer_and_fails_values_off_by_ten_percent() {
    let path = every_order_q1_scene("check-all-q1");
    let scene = mcrt_noise::Scene::from_toml_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let dir = temp_dir("check-all");
    let run = |scale: f64| {
        let values = dir.join(format!("values-{scale}.txt"));
        let lines: String = traced_values(&scene, 100_000, scale).iter().map(|v| format!("{v:e}\n")).collect();
        std::fs::write(&values, lines).unwrap();
        bin().arg("check").arg(&path).arg("--values").arg(&values).output().unwrap()
    };
    let (good, off) = (run(1.0), run(1.1));
    std::fs::remove_file(&path).ok();
    std::fs::remove_dir_all(&dir).ok();
    let text = String::from_utf8_lossy(&good.stdout);
    assert_eq!(good.status.code(), Some(0), "{text}{}", String::from_utf8_lossy(&good.stderr));
    assert!(text.starts_with("PASS") && text.contains("finite-sphere model"), "{text}");
    assert_eq!(text.matches("(quadrature), model exact").count(), 2, "{text}");
    let text = String::from_utf8_lossy(&off.stdout);
    assert_eq!(off.status.code(), Some(1), "{text}{}", String::from_utf8_lossy(&off.stderr));
    assert!(text.starts_with("FAIL") && text.contains("fails: mean L"), "{text}");
}

/// When Var L's integrals of every order spend the budget, the oracle still
/// reports the mean (computed first) with exit 0, and says why Var L is
/// missing. (10⁸ evaluations: the means charge the budget 4.35·10⁷, Var
/// L's integrals, beside them on a budget of their own, need 1.24·10⁸ and
/// stop at 10⁸; measured 7 December 2026 once the scale passes read the
/// primary passes' tables, docs/model.md §10.6; before, 5.1·10⁷ and 1.7·10⁸
/// with a budget of 1.5·10⁸.)
#[test]
fn oracle_keeps_the_mean_of_every_order_when_the_variance_spends_the_budget() {
    let path = every_order_q1_scene("all-budget");
    let out = bin().args(["oracle", path.to_str().unwrap(), "--json", "--max-evals", "100000000"]).output().unwrap();
    std::fs::remove_file(&path).ok();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(v.pointer("/mean/value").and_then(|x| x.as_f64()).is_some_and(|m| m > 0.0), "{v}");
    assert!(v["variance"].is_null(), "{v}");
    let why = v["variance_missing"].as_str().unwrap();
    assert!(why.contains("budget") && why.contains("the mean above stands"), "{why}");
}

/// With scattering_orders = 2 the oracle gives the exact mean, the
/// small-sphere mean and the bias (docs/model.md §10), says why Var L is
/// missing, and `predict` (through `check`'s prediction) refuses the scene
/// naming the field; order 12 is beyond the cut integral's reach and is
/// refused, exit 2, naming the field and the allowed range.
#[test]
fn oracle_gives_the_mean_of_order_two_and_refuses_order_twelve() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic-order1.toml"))
        .unwrap()
        .replace("scattering_orders = 1", "scattering_orders = 2");
    let path = std::env::temp_dir().join(format!("mcrt-noise-order2-{}.toml", std::process::id()));
    std::fs::write(&path, &text).unwrap();
    let out = bin().args(["oracle", path.to_str().unwrap(), "--json"]).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let get = |p: &str| v.pointer(p).and_then(|x| x.as_f64()).unwrap_or_else(|| panic!("{p} in {v}"));
    let (mean, bar) = (get("/mean/value"), get("/mean/error"));
    assert!(mean > 0.0 && bar > 0.0 && bar <= 1e-5 * mean, "{v}");
    let (small, bias) = (get("/small_sphere_mean/value"), get("/bias/value"));
    assert!((mean - small - bias).abs() <= get("/bias/error") + 1e-15 * mean, "{v}");
    assert!(v["variance_missing"].as_str().unwrap().contains("not modelled"), "{v}");
    std::fs::write(&path, text.replace("scattering_orders = 2", "scattering_orders = 12")).unwrap();
    let out = bin().args(["oracle", path.to_str().unwrap()]).output().unwrap();
    std::fs::remove_file(&path).ok();
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("scattering_orders = 12") && err.contains("\"all\""), "{err}");
}

#[test]
fn sweep_prints_ratios_and_order() {
    let out = run_in_repo(&["sweep", "scenes/beam-isotropic.toml", "--radii", "1e-2,1e-3,1e-4,1e-5", "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let order = v.pointer("/order23/order").and_then(|x| x.as_f64()).unwrap();
    let err = v.pointer("/order23/error").and_then(|x| x.as_f64()).unwrap();
    assert!((order - 1.0).abs() <= 0.01 && err < 0.01, "order {order} ± {err}");
    let bad = run_in_repo(&["sweep", "scenes/beam-isotropic.toml", "--radii", "1e-2,-1"]);
    assert_eq!(bad.status.code(), Some(2));
}

fn trace_json(args: &[&str]) -> serde_json::Value {
    let out = bin().args(args).output().unwrap();
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn shards_traced_by_separate_processes_merge_into_the_single_run() {
    let dir = std::env::temp_dir().join(format!("mcrt-noise-shards-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/point-hg-forward.toml");
    let scene = scene.to_str().unwrap();
    let whole = trace_json(&["trace", scene, "--trials", "9000", "--seed", "4", "--threads", "1", "--json"]);
    assert!(whole["counters"]["nonzero_trials"].as_u64().unwrap() >= 100, "{whole}");
    let mut shards = Vec::new();
    for (k, range) in ["0..2500", "2500..8999", "8999..9000"].iter().enumerate() {
        let path = dir.join(format!("shard{k}.json"));
        let p = path.to_str().unwrap().to_string();
        let args = ["trace", scene, "--trials", range, "--seed", "4", "--threads", "2", "--json", "--out", &p];
        let out = bin().args(args).output().unwrap();
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        // 0..2500 has fewer than 100 trials with hits (41): not resolved, exit 1, but its
        // shard is written and merges; 8999..9000 is below 4 trials: exit 0.
        let nonzero = json["counters"]["nonzero_trials"].as_u64().unwrap();
        let trials = json["trial_count"].as_u64().unwrap();
        let expected = if trials >= 4 && nonzero < 100 { 1 } else { 0 };
        assert_eq!(out.status.code(), Some(expected), "{range}: {json}");
        assert_eq!(json["mean"].is_null(), trials < 4 || nonzero < 100, "{range}: {json}");
        shards.push(p);
    }
    let mut args = vec!["merge", "--json"];
    args.extend(shards.iter().map(String::as_str));
    let merged = trace_json(&args);
    for key in ["mean", "variance", "counters", "trials", "trial_count", "seed"] {
        assert_eq!(merged[key], whole[key], "{key}");
    }
    // The same shard twice overlaps itself: refused.
    let out = bin().args(["merge", &shards[0], &shards[0]]).output().unwrap();
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("overlap"));
}

#[test]
fn trace_refuses_bad_trial_ranges_and_thread_counts() {
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/point-isotropic.toml");
    for (args, needle) in [
        (vec!["--trials", "5..5"], "--trials"),
        (vec!["--trials", "ten"], "--trials"),
        (vec!["--trials", "100", "--threads", "0"], "--threads"),
        (vec!["--trials", "100", "--radius=-1"], "--radius"),
    ] {
        let out = bin().arg("trace").arg(&scene).args(&args).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(out.stdout.is_empty());
        assert!(String::from_utf8_lossy(&out.stderr).contains(needle), "{args:?}");
    }
}

#[test]
fn compare_prints_both_sides_and_a_verdict() {
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/point-isotropic.toml");
    let json = trace_json(&["compare", scene.to_str().unwrap(), "--trials", "200000", "--seed", "3", "--json"]);
    for side in ["mean", "variance"] {
        for key in ["oracle", "oracle_error", "tracer", "tracer_se", "ratio", "ratio_error", "z"] {
            assert!(json[side][key].is_f64(), "{side}.{key}");
        }
    }
    assert_eq!(json["pass"], true, "{json}");
    assert_eq!(json["model"], "finite-sphere", "{json}");
    assert!(json["verdict"].as_str().unwrap().starts_with("AGREE"));
}

/// A temporary directory of this test process.
fn temp_dir(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("mcrt-noise-cli-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The reference tracer's per-iteration values on a bundled scene, scaled.
fn traced_values(scene: &mcrt_noise::Scene, n: u64, scale: f64) -> Vec<f64> {
    let tracer = mcrt_noise::reference::Tracer::new(scene).unwrap();
    (0..n).map(|i| scale * tracer.trial(11, i, mcrt_noise::reference::HitMethod::Sorted).0).collect()
}

#[test]
fn check_passes_a_correct_renderer_fails_a_wrong_one_and_refuses_bad_input() {
    let dir = temp_dir("check");
    let scene_path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/point-isotropic.toml");
    let mut scene = mcrt_noise::Scene::from_toml_str(&std::fs::read_to_string(&scene_path).unwrap()).unwrap();
    scene.estimator.forward_rays = 20;
    scene.estimator.radius = 0.2;
    let scene_file = dir.join("scene.toml");
    std::fs::write(&scene_file, scene.to_toml_string()).unwrap();
    let good = traced_values(&scene, 100_000, 1.0);
    let run = |values: &std::path::Path, extra: &[&str]| {
        bin().arg("check").arg(&scene_file).arg("--values").arg(values).args(extra).output().unwrap()
    };
    // One value per line: pass, exit 0, the detectable error stated.
    let lines = dir.join("values.txt");
    std::fs::write(&lines, good.iter().map(|v| format!("{v:e}\n")).collect::<String>()).unwrap();
    let out = run(&lines, &[]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}{}", String::from_utf8_lossy(&out.stderr));
    assert!(
        text.starts_with("PASS") && text.contains("what this check shows: a renderer whose mean is off by"),
        "{text}"
    );
    // The finite-sphere model's zero bar is said in words, not printed as 0.
    assert_eq!(text.matches("(quadrature), model exact").count(), 2, "{text}");
    assert!(!text.contains("0.0e0"), "{text}");
    // Both ratios with their standard error and bar.
    assert_eq!(text.matches(" (s.e.)   ratio ").count(), 2, "{text}");
    assert_eq!(text.matches(" (bars)   z ").count(), 2, "{text}");
    // From standard input too.
    let mut child = bin()
        .arg("check")
        .arg(&scene_file)
        .args(["--values", "-"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::io::Write::write_all(&mut child.stdin.take().unwrap(), &std::fs::read(&lines).unwrap()).unwrap();
    let piped = child.wait_with_output().unwrap();
    assert_eq!(piped.status.code(), Some(0));
    assert_eq!(piped.stdout, out.stdout);
    // The same values as a JSON array and as power sums: the same verdict.
    let array = dir.join("values.json");
    std::fs::write(&array, serde_json::to_string(&good).unwrap()).unwrap();
    let from_array: serde_json::Value = serde_json::from_slice(&run(&array, &["--json"]).stdout).unwrap();
    let sums: Vec<f64> = (1..=6).map(|k| good.iter().map(|v| v.powi(k)).sum()).collect();
    let (lo, hi) = good.iter().fold((f64::MAX, 0f64), |(a, b), v| (a.min(*v), b.max(*v)));
    let sums_file = dir.join("sums.json");
    let sums_json = serde_json::json!({"count": good.len(), "sums": sums, "min": lo, "max": hi});
    std::fs::write(&sums_file, sums_json.to_string()).unwrap();
    // Pretty-printed past 4096 bytes (padded with spaces), the same; anything
    // after the object is refused.
    let padded = dir.join("sums-padded.json");
    let pretty = serde_json::to_string_pretty(&sums_json).unwrap().replace('\n', &format!("\n{}", " ".repeat(600)));
    assert!(pretty.len() > 4096);
    std::fs::write(&padded, &pretty).unwrap();
    assert_eq!(run(&padded, &[]).stdout, run(&sums_file, &[]).stdout);
    // The 8 largest values in place of "max": the same verdict as the values themselves.
    let mut sorted = good.clone();
    sorted.sort_by(|a, b| b.total_cmp(a));
    let top = dir.join("sums-top.json");
    let top_json = serde_json::json!({"count": good.len(), "sums": sums, "min": lo, "largest": &sorted[..8]});
    std::fs::write(&top, top_json.to_string()).unwrap();
    let from_top: serde_json::Value = serde_json::from_slice(&run(&top, &["--json"]).stdout).unwrap();
    let from_values: serde_json::Value = serde_json::from_slice(&run(&lines, &["--json"]).stdout).unwrap();
    assert_eq!(from_top["status"], from_values["status"], "{from_top}");
    // (the same to the f64 sums' rounding, ~10⁻¹⁰ relative here)
    let influence = |j: &serde_json::Value| j["checks"][1]["influence"].as_f64().unwrap();
    assert!((influence(&from_top) / influence(&from_values) - 1.0).abs() < 1e-6, "{from_top}");
    let wrong_max = dir.join("sums-wrong-max.json");
    let wrong_json =
        serde_json::json!({"count": good.len(), "sums": sums, "min": lo, "max": sorted[1], "largest": &sorted[..8]});
    std::fs::write(&wrong_max, wrong_json.to_string()).unwrap();
    let trailing = dir.join("sums-trailing.json");
    std::fs::write(&trailing, format!("{pretty}\n{{\"count\": 1}}")).unwrap();
    let from_sums: serde_json::Value = serde_json::from_slice(&run(&sums_file, &["--json"]).stdout).unwrap();
    assert_eq!(from_array["pass"], true);
    assert_eq!(from_sums["pass"], true);
    let z = |j: &serde_json::Value, k: usize| j["checks"][k]["z"].as_f64().unwrap();
    assert!((z(&from_array, 0) - z(&from_sums, 0)).abs() < 1e-6 && (z(&from_array, 1) - z(&from_sums, 1)).abs() < 1e-3);
    assert!(from_sums["checks"][1]["rounding_bar"].as_f64().unwrap() > 0.0);
    // Power sums' rounding bar is printed beside the standard error.
    let sums_text = String::from_utf8_lossy(&run(&sums_file, &[]).stdout).to_string();
    assert_eq!(sums_text.matches(" (s.e.) ± ").count(), 4, "{sums_text}");
    assert_eq!(sums_text.matches(" (rounding)   ratio ").count(), 2, "{sums_text}");
    // Sums without a nonzero count: sparsity could not be checked, and the verdict says so.
    assert!(from_sums["statement"].as_str().unwrap().contains("sparsity could not be checked"), "{from_sums}");
    assert!(
        from_sums["statement"].as_str().unwrap().contains("only 1 of the 8 largest values were given"),
        "{from_sums}"
    );
    assert!(!from_array["statement"].as_str().unwrap().contains("largest values were given"), "{from_array}");
    assert!(from_sums["nonzero"].is_null() && from_array["nonzero"].as_u64().unwrap() >= 100, "{from_array}");
    assert!(!from_array["statement"].as_str().unwrap().contains("sparsity"), "{from_array}");
    // With a nonzero count below 100: not resolved, exit 1, the reason given.
    // (The sums of 37 of the values, the rest zeros: sums 37 nonzero values can have.)
    let sparse_sums = dir.join("sparse-sums.json");
    let count = good.len();
    let hits: Vec<f64> = good.iter().copied().filter(|v| *v != 0.0).take(37).collect();
    let hit_sums: Vec<f64> = (1..=6).map(|k| hits.iter().map(|v| v.powi(k)).sum()).collect();
    let largest = hits.iter().copied().fold(0.0, f64::max);
    let sparse_json = serde_json::json!({"count": count, "sums": hit_sums, "nonzero": 37, "min": 0.0, "max": largest});
    std::fs::write(&sparse_sums, sparse_json.to_string()).unwrap();
    let out = run(&sparse_sums, &[]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{text}{}", String::from_utf8_lossy(&out.stderr));
    assert!(
        text.contains(&format!(
            "not resolved: mean L and Var L: only 37 of the {count} values are nonzero (fewer than 100)"
        )),
        "{text}"
    );
    for k in 0..2 {
        let ratio = &from_sums["checks"][k]["ratio"];
        assert!(ratio["standard_error"].as_f64().unwrap() > 0.0 && ratio["bar"].as_f64().unwrap() > 0.0, "{ratio}");
    }
    // A renderer 10 % too bright: fail, exit 1, the verdict once, on stdout only.
    let bright = dir.join("bright.txt");
    let wrong = traced_values(&scene, 100_000, 1.1);
    std::fs::write(&bright, wrong.iter().map(|v| format!("{v:e}\n")).collect::<String>()).unwrap();
    let out = run(&bright, &[]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(text.starts_with("FAIL") && text.contains("fails: mean L"), "{text}");
    assert_eq!(text.matches("FAIL").count(), 1);
    assert!(out.stderr.is_empty(), "{}", String::from_utf8_lossy(&out.stderr));
    // A target the samples cannot resolve: not resolved, with the samples that would.
    let out = run(&lines, &["--target-variance", "0.001"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(text.starts_with("NOT RESOLVED"), "{text}");
    assert!(text.contains("too few samples to resolve the target 0.100 %") && text.contains("samples would"), "{text}");
    // A plan from a pilot of these values: exit 0, the count, the pilot's verdict.
    let pilot = dir.join("pilot.txt");
    std::fs::write(&pilot, good[..10_000].iter().map(|v| format!("{v:e}\n")).collect::<String>()).unwrap();
    let out = run(&pilot, &["--plan"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.starts_with("PLAN: about ") && text.contains("pilot's verdict"), "{text}");
    let plan: serde_json::Value = serde_json::from_slice(&run(&pilot, &["--plan", "--json"]).stdout).unwrap();
    assert!(plan["samples"].as_f64().unwrap() > 10_000.0 && plan["pilot"]["status"].is_string(), "{plan}");
    // Five zeros: not resolved (exit 1), zero spread named, no "0 ± 0" row.
    let zeros = dir.join("zeros.txt");
    std::fs::write(&zeros, "0\n0\n0\n0\n0\n").unwrap();
    let out = run(&zeros, &[]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(
        text.contains("not resolved: mean L and Var L: all 5 values are equal (0.000000e0): zero spread"),
        "{text}"
    );
    assert!(!text.contains("± 0.0e0 (s.e.)") && !text.contains("too large"), "{text}");
    let json: serde_json::Value = serde_json::from_slice(&run(&zeros, &["--json"]).stdout).unwrap();
    assert!(json["checks"][0]["measured"].is_null() && json["checks"][1]["not_resolved"].is_string(), "{json}");
    // Bad input: exit 2, a message naming the line or flag, nothing on stdout.
    let not_number = dir.join("bad.txt");
    std::fs::write(&not_number, "1e-3\n2e-3\nnan\n").unwrap();
    let string_in_array = dir.join("strings.json");
    std::fs::write(&string_in_array, r#"[1e-3, "x"]"#).unwrap();
    let long_line = dir.join("long.txt");
    std::fs::write(&long_line, "1".repeat(5000)).unwrap();
    let nonsense_sums = dir.join("nonsense.json");
    std::fs::write(&nonsense_sums, r#"{"count": 10, "sums": [10.0, 1.0, 1.0, 1.0, 1.0, 1.0], "min": 0, "max": 1}"#)
        .unwrap();
    // The adversarial probe's sums: Σ L⁴ far above (Σ L²)² (they passed once).
    let huge_fourth = dir.join("huge-fourth.json");
    std::fs::write(&huge_fourth, r#"{"count": 10000, "sums": [11.1, 0.8, 0.5, 1e10, 1e10, 1e21], "min": 0, "max": 1}"#)
        .unwrap();
    let huge_fourth_300 = dir.join("huge-fourth-300.json");
    std::fs::write(
        &huge_fourth_300,
        r#"{"count": 100, "sums": [0.1, 0.01, 0.001, 1e300, 1e300, 1e300], "min": 0, "max": 1}"#,
    )
    .unwrap();
    let too_many_nonzero = dir.join("too-many-nonzero.json");
    std::fs::write(
        &too_many_nonzero,
        r#"{"count": 10, "nonzero": 20, "sums": [3, 3, 3, 3, 3, 3], "min": 0, "max": 1}"#,
    )
    .unwrap();
    let too_few_nonzero = dir.join("too-few-nonzero.json");
    std::fs::write(&too_few_nonzero, r#"{"count": 10, "nonzero": 2, "sums": [3, 3, 3, 3, 3, 3], "min": 0, "max": 1}"#)
        .unwrap();
    let four_sums = dir.join("four-sums.json");
    std::fs::write(&four_sums, r#"{"count": 4, "sums": [10.0, 30.0, 100.0, 354.0], "min": 1, "max": 4}"#).unwrap();
    let no_range = dir.join("no-range.json");
    std::fs::write(&no_range, r#"{"count": 4, "sums": [10.0, 30.0, 100.0, 354.0, 1300.0, 4890.0]}"#).unwrap();
    let negative = dir.join("negative.txt");
    std::fs::write(&negative, "1e-3\n# a comment\n-2e-3\n").unwrap();
    let negative_array = dir.join("negative.json");
    std::fs::write(&negative_array, "[1e-3, 0, -0.5]").unwrap();
    for (values, extra, needle) in [
        (&not_number, &[][..], "line 3: sample 2 = NaN: must be finite"),
        (&nonsense_sums, &[][..], "not the power sums of real numbers: (Σ L)² ≤ N·Σ L² must hold (N = count = 10"),
        (&huge_fourth, &[][..], "with count = 10000: not the power sums of real numbers: Σ L⁴ ≤ (Σ L²)² must hold"),
        (&huge_fourth_300, &[][..], "Σ L⁴ ≤ (Σ L²)² must hold, but its left side is 1.00000e300"),
        (&too_many_nonzero, &[][..], "nonzero = 20: must be in [0, count = 10]"),
        (
            &too_few_nonzero,
            &[][..],
            "and nonzero = 2: not the power sums of real numbers: (Σ L)² ≤ N·Σ L² must hold (N = nonzero = 2)",
        ),
        (&string_in_array, &[][..], "JSON array: invalid type: string"),
        (&long_line, &[][..], "line 1 is longer than 4096 bytes"),
        (&dir.join("missing.txt"), &[][..], "missing.txt"),
        (&lines, &["--false-alarm-rate", "0"][..], "--false-alarm-rate = 0: must be in [1e-300, 0.5]"),
        (&lines, &["--false-alarm-rate", "1e-301"][..], "--false-alarm-rate = 1e-301: must be in [1e-300, 0.5]"),
        (&four_sums, &[][..], "\"sums\" has 4 entries: must have 6"),
        (&no_range, &[][..], "\"min\" and \"max\" (the smallest and largest value) are required"),
        (&negative, &[][..], "line 3: sample 1 = -2e-3: must be >= 0"),
        (&negative_array, &[][..], "JSON array: sample 2 = -5e-1: must be >= 0"),
        (&trailing, &[][..], "power sums JSON: trailing characters"),
        (&wrong_max, &[][..], "is not the largest of \"largest\""),
        (&lines, &["--target-mean", "-1"][..], "--target-mean = -1: must be finite and > 0"),
    ] {
        let out = run(values, extra);
        assert_eq!(out.status.code(), Some(2), "{extra:?}");
        assert!(out.stdout.is_empty(), "{extra:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(needle), "{needle:?} not in {err}");
    }
}

#[test]
fn compare_prints_its_verdict_once_on_stdout_and_exits_2_on_bad_input() {
    // (A disagreement, exit 1, cannot be arranged through the CLI: the oracle
    // and the tracer read the same scene. `check`'s test covers exit 1.)
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/point-isotropic.toml");
    let out = bin().args(["compare", scene.to_str().unwrap(), "--trials", "20000"]).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
    assert_eq!(text.matches("AGREE").count(), 1, "{text}");
    assert!(out.stderr.is_empty());
    let out = bin().args(["compare", scene.to_str().unwrap(), "--trials", "0..0"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
}

// ---- Issue 11, adversarial probe of the tracer's commands ----

/// `scenes/point-isotropic.toml` with text replacements, written to a temporary file.
fn edited_scene(tag: &str, edits: &[(&str, &str)]) -> std::path::PathBuf {
    let mut text =
        std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/point-isotropic.toml"))
            .unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "no {from:?} to replace");
        text = text.replacen(from, to, 1);
    }
    let path = temp_dir("probe").join(format!("{tag}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

/// Runs the binary, killing it after `seconds` (then `None`: it hung).
fn run_within(args: &[&str], seconds: u64) -> Option<std::process::Output> {
    use std::process::Stdio;
    let mut child = bin().args(args).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed().as_secs() >= seconds {
            child.kill().ok();
            child.wait().ok();
            return None;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    Some(child.wait_with_output().unwrap())
}

/// Exit code, stdout, stderr of a run that must end within 60 s.
fn ended(args: &[&str]) -> (Option<i32>, String, String) {
    let out = run_within(args, 60).unwrap_or_else(|| panic!("{args:?} still running after 60 s"));
    (out.status.code(), String::from_utf8_lossy(&out.stdout).into(), String::from_utf8_lossy(&out.stderr).into())
}

/// Nothing printed is inf or NaN.
fn assert_finite_output(text: &str) {
    let lower = text.to_lowercase();
    assert!(!lower.contains("nan") && !lower.contains("inf"), "inf or NaN printed:\n{text}");
}

/// The probe: `trace` panicked at `reference/src/moments.rs:56` ("fourth
/// power is not finite") for `sigma_ext = 5e-324`, `flux = 1e300` and
/// `radius = 1e-300`, all accepted by `validate`, and printed `± NaN` and
/// `Var L -0.0` for `flux = 1e-300`. L is now scaled by a power of two
/// (exact), and what no scaling saves is refused up front (exit 2).
#[test]
fn trace_scales_extreme_fluxes_exactly_and_refuses_degenerate_lengths() {
    let p = |tag, edits: &[(&str, &str)]| edited_scene(tag, edits).to_str().unwrap().to_string();
    let base = p("flux1", &[]);
    let (code, one, err) = ended(&["trace", &base, "--trials", "20000", "--seed", "3", "--json"]);
    assert_eq!(code, Some(0), "{err}");
    let one: serde_json::Value = serde_json::from_str(&one).unwrap();
    // Fluxes 2^33 and 2^-33 (the scene's bounds are [1e-10, 1e10]): L is linear in the flux, and
    // scaling by a power of two is exact.
    for (tag, flux, k) in
        [("fluxbig", "flux = 8589934592.0", 33), ("fluxsmall", "flux = 1.16415321826934814453125e-10", -33)]
    {
        let path = p(tag, &[("flux = 1.0", flux)]);
        let (code, text, err) = ended(&["trace", &path, "--trials", "20000", "--seed", "3"]);
        assert_eq!(code, Some(0), "{tag}: {err}");
        assert_finite_output(&text);
        let (code, json, _) = ended(&["trace", &path, "--trials", "20000", "--seed", "3", "--json"]);
        assert_eq!(code, Some(0));
        let json: serde_json::Value = serde_json::from_str(&json).unwrap();
        let scale = 2f64.powi(k / 2) * 2f64.powi(k - k / 2);
        // Exact (reference/tests/limits.rs); here to 1e-15, since serde_json's parser may miss by an ulp.
        for key in ["value", "se"] {
            let (got, want) = (json["mean"][key].as_f64().unwrap(), one["mean"][key].as_f64().unwrap() * scale);
            assert!(((got - want) / want).abs() <= 1e-15, "{tag} {key}: {got:e} against {want:e}");
        }
        for key in ["value", "se"] {
            let (got, want) =
                (json["variance"][key].as_f64().unwrap(), one["variance"][key].as_f64().unwrap() * scale * scale);
            assert!(((got - want) / want).abs() <= 1e-15, "{tag} Var {key}: {got:e} against {want:e}");
        }
    }
    // flux = 1e300 and 1e-300 (the probe's panic and NaN): refused by the scene's bounds, the field named.
    for (tag, flux) in [("f300", "flux = 1e300"), ("fm300", "flux = 1e-300")] {
        let path = p(tag, &[("flux = 1.0", flux)]);
        let (code, text, err) = ended(&["trace", &path, "--trials", "1000"]);
        assert_eq!(code, Some(2), "{tag}: {err}");
        assert!(text.is_empty() && err.contains("lights[0].flux") && !err.contains("panicked"), "{tag}: {err}");
    }
    // Lengths the tracer cannot square or step: refused up front, the field named, exit 2.
    for (tag, edit, field) in [
        ("ext", ("sigma_ext = 1.0", "sigma_ext = 5e-324"), "medium.sigma_ext"),
        ("rad", ("radius = 0.01", "radius = 1e-300"), "estimator.radius"),
    ] {
        let (code, text, err) = ended(&["trace", &p(tag, &[edit]), "--trials", "1000"]);
        assert_eq!(code, Some(2), "{tag}: {text}{err}");
        assert!(text.is_empty() && err.contains(field) && !err.contains("panicked"), "{tag}: {err}");
    }
}

/// The probe: `camera_rays = 2^40` and `--trials 18446744073709551615`
/// aborted on a failed allocation (exit 134); `q = 1e-12` grew past 18 GB;
/// `forward_rays = 2^40` and `scattering_orders = 1000000` with albedo 1 ran
/// past 120 s with no progress. Each is now refused before any trial (exit
/// 2) with the field or flag and its bound named: the scene's bounds
/// (`forward_rays` ≤ 10⁸, `camera_rays` ≤ 10⁶, q ≥ 10⁻⁶) or the tracer's
/// (`reference/src/limits.rs`: 2²⁴ forward segments per trial, 2⁶⁰ units of
/// work per run, which bounds `--trials`). A million orders of a single
/// forward ray fit the per-trial bound and run in about a second.
#[test]
fn trace_refuses_trials_beyond_its_memory_and_work_bounds_with_the_field_named() {
    let p = |tag, edits: &[(&str, &str)]| edited_scene(tag, edits).to_str().unwrap().to_string();
    let scene = p("bounds", &[]);
    for (path, trials, needle) in [
        (p("cam", &[("camera_rays = 8", "camera_rays = 1099511627776")]), "10", "estimator.camera_rays"),
        (p("q", &[("q = 0.5", "q = 1e-12")]), "10", "estimator.q"),
        (p("fwd", &[("forward_rays = 200", "forward_rays = 1099511627776")]), "10", "estimator.forward_rays"),
        (
            p("orders", &[("scattering_orders = 0", "scattering_orders = 1000000"), ("albedo = 0.8", "albedo = 1.0")]),
            "10",
            "effects.scattering_orders",
        ),
        (scene.clone(), "18446744073709551615", "--trials"),
        (scene.clone(), "0..18446744073709551615", "--trials"),
    ] {
        let (code, text, err) = ended(&["trace", &path, "--trials", trials]);
        assert_eq!(code, Some(2), "{needle}: {text}{err}");
        assert!(
            text.is_empty() && err.contains(needle) && (err.contains("at most") || err.contains("must be")),
            "{needle}: {err}"
        );
        if needle == "--trials" {
            assert!(err.contains("at most 2^60") && err.contains("trials per run or shard"), "{err}");
        }
    }
    let one_ray = p(
        "orders1",
        &[
            ("scattering_orders = 0", "scattering_orders = 1000000"),
            ("albedo = 0.8", "albedo = 1.0"),
            ("forward_rays = 200", "forward_rays = 1"),
        ],
    );
    let start = std::time::Instant::now();
    let (code, text, err) = ended(&["trace", &one_ray, "--trials", "10"]);
    assert!(start.elapsed().as_secs() < 30, "{:?}", start.elapsed());
    // 10⁷ segments and no sphere met: not resolved, said in the report, exit 1.
    assert_eq!(code, Some(1), "{text}{err}");
    assert!(text.contains("segments 10000010") && text.contains("no hits in 10 trials"), "{text}");
}

/// The probe: `--trials 18446744073709550000..18446744073709551615 --out
/// s.json` ran 0 trials and exited 0 while the shard claimed the range
/// (`a + CHUNK` wrapped in `reference/src/run.rs`). The range is 1615
/// trials, within every bound: traced in full (range arithmetic saturates),
/// and its shard merges.
#[test]
fn trial_ranges_near_the_end_of_u64_are_traced_and_merged() {
    let dir = temp_dir("u64max");
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/point-isotropic.toml");
    let scene = scene.to_str().unwrap();
    let (a, b) = (dir.join("a.json"), dir.join("b.json"));
    let (a, b) = (a.to_str().unwrap(), b.to_str().unwrap());
    // R = 0.05: enough trials with hits (≥ 100) to resolve the mean.
    let json = trace_json(&[
        "trace",
        scene,
        "--radius",
        "0.05",
        "--trials",
        "18446744073709550000..18446744073709551615",
        "--json",
        "--out",
        a,
    ]);
    assert_eq!(json["trial_count"], 1615, "{json}");
    assert_eq!(json["counters"]["trials"], 1615);
    assert!(json["mean"]["se"].as_f64().unwrap() > 0.0);
    let args = ["trace", scene, "--radius", "0.05", "--trials", "18446744073709549000..18446744073709550000"];
    trace_json(&[&args[..], &["--json", "--out", b]].concat());
    let merged = trace_json(&["merge", a, b, "--json"]);
    assert_eq!(merged["trial_count"], 2615);
    assert_eq!(merged["trials"][0][0].as_u64(), Some(18446744073709549000));
    assert_eq!(merged["trials"][0][1].as_u64(), Some(u64::MAX));
}

/// The probe: with no hits the tracer reported `0 ± 0` (exit 0) and
/// `compare` said DISAGREE with z = −7e10 on a valid scene.
#[test]
fn zero_hits_are_reported_as_not_resolved_by_trace_and_compare() {
    let far = edited_scene("far", &[("position = [1.0, 0.0, 1.0]", "position = [40.0, 0.0, 1.0]")]);
    let far = far.to_str().unwrap();
    // Not resolved is a computed failure: exit 1, the reason in the report, nothing on stderr.
    let (code, text, err) = ended(&["trace", far, "--trials", "20000"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.is_empty(), "{err}");
    assert!(text.contains("no hits in 20000 trials: the mean and variance are not resolved"), "{text}");
    assert!(!text.contains("± 0.00e0"), "{text}");
    let (code, json, _) = ended(&["trace", far, "--trials", "20000", "--json"]);
    assert_eq!(code, Some(1));
    let json: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert!(json["mean"].is_null() && json["variance"].is_null(), "{json}");
    assert!(json["not_resolved"].as_str().unwrap().contains("no hits"), "{json}");
    // Below 4 trials the variance's error is undefined by construction: a shard to merge, exit 0.
    let (code, _, err) = ended(&["trace", far, "--trials", "3"]);
    assert_eq!(code, Some(0), "{err}");
    let (code, text, _) = ended(&["compare", far, "--trials", "20000"]);
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("NOT RESOLVED: no hits in 20000 trials") && !text.contains("DISAGREE"), "{text}");
    assert_finite_output(&text);
    let (code, json, _) = ended(&["compare", far, "--trials", "20000", "--json"]);
    assert_eq!(code, Some(1));
    let json: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(json["pass"], false);
    assert!(json["verdict"].as_str().unwrap().starts_with("NOT RESOLVED"), "{json}");
}

#[test]
fn merge_validates_every_field_of_every_shard() {
    let dir = temp_dir("badshards");
    let shard = resolved_shard(&dir.join("good.json"), "2000");
    let (trials, hits) = (shard["counters"]["trials"].as_u64().unwrap(), shard["counters"]["hits"].as_u64().unwrap());
    let edit = |f: &dyn Fn(&mut serde_json::Value)| {
        let mut s = shard.clone();
        f(&mut s);
        s
    };
    let albedo7 = shard["scene"].as_str().unwrap().replace("albedo = 0.8", "albedo = 7.0");
    for (tag, bad, needle) in [
        ("inf", edit(&|s| s["sums"][0] = "@inf@".into()), "sums"),
        ("nan", edit(&|s| s["sums"][3] = "@nan@".into()), "sums"),
        ("notscene", edit(&|s| s["scene"] = "not a scene".into()), "scene"),
        ("albedo", edit(&|s| s["scene"] = albedo7.clone().into()), "medium.albedo"),
        ("rays", edit(&|s| s["counters"]["forward_rays"] = 7.into()), "counters.forward_rays"),
        ("order", edit(&|s| s["ranges"] = serde_json::json!([[50, 100], [0, 50]])), "ranges"),
        ("overlap", edit(&|s| s["ranges"] = serde_json::json!([[0, 60], [40, 80]])), "ranges"),
        ("negative", edit(&|s| s["sums"][1] = "-1.0".into()), "sums"),
        ("nztrials", edit(&|s| s["counters"]["nonzero_trials"] = (trials + 1).into()), "counters.nonzero_trials"),
        ("nzhits", edit(&|s| s["counters"]["nonzero_trials"] = (hits + 1).into()), "counters.nonzero_trials"),
        ("nzzero", edit(&|s| s["counters"]["nonzero_trials"] = 0.into()), "counters.nonzero_trials"),
        (
            "nzmissing",
            edit(&|s| s["counters"].as_object_mut().unwrap().retain(|k, _| k != "nonzero_trials")),
            "nonzero_trials",
        ),
        ("format1", edit(&|s| s["format"] = "mcrt-noise trace shard 1".into()), "format"),
        // The outside probe, item 15: a real shard of format 1 (no
        // nonzero_trials) was refused as "missing field `nonzero_trials` at
        // line 29", naming neither format.
        (
            "version1",
            edit(&|s| {
                s["format"] = "mcrt-noise trace shard 1".into();
                s["counters"].as_object_mut().unwrap().retain(|k, _| k != "nonzero_trials");
            }),
            "format: expected \"mcrt-noise trace shard 2\", found \"mcrt-noise trace shard 1\"",
        ),
        ("noformat", edit(&|s| s.as_object_mut().unwrap().retain(|k, _| k != "format")), "format: missing"),
    ] {
        let path = dir.join(format!("{tag}.json"));
        std::fs::write(&path, serde_json::to_string(&bad).unwrap()).unwrap();
        let (code, text, err) = ended(&["merge", path.to_str().unwrap()]);
        assert_eq!(code, Some(2), "{tag}: {text}{err}");
        assert!(text.is_empty() && err.contains(&format!("{tag}.json")) && err.contains(needle), "{tag}: {err}");
    }
}

/// The probe: `trace … --out /nonexistent/x.json` failed only after the
/// run, and printed nothing of it.
#[test]
fn trace_checks_its_output_path_before_the_run_and_prints_the_result_if_writing_fails() {
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/point-isotropic.toml");
    let scene = scene.to_str().unwrap();
    // A billion trials would take hours: the bad path must be refused first.
    let (code, text, err) = ended(&["trace", scene, "--trials", "1000000000", "--out", "/nonexistent/x.json"]);
    assert_eq!(code, Some(2), "{text}{err}");
    assert!(text.is_empty() && err.contains("/nonexistent/x.json") && err.contains("--out"), "{err}");
    if std::path::Path::new("/dev/full").exists() {
        // Writable when opened, full when written: the result is printed before the error.
        let (code, text, err) = ended(&["trace", scene, "--trials", "1000", "--out", "/dev/full"]);
        assert_eq!(code, Some(2), "{err}");
        assert!(text.contains("mean L") && err.contains("/dev/full"), "{text}{err}");
    }
}

#[test]
fn every_numeric_flag_is_range_checked_exit_2_naming_flag_value_and_range() {
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/point-isotropic.toml");
    let scene = scene.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["oracle", scene, "--rel-tol", "0"], "'--rel-tol <REL_TOL>': 0 is outside [1e-30, 0.1]"),
        (&["oracle", scene, "--rel-tol", "NaN"], "'--rel-tol <REL_TOL>': NaN is outside [1e-30, 0.1]"),
        (&["oracle", scene, "--rel-tol", "-1"], "'--rel-tol <REL_TOL>': -1 is outside [1e-30, 0.1]"),
        (&["oracle", scene, "--rel-tol", "2"], "'--rel-tol <REL_TOL>': 2 is outside [1e-30, 0.1]"),
        (&["oracle", scene, "--rel-tol", "inf"], "'--rel-tol <REL_TOL>': inf is outside [1e-30, 0.1]"),
        (&["kernel", "--theta", "1", "--radius", "1e-3", "--rel-tol", "0.5"], "--rel-tol"),
        (&["kernel", "--theta", "7", "--radius", "1e-3"], "--theta: 7 is outside (0, π]"),
        (&["kernel", "--theta", "-1", "--radius", "1e-3"], "--theta: -1 is outside (0, π]"),
        (&["kernel", "--theta", "1", "--radius", "-0.001"], "--radius: -0.001 is outside [1e-200, 1e300]"),
        (&["kernel", "--theta", "1", "--radius", "1e-300"], "--radius: 1e-300 is outside [1e-200, 1e300]"),
        (&["trace", scene, "--trials", "10", "--radius", "-0.001"], "-0.001 is outside (0, ∞)"),
        (
            &["trace", scene, "--trials", "10", "--radius", "1e-300"],
            "--radius = 1e-300: must be finite and > 0 with σ_ext",
        ),
        (&["trace", scene, "--trials", "10", "--threads", "1099511627776"], "1099511627776 is outside [1, 1024]"),
        (&["compare", scene, "--trials", "10", "--threads", "0"], "'--threads <THREADS>': 0 is outside [1, 1024]"),
        (&["sweep", scene, "--radii", "1e-2,1e-300"], "--radii: scene has 1 invalid value(s):\n  R = 1e-300"),
        (&["accuracy", "--points", "1099511627776"], "'--points <POINTS>': 1099511627776 is outside [1, 10000000]"),
        (&["cost", "--repeats", "0"], "'--repeats <REPEATS>': 0 is outside [1, 10000]"),
    ];
    for (args, needle) in cases {
        let out = bin().args(*args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(out.stdout.is_empty(), "{args:?}");
        assert!(err.contains(needle), "{args:?}: {needle:?} not in {err}");
        assert!(!err.contains("panicked") && !err.contains("NOT CONVERGED"), "{args:?}: {err}");
    }
}

/// A beam whose axis crosses the camera line behind its disk: the line
/// itself passes just outside the beam (the small-sphere model sees no
/// light), while the spheres of radius R = 0.01 graze it.
const GRAZING_BEAM: &str = r#"
[medium]
sigma_ext = 1.0
albedo = 0.8
[[lights]]
kind = "beam"
center = [0.075, 0.0, 1.075]
direction = [1.0, 0.0, 1.0]
radius = 0.1
flux = 1.0
[camera]
origin = [0.0, 0.0, 0.0]
direction = [0.0, 0.0, 1.0]
[estimator]
radius = 0.01
q = 0.5
forward_rays = 200
camera_rays = 8
"#;

#[test]
fn oracle_names_the_light_grazing_spheres_receive_when_the_camera_ray_misses_every_beam() {
    let dir = temp_dir("grazing");
    let path = dir.join("grazing.toml");
    std::fs::write(&path, GRAZING_BEAM).unwrap();
    let out = bin().arg("oracle").arg(&path).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(out.stdout.is_empty());
    assert!(err.contains("spheres of radius R = 0.01 graze a beam") && !err.contains("meets no light"), "{err}");
    let mean: f64 = err
        .split("mean luminance at this R is ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no finite-sphere mean in {err}"));
    // The tracer measures that light: the message's mean, not "no light".
    let scene = mcrt_noise::Scene::from_toml_str(GRAZING_BEAM).unwrap();
    let tracer = mcrt_noise::reference::Tracer::new(&scene).unwrap();
    let n = 100_000u64;
    let values: Vec<f64> = (0..n).map(|i| tracer.trial(5, i, mcrt_noise::reference::HitMethod::Sorted).0).collect();
    let m = values.iter().sum::<f64>() / n as f64;
    let se = (values.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (n - 1) as f64 / n as f64).sqrt();
    assert!(m > 0.0 && ((m - mean) / se).abs() < 4.0, "tracer {m} ± {se}, oracle's finite-sphere mean {mean}");
    // Moved 1 further off the line: not even the spheres see it.
    std::fs::write(&path, GRAZING_BEAM.replace("center = [0.075, 0.0, 1.075]", "center = [0.075, 1.0, 1.075]"))
        .unwrap();
    let out = bin().arg("oracle").arg(&path).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("meets no light, nor do its spheres of radius R = 0.01"), "{err}");
}

/// `mcrt-noise oracle … | head -2` panicked in `println!` ("failed printing
/// to stdout: Broken pipe") when the reader had gone. A closed pipe now ends
/// the process quietly, as for any Unix filter: nothing on stderr.
#[cfg(unix)]
#[test]
fn a_closed_pipe_ends_quietly_without_a_panic() {
    use std::process::Stdio;
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/point-isotropic.toml");
    let mut child =
        bin().args(["oracle", scene]).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().expect("the binary runs");
    // Close the reading end before the oracle has printed anything.
    drop(child.stdout.take());
    let out = child.wait_with_output().expect("the binary ends");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(stderr.is_empty(), "{stderr}");
}

/// A scene inside every bound of validation whose Var L (≈ 7e-330) is
/// below the smallest double: σ_ext = 1e-10, flux 1e-10, the light at an
/// optical distance of 599 (the bound is 600), σ_ext·R = 0.01.
const VAR_UNDERFLOWS: &str = r#"
[medium]
sigma_ext = 1e-10
albedo = 0.8
[[lights]]
kind = "point"
position = [5.99e12, 0.0, 5.99e10]
flux = 1e-10
[camera]
origin = [0.0, 0.0, 0.0]
direction = [0.0, 0.0, 1.0]
[estimator]
radius = 1e8
q = 0.5
forward_rays = 200
camera_rays = 8
"#;

/// The exit-code policy of `main` (and `--help`, README.md), one case per
/// class: 1 for a computed failure (NOT CONVERGED, the budget or deadline
/// spent, a result not representable in f64), 2 for usage or bad input
/// (a bad flag, a missing or invalid file, an unsupported scene, an output
/// path that cannot be written). Until issue 11 every failure but a failed
/// verdict exited 2, so a script could not tell a typo from a computation
/// that did not converge.
#[test]
fn exit_codes_follow_the_documented_policy() {
    let dir = temp_dir("exit-codes");
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = root.join("scenes/point-isotropic.toml");
    let scene = scene.to_str().unwrap();
    let order1 = root.join("scenes/point-isotropic-order1.toml");
    let order1 = order1.to_str().unwrap();
    let underflows = dir.join("var-underflows.toml");
    std::fs::write(&underflows, VAR_UNDERFLOWS).unwrap();
    let underflows = underflows.to_str().unwrap();
    let invalid = edited_scene("exit-invalid", &[("q = 0.5", "q = 1.5")]);
    let invalid = invalid.to_str().unwrap();
    let order2 = edited_scene("exit-order2", &[("scattering_orders = 0", "scattering_orders = 2")]);
    let order2 = order2.to_str().unwrap();
    let order12 = edited_scene("exit-order12", &[("scattering_orders = 0", "scattering_orders = 12")]);
    let order12 = order12.to_str().unwrap();
    let hg_all = edited_scene(
        "exit-hg-all",
        &[
            ("scattering_orders = 0", "scattering_orders = \"all\""),
            ("kind = \"isotropic\"", "kind = \"henyey-greenstein\"\ng = 0.5"),
        ],
    );
    let hg_all = hg_all.to_str().unwrap();
    let lossless_all = edited_scene(
        "exit-lossless-all",
        &[("scattering_orders = 0", "scattering_orders = \"all\""), ("albedo = 0.8", "albedo = 1.0")],
    );
    let lossless_all = lossless_all.to_str().unwrap();
    let on_ray_all = edited_scene(
        "exit-on-ray-all",
        &[
            ("scattering_orders = 0", "scattering_orders = \"all\""),
            ("position = [1.0, 0.0, 1.0]", "position = [0.0, 0.0, 1.0]"),
        ],
    );
    let on_ray_all = on_ray_all.to_str().unwrap();
    let behind = edited_scene("exit-behind", &[("position = [1.0, 0.0, 1.0]", "position = [0.0, 0.0, -1.0]")]);
    let behind = behind.to_str().unwrap();
    let values = dir.join("values.txt");
    std::fs::write(&values, "1e-3\n2e-3\n3e-3\n4e-3\n").unwrap();
    let values = values.to_str().unwrap();
    let not_a_shard = dir.join("not-a-shard.json");
    std::fs::write(&not_a_shard, "{\"format\": 1}").unwrap();
    let not_a_shard = not_a_shard.to_str().unwrap();
    let cases: &[(&[&str], i32, &str)] = &[
        // Computed failures: exit 1, the reason on stderr.
        (&["oracle", scene, "--max-evals", "1000"], 1, "NOT CONVERGED: the computation's evaluation budget of 1000"),
        (&["oracle", order1, "--time-limit", "0.01"], 1, "time limit"),
        (&["oracle", underflows], 1, "not representable in f64: Var L (small-sphere) is 0e0"),
        (&["kernel", "--theta", "1", "--radius", "1e-3", "--rel-tol", "1e-30"], 1, "NOT CONVERGED"),
        // Usage or bad input: exit 2, the flag, file or field named.
        (&["oracle", scene, "--no-such-flag"], 2, "--no-such-flag"),
        (&["oracle", scene, "--precision", "7"], 2, "--precision \"7\""),
        (&["oracle", "/nonexistent/scene.toml"], 2, "/nonexistent/scene.toml"),
        (&["trace", "/nonexistent/scene.toml", "--trials", "10"], 2, "/nonexistent/scene.toml"),
        (&["oracle", invalid], 2, "estimator.q = 1.5"),
        (&["oracle", order12], 2, "scattering_orders = 12"),
        (&["oracle", order2, "--precision", "128"], 2, "--precision = 128"),
        (&["oracle", order2, "--finite-pairs", "--rel-tol", "1e-3"], 2, "--finite-pairs"),
        (&["oracle", order2, "--rel-tol", "1e-9"], 2, "--rel-tol = 1e-9"),
        (&["oracle", hg_all, "--max-evals", "1000"], 2, "medium.phase.kind"),
        (&["oracle", lossless_all, "--max-evals", "1000"], 2, "albedo = 1"),
        (&["oracle", on_ray_all, "--max-evals", "1000"], 2, "lights[0].position"),
        (&["check", order2, "--values", values], 2, "oracle: unsupported"),
        (&["sweep", behind, "--radii", "1e-2,1e-3"], 2, "the R → 0 form of (23) does not exist for this scene"),
        (&["kernel", "--theta", "abc", "--radius", "1e-3"], 2, "--theta"),
        (&["merge", not_a_shard], 2, "not-a-shard.json"),
        (&["trace", scene, "--trials", "10", "--out", "/nonexistent/x.json"], 2, "--out /nonexistent/x.json"),
        (&["accuracy", "--points", "1", "--out", "/nonexistent/x.md"], 2, "--out /nonexistent/x.md"),
        (&["model-error", "--scenes", "/nonexistent", "--out", "/nonexistent/x.md"], 2, "--scenes /nonexistent"),
    ];
    for (args, code, needle) in cases {
        let (got, text, err) = ended(args);
        assert_eq!(got, Some(*code), "{args:?}: {text}{err}");
        assert!(text.is_empty(), "{args:?}: printed {text}");
        assert!(err.contains(needle), "{args:?}: {needle:?} not in {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

/// `--help` states the exit codes, as README.md does.
#[test]
fn help_states_the_exit_codes() {
    let out = bin().arg("--help").output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success());
    for needle in ["Exit codes:", "0  done", "1  a computed failure", "2  usage or bad input"] {
        assert!(text.contains(needle), "{needle:?} not in {text}");
    }
}

// ---- Adversarial probe of trace, merge, compare (branch fix-tracer-robustness) ----

/// A bundled scene's path.
fn bundled(name: &str) -> String {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name).to_str().unwrap().to_string()
}

/// The probe: `compare scenes/point-hg-forward.toml --trials 300 --seed 36`
/// said DISAGREE with z = −160 for Var L from a run with a single hit (11
/// of seeds 1–40 said DISAGREE). Standard errors from a handful of nonzero
/// trials are meaningless: below 100 trials with hits the run is not
/// resolved (exit 1), and `compare` says NOT RESOLVED, never a z-score.
#[test]
fn barely_hit_runs_are_not_resolved_and_never_disagree() {
    let scene = bundled("point-hg-forward.toml");
    let (code, text, err) = ended(&["compare", &scene, "--trials", "300", "--seed", "36"]);
    assert_eq!(code, Some(1), "{text}{err}");
    assert!(err.is_empty(), "{err}");
    assert!(text.contains("NOT RESOLVED: only 1 of 300 trials had hits"), "{text}");
    assert!(text.contains("at least 100") && !text.contains("DISAGREE") && !text.contains("z ="), "{text}");
    let (code, json, _) = ended(&["compare", &scene, "--trials", "300", "--seed", "36", "--json"]);
    assert_eq!(code, Some(1));
    let json: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert!(json["mean"].is_null() && json["variance"].is_null() && json["pass"] == false, "{json}");
    // `trace` of the same run: the reason instead of mean ± s.e., exit 1.
    let (code, text, _) = ended(&["trace", &scene, "--trials", "300", "--seed", "36"]);
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("only 1 of 300 trials had hits") && !text.contains(" ± "), "{text}");
    // Every seed of the probe: not resolved (exit 1), the count of trials with hits stated.
    for seed in 1..=40 {
        let seed = seed.to_string();
        let (code, json, err) = ended(&["trace", &scene, "--trials", "300", "--seed", &seed, "--json"]);
        assert_eq!(code, Some(1), "seed {seed}: {json}{err}");
        let json: serde_json::Value = serde_json::from_str(&json).unwrap();
        let k = json["counters"]["nonzero_trials"].as_u64().unwrap_or_else(|| panic!("seed {seed}: {json}"));
        let why = json["not_resolved"].as_str().unwrap();
        let hits = json["counters"]["hits"].as_u64().unwrap();
        assert!(k <= hits && (k == 0) == (hits == 0), "seed {seed}: {json}");
        if k == 0 {
            assert!(why.starts_with("no hits in 300 trials"), "seed {seed}: {why}");
        } else {
            assert!(why.starts_with(&format!("only {k} of 300 trials had hits")), "seed {seed}: {why}");
        }
        assert!(json["mean"].is_null() && json["variance"].is_null(), "seed {seed}: {json}");
    }
}

/// A shard of `point-isotropic` with R = 0.05, 2000 trials, seed 5
/// (resolved: several hundred trials with hits), written to `path`.
fn resolved_shard(path: &std::path::Path, range: &str) -> serde_json::Value {
    let scene = bundled("point-isotropic.toml");
    let p = path.to_str().unwrap();
    let json =
        trace_json(&["trace", &scene, "--radius", "0.05", "--trials", range, "--seed", "5", "--json", "--out", p]);
    assert!(json["mean"]["se"].as_f64().is_some_and(|se| se > 0.0), "{json}");
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Exact sums as a shard stores them (canonical hexadecimal).
fn hex_sums(count: u64, sums: [f64; 4]) -> [String; 4] {
    mcrt_noise::reference::moments::PowerSums::from_f64_sums(count, sums).unwrap().to_hex()
}

/// The probe: `merge` accepted a shard with Σ L = −1 (every L is a sum of
/// non-negative contributions), and sums no non-negative numbers have.
#[test]
fn merge_refuses_sums_no_non_negative_luminances_have() {
    let dir = temp_dir("negsums");
    let good_path = dir.join("good.json");
    let good = resolved_shard(&good_path, "2000");
    let n = good["counters"]["trials"].as_u64().unwrap();
    let negated = |k: usize| {
        let mut sums: Vec<String> = (0..4).map(|j| good["sums"][j].as_str().unwrap().to_string()).collect();
        assert!(!sums[k].starts_with('-'));
        sums[k] = format!("-{}", sums[k]);
        sums
    };
    for (tag, sums, needle) in [
        // Σ L < 0 and Σ L³ < 0, the rest unchanged (each passes the real-number checks).
        ("negsum1", negated(0), "sums[0]"),
        ("negsum3", negated(2), "sums[2]"),
        // (Σ L²)² > Σ L · Σ L³, and (Σ L³)² > Σ L² · Σ L⁴: real, but not non-negative numbers.
        ("cs1", hex_sums(n, [1.0, 2.0, 1.0, 16.0]).to_vec(), "sums"),
        ("cs2", hex_sums(n, [1.0, 1.0, 2.0, 1.0]).to_vec(), "sums"),
    ] {
        let mut shard = good.clone();
        shard["sums"] = serde_json::json!(sums);
        let path = dir.join(format!("{tag}.json"));
        std::fs::write(&path, serde_json::to_string(&shard).unwrap()).unwrap();
        let (code, text, err) = ended(&["merge", path.to_str().unwrap()]);
        assert_eq!(code, Some(2), "{tag}: {text}{err}");
        assert!(text.is_empty() && err.contains(&format!("{tag}.json")) && err.contains(needle), "{tag}: {err}");
        assert!(err.contains("non-negative"), "{tag}: {err}");
    }
}

/// The probe: `merge` printed `time 0.0 ms (0.000e0 trials/s, …)`, a zero
/// standing in for a time nobody measured. Merged shards say so instead.
#[test]
fn merge_says_the_time_of_merged_shards_is_not_measured() {
    let dir = temp_dir("mergetime");
    let (a, b) = (dir.join("a.json"), dir.join("b.json"));
    resolved_shard(&a, "0..1000");
    resolved_shard(&b, "1000..2000");
    let (a, b) = (a.to_str().unwrap(), b.to_str().unwrap());
    let (code, text, err) = ended(&["merge", a, b]);
    assert_eq!(code, Some(0), "{text}{err}");
    assert!(text.contains("time not measured") && !text.contains("0.0 ms") && !text.contains("0.000e0"), "{text}");
    let json = trace_json(&["merge", a, b, "--json"]);
    for key in ["wall_time_ms", "trials_per_second", "forward_segments_per_second"] {
        assert!(json[key].is_null(), "{key}: {json}");
    }
    assert!(json["time_not_measured"].as_str().unwrap().contains("merged"), "{json}");
    // `trace` measures its time: numbers, no reason.
    let json = trace_json(&["trace", &bundled("point-isotropic.toml"), "--trials", "20000", "--json"]);
    assert!(json["wall_time_ms"].as_f64().is_some_and(|t| t > 0.0) && json["time_not_measured"].is_null(), "{json}");
}

/// The probe: `trace self.toml --trials 100 --out self.toml` exited 0 and
/// replaced the scene file with the shard; `merge a.json b.json --out
/// a.json` replaced a shard. An output that is one of the inputs is refused
/// before the run (exit 2), however the path is spelled, and the input is
/// left as it was.
#[test]
fn an_output_path_that_is_an_input_is_refused_before_the_run() {
    let dir = temp_dir("outisinput");
    let scene = dir.join("self.toml");
    std::fs::copy(bundled("point-isotropic.toml"), &scene).unwrap();
    let original = std::fs::read(&scene).unwrap();
    let s = scene.to_str().unwrap();
    let spelled_otherwise = dir.join("sub/../self.toml");
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    let link = dir.join("link.toml");
    std::fs::remove_file(&link).ok();
    std::fs::hard_link(&scene, &link).unwrap();
    for out in [s, spelled_otherwise.to_str().unwrap(), link.to_str().unwrap()] {
        // A billion trials would take hours: refused before the run.
        let (code, text, err) = ended(&["trace", s, "--trials", "1000000000", "--out", out]);
        assert_eq!(code, Some(2), "{out}: {text}{err}");
        assert!(text.is_empty() && err.contains(&format!("--out {out}")) && err.contains("scene file"), "{err}");
        assert_eq!(std::fs::read(&scene).unwrap(), original, "{out}: the scene file was changed");
    }
    let (a, b) = (dir.join("a.json"), dir.join("b.json"));
    resolved_shard(&a, "0..1000");
    resolved_shard(&b, "1000..2000");
    let shard_a = std::fs::read(&a).unwrap();
    let (a, b) = (a.to_str().unwrap(), b.to_str().unwrap());
    let (code, text, err) = ended(&["merge", a, b, "--out", a]);
    assert_eq!(code, Some(2), "{text}{err}");
    assert!(text.is_empty() && err.contains(&format!("--out {a}")) && err.contains("shard"), "{err}");
    assert_eq!(std::fs::read(a).unwrap(), shard_a, "the shard was changed");
    // A new path is written as before.
    let merged = dir.join("merged.json");
    std::fs::remove_file(&merged).ok();
    let (code, _, err) = ended(&["merge", a, b, "--out", merged.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{err}");
    assert!(merged.exists());
}

/// The probe: `trace --trials -5` and `--seed -1` got clap's "unexpected
/// argument '-5' found", naming neither the flag nor its range. Every
/// numeric flag of trace, compare (and oracle, sweep) names itself, the
/// value and the range (exit 2).
#[test]
fn negative_numbers_for_numeric_flags_name_the_flag_the_value_and_the_range() {
    let scene = bundled("point-isotropic.toml");
    let s = scene.as_str();
    let cases: &[(&[&str], &[&str])] = &[
        (&["trace", s, "--trials", "-5"], &["--trials", "\"-5\"", "[1, 18446744073709551615]"]),
        (&["trace", s, "--trials", "-5..10"], &["--trials", "\"-5..10\"", "A..B"]),
        (&["compare", s, "--trials", "-5"], &["--trials", "\"-5\"", "[1, 18446744073709551615]"]),
        (&["trace", s, "--trials", "10", "--seed", "-1"], &["--seed", "-1", "[0, 18446744073709551615]"]),
        (&["compare", s, "--trials", "10", "--seed", "-1"], &["--seed", "-1", "[0, 18446744073709551615]"]),
        (&["trace", s, "--trials", "10", "--seed", "1.5"], &["--seed", "1.5", "[0, 18446744073709551615]"]),
        (&["trace", s, "--trials", "10", "--threads", "-1"], &["--threads", "-1", "[1, 1024]"]),
        (&["oracle", s, "--max-evals", "-5"], &["--max-evals", "-5", "[1, 1e15]"]),
        (&["oracle", s, "--time-limit", "-1"], &["--time-limit", "-1", "(0, 1e6]"]),
        (&["sweep", s, "--radii", "-1,2"], &["--radii", "-1", "finite and > 0"]),
    ];
    for (args, needles) in cases {
        let (code, text, err) = ended(args);
        assert_eq!(code, Some(2), "{args:?}: {text}{err}");
        assert!(text.is_empty(), "{args:?}: {text}");
        assert!(!err.contains("unexpected argument"), "{args:?}: {err}");
        for needle in *needles {
            assert!(err.contains(needle), "{args:?}: {needle:?} not in {err}");
        }
    }
}

/// The probe: `compare` printed `ratio 0.68368` with no bar. The ratio
/// carries the tracer's standard error and the oracle's bar, propagated.
#[test]
fn compare_gives_the_ratio_its_bar() {
    let scene = bundled("point-isotropic.toml");
    let json = trace_json(&["compare", &scene, "--trials", "20000", "--seed", "3", "--json"]);
    for side in ["mean", "variance"] {
        let f = |k: &str| json[side][k].as_f64().unwrap_or_else(|| panic!("{side}.{k}: {json}"));
        let (o, bar, t, se, r, dr) =
            (f("oracle"), f("oracle_error"), f("tracer"), f("tracer_se"), f("ratio"), f("ratio_error"));
        let want = r * ((se / t).powi(2) + (bar / o).powi(2)).sqrt();
        assert!(dr > 0.0 && ((dr - want) / want).abs() < 1e-12, "{side}: ratio {r} ± {dr}, want ± {want}");
    }
    let (code, text, err) = ended(&["compare", &scene, "--trials", "20000", "--seed", "3"]);
    assert_eq!(code, Some(0), "{text}{err}");
    for line in text.lines().filter(|l| l.starts_with("mean L") || l.starts_with("Var L")) {
        let ratio = line.split("ratio ").nth(1).unwrap_or_else(|| panic!("{line}"));
        let bar = ratio.split_whitespace().collect::<Vec<_>>();
        assert!(bar.len() >= 3 && bar[1] == "±" && bar[2].parse::<f64>().is_ok_and(|x| x > 0.0), "{line}");
    }
}

/// The outside probe, item 5: `kernel --theta 8@0 --radius 1` computed at
/// ϑ = 8 (exit 0): the flags are read by MPFR's parser, which takes `@`
/// exponents, `_` separators and hexadecimal, while the range check parsed
/// them as f64 and skipped what it could not read. Every kernel flag must be
/// a plain decimal (or `pi`, `pi/2` for ϑ) and is range-checked at the
/// working precision: exit 2 naming the flag and the value, nothing on
/// standard output.
#[test]
fn kernel_flags_take_plain_decimals_in_range_at_the_working_precision() {
    let cases: &[(&[&str], &str)] = &[
        (&["--theta", "8@0", "--radius", "1"], "--theta: \"8@0\" is not a plain decimal"),
        (&["--theta", "7_0", "--radius", "1"], "--theta: \"7_0\" is not a plain decimal"),
        (&["--theta", "6.5@0", "--radius", "1"], "--theta: \"6.5@0\" is not a plain decimal"),
        (&["--theta", "0x1p1", "--radius", "1"], "--theta: \"0x1p1\" is not a plain decimal"),
        (&["--theta", "inf", "--radius", "1"], "--theta: \"inf\" is not a plain decimal"),
        (&["--theta", "1", "--radius", "1@301"], "--radius: \"1@301\" is not a plain decimal"),
        (&["--theta", "1", "--radius", "1@-250"], "--radius: \"1@-250\" is not a plain decimal"),
        (&["--theta", "1", "--radius", "1_0"], "--radius: \"1_0\" is not a plain decimal"),
        // Beyond the range only at the working precision (256 bits), where
        // f64 rounds them onto its ends.
        (
            &["--theta", "1", "--radius", "1.0000000000000000000001e300", "--precision", "256"],
            "--radius: 1.0000000000000000000001e300 is outside [1e-200, 1e300]",
        ),
        (
            &["--theta", "1", "--radius", "0.99999999999999999999999e-200", "--precision", "256"],
            "--radius: 0.99999999999999999999999e-200 is outside [1e-200, 1e300]",
        ),
        (
            &[
                "--theta",
                "3.14159265358979323846264338327950288419716939937510582097494459231",
                "--radius",
                "1",
                "--precision",
                "256",
            ],
            "is outside (0, π]",
        ),
    ];
    for (args, needle) in cases {
        let out = bin().arg("kernel").args(*args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}{err}", String::from_utf8_lossy(&out.stdout));
        assert!(out.stdout.is_empty(), "{args:?}");
        assert!(err.contains(needle), "{args:?}: {needle:?} not in {err}");
    }
    for theta in ["pi", "pi/2", ".5", "1e0", "+1"] {
        let out = bin().args(["kernel", "--theta", theta, "--radius", "1e-3"]).output().unwrap();
        assert!(out.status.success(), "{theta}: {}", String::from_utf8_lossy(&out.stderr));
    }
}
