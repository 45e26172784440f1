//! Bar charts: stacked (one bar per category, split into named segments) and grouped (one bar
//! per series side by side within each category). Bars start at zero so lengths compare
//! honestly; non-finite values are not drawn and a footnote counts them.

use super::*;

/// The most room category labels take under the plot: rotated labels are cut to 150 px.
const LABELS_MAX: u32 = 150 + 14;

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
    /// Label the y axis as percentages: 0.5 → "50%".
    pub percent: bool,
    /// x category, then its (series name, value) bars side by side.
    pub groups: Vec<(String, Vec<(String, f64)>)>,
}

/// Distinct names of the finite values, in order of first appearance.
fn distinct<'a>(values: impl Iterator<Item = &'a (String, f64)>) -> Vec<&'a str> {
    let mut out: Vec<&str> = Vec::new();
    for (name, v) in values {
        if v.is_finite() && !out.contains(&name.as_str()) {
            out.push(name);
        }
    }
    out
}

impl StackedBarChart {
    /// The chart as a standalone SVG document (see the [module docs](super)).
    pub fn to_svg(&self) -> String {
        let names = distinct(self.bars.iter().flat_map(|b| &b.segments));
        let mut rects = Vec::new();
        for (i, bar) in self.bars.iter().enumerate() {
            let (mut up, mut down) = (0.0, 0.0);
            for (name, v) in bar.segments.iter().filter(|(_, v)| v.is_finite() && *v != 0.0) {
                let end = if *v > 0.0 { &mut up } else { &mut down };
                let k = names.iter().position(|n| n == name).unwrap_or(0);
                rects.push(Rect { colour: k, x: (i as f64 + 0.14, i as f64 + 0.86), y: (*end, *end + v) });
                *end += v;
            }
        }
        Bars {
            title: &self.title,
            y_label: &self.y_label,
            categories: self.bars.iter().map(|b| b.label.as_str()).collect(),
            legend: names.iter().enumerate().rev().map(|(k, n)| (*n, k)).collect(),
            rects,
            y_max: None,
            percent: false,
            omitted: self.bars.iter().flat_map(|b| &b.segments).filter(|(_, v)| !v.is_finite()).count(),
        }
        .to_svg()
    }
}

impl GroupedBarChart {
    /// The chart as a standalone SVG document (see the [module docs](super)), each series in
    /// the palette colour of its position.
    pub fn to_svg(&self) -> String {
        self.to_svg_with(&|_| None)
    }

    /// [`GroupedBarChart::to_svg`] with each series in the palette colour `colour` gives its
    /// name (a report's one colour per method), or of its position where it gives none.
    pub fn to_svg_with(&self, colour: ColourOf) -> String {
        let series = distinct(self.groups.iter().flat_map(|(_, bars)| bars));
        let colours: Vec<usize> = series.iter().enumerate().map(|(k, n)| colour(n).unwrap_or(k)).collect();
        // Bars fill 80% of the group's slot; a sliver between bars keeps neighbours apart.
        let band = 0.8 / series.len().max(1) as f64;
        let mut rects = Vec::new();
        for (g, (_, bars)) in self.groups.iter().enumerate() {
            for (name, v) in bars.iter().filter(|(_, v)| v.is_finite()) {
                let k = series.iter().position(|n| n == name).unwrap_or(0);
                let x0 = g as f64 + 0.1 + band * (k as f64 + 0.06);
                rects.push(Rect { colour: colours[k], x: (x0, x0 + band * 0.88), y: (0.0, *v) });
            }
        }
        // A lone unnamed series needs no legend.
        let legend = if series == [""] { Vec::new() } else { series.iter().copied().zip(colours).collect() };
        Bars {
            title: &self.title,
            y_label: &self.y_label,
            categories: self.groups.iter().map(|(label, _)| label.as_str()).collect(),
            legend,
            rects,
            y_max: self.y_max,
            percent: self.percent,
            omitted: self.groups.iter().flat_map(|(_, bars)| bars).filter(|(_, v)| !v.is_finite()).count(),
        }
        .to_svg()
    }
}

/// The category labels cut to `max` pixels, each still telling its category apart: where two
/// labels would be cut to the same text ("megakernel-regenerat…" for its 4 and 16 spp runs),
/// they keep their ends instead ("megakern…ate 16spp").
fn distinct_labels(root: &Area, categories: &[&str], max: f64) -> Vec<String> {
    let cut_end: Vec<String> = categories.iter().map(|c| cut(root, c, max)).collect();
    let clashes =
        |i: usize| (0..cut_end.len()).any(|j| cut_end[j] == cut_end[i] && categories[j] != categories[i]);
    (0..cut_end.len())
        .map(|i| if clashes(i) { cut_middle(root, categories[i], max) } else { cut_end[i].clone() })
        .collect()
}

/// `s` cut to at most `max` pixels by dropping characters from its middle, so that its end,
/// where names differ, stays ("megakern…ate 16spp").
fn cut_middle(root: &Area, s: &str, max: f64) -> String {
    let chars: Vec<char> = clean(s).chars().collect();
    if text_width(root, &chars.iter().collect::<String>()) <= max {
        return chars.into_iter().collect();
    }
    let mut keep = chars.len();
    loop {
        keep -= 1;
        let (head, tail) = (keep / 2, keep - keep / 2);
        let text: String =
            chars[..head].iter().chain(['…'].iter()).chain(&chars[chars.len() - tail..]).collect();
        if keep == 0 || text_width(root, &text) <= max {
            return text;
        }
    }
}

/// One drawn bar: its palette index and its extent in (category slot, value) units.
struct Rect {
    colour: usize,
    x: (f64, f64),
    y: (f64, f64),
}

/// A bar chart as drawn: category `i` spans x from `i` to `i + 1`.
struct Bars<'a> {
    title: &'a str,
    y_label: &'a str,
    categories: Vec<&'a str>,
    /// Legend entries in order: name and palette index.
    legend: Vec<(&'a str, usize)>,
    rects: Vec<Rect>,
    y_max: Option<f64>,
    percent: bool,
    omitted: usize,
}

impl Bars<'_> {
    fn to_svg(&self) -> String {
        if self.rects.is_empty() && self.legend.is_empty() {
            return no_data(self.title);
        }
        let legend = Legend::new(&self.legend.iter().map(|e| e.0).collect::<Vec<_>>());
        render(legend.height_for(LABELS_MAX), |root| self.draw(root, legend))
    }

    /// The value axis: from zero (or below, for negative values) to the data or `y_max`,
    /// whichever is larger; 5% room beyond the data.
    fn value_range(&self) -> (f64, f64) {
        let values = self.rects.iter().flat_map(|r| [r.y.0, r.y.1]);
        let (lo, hi) = values.fold((0.0, 0.0), |(lo, hi): (f64, f64), v| (lo.min(v), hi.max(v)));
        let room = 0.05 * (hi - lo);
        let hi = match self.y_max {
            Some(top) if top.is_finite() && top >= hi && top > lo => top,
            _ => hi + room,
        };
        let lo = if lo < 0.0 { lo - room } else { 0.0 };
        (lo, if hi > lo { hi } else { lo + 1.0 })
    }

    fn draw(&self, root: &Area, legend: Legend) -> Drawn {
        let n = self.categories.len().max(1);
        let legend_w = legend.width;
        // Category labels: horizontal where they fit their slot, else rotated, cut if long and,
        // in narrow slots, smaller (down to 7 px) and only then thinned.
        let slot = (WIDTH - MARGIN - Y_AXIS - legend_w) as f64 / n as f64;
        let rotate = self.categories.iter().any(|c| text_width(root, &clean(c)) > slot - 4.0);
        let labels = distinct_labels(root, &self.categories, if rotate { 150.0 } else { slot });
        let label_height =
            if rotate { labels.iter().map(|l| text_width(root, l)).fold(0.0, f64::max) as u32 } else { LINE };
        // Label every `every`-th slot, in a font (in pixels; plotters' sizes are 1.24 times
        // larger) at least 7 px and a pixel less than the labels' spacing.
        let every = if rotate { (8.0 / slot).ceil() as usize } else { 1 };
        let size = if rotate { (slot * every as f64 - 1.0).min(FONT / 1.24) } else { FONT / 1.24 };

        let (lo, hi) = self.value_range();
        title(root, self.title)?;
        let mut chart = layout(root, legend_w, self.omitted > 0)
            .x_label_area_size(label_height + 14)
            .build_cartesian_2d(0.0..n as f64, lo..hi)?;
        let percent = |v: &f64| format!("{}%", tick(v * 100.0));
        let plain = |v: &f64| tick(*v);
        let format: &dyn Fn(&f64) -> String = if self.percent { &percent } else { &plain };
        let desc = desc_font(root, chart.plotting_area(), "", &clean(self.y_label));
        chart
            .configure_mesh()
            .axis_desc_style(desc)
            .disable_x_mesh()
            .light_line_style(TRANSPARENT)
            .x_labels(0)
            .y_labels(8)
            .y_desc(clean(self.y_label))
            .y_label_formatter(format)
            .label_style(font())
            .draw()?;

        let bars = self
            .rects
            .iter()
            .map(|r| Rectangle::new([(r.x.0, r.y.0), (r.x.1, r.y.1)], color(r.colour).filled()));
        chart.draw_series(bars)?;
        if lo < 0.0 {
            chart.draw_series(LineSeries::new([(0.0, 0.0), (n as f64, 0.0)], BLACK))?;
        }
        let font = ("sans-serif", size * 1.24).into_text_style(root);
        let style = if rotate {
            font.transform(FontTransform::Rotate270).pos(Pos::new(HPos::Right, VPos::Center))
        } else {
            font.pos(Pos::new(HPos::Center, VPos::Top))
        };
        for (i, label) in labels.iter().enumerate().step_by(every) {
            let (x, y) = chart.backend_coord(&(i as f64 + 0.5, lo));
            root.draw_text(label, &style, (x, y + 8))?;
        }
        let entries: Vec<_> =
            legend.names.into_iter().zip(&self.legend).map(|(n, &(_, k))| (n, Swatch::Box(k))).collect();
        draw_legend(root, chart.plotting_area(), &entries)?;
        footnote(root, self.omitted, "value", "not finite")
    }
}
