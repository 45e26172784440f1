//! Bar charts: stacked (one bar per category, split into named segments) and grouped (one bar
//! per series side by side within each category). Bars start at zero so lengths compare
//! honestly; non-finite values are not drawn and a footnote counts them.

use super::axis::{format_value, Axis};
use super::category_axis::CategoryAxis;
use super::frame::{self, Plot, AXIS, HEIGHT, NOTE_HEIGHT, TOP, WIDTH};
use super::legend::{self, LegendEntry, Swatch};
use super::palette::color;
use super::svg::SvgWriter;

/// One stacked bar: its category label and its segments (name, value), stacked in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bar {
    pub label: String,
    pub segments: Vec<(String, f64)>,
}

/// A stacked bar chart. Each distinct segment name has one colour in every bar; positive values
/// stack up from zero, negative ones down. The legend lists the segment names in reverse order
/// of first appearance, so it reads like a stack (top first) when the bars share an order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StackedBarChart {
    pub title: String,
    pub y_label: String,
    pub bars: Vec<Bar>,
}

/// A grouped bar chart: for each x category, one bar per series, side by side. A series keeps
/// its colour and its position within every group (a group lacking it leaves its place empty).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GroupedBarChart {
    pub title: String,
    pub y_label: String,
    /// Top of the y axis (e.g. `Some(1.0)` for efficiencies); the axis still extends to any
    /// larger value rather than cut a bar off. `None`: from the data.
    pub y_max: Option<f64>,
    /// Label the y axis (and tooltips) as percentages: 0.5 → "50%".
    pub percent: bool,
    /// x category, then its (series name, value) bars side by side.
    pub groups: Vec<(String, Vec<(String, f64)>)>,
}

/// Distinct names in order of first appearance.
fn distinct<'a>(names: impl Iterator<Item = &'a str>) -> Vec<&'a str> {
    let mut out: Vec<&str> = Vec::new();
    for name in names {
        if !out.contains(&name) {
            out.push(name);
        }
    }
    out
}

/// A value axis from zero to the data's extent (zero is always included: bars start there).
fn value_axis(lo: f64, hi: f64) -> Axis {
    let (lo, hi) = (lo.min(0.0), hi.max(0.0));
    let hi = if lo == hi { 1.0 } else { hi };
    Axis::linear(lo, hi, 5)
}

/// The plot rectangle and category labels for `labels.len()` evenly spaced slots.
fn layout(
    axis: &Axis,
    y_title: &str,
    entries: &[LegendEntry],
    labels: &[&str],
    note: bool,
) -> (Plot, CategoryAxis) {
    let right = WIDTH - legend::width(entries).max(16.0);
    let slot = |left: f64| (right - left) / labels.len().max(1) as f64;
    let mut left = frame::y_axis_width(axis, y_title);
    let mut categories = CategoryAxis::layout(labels, slot(left));
    // A long first label rotated -45° reaches left past the y axis: keep it on the canvas.
    let needed = categories.overhang - slot(left) / 2.0 + 4.0;
    if needed > left {
        left = needed;
        categories = CategoryAxis::layout(labels, slot(left));
    }
    let bottom = HEIGHT - categories.height - 6.0 - if note { NOTE_HEIGHT } else { 0.0 };
    (Plot { left, top: TOP, right, bottom }, categories)
}

/// Maps values to y pixels.
struct ValueScale<'a> {
    plot: &'a Plot,
    axis: &'a Axis,
}

impl ValueScale<'_> {
    fn y(&self, v: f64) -> f64 {
        self.plot.y(self.axis.fraction(v))
    }
}

/// A bar between the values `a` and `b` with its tooltip.
fn bar(w: &mut SvgWriter, scale: &ValueScale, x: f64, width: f64, (a, b): (f64, f64), fill: &str, tip: &str) {
    let (ya, yb) = (scale.y(a), scale.y(b));
    w.tag("rect")
        .attr("class", "bar")
        .attr("x", x)
        .attr("y", ya.min(yb))
        .attr("width", width)
        .attr("height", (ya - yb).abs())
        .attr("fill", fill)
        .open();
    w.tag("title").text(tip);
    w.close();
}

/// The baseline the bars grow from (value axes always include zero).
fn zero_line(w: &mut SvgWriter, scale: &ValueScale) {
    let y = scale.y(0.0);
    frame::line(w, scale.plot.left, y, scale.plot.right, y, AXIS);
}

fn omitted_note(w: &mut SvgWriter, omitted: usize) {
    if omitted > 0 {
        let noun = if omitted == 1 { "value" } else { "values" };
        frame::note(w, &format!("{omitted} {noun} not drawn (not finite)"));
    }
}

impl StackedBarChart {
    /// The chart as a standalone SVG document (see the [module docs](super)).
    pub fn to_svg(&self) -> String {
        let finite =
            |b: &'_ Bar| b.segments.iter().filter(|(_, v)| v.is_finite()).cloned().collect::<Vec<_>>();
        let names = distinct(
            self.bars
                .iter()
                .flat_map(|b| b.segments.iter().filter(|(_, v)| v.is_finite()).map(|(n, _)| n.as_str())),
        );
        if names.is_empty() {
            return frame::no_data(&self.title);
        }
        let omitted = self.bars.iter().flat_map(|b| &b.segments).filter(|(_, v)| !v.is_finite()).count();
        // Each bar spans from the sum of its negative segments to the sum of its positive ones.
        let extents: Vec<(f64, f64)> = self
            .bars
            .iter()
            .map(|b| {
                let segs = finite(b);
                (segs.iter().map(|s| s.1.min(0.0)).sum(), segs.iter().map(|s| s.1.max(0.0)).sum())
            })
            .collect();
        let axis = value_axis(
            extents.iter().map(|e| e.0).fold(0.0, f64::min),
            extents.iter().map(|e| e.1).fold(0.0, f64::max),
        );
        let colour_of = |name: &str| color(names.iter().position(|n| *n == name).unwrap_or(0));
        let entries: Vec<LegendEntry> = names
            .iter()
            .rev()
            .map(|n| LegendEntry { name: n.to_string(), color: colour_of(n), swatch: Swatch::Box })
            .collect();
        let labels: Vec<&str> = self.bars.iter().map(|b| b.label.as_str()).collect();
        let (plot, categories) = layout(&axis, &self.y_label, &entries, &labels, omitted > 0);

        let mut w = frame::begin(&self.title);
        frame::draw_y_axis(&mut w, &plot, &axis, &self.y_label);
        let scale = ValueScale { plot: &plot, axis: &axis };
        let slot = plot.width() / self.bars.len() as f64;
        let width = (slot * 0.72).max(slot.min(1.0));
        for (i, b) in self.bars.iter().enumerate() {
            let x = plot.left + slot * i as f64 + (slot - width) / 2.0;
            let segs = finite(b);
            let total: f64 = segs.iter().map(|s| s.1).sum();
            let (mut up, mut down) = (0.0, 0.0);
            for (name, v) in segs.iter().filter(|s| s.1 != 0.0) {
                let end = if *v > 0.0 { &mut up } else { &mut down };
                let span = (*end, *end + v);
                *end += v;
                let tip =
                    format!("{}: {name} = {} (total {})", b.label, format_value(*v), format_value(total));
                bar(&mut w, &scale, x, width, span, colour_of(name), &tip);
            }
        }
        zero_line(&mut w, &scale);
        categories.draw(&mut w, &plot, &labels, |i| plot.left + slot * (i as f64 + 0.5));
        legend::draw(&mut w, plot.right, plot.top, HEIGHT - 8.0, &entries);
        omitted_note(&mut w, omitted);
        w.finish()
    }
}

impl GroupedBarChart {
    /// The chart as a standalone SVG document (see the [module docs](super)).
    pub fn to_svg(&self) -> String {
        let values = || self.groups.iter().flat_map(|(_, bars)| bars).filter(|(_, v)| v.is_finite());
        let series = distinct(values().map(|(n, _)| n.as_str()));
        if series.is_empty() {
            return frame::no_data(&self.title);
        }
        let omitted = self.groups.iter().flat_map(|(_, bars)| bars).filter(|(_, v)| !v.is_finite()).count();
        let lo = values().map(|b| b.1).fold(0.0, f64::min);
        let mut hi = values().map(|b| b.1).fold(0.0, f64::max);
        if let Some(top) = self.y_max.filter(|t| t.is_finite() && *t > lo) {
            hi = hi.max(top);
        }
        let axis = value_axis(lo, hi);
        let axis = if self.percent { axis.percent() } else { axis };
        let show =
            |v: f64| if self.percent { format!("{}%", format_value(v * 100.0)) } else { format_value(v) };
        let entries: Vec<LegendEntry> = if series.len() == 1 && series[0].is_empty() {
            Vec::new()
        } else {
            series
                .iter()
                .enumerate()
                .map(|(k, n)| LegendEntry { name: n.to_string(), color: color(k), swatch: Swatch::Box })
                .collect()
        };
        let labels: Vec<&str> = self.groups.iter().map(|(label, _)| label.as_str()).collect();
        let (plot, categories) = layout(&axis, &self.y_label, &entries, &labels, omitted > 0);

        let mut w = frame::begin(&self.title);
        frame::draw_y_axis(&mut w, &plot, &axis, &self.y_label);
        let scale = ValueScale { plot: &plot, axis: &axis };
        let slot = plot.width() / self.groups.len() as f64;
        // Bars fill 80% of the group's slot; a sliver between bars keeps neighbours apart.
        let band = slot * 0.8 / series.len() as f64;
        let width = if band > 3.0 { band * 0.88 } else { band };
        for (g, (label, bars)) in self.groups.iter().enumerate() {
            for (name, v) in bars.iter().filter(|(_, v)| v.is_finite()) {
                let k = series.iter().position(|n| n == name).unwrap_or(0);
                let x = plot.left + slot * (g as f64 + 0.1) + band * k as f64 + (band - width) / 2.0;
                let tip = if name.is_empty() {
                    format!("{label}: {}", show(*v))
                } else {
                    format!("{name} — {label}: {}", show(*v))
                };
                bar(&mut w, &scale, x, width, (0.0, *v), color(k), &tip);
            }
        }
        zero_line(&mut w, &scale);
        categories.draw(&mut w, &plot, &labels, |i| plot.left + slot * (i as f64 + 0.5));
        legend::draw(&mut w, plot.right, plot.top, HEIGHT - 8.0, &entries);
        omitted_note(&mut w, omitted);
        w.finish()
    }
}
