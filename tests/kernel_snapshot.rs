//! The acceptance-integral table, pinned. Values are rounded to 14
//! significant digits (the f64 goal is 1e-13 relative); error bars to their
//! decade (the bound 10^⌈log₁₀ bar⌉), so that a reviewer sees a bar that grows
//! by a factor 10 or more, not every retuning of the engine.

use mcrt_noise::reports::tables::acceptance_rows_f64;

#[test]
fn acceptance_table_is_pinned() {
    let decade = |bar: f64| format!("<= 1e{}", bar.log10().ceil() as i32);
    let mut table = String::from("case | value (14 sig. digits) | error bar | reference\n");
    for (label, out, reference) in acceptance_rows_f64() {
        let e = out.unwrap_or_else(|f| panic!("{label}: {f}"));
        table.push_str(&format!("{label} | {:.13e} | {} | {:.13e}\n", e.value, decade(e.error), reference));
    }
    insta::with_settings!({snapshot_path => "../snapshots", prepend_module_to_snapshot => false}, {
        insta::assert_snapshot!("acceptance_integral_table", table);
    });
}
