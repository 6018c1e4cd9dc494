//! Log-log line charts as standalone SVG: the convergence plots of `caustic converge`.

use std::fmt::Write;

/// One named line of (x, y) points; points with a non-positive or non-finite coordinate are
/// left out (they have no place on log axes).
pub struct Series<'a> {
    /// Legend text.
    pub name: &'a str,
    /// The points, in drawing order.
    pub points: Vec<(f64, f64)>,
}

const WIDTH: f64 = 640.0;
const HEIGHT: f64 = 420.0;
const MARGIN: (f64, f64, f64, f64) = (70.0, 20.0, 30.0, 50.0); // left, right, top, bottom
const COLOURS: [&str; 4] = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd"];

/// An SVG document plotting `series` on logarithmic x and y axes, with decade grid lines.
pub fn log_log_svg(title: &str, x_label: &str, y_label: &str, series: &[Series<'_>]) -> String {
    let valid = |&(x, y): &(f64, f64)| x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite();
    let points: Vec<(f64, f64)> = series.iter().flat_map(|s| s.points.iter().copied().filter(valid)).collect();
    let decades = |values: Vec<f64>| {
        let lo = values.iter().copied().fold(f64::INFINITY, f64::min).log10().floor();
        let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max).log10().ceil();
        if lo.is_finite() && hi.is_finite() { (lo, hi.max(lo + 1.0)) } else { (0.0, 1.0) }
    };
    let (x_lo, x_hi) = decades(points.iter().map(|p| p.0).collect());
    let (y_lo, y_hi) = decades(points.iter().map(|p| p.1).collect());
    let (left, right, top, bottom) = MARGIN;
    let to_x = |x: f64| left + (x.log10() - x_lo) / (x_hi - x_lo) * (WIDTH - left - right);
    let to_y = |y: f64| HEIGHT - bottom - (y.log10() - y_lo) / (y_hi - y_lo) * (HEIGHT - top - bottom);
    let mut svg = String::new();
    let _ = writeln!(svg, r#"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{HEIGHT}" font-family="sans-serif" font-size="12">"#);
    let _ = writeln!(svg, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(svg, r#"<text x="{}" y="18" text-anchor="middle" font-size="14">{}</text>"#, WIDTH / 2.0, escape(title));
    for decade in x_lo as i32..=x_hi as i32 {
        let x = to_x(10f64.powi(decade));
        let _ = writeln!(svg, r##"<line x1="{x:.1}" y1="{top}" x2="{x:.1}" y2="{}" stroke="#ddd"/>"##, HEIGHT - bottom);
        let _ = writeln!(svg, r#"<text x="{x:.1}" y="{}" text-anchor="middle">1e{decade}</text>"#, HEIGHT - bottom + 16.0);
    }
    for decade in y_lo as i32..=y_hi as i32 {
        let y = to_y(10f64.powi(decade));
        let _ = writeln!(svg, r##"<line x1="{left}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="#ddd"/>"##, WIDTH - right);
        let _ = writeln!(svg, r#"<text x="{}" y="{:.1}" text-anchor="end">1e{decade}</text>"#, left - 6.0, y + 4.0);
    }
    let _ = writeln!(svg, r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#, WIDTH / 2.0, HEIGHT - 12.0, escape(x_label));
    let _ = writeln!(svg, r#"<text x="16" y="{0}" text-anchor="middle" transform="rotate(-90 16 {0})">{1}</text>"#, HEIGHT / 2.0, escape(y_label));
    for (i, s) in series.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        let path: Vec<String> = s.points.iter().filter(|p| valid(p)).map(|&(x, y)| format!("{:.1},{:.1}", to_x(x), to_y(y))).collect();
        let _ = writeln!(svg, r#"<polyline fill="none" stroke="{colour}" stroke-width="2" points="{}"/>"#, path.join(" "));
        let legend_y = top + 16.0 * (i as f64 + 1.0);
        let _ = writeln!(svg, r#"<text x="{}" y="{legend_y}" fill="{colour}" text-anchor="end">{}</text>"#, WIDTH - right - 8.0, escape(s.name));
    }
    svg.push_str("</svg>\n");
    svg
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plots_decades_and_skips_points_log_axes_cannot_show() {
        let series = [
            Series { name: "relMSE", points: vec![(0.5, 0.1), (5.0, 0.01), (0.0, 1.0), (50.0, f64::NAN)] },
            Series { name: "a < b", points: vec![(1.0, 0.5)] },
        ];
        let svg = log_log_svg("t", "seconds", "error", &series);
        assert!(svg.starts_with("<svg") && svg.ends_with("</svg>\n"));
        for label in [">1e-1<", ">1e1<", ">1e-2<", ">1e0<"] {
            assert!(svg.contains(label), "missing axis label {label}");
        }
        let first = svg.lines().find(|l| l.starts_with("<polyline")).unwrap();
        assert_eq!(first.matches(',').count(), 2, "only the two valid points: {first}");
        assert!(svg.contains("a &lt; b"));
    }
}
