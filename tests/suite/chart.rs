//! The chart module (plotters underneath): properties of the rendered documents (well-formed,
//! standalone XML, finite coordinates on the canvas, escaping), and what each chart must show
//! (series in the legend, log axes labelled as such and ticked in decades, points that cannot be
//! drawn left out and counted, "no data", consistent colours, proportional bars).

use roxmltree::{Document, Node};
use wavetrace::chart::*;

// ---------------------------------------------------------------------------------------------
// Reading the SVG.

/// Parses `svg` and checks what every chart must be: well-formed XML with an `<svg>` root 720
/// wide and at least 420 tall (taller only to show a long legend whole), standalone (nothing external, no ids that could clash when inlined in HTML, no
/// scripts), every number finite and every position on the canvas.
fn check_svg(svg: &str) -> Document<'_> {
    let doc = Document::parse(svg).unwrap_or_else(|e| panic!("malformed SVG ({e}):\n{svg}"));
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    assert_eq!(root.tag_name().namespace(), Some("http://www.w3.org/2000/svg"));
    let height: f64 = root.attribute("height").unwrap().parse().unwrap();
    assert!(height >= 420.0, "height {height}");
    assert_eq!(root.attribute("viewBox"), Some(format!("0 0 720 {height}").as_str()));
    for node in doc.descendants().filter(Node::is_element) {
        let name = node.tag_name().name();
        assert!(!["script", "image", "use", "style", "foreignObject"].contains(&name), "<{name}> in:\n{svg}");
        for a in node.attributes() {
            let (key, value) = (a.name(), a.value());
            assert!(
                !["id", "href", "class", "style"].contains(&key) && !key.starts_with("on"),
                "{key}= in {svg}"
            );
            assert!(!value.contains("url("), "{key}={value:?}");
            let numbers: Vec<&str> = match key {
                "x" | "y" | "x1" | "y1" | "x2" | "y2" | "cx" | "cy" | "r" | "width" | "height"
                | "font-size" | "opacity" | "stroke-width" => vec![value],
                "points" => value.split([' ', ',']).filter(|s| !s.is_empty()).collect(),
                _ => continue,
            };
            for n in numbers {
                let v: f64 = n.parse().unwrap_or_else(|_| panic!("{key}={value:?} is not numeric"));
                assert!(v.is_finite(), "{key}={value:?}");
                // A polyline's points mix x and y.
                let limit = match key {
                    "x" | "x1" | "x2" | "cx" | "width" => 721.0,
                    "points" => f64::max(721.0, height + 1.0),
                    _ => height + 1.0,
                };
                if key != "font-size" && key != "opacity" && key != "stroke-width" {
                    assert!((-1.0..=limit).contains(&v), "{key}={v} off the canvas in <{name}>");
                }
            }
        }
    }
    doc
}

/// The text of every `<text>` element, trimmed.
fn texts(doc: &Document) -> Vec<String> {
    text_nodes(doc).into_iter().map(|(t, _)| t).collect()
}

fn text_nodes<'a, 'i>(doc: &'a Document<'i>) -> Vec<(String, Node<'a, 'i>)> {
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| (n.text().unwrap_or("").trim().to_string(), n))
        .collect()
}

fn shows(doc: &Document, want: &str) -> bool {
    texts(doc).iter().any(|t| t == want)
}

fn num(node: Node, key: &str) -> f64 {
    node.attribute(key).unwrap_or_else(|| panic!("no {key}")).parse().unwrap()
}

fn fill_is(node: Node, c: RGBColor) -> bool {
    node.attribute("fill").is_some_and(|f| f.eq_ignore_ascii_case(&hex([c.0, c.1, c.2])))
}

fn stroke_is(node: Node, c: RGBColor) -> bool {
    node.attribute("stroke").is_some_and(|f| f.eq_ignore_ascii_case(&hex([c.0, c.1, c.2])))
}

fn points(node: Node) -> Vec<(f64, f64)> {
    let v: Vec<f64> = node
        .attribute("points")
        .unwrap()
        .split([' ', ','])
        .filter(|s| !s.is_empty())
        .map(|n| n.parse().unwrap())
        .collect();
    v.chunks(2).map(|p| (p[0], p[1])).collect()
}

/// Centres of the markers (filled polygons) of the `i`-th line series, data and legend alike,
/// in document order.
fn markers(doc: &Document, i: usize) -> Vec<(f64, f64)> {
    doc.descendants()
        .filter(|n| n.has_tag_name("polygon") && fill_is(*n, color(i)))
        .map(|n| {
            let p = points(n);
            let mid = |f: fn(&(f64, f64)) -> f64| {
                (p.iter().map(f).fold(f64::MAX, f64::min) + p.iter().map(f).fold(f64::MIN, f64::max)) / 2.0
            };
            (mid(|p| p.0), mid(|p| p.1))
        })
        .collect()
}

/// Polylines stroked in the `i`-th palette colour (a series' line runs, and its legend swatch).
fn lines(doc: &Document, i: usize) -> usize {
    doc.descendants().filter(|n| n.has_tag_name("polyline") && stroke_is(*n, color(i))).count()
}

/// The left edge of the legend: its entries' names are drawn 24 px right of their swatches.
fn legend_left(doc: &Document, names: &[&str]) -> f64 {
    let xs =
        text_nodes(doc).into_iter().filter(|(t, _)| names.contains(&t.as_str())).map(|(_, n)| num(n, "x"));
    xs.fold(f64::INFINITY, f64::min) - 24.0
}

/// Filled rectangles in palette colour `i` left of `x_max`: (x, y, width, height).
fn rects(doc: &Document, i: usize, x_max: f64) -> Vec<(f64, f64, f64, f64)> {
    doc.descendants()
        .filter(|n| n.has_tag_name("rect") && fill_is(*n, color(i)) && num(*n, "x") < x_max)
        .map(|n| (num(n, "x"), num(n, "y"), num(n, "width"), num(n, "height")))
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Colours.

#[test]
fn viridis_matches_published_endpoints_and_clamps() {
    assert_eq!(viridis(0.0), [0x44, 0x01, 0x54]);
    assert_eq!(viridis(1.0), [0xfd, 0xe7, 0x25]);
    assert_eq!(hex(viridis(0.0)), "#440154");
    assert_eq!(hex(viridis(1.0)), "#fde725");
    assert_eq!(viridis(-3.0), viridis(0.0));
    assert_eq!(viridis(7.0), viridis(1.0));
    assert_eq!(viridis(f32::NAN), viridis(0.0));
    // matplotlib's viridis(0.5) is #21918c; the interpolated table is within 2/255.
    let mid = viridis(0.5);
    for (c, want) in mid.iter().zip([0x21u8, 0x91, 0x8c]) {
        assert!(c.abs_diff(want) <= 2, "{mid:?}");
    }
    // Viridis brightens monotonically (its defining property for a sequential map).
    let luma = |[r, g, b]: [u8; 3]| 0.2126 * r as f32 + 0.7152 * g as f32 + 0.0722 * b as f32;
    for i in 0..100 {
        assert!(luma(viridis((i + 1) as f32 / 100.0)) >= luma(viridis(i as f32 / 100.0)) - 0.5);
    }
}

#[test]
fn palette_colours_are_distinct_and_cycle() {
    assert!(PALETTE.len() >= 8);
    for (i, c) in PALETTE.iter().enumerate() {
        assert!(!PALETTE[..i].contains(c), "{c:?} repeated");
        assert_ne!(*c, RGBColor(255, 255, 255), "white is the background");
    }
    assert_eq!(color(0), RGBColor(0x00, 0x72, 0xb2), "Okabe–Ito blue first");
    assert_eq!(color(PALETTE.len()), PALETTE[0]);
}

// ---------------------------------------------------------------------------------------------
// Line charts.

fn line_chart(series: Vec<Series>) -> LineChart {
    LineChart {
        title: "time per frame".into(),
        x_label: "pool size".into(),
        y_label: "ms".into(),
        x_log: false,
        y_log: false,
        x_zero: false,
        series,
    }
}

fn series(name: &str, points: &[(f64, f64)]) -> Series {
    Series { name: name.into(), points: points.to_vec(), intervals: Vec::new(), labels: Vec::new() }
}

#[test]
fn line_chart_draws_every_point_and_names_every_series() {
    let chart = line_chart(vec![
        series("megakernel", &[(1.0, 10.0), (2.0, 8.0), (4.0, 7.5)]),
        series("wavefront", &[(1.0, 12.0), (2.0, 7.0), (4.0, 5.0), (8.0, 4.2)]),
    ]);
    let svg = chart.to_svg();
    let doc = check_svg(&svg);
    // One marker per point, plus one in the legend; one line per series, plus its legend swatch.
    assert_eq!(markers(&doc, 0).len(), 3 + 1);
    assert_eq!(markers(&doc, 1).len(), 4 + 1);
    assert_eq!((lines(&doc, 0), lines(&doc, 1)), (2, 2));
    for want in ["time per frame", "pool size", "ms", "megakernel", "wavefront"] {
        assert!(shows(&doc, want), "{want:?} not shown: {:?}", texts(&doc));
    }
    // The legend lists the series in order, beside the plot rather than over the data.
    let legend = legend_left(&doc, &["megakernel", "wavefront"]);
    let data = markers(&doc, 0).into_iter().chain(markers(&doc, 1)).filter(|m| m.0 < legend);
    assert_eq!(data.count(), 7);
    let y_of = |name: &str| num(text_nodes(&doc).into_iter().find(|(t, _)| t == name).unwrap().1, "y");
    assert!(y_of("megakernel") < y_of("wavefront"));
    // Linear axes do not claim to be logarithmic; nothing was left out.
    assert!(!svg.contains("log scale") && !svg.contains("not drawn"));
}

#[test]
fn line_chart_markers_follow_the_data() {
    // y = 2x: marker positions must be collinear, and ordered as the data. A lone unnamed series
    // has no legend, so every marker is a data point.
    let chart = line_chart(vec![series("", &[(0.0, 0.0), (1.0, 2.0), (3.0, 6.0), (5.0, 10.0)])]);
    let svg = chart.to_svg();
    let doc = check_svg(&svg);
    let pts = markers(&doc, 0);
    assert_eq!(pts.len(), 4);
    for w in pts.windows(2) {
        assert!(w[1].0 > w[0].0 && w[1].1 < w[0].1, "{pts:?}");
    }
    // Pixels are whole numbers: the slopes agree to within rounding.
    let slope = |a: (f64, f64), b: (f64, f64)| (b.1 - a.1) / (b.0 - a.0);
    assert!((slope(pts[0], pts[1]) - slope(pts[1], pts[3])).abs() < 0.05, "{pts:?}");
    // The line passes through the markers.
    let line = doc.descendants().find(|n| n.has_tag_name("polyline") && stroke_is(*n, color(0))).unwrap();
    assert_eq!(points(line), pts);
}

#[test]
fn log_axes_are_labelled_in_decades_and_drop_what_they_cannot_draw() {
    let mut chart = line_chart(vec![series(
        "",
        &[
            (1.0, 0.0),
            (2.0, 0.5),
            (4.0, 0.05),
            (8.0, -1.0),
            (16.0, f64::NAN),
            (32.0, 0.001),
            (f64::INFINITY, 1.0),
        ],
    )]);
    chart.x_log = true;
    chart.y_log = true;
    let svg = chart.to_svg();
    let doc = check_svg(&svg);
    let pts = markers(&doc, 0);
    assert_eq!(pts.len(), 3, "kept: (2, 0.5), (4, 0.05), (32, 0.001)");
    // Equal factors in x are equal distances: 2 → 4 is a quarter of 2 → 32.
    let (dx1, dx2) = (pts[1].0 - pts[0].0, pts[2].0 - pts[0].0);
    assert!((dx2 / dx1 - 4.0).abs() < 0.1, "{pts:?}");
    // The line breaks at the dropped points: (2, 4) is one run, (32) alone draws no line.
    assert_eq!(lines(&doc, 0), 1);
    assert!(shows(&doc, "pool size (log scale)"), "{:?}", texts(&doc));
    assert!(shows(&doc, "ms (log scale)"), "{:?}", texts(&doc));
    assert!(shows(&doc, "4 points not drawn (not finite, or ≤ 0 on a log axis)"), "{:?}", texts(&doc));
    // Tick labels are whole decades spanning the data: 1..100 in x, 0.001..1 in y.
    let ticks: Vec<f64> = texts(&doc).iter().filter_map(|t| t.parse().ok()).collect();
    for want in [1.0, 10.0, 100.0, 0.001, 0.01, 0.1] {
        assert!(ticks.contains(&want), "no {want} tick in {ticks:?}");
    }
    for t in &ticks {
        assert_eq!(t.log10(), t.log10().round(), "tick {t} is not a decade");
    }
}

/// `x_zero`: x = 0 on a log axis is drawn at a tick of its own marked "0", a decade left of the
/// data, rather than left out; the axis title says so.
#[test]
fn zero_on_a_log_x_axis_sits_at_its_own_tick() {
    let mut chart = line_chart(vec![series("far", &[(0.0, 1.0), (1e3, 2.0), (1e5, 30.0)])]);
    chart.x_log = true;
    chart.y_log = true;
    chart.x_zero = true;
    let svg = chart.to_svg();
    let doc = check_svg(&svg);
    let pts = markers(&doc, 0);
    assert_eq!(pts.len(), 3 + 1, "every point drawn, and the legend's marker");
    assert!(!svg.contains("not drawn"), "nothing left out");
    assert!(shows(&doc, "pool size (log scale; 0 drawn at the tick marked 0)"), "{:?}", texts(&doc));
    // Ticks 0, 1000, 10k, 100k: "0" a decade left of 1000, where 100 would be.
    let x_of = |t: &str| num(text_nodes(&doc).into_iter().find(|(s, _)| s == t).unwrap().1, "x");
    let (zero, thousand, ten_k) = (x_of("0"), x_of("1000"), x_of("10k"));
    assert!(
        zero < thousand && ((thousand - zero) - (ten_k - thousand)).abs() < 2.0,
        "{zero} {thousand} {ten_k}"
    );
    // The zero point sits on the 0 tick.
    let leftmost = markers(&doc, 0).into_iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
    assert!((leftmost - zero).abs() < 3.0, "{leftmost} vs {zero}");
    // Without x_zero (or on a linear axis) a zero is left out on a log axis, as before.
    chart.x_zero = false;
    assert!(chart.to_svg().contains("1 point not drawn"));
}

#[test]
fn nonfinite_points_on_linear_axes_are_dropped() {
    let chart =
        line_chart(vec![series("", &[(0.0, 1.0), (1.0, f64::NAN), (2.0, 3.0), (f64::NEG_INFINITY, 0.0)])]);
    let svg = chart.to_svg();
    let doc = check_svg(&svg);
    assert_eq!(markers(&doc, 0).len(), 2);
    assert_eq!(lines(&doc, 0), 0, "the gap is not bridged");
    assert!(shows(&doc, "2 points not drawn (not finite)"), "{:?}", texts(&doc));
}

#[test]
fn tick_labels_are_compact() {
    // Tick labels: every text that is a number, possibly with an SI suffix.
    let ticks = |doc: &Document| -> Vec<String> {
        let number = |t: &str| t.trim_end_matches(['k', 'M', 'G']).parse::<f64>().is_ok();
        texts(doc).into_iter().filter(|t| number(t)).collect()
    };
    for (lo, hi) in [(0.0, 0.93), (-1e-3, 7e-3), (1e5, 3.3e5), (0.1, 0.3)] {
        let chart = line_chart(vec![series("", &[(lo, lo), (hi, hi)])]);
        let svg = chart.to_svg();
        let ticks = ticks(&check_svg(&svg));
        assert!(ticks.len() >= 6, "{ticks:?}");
        for t in ticks {
            assert!(t.len() <= 6, "tick {t:?} too long (floating-point noise?)");
        }
    }
    // Large values in thousands ("10k", "15k"), not "1e4" beside "15000".
    let chart = line_chart(vec![series("", &[(0.0, 0.0), (0.5, 32_000.0)])]);
    let svg = chart.to_svg();
    let ticks = ticks(&check_svg(&svg));
    let thousands: Vec<&String> = ticks.iter().filter(|t| t.ends_with('k')).collect();
    assert!(thousands.len() >= 3 && ticks.contains(&"10k".to_string()), "{ticks:?}");
    assert!(!ticks.iter().any(|t| t.contains('e')), "{ticks:?}");
}

#[test]
fn names_and_titles_are_escaped() {
    let mut chart =
        line_chart(vec![series("a<b & \"c\"\u{1}", &[(1.0, 1.0), (2.0, 2.0)]), series("x'y", &[(1.0, 3.0)])]);
    chart.title = "<script>alert(1)</script> & co".into();
    chart.x_label = "\"quoted\" & <x>".into();
    let svg = chart.to_svg();
    let doc = check_svg(&svg);
    assert!(!svg.contains("<script>") && !svg.contains("a<b"));
    for want in ["<script>alert(1)</script> & co", "a<b & \"c\"", "x'y", "\"quoted\" & <x>"] {
        assert!(shows(&doc, want), "{want:?} not in {:?}", texts(&doc));
    }
}

#[test]
fn single_point_and_constant_series_are_padded_mid_plot() {
    // (chart, whether x is degenerate too); a degenerate coordinate must land mid-plot, not on
    // an edge produced by a zero-width range.
    for (chart, x_degenerate) in [
        (line_chart(vec![series("", &[(3.0, 7.0)])]), true),
        (line_chart(vec![series("", &[(1.0, 5.0), (2.0, 5.0), (3.0, 5.0)])]), false),
        (line_chart(vec![series("", &[(0.0, 0.0), (0.0, 0.0)])]), true),
        (LineChart { x_log: true, y_log: true, ..line_chart(vec![series("", &[(100.0, 1e-3)])]) }, true),
    ] {
        let svg = chart.to_svg();
        let doc = check_svg(&svg);
        let pts = markers(&doc, 0);
        assert!(!pts.is_empty());
        for (x, y) in pts {
            assert!(y > 120.0 && y < 300.0, "y = {y}");
            if x_degenerate {
                assert!(x > 250.0 && x < 550.0, "x = {x}");
            }
        }
    }
}

#[test]
fn empty_charts_say_no_data() {
    let charts = [
        line_chart(vec![]).to_svg(),
        line_chart(vec![series("a", &[])]).to_svg(),
        line_chart(vec![series("a", &[(f64::NAN, 1.0), (1.0, f64::INFINITY)])]).to_svg(),
        LineChart { y_log: true, ..line_chart(vec![series("a", &[(1.0, 0.0), (2.0, -1.0)])]) }.to_svg(),
        StackedBarChart { title: "time per frame".into(), y_label: "ms".into(), bars: vec![] }.to_svg(),
        StackedBarChart {
            title: "time per frame".into(),
            y_label: "ms".into(),
            bars: vec![Bar { label: "a".into(), segments: vec![("x".into(), f64::NAN)] }],
        }
        .to_svg(),
        GroupedBarChart {
            title: "time per frame".into(),
            groups: vec![("g".into(), vec![])],
            ..Default::default()
        }
        .to_svg(),
    ];
    for svg in charts {
        let doc = check_svg(&svg);
        assert_eq!(texts(&doc), ["time per frame", "no data"], "{svg}");
        let shapes =
            doc.descendants().filter(|n| ["polygon", "polyline", "rect"].contains(&n.tag_name().name()));
        let drawn = shapes.filter(|n| PALETTE.iter().any(|&c| fill_is(*n, c) || stroke_is(*n, c)));
        assert_eq!(drawn.count(), 0, "{svg}");
    }
}

#[test]
fn many_series_keep_the_legend_beside_the_plot() {
    let names: Vec<String> = (0..30).map(|i| format!("a rather long series name number {i}")).collect();
    let many: Vec<Series> =
        names.iter().enumerate().map(|(i, n)| series(n, &[(0.0, i as f64), (1.0, i as f64 + 1.0)])).collect();
    let svg = line_chart(many).to_svg();
    let doc = check_svg(&svg);
    // Every name is shown whole, wrapped onto lines: nothing cut, nothing summarised.
    let legend: Vec<(String, Node)> =
        text_nodes(&doc).into_iter().filter(|(t, _)| t.starts_with("a rather")).collect();
    assert_eq!(legend.len(), 30, "one entry per series");
    let left = legend.iter().map(|(_, n)| num(*n, "x")).fold(f64::INFINITY, f64::min) - 24.0;
    let lines: Vec<(String, Node)> =
        text_nodes(&doc).into_iter().filter(|(_, n)| num(*n, "x") >= left).collect();
    assert!(lines.len() > 30, "long names wrap: {} lines", lines.len());
    assert!(lines.iter().all(|(t, _)| !t.contains('…') && !t.contains("more")), "{:?}", texts(&doc));
    let read: Vec<&str> = lines.iter().map(|(t, _)| t.as_str()).collect();
    assert_eq!(read.join(" "), names.join(" "), "the legend reads every name in order");
    // The canvas grew to hold them, every line inside it and below the one before.
    let height = num(doc.root_element(), "height");
    assert!(height > 420.0, "height {height}");
    let ys: Vec<f64> = lines.iter().map(|(_, n)| num(*n, "y")).collect();
    assert!(ys.windows(2).all(|w| w[1] > w[0]) && ys.iter().all(|&y| y < height), "{ys:?}");
    // Every data marker is left of the legend; the legend's own markers are inside it.
    for i in 0..30 {
        let (data, swatch): (Vec<_>, Vec<_>) = markers(&doc, i).into_iter().partition(|m| m.0 < left - 5.0);
        // Palette colours repeat after 12 and shapes after 4: series i shares both with i ± 12k.
        assert!(data.len() >= 2 && data.len() % 2 == 0, "series {i}: {data:?}");
        assert!(swatch.iter().all(|m| m.0 < left + 20.0), "series {i}: {swatch:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// Bar charts.

fn stacked() -> StackedBarChart {
    let bar = |label: &str, segs: &[(&str, f64)]| Bar {
        label: label.into(),
        segments: segs.iter().map(|(n, v)| (n.to_string(), *v)).collect(),
    };
    StackedBarChart {
        title: "passes".into(),
        y_label: "ms".into(),
        bars: vec![
            bar("pool 1M", &[("generate", 1.0), ("intersect", 4.0), ("shade", 2.0)]),
            bar("pool 4M", &[("shade", 3.0), ("generate", 0.5), ("compact", 1.0), ("intersect", 6.0)]),
            bar("pool 16M", &[("compact", 2.0), ("bogus", f64::NAN)]),
        ],
    }
}

const SEGMENTS: [&str; 4] = ["generate", "intersect", "shade", "compact"];

#[test]
fn stacked_bars_keep_one_colour_per_segment_and_list_it_once() {
    let svg = stacked().to_svg();
    let doc = check_svg(&svg);
    let left = legend_left(&doc, &SEGMENTS);
    // Colours by first appearance: generate, intersect, shade, compact; the NaN segment is left
    // out and counted.
    let counts: Vec<usize> = (0..4).map(|k| rects(&doc, k, left).len()).collect();
    assert_eq!(counts, [2, 2, 2, 2]);
    assert!(rects(&doc, 4, left).is_empty(), "nothing drawn for the NaN segment");
    assert!(shows(&doc, "1 value not drawn (not finite)"), "{:?}", texts(&doc));
    // The legend lists each segment once, top to bottom as the stack reads (reverse order of
    // first appearance), each beside a swatch of its colour.
    let legend: Vec<(String, Node)> =
        text_nodes(&doc).into_iter().filter(|(t, _)| SEGMENTS.contains(&t.as_str())).collect();
    let order: Vec<&str> = legend.iter().map(|(t, _)| t.as_str()).collect();
    assert_eq!(order, ["compact", "shade", "intersect", "generate"]);
    for (name, node) in &legend {
        let k = SEGMENTS.iter().position(|s| s == name).unwrap();
        let swatch = rects(&doc, k, 721.0).into_iter().find(|r| r.0 >= left).expect("a swatch");
        assert!((swatch.1 + swatch.3 / 2.0 - num(*node, "y")).abs() <= 1.0, "{name}'s swatch is beside it");
    }
    for label in ["pool 1M", "pool 4M", "pool 16M"] {
        assert!(shows(&doc, label));
    }
}

#[test]
fn stacked_segments_are_proportional_and_stack_from_zero() {
    let svg = stacked().to_svg();
    let doc = check_svg(&svg);
    let left = legend_left(&doc, &SEGMENTS);
    // Bar "pool 1M" (the leftmost): generate 1, intersect 4, shade 2, bottom-up without gaps.
    let first = |k: usize| rects(&doc, k, left).into_iter().min_by(|a, b| a.0.total_cmp(&b.0)).unwrap();
    let (generate, intersect, shade) = (first(0), first(1), first(2));
    assert!(generate.0 == intersect.0 && intersect.0 == shade.0, "one bar");
    let unit = (generate.3 + intersect.3 + shade.3) / 7.0;
    assert!((intersect.3 - 4.0 * unit).abs() <= 1.5 && (shade.3 - 2.0 * unit).abs() <= 1.5, "{unit}");
    assert_eq!(generate.1, intersect.1 + intersect.3, "generate sits under intersect");
    assert_eq!(intersect.1, shade.1 + shade.3, "intersect sits under shade");
    // All bars stand on the same baseline.
    let base = generate.1 + generate.3;
    let compact = rects(&doc, 3, left).into_iter().max_by(|a, b| a.0.total_cmp(&b.0)).unwrap();
    assert_eq!(compact.1 + compact.3, base);
}

#[test]
fn long_category_labels_are_rotated_cut_shrunk_and_thinned() {
    let bars: Vec<Bar> = (0..60)
        .map(|i| Bar {
            label: format!("configuration with a very long descriptive name #{i}"),
            segments: vec![("a".into(), 1.0 + i as f64), ("b".into(), 2.0)],
        })
        .collect();
    let svg = StackedBarChart { title: "many".into(), y_label: "ms".into(), bars }.to_svg();
    let doc = check_svg(&svg);
    let left = legend_left(&doc, &["a", "b"]);
    let (a, b) = (rects(&doc, 0, left), rects(&doc, 1, left));
    assert_eq!((a.len(), b.len()), (60, 60));
    // Bars do not overlap each other.
    let mut xs: Vec<(f64, f64)> = a.iter().map(|r| (r.0, r.2)).collect();
    xs.sort_by(|p, q| p.0.total_cmp(&q.0));
    for w in xs.windows(2) {
        assert!(w[0].0 + w[0].1 <= w[1].0, "{w:?}");
    }
    let labels: Vec<Node> =
        text_nodes(&doc).into_iter().filter(|(t, _)| t.starts_with("config")).map(|(_, n)| n).collect();
    assert_eq!(labels.len(), 60, "slots of about 10 px still take a (smaller) label each");
    // Cut at their end they would all read the same: they keep their numbers instead.
    assert!(labels.iter().all(|l| l.text().unwrap().trim().contains('#')), "labels tell their bars apart");
    let mut xs: Vec<f64> = Vec::new();
    for l in &labels {
        assert!(
            l.attribute("transform").is_some_and(|t| t.starts_with("rotate(270")),
            "long labels are rotated"
        );
        assert!(l.text().unwrap().trim().contains('…'), "long labels are cut");
        xs.push(num(*l, "x"));
    }
    // Rotated labels are at least a line of their font apart, and that font is readable.
    let font = num(labels[0], "font-size");
    assert!(font >= 7.0, "{font} px");
    for w in xs.windows(2) {
        assert!(w[1] - w[0] >= font, "labels at {} and {} overlap", w[0], w[1]);
    }
    // With more bars than 7 px labels fit, every n-th is labelled.
    let bars: Vec<Bar> =
        (0..200).map(|i| Bar { label: format!("run {i:03}"), segments: vec![("a".into(), 1.0)] }).collect();
    let svg = StackedBarChart { title: "many".into(), y_label: "ms".into(), bars }.to_svg();
    let doc = check_svg(&svg);
    let labels: Vec<String> = texts(&doc).into_iter().filter(|t| t.starts_with("run ")).collect();
    assert!(labels.len() > 30 && labels.len() <= 100, "{} labels", labels.len());
    assert_eq!(labels[0], "run 000");
}

#[test]
fn short_labels_stay_horizontal() {
    let bars: Vec<Bar> = ["a", "b", "c"]
        .iter()
        .map(|l| Bar { label: l.to_string(), segments: vec![("t".into(), 1.0)] })
        .collect();
    let svg = StackedBarChart { title: "t".into(), y_label: String::new(), bars }.to_svg();
    let doc = check_svg(&svg);
    let (_, label) = text_nodes(&doc).into_iter().find(|(t, _)| t == "b").unwrap();
    assert!(label.attribute("transform").is_none());
}

fn efficiency() -> GroupedBarChart {
    GroupedBarChart {
        title: "SIMD efficiency".into(),
        y_label: "active lanes".into(),
        y_max: Some(1.0),
        percent: true,
        groups: vec![
            ("intersect".into(), vec![("megakernel".into(), 0.25), ("wavefront".into(), 0.5)]),
            ("shade".into(), vec![("megakernel".into(), 0.4), ("wavefront".into(), f64::INFINITY)]),
            ("compact".into(), vec![("wavefront".into(), 0.93)]),
        ],
    }
}

#[test]
fn grouped_bars_in_percent() {
    let svg = efficiency().to_svg();
    let doc = check_svg(&svg);
    for want in ["0%", "20%", "100%", "megakernel", "wavefront", "intersect", "shade", "compact"] {
        assert!(shows(&doc, want), "{want:?} not in {:?}", texts(&doc));
    }
    // y_max 1.0 with values below it: the axis ends at 100%, not beyond.
    assert!(!texts(&doc)
        .iter()
        .any(|t| t.ends_with('%') && t.trim_end_matches('%').parse::<f64>().unwrap() > 100.0));
    let left = legend_left(&doc, &["megakernel", "wavefront"]);
    let (mega, wave) = (rects(&doc, 0, left), rects(&doc, 1, left));
    assert_eq!((mega.len(), wave.len()), (2, 2), "the infinite value is not drawn");
    assert!(shows(&doc, "1 value not drawn (not finite)"));
    // Heights proportional to values, on a common baseline; each series keeps its side.
    let (quarter, half) = (mega[0], wave[0]);
    assert!((half.3 - 2.0 * quarter.3).abs() <= 1.5, "{quarter:?} {half:?}");
    assert_eq!(half.1 + half.3, quarter.1 + quarter.3, "common baseline");
    assert!(quarter.0 + quarter.2 <= half.0, "megakernel left of wavefront");
}

#[test]
fn grouped_axis_extends_past_y_max_rather_than_cut_bars() {
    let mut chart = efficiency();
    chart.groups[0].1[1].1 = 1.3;
    let svg = chart.to_svg();
    let doc = check_svg(&svg);
    let top_label = texts(&doc)
        .iter()
        .filter_map(|t| t.strip_suffix('%').and_then(|v| v.parse::<f64>().ok()))
        .fold(0.0, f64::max);
    assert!(top_label >= 120.0, "axis tops out at {top_label}%");
    // The 130% bar fits under the title.
    let tallest =
        rects(&doc, 1, legend_left(&doc, &["wavefront"])).into_iter().map(|r| r.1).fold(f64::MAX, f64::min);
    assert!(tallest >= 30.0, "bar top {tallest} in the title");
}

#[test]
fn negative_values_hang_below_zero() {
    let chart = GroupedBarChart {
        title: "speedup change".into(),
        y_label: "%".into(),
        y_max: None,
        percent: false,
        groups: vec![("a".into(), vec![("".into(), -2.0)]), ("b".into(), vec![("".into(), 3.0)])],
    };
    let svg = chart.to_svg();
    let doc = check_svg(&svg);
    let bars = rects(&doc, 0, 721.0);
    let (neg, pos) = (bars[0], bars[1]);
    // The negative bar starts where the positive one ends: at zero.
    assert_eq!(neg.1, pos.1 + pos.3, "{bars:?}");
    assert!((neg.3 / pos.3 - 2.0 / 3.0).abs() < 0.02, "{bars:?}");
}

/// Rotated category labels that would be cut into the same text ("megakernel-regenerat…" for
/// the 4 and 16 spp runs) keep their ends instead, so every label still names its bar.
#[test]
fn cut_labels_never_become_duplicates() {
    let names = [
        "megakernel-regenerate-with-persistent-threads 4spp",
        "megakernel-regenerate-with-persistent-threads 16spp",
        "megakernel_traverse_bounding_volume_hierarchy_inner",
        "megakernel_traverse_bounding_volume_hierarchy_leaf",
    ];
    let bars: Vec<Bar> =
        names.iter().map(|l| Bar { label: l.to_string(), segments: vec![("t".into(), 1.0)] }).collect();
    let doc_text = StackedBarChart { title: "t".into(), y_label: "ms".into(), bars }.to_svg();
    let doc = check_svg(&doc_text);
    let labels: Vec<String> = texts(&doc).into_iter().filter(|t| t.starts_with("megak")).collect();
    assert_eq!(labels.len(), 4, "{labels:?}");
    let distinct: std::collections::BTreeSet<&String> = labels.iter().collect();
    assert_eq!(distinct.len(), 4, "cut labels clash: {labels:?}");
    assert!(labels.iter().all(|l| l.contains('…')), "{labels:?}");
    assert!(labels[1].ends_with("16spp") && labels[3].ends_with("leaf"), "{labels:?}");
}

/// A report gives each method one colour in every chart: `to_svg_with` colours a series (line
/// or bar) by its name, wherever it sits in the chart.
#[test]
fn series_take_the_colour_their_name_is_given() {
    let colour = |name: &str| match name {
        "wavefront" => Some(3),
        "megakernel" => Some(1),
        _ => None,
    };
    let chart =
        line_chart(vec![series("wavefront", &[(1.0, 1.0), (2.0, 2.0)]), series("cpu", &[(1.0, 3.0)])]);
    let doc_text = chart.to_svg_with(&colour);
    let doc = check_svg(&doc_text);
    assert_eq!(lines(&doc, 3), 2, "the wavefront's line and its legend swatch in colour 3");
    assert_eq!(lines(&doc, 0), 0, "no series at its position's colour 0");
    assert_eq!(
        markers(&doc, 1).len(),
        2,
        "cpu, unnamed by the colours, keeps its position's colour 1 (point and legend)"
    );
    let doc_text = efficiency().to_svg_with(&colour);
    let doc = check_svg(&doc_text);
    let left = legend_left(&doc, &["megakernel", "wavefront"]);
    assert_eq!((rects(&doc, 1, left).len(), rects(&doc, 3, left).len()), (2, 2));
}

/// Points carry their labels (the spp of a speed-vs-error point), written once where the same
/// text already sits close by.
#[test]
fn point_labels_are_written_beside_their_points() {
    let mut a = series("a", &[(1.0, 1.0), (100.0, 0.01)]);
    a.labels = vec!["4 spp".into(), "16 spp".into()];
    let mut b = series("b", &[(1.0001, 1.0), (50.0, 0.02)]);
    b.labels = vec!["4 spp".into(), "16 spp".into()];
    let doc_text = line_chart(vec![a, b]).to_svg();
    let doc = check_svg(&doc_text);
    let count = |t: &str| texts(&doc).iter().filter(|x| *x == t).count();
    assert_eq!((count("4 spp"), count("16 spp")), (1, 2), "{:?}", texts(&doc));
}
