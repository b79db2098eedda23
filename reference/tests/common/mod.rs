//! Scenes for the tracer's tests: the bundled ones, edited.

#![allow(dead_code)]

use mcrt_scene::Scene;
use std::path::Path;

/// A bundled scene (`scenes/NAME.toml`) with text replacements applied.
pub fn scene(name: &str, edits: &[(&str, &str)]) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes").join(format!("{name}.toml"));
    let mut text = std::fs::read_to_string(&path).unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "{name}: no \"{from}\" to replace");
        text = text.replacen(from, to, 1);
    }
    Scene::from_toml_str(&text).unwrap()
}
