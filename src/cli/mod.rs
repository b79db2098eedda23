pub mod trace_cmd;
