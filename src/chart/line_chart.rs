//! Line charts: series of (x, y) points on linear or log10 axes.

use super::axis::{format_value, Axis};
use super::frame::{self, Plot, HEIGHT, NOTE_HEIGHT, TOP, WIDTH, X_AXIS_HEIGHT};
use super::legend::{self, LegendEntry, Swatch};
use super::marker::Marker;
use super::palette::color;
use super::svg::{num, SvgWriter};

/// A named sequence of points, drawn as a polyline with a marker at each point, in the given
/// order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

/// A line chart. Points that cannot be drawn (non-finite, or ≤ 0 on a log axis) are left out,
/// the line is broken where they were, and a footnote says how many were left out.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LineChart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x_log: bool,
    pub y_log: bool,
    pub series: Vec<Series>,
}

impl LineChart {
    fn drawable(&self, (x, y): (f64, f64)) -> bool {
        x.is_finite() && y.is_finite() && (!self.x_log || x > 0.0) && (!self.y_log || y > 0.0)
    }

    /// The chart as a standalone SVG document (see the [module docs](super)).
    pub fn to_svg(&self) -> String {
        let points =
            || self.series.iter().flat_map(|s| s.points.iter().copied()).filter(|&p| self.drawable(p));
        let Some((x0, x1, y0, y1)) = points().fold(None, |b: Option<(f64, f64, f64, f64)>, (x, y)| {
            Some(match b {
                None => (x, x, y, y),
                Some((x0, x1, y0, y1)) => (x0.min(x), x1.max(x), y0.min(y), y1.max(y)),
            })
        }) else {
            return frame::no_data(&self.title);
        };
        let axis = |lo, hi, log, target| if log { Axis::log10(lo, hi) } else { Axis::linear(lo, hi, target) };
        let (x_axis, y_axis) = (axis(x0, x1, self.x_log, 6), axis(y0, y1, self.y_log, 5));
        let x_title = frame::axis_title(&self.x_label, self.x_log);
        let y_title = frame::axis_title(&self.y_label, self.y_log);

        let total = self.series.iter().map(|s| s.points.len()).sum::<usize>();
        let omitted = total - points().count();
        let entries: Vec<LegendEntry> = self
            .series
            .iter()
            .enumerate()
            .map(|(i, s)| LegendEntry {
                name: s.name.clone(),
                color: color(i),
                swatch: Swatch::Line(Marker::for_series(i)),
            })
            .collect();
        // A lone unnamed series needs no legend.
        let entries = if entries.len() == 1 && entries[0].name.is_empty() { Vec::new() } else { entries };

        // Room on the right for the legend, or for half of the last x tick label.
        let last_label = x_axis.ticks.iter().rev().find_map(|t| t.label.as_deref()).unwrap_or("");
        let right =
            legend::width(&entries).max(frame::text_width(last_label, frame::FONT) / 2.0 + 8.0).max(16.0);
        let note_height = if omitted > 0 { NOTE_HEIGHT } else { 0.0 };
        let plot = Plot {
            left: frame::y_axis_width(&y_axis, &y_title),
            top: TOP,
            right: WIDTH - right,
            bottom: HEIGHT - X_AXIS_HEIGHT - note_height,
        };

        let mut w = frame::begin(&self.title);
        frame::draw_y_axis(&mut w, &plot, &y_axis, &y_title);
        frame::draw_x_axis(&mut w, &plot, &x_axis, &x_title);
        for (i, series) in self.series.iter().enumerate() {
            self.draw_series(&mut w, &plot, &x_axis, &y_axis, series, i);
        }
        legend::draw(&mut w, plot.right, plot.top, HEIGHT - 8.0, &entries);
        if omitted > 0 {
            let what =
                if self.x_log || self.y_log { "not finite, or ≤ 0 on a log axis" } else { "not finite" };
            let noun = if omitted == 1 { "point" } else { "points" };
            frame::note(&mut w, &format!("{omitted} {noun} not drawn ({what})"));
        }
        w.finish()
    }

    fn draw_series(
        &self,
        w: &mut SvgWriter,
        plot: &Plot,
        x_axis: &Axis,
        y_axis: &Axis,
        series: &Series,
        i: usize,
    ) {
        let (stroke, marker) = (color(i), Marker::for_series(i));
        let to_px = |(x, y): (f64, f64)| (plot.x(x_axis.fraction(x)), plot.y(y_axis.fraction(y)));
        // Break the line where a point was left out, so a gap in the data shows as a gap.
        let mut runs: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
        for &p in &series.points {
            if self.drawable(p) {
                runs.last_mut().expect("never empty").push(to_px(p));
            } else if !runs.last().expect("never empty").is_empty() {
                runs.push(Vec::new());
            }
        }
        w.tag("g").attr("class", "series").open();
        for run in runs.iter().filter(|r| r.len() >= 2) {
            let pts: Vec<String> = run.iter().map(|&(x, y)| format!("{},{}", num(x), num(y))).collect();
            w.tag("polyline")
                .attr("points", pts.join(" "))
                .attr("fill", "none")
                .attr("stroke", stroke)
                .attr("stroke-width", 1.8)
                .attr("stroke-linejoin", "round")
                .empty();
        }
        // Smaller markers when they would crowd each other.
        let r = if series.points.len() > 40 { 2.5 } else { 3.5 };
        let prefix = if series.name.is_empty() { String::new() } else { format!("{}: ", series.name) };
        for &(x, y) in series.points.iter().filter(|&&p| self.drawable(p)) {
            let (px, py) = to_px((x, y));
            marker
                .start(w, px, py, r, stroke)
                .attr("class", "point")
                .attr("stroke", "#ffffff")
                .attr("stroke-width", 0.8)
                .open();
            w.tag("title").text(&format!("{prefix}x = {}, y = {}", format_value(x), format_value(y)));
            w.close();
        }
        w.close();
    }
}
