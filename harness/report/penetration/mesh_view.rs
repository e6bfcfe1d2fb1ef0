//! One mesh picture ([`SectionFrame`]) as a self-contained SVG: each body's triangles filled
//! in its own colour with their edges drawn, clipped to the window, with millimetre ticks on
//! two sides, the time and event in the title and a legend of the bodies.

use impact_solver::remesh::SectionFrame;

use crate::report::{format, text_fit};

/// Width of a mesh picture (px).
pub const MESH_VIEW_WIDTH: u32 = 360;

/// Fill and edge colours of the bodies: the remeshed body first, then the others in model
/// order (Tableau hues, light fills so that the edges read).
const REMESHED: (&str, &str) = ("#f3e3c8", "#8a5a19");
const OTHERS: [(&str, &str); 3] = [
    ("#c6dbef", "#1f4e8c"),
    ("#d4ecd0", "#2c7a2c"),
    ("#e5d7ee", "#6a3d9a"),
];

/// The time in the unit that suits it: microseconds below a millisecond.
pub fn time_text(t: f64) -> String {
    if !t.is_finite() {
        "t = ?".into()
    } else if t.abs() < 1e-3 {
        format!("t = {} µs", format::num(t * 1e6))
    } else {
        format!("t = {} ms", format::num(t * 1e3))
    }
}

/// The caption of a picture: the time, what the state is and the remeshings made.
pub fn caption(frame: &SectionFrame) -> String {
    let what = match frame.event.as_str() {
        "start" => "start".to_string(),
        "remeshing" => format!("after remeshing {}", frame.remeshings),
        "end" => format!("end ({} remeshings)", frame.remeshings),
        other => other.to_string(),
    };
    format!("{}, {what}", time_text(frame.time))
}

/// A step of 1, 2 or 5 times a power of ten giving about `n` intervals over `span`.
fn nice_step(span: f64, n: f64) -> f64 {
    let raw = (span / n).max(f64::MIN_POSITIVE);
    let p = 10f64.powf(raw.log10().floor());
    let m = raw / p;
    p * if m < 1.5 {
        1.0
    } else if m < 3.5 {
        2.0
    } else if m < 7.5 {
        5.0
    } else {
        10.0
    }
}

/// The extent `[[h_min, v_min], [h_max, v_max]]` shown: the window, or the triangles' bounding
/// box; `None` when there is nothing to show.
fn extent(frame: &SectionFrame) -> Option<[[f64; 2]; 2]> {
    if let Some(w) = frame.window {
        return Some(w);
    }
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for t in frame.bodies.iter().flat_map(|b| &b.triangles) {
        for k in 0..3 {
            for a in 0..2 {
                lo[a] = lo[a].min(t[2 * k + a]);
                hi[a] = hi[a].max(t[2 * k + a]);
            }
        }
    }
    (lo[0] < hi[0] && lo[1] < hi[1]).then_some([lo, hi])
}

/// The `<text>` elements of the title lines `t1` (in the title's size) and the caption lines
/// `t2` below them, centred on `cx`, `step` apart.
fn title_lines(t1: &[String], t2: &[String], cx: f64, font: f64, step: f64) -> String {
    let sized = t1
        .iter()
        .map(|l| (l, format!(" font-size=\"{:.1}\"", font * 1.1)));
    let plain = t2.iter().map(|l| (l, String::new()));
    sized
        .chain(plain)
        .enumerate()
        .map(|(i, (line, size))| {
            format!(
                "<text x=\"{cx:.1}\" y=\"{:.1}\" text-anchor=\"middle\"{size}>{}</text>\n",
                font * 1.2 + i as f64 * step,
                format::html(line)
            )
        })
        .collect()
}

/// A legend entry: its label, its colours (fill, edge), its x (px) and its row.
type LegendEntry = (String, (&'static str, &'static str), f64, usize);

/// The legend's entries, one per body with its element count, wrapped to the width `w` (px)
/// from `left`; and the last row's index.
fn legend_entries(frame: &SectionFrame, left: f64, w: f64, font: f64) -> (Vec<LegendEntry>, usize) {
    let mut entries = Vec::new();
    let (mut x, mut row) = (left, 0usize);
    let mut others = OTHERS.iter().cycle();
    for body in &frame.bodies {
        let colours = if body.remeshed {
            REMESHED
        } else {
            *others.next().unwrap_or(&OTHERS[0])
        };
        let label = format!("{} ({} elements)", body.name, body.elements);
        let entry_w = font + 12.0 + 6.2 * label.chars().count() as f64;
        if x > left && x + entry_w > w {
            x = left;
            row += 1;
        }
        entries.push((label, colours, x, row));
        x += entry_w;
    }
    (entries, row)
}

/// The picture as an SVG `width` px wide; `id` makes its clip path's id unique on the page.
pub fn mesh_svg(frame: &SectionFrame, title: &str, id: &str, width: u32) -> String {
    let font = 11.0;
    let w = width as f64;
    // Title and caption lines, wrapped to the width rather than cut at its edges, then the
    // vertical axis's name above the picture.
    let title_font = font * 1.1;
    let step = font * 1.25;
    let t1 = text_fit::wrap(title, title_font, w - 8.0);
    let t2 = text_fit::wrap(
        &format!(
            "{}, plane {} = {} mm",
            caption(frame),
            frame.axis.name(),
            format::num(frame.value * 1e3)
        ),
        font,
        w - 8.0,
    );
    let extra_lines = (t1.len() + t2.len()).saturating_sub(2) as f64;
    let (left, right, top) = (44.0, 10.0, font * 4.6 + extra_lines * step);
    let plot_w = w - left - right;
    let names: Vec<String> = frame
        .drawing_axes
        .iter()
        .map(|a| a.name().to_string())
        .collect();
    let mut s = String::new();
    let Some([lo, hi]) = extent(frame) else {
        return format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"60\" \
             font-family=\"sans-serif\" font-size=\"{font}\"><text x=\"8\" y=\"20\">{}</text>\
             <text x=\"8\" y=\"40\">no face in the plane {} = {}</text></svg>\n",
            format::html(title),
            frame.axis.name(),
            format::num(frame.value)
        );
    };
    let span = [hi[0] - lo[0], hi[1] - lo[1]];
    let scale = plot_w / span[0];
    // A tall window is shrunk to at most 1.8 times the width.
    let scale = scale.min(1.8 * plot_w / span[1]);
    let (pw, ph) = (span[0] * scale, span[1] * scale);
    let (entries, row) = legend_entries(frame, left, w, font);
    // Tick labels, the horizontal axis's name, then the legend.
    let legend_y = top + ph + font * 5.0;
    let height = legend_y + font * 1.5 * (row as f64 + 1.0);
    let px = |h: f64| left + (h - lo[0]) * scale;
    let py = |v: f64| top + ph - (v - lo[1]) * scale;
    s.push_str(&format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{h:.0}\" \
         viewBox=\"0 0 {width} {h:.0}\" font-family=\"sans-serif\" font-size=\"{font}\">\n\
         <rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n{lines}\
         <defs><clipPath id=\"{id}\"><rect x=\"{left:.2}\" y=\"{top:.2}\" width=\"{pw:.2}\" height=\"{ph:.2}\"/></clipPath></defs>\n",
        h = height.ceil(),
        lines = title_lines(&t1, &t2, w / 2.0, font, step),
    ));
    s.push_str(&format!(
        "<g clip-path=\"url(#{id})\" stroke-linejoin=\"round\">\n"
    ));
    for (body, (_, (fill, edge), _, _)) in frame.bodies.iter().zip(&entries) {
        if body.triangles.is_empty() {
            continue;
        }
        let mut d = String::with_capacity(body.triangles.len() * 40);
        for t in &body.triangles {
            d.push_str(&format!(
                "M{:.1} {:.1}L{:.1} {:.1}L{:.1} {:.1}Z",
                px(t[0]),
                py(t[1]),
                px(t[2]),
                py(t[3]),
                px(t[4]),
                py(t[5])
            ));
        }
        s.push_str(&format!(
            "<path d=\"{d}\" fill=\"{fill}\" stroke=\"{edge}\" stroke-width=\"0.5\"><title>{}</title></path>\n",
            format::html(&body.name)
        ));
    }
    s.push_str("</g>\n");
    s.push_str(&format!(
        "<rect x=\"{left:.2}\" y=\"{top:.2}\" width=\"{pw:.2}\" height=\"{ph:.2}\" fill=\"none\" stroke=\"#444\" stroke-width=\"0.8\"/>\n"
    ));
    // Millimetre ticks on the bottom and left sides.
    let step = nice_step(span[0].max(span[1]) * 1e3, 5.0) * 1e-3;
    let ticks = |a: f64, b: f64| {
        let first = (a / step).ceil() as i64;
        let last = (b / step).floor() as i64;
        (first..=last).map(move |k| k as f64 * step)
    };
    let bottom = top + ph;
    for h in ticks(lo[0], hi[0]) {
        let x = px(h);
        s.push_str(&format!(
            "<line x1=\"{x:.2}\" y1=\"{bottom:.2}\" x2=\"{x:.2}\" y2=\"{:.2}\" stroke=\"#444\"/>\
             <text x=\"{x:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}</text>\n",
            bottom + 4.0,
            bottom + 4.0 + font,
            format::tick(h * 1e3)
        ));
    }
    for v in ticks(lo[1], hi[1]) {
        let y = py(v);
        s.push_str(&format!(
            "<line x1=\"{:.2}\" y1=\"{y:.2}\" x2=\"{left:.2}\" y2=\"{y:.2}\" stroke=\"#444\"/>\
             <text x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"end\">{}</text>\n",
            left - 4.0,
            left - 6.0,
            y + font * 0.35,
            format::tick(v * 1e3)
        ));
    }
    s.push_str(&format!(
        "<text x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{} (mm)</text>\n\
         <text x=\"4\" y=\"{:.2}\">{} (mm)</text>\n",
        left + pw / 2.0,
        bottom + 4.0 + 2.3 * font,
        names[0],
        top - font * 0.7,
        names[1]
    ));
    // Legend: one swatch per body with its element count.
    for (label, (fill, edge), x, row) in &entries {
        let y = legend_y + font * 1.5 * *row as f64;
        s.push_str(&format!(
            "<rect x=\"{x:.2}\" y=\"{:.2}\" width=\"{f:.1}\" height=\"{f:.1}\" fill=\"{fill}\" stroke=\"{edge}\"/>\
             <text x=\"{:.2}\" y=\"{y:.2}\">{}</text>\n",
            y - font * 0.85,
            x + font + 4.0,
            format::html(label),
            f = font
        ));
    }
    s.push_str("</svg>\n");
    s
}
