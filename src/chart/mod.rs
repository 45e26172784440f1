//! SVG charts for experiment reports, drawn with [`plotters`]: line charts (linear or log10
//! axes), stacked and grouped bar charts, a colour-blind-safe palette and the viridis colormap.
//!
//! Every chart renders to a standalone SVG document of fixed size (720×420, sans-serif text
//! left to the viewer's fonts) that also works inlined in HTML: plotters emits no ids, scripts or
//! external resources. What this module adds to plotters keeps the charts honest:
//!
//! - log axes say "(log scale)" in their title and span whole decades;
//! - a log x axis may draw x = 0 (`LineChart::x_zero`): at a tick of its own marked "0", a
//!   decade left of the data, and its title says so;
//! - values that cannot be drawn (non-finite, or ≤ 0 on a log axis) are left out, never moved,
//!   and a footnote counts them; a line breaks where a point was left out;
//! - a chart with nothing to draw shows its title and a centred "no data" note;
//! - a zero-width data range is padded instead of dividing by zero;
//! - the legend sits beside the plot, never over the data, and names every series in full:
//!   long names wrap, and a chart with more entries than its height holds grows taller.
//!
//! ```
//! use wavetrace::chart::{LineChart, Series};
//!
//! let chart = LineChart {
//!     title: "Error vs samples".into(),
//!     x_label: "samples per pixel".into(),
//!     y_label: "relMSE".into(),
//!     x_log: true,
//!     y_log: true,
//!     x_zero: false,
//!     series: vec![Series { name: "wavefront".into(), points: vec![(1.0, 0.3), (16.0, 0.02), (256.0, 0.001)], intervals: Vec::new(), labels: Vec::new() }],
//! };
//! let svg = chart.to_svg();
//! assert!(svg.starts_with("<svg ") && svg.contains("relMSE (log scale)"));
//! ```

mod bar_chart;
mod line_chart;
mod palette;

pub use bar_chart::{Bar, GroupedBarChart, StackedBarChart};
pub use line_chart::{LineChart, Series};
pub use palette::{color, hex, viridis, PALETTE};
pub use plotters::style::RGBColor;

use plotters::coord::Shift;
use plotters::data::float::pretty_print_float;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

const WIDTH: u32 = 720;
/// The height of a chart whose legend fits beside its plot; taller ones grow (`height_for`).
const HEIGHT: u32 = 420;
/// Space around the chart, above the plot for the title, and left of it for the y axis.
const MARGIN: u32 = 10;
const TITLE_HEIGHT: u32 = 36;
const Y_AXIS: u32 = 64;
/// Text sizes in plotters' units (the SVG's `font-size` is this / 1.24).
const FONT: f64 = 14.0;
const TITLE_FONT: f64 = 18.0;
/// Height of one legend line and of the footnote's band.
const LINE: u32 = 16;

/// A series' palette index by its name (a report gives each method one colour across its
/// charts), or None for the palette colour of the series' position.
pub type ColourOf<'a> = &'a dyn Fn(&str) -> Option<usize>;

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;
type Drawn = Result<(), Box<dyn std::error::Error>>;

fn font() -> TextStyle<'static> {
    ("sans-serif", FONT).into_text_style(&(WIDTH, HEIGHT))
}

/// Text as plotters will escape it: XML forbids most control characters even as references, so
/// a stray byte in a series name must not make the whole document unparsable.
fn clean(s: &str) -> String {
    let allowed = |c: char| !(c.is_control() || c == '\u{FFFE}' || c == '\u{FFFF}') || "\t\n\r".contains(c);
    s.chars().filter(|&c| allowed(c)).collect()
}

/// An axis title that says when the axis is logarithmic.
fn axis_title(label: &str, log: bool) -> String {
    clean(&if log { format!("{label} (log scale)") } else { label.to_string() })
}

/// A compact tick label without floating-point noise: "0.25" and "1500" from 0.001 to 9999, SI
/// suffixes up to 10^12 ("10k", "2.5M", "1G"), exponents beyond ("1e-4", "1e12").
fn tick(v: f64) -> String {
    match v.abs() {
        a if a == 0.0 || (1e-3..1e4).contains(&a) => pretty_print_float(v, false),
        a if (1e4..1e12).contains(&a) => {
            let (unit, suffix) = [(1e3, "k"), (1e6, "M"), (1e9, "G")][(a.log10() as usize / 3 - 1).min(2)];
            format!("{}{suffix}", pretty_print_float(v / unit, false))
        }
        _ => pretty_print_float(v, true),
    }
}

/// Draws a chart `height` pixels tall into a fresh SVG document. Should plotters fail (it has no
/// failure path when writing into a string, but its API is fallible), the chart says so rather
/// than look complete.
fn render(height: u32, draw: impl FnOnce(&Area) -> Drawn) -> String {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, height)).into_drawing_area();
        let drawn = root.fill(&WHITE).map_err(Into::into).and_then(|()| draw(&root));
        if let Err(e) = drawn {
            let _ = root.draw_text(&format!("chart not fully drawn: {e}"), &font().color(&RED), (8, 8));
        }
    } // Dropping the backend closes the document.
    svg
}

/// The title, centred on the canvas and cut to fit it.
fn title(root: &Area, title: &str) -> Drawn {
    let style = ("sans-serif", TITLE_FONT).into_text_style(root).pos(Pos::new(HPos::Center, VPos::Top));
    let title = cut(root, title, (WIDTH - 2 * MARGIN) as f64 * FONT / TITLE_FONT);
    root.draw_text(&title, &style, (WIDTH as i32 / 2, MARGIN as i32))?;
    Ok(())
}

/// The layout every chart shares below its title: `right` pixels beside the plot for the
/// legend, and a line below it for a footnote where there is one.
fn layout<'a, 'b>(root: &'a Area<'b>, right: u32, note: bool) -> ChartBuilder<'a, 'b, SVGBackend<'b>> {
    let mut builder = ChartBuilder::on(root);
    builder
        .margin(MARGIN)
        .margin_top(TITLE_HEIGHT)
        .margin_right(right)
        .margin_bottom(if note { MARGIN + LINE } else { MARGIN })
        .y_label_area_size(Y_AXIS);
    builder
}

/// A chart with nothing to draw: its title and a centred "no data" note.
fn no_data(text: &str) -> String {
    render(HEIGHT, |root| {
        title(root, text)?;
        let centre = font().pos(Pos::new(HPos::Center, VPos::Center));
        root.draw_text("no data", &centre, (WIDTH as i32 / 2, HEIGHT as i32 / 2))?;
        Ok(())
    })
}

/// Estimated width of `text` in pixels (plotters' estimate for fonts it cannot measure).
fn text_width(root: &Area, text: &str) -> f64 {
    root.estimate_text_size(text, &font()).map_or(0.0, |(w, _)| w as f64)
}

/// The axis titles' font: the usual size, or smaller where a title is longer than its axis (a
/// y title longer than a short plot would otherwise be cut off by the canvas), down to 8 px.
fn desc_font<X: Ranged, Y: Ranged>(
    root: &Area,
    plot: &DrawingArea<SVGBackend, Cartesian2d<X, Y>>,
    x_title: &str,
    y_title: &str,
) -> TextStyle<'static> {
    let (xs, ys) = plot.get_pixel_range();
    let fit = |title: &str, length: i32| {
        let w = text_width(root, title);
        if w > length as f64 {
            length as f64 / w
        } else {
            1.0
        }
    };
    let scale = fit(x_title, xs.end - xs.start).min(fit(y_title, ys.end - ys.start - 4));
    ("sans-serif", (FONT * scale).max(8.0 * 1.24)).into_text_style(&(WIDTH, HEIGHT))
}

/// Runs `f` with an area to measure text on before there is a chart to draw on (the legend
/// sizes the canvas).
fn measuring<T>(f: impl FnOnce(&Area) -> T) -> T {
    let mut sink = String::new();
    let area = SVGBackend::with_string(&mut sink, (WIDTH, HEIGHT)).into_drawing_area();
    f(&area)
}

/// `s` cut to at most `max` pixels wide, ending in "…" if it was cut.
fn cut(root: &Area, s: &str, max: f64) -> String {
    let mut out = clean(s);
    if text_width(root, &out) <= max {
        return out;
    }
    while !out.is_empty() && text_width(root, &format!("{out}…")) > max {
        out.pop();
    }
    out + "…"
}

/// `s` in lines of at most `max` pixels: broken after spaces (which are dropped) or after
/// `=`, `,`, `/`, `+` and `_` (kept), and inside a word only where one alone is too wide. Nothing
/// is cut: series names often differ only at the end ("… batched", "… batched slot").
fn wrap(area: &Area, s: &str, max: f64) -> Vec<String> {
    const BREAK_AFTER: &str = "=,/+_";
    // The pieces a line may end after, each with whether a space preceded it.
    let (mut pieces, mut word, mut spaced, mut word_spaced) = (Vec::new(), String::new(), false, false);
    for c in clean(s).chars() {
        if c == ' ' {
            if !word.is_empty() {
                pieces.push((std::mem::take(&mut word), word_spaced));
            }
            spaced = true;
            continue;
        }
        if word.is_empty() {
            (word_spaced, spaced) = (spaced, false);
        }
        word.push(c);
        if BREAK_AFTER.contains(c) {
            pieces.push((std::mem::take(&mut word), word_spaced));
        }
    }
    if !word.is_empty() {
        pieces.push((word, word_spaced));
    }
    let mut lines = Vec::new();
    let mut line = String::new();
    for (piece, spaced) in pieces {
        let joined = match (line.is_empty(), spaced) {
            (true, _) => piece.clone(),
            (false, true) => format!("{line} {piece}"),
            (false, false) => format!("{line}{piece}"),
        };
        if line.is_empty() || text_width(area, &joined) <= max {
            line = joined;
        } else {
            lines.push(std::mem::replace(&mut line, piece));
        }
        // A piece wider than a line on its own is split where it must be.
        while text_width(area, &line) > max && line.chars().count() > 1 {
            let chars: Vec<char> = line.chars().collect();
            let k = (1..chars.len())
                .rev()
                .find(|&k| text_width(area, &chars[..k].iter().collect::<String>()) <= max)
                .unwrap_or(1);
            lines.push(chars[..k].iter().collect());
            line = chars[k..].iter().collect();
        }
    }
    if !line.is_empty() || lines.is_empty() {
        lines.push(line);
    }
    lines
}

/// A legend beside the plot: every name whole, wrapped to a fifth of the chart's width.
struct Legend {
    names: Vec<Vec<String>>,
    /// Room the legend needs right of the plot (a small margin when there is no legend).
    width: u32,
}

impl Legend {
    fn new(names: &[&str]) -> Self {
        measuring(|area| {
            let names: Vec<Vec<String>> = names.iter().map(|n| wrap(area, n, WIDTH as f64 / 5.0)).collect();
            let widest = names.iter().flatten().map(|l| text_width(area, l)).reduce(f64::max);
            Legend { names, width: widest.map_or(24, |w| w as u32 + 56) }
        })
    }

    fn lines(&self) -> u32 {
        self.names.iter().map(|n| n.len() as u32).sum()
    }

    /// The canvas height that shows every line beside a plot with `below` pixels under it (x
    /// axis, labels and footnote): the usual height, or taller for a long legend.
    fn height_for(&self, below: u32) -> u32 {
        HEIGHT.max(TITLE_HEIGHT + self.lines() * LINE + below + MARGIN + LINE)
    }
}

/// What a legend entry shows beside its name.
enum Swatch {
    /// The `i`-th line series: its line and marker.
    Line(usize),
    /// A filled box of the `i`-th palette colour.
    Box(usize),
}

/// The `i`-th series' marker around `(x, y)` in pixels: round, square, triangle or diamond, so
/// lines stay distinguishable without colour.
fn marker(i: usize, (x, y): (i32, i32)) -> Polygon<(i32, i32)> {
    let shape: &[(i32, i32)] = match i % 4 {
        0 => &[(-2, -4), (2, -4), (4, -2), (4, 2), (2, 4), (-2, 4), (-4, 2), (-4, -2)],
        1 => &[(-4, -4), (4, -4), (4, 4), (-4, 4)],
        2 => &[(0, -5), (5, 4), (-5, 4)],
        _ => &[(0, -5), (5, 0), (0, 5), (-5, 0)],
    };
    Polygon::new(shape.iter().map(|&(dx, dy)| (x + dx, y + dy)).collect::<Vec<_>>(), color(i).filled())
}

/// Draws the legend to the right of the plot (plotters' own legend stays inside the plot, over
/// the data), top-aligned with it: each swatch beside the first line of its name. The canvas was
/// made tall enough for every line ([`Legend::height_for`]).
fn draw_legend<X: Ranged, Y: Ranged>(
    root: &Area,
    plot: &DrawingArea<SVGBackend, Cartesian2d<X, Y>>,
    entries: &[(Vec<String>, Swatch)],
) -> Drawn {
    let (xs, ys) = plot.get_pixel_range();
    let (x, top, line) = (xs.end + 10, ys.start, LINE as i32);
    let text = font().pos(Pos::new(HPos::Left, VPos::Center));
    let mut row = 0;
    for (name, swatch) in entries {
        let y = top + line * row + line / 2;
        match *swatch {
            Swatch::Line(i) => {
                root.draw(&PathElement::new([(x, y), (x + 18, y)], color(i).stroke_width(2)))?;
                root.draw(&marker(i, (x + 9, y)))?;
            }
            Swatch::Box(i) => {
                root.draw(&Rectangle::new([(x + 2, y - 5), (x + 16, y + 5)], color(i).filled()))?
            }
        }
        for (k, part) in name.iter().enumerate() {
            root.draw_text(part, &text, (x + 24, y + line * k as i32))?;
        }
        row += name.len() as i32;
    }
    Ok(())
}

/// The footnote counting values left out, at the bottom left.
fn footnote(root: &Area, omitted: usize, noun: &str, why: &str) -> Drawn {
    if omitted > 0 {
        let plural = if omitted == 1 { "" } else { "s" };
        let text = format!("{omitted} {noun}{plural} not drawn ({why})");
        root.draw_text(
            &text,
            &font().pos(Pos::new(HPos::Left, VPos::Bottom)),
            (MARGIN as i32, root.dim_in_pixel().1 as i32 - 6),
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What a reader gets back from wrapped lines: the text without the spaces the breaks took.
    fn unspaced(s: &str) -> String {
        s.chars().filter(|&c| c != ' ').collect()
    }

    #[test]
    fn wrapped_names_keep_every_character_within_the_width() {
        let max = WIDTH as f64 / 5.0;
        measuring(|area| {
            for name in [
                "wavefront schedule=regenerate,tail=megakernel refill_below=0.5 queue_order=slot",
                "a_single_identifier_far_wider_than_any_legend_line_can_hold_in_one_piece",
                "short",
                "",
            ] {
                let lines = wrap(area, name, max);
                assert!(!lines.is_empty(), "{name:?}");
                assert_eq!(unspaced(&lines.concat()), unspaced(name), "{lines:?}");
                assert!(
                    lines.iter().all(|l| text_width(area, l) <= max || l.chars().count() == 1),
                    "{lines:?}"
                );
                assert!(lines.iter().all(|l| !l.starts_with(' ') && !l.ends_with(' ')), "{lines:?}");
            }
            // Breaks fall after the separators, so each key=value stays readable.
            let lines = wrap(area, "schedule=regenerate,tail=megakernel,refill_below=0.5", max);
            assert!(
                lines.len() > 1 && lines[..lines.len() - 1].iter().all(|l| l.ends_with([',', '=', '_'])),
                "{lines:?}"
            );
            assert_eq!(wrap(area, "short", max), ["short"]);
        });
    }
}
