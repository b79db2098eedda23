//! Report generators and command support: the code behind the CLI's
//! tables and the generated documents in `docs/`. It uses the library
//! (oracle, model, quadrature, tracer) and nothing in the library uses it.

pub mod accuracy;
pub mod calibrate;
pub mod check_calibration;
pub mod choosing;
pub mod compare;
pub mod cost;
pub mod every_order_checks;
pub mod heatmap;
pub mod model_error;
pub mod optimum;
pub mod sweep;
pub mod tables;
pub mod tracer_checks;
