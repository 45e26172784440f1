//! Legends, drawn as a column right of the plot so they never cover data.

use super::frame::{fitted_text, text_width, FONT, MUTED, TEXT};
use super::marker::Marker;
use super::svg::SvgWriter;

/// How an entry shows its colour: a line with the series' marker, or a filled box (bars).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Swatch {
    Line(Marker),
    Box,
}

#[derive(Clone, Debug)]
pub(crate) struct LegendEntry {
    pub name: String,
    pub color: &'static str,
    pub swatch: Swatch,
}

const ROW: f64 = 18.0;
const SWATCH_WIDTH: f64 = 24.0;
/// Longer names are cut (the full name stays as a tooltip) so the plot keeps its width.
const MAX_NAME_PX: f64 = 150.0;
/// Space between the plot's right edge and the legend.
const GAP: f64 = 16.0;

fn shown_name(entry: &LegendEntry) -> &str {
    if entry.name.is_empty() {
        "(unnamed)"
    } else {
        &entry.name
    }
}

/// Horizontal space the legend takes right of the plot (0 without entries).
pub(crate) fn width(entries: &[LegendEntry]) -> f64 {
    if entries.is_empty() {
        return 0.0;
    }
    let widest = entries.iter().map(|e| text_width(shown_name(e), FONT)).fold(0.0, f64::max);
    GAP + SWATCH_WIDTH + 6.0 + widest.min(MAX_NAME_PX) + 8.0
}

/// Draws the legend starting at `plot_right`, between `top` and `bottom`; entries that do not
/// fit are summarised as "+N more".
pub(crate) fn draw(w: &mut SvgWriter, plot_right: f64, top: f64, bottom: f64, entries: &[LegendEntry]) {
    let x = plot_right + GAP;
    let rows = ((bottom - top) / ROW).floor().max(1.0) as usize;
    let shown = if entries.len() <= rows { entries.len() } else { rows - 1 };
    let row_y = |i: usize| top + ROW * (i as f64 + 0.5);
    for (i, entry) in entries.iter().take(shown).enumerate() {
        let cy = row_y(i);
        match entry.swatch {
            Swatch::Line(marker) => {
                w.tag("line")
                    .attr("x1", x)
                    .attr("y1", cy)
                    .attr("x2", x + SWATCH_WIDTH)
                    .attr("y2", cy)
                    .attr("stroke", entry.color)
                    .attr("stroke-width", 2.0)
                    .empty();
                marker.start(w, x + SWATCH_WIDTH / 2.0, cy, 3.5, entry.color).empty();
            }
            Swatch::Box => {
                w.tag("rect")
                    .attr("x", x + 6.0)
                    .attr("y", cy - 6.0)
                    .attr("width", 12.0)
                    .attr("height", 12.0)
                    .attr("fill", entry.color)
                    .empty();
            }
        }
        fitted_text(w, shown_name(entry), MAX_NAME_PX, FONT, |t| {
            t.attr("x", x + SWATCH_WIDTH + 6.0).attr("y", cy + FONT * 0.35).attr("fill", TEXT)
        });
    }
    if shown < entries.len() {
        w.tag("text")
            .attr("x", x + SWATCH_WIDTH + 6.0)
            .attr("y", row_y(shown) + FONT * 0.35)
            .attr("fill", MUTED)
            .text(&format!("+{} more", entries.len() - shown));
    }
}
