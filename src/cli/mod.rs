pub mod check_cmd;
pub mod flags;
pub mod trace_cmd;
