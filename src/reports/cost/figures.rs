//! The cost report's figures: what accuracy costs, as SVG.

/// One named series of (x, y) points, both already log₁₀.
pub(crate) type Series = (String, Vec<[f64; 2]>);

/// A scatter plot of several series on log₁₀ axes (the caller takes the
/// logarithms, so that a zero or failed point is left out visibly in the
/// tables rather than drawn at −∞).
pub(crate) fn log_log_svg(title: &str, x_label: &str, y_label: &str, series: Vec<Series>) -> Result<String, String> {
    use poloto::build;
    let plots: Vec<_> = series
        .into_iter()
        .filter(|(_, pts)| !pts.is_empty())
        .map(|(name, pts)| build::plot(name).line(pts.into_iter().filter(|p| p[0].is_finite() && p[1].is_finite())))
        .collect();
    if plots.is_empty() {
        return Err(format!("{title}: no point to draw"));
    }
    poloto::frame_build()
        .data(plots)
        .build_and_label((title.to_string(), x_label.to_string(), y_label.to_string()))
        .append_to(poloto::header().light_theme())
        .render_string()
        .map_err(|e| e.to_string())
}

/// Writes `svg` to `dir/name` (creating `dir`); the Markdown line that shows it.
pub(crate) fn write(dir: &std::path::Path, name: &str, svg: &str) -> Result<String, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let path = dir.join(name);
    std::fs::write(&path, svg).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(format!("![{name}](figures/{name})"))
}
