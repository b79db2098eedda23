//! The reference machine's per-operation costs, used when a scene has no
//! `[cost]` table and no `--costs` file is given: the reference tracer's
//! own, fitted by `mcrt-noise calibrate --seconds 2 --json` on the
//! reference machine (2 cores, otherwise idle, one thread timed;
//! 2026-12-01). That fit: RMS relative residual 6.1 % over the 16
//! calibration runs (largest 14.3 %); the 12 validation cases, none of
//! them a calibration run, within 12.0 % of their measured time per
//! iteration. Held at 0 because the fit made them negative: `hg_ns` (the
//! tracer's extra cost per hit in a Henyey–Greenstein medium is below its
//! timing noise). A renderer's costs are its own: give them in a `[cost]` table.

use super::cost::CostTable;

/// The costs in the order of [`mcrt_scene::COST_KEYS`], their standard
/// errors and covariance (ns, ns²).
pub const REFERENCE_COSTS: CostTable = CostTable {
    keys: mcrt_scene::COST_KEYS,
    ns: [
        6.689253e+01,
        1.220148e+00,
        2.278792e+01,
        4.894590e+01,
        1.907559e+01,
        9.606706e-01,
        1.665690e+01,
        2.710118e+00,
        0.0,
    ],
    std_errors: [
        1.223530e+02,
        8.519068e+00,
        3.627316e+01,
        7.378216e+00,
        1.089548e+01,
        9.612847e-01,
        4.170508e+01,
        3.588904e+00,
        0.0,
    ],
    source: String::new(),
    covariance: Some([
        [
            1.497026e+04,
            -2.922535e+02,
            -1.302484e+03,
            1.082893e+02,
            -1.499209e+02,
            1.389573e+01,
            2.419571e+03,
            -6.480389e+01,
            0.0,
        ],
        [
            -2.922535e+02,
            7.257452e+01,
            -3.033501e+00,
            -5.999267e+01,
            5.796204e+00,
            -5.034865e-01,
            -7.987850e+01,
            3.153441e+00,
            0.0,
        ],
        [
            -1.302484e+03,
            -3.033501e+00,
            1.315742e+03,
            1.134686e+01,
            -2.429765e+02,
            1.995331e+01,
            -9.059350e+02,
            1.903359e+01,
            0.0,
        ],
        [
            1.082893e+02,
            -5.999267e+01,
            1.134686e+01,
            5.443807e+01,
            -3.456207e+00,
            2.841361e-01,
            1.480635e+01,
            -1.596081e-01,
            0.0,
        ],
        [
            -1.499209e+02,
            5.796204e+00,
            -2.429765e+02,
            -3.456207e+00,
            1.187115e+02,
            -1.032726e+01,
            6.934116e+01,
            -2.735330e+00,
            0.0,
        ],
        [
            1.389573e+01,
            -5.034865e-01,
            1.995331e+01,
            2.841361e-01,
            -1.032726e+01,
            9.240683e-01,
            -4.718474e+00,
            -4.994188e-02,
            0.0,
        ],
        [
            2.419571e+03,
            -7.987850e+01,
            -9.059350e+02,
            1.480635e+01,
            6.934116e+01,
            -4.718474e+00,
            1.739314e+03,
            -8.461388e+01,
            0.0,
        ],
        [
            -6.480389e+01,
            3.153441e+00,
            1.903359e+01,
            -1.596081e-01,
            -2.735330e+00,
            -4.994188e-02,
            -8.461388e+01,
            1.288023e+01,
            0.0,
        ],
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    ]),
};
