//! Renders a [`PlotData`] as an SVG string with plotters' SVG backend (text stays `<text>`, so
//! no font files are needed). Bad data never panics: non-finite points, and non-positive ones on
//! log axes, are dropped; a plot with nothing left becomes a small "no data" SVG.

use std::error::Error;

use plotters::backend::SVGBackend;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::{to_plot, Axis};
use super::text_fit;
use crate::results::PlotData;

/// Size of a case plot: wide enough for six tick labels, small enough for two side by side on
/// a 1280 px screen.
pub const PLOT_SIZE: (u32, u32) = (560, 360);
/// Size of a trend plot: three of them sit in a row on a 1280 px screen.
pub const TREND_SIZE: (u32, u32) = (370, 250);

/// Tableau-10: distinguishable on white and for the common colour-vision deficiencies.
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];
const FONT: &str = "sans-serif";
/// plotters writes `font-size` as the requested size divided by 1.24: 17 gives about 13.7 px.
const LABEL_FONT: u32 = 17;
const DESC_FONT: u32 = 18;
const TITLE_FONT: u32 = 22;
/// plotters' SVG backend writes a requested font size `s` as `font-size="s / 1.24"` pixels.
const SVG_FONT_SCALE: f64 = 1.24;
/// Space above and below the title, as plotters leaves around a caption.
const TITLE_PAD: i32 = 5;
const LEGEND_FONT: u32 = 17;
const LEGEND_ROW: u32 = 22;
const LEGEND_SWATCH: i32 = 28;
const CHART_MARGIN: u32 = 12;
/// Left edge of the legend: under the y labels, so that two entries fit on a trend plot's row.
const LEGEND_LEFT: i32 = 40;
const Y_LABEL_AREA: u32 = 88;
const X_LABEL_AREA: u32 = 50;
/// Curves with more points than this are drawn without markers (markers would blur the line).
const MAX_MARKERS: usize = 40;

/// Renders `plot` at the default case-plot size.
pub fn render_plot(plot: &PlotData) -> String {
    render_plot_sized(plot, PLOT_SIZE)
}

/// Renders `plot` at `size` (the legend adds rows below); never panics on bad data.
pub fn render_plot_sized(plot: &PlotData, size: (u32, u32)) -> String {
    render_plot_with(plot, &PlotExtras::default(), size)
}

/// A target window `[x_lo, x_hi] x [y_lo, y_hi]` in data units with its legend label.
pub type TargetWindow<'a> = ([f64; 2], [f64; 2], &'a str);

/// What a plot may show beyond [`PlotData`]: a logarithmic x axis alone, target windows, and
/// reference curves drawn dashed.
#[derive(Debug, Clone, Default)]
pub struct PlotExtras<'a> {
    /// Logarithmic x axis alone (`PlotData::log_log` makes both logarithmic).
    pub log_x: bool,
    /// Logarithmic y axis alone.
    pub log_y: bool,
    /// Target windows, drawn shaded behind the curves.
    pub boxes: Vec<TargetWindow<'a>>,
    /// Names of the series drawn dashed (reference curves rather than results).
    pub dashed: Vec<&'a str>,
}

/// Renders `plot` with `extras` at `size`; never panics on bad data.
pub fn render_plot_with(plot: &PlotData, extras: &PlotExtras<'_>, size: (u32, u32)) -> String {
    match Scene::prepare(plot, extras) {
        Some(scene) => draw_scene(&scene, plot, size)
            .unwrap_or_else(|e| message_svg(&plot.title, &format!("plot failed: {e}"), size.0)),
        None => message_svg(&plot.title, "no data to plot", size.0),
    }
}

/// A curve in plot space.
struct Curve {
    name: String,
    color: RGBColor,
    points: Vec<(f64, f64)>,
    dashed: bool,
}

/// A target window in plot space, clamped to the axes.
struct TargetBox {
    label: String,
    color: RGBColor,
    x: (f64, f64),
    y: (f64, f64),
}

/// A reference line and its acceptance band, in plot space; either may be missing (off a log
/// axis).
struct Reference {
    label: String,
    color: RGBColor,
    y: Option<f64>,
    band: Option<(f64, f64)>,
}

/// What is left of a [`PlotData`] once undrawable values are dropped, with the axes to draw on.
struct Scene {
    x: Axis,
    y: Axis,
    curves: Vec<Curve>,
    references: Vec<Reference>,
    boxes: Vec<TargetBox>,
}

impl Scene {
    /// The drawable part of `plot`, or `None` when no series has a drawable point (reference
    /// lines alone say nothing).
    fn prepare(plot: &PlotData, extras: &PlotExtras<'_>) -> Option<Scene> {
        let log_y = plot.log_log || extras.log_y;
        let log_x = plot.log_log || extras.log_x;
        let curves = curves(plot, extras, log_x, log_y);
        let points = || curves.iter().flat_map(|c| c.points.iter());
        let box_values = |log: bool, pick: fn(&TargetWindow<'_>) -> [f64; 2]| {
            extras
                .boxes
                .iter()
                .flat_map(pick)
                .filter_map(move |v| to_plot(v, log))
                .collect::<Vec<f64>>()
        };
        let mut x = Axis::spanning(
            points().map(|p| p.0).chain(box_values(log_x, |b| b.0)),
            log_x,
        )?;
        x.integer = !log_x && points().all(|p| p.0.fract() == 0.0);
        let y = Axis::spanning(
            points()
                .map(|p| p.1)
                .chain(reference_plot_values(plot, log_y))
                .chain(box_values(log_y, |b| b.1)),
            log_y,
        )?;
        let references = references(plot, &y, curves.len());
        let first_box_color = plot.series.len() + plot.reference_lines.len();
        let boxes = extras
            .boxes
            .iter()
            .enumerate()
            .filter_map(|(i, (bx, by, label))| {
                Some(TargetBox {
                    label: label.to_string(),
                    color: PALETTE[(first_box_color + i) % PALETTE.len()],
                    x: band(&x, *bx)?,
                    y: band(&y, *by)?,
                })
            })
            .collect();
        Some(Scene {
            x,
            y,
            curves,
            references,
            boxes,
        })
    }
}

/// The series with their drawable points mapped to plot space; empty series are dropped, and
/// colours follow the series index so that they do not shift when one is dropped.
fn curves(plot: &PlotData, extras: &PlotExtras<'_>, log_x: bool, log_y: bool) -> Vec<Curve> {
    plot.series
        .iter()
        .enumerate()
        .map(|(i, s)| Curve {
            name: s.name.clone(),
            color: PALETTE[i % PALETTE.len()],
            points: s
                .x
                .iter()
                .zip(&s.y)
                .filter_map(|(&x, &y)| Some((to_plot(x, log_x)?, to_plot(y, log_y)?)))
                .collect(),
            dashed: extras.dashed.contains(&s.name.as_str()),
        })
        .filter(|c| !c.points.is_empty())
        .collect()
}

/// Plot-space values of the reference lines and bands, so that the y axis covers them.
fn reference_plot_values(plot: &PlotData, log: bool) -> Vec<f64> {
    plot.reference_lines
        .iter()
        .flat_map(|r| std::iter::once(r.y).chain(r.band.into_iter().flatten()))
        .filter_map(|v| to_plot(v, log))
        .collect()
}

/// The reference lines in plot space. A band reaching below zero on a log axis is cut at the
/// bottom of the axis; colours continue after the series' so that no line shares a colour.
fn references(plot: &PlotData, y: &Axis, first_color: usize) -> Vec<Reference> {
    plot.reference_lines
        .iter()
        .enumerate()
        .map(|(i, r)| Reference {
            label: r.label.clone(),
            color: PALETTE[(first_color + i) % PALETTE.len()],
            y: y.map(r.y),
            band: r.band.and_then(|b| band(y, b)),
        })
        .filter(|r| r.y.is_some() || r.band.is_some())
        .collect()
}

/// A band `[a, b]` in plot space, clamped to the axis; `None` if it cannot be drawn.
fn band(y: &Axis, [a, b]: [f64; 2]) -> Option<(f64, f64)> {
    if !(a.is_finite() && b.is_finite()) {
        return None;
    }
    let (lo, hi) = (a.min(b), a.max(b));
    let hi = y.map(hi)?;
    let lo = y.map(lo).unwrap_or(y.lo);
    Some((y.clamp(lo), y.clamp(hi)))
}

/// Draws the chart and its legend strip into one SVG string; a title too long for one line
/// adds its further lines to the height, so that the chart keeps its size.
fn draw_scene(scene: &Scene, plot: &PlotData, size: (u32, u32)) -> Result<String, Box<dyn Error>> {
    let legend = Legend::layout(scene, size.0);
    let title = Title::layout(&plot.title, size.0);
    let chart_h = size.1 + title.extra_height();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (size.0, chart_h + legend.height))
            .into_drawing_area();
        root.fill(&WHITE)?;
        let (chart_area, legend_area) = root.split_vertically(chart_h);
        let chart_area = title.draw(&chart_area)?;
        draw_chart(&chart_area, scene, plot)?;
        legend.draw(&legend_area)?;
        root.present()?;
    }
    Ok(svg)
}

/// Axes, grid, bands, reference lines and curves, in that order so that curves stay on top.
fn draw_chart(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    scene: &Scene,
    plot: &PlotData,
) -> Result<(), Box<dyn Error>> {
    let (x, y) = (scene.x, scene.y);
    let mut chart = ChartBuilder::on(area)
        .margin(CHART_MARGIN)
        .margin_right(2 * CHART_MARGIN)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(x, y)?;
    chart
        .configure_mesh()
        .x_desc(plot.x_label.as_str())
        .y_desc(plot.y_label.as_str())
        .x_label_formatter(&|v| x.label(*v))
        .y_label_formatter(&|v| y.label(*v))
        .label_style((FONT, LABEL_FONT))
        .axis_desc_style((FONT, DESC_FONT))
        .bold_line_style(BLACK.mix(0.12))
        .light_line_style(TRANSPARENT)
        .draw()?;
    for r in &scene.references {
        if let Some((lo, hi)) = r.band {
            chart.draw_series(std::iter::once(Rectangle::new(
                [(x.lo, lo), (x.hi, hi)],
                r.color.mix(0.15).filled(),
            )))?;
        }
        if let Some(v) = r.y {
            chart.draw_series(DashedLineSeries::new(
                [(x.lo, v), (x.hi, v)],
                8,
                5,
                r.color.stroke_width(2),
            ))?;
        }
    }
    for b in &scene.boxes {
        chart.draw_series(std::iter::once(Rectangle::new(
            [(b.x.0, b.y.0), (b.x.1, b.y.1)],
            b.color.mix(0.18).filled(),
        )))?;
        chart.draw_series(std::iter::once(Rectangle::new(
            [(b.x.0, b.y.0), (b.x.1, b.y.1)],
            b.color.stroke_width(1),
        )))?;
    }
    for c in &scene.curves {
        if c.dashed {
            chart.draw_series(DashedLineSeries::new(
                c.points.iter().copied(),
                8,
                5,
                c.color.stroke_width(2),
            ))?;
            continue;
        }
        chart.draw_series(LineSeries::new(
            c.points.iter().copied(),
            c.color.stroke_width(2),
        ))?;
        if c.points.len() <= MAX_MARKERS {
            chart.draw_series(
                c.points
                    .iter()
                    .map(|&p| Circle::new(p, 3, c.color.filled())),
            )?;
        }
    }
    Ok(())
}

/// The plot's title, wrapped to the plot's width: plotters' caption is one line centred on the
/// plot, and a longer one runs off both edges, cut at the left where the reader starts.
struct Title {
    lines: Vec<String>,
    width: u32,
}

impl Title {
    /// The title in the pixel size plotters writes it at.
    const FONT_PX: f64 = TITLE_FONT as f64 / SVG_FONT_SCALE;
    /// Baseline-to-baseline distance of the title's lines.
    const LINE_STEP: u32 = (Self::FONT_PX * 1.25) as u32 + 1;

    /// `title` broken into lines that fit `width` less the chart's margins on both sides; no
    /// lines for an empty title.
    fn layout(title: &str, width: u32) -> Title {
        let room = f64::from(width.saturating_sub(2 * CHART_MARGIN));
        let lines = if title.trim().is_empty() {
            Vec::new()
        } else {
            text_fit::wrap(title, Self::FONT_PX, room)
        };
        Title { lines, width }
    }

    /// The height the lines after the first add to the plot.
    fn extra_height(&self) -> u32 {
        self.lines.len().saturating_sub(1) as u32 * Self::LINE_STEP
    }

    /// Draws the lines centred at the top of `area`; returns the area below them.
    fn draw<'a>(
        &self,
        area: &DrawingArea<SVGBackend<'a>, Shift>,
    ) -> Result<DrawingArea<SVGBackend<'a>, Shift>, Box<dyn Error>> {
        if self.lines.is_empty() {
            return Ok(area.clone());
        }
        let style = TextStyle::from((FONT, TITLE_FONT).into_font())
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Top));
        let cx = self.width as i32 / 2;
        for (i, line) in self.lines.iter().enumerate() {
            let y = TITLE_PAD + (i as u32 * Self::LINE_STEP) as i32;
            area.draw(&Text::new(line.clone(), (cx, y), &style))?;
        }
        let height = 2 * TITLE_PAD as u32 + Self::FONT_PX.ceil() as u32 + self.extra_height();
        Ok(area.split_vertically(height).1)
    }
}

/// How a legend entry's swatch looks.
#[derive(Clone, Copy)]
enum Swatch {
    Line,
    Dashed,
    DashedOnBand,
    Band,
}

/// One legend entry placed at `(x, row)`, its label on one line or, if wider than the strip,
/// on as many rows as it needs.
struct Entry {
    swatch: Swatch,
    color: RGBColor,
    lines: Vec<String>,
    x: i32,
    row: u32,
}

/// The legend below the chart: drawn by hand in its own strip because plotters' in-chart legend
/// box hides the curves it labels.
struct Legend {
    entries: Vec<Entry>,
    height: u32,
}

impl Legend {
    /// Flows the entries left to right into rows no wider than `width`.
    fn layout(scene: &Scene, width: u32) -> Legend {
        let items = scene
            .curves
            .iter()
            .map(|c| {
                let swatch = if c.dashed {
                    Swatch::Dashed
                } else {
                    Swatch::Line
                };
                (swatch, c.color, c.name.clone())
            })
            .chain(
                scene
                    .references
                    .iter()
                    .map(|r| (swatch(r), r.color, r.label.clone())),
            )
            .chain(
                scene
                    .boxes
                    .iter()
                    .map(|b| (Swatch::Band, b.color, b.label.clone())),
            )
            .filter(|(_, _, label)| !label.is_empty());
        let left = LEGEND_LEFT;
        // Widths bounded from above glyph by glyph (`text_fit`): no label runs off the picture.
        let font_px = f64::from(LEGEND_FONT) / SVG_FONT_SCALE;
        let label_room = (width as i32 - left - LEGEND_SWATCH - 8 - CHART_MARGIN as i32).max(40);
        let (mut x, mut row) = (left, 0);
        let mut entries = Vec::new();
        for (swatch, color, label) in items {
            let text_w = text_fit::width_bound(&label, font_px).ceil() as i32;
            let lines = if text_w > label_room {
                text_fit::wrap(&label, font_px, f64::from(label_room))
            } else {
                vec![label]
            };
            let w = LEGEND_SWATCH + 8 + text_w.min(label_room) + 20;
            if x > left && (x + w > width as i32 || lines.len() > 1) {
                x = left;
                row += 1;
            }
            let rows = lines.len() as u32;
            entries.push(Entry {
                swatch,
                color,
                lines,
                x,
                row,
            });
            if rows > 1 {
                // A wrapped label takes its rows whole; the next entry starts below it.
                x = left;
                row += rows;
            } else {
                x += w;
            }
        }
        let height = entries
            .last()
            .map_or(0, |e| (e.row + e.lines.len() as u32) * LEGEND_ROW + 8);
        Legend { entries, height }
    }

    /// Draws the entries into the legend strip.
    fn draw(&self, area: &DrawingArea<SVGBackend<'_>, Shift>) -> Result<(), Box<dyn Error>> {
        let style = TextStyle::from((FONT, LEGEND_FONT).into_font())
            .color(&BLACK)
            .pos(Pos::new(HPos::Left, VPos::Center));
        for e in &self.entries {
            let cy = (e.row * LEGEND_ROW + LEGEND_ROW / 2) as i32;
            draw_swatch(area, e.swatch, e.color, (e.x, cy))?;
            for (k, line) in e.lines.iter().enumerate() {
                area.draw(&Text::new(
                    line.clone(),
                    (e.x + LEGEND_SWATCH + 8, cy + (k as u32 * LEGEND_ROW) as i32),
                    &style,
                ))?;
            }
        }
        Ok(())
    }
}

/// The swatch of a reference: dashed line, band, or dashed line on its band.
fn swatch(r: &Reference) -> Swatch {
    match (r.y.is_some(), r.band.is_some()) {
        (true, true) => Swatch::DashedOnBand,
        (true, false) => Swatch::Dashed,
        _ => Swatch::Band,
    }
}

/// Draws one swatch whose left end is at `(x, cy)`.
fn draw_swatch(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    swatch: Swatch,
    color: RGBColor,
    (x, cy): (i32, i32),
) -> Result<(), Box<dyn Error>> {
    let end = x + LEGEND_SWATCH;
    if matches!(swatch, Swatch::Band | Swatch::DashedOnBand) {
        area.draw(&Rectangle::new(
            [(x, cy - 7), (end, cy + 7)],
            color.mix(0.15).filled(),
        ))?;
    }
    let stroke = color.stroke_width(2);
    match swatch {
        Swatch::Line => {
            area.draw(&PathElement::new(vec![(x, cy), (end, cy)], stroke))?;
            area.draw(&Circle::new((x + LEGEND_SWATCH / 2, cy), 3, color.filled()))?;
        }
        Swatch::Dashed | Swatch::DashedOnBand => {
            area.draw(&PathElement::new(vec![(x, cy), (x + 10, cy)], stroke))?;
            area.draw(&PathElement::new(vec![(x + 16, cy), (end, cy)], stroke))?;
        }
        Swatch::Band => {}
    }
    Ok(())
}

/// A small SVG standing in for a plot that cannot be drawn, saying why; the text wraps to the
/// width like a title.
fn message_svg(title: &str, why: &str, width: u32) -> String {
    const LINE_STEP: u32 = 20;
    let text = if title.is_empty() {
        why.to_string()
    } else {
        format!("{title}: {why}")
    };
    let font_px = LABEL_FONT as f64 / SVG_FONT_SCALE;
    let lines = text_fit::wrap(&text, font_px, f64::from(width.saturating_sub(16)));
    let height = 90 + (lines.len() as u32 - 1) * LINE_STEP;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        let grey = BLACK.mix(0.6);
        let style = TextStyle::from((FONT, LABEL_FONT).into_font())
            .color(&grey)
            .pos(Pos::new(HPos::Center, VPos::Center));
        // Drawing into a string cannot fail for lack of space; ignore errors rather than panic.
        let _ = root.fill(&RGBColor(248, 248, 248));
        let _ = root.draw(&Rectangle::new(
            [(0, 0), (width as i32 - 1, height as i32 - 1)],
            BLACK.mix(0.2).stroke_width(1),
        ));
        let first = height as i32 / 2 - ((lines.len() as u32 - 1) * LINE_STEP / 2) as i32;
        for (i, line) in lines.into_iter().enumerate() {
            let y = first + (i as u32 * LINE_STEP) as i32;
            let _ = root.draw(&Text::new(line, (width as i32 / 2, y), &style));
        }
        let _ = root.present();
    }
    svg
}
