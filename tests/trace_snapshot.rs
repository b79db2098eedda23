//! `mcrt-noise trace --json` of every bundled scene at a fixed seed and trial
//! count, pinned. The run is bit-reproducible (exact sums, per-trial
//! streams); floats are stored at 10 significant digits so that a platform
//! whose libm rounds ln, sin or cos differently in the last bit still
//! matches, while any change of the estimator or its statistics shows.
//! Wall time and rates are removed (they are not reproducible).

use serde_json::Value;
use std::path::Path;
use std::process::Command;

fn rounded(v: &Value) -> Value {
    match v {
        Value::Number(n) if n.is_f64() => Value::String(format!("{:.9e}", n.as_f64().unwrap())),
        Value::Array(a) => Value::Array(a.iter().map(rounded).collect()),
        Value::Object(o) => Value::Object(o.iter().map(|(k, v)| (k.clone(), rounded(v))).collect()),
        other => other.clone(),
    }
}

#[test]
fn trace_json_of_every_bundled_scene_is_pinned() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut names: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    names.sort();
    for path in names {
        let out = Command::new(env!("CARGO_BIN_EXE_mcrt-noise"))
            .args(["trace", "--trials", "20000", "--seed", "2026", "--threads", "2", "--json"])
            .arg(&path)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}: {}", path.display(), String::from_utf8_lossy(&out.stderr));
        let mut json: Value = serde_json::from_slice(&out.stdout).unwrap();
        let obj = json.as_object_mut().unwrap();
        for key in ["wall_time_ms", "trials_per_second", "forward_segments_per_second"] {
            assert!(obj.remove(key).is_some(), "{key} missing");
        }
        for key in ["mean", "variance"] {
            assert!(obj[key]["value"].is_f64() && obj[key]["se"].is_f64(), "{key}: value and se");
        }
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let text = serde_json::to_string_pretty(&rounded(&json)).unwrap();
        insta::with_settings!({snapshot_path => "../snapshots", prepend_module_to_snapshot => false}, {
            insta::assert_snapshot!(format!("trace_{name}"), text);
        });
    }
}
