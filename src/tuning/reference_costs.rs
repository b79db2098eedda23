//! The reference machine's per-operation costs, used when a scene has no
//! `[cost]` table and no `--costs` file is given: the reference tracer's
//! own, fitted by `mcrt-noise calibrate --seconds 2 --json` on the
//! reference machine (2 cores, otherwise idle, one thread timed;
//! 2026-12-01). That fit: RMS relative residual 5.7 % over the 16
//! calibration runs (largest 12.6 %); the 12 validation cases, none of
//! them a calibration run, within 10.6 % of their measured time per
//! iteration. A renderer's costs are its own: give them in a `[cost]` table.

use super::cost::CostTable;

/// The costs in the order of [`mcrt_scene::COST_KEYS`], their standard
/// errors and covariance (ns, ns²).
pub const REFERENCE_COSTS: CostTable = CostTable {
    keys: mcrt_scene::COST_KEYS,
    ns: [
        4.146852e+01,
        8.153115e-01,
        1.570797e+01,
        5.035242e+01,
        2.115330e+01,
        8.294195e-01,
        1.666607e+01,
        2.094821e+00,
        0.0,
    ],
    std_errors: [
        1.138356e+02,
        8.120901e+00,
        3.365326e+01,
        7.039001e+00,
        1.020712e+01,
        9.013409e-01,
        3.923016e+01,
        3.369660e+00,
        0.0,
    ],
    source: String::new(),
    covariance: Some([
        [
            1.295855e+04,
            -2.634435e+02,
            -1.135651e+03,
            9.979601e+01,
            -1.302734e+02,
            1.211880e+01,
            2.137658e+03,
            -5.820564e+01,
            0.0,
        ],
        [
            -2.634435e+02,
            6.594903e+01,
            -1.621934e+00,
            -5.460480e+01,
            5.045995e+00,
            -4.401443e-01,
            -7.263116e+01,
            2.869675e+00,
            0.0,
        ],
        [
            -1.135651e+03,
            -1.621934e+00,
            1.132542e+03,
            9.418620e+00,
            -2.084098e+02,
            1.709767e+01,
            -7.983836e+02,
            1.755574e+01,
            0.0,
        ],
        [
            9.979601e+01,
            -5.460480e+01,
            9.418620e+00,
            4.954753e+01,
            -3.024951e+00,
            2.493601e-01,
            1.476001e+01,
            -2.182662e-01,
            0.0,
        ],
        [
            -1.302734e+02,
            5.045995e+00,
            -2.084098e+02,
            -3.024951e+00,
            1.041854e+02,
            -9.069331e+00,
            5.920464e+01,
            -2.544623e+00,
            0.0,
        ],
        [
            1.211880e+01,
            -4.401443e-01,
            1.709767e+01,
            2.493601e-01,
            -9.069331e+00,
            8.124155e-01,
            -3.968973e+00,
            -3.732676e-02,
            0.0,
        ],
        [
            2.137658e+03,
            -7.263116e+01,
            -7.983836e+02,
            1.476001e+01,
            5.920464e+01,
            -3.968973e+00,
            1.539005e+03,
            -7.500039e+01,
            0.0,
        ],
        [
            -5.820564e+01,
            2.869675e+00,
            1.755574e+01,
            -2.182662e-01,
            -2.544623e+00,
            -3.732676e-02,
            -7.500039e+01,
            1.135461e+01,
            0.0,
        ],
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    ]),
};
