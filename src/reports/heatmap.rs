//! A log–log heat map as SVG (poloto draws lines and scatter plots, not
//! filled grids): one rectangle per cell coloured by log₁₀ of its value on
//! a perceptually ordered ramp, empty cells hatched grey, the optimum
//! marked, axes in decades, a colour bar with its scale.

use crate::tuning::maps::Map;
use std::fmt::Write;

/// Viridis at eight stops (Smith & van der Walt), interpolated linearly.
const RAMP: [(f64, f64, f64); 8] = [
    (68.0, 1.0, 84.0),
    (70.0, 50.0, 127.0),
    (54.0, 92.0, 141.0),
    (39.0, 127.0, 142.0),
    (31.0, 161.0, 135.0),
    (74.0, 194.0, 109.0),
    (159.0, 218.0, 58.0),
    (253.0, 231.0, 37.0),
];

fn colour(t: f64) -> String {
    let t = t.clamp(0.0, 1.0) * (RAMP.len() - 1) as f64;
    let i = (t.floor() as usize).min(RAMP.len() - 2);
    let f = t - i as f64;
    let (a, b) = (RAMP[i], RAMP[i + 1]);
    let mix = |x: f64, y: f64| (x + (y - x) * f).round() as u8;
    format!("#{:02x}{:02x}{:02x}", mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// The map as an SVG document titled `title`.
pub fn svg(title: &str, map: &Map) -> String {
    let (w, h, left, top, cell_w, cell_h) = (720.0, 520.0, 90.0, 50.0, 520.0, 400.0);
    let nx = map.x.len();
    let ny = map.y.len();
    let logs: Vec<f64> = map.values.iter().flatten().flatten().map(|v| v.log10()).filter(|v| v.is_finite()).collect();
    let (lo, hi) = logs.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
    let span = if hi > lo { hi - lo } else { 1.0 };
    let lx = |x: f64| (x.log10() - map.x[0].log10()) / (map.x[nx - 1].log10() - map.x[0].log10());
    let ly = |y: f64| (y.log10() - map.y[0].log10()) / (map.y[ny - 1].log10() - map.y[0].log10());
    let (dw, dh) = (cell_w / nx as f64, cell_h / ny as f64);
    // Cell i is centred on x[i]: a position's pixel is at (t(n − 1) + ½) cells.
    let px = |x: f64| left + (lx(x) * (nx - 1) as f64 + 0.5) * dw;
    let py = |y: f64| top + cell_h - (ly(y) * (ny - 1) as f64 + 0.5) * dh;
    let mut s = String::new();
    writeln!(s, r##"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">"##).unwrap();
    writeln!(s, r##"<defs><pattern id="none" width="6" height="6" patternUnits="userSpaceOnUse"><rect width="6" height="6" fill="#eee"/><path d="M0 6 L6 0" stroke="#bbb"/></pattern></defs>"##).unwrap();
    writeln!(
        s,
        r##"<text x="{}" y="24" text-anchor="middle" font-size="14">{}</text>"##,
        left + cell_w / 2.0,
        escape(title)
    )
    .unwrap();
    for (j, row) in map.values.iter().enumerate() {
        for (i, v) in row.iter().enumerate() {
            let x = left + i as f64 * dw;
            let y = top + cell_h - (j + 1) as f64 * dh;
            let fill = match v {
                Some(v) if v.is_finite() && *v > 0.0 => colour((v.log10() - lo) / span),
                _ => "url(#none)".into(),
            };
            writeln!(
                s,
                r##"<rect x="{x:.2}" y="{y:.2}" width="{:.2}" height="{:.2}" fill="{fill}"/>"##,
                dw + 0.3,
                dh + 0.3
            )
            .unwrap();
        }
    }
    // The optimum.
    let (ox, oy) =
        (left + cell_w * lx(map.optimum.0).clamp(0.0, 1.0), top + cell_h * (1.0 - ly(map.optimum.1).clamp(0.0, 1.0)));
    writeln!(s, r##"<circle cx="{ox:.2}" cy="{oy:.2}" r="6" fill="none" stroke="white" stroke-width="2"/><circle cx="{ox:.2}" cy="{oy:.2}" r="6" fill="none" stroke="black" stroke-width="1"/>"##).unwrap();
    // Axes in decades.
    let decades = |a: f64, b: f64| (a.log10().ceil() as i32..=b.log10().floor() as i32).collect::<Vec<_>>();
    for d in decades(map.x[0], map.x[nx - 1]) {
        let x = px(10f64.powi(d));
        writeln!(s, r##"<line x1="{x:.2}" y1="{}" x2="{x:.2}" y2="{}" stroke="black"/><text x="{x:.2}" y="{}" text-anchor="middle">1e{d}</text>"##, top + cell_h, top + cell_h + 5.0, top + cell_h + 18.0).unwrap();
    }
    for d in decades(map.y[0], map.y[ny - 1]) {
        let y = py(10f64.powi(d));
        writeln!(s, r##"<line x1="{}" y1="{y:.2}" x2="{left}" y2="{y:.2}" stroke="black"/><text x="{}" y="{:.2}" text-anchor="end">1e{d}</text>"##, left - 5.0, left - 8.0, y + 4.0).unwrap();
    }
    writeln!(
        s,
        r##"<text x="{}" y="{}" text-anchor="middle">{}</text>"##,
        left + cell_w / 2.0,
        top + cell_h + 38.0,
        escape(&map.x_name)
    )
    .unwrap();
    writeln!(
        s,
        r##"<text x="20" y="{}" text-anchor="middle" transform="rotate(-90 20 {})">{}</text>"##,
        top + cell_h / 2.0,
        top + cell_h / 2.0,
        escape(&map.y_name)
    )
    .unwrap();
    // Colour bar.
    let bx = left + cell_w + 30.0;
    for k in 0..50 {
        let t = k as f64 / 49.0;
        let y = top + cell_h * (1.0 - t) - cell_h / 50.0;
        writeln!(
            s,
            r##"<rect x="{bx}" y="{y:.2}" width="18" height="{:.2}" fill="{}"/>"##,
            cell_h / 50.0 + 0.3,
            colour(t)
        )
        .unwrap();
    }
    for (t, v) in [(0.0, lo), (0.5, (lo + hi) / 2.0), (1.0, hi)] {
        writeln!(
            s,
            r##"<text x="{}" y="{:.2}">{:.2e}</text>"##,
            bx + 24.0,
            top + cell_h * (1.0 - t) + 4.0,
            10f64.powf(v)
        )
        .unwrap();
    }
    writeln!(s, r##"<text x="{}" y="{}" >rel. RMSE</text>"##, bx - 4.0, top - 10.0).unwrap();
    writeln!(s, "</svg>").unwrap();
    s
}

fn escape(t: &str) -> String {
    t.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_map_draws_one_rectangle_per_cell_and_hatches_empty_ones() {
        let map = Map {
            x_name: "q".into(),
            y_name: "R".into(),
            x: vec![0.01, 0.1, 1.0],
            y: vec![0.001, 0.01],
            values: vec![vec![Some(1.0), Some(2.0), None], vec![Some(4.0), Some(8.0), Some(16.0)]],
            optimum: (0.1, 0.001),
        };
        let s = svg("test <map>", &map);
        assert_eq!(s.matches("<rect x=").count() - 50, 6, "six cells plus the colour bar");
        assert_eq!(s.matches("url(#none)").count(), 1);
        assert!(s.contains("test &lt;map&gt;") && s.contains("#440154") && s.contains("#fde725"));
    }
}
