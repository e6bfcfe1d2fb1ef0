//! The side view of a beam frame as a self-contained SVG: cells coloured by `eps_1/eps_r`, the
//! outline, supports, impactor footprint, title and colour legend.

use super::{BeamRecord, SideView};
use crate::report::{format, text_fit};

/// Width of a full-size side view (px).
pub const SIDE_VIEW_WIDTH: u32 = 720;
/// Width of a filmstrip picture (px).
pub const FILMSTRIP_WIDTH: u32 = 340;
/// Number of colour steps from 0 to 1; values of 1 and more get their own colour.
pub(super) const STEPS: usize = 10;

/// The colour bin of a value: `0..STEPS` for `[0, 1)`, `STEPS` for cracked (1 and more).
fn bin(v: f64) -> Option<usize> {
    if !v.is_finite() {
        return None;
    }
    Some(if v >= 1.0 {
        STEPS
    } else {
        ((v.max(0.0) * STEPS as f64) as usize).min(STEPS - 1)
    })
}

/// The colour of a bin: pale yellow through orange to red below 1, dark crimson for cracked.
pub(super) fn bin_colour(b: usize) -> String {
    if b >= STEPS {
        return "#5a0016".into();
    }
    let t = (b as f64 + 0.5) / STEPS as f64;
    // Pale grey-yellow (uncracked) -> yellow -> orange -> red.
    let stops = [
        (0.0, [245.0, 245.0, 235.0]),
        (0.35, [254.0, 217.0, 118.0]),
        (0.7, [253.0, 141.0, 60.0]),
        (1.0, [215.0, 25.0, 28.0]),
    ];
    let k = stops.windows(2).position(|w| t <= w[1].0).unwrap_or(2);
    let (a, b) = (stops[k], stops[k + 1]);
    let s = (t - a.0) / (b.0 - a.0);
    let c: Vec<u8> = (0..3)
        .map(|i| (a.1[i] + s * (b.1[i] - a.1[i])).round() as u8)
        .collect();
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// The title of a frame: the case and the time.
pub fn frame_title(record: &BeamRecord, f: &SideView) -> String {
    let when = if f.time.is_finite() {
        format!("t = {} ms", format::num(1e3 * f.time))
    } else {
        "final state".to_string()
    };
    let case = match record.speed {
        Some(v) => format!("{} ({} m/s)", record.case, format::num(v)),
        None => record.case.clone(),
    };
    if f.last {
        format!("{case}: crack pattern at the end, {when}")
    } else if f.contact_end {
        format!("{case}: crack pattern at the end of the contact, {when}")
    } else {
        format!("{case}: crack pattern, {when}")
    }
}

/// The side view of one frame as a self-contained SVG `width` px wide: cells coloured by
/// `eps_1/eps_r`, the beam's outline, the supports (triangles below), the impactor's footprint
/// (a bar above), the time in the title and the colour legend below.
pub fn side_view_svg(record: &BeamRecord, f: &SideView, width: u32) -> String {
    let small = width < 500;
    let font = if small { 11.0 } else { 13.0 };
    let margin = if small { 8.0 } else { 16.0 };
    let w = width as f64;
    let scale = (w - 2.0 * margin) / record.size[0].max(f64::MIN_POSITIVE);
    let beam_h = record.size[1] * scale;
    // The title wraps to the width rather than running off both edges (a filmstrip picture is
    // narrower than a case id and its time).
    let title_font = font * 1.1;
    let title_step = title_font * 1.25;
    let title_lines = text_fit::wrap(&frame_title(record, f), title_font, w - 8.0);
    let title_h = font * 2.0 + (title_lines.len() - 1) as f64 * title_step;
    let top_band = font * 0.9 + 4.0; // the footprint bar
    let y_top = title_h + top_band;
    let support_h = font * 0.9 + 4.0;
    let legend_y = y_top + beam_h + support_h + 6.0;
    let legend_h = font * 2.6;
    let height = legend_y + legend_h;
    let px = |x: f64| margin + (x - record.origin[0]) * scale;
    // y up: row 0 at the bottom.
    let py = |y: f64| y_top + beam_h - (y - record.origin[1]) * scale;
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{h:.0}\" \
         viewBox=\"0 0 {width} {h:.0}\" font-family=\"sans-serif\" font-size=\"{font}\">\n\
         <rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
        h = height.ceil(),
    );
    for (i, line) in title_lines.iter().enumerate() {
        s.push_str(&format!(
            "<text x=\"{cx:.1}\" y=\"{ty:.1}\" text-anchor=\"middle\" font-size=\"{title_font:.1}\">{}</text>\n",
            format::html(line),
            cx = w / 2.0,
            ty = font * 1.3 + i as f64 * title_step,
        ));
    }
    // Cells, merged along x where neighbours share a colour.
    let (nx, ny) = (f.nx, f.ny);
    let (cw, ch) = (
        record.size[0] / nx.max(1) as f64,
        record.size[1] / ny.max(1) as f64,
    );
    s.push_str("<g shape-rendering=\"crispEdges\">\n");
    for j in 0..ny {
        let mut i = 0;
        while i < nx {
            let Some(b) = f.values.get(j * nx + i).copied().and_then(bin) else {
                i += 1;
                continue;
            };
            let mut k = i + 1;
            while k < nx && f.values.get(j * nx + k).copied().and_then(bin) == Some(b) {
                k += 1;
            }
            let (x0, x1) = (
                px(record.origin[0] + i as f64 * cw),
                px(record.origin[0] + k as f64 * cw),
            );
            let (y1, y0) = (
                py(record.origin[1] + j as f64 * ch),
                py(record.origin[1] + (j + 1) as f64 * ch),
            );
            s.push_str(&format!(
                "<rect x=\"{x0:.2}\" y=\"{y0:.2}\" width=\"{:.2}\" height=\"{:.2}\" fill=\"{}\"/>\n",
                x1 - x0,
                y1 - y0,
                bin_colour(b)
            ));
            i = k;
        }
    }
    s.push_str("</g>\n");
    // Outline.
    s.push_str(&format!(
        "<rect x=\"{:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{:.2}\" fill=\"none\" stroke=\"#222\" stroke-width=\"1.2\"/>\n",
        px(record.origin[0]),
        py(record.origin[1] + record.size[1]),
        record.size[0] * scale,
        beam_h
    ));
    // Supports: triangles under the bottom face.
    let bottom = py(record.origin[1]);
    for [a, b] in &record.supports {
        let (xa, xb) = (px(*a), px(*b));
        let mid = 0.5 * (xa + xb);
        let half = (0.5 * (xb - xa)).max(support_h * 0.6);
        s.push_str(&format!(
            "<polygon points=\"{mid:.2},{bottom:.2} {:.2},{:.2} {:.2},{:.2}\" fill=\"#555\"/>\n",
            mid - half,
            bottom + support_h - 2.0,
            mid + half,
            bottom + support_h - 2.0
        ));
    }
    // Impactor footprint: a hatched bar above the top face.
    if let Some([a, b]) = record.footprint {
        let top = py(record.origin[1] + record.size[1]);
        s.push_str(&format!(
            "<rect x=\"{:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{:.2}\" fill=\"#4a7bb7\" fill-opacity=\"0.55\" stroke=\"#1f3f73\"><title>impactor footprint</title></rect>\n",
            px(a),
            top - top_band + 2.0,
            (b - a) * scale,
            top_band - 3.0
        ));
    }
    // Legend: the colour steps from 0 to 1 and the cracked colour.
    let lw = (w - 2.0 * margin) * if small { 0.55 } else { 0.45 };
    let step_w = lw / STEPS as f64;
    let sh = font * 0.9;
    for b in 0..STEPS {
        s.push_str(&format!(
            "<rect x=\"{:.2}\" y=\"{legend_y:.2}\" width=\"{:.2}\" height=\"{sh:.2}\" fill=\"{}\"/>\n",
            margin + b as f64 * step_w,
            step_w + 0.3,
            bin_colour(b)
        ));
    }
    s.push_str(&format!(
        "<rect x=\"{margin:.2}\" y=\"{legend_y:.2}\" width=\"{lw:.2}\" height=\"{sh:.2}\" fill=\"none\" stroke=\"#444\" stroke-width=\"0.6\"/>\n"
    ));
    let crack_x = margin + lw + 10.0;
    s.push_str(&format!(
        "<rect x=\"{crack_x:.2}\" y=\"{legend_y:.2}\" width=\"{sh:.2}\" height=\"{sh:.2}\" fill=\"{}\" stroke=\"#444\" stroke-width=\"0.6\"/>\n\
         <text x=\"{:.2}\" y=\"{:.2}\">≥ 1 cracked</text>\n",
        bin_colour(STEPS),
        crack_x + sh + 4.0,
        legend_y + sh * 0.85
    ));
    let label_y = legend_y + sh + font + 1.0;
    s.push_str(&format!(
        "<text x=\"{margin:.2}\" y=\"{label_y:.2}\">0</text>\n\
         <text x=\"{:.2}\" y=\"{label_y:.2}\" text-anchor=\"middle\">0.5</text>\n\
         <text x=\"{:.2}\" y=\"{label_y:.2}\" text-anchor=\"end\">1</text>\n\
         <text x=\"{:.2}\" y=\"{label_y:.2}\">{}</text>\n",
        margin + lw / 2.0,
        margin + lw,
        crack_x,
        if small {
            "eps_1/eps_r"
        } else {
            "eps_1/eps_r, max over the width"
        }
    ));
    s.push_str("</svg>\n");
    s
}
