//! Log–log line plots written as SVG text: one or more panels side by side,
//! each with decade grid lines, labelled axes, and one polyline with markers
//! per series. No plotting crate: the report needs only this.

use std::fmt::Write;

/// One series: a name and its points (non-positive values are drawn at the
/// axis floor).
pub struct Series {
    /// Legend text.
    pub name: String,
    /// (x, y) points, joined in order.
    pub points: Vec<(f64, f64)>,
}

/// One panel of a figure.
pub struct Panel {
    /// Title above the panel.
    pub title: String,
    /// x axis label.
    pub x_label: String,
    /// y axis label.
    pub y_label: String,
    /// The series.
    pub series: Vec<Series>,
    /// Values below this on x are drawn at it (0 cannot be shown on a log axis).
    pub x_floor: f64,
}

const COLOURS: [&str; 10] = [
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
    "#bcbd22", "#17becf",
];

const PANEL_W: f64 = 520.0;
const PANEL_H: f64 = 380.0;
const LEFT: f64 = 70.0;
const TOP: f64 = 40.0;
const PLOT_W: f64 = 300.0;
const PLOT_H: f64 = 280.0;

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Decade range `[10^a, 10^b]` covering the positive values in `v`.
fn decades(v: impl Iterator<Item = f64>) -> (i32, i32) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for x in v.filter(|x| *x > 0.0 && x.is_finite()) {
        lo = lo.min(x);
        hi = hi.max(x);
    }
    if !lo.is_finite() {
        return (0, 1);
    }
    let a = lo.log10().floor() as i32;
    let b = (hi.log10().ceil() as i32).max(a + 1);
    (a, b)
}

fn tick(e: i32) -> String {
    match e {
        0 => "1".into(),
        1 => "10".into(),
        2 => "100".into(),
        -1 => "0.1".into(),
        _ => format!("1e{e}"),
    }
}

/// The SVG text of `panels`, `columns` to a row.
pub fn figure(panels: &[Panel], columns: usize) -> String {
    let columns = columns.clamp(1, panels.len().max(1));
    let rows = panels.len().div_ceil(columns).max(1);
    let width = PANEL_W * columns as f64;
    let height = PANEL_H * rows as f64;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    for (k, p) in panels.iter().enumerate() {
        let (x0, y0) = (
            (k % columns) as f64 * PANEL_W,
            (k / columns) as f64 * PANEL_H,
        );
        let _ = writeln!(s, r#"<g transform="translate({x0},{y0})">"#);
        panel(&mut s, p, 0.0);
        s.push_str("</g>\n");
    }
    s.push_str("</svg>\n");
    s
}

fn panel(s: &mut String, p: &Panel, x0: f64) {
    let floor = |x: f64| if x < p.x_floor { p.x_floor } else { x };
    let xs = p
        .series
        .iter()
        .flat_map(|r| r.points.iter().map(|q| floor(q.0)));
    let ys = p.series.iter().flat_map(|r| r.points.iter().map(|q| q.1));
    let (xa, xb) = decades(xs);
    let (ya, yb) = decades(ys);
    let px = |x: f64| {
        x0 + LEFT + PLOT_W * (floor(x).max(1e-300).log10() - f64::from(xa)) / f64::from(xb - xa)
    };
    let py = |y: f64| {
        TOP + PLOT_H - PLOT_H * (y.max(1e-300).log10() - f64::from(ya)) / f64::from(yb - ya)
    };
    let _ = writeln!(
        s,
        r#"<text x="{}" y="20" font-size="14" font-weight="bold">{}</text>"#,
        x0 + LEFT,
        escape(&p.title)
    );
    for e in xa..=xb {
        let x = px(10f64.powi(e));
        let _ = writeln!(
            s,
            r##"<line x1="{x:.1}" y1="{TOP}" x2="{x:.1}" y2="{}" stroke="#ddd"/><text x="{x:.1}" y="{}" text-anchor="middle">{}</text>"##,
            TOP + PLOT_H,
            TOP + PLOT_H + 16.0,
            tick(e)
        );
    }
    for e in ya..=yb {
        let y = py(10f64.powi(e));
        let _ = writeln!(
            s,
            r##"<line x1="{}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="#ddd"/><text x="{}" y="{:.1}" text-anchor="end">{}</text>"##,
            x0 + LEFT,
            x0 + LEFT + PLOT_W,
            x0 + LEFT - 5.0,
            y + 4.0,
            tick(e)
        );
    }
    let _ = writeln!(
        s,
        r#"<rect x="{}" y="{TOP}" width="{PLOT_W}" height="{PLOT_H}" fill="none" stroke="black"/>"#,
        x0 + LEFT
    );
    let _ = writeln!(
        s,
        r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#,
        x0 + LEFT + PLOT_W / 2.0,
        TOP + PLOT_H + 34.0,
        escape(&p.x_label)
    );
    let _ = writeln!(
        s,
        r#"<text transform="translate({},{}) rotate(-90)" text-anchor="middle">{}</text>"#,
        x0 + 18.0,
        TOP + PLOT_H / 2.0,
        escape(&p.y_label)
    );
    for (k, r) in p.series.iter().enumerate() {
        let c = COLOURS[k % COLOURS.len()];
        let pts: Vec<String> = r
            .points
            .iter()
            .map(|&(x, y)| format!("{:.1},{:.1}", px(x), py(y)))
            .collect();
        if pts.len() > 1 {
            let _ = writeln!(
                s,
                r#"<polyline points="{}" fill="none" stroke="{c}" stroke-width="1.5"/>"#,
                pts.join(" ")
            );
        }
        for &(x, y) in &r.points {
            let _ = writeln!(
                s,
                r#"<circle cx="{:.1}" cy="{:.1}" r="3.5" fill="{c}"/>"#,
                px(x),
                py(y)
            );
        }
        let ly = TOP + 8.0 + 16.0 * k as f64;
        let lx = x0 + LEFT + PLOT_W + 10.0;
        let _ = writeln!(
            s,
            r#"<circle cx="{}" cy="{ly}" r="4" fill="{c}"/><text x="{}" y="{}">{}</text>"#,
            lx + 4.0,
            lx + 12.0,
            ly + 4.0,
            escape(&r.name)
        );
    }
}

/// What the smoke test checks of the plotting itself: one polyline per
/// series of several points, a marker per point, escaped text, and the
/// floor standing in for zero on a log axis.
pub fn self_check() -> Result<(), String> {
    let p = Panel {
        title: "a < b".into(),
        x_label: "x".into(),
        y_label: "y".into(),
        series: vec![
            Series {
                name: "one".into(),
                points: vec![(1e-3, 2.0), (0.0, 30.0)],
            },
            Series {
                name: "dot".into(),
                points: vec![(1.0, 5.0)],
            },
        ],
        x_floor: 1e-7,
    };
    let svg = figure(&[p], 2);
    let ok = svg.starts_with("<svg")
        && svg.ends_with("</svg>\n")
        && svg.matches("<polyline").count() == 1
        && svg.matches(r#"r="3.5""#).count() == 3
        && svg.contains("a &lt; b")
        && svg.contains("1e-7");
    if ok {
        Ok(())
    } else {
        Err(format!("a test figure came out wrong:\n{svg}"))
    }
}

/// Grouped vertical bars on a linear axis from 0 to `y_max`: one group per
/// entry of `groups`, one bar per series (its values in the groups'
/// order), with a legend.
pub fn bars(
    title: &str,
    y_label: &str,
    groups: &[&str],
    series: &[(String, Vec<f64>)],
    y_max: f64,
) -> String {
    let n = series.len().max(1) as f64;
    let group_w = 20.0 + 14.0 * n;
    let plot_w = group_w * groups.len().max(1) as f64;
    let width = LEFT + plot_w + 120.0;
    let height = TOP + PLOT_H + 60.0;
    let py = |y: f64| TOP + PLOT_H - PLOT_H * (y / y_max).clamp(0.0, 1.0);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{LEFT}" y="20" font-size="14" font-weight="bold">{}</text>"#,
        escape(title)
    );
    for k in 0..=4 {
        let v = y_max * f64::from(k) / 4.0;
        let y = py(v);
        let _ = writeln!(
            s,
            r##"<line x1="{LEFT}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#ddd"/><text x="{}" y="{:.1}" text-anchor="end">{v:.0}</text>"##,
            LEFT + plot_w,
            LEFT - 5.0,
            y + 4.0
        );
    }
    for (g, name) in groups.iter().enumerate() {
        let gx = LEFT + group_w * g as f64 + 10.0;
        for (k, (_, values)) in series.iter().enumerate() {
            let v = values.get(g).copied().unwrap_or(0.0);
            let c = COLOURS[k % COLOURS.len()];
            let y = py(v);
            let _ = writeln!(
                s,
                r#"<rect x="{:.1}" y="{y:.1}" width="12" height="{:.1}" fill="{c}"/>"#,
                gx + 14.0 * k as f64,
                TOP + PLOT_H - y
            );
        }
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{}" text-anchor="middle">{}</text>"#,
            gx + 7.0 * n,
            TOP + PLOT_H + 16.0,
            escape(name)
        );
    }
    let _ = writeln!(
        s,
        r#"<rect x="{LEFT}" y="{TOP}" width="{plot_w:.1}" height="{PLOT_H}" fill="none" stroke="black"/>"#
    );
    let _ = writeln!(
        s,
        r#"<text transform="translate(18,{}) rotate(-90)" text-anchor="middle">{}</text>"#,
        TOP + PLOT_H / 2.0,
        escape(y_label)
    );
    for (k, (name, _)) in series.iter().enumerate() {
        let c = COLOURS[k % COLOURS.len()];
        let (lx, ly) = (LEFT + plot_w + 10.0, TOP + 8.0 + 16.0 * k as f64);
        let _ = writeln!(
            s,
            r#"<rect x="{lx}" y="{}" width="10" height="10" fill="{c}"/><text x="{}" y="{}">{}</text>"#,
            ly - 5.0,
            lx + 14.0,
            ly + 4.0,
            escape(name)
        );
    }
    s.push_str("</svg>\n");
    s
}
