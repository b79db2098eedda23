//! `mcrt-noise optimize` and `mcrt-noise calibrate`.

use super::CliError;
use mcrt_noise::quad::Budget;
use mcrt_noise::reports;
use mcrt_noise::scene::Scene;
use mcrt_noise::tuning::cost::CostTable;
use mcrt_noise::tuning::radii::RadiusCache;
use mcrt_noise::tuning::Searched;
use mcrt_noise::tuning::{maps, optimize_with, Options, TuningError};
use std::path::{Path, PathBuf};

impl From<TuningError> for CliError {
    fn from(e: TuningError) -> Self {
        match e {
            TuningError::Oracle(o) => CliError::from(o),
            TuningError::Infeasible(m) => CliError::Computed(m),
            TuningError::Radius(..) | TuningError::Option(_) => CliError::Usage(e.to_string()),
        }
    }
}

/// The flags of `optimize`.
pub struct OptimizeArgs<'a> {
    /// The scene file.
    pub scene: &'a Path,
    /// T, seconds of one core.
    pub budget: f64,
    /// A costs file (a `[cost]` table), overriding the scene's.
    pub costs: Option<&'a Path>,
    /// Spheres per iteration at most.
    pub max_spheres: Option<f64>,
    /// R searched over [lo, hi].
    pub radius_range: Option<(f64, f64)>,
    /// Write the two SVG maps into this directory.
    pub maps: Option<&'a Path>,
    /// JSON instead of text.
    pub json: bool,
}

/// The costs: `--costs FILE`, else the scene's `[cost]`, else the reference machine's.
fn costs_for(scene: &Scene, file: Option<&Path>) -> Result<CostTable, CliError> {
    if let Some(path) = file {
        let text =
            std::fs::read_to_string(path).map_err(|e| CliError::usage(format!("--costs {}: {e}", path.display())))?;
        let costs =
            parse_costs(&text, path).map_err(|e| CliError::usage(format!("--costs {}: {e}", path.display())))?;
        costs.validate().map_err(|e| CliError::usage(format!("--costs {}: {e}", path.display())))?;
        return Ok(costs);
    }
    Ok(CostTable::from_scene(scene).unwrap_or_else(|| {
        let mut c = CostTable::reference_machine();
        c.source = "the reference machine's (this tracer on 2 cores, one thread timed; run `mcrt-noise calibrate` for \
                    this machine's, or give a renderer's in a [cost] table)"
            .into();
        c
    }))
}

/// A `[cost]` table in a file of its own (as `calibrate --out` writes it),
/// with the keys and checks of a scene's `[cost]` table.
fn parse_costs(text: &str, path: &Path) -> Result<CostTable, String> {
    let k = mcrt_noise::scene::Cost::from_toml_str(text).map_err(|e| e.to_string())?;
    Ok(CostTable::from_array(k.ns, k.std_errors, format!("the --costs file {}", path.display())))
}

/// `optimize`.
pub fn optimize_cmd(a: &OptimizeArgs<'_>, load: impl Fn(&PathBuf) -> Result<Scene, CliError>) -> Result<(), CliError> {
    let scene = load(&a.scene.to_path_buf())?;
    if let (Some(dir), Searched::StandardMethod) = (a.maps, Searched::of(&scene)) {
        return Err(CliError::usage(format!(
            "--maps {}: the maps vary q and N_B, which optimize holds at 1 for this scene's {} (the finite-sphere \
             model gives its Var L at q = 1 and N_B = 1 only: docs/model.md {}); omit --maps",
            dir.display(),
            if scene.effects.scattering_orders == mcrt_noise::ScatteringOrders::Limited(1) {
                "single-scattered light"
            } else {
                "scattered light of every order"
            },
            if scene.effects.scattering_orders == mcrt_noise::ScatteringOrders::Limited(1) {
                "§9.7"
            } else {
                "§10.4"
            }
        )));
    }
    if let Some(dir) = a.maps {
        super::paths::writable_dir(&format!("--maps {}", dir.display()), dir)?;
    }
    let mut opts = Options::new(a.budget, costs_for(&scene, a.costs)?);
    opts.max_spheres = a.max_spheres;
    opts.radius_range = a.radius_range;
    if mcrt_noise::tuning::every_order(&scene) {
        // A finite order's Var L needs up to 1.4·10⁹ evaluations a radius
        // (order 9), more than the default: what `predict` gives it.
        opts.evaluations = mcrt_noise::prec::EVERY_ORDER_PREDICTION_EVALUATIONS;
    }
    let mut cache = RadiusCache::new(&scene, Budget::new(opts.evaluations), None);
    let optimum = optimize_with(&scene, &opts, &mut cache).map_err(|e| CliError::from(e).at(a.scene.display()))?;
    if let Some(dir) = a.maps {
        let n = 33;
        let range = optimum.radius_range;
        if optimum.bias_predicted {
            let m = maps::q_and_radius(&scene, &opts, &mut cache, &optimum.best, range, n)?;
            write_svg(dir, "rmse-q-radius.svg", &reports::heatmap::svg("predicted rel. RMSE over (q, R)", &m))?;
        }
        let m = maps::q_and_ray_ratio(&scene, &opts, &mut cache, &optimum.best, n)?;
        write_svg(dir, "rmse-q-ray-ratio.svg", &reports::heatmap::svg("predicted rel. RMSE over (q, N_B/N_F)", &m))?;
    }
    if a.json {
        println!("{}", super::to_json(&optimum)?);
    } else {
        print!("{}", reports::optimum::text(&a.scene.display().to_string(), &optimum));
    }
    Ok(())
}

fn write_svg(dir: &Path, name: &str, svg: &str) -> Result<(), CliError> {
    let path = dir.join(name);
    std::fs::write(&path, svg).map_err(|e| CliError::usage(format!("--maps {}: {e}", path.display())))
}

/// `calibrate --out`: writable (checked without truncating it: a failed
/// calibration must not destroy an existing costs file) and not in the
/// scenes directory the calibration reads.
fn check_out(path: &Path, scenes: &Path) -> Result<(), CliError> {
    super::paths::writable_file("--out", path)?;
    let bad = |why: String| CliError::usage(format!("--out {}: {why}", path.display()));
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let (dir, scenes) = (dir.canonicalize().map_err(|e| bad(e.to_string()))?, scenes.canonicalize().ok());
    if scenes.is_some_and(|s| dir.starts_with(s)) {
        return Err(bad("is inside the scenes directory the calibration reads; write it elsewhere".into()));
    }
    Ok(())
}

/// `calibrate`.
pub fn calibrate_cmd(scenes: &Path, seconds: f64, out: Option<&Path>, json: bool) -> Result<(), CliError> {
    if !(seconds.is_finite() && (0.05..=600.0).contains(&seconds)) {
        return Err(CliError::usage(format!("--seconds {seconds}: must be in [0.05, 600] seconds per case")));
    }
    let names = reports::calibrate::scene_names();
    super::paths::scenes_dir(scenes, super::paths::Needed::Named(&names))?;
    if let Some(path) = out {
        check_out(path, scenes)?;
    }
    let source = format!(
        "calibrated by `mcrt-noise calibrate` on this machine ({} cores available, one thread timed), {} s per case",
        std::thread::available_parallelism().map_or(1, |n| n.get()),
        seconds
    );
    let c = reports::calibrate::calibrate(scenes, seconds, source).map_err(CliError::computed)?;
    if let Some(path) = out {
        std::fs::write(path, c.fit.to_toml()).map_err(|e| CliError::usage(format!("--out {}: {e}", path.display())))?;
    }
    if json {
        println!("{}", super::to_json(&c)?);
    } else {
        print!("{}", reports::calibrate::markdown(&c));
        println!("\n{}", c.fit.to_toml());
    }
    Ok(())
}
