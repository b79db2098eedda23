//! Output paths and `--scenes` directories, checked before a run (the
//! outside probe, items 9 and 10): a path that cannot be written, or a
//! scenes directory that is missing, empty, not a directory or holds an
//! invalid scene, is refused at once with exit 2 naming the flag and the
//! path, nothing on standard output. These runs took minutes and then
//! failed with exit 1 (`tracer-checks --out` into a read-only directory:
//! 271 s, "Operation not permitted", no path), or failed as a computation
//! (exit 1) on bad input.

use std::path::PathBuf;
use std::process::{Command, Stdio};

/// Exit code, stdout, stderr of a run that must end within 20 s (each of
/// these is refused before any work; the runs they stand for take minutes).
fn refused(args: &[&str]) -> (Option<i32>, String, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_mcrt-noise"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed().as_secs() >= 20 {
            child.kill().ok();
            child.wait().ok();
            panic!("{args:?}: still running after 20 s (the path was not checked before the run)");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    (out.status.code(), String::from_utf8_lossy(&out.stdout).into(), String::from_utf8_lossy(&out.stderr).into())
}

fn assert_refused(args: &[&str], needles: &[&str]) {
    let (code, text, err) = refused(args);
    assert_eq!(code, Some(2), "{args:?}: {text}{err}");
    assert!(text.is_empty(), "{args:?}: printed {text}");
    for needle in needles {
        assert!(err.contains(needle), "{args:?}: {needle:?} not in {err}");
    }
}

/// A fresh directory of this test process.
fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mcrt-noise-paths-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `/proc` takes no new files, even from root: every generating command,
/// and `optimize --maps`, is refused before its run, naming the flag and
/// the path.
#[cfg(target_os = "linux")]
#[test]
fn unwritable_outputs_are_refused_before_the_run() {
    let out = "/proc/mcrt-noise-no-such-file.md";
    for cmd in ["tracer-checks", "choosing-parameters", "model-error", "asymptotic-checks", "cost"] {
        assert_refused(&[cmd, "--out", out], &[&format!("--out {out}: cannot be written")]);
    }
    assert_refused(&["accuracy", "--points", "1", "--out", out], &[&format!("--out {out}: cannot be written")]);
    assert_refused(
        &["optimize", "scenes/point-isotropic.toml", "--budget", "1", "--maps", "/proc/mcrt-noise-maps"],
        &["--maps /proc/mcrt-noise-maps: cannot be written"],
    );
    assert_refused(&["calibrate", "--out", out], &[&format!("--out {out}: cannot be written")]);
}

/// The document goes to a writable directory, but its figures directory
/// beside it cannot be made (a file named `figures` is there): refused
/// before the run, naming `--out` and the figures directory; the file is
/// left as it was.
#[test]
fn an_unwritable_figures_directory_is_refused_naming_out() {
    let dir = temp_dir("figures");
    std::fs::write(dir.join("figures"), "a file").unwrap();
    let out = dir.join("doc.md");
    let out = out.to_str().unwrap();
    for cmd in ["model-error", "tracer-checks", "cost"] {
        assert_refused(&[cmd, "--out", out], &[&format!("--out {out}: its figures directory"), "not a directory"]);
    }
    assert_eq!(std::fs::read_to_string(dir.join("figures")).unwrap(), "a file");
    assert!(!dir.join("doc.md").exists());
    // A missing directory for the document itself names --out, not figures.
    let missing = dir.join("missing").join("doc.md");
    let missing = missing.to_str().unwrap();
    assert_refused(&["model-error", "--out", missing], &[&format!("--out {missing}: cannot be written")]);
}

/// `CMD --scenes SCENES [--out OUT]` (`calibrate` writes no document).
fn args<'a>(cmd: &'a str, scenes: &'a str, out: &'a str) -> Vec<&'a str> {
    let mut v = vec![cmd, "--scenes", scenes];
    if cmd != "calibrate" {
        v.extend(["--out", out]);
    }
    v
}

/// `--scenes` missing, a file, empty, or holding an invalid scene that the
/// command reads: exit 2 naming `--scenes` and the file.
#[test]
fn bad_scenes_directories_are_refused_naming_the_file() {
    let empty = temp_dir("empty");
    let invalid = temp_dir("invalid");
    for entry in std::fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes")).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, invalid.join(path.file_name().unwrap())).unwrap();
    }
    let beam = invalid.join("beam-isotropic.toml");
    let text = std::fs::read_to_string(&beam).unwrap();
    std::fs::write(&beam, text.replace("q = 0.5", "q = 7")).unwrap();
    let out = temp_dir("scenes-out").join("doc.md");
    let out = out.to_str().unwrap();
    let (empty, invalid, beam) = (empty.to_str().unwrap(), invalid.to_str().unwrap(), beam.to_str().unwrap());
    for cmd in ["model-error", "calibrate", "asymptotic-checks", "tracer-checks", "choosing-parameters"] {
        assert_refused(&args(cmd, "/nonexistent-scenes", out), &["--scenes /nonexistent-scenes: no such directory"]);
        assert_refused(&args(cmd, "README.md", out), &["--scenes README.md: not a directory"]);
        let needle = if cmd == "asymptotic-checks" { "holds no scene files".to_string() } else { format!("{empty}/") };
        assert_refused(&args(cmd, empty, out), &[&format!("--scenes {empty}: "), &needle]);
        if cmd != "tracer-checks" {
            // tracer-checks reads no beam scene.
            assert_refused(&args(cmd, invalid, out), &[&format!("--scenes {invalid}: {beam}"), "estimator.q = 7"]);
        }
    }
    assert!(!std::path::Path::new(out).exists(), "nothing written");
}

/// `trace --out` truncated an existing file before the run: a run that was
/// interrupted (or failed) left the shard there empty. The path is now
/// checked without changing it and written after the run: a run of 10⁹
/// trials, killed after 2 s, leaves the file as it was.
#[test]
fn an_interrupted_trace_leaves_its_out_file_as_it_was() {
    let dir = temp_dir("keep");
    let out = dir.join("shard.json");
    std::fs::write(&out, "{\"an earlier\": \"shard\"}").unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_mcrt-noise"))
        .args(["trace", "scenes/point-isotropic.toml", "--trials", "1000000000", "--out", out.to_str().unwrap()])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_secs(2));
    assert!(child.try_wait().unwrap().is_none(), "10⁹ trials cannot have ended in 2 s");
    child.kill().unwrap();
    child.wait().unwrap();
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "{\"an earlier\": \"shard\"}");
}
