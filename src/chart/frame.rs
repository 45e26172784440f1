//! The layout every chart shares: canvas, title, plot rectangle, numeric axes with gridlines,
//! footnotes, and the "no data" placeholder.

use super::axis::Axis;
use super::svg::{SvgWriter, Tag};

pub(crate) const WIDTH: f64 = 720.0;
pub(crate) const HEIGHT: f64 = 420.0;
/// Font size of tick labels and legends.
pub(crate) const FONT: f64 = 11.0;
const TITLE_FONT: f64 = 15.0;
const LABEL_FONT: f64 = 12.0;
const NOTE_FONT: f64 = 10.0;
/// Space above the plot: the title.
pub(crate) const TOP: f64 = 40.0;
/// Space a numeric x axis needs below the plot: tick labels and the axis label.
pub(crate) const X_AXIS_HEIGHT: f64 = 6.0 + FONT + 8.0 + LABEL_FONT + 6.0;
/// Space a footnote needs at the bottom of the canvas.
pub(crate) const NOTE_HEIGHT: f64 = NOTE_FONT + 6.0;

pub(crate) const TEXT: &str = "#222222";
pub(crate) const MUTED: &str = "#555555";
const GRID: &str = "#e3e3e3";
const MINOR_GRID: &str = "#f4f4f4";
pub(crate) const AXIS: &str = "#888888";

/// Estimated width of `s` in pixels at `font`. Text cannot be measured without a renderer, so
/// this assumes a generous average sans-serif advance of 0.6 em; layouts leave room for error.
pub(crate) fn text_width(s: &str, font: f64) -> f64 {
    s.chars().count() as f64 * font * 0.6
}

/// `s` cut with an ellipsis to fit `max_px` at `font`, or `None` when it already fits.
pub(crate) fn truncate(s: &str, max_px: f64, font: f64) -> Option<String> {
    if text_width(s, font) <= max_px {
        return None;
    }
    let keep = ((max_px / (font * 0.6)).floor() as usize).saturating_sub(1).max(1);
    Some(s.chars().take(keep).collect::<String>() + "…")
}

/// Writes a `<text>` cut to `max_px`; a cut text keeps the full text as its tooltip.
pub(crate) fn fitted_text(
    w: &mut SvgWriter,
    text: &str,
    max_px: f64,
    font: f64,
    attrs: impl FnOnce(Tag<'_>) -> Tag<'_>,
) {
    match truncate(text, max_px, font) {
        None => attrs(w.tag("text")).text(text),
        Some(short) => {
            w.tag("g").open();
            w.tag("title").text(text);
            attrs(w.tag("text")).text(&short);
            w.close();
        }
    }
}

/// The plot area in canvas pixels.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Plot {
    pub left: f64,
    pub top: f64,
    pub right: f64,
    pub bottom: f64,
}

impl Plot {
    pub fn width(&self) -> f64 {
        self.right - self.left
    }

    /// The x pixel of an axis fraction (0 = left edge).
    pub fn x(&self, frac: f64) -> f64 {
        self.left + frac * self.width()
    }

    /// The y pixel of an axis fraction (0 = bottom edge).
    pub fn y(&self, frac: f64) -> f64 {
        self.bottom - frac * (self.bottom - self.top)
    }
}

/// Starts a chart document: the root element, a white background (so the chart reads the same
/// inlined in a dark page), and the title.
pub(crate) fn begin(title: &str) -> SvgWriter {
    let mut w = SvgWriter::new();
    w.tag("svg")
        .attr("xmlns", "http://www.w3.org/2000/svg")
        .attr("viewBox", format!("0 0 {WIDTH} {HEIGHT}"))
        .attr("width", WIDTH)
        .attr("height", HEIGHT)
        .attr("font-family", "sans-serif")
        .attr("font-size", FONT)
        .attr("role", "img")
        .attr("aria-label", title)
        // Inlined in HTML, shrink with a narrow page instead of overflowing it.
        .attr("style", "max-width:100%;height:auto")
        .open();
    w.tag("rect").attr("width", WIDTH).attr("height", HEIGHT).attr("fill", "#ffffff").empty();
    fitted_text(&mut w, title, WIDTH - 24.0, TITLE_FONT, |t| {
        t.attr("x", WIDTH / 2.0)
            .attr("y", 25.0)
            .attr("text-anchor", "middle")
            .attr("font-size", TITLE_FONT)
            .attr("font-weight", "bold")
            .attr("fill", TEXT)
    });
    w
}

/// A complete chart with only its title and a centred "no data" note.
pub(crate) fn no_data(title: &str) -> String {
    let mut w = begin(title);
    w.tag("text")
        .attr("x", WIDTH / 2.0)
        .attr("y", HEIGHT / 2.0)
        .attr("text-anchor", "middle")
        .attr("font-size", 14.0)
        .attr("font-style", "italic")
        .attr("fill", MUTED)
        .text("no data");
    w.finish()
}

/// A footnote at the bottom left of the canvas (e.g. how many values were not drawn).
pub(crate) fn note(w: &mut SvgWriter, text: &str) {
    fitted_text(w, text, WIDTH - 16.0, NOTE_FONT, |t| {
        t.attr("x", 8.0).attr("y", HEIGHT - 6.0).attr("font-size", NOTE_FONT).attr("fill", MUTED)
    });
}

/// The axis label as drawn: a log axis says so.
pub(crate) fn axis_title(label: &str, log: bool) -> String {
    match (log, label.is_empty()) {
        (false, _) => label.to_string(),
        (true, true) => "log scale".to_string(),
        (true, false) => format!("{label} (log scale)"),
    }
}

/// Width the y axis needs left of the plot: the rotated axis title and the tick labels.
pub(crate) fn y_axis_width(axis: &Axis, title: &str) -> f64 {
    let widest =
        axis.ticks.iter().filter_map(|t| t.label.as_deref()).map(|l| text_width(l, FONT)).fold(0.0, f64::max);
    let title_band = if title.is_empty() { 0.0 } else { LABEL_FONT + 6.0 };
    8.0 + title_band + widest + 8.0
}

/// Gridlines, tick marks, tick labels and title of a vertical numeric axis.
pub(crate) fn draw_y_axis(w: &mut SvgWriter, plot: &Plot, axis: &Axis, title: &str) {
    for tick in &axis.ticks {
        let y = plot.y(axis.fraction(tick.value));
        let (grid, mark) = if tick.label.is_some() { (GRID, 5.0) } else { (MINOR_GRID, 3.0) };
        line(w, plot.left, y, plot.right, y, grid);
        line(w, plot.left - mark, y, plot.left, y, AXIS);
        if let Some(label) = &tick.label {
            w.tag("text")
                .attr("x", plot.left - 7.0)
                .attr("y", y + FONT * 0.35)
                .attr("text-anchor", "end")
                .attr("fill", MUTED)
                .text(label);
        }
    }
    line(w, plot.left, plot.top, plot.left, plot.bottom, AXIS);
    if !title.is_empty() {
        // Rotated -90°, glyphs extend left of the baseline: x is the baseline.
        let (x, y) = (8.0 + LABEL_FONT, (plot.top + plot.bottom) / 2.0);
        fitted_text(w, title, plot.bottom - plot.top, LABEL_FONT, |t| {
            t.attr("x", x)
                .attr("y", y)
                .attr("transform", format!("rotate(-90 {} {})", super::svg::num(x), super::svg::num(y)))
                .attr("text-anchor", "middle")
                .attr("font-size", LABEL_FONT)
                .attr("fill", TEXT)
        });
    }
}

/// Gridlines, tick marks, tick labels and title of a horizontal numeric axis.
pub(crate) fn draw_x_axis(w: &mut SvgWriter, plot: &Plot, axis: &Axis, title: &str) {
    // Long labels on a narrow plot would collide: keep only every n-th label then.
    let labelled: Vec<(f64, &str)> = axis
        .ticks
        .iter()
        .filter_map(|t| t.label.as_deref().map(|l| (plot.x(axis.fraction(t.value)), l)))
        .collect();
    let widest = labelled.iter().map(|(_, l)| text_width(l, FONT)).fold(0.0, f64::max);
    let closest = labelled.windows(2).map(|p| p[1].0 - p[0].0).fold(f64::INFINITY, f64::min);
    let stride = if closest.is_finite() && closest > 0.0 {
        ((widest + 8.0) / closest).ceil().max(1.0) as usize
    } else {
        1
    };
    let mut nth = 0usize;
    for tick in &axis.ticks {
        let x = plot.x(axis.fraction(tick.value));
        let (grid, mark) = if tick.label.is_some() { (GRID, 5.0) } else { (MINOR_GRID, 3.0) };
        line(w, x, plot.top, x, plot.bottom, grid);
        line(w, x, plot.bottom, x, plot.bottom + mark, AXIS);
        if let Some(label) = &tick.label {
            if nth.is_multiple_of(stride) {
                w.tag("text")
                    .attr("x", x)
                    .attr("y", plot.bottom + 6.0 + FONT)
                    .attr("text-anchor", "middle")
                    .attr("fill", MUTED)
                    .text(label);
            }
            nth += 1;
        }
    }
    line(w, plot.left, plot.bottom, plot.right, plot.bottom, AXIS);
    if !title.is_empty() {
        fitted_text(w, title, plot.width(), LABEL_FONT, |t| {
            t.attr("x", (plot.left + plot.right) / 2.0)
                .attr("y", plot.bottom + 6.0 + FONT + 8.0 + LABEL_FONT)
                .attr("text-anchor", "middle")
                .attr("font-size", LABEL_FONT)
                .attr("fill", TEXT)
        });
    }
}

/// A one-pixel line.
pub(crate) fn line(w: &mut SvgWriter, x1: f64, y1: f64, x2: f64, y2: f64, stroke: &str) {
    w.tag("line")
        .attr("x1", x1)
        .attr("y1", y1)
        .attr("x2", x2)
        .attr("y2", y2)
        .attr("stroke", stroke)
        .attr("stroke-width", 1.0)
        .attr("shape-rendering", "crispEdges")
        .empty();
}
