pub mod check_cmd;
pub mod trace_cmd;
