//! Scenes for the tracer's tests (the bundled ones, edited) and the
//! shard-refusal check they share.

#![allow(dead_code)]

use mcrt_reference::{Run, Shard};
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

/// `good` with `edit` applied must be refused on read, with an error that
/// contains `needle` (the field or rule it breaks).
pub fn assert_shard_refused(good: &Shard, edit: &dyn Fn(&mut Shard), needle: &str) {
    let mut shard = good.clone();
    edit(&mut shard);
    let err = Run::from_shard(&shard).unwrap_err();
    assert!(err.contains(needle), "{needle}: {err}");
}
