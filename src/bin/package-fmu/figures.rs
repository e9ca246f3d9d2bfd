//! The figures of documentation/: the default pair in the transverse plane (drawn from the
//! geometry, docs/model.md §2, §3.1) and the example result (plotted from the stored
//! reference run, data/reference_run/GearedRotor_ref.csv).

use geared_rotor::gear::PairGeometry;
use std::fmt::Write as _;

/// SVG of the default pair in the transverse plane at 6 px/mm: base, reference and tip
/// circles, the line of action between the tangent points, the active part A-E and the
/// pitch point C. Labels sit beside the line, alternating sides, so that they do not
/// overlap; the legend is in the HTML caption.
pub fn transverse(g: &PairGeometry) -> String {
    let s = 6000.0; // px per m
    let (w, h) = (980.0, 640.0);
    let (cx1, cy) = (60.0 + g.ra1 * s, h / 2.0);
    let cx2 = cx1 + g.a_w * s;
    let a = g.alpha_wt;
    // e_w = (cos a, -sin a) from c1 to the tangent point (theta = 0); SVG y points down
    let (ex, ey) = (a.cos(), a.sin());
    let t1 = (cx1 + g.rb1 * s * ex, cy + g.rb1 * s * ey);
    let t2 = (cx2 - g.rb2 * s * ex, cy - g.rb2 * s * ey);
    let len = g.a_w * a.sin() * s;
    let dir = ((t2.0 - t1.0) / len, (t2.1 - t1.1) / len);
    let normal = (dir.1, -dir.0); // perpendicular, towards upper left
    let p = |sig: f64| (t1.0 + sig * s * dir.0, t1.1 + sig * s * dir.1);
    let (pa, pe, pc) = (p(g.sigma_a), p(g.sigma_e), p(g.sigma_c));
    let mut o = String::new();
    let _ = writeln!(
        o,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="15">"#
    );
    let _ = writeln!(o, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
    for (cx, rb, r, ra, col) in [
        (cx1, g.rb1, g.r1, g.ra1, "#c0392b"),
        (cx2, g.rb2, g.r2, g.ra2, "#1f4e9c"),
    ] {
        let _ = writeln!(
            o,
            r##"<circle cx="{cx:.1}" cy="{cy:.1}" r="{:.1}" fill="{col}" fill-opacity="0.06" stroke="{col}" stroke-dasharray="6 4"/>"##,
            ra * s
        );
        let _ = writeln!(
            o,
            r##"<circle cx="{cx:.1}" cy="{cy:.1}" r="{:.1}" fill="none" stroke="#555" stroke-dasharray="1 4"/>"##,
            r * s
        );
        let _ = writeln!(
            o,
            r##"<circle cx="{cx:.1}" cy="{cy:.1}" r="{:.1}" fill="none" stroke="{col}" stroke-width="2"/>"##,
            rb * s
        );
        let _ = writeln!(o, r##"<circle cx="{cx:.1}" cy="{cy:.1}" r="4"/>"##);
    }
    let _ = writeln!(
        o,
        r##"<text x="{:.1}" y="{:.1}" fill="#c0392b">gear 1 (c1)</text><text x="{:.1}" y="{:.1}" fill="#1f4e9c">gear 2 (c2)</text>"##,
        cx1 - 40.0,
        cy + 24.0,
        cx2 - 20.0,
        cy + 24.0
    );
    let _ = writeln!(
        o,
        r##"<line x1="{cx1:.1}" y1="{cy:.1}" x2="{cx2:.1}" y2="{cy:.1}" stroke="#999" stroke-dasharray="3 3"/>"##
    );
    for (c, t) in [((cx1, cy), t1), ((cx2, cy), t2)] {
        let _ = writeln!(
            o,
            r##"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#777"/>"##,
            c.0, c.1, t.0, t.1
        );
    }
    let _ = writeln!(
        o,
        r##"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#222" stroke-width="1.5"/>"##,
        t1.0, t1.1, t2.0, t2.1
    );
    let _ = writeln!(
        o,
        r##"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#2e7d32" stroke-width="6" stroke-opacity="0.8"/>"##,
        pa.0, pa.1, pe.0, pe.1
    );
    // labels: tangent points below/right, A and E on one side, C on the other
    let sub = |n: u8| format!(r#"T<tspan baseline-shift="sub" font-size="11">{n}</tspan>"#);
    for (i, (pt, lab)) in [
        (t1, sub(1)),
        (t2, sub(2)),
        (pa, "A".into()),
        (pe, "E".into()),
        (pc, "C".into()),
    ]
    .iter()
    .enumerate()
    {
        let side = if i == 4 { -1.0 } else { 1.0 };
        let off = if i < 2 { 16.0 } else { 14.0 };
        let (lx, ly) = (
            pt.0 + side * off * normal.0 - 6.0,
            pt.1 + side * off * normal.1 + 5.0,
        );
        let _ = writeln!(
            o,
            r##"<circle cx="{:.1}" cy="{:.1}" r="3.5"/><text x="{lx:.1}" y="{ly:.1}" font-weight="bold">{lab}</text>"##,
            pt.0, pt.1
        );
    }
    // scale bar 10 mm
    let _ = writeln!(
        o,
        r##"<line x1="30" y1="{y:.1}" x2="{x2:.1}" y2="{y:.1}" stroke="black" stroke-width="3"/><text x="30" y="{ty:.1}">10 mm</text>"##,
        y = h - 30.0,
        x2 = 30.0 + 0.010 * s,
        ty = h - 40.0
    );
    let _ = writeln!(o, "</svg>");
    o
}

/// Columns of a CSV with a header line of quoted names.
pub fn read_csv(text: &str) -> Result<(Vec<String>, Vec<Vec<f64>>), String> {
    let mut lines = text.lines();
    let head: Vec<String> = lines
        .next()
        .ok_or("empty CSV")?
        .split(',')
        .map(|s| s.trim().trim_matches('"').to_string())
        .collect();
    let mut cols = vec![Vec::new(); head.len()];
    for (n, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        for (i, f) in line.split(',').enumerate() {
            let v: f64 = f
                .trim()
                .parse()
                .map_err(|e| format!("CSV line {}: {f}: {e}", n + 2))?;
            cols.get_mut(i).ok_or("ragged CSV")?.push(v);
        }
    }
    Ok((head, cols))
}

fn nice_step(span: f64) -> f64 {
    let raw = span / 5.0;
    let mag = 10f64.powf(raw.log10().floor());
    let r = raw / mag;
    mag * if r < 1.5 {
        1.0
    } else if r < 3.5 {
        2.0
    } else if r < 7.5 {
        5.0
    } else {
        10.0
    }
}

/// One panel: y(x) with ticks and labels, at (x0, y0) of size (w, h).
#[allow(clippy::too_many_arguments)]
fn panel(
    o: &mut String,
    x0: f64,
    y0: f64,
    w: f64,
    h: f64,
    xs: &[f64],
    ys: &[f64],
    label: &str,
    col: &str,
) {
    let (xmin, xmax) = (xs[0], xs[xs.len() - 1]);
    let (mut ymin, mut ymax) = ys
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &y| (a.min(y), b.max(y)));
    if ymax - ymin < 1e-12 {
        ymax += 1.0;
        ymin -= 1.0;
    }
    let ys_step = nice_step(ymax - ymin);
    let (ylo, yhi) = (
        (ymin / ys_step).floor() * ys_step,
        (ymax / ys_step).ceil() * ys_step,
    );
    let px = |x: f64| x0 + (x - xmin) / (xmax - xmin) * w;
    let py = |y: f64| y0 + h - (y - ylo) / (yhi - ylo) * h;
    let _ = writeln!(
        o,
        r##"<rect x="{x0}" y="{y0}" width="{w}" height="{h}" fill="none" stroke="#444"/>"##
    );
    let mut y = ylo;
    while y <= yhi + 1e-9 * ys_step {
        let _ = writeln!(
            o,
            r##"<line x1="{x0}" y1="{py:.1}" x2="{x1}" y2="{py:.1}" stroke="#ddd"/><text x="{tx}" y="{ty:.1}" text-anchor="end">{y}</text>"##,
            py = py(y),
            x1 = x0 + w,
            tx = x0 - 6.0,
            ty = py(y) + 5.0,
            y = (y * 1e6).round() / 1e6
        );
        y += ys_step;
    }
    let xs_step = nice_step(xmax - xmin);
    let mut x = (xmin / xs_step).ceil() * xs_step;
    while x <= xmax + 1e-9 * xs_step {
        let _ = writeln!(
            o,
            r##"<line x1="{px:.1}" y1="{y0}" x2="{px:.1}" y2="{y1}" stroke="#ddd"/><text x="{px:.1}" y="{ty}" text-anchor="middle">{x}</text>"##,
            px = px(x),
            y1 = y0 + h,
            ty = y0 + h + 18.0,
            x = (x * 1e6).round() / 1e6
        );
        x += xs_step;
    }
    let pts: Vec<String> = xs
        .iter()
        .zip(ys)
        .map(|(&x, &y)| format!("{:.1},{:.1}", px(x), py(y)))
        .collect();
    let _ = writeln!(
        o,
        r##"<polyline points="{}" fill="none" stroke="{col}" stroke-width="1.6"/>"##,
        pts.join(" ")
    );
    let _ = writeln!(
        o,
        r##"<text x="{x0}" y="{ty}" font-weight="bold">{label}</text>"##,
        ty = y0 - 8.0
    );
}

/// SVG of the reference run: T1, Fn and TE over time, from the stored CSV.
pub fn result_plot(csv: &str) -> Result<String, String> {
    let (head, cols) = read_csv(csv)?;
    let col = |n: &str| {
        head.iter()
            .position(|h| h == n)
            .map(|i| &cols[i])
            .ok_or(format!("reference CSV has no column {n}"))
    };
    let t: Vec<f64> = col("time")?.iter().map(|t| t * 1e3).collect();
    let t1 = col("T1")?.clone();
    let fn_kn: Vec<f64> = col("Fn")?.iter().map(|f| f * 1e-3).collect();
    let te_um: Vec<f64> = col("TE")?.iter().map(|x| x * 1e6).collect();
    let (w, h) = (900.0, 620.0);
    let mut o = String::new();
    let _ = writeln!(
        o,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="14">"#
    );
    let _ = writeln!(o, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
    let (x0, pw, ph) = (80.0, 790.0, 130.0);
    panel(
        &mut o,
        x0,
        40.0,
        pw,
        ph,
        &t,
        &t1,
        "T1 driving torque [N m]",
        "#c0392b",
    );
    panel(
        &mut o,
        x0,
        230.0,
        pw,
        ph,
        &t,
        &fn_kn,
        "Fn normal contact force [kN]",
        "#1f4e9c",
    );
    panel(
        &mut o,
        x0,
        420.0,
        pw,
        ph,
        &t,
        &te_um,
        "TE transmission error [\u{b5}m]",
        "#2e7d32",
    );
    let _ = writeln!(
        o,
        r#"<text x="{}" y="{}" text-anchor="middle">time [ms]</text>"#,
        x0 + pw / 2.0,
        h - 20.0
    );
    let _ = writeln!(o, "</svg>");
    Ok(o)
}
