//! Paths checked before a run (exit 2 naming the flag and the path): an
//! output file or directory that cannot be written, a `--scenes`
//! directory that is missing, empty or holds an invalid scene. A run of
//! minutes used to find them at its end (`tracer-checks --out` into a
//! read-only directory: exit 1 after 271 s, "Operation not permitted", no
//! path), or to fail as a computation (exit 1) on bad input.

use super::CliError;
use mcrt_noise::scene::Scene;
use std::fs::OpenOptions;
use std::path::{Path, PathBuf};

/// The directory a file `path` goes into (`.` for a bare name).
fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// `flag PATH` can be written, checked without changing anything that is
/// there: its directory exists and takes a new file (one is created and
/// removed), and an existing file opens for writing (to append, so its
/// content stays until the run has a result).
pub fn writable_file(flag: &str, path: &Path) -> Result<(), CliError> {
    let cannot = |why: String| CliError::usage(format!("{flag} {}: cannot be written: {why}", path.display()));
    if path.is_dir() {
        return Err(cannot("is a directory".into()));
    }
    let dir = parent_dir(path);
    if !dir.is_dir() {
        return Err(cannot(format!("{} is not a directory", dir.display())));
    }
    if path.exists() {
        OpenOptions::new().append(true).open(path).map_err(|e| cannot(e.to_string()))?;
        return Ok(());
    }
    OpenOptions::new().write(true).create_new(true).open(path).map_err(|e| cannot(e.to_string()))?;
    std::fs::remove_file(path).map_err(|e| cannot(e.to_string()))
}

/// Files can be written into the directory `dir`, named in a refusal as
/// `label` (`--maps DIR`, or `--out FILE: its figures directory DIR`): it
/// is created if missing, and a file is created in it and removed.
pub fn writable_dir(label: &str, dir: &Path) -> Result<(), CliError> {
    let cannot = |why: String| CliError::usage(format!("{label}: cannot be written: {why}"));
    if dir.exists() && !dir.is_dir() {
        return Err(cannot("exists and is not a directory".into()));
    }
    std::fs::create_dir_all(dir).map_err(|e| cannot(e.to_string()))?;
    let probe = dir.join(format!(".mcrt-noise-write-check-{}", std::process::id()));
    OpenOptions::new().write(true).create_new(true).open(&probe).map_err(|e| cannot(e.to_string()))?;
    std::fs::remove_file(&probe).map_err(|e| cannot(e.to_string()))
}

/// The scenes a command reads from its `--scenes` directory.
pub enum Needed<'a> {
    /// These names (`NAME.toml` each).
    Named(&'a [&'a str]),
    /// Every `*.toml` in it, at least one.
    All,
}

/// `--scenes DIR` holds the scenes the command reads, each a valid scene
/// file: else exit 2 naming the flag, the directory and the file.
pub fn scenes_dir(dir: &Path, needed: Needed<'_>) -> Result<(), CliError> {
    let bad = |why: String| CliError::usage(format!("--scenes {}: {why}", dir.display()));
    if !dir.exists() {
        return Err(bad("no such directory".into()));
    }
    if !dir.is_dir() {
        return Err(bad("not a directory".into()));
    }
    let files: Vec<PathBuf> = match needed {
        Needed::Named(names) => names.iter().map(|n| dir.join(format!("{n}.toml"))).collect(),
        Needed::All => {
            let mut all: Vec<PathBuf> = std::fs::read_dir(dir)
                .map_err(|e| bad(e.to_string()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "toml"))
                .collect();
            all.sort();
            if all.is_empty() {
                return Err(bad("holds no scene files (*.toml)".into()));
            }
            all
        }
    };
    for file in files {
        let text = std::fs::read_to_string(&file)
            .map_err(|e| bad(format!("{}: {e} (this command reads it)", file.display())))?;
        Scene::from_toml_str(&text).map_err(|e| bad(format!("{}: {e}", file.display())))?;
    }
    Ok(())
}
