//! The commands beside `main.rs`, and [`CliError`]: why a command ended
//! without a result, whose kind is the exit code.

pub mod check_cmd;
pub mod flags;
pub mod paths;
pub mod trace_cmd;
pub mod tuning_cmd;

use mcrt_noise::model::OracleError;
use mcrt_noise::reports::sweep::SweepError;
use mcrt_noise::reports::tables::KernelCliError;
use mcrt_noise::PredictError;
use std::fmt::Display;
use std::process::ExitCode;

/// Why a command ended without a result. The kind is the exit code (the
/// policy is stated once, in `main`'s doc comment, `--help` and README.md):
/// 2 for the input, 1 for the computation.
#[derive(Debug, Clone, PartialEq)]
pub enum CliError {
    /// Usage or bad input, exit 2: a flag, an unreadable or invalid scene
    /// file or shard, a value out of range, a scene the model does not
    /// support, an output path that cannot be written or is an input. The message names
    /// the flag, field or line, the value and what is allowed.
    Usage(String),
    /// A computed failure, exit 1: the input was valid, the computation gave
    /// no result it can vouch for (`NOT CONVERGED`, the evaluation budget or
    /// deadline spent, a result not representable in f64). The message says
    /// which and why.
    Computed(String),
    /// A computed failure already stated on standard output, exit 1 with
    /// nothing on standard error: a verdict that failed or was not resolved
    /// (`compare`, `check`), a tracer run whose mean and variance are not
    /// resolved (fewer than `mcrt_reference::MIN_NONZERO_TRIALS` trials with hits).
    Stated,
}

impl CliError {
    /// Usage or bad input (exit 2).
    pub fn usage(msg: impl Display) -> CliError {
        CliError::Usage(msg.to_string())
    }

    /// A computed failure (exit 1).
    pub fn computed(msg: impl Display) -> CliError {
        CliError::Computed(msg.to_string())
    }

    /// The same kind, its message prefixed with `at: ` (a file, a radius).
    pub fn at(self, at: impl Display) -> CliError {
        match self {
            CliError::Usage(m) => CliError::Usage(format!("{at}: {m}")),
            CliError::Computed(m) => CliError::Computed(format!("{at}: {m}")),
            CliError::Stated => CliError::Stated,
        }
    }

    /// 2 for usage or bad input, 1 for a computed failure.
    pub fn exit_code(&self) -> ExitCode {
        match self {
            CliError::Usage(_) => ExitCode::from(2),
            CliError::Computed(_) | CliError::Stated => ExitCode::from(1),
        }
    }

    /// What goes to standard error (`None`: already stated on standard output).
    pub fn message(&self) -> Option<&str> {
        match self {
            CliError::Usage(m) | CliError::Computed(m) => Some(m),
            CliError::Stated => None,
        }
    }
}

/// `Unsupported` is about the scene (exit 2); a quadrature that did not
/// converge or a result beyond f64 is computed (exit 1).
impl From<OracleError> for CliError {
    fn from(e: OracleError) -> CliError {
        match e {
            OracleError::Unsupported(_) => CliError::usage(e),
            OracleError::Quadrature { .. } | OracleError::NotRepresentable(_) => CliError::computed(e),
        }
    }
}

/// An invalid or unsupported scene is input (exit 2); the oracle's own
/// failures are classified as [`OracleError`]'s.
impl From<PredictError> for CliError {
    fn from(e: PredictError) -> CliError {
        match &e {
            PredictError::Scene(_)
            | PredictError::Unsupported(_)
            | PredictError::Oracle(OracleError::Unsupported(_)) => CliError::usage(e),
            PredictError::Oracle(_) => CliError::computed(e),
        }
    }
}

/// A bad flag is usage (exit 2); the integral's failure is computed (exit 1).
impl From<KernelCliError> for CliError {
    fn from(e: KernelCliError) -> CliError {
        match e {
            KernelCliError::Flag(m) => CliError::Usage(m),
            KernelCliError::Failure(m) => CliError::Computed(m),
        }
    }
}

/// The oracle's failure at one radius (classified as [`OracleError`]'s), or
/// a scene without an R → 0 form (input: exit 2).
impl From<SweepError> for CliError {
    fn from(e: SweepError) -> CliError {
        match &e {
            SweepError::Oracle { error: OracleError::Unsupported(_), .. } | SweepError::NoAsymptoticForm { .. } => {
                CliError::usage(e)
            }
            SweepError::Oracle { .. } => CliError::computed(e),
        }
    }
}

/// The tracer refuses a scene (invalid, beyond its bounds, no flux, endless
/// paths) before any trial: always the input (exit 2).
impl From<mcrt_noise::reference::TraceError> for CliError {
    fn from(e: mcrt_noise::reference::TraceError) -> CliError {
        CliError::usage(e)
    }
}

/// JSON output of a report (cannot fail for these types; a computed failure if it did).
pub fn to_json<T: serde::Serialize>(value: &T) -> Result<String, CliError> {
    serde_json::to_string_pretty(value).map_err(CliError::computed)
}
