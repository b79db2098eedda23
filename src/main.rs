//! `mcrt-noise` command-line interface.

use clap::{Parser, Subcommand};
use cli::paths::Needed;
use cli::CliError;
use mcrt_noise::oracle::{Precision, Scope};
use mcrt_noise::quad::Budget;
use mcrt_noise::reports;
use mcrt_noise::scene::Scene;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

mod cli;

#[derive(Parser)]
#[command(
    name = "mcrt-noise",
    version,
    about = "Noise oracle for multiple-integration-sphere MCRT in scattering media",
    after_help = EXIT_CODES
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// The evaluation budget (and optional deadline) of one computation,
/// shared by every integral and level of it.
#[derive(clap::Args, Clone, Copy)]
struct BudgetArgs {
    /// Integrand evaluations the whole run may spend, over every integral and level, in [1, 1e15] (default 1e9 in f64, ~20 s, and for `oracle` with scattering_orders >= 2 or "all" 3e9, as `check` gives them; in MPFR 5e7 up to 128 bits, a few minutes, and 5e7·(128/bits)² above, as evaluations get dearer).
    #[arg(long, allow_negative_numbers = true, value_parser = cli::flags::max_evals)]
    max_evals: Option<u64>,
    /// Wall-time limit of the run in seconds, in (0, 1e6] (none by default; a run that meets it depends on the machine's speed).
    #[arg(long, allow_negative_numbers = true, value_parser = cli::flags::time_limit)]
    time_limit: Option<f64>,
}

#[derive(Subcommand)]
enum Command {
    /// Parse and validate a scene; print it normalised (defaults filled in) or list its errors.
    Validate { scene: PathBuf },
    /// Predict the pixel's mean and noise: exact (23), (24), their R → 0 forms, Var L (scattering orders 2–9 and "all": the exact mean and bias; at q = 1 and camera_rays = 1 also Var L)
    Oracle {
        scene: PathBuf,
        /// `f64` or a number of MPFR bits.
        #[arg(long, default_value = "f64")]
        precision: String,
        /// Relative tolerance of every integral, in [1e-30, 0.1] (default 1e-10 in f64, 2^-(bits-22) in MPFR).
        #[arg(long, allow_negative_numbers = true, value_parser = cli::flags::rel_tol)]
        rel_tol: Option<f64>,
        #[command(flatten)]
        budget: BudgetArgs,
        /// One JSON object instead of the table.
        #[arg(long)]
        json: bool,
        /// Also compute the finite-sphere Q and the correlations Var L weighs (C₂₃ where q < 1, C₂₄ where camera_rays > 1) of single-scattered light (scattering_orders = 1, isotropic medium, point lights), so that the prediction is the exact finite-sphere model (the library's `predict` does so at a goal of 1e-3): about a minute on two cores at --rel-tol 1e-3 (~7e8 evaluations; minutes with a light near the camera line), so it needs --rel-tol, and --max-evals to match (e.g. 1e-3 and 3e9). For point lights in a Henyey–Greenstein medium at q = 1 and camera_rays = 1 it computes Var L itself (M₂ with the same-path term, docs/model.md §9.10): ~4e9 evaluations and minutes at 1e-3 (give --max-evals 3e10).
        #[arg(long, requires = "rel_tol")]
        finite_pairs: bool,
    },
    /// Kernel of integral (23), I(ϑ, R), at a chosen precision, with error bar and cost.
    Kernel {
        /// Angle ϑ in radians, in (0, π]: a plain decimal (e.g. 0.5, 1e-3) or `pi`, `pi/2`, read and range-checked at the working precision.
        #[arg(long, allow_hyphen_values = true)]
        theta: String,
        /// Sphere radius R in units of 1/σ_ext, in [1e-200, 1e300]: a plain decimal, read and range-checked at the working precision.
        #[arg(long, allow_hyphen_values = true)]
        radius: String,
        /// `f64` or a number of MPFR bits.
        #[arg(long, default_value = "f64")]
        precision: String,
        /// Relative tolerance, in [1e-30, 0.1] (default 1e-13 for f64, 2^-(bits-22) for MPFR).
        #[arg(long, allow_negative_numbers = true, value_parser = cli::flags::rel_tol)]
        rel_tol: Option<f64>,
        /// The 2-D integral by the nested engine with the kink declared (the
        /// engine's benchmark), instead of the series checked by 1-D quadrature.
        #[arg(long, conflicts_with = "bare")]
        nested: bool,
        /// The bare 2-D integrand by the nested engine, without telling it the kink.
        #[arg(long)]
        bare: bool,
        #[command(flatten)]
        budget: BudgetArgs,
    },
    /// Exact/asymptotic ratios of (23), (24) as R → 0 with the fitted order, and the finite-sphere model against the small-sphere one.
    Sweep {
        scene: PathBuf,
        /// Comma-separated radii, e.g. 1e-1,1e-2,1e-3.
        #[arg(
            long,
            value_delimiter = ',',
            allow_hyphen_values = true,
            default_values_t = mcrt_noise::reports::sweep::DOC_RADII
        )]
        radii: Vec<f64>,
        /// One budget for the whole sweep, shared by its radii.
        #[command(flatten)]
        budget: BudgetArgs,
        /// One JSON object instead of the table.
        #[arg(long)]
        json: bool,
    },
    /// Run the estimator many times (reference tracer): mean and variance of L with standard errors.
    Trace {
        #[command(flatten)]
        run: TraceArgs,
        /// Also write the run as a shard file for `merge`.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Merge shard files of one scene and seed over disjoint trial ranges (exact).
    Merge {
        shards: Vec<PathBuf>,
        #[arg(long)]
        json: bool,
        /// Write the merged run as a shard file.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Oracle beside tracer for the mean and variance of L, with z-scores and a verdict.
    Compare {
        #[command(flatten)]
        run: TraceArgs,
    },
    /// Check a renderer's per-iteration pixel values against the prediction: PASS, FAIL or NOT RESOLVED at a stated false-alarm rate, with the errors a pass would have caught; or, with --plan, how many values a check needs. Exit 0 pass (or a plan made), 1 fail or not resolved (or a pilot that fails), 2 bad input.
    Check {
        scene: PathBuf,
        /// The renderer's values, each >= 0: one L per line (`#` comments allowed), a JSON array, or power sums as JSON
        /// `{"count": M, "sums": [ΣL, ΣL², ΣL³, ΣL⁴, ΣL⁵, ΣL⁶], "sums_relative_error": ε, "nonzero": N, "min": a, "max": b}` (ε defaults to
        /// (M + 2)·2⁻⁵³; N, the number of nonzero values, is optional: without it sparsity is not checked; a and b, the smallest
        /// and largest value, are required; "largest": [b₁, b₂, …], the up to 8 largest values, may stand for "max"); `-` reads stdin.
        #[arg(long)]
        values: PathBuf,
        /// Family-wise probability that a correct renderer fails (all tests together), in [1e-300, 0.5].
        #[arg(long, default_value_t = 1e-3, allow_negative_numbers = true)]
        false_alarm_rate: f64,
        /// Probability with which an error of the reported detectable size fails, in [0.5, 1).
        #[arg(long, default_value_t = 0.9, allow_negative_numbers = true)]
        power: f64,
        /// Relative error of the mean the values must be able to detect, else NOT RESOLVED (default 0.1).
        #[arg(long, allow_negative_numbers = true)]
        target_mean: Option<f64>,
        /// Relative error of Var L the values must be able to detect, else NOT RESOLVED (default 0.2).
        #[arg(long, allow_negative_numbers = true)]
        target_variance: Option<f64>,
        /// Treat the values as a pilot: print how many samples the check needs for the targets (and the pilot's verdict).
        #[arg(long)]
        plan: bool,
        /// One JSON object instead of the text.
        #[arg(long)]
        json: bool,
    },
    /// Regenerate the check's calibration table in docs/library.md: thousands of independent tracer runs checked where the model is exact, false alarms against the binomial 99 % interval of the stated rate (~1.7 h on two cores); exit 1 if a case lies outside it.
    CheckCalibration {
        #[arg(long, default_value = "docs/library.md")]
        out: PathBuf,
        /// Divide every case's runs by this factor, in [1, 1000] (a quick look; the documented table uses 1).
        #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=1000))]
        reduce: u64,
    },
    /// Regenerate docs/asymptotic-checks.md (and its SVG figures) from the bundled scenes.
    AsymptoticChecks {
        #[arg(long, default_value = "docs/asymptotic-checks.md")]
        out: PathBuf,
        #[arg(long, default_value = "scenes")]
        scenes: PathBuf,
    },
    /// Choose q, R, N_F, N_B for the least predicted RMSE (bias and noise) after a time budget, beside q = 1, the cylinder limit, the scene's own parameters, the asymptotic rule's R and N_B = 1 (single-scattered light in an isotropic medium: R and N_F at q = 1, N_B = 1, beside the small-sphere model's choice at the scene's R; scattering orders 2–9 and "all", point lights and beams in an isotropic medium: R and N_F at q = 1, N_B = 1, ~10 s per radius for "all", ~30 s for order 5, about a minute with a beam, minutes in all).
    Optimize {
        scene: PathBuf,
        /// Wall-time budget T in seconds of one core, in (0, 1e9].
        #[arg(long, allow_negative_numbers = true, value_parser = cli::flags::budget_seconds)]
        budget: f64,
        /// Per-operation costs: a file with a [cost] table (`calibrate --out` writes one); default the scene's [cost], else the reference machine's.
        #[arg(long)]
        costs: Option<PathBuf>,
        /// At most this many spheres per iteration (memory), in [1, 1e7].
        #[arg(long, allow_negative_numbers = true, value_parser = cli::flags::max_spheres)]
        max_spheres: Option<f64>,
        /// Radii searched, LO,HI (one argument), with σ_ext·LO < σ_ext·HI in [1e-12, 1e3] (default σ_ext·R in [1e-3, 0.5]); R is searched for uncollided light and, at q = 1 and N_B = 1, for single-scattered light and orders 2–9 and "all" in an isotropic medium; any other scene with scattered light keeps its R, which must lie in the range.
        #[arg(long, allow_hyphen_values = true, value_parser = cli::flags::radius_range)]
        radius_range: Option<(f64, f64)>,
        /// Write SVG maps of the predicted RMSE over (q, R) and (q, N_B/N_F) into this directory (refused for single-scattered light in an isotropic medium and for every scattering order, whose q and N_B are held at 1).
        #[arg(long)]
        maps: Option<PathBuf>,
        /// One JSON object instead of the text.
        #[arg(long)]
        json: bool,
    },
    /// Fit this machine's per-operation costs from timed tracer runs (one thread) and validate the cost model on other parameter sets.
    Calibrate {
        /// Seconds of timing per parameter set, in [0.05, 600].
        #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
        seconds: f64,
        /// Write the fitted [cost] table to this file (for `optimize --costs`, or to paste into a scene).
        #[arg(long)]
        out: Option<PathBuf>,
        #[arg(long, default_value = "scenes")]
        scenes: PathBuf,
        /// One JSON object instead of the tables.
        #[arg(long)]
        json: bool,
    },
    /// Regenerate docs/choosing-parameters.md: calibrate, validate the cost model, optimise two scenes and check the predicted RMSE with the tracer (~7 min).
    ChoosingParameters {
        #[arg(long, default_value = "docs/choosing-parameters.md")]
        out: PathBuf,
        #[arg(long, default_value = "scenes")]
        scenes: PathBuf,
    },
    /// Regenerate docs/model-error.md: the finite-sphere model against the small-sphere one, R = 1 … 1e-4.
    ModelError {
        #[arg(long, default_value = "docs/model-error.md")]
        out: PathBuf,
        #[arg(long, default_value = "scenes")]
        scenes: PathBuf,
    },
    /// Regenerate docs/tracer-checks.md: tracer against oracle as R falls and at every scattering order, and the tracer's speed.
    TracerChecks {
        #[arg(long, default_value = "docs/tracer-checks.md")]
        out: PathBuf,
        #[arg(long, default_value = "scenes")]
        scenes: PathBuf,
    },
    /// Measure the f64 special functions against MPFR and write the table.
    Accuracy {
        /// Points per function, in [1, 10^7].
        #[arg(long, default_value_t = 100_000, allow_negative_numbers = true, value_parser = cli::flags::points)]
        points: usize,
        /// Write the Markdown report here (e.g. docs/accuracy.md).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// What accuracy costs in time: the kernel, the oracle and the tracer, each row against its speed target (~10 min).
    Cost {
        /// Write the Markdown report here (e.g. docs/accuracy-cost.md); its SVG figures go to figures/ beside it (./figures without --out).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Repetitions per f64 row (the minimum time is reported), in [1, 10^4].
        #[arg(long, default_value_t = 50, allow_negative_numbers = true, value_parser = cli::flags::repeats)]
        repeats: usize,
    },
}

/// What `trace` and `compare` share: the scene and the run.
#[derive(clap::Args)]
struct TraceArgs {
    scene: PathBuf,
    /// A count M (trials 0..M) or a range A..B of trial indices, within [0, 2^64 − 1].
    #[arg(long, allow_hyphen_values = true)]
    trials: String,
    /// The run's seed, an integer in [0, 2^64 − 1].
    #[arg(long, default_value_t = 1, allow_negative_numbers = true, value_parser = cli::flags::seed)]
    seed: u64,
    /// Worker threads, in [1, 1024] (default: all cores). The numbers do not depend on it.
    #[arg(long, allow_negative_numbers = true, value_parser = cli::flags::threads)]
    threads: Option<usize>,
    /// Sphere radius R instead of the scene's estimator.radius (its range: σ_ext·R in [1e-12, 1e3]).
    #[arg(long, allow_negative_numbers = true, value_parser = cli::flags::positive)]
    radius: Option<f64>,
    /// One JSON object instead of the table.
    #[arg(long)]
    json: bool,
}

/// The exit codes, as `--help` states them (the policy: [`main`]).
const EXIT_CODES: &str = "\
Exit codes:
  0  done, or the verdict passed
  1  a computed failure: a quadrature NOT CONVERGED, the evaluation budget or deadline spent, a result not
     representable in f64, a verdict that failed or was not resolved (compare, check), a tracer run whose mean and
     variance are not resolved (fewer than 100 trials with hits); the reason on standard error, or with the verdict
     or the tracer's report on standard output
  2  usage or bad input: a bad flag, an unreadable or invalid scene file or shard, a value out of range, a scene the
     model does not support, an output path that cannot be written or is an input, a --scenes directory that is
     missing, empty or holds an invalid scene (all checked before the run); the message names the flag, field or
     line";

/// Runs one command. Exit codes (stated here once; `--help` and README.md
/// repeat them, [`cli::CliError`] carries the kind):
/// - **0**: done, or the verdict passed;
/// - **1**: a computed failure: the input was valid but gave no result the
///   program can vouch for: a quadrature `NOT CONVERGED`, the evaluation
///   budget or deadline spent, a result not representable in f64
///   (`OracleError::NotRepresentable`), a verdict that failed or was not
///   resolved (`compare`, `check`), a tracer run of 4 trials or more whose
///   mean and variance are not resolved (fewer than
///   `mcrt_reference::MIN_NONZERO_TRIALS` trials with hits, no spread);
/// - **2**: usage or bad input: a bad flag (clap's own errors exit 2 too), an
///   unreadable or invalid scene file or shard, an invalid trial range, a
///   value out of range, a scene the model does not support
///   (`OracleError::Unsupported`), an output path that cannot be written
///   or is one of the command's inputs, a `--scenes` directory that is
///   missing, empty or holds an invalid scene (`cli::paths`).
///
/// Every message names the flag, field or line, the value and the range;
/// it goes to standard error, except a verdict's or a tracer report's
/// reason, printed once on standard output.
fn main() -> ExitCode {
    quiet_on_closed_pipe();
    let cli = Cli::parse();
    match run(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            if let Some(msg) = e.message() {
                eprintln!("error: {msg}");
            }
            e.exit_code()
        }
    }
}

fn run(command: Command) -> Result<(), CliError> {
    match command {
        Command::Validate { scene } => validate(&scene),
        Command::Oracle { scene, precision, rel_tol, budget, json, finite_pairs } => {
            let precision = Precision::parse(&precision).map_err(CliError::Usage)?;
            let scope = if finite_pairs { Scope::FinitePairs } else { Scope::Everything };
            oracle(&scene, precision, rel_tol, budget, scope, json)
        }
        Command::Kernel { theta, radius, precision, rel_tol, nested, bare, budget } => {
            let path = match (nested, bare) {
                (_, true) => reports::tables::KernelPath::Bare,
                (true, false) => reports::tables::KernelPath::Nested,
                (false, false) => reports::tables::KernelPath::Reduced,
            };
            let precision = Precision::parse(&precision).map_err(CliError::Usage)?;
            kernel_args(&theta, &radius, precision)?;
            let budget = budget_from_flags(precision, budget);
            Ok(reports::tables::kernel_cli(&theta, &radius, precision, rel_tol, path, &budget)?)
        }
        Command::Sweep { scene, radii, budget, json } => {
            sweep(&scene, &radii, &budget_from_flags(Precision::F64, budget), json)
        }
        Command::Trace { run: a, out } => {
            let scene = load_with_radius(&a.scene, a.radius)?;
            cli::trace_cmd::trace_cmd(&scene, &a.scene, &a.trials, a.seed, a.threads, a.json, out.as_deref())
        }
        Command::Merge { shards, json, out } => cli::trace_cmd::merge_cmd(&shards, json, out.as_deref()),
        Command::Compare { run: a } => {
            let scene = load_with_radius(&a.scene, a.radius)?;
            cli::trace_cmd::compare_cmd(&scene, &a.trials, a.seed, a.threads, a.json)
        }
        Command::Optimize { scene, budget, costs, max_spheres, radius_range, maps, json } => {
            let args = cli::tuning_cmd::OptimizeArgs {
                scene: &scene,
                budget,
                costs: costs.as_deref(),
                max_spheres,
                radius_range,
                maps: maps.as_deref(),
                json,
            };
            cli::tuning_cmd::optimize_cmd(&args, load)
        }
        Command::Calibrate { seconds, out, scenes, json } => {
            cli::tuning_cmd::calibrate_cmd(&scenes, seconds, out.as_deref(), json)
        }
        Command::Check { scene, values, false_alarm_rate, power, target_mean, target_variance, plan, json } => {
            let args = cli::check_cmd::CheckArgs {
                values: &values,
                false_alarm_rate,
                power,
                targets: (target_mean, target_variance),
                plan,
                json,
            };
            cli::check_cmd::check_cmd(&load(&scene)?, &args)
        }
        Command::CheckCalibration { out, reduce } => check_calibration(&out, reduce),
        Command::AsymptoticChecks { out, scenes } => {
            let figures = figures_beside(&out);
            let inputs = Inputs { scenes: Some((&scenes, Needed::All)), figures: Some(&figures) };
            generate(inputs, Some(out), || mcrt_noise::reports::sweep::asymptotic_checks_markdown(&scenes, &figures))
        }
        Command::ChoosingParameters { out, scenes } => {
            let figures = figures_beside(&out);
            let names = mcrt_noise::reports::choosing::scene_names();
            let inputs = Inputs { scenes: Some((&scenes, Needed::Named(&names))), figures: Some(&figures) };
            generate(inputs, Some(out), || mcrt_noise::reports::choosing::markdown(&scenes, &figures))
        }
        Command::ModelError { out, scenes } => {
            let figures = figures_beside(&out);
            let names = mcrt_noise::reports::model_error::scene_names();
            let inputs = Inputs { scenes: Some((&scenes, Needed::Named(&names))), figures: Some(&figures) };
            generate(inputs, Some(out), || mcrt_noise::reports::model_error::markdown(&scenes, &figures))
        }
        Command::TracerChecks { out, scenes } => {
            let figures = figures_beside(&out);
            let names = mcrt_noise::reports::tracer_checks::SCENE_NAMES;
            let inputs = Inputs { scenes: Some((&scenes, Needed::Named(&names))), figures: Some(&figures) };
            generate(inputs, Some(out), || mcrt_noise::reports::tracer_checks::markdown(&scenes, &figures))
        }
        Command::Accuracy { points, out } => {
            generate(Inputs { scenes: None, figures: None }, out, || reports::accuracy::accuracy_markdown(points))
        }
        Command::Cost { out, repeats } => {
            let figures = out.as_deref().and_then(|o| o.parent()).unwrap_or(Path::new(".")).join("figures");
            let inputs = Inputs { scenes: None, figures: Some(&figures) };
            generate(inputs, out, || reports::cost::cost_markdown(repeats, &figures))
        }
    }
}

/// A closed pipe (`mcrt-noise oracle … | head -2`) ends the process quietly,
/// as it does any Unix filter, instead of a panic in `println!` (Rust
/// ignores SIGPIPE by default, so every write would fail with EPIPE).
fn quiet_on_closed_pipe() {
    #[cfg(unix)]
    // SAFETY: restores the default disposition of one signal before any
    // thread is started; no handler runs Rust code.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

fn validate(path: &PathBuf) -> Result<(), CliError> {
    let scene = load(path)?;
    let text = scene.to_toml_string();
    print!("{text}");
    if !text.ends_with('\n') {
        println!();
    }
    Ok(())
}

/// The scene file, read and validated (exit 2 naming the file and every bad field).
fn load(path: &PathBuf) -> Result<Scene, CliError> {
    let text = std::fs::read_to_string(path).map_err(|e| CliError::usage(e).at(path.display()))?;
    Scene::from_toml_str(&text).map_err(|e| CliError::usage(e).at(path.display()))
}

/// `kernel --theta`, `--radius`: plain decimals in range, read at the
/// working precision (`cli::flags`).
fn kernel_args(theta: &str, radius: &str, precision: Precision) -> Result<(), CliError> {
    let bits = precision.mpfr_bits();
    cli::flags::check_theta(theta, bits).map_err(CliError::Usage)?;
    cli::flags::check_kernel_radius(radius, bits).map_err(CliError::Usage)
}

/// The scene with estimator.radius replaced, validated as in a scene file
/// (its bound σ_ext·R is the scene's), an error naming `--radius`.
fn load_with_radius(path: &PathBuf, radius: Option<f64>) -> Result<Scene, CliError> {
    let mut scene = load(path)?;
    if let Some(r) = radius {
        scene.estimator.radius = r;
        scene = scene.validated().map_err(|e| {
            CliError::Usage(match e {
                mcrt_noise::scene::SceneError::Invalid(errors) => errors
                    .iter()
                    .map(|e| e.to_string().replace("estimator.radius", "--radius"))
                    .collect::<Vec<_>>()
                    .join("; "),
                other => other.to_string(),
            })
        })?;
    }
    Ok(scene)
}

/// The run's evaluation budget from `--max-evals` (default: the
/// precision's, `Precision::default_evaluations`) and `--time-limit` (both
/// range-checked by their value parsers).
fn budget_from_flags(precision: Precision, flags: BudgetArgs) -> Budget {
    let limit = flags.max_evals.unwrap_or_else(|| precision.default_evaluations());
    match flags.time_limit {
        None => Budget::new(limit),
        Some(t) => Budget::with_deadline(limit, std::time::Duration::from_secs_f64(t)),
    }
}

/// `oracle`: an unsupported scene is input (exit 2); NOT CONVERGED, the
/// budget spent or a result beyond f64 is computed (exit 1).
fn oracle(
    path: &PathBuf,
    precision: Precision,
    rel_tol: Option<f64>,
    flags: BudgetArgs,
    scope: Scope,
    json: bool,
) -> Result<(), CliError> {
    let scene = load(path)?;
    if matches!(scene.effects.scattering_orders, mcrt_noise::ScatteringOrders::Limited(n) if n >= 2)
        || scene.effects.scattering_orders == mcrt_noise::ScatteringOrders::All
    {
        // Every order has a prediction's budget by default (a beam's Var L
        // of order 5 spends ~1.1·10⁹ at 10⁻⁴, docs/model.md §10.6).
        let flags = BudgetArgs {
            max_evals: flags.max_evals.or(Some(mcrt_noise::prec::EVERY_ORDER_PREDICTION_EVALUATIONS)),
            ..flags
        };
        let budget = &budget_from_flags(precision, flags);
        return every_order_oracle(path, &scene, precision, rel_tol, budget, scope, json);
    }
    let budget = &budget_from_flags(precision, flags);
    let report = mcrt_noise::oracle::run_within_scoped(&scene, precision, rel_tol, budget, scope)
        .map_err(|e| CliError::from(e).at(path.display()))?;
    if json {
        println!("{}", cli::to_json(&report)?);
    } else {
        print!("{}", reports::tables::oracle_table(&report));
    }
    Ok(())
}

/// `oracle` on a scene with scattering orders >= 2: the exact mean, its
/// small-sphere limit and the bias, and Var L where the model has it
/// (f64 only; docs/model.md §10).
fn every_order_oracle(
    path: &std::path::Path,
    scene: &mcrt_noise::Scene,
    precision: Precision,
    rel_tol: Option<f64>,
    budget: &Budget,
    scope: Scope,
    json: bool,
) -> Result<(), CliError> {
    if let Precision::Bits(bits) = precision {
        return Err(CliError::usage(format!(
            "--precision = {bits}: with effects.scattering_orders >= 2 the oracle computes in f64 only (allowed: f64); \
             scene {}",
            path.display()
        )));
    }
    if scope == Scope::FinitePairs {
        return Err(CliError::usage(format!(
            "--finite-pairs: with effects.scattering_orders >= 2 there are no correlations of two spheres to add \
             (not modelled yet, docs/model.md §10.4); without the flag the oracle gives the exact mean, and Var L \
             at q = 1 and camera_rays = 1; scene {}",
            path.display()
        )));
    }
    let m = mcrt_noise::oracle::every_order_mean(scene, rel_tol, budget)
        .map_err(|e| CliError::from(e).at(path.display()))?;
    if json {
        println!("{}", cli::to_json(&m)?);
    } else {
        print!("{m}");
    }
    Ok(())
}

fn sweep(path: &PathBuf, radii: &[f64], budget: &Budget, json: bool) -> Result<(), CliError> {
    if let Some(bad) = radii.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
        return Err(CliError::usage(format!("--radii: {bad} is not a radius (finite and > 0)")));
    }
    let scene = load(path)?;
    for &r in radii {
        let mut s = scene.clone();
        s.estimator.radius = r;
        s.validated()
            .map_err(|e| CliError::usage(format!("--radii: {}", e.to_string().replace("estimator.radius", "R"))))?;
    }
    let rows = mcrt_noise::reports::sweep::sweep_within(&scene, radii, budget)?;
    if json {
        use mcrt_noise::model::correlations::Which;
        use mcrt_noise::reports::sweep::fit_order;
        use mcrt_noise::reports::sweep::{fit_finite_order, FiniteRatio};
        let out = serde_json::json!({
            "rows": rows,
            "order23": fit_order(&rows, Which::Eq23),
            "order24": fit_order(&rows, Which::Eq24),
            "finite_order_mean": fit_finite_order(&rows, FiniteRatio::Mean),
            "finite_order_variance": fit_finite_order(&rows, FiniteRatio::Variance),
        });
        println!("{}", cli::to_json(&out)?);
    } else {
        print!("{}", mcrt_noise::reports::sweep::table(&rows));
        if rows.iter().any(|r| r.finite.is_some()) {
            println!("\nThe finite-sphere model (exact at each R) against the small-sphere one:\n");
            print!("{}", mcrt_noise::reports::sweep::finite_table(&rows));
        }
    }
    Ok(())
}

/// `DIR/figures` for a document written to `DIR/NAME.md`.
fn figures_beside(out: &Path) -> PathBuf {
    out.parent().unwrap_or(Path::new(".")).join("figures")
}

/// `check-calibration`: runs the documented cases (runs divided by
/// `reduce`), prints the block and writes it into `out` between its markers.
fn check_calibration(out: &Path, reduce: u64) -> Result<(), CliError> {
    use mcrt_noise::reports::check_calibration as cal;
    let read = || {
        std::fs::read_to_string(out)
            .map_err(|e| CliError::usage(format!("--out {}: cannot be read: {e}", out.display())))
    };
    cal::replace_block(&read()?, "").map_err(|e| CliError::usage(format!("--out {}: {e}", out.display())))?;
    cli::paths::writable_file("--out", out)?;
    let mut outcomes = Vec::new();
    for mut case in cal::documented_cases() {
        case.runs = (case.runs / reduce).max(1);
        eprintln!(
            "check-calibration: {} at M = {}, α = {}, {} runs …",
            case.label, case.samples, case.false_alarm_rate, case.runs
        );
        let outcome = cal::run(&case).map_err(CliError::Computed)?;
        eprintln!(
            "  {} FAIL (interval [{}, {}]), {} NOT RESOLVED, {} PASS, {:.0} s",
            outcome.fails,
            outcome.interval.0,
            outcome.interval.1,
            outcome.not_resolved,
            outcome.passes,
            outcome.seconds
        );
        outcomes.push(outcome);
    }
    let block = cal::markdown(&outcomes);
    print!("{block}");
    // Read again: the document may have been edited during the run.
    let updated = cal::replace_block(&read()?, &block).map_err(CliError::Computed)?;
    std::fs::write(out, updated)
        .map_err(|e| CliError::usage(format!("--out {}: cannot be written: {e}", out.display())))?;
    match outcomes.iter().filter(|o| !o.calibrated()).count() {
        0 => Ok(()),
        k => Err(CliError::Computed(format!("{k} case(s) outside the binomial 99 % interval of their stated rate"))),
    }
}

/// What a generated document reads and writes besides `--out`: its
/// `--scenes` directory and the scenes it needs there, its figures directory.
struct Inputs<'a> {
    scenes: Option<(&'a Path, Needed<'a>)>,
    figures: Option<&'a Path>,
}

/// A generated document or table: the scenes it reads must be there and
/// valid, `--out` and the figures directory writable, all checked before
/// the generation (which takes minutes; exit 2 naming the flag and the
/// path, `cli::paths`). A failure of the generation itself is computed
/// (exit 1); the text goes to `--out`, or to standard output.
fn generate(
    inputs: Inputs<'_>,
    out: Option<PathBuf>,
    text: impl FnOnce() -> Result<String, String>,
) -> Result<(), CliError> {
    if let Some((dir, needed)) = inputs.scenes {
        cli::paths::scenes_dir(dir, needed)?;
    }
    if let Some(path) = &out {
        cli::paths::writable_file("--out", path)?;
    }
    if let Some(dir) = inputs.figures {
        let flag = out.as_ref().map_or("without --out".to_string(), |o| format!("--out {}", o.display()));
        cli::paths::writable_dir(&format!("{flag}: its figures directory {}", dir.display()), dir)?;
    }
    let text = text().map_err(CliError::Computed)?;
    match out {
        Some(path) => std::fs::write(&path, text)
            .map_err(|e| CliError::usage(format!("--out {}: cannot be written: {e}", path.display()))),
        None => {
            print!("{text}");
            Ok(())
        }
    }
}
