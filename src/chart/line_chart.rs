//! Line charts: series of (x, y) points on linear or log10 axes.

use std::ops::Range;

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};

use super::*;

/// Height of the x axis's labels and title under the plot.
const X_AXIS: u32 = 44;

/// A named sequence of points, drawn as a line with a marker at each point, in the given order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    /// Empty, or one (low, high) per point: drawn as a vertical bar through it (the interval of
    /// a ratio of medians, say).
    pub intervals: Vec<(f64, f64)>,
    /// Empty, or one text per point, written beside its marker (the spp of a point on a
    /// speed-vs-error line, say).
    pub labels: Vec<String>,
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
    /// On a log x axis, draw x = 0 instead of leaving it out: at the decade below the smallest
    /// positive x's decade, whose tick reads "0", and the x axis title says so. (No effect on a
    /// linear axis, or when no x is positive.)
    pub x_zero: bool,
    pub series: Vec<Series>,
}

impl LineChart {
    fn drawable(&self, (x, y): (f64, f64)) -> bool {
        x.is_finite() && y.is_finite() && (!self.x_log || x > 0.0) && (!self.y_log || y > 0.0)
    }

    /// Where x = 0 is drawn (`x_zero`): a decade below the smallest positive x's decade, so that
    /// it sits on a tick of its own with no other tick between it and the data.
    fn zero_at(&self) -> Option<f64> {
        if !(self.x_log && self.x_zero) {
            return None;
        }
        let points = self.series.iter().flat_map(|s| &s.points);
        let has_zero = points.clone().any(|&(x, y)| x == 0.0 && self.drawable((1.0, y)));
        let min = points.map(|p| p.0).filter(|&x| x > 0.0 && x.is_finite()).reduce(f64::min)?;
        // The nearest double to the power of ten, so that the axis's decades start at it.
        let decade = |k: f64| format!("1e{k}").parse::<f64>().ok();
        has_zero.then(|| decade(min.log10().floor() - 1.0)).flatten().filter(|z| *z > 0.0)
    }

    /// The chart as a standalone SVG document (see the [module docs](super)), each series in
    /// the palette colour of its position.
    pub fn to_svg(&self) -> String {
        self.to_svg_with(&|_| None)
    }

    /// [`LineChart::to_svg`] with each series in the palette colour `colour` gives its name
    /// (a report's one colour per method), or of its position where it gives none.
    pub fn to_svg_with(&self, colour: ColourOf) -> String {
        let zero = self.zero_at();
        if let Some(z) = zero {
            let mut moved = self.clone();
            for p in moved.series.iter_mut().flat_map(|s| &mut s.points) {
                if p.0 == 0.0 {
                    p.0 = z;
                }
            }
            return moved.svg(zero, colour);
        }
        self.svg(None, colour)
    }

    fn svg(&self, zero: Option<f64>, colour: ColourOf) -> String {
        let points: Vec<(f64, f64)> =
            self.series.iter().flat_map(|s| &s.points).copied().filter(|&p| self.drawable(p)).collect();
        if points.is_empty() {
            return no_data(&self.title);
        }
        let omitted = self.series.iter().map(|s| s.points.len()).sum::<usize>() - points.len();
        let x = range(points.iter().map(|p| p.0), self.x_log);
        // The bars' ends too, so none is cut off by the frame.
        let bar_ends = self.series.iter().flat_map(|s| s.points.iter().zip(&s.intervals)).flat_map(
            |(&(x, _), &(lo, hi))| [(x, lo), (x, hi)].into_iter().filter(|&p| self.drawable(p)).map(|p| p.1),
        );
        let y = range(points.iter().map(|p| p.1).chain(bar_ends), self.y_log);
        // A lone unnamed series needs no legend.
        let has_legend = !(self.series.len() == 1 && self.series[0].name.is_empty());
        let named: Vec<&str> =
            if has_legend { self.series.iter().map(|s| s.name.as_str()).collect() } else { Vec::new() };
        let legend = Legend::new(&named);
        let colours: Vec<usize> =
            self.series.iter().enumerate().map(|(i, s)| colour(&s.name).unwrap_or(i)).collect();
        let how = Drawing { omitted, zero, legend, colours };
        render(how.legend.height_for(X_AXIS), |root| match (self.x_log, self.y_log) {
            (false, false) => self.draw(root, x, y, how),
            (true, false) => self.draw(root, x.log_scale(), y, how),
            (false, true) => self.draw(root, x, y.log_scale(), how),
            (true, true) => self.draw(root, x.log_scale(), y.log_scale(), how),
        })
    }

    fn draw<X, Y>(&self, root: &Area, x: X, y: Y, how: Drawing) -> Drawn
    where
        X: AsRangedCoord<Value = f64>,
        Y: AsRangedCoord<Value = f64>,
        X::CoordDescType: ValueFormatter<f64>,
        Y::CoordDescType: ValueFormatter<f64>,
    {
        let Drawing { omitted, zero, legend, colours } = how;
        title(root, &self.title)?;
        let mut chart =
            layout(root, legend.width, omitted > 0).x_label_area_size(X_AXIS).build_cartesian_2d(x, y)?;
        let x_title = match zero {
            Some(_) => clean(&format!("{} (log scale; 0 drawn at the tick marked 0)", self.x_label)),
            None => axis_title(&self.x_label, self.x_log),
        };
        let x_tick = |v: &f64| match zero {
            Some(z) if (v / z - 1.0).abs() < 1e-6 => "0".to_string(),
            // Nothing lies left of 0.
            Some(z) if *v < z => String::new(),
            _ => tick(*v),
        };
        let y_title = axis_title(&self.y_label, self.y_log);
        let desc = desc_font(root, chart.plotting_area(), &x_title, &y_title);
        chart
            .configure_mesh()
            .x_desc(x_title)
            .y_desc(y_title)
            .axis_desc_style(desc)
            .x_labels(8)
            .y_labels(8)
            .max_light_lines(5)
            .x_label_formatter(&x_tick)
            .y_label_formatter(&|v| tick(*v))
            .label_style(font())
            .draw()?;

        let text = font().pos(Pos::new(HPos::Left, VPos::Bottom));
        let mut written: Vec<(String, i32, i32)> = Vec::new();
        for (s, &i) in self.series.iter().zip(&colours) {
            let line = color(i).stroke_width(2);
            // Break the line where a point was left out, so a gap in the data shows as a gap.
            for run in s.points.split(|&p| !self.drawable(p)).filter(|run| run.len() >= 2) {
                chart.draw_series(LineSeries::new(run.iter().copied(), line))?;
            }
            let points = s.points.iter().filter(|&&p| self.drawable(p));
            chart.draw_series(points.map(|&p| EmptyElement::at(p) + marker(i, (0, 0))))?;
            // A label once where the same text is already written close by (the methods' points
            // at one spp often sit together).
            for (&p, l) in s.points.iter().zip(&s.labels).filter(|&(&p, l)| self.drawable(p) && !l.is_empty())
            {
                let (x, y) = chart.backend_coord(&p);
                if !written.iter().any(|(t, wx, wy)| t == l && (wx - x).abs() < 48 && (wy - y).abs() < 14) {
                    root.draw_text(&clean(l), &text, (x + 5, y - 4))?;
                    written.push((l.clone(), x, y));
                }
            }
            let bars =
                s.points.iter().zip(&s.intervals).filter(|&(&(x, _), &(lo, hi))| {
                    self.drawable((x, lo)) && self.drawable((x, hi)) && lo < hi
                });
            chart.draw_series(
                bars.map(|(&(x, _), &(lo, hi))| PathElement::new(vec![(x, lo), (x, hi)], color(i))),
            )?;
        }
        let entries: Vec<_> =
            legend.names.into_iter().zip(colours).map(|(n, i)| (n, Swatch::Line(i))).collect();
        draw_legend(root, chart.plotting_area(), &entries)?;
        let why = if self.x_log || self.y_log { "not finite, or ≤ 0 on a log axis" } else { "not finite" };
        footnote(root, omitted, "point", why)
    }
}

/// How a line chart is drawn besides its data: points left out, where x = 0 sits, the legend,
/// and each series' palette index.
struct Drawing {
    omitted: usize,
    zero: Option<f64>,
    legend: Legend,
    colours: Vec<usize>,
}

/// The axis range for the drawable `values`: log axes span whole decades (so that each end has a
/// labelled tick); both get 5% room on each side (in log space for log axes) so no marker sits
/// on the frame; a zero-width range is padded (a decade, or 10% of the value).
fn range(values: impl Iterator<Item = f64>, log: bool) -> Range<f64> {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if log {
        let (mut e0, mut e1) = (lo.log10().floor(), hi.log10().ceil());
        if e0 == e1 {
            (e0, e1) = (e0 - 1.0, e1 + 1.0);
        }
        let pad = (e1 - e0) * 0.05;
        10f64.powf(e0 - pad)..10f64.powf(e1 + pad).min(f64::MAX)
    } else {
        let span = hi - lo;
        let pad = if span > lo.abs().max(hi.abs()) * 1e-12 {
            span * 0.05
        } else if lo == 0.0 {
            1.0
        } else {
            lo.abs() * 0.1
        };
        lo - pad..hi + pad
    }
}
