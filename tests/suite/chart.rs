//! The SVG chart module: tick rules, label formatting, colours, and properties of the rendered
//! documents (well-formed XML, finite coordinates, escaping, dropped points, consistent colours).

use wavetrace::chart::*;

// ---------------------------------------------------------------------------------------------
// A tiny XML reader, strict enough for what the charts emit: balanced tags, one root, quoted
// attributes, no raw `<` or bad entities in text or attribute values.

#[derive(Debug)]
struct Node {
    name: String,
    attrs: Vec<(String, String)>,
    /// Unescaped direct text content.
    text: String,
    children: Vec<usize>,
}

impl Node {
    fn attr(&self, key: &str) -> Option<&str> {
        self.attrs.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
    }
}

fn unescape(s: &str) -> Result<String, String> {
    let mut out = String::new();
    let mut rest = s;
    while let Some(amp) = rest.find('&') {
        out.push_str(&rest[..amp]);
        let semi = rest[amp..].find(';').ok_or_else(|| format!("unterminated entity in {s:?}"))?;
        let entity = &rest[amp + 1..amp + semi];
        out.push(match entity {
            "amp" => '&',
            "lt" => '<',
            "gt" => '>',
            "quot" => '"',
            "apos" | "#39" => '\'',
            _ => return Err(format!("unknown entity &{entity}; in {s:?}")),
        });
        rest = &rest[amp + semi + 1..];
    }
    out.push_str(rest);
    if out.contains('<') && !s.contains("&lt;") {
        return Err(format!("raw '<' in {s:?}"));
    }
    Ok(out)
}

/// Parses `doc`, returning its nodes (index 0 is the root) or the first problem found.
fn parse_xml(doc: &str) -> Result<Vec<Node>, String> {
    let mut nodes: Vec<Node> = Vec::new();
    let mut stack: Vec<usize> = Vec::new();
    let mut i = 0;
    loop {
        let next = doc[i..].find('<').map(|o| i + o);
        let text = &doc[i..next.unwrap_or(doc.len())];
        match stack.last() {
            Some(&top) => nodes[top].text.push_str(&unescape(text)?),
            None if !text.trim().is_empty() => return Err(format!("text outside the root: {text:?}")),
            None => {}
        }
        let Some(start) = next else { break };
        let end = start + doc[start..].find('>').ok_or("unterminated tag")?;
        let inner = &doc[start + 1..end];
        if let Some(name) = inner.strip_prefix('/') {
            let open = stack.pop().ok_or_else(|| format!("</{name}> closes nothing"))?;
            if nodes[open].name != name.trim() {
                return Err(format!("</{name}> closes <{}>", nodes[open].name));
            }
        } else {
            let self_closing = inner.ends_with('/');
            let inner = inner.strip_suffix('/').unwrap_or(inner);
            let name_end = inner.find(char::is_whitespace).unwrap_or(inner.len());
            let name = &inner[..name_end];
            if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == ':') {
                return Err(format!("bad element name {name:?}"));
            }
            let mut attrs = Vec::new();
            let mut rest = inner[name_end..].trim_start();
            while !rest.is_empty() {
                let eq = rest.find('=').ok_or_else(|| format!("attribute without value in <{name}>"))?;
                let key = rest[..eq].trim();
                let after = &rest[eq + 1..];
                let value = after.strip_prefix('"').ok_or_else(|| format!("unquoted attribute {key}"))?;
                let close = value.find('"').ok_or_else(|| format!("unterminated attribute {key}"))?;
                if attrs.iter().any(|(k, _): &(String, String)| k == key) {
                    return Err(format!("duplicate attribute {key} in <{name}>"));
                }
                attrs.push((key.to_string(), unescape(&value[..close])?));
                rest = value[close + 1..].trim_start();
            }
            if stack.is_empty() && !nodes.is_empty() {
                return Err("more than one root element".into());
            }
            let id = nodes.len();
            nodes.push(Node { name: name.to_string(), attrs, text: String::new(), children: Vec::new() });
            if let Some(&parent) = stack.last() {
                nodes[parent].children.push(id);
            }
            if !self_closing {
                stack.push(id);
            }
        }
        i = end + 1;
    }
    if let Some(&open) = stack.last() {
        return Err(format!("<{}> never closed", nodes[open].name));
    }
    if nodes.is_empty() {
        return Err("empty document".into());
    }
    Ok(nodes)
}

/// Checks the properties every chart must have and returns its parsed nodes.
fn check_svg(svg: &str) -> Vec<Node> {
    let nodes = parse_xml(svg).unwrap_or_else(|e| panic!("malformed SVG ({e}):\n{svg}"));
    let root = &nodes[0];
    assert_eq!(root.name, "svg");
    assert_eq!(root.attr("xmlns"), Some("http://www.w3.org/2000/svg"));
    assert_eq!(root.attr("viewBox"), Some("0 0 720 420"));
    assert_eq!(root.attr("font-family"), Some("sans-serif"));
    assert!(!svg.contains("NaN") && !svg.contains("inf"), "non-finite number in:\n{svg}");
    for node in &nodes {
        for (key, value) in &node.attrs {
            let numeric: Vec<&str> = match key.as_str() {
                "x" | "y" | "x1" | "y1" | "x2" | "y2" | "cx" | "cy" | "r" | "width" | "height"
                | "font-size" => {
                    vec![value.as_str()]
                }
                "points" => value.split([' ', ',']).collect(),
                "transform" => value.trim_start_matches("rotate(").trim_end_matches(')').split(' ').collect(),
                _ => continue,
            };
            for n in numeric {
                let v: f64 = n.parse().unwrap_or_else(|_| panic!("{key}={value:?} is not numeric"));
                assert!(v.is_finite(), "{key}={value:?}");
            }
            if ["x", "x1", "x2", "cx"].contains(&key.as_str()) {
                let v: f64 = value.parse().unwrap();
                assert!((-1.0..=721.0).contains(&v), "{key}={v} off the canvas");
            }
            if ["y", "y1", "y2", "cy"].contains(&key.as_str()) {
                let v: f64 = value.parse().unwrap();
                assert!((-1.0..=421.0).contains(&v), "{key}={v} off the canvas");
            }
        }
    }
    nodes
}

fn with_class<'a>(nodes: &'a [Node], class: &str) -> Vec<&'a Node> {
    nodes.iter().filter(|n| n.attr("class") == Some(class)).collect()
}

/// The tooltip text of a node (its `<title>` child).
fn tooltip(nodes: &[Node], node: &Node) -> String {
    node.children
        .iter()
        .map(|&c| &nodes[c])
        .find(|c| c.name == "title")
        .map(|c| c.text.clone())
        .unwrap_or_else(|| panic!("<{}> without a <title>", node.name))
}

/// All text shown by `<text>` elements.
fn texts(nodes: &[Node]) -> Vec<String> {
    nodes.iter().filter(|n| n.name == "text").map(|n| n.text.clone()).collect()
}

/// Centre of a data marker (circle, square or polygon).
fn marker_centre(node: &Node) -> (f64, f64) {
    match node.name.as_str() {
        "circle" => (num_attr(node, "cx"), num_attr(node, "cy")),
        "rect" => (
            num_attr(node, "x") + num_attr(node, "width") / 2.0,
            num_attr(node, "y") + num_attr(node, "height") / 2.0,
        ),
        "polygon" => {
            let v: Vec<f64> =
                node.attr("points").unwrap().split([' ', ',']).map(|n| n.parse().unwrap()).collect();
            let xs: Vec<f64> = v.iter().step_by(2).copied().collect();
            let ys: Vec<f64> = v.iter().skip(1).step_by(2).copied().collect();
            let mid = |a: &[f64]| {
                (a.iter().copied().fold(f64::MAX, f64::min) + a.iter().copied().fold(f64::MIN, f64::max))
                    / 2.0
            };
            (mid(&xs), mid(&ys))
        }
        other => panic!("unexpected marker <{other}>"),
    }
}

fn num_attr(node: &Node, key: &str) -> f64 {
    node.attr(key).unwrap_or_else(|| panic!("no {key}")).parse().unwrap()
}

#[test]
fn xml_checker_catches_errors() {
    assert!(parse_xml("<a><b></a></b>").is_err());
    assert!(parse_xml("<a x=\"1\"><b/></a>").is_ok());
    assert!(parse_xml("<a>x & y</a>").is_err());
    assert!(parse_xml("<a x=1/>").is_err());
    assert!(parse_xml("<a/><b/>").is_err());
    assert!(parse_xml("<a>").is_err());
}

// ---------------------------------------------------------------------------------------------
// Axes and labels.

#[test]
fn log_ticks_are_exact_decades() {
    assert_eq!(log_ticks(1e-4, 1.0), vec![1e-4, 1e-3, 1e-2, 1e-1, 1.0]);
    // Widened outward to whole decades.
    assert_eq!(log_ticks(3.0, 70.0), vec![1.0, 10.0, 100.0]);
    assert_eq!(log_ticks(1e3, 1e6), vec![1e3, 1e4, 1e5, 1e6]);
    assert!(log_ticks(0.0, 1.0).is_empty());
    assert!(log_ticks(-1.0, 1.0).is_empty());
    assert!(log_ticks(f64::NAN, 1.0).is_empty());
}

#[test]
fn log_axis_labels() {
    let labelled = |a: &Axis| -> Vec<(f64, String)> {
        a.ticks.iter().filter_map(|t| t.label.clone().map(|l| (t.value, l))).collect()
    };
    // Four decades: only decades are labelled, in compact form.
    let a = Axis::log10(1e-4, 1.0);
    assert_eq!((a.min, a.max, a.log), (1e-4, 1.0, true));
    assert_eq!(
        labelled(&a),
        vec![
            (1e-4, "1e-4".to_string()),
            (1e-3, "0.001".to_string()),
            (1e-2, "0.01".to_string()),
            (0.1, "0.1".to_string()),
            (1.0, "1".to_string())
        ]
    );
    // Unlabelled minor marks at 2..9 of each decade.
    assert_eq!(a.ticks.len(), 4 * 9 + 1);
    // Two decades or fewer: 1, 2 and 5 of each decade are labelled.
    let a = Axis::log10(1.5, 80.0);
    let values: Vec<f64> = labelled(&a).into_iter().map(|(v, _)| v).collect();
    assert_eq!(values, vec![1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0]);
    // Many decades: at most about 8 labels.
    let a = Axis::log10(1e-12, 1e12);
    let n = labelled(&a).len();
    assert!((4..=9).contains(&n), "{n} labels");
    // A single value gets a decade either side; fraction is 0 and 1 at the ends.
    let a = Axis::log10(10.0, 10.0);
    assert_eq!((a.min, a.max), (1.0, 100.0));
    assert_eq!(a.fraction(10.0), 0.5);
}

#[test]
fn nice_ticks_follow_1_2_5_steps() {
    assert_eq!(nice_ticks(0.0, 0.93, 5), vec![0.0, 0.2, 0.4, 0.6, 0.8, 1.0]);
    assert_eq!(nice_ticks(0.1, 0.35, 5), vec![0.1, 0.15, 0.2, 0.25, 0.3, 0.35]);
    assert_eq!(nice_ticks(-3.2, 7.9, 5), vec![-5.0, 0.0, 5.0, 10.0]);
    assert_eq!(nice_ticks(0.0, 1.0, 5), vec![0.0, 0.2, 0.4, 0.6, 0.8, 1.0]);
    assert_eq!(nice_ticks(1000.0, 4_200_000.0, 5), vec![0.0, 1e6, 2e6, 3e6, 4e6, 5e6]);
    assert_eq!(nice_ticks(0.0, 0.0007, 5), vec![0.0, 0.0002, 0.0004, 0.0006, 0.0008]);
    // Reversed bounds are sorted.
    assert_eq!(nice_ticks(0.93, 0.0, 5), nice_ticks(0.0, 0.93, 5));
}

#[test]
fn degenerate_ranges_are_padded() {
    // All-equal values: ±10% around the value.
    let t = nice_ticks(5.0, 5.0, 5);
    assert_eq!(t, vec![4.4, 4.6, 4.8, 5.0, 5.2, 5.4, 5.6]);
    // Zero: ±1.
    assert_eq!(nice_ticks(0.0, 0.0, 4), vec![-1.0, -0.5, 0.0, 0.5, 1.0]);
    // Non-finite bounds fall back to [0, 1].
    assert_eq!(nice_ticks(f64::NAN, 1.0, 5), vec![0.0, 0.2, 0.4, 0.6, 0.8, 1.0]);
    let a = Axis::linear(3.0, 3.0, 5);
    assert!(a.min < 3.0 && a.max > 3.0);
    assert!((a.fraction(3.0) - 0.5).abs() < 1e-12);
}

#[test]
fn tick_labels_are_compact_and_exact() {
    assert_eq!(format_tick(0.1 + 0.2, 0.1), "0.3");
    assert_eq!(format_tick(0.7 * 100.0, 10.0), "70");
    assert_eq!(format_tick(1e-4, 1e-4), "1e-4");
    assert_eq!(format_tick(2.5e-5, 5e-6), "2.5e-5");
    assert_eq!(format_tick(0.001, 0.001), "0.001");
    assert_eq!(format_tick(1500.0, 500.0), "1500");
    assert_eq!(format_tick(10_000.0, 10_000.0), "10k");
    assert_eq!(format_tick(12_500.0, 2500.0), "12.5k");
    assert_eq!(format_tick(2_500_000.0, 500_000.0), "2.5M");
    assert_eq!(format_tick(3e9, 1e9), "3G");
    assert_eq!(format_tick(1e12, 1e12), "1e12");
    assert_eq!(format_tick(-0.5, 0.5), "-0.5");
    assert_eq!(format_tick(0.0, 0.2), "0");
    assert_eq!(format_tick(-0.0, 0.2), "0");
    assert_eq!(format_value(0.123456789), "0.123457");
    assert_eq!(format_value(1234567.0), "1.23457M");

    let labels = |a: Axis| a.ticks.into_iter().filter_map(|t| t.label).collect::<Vec<_>>();
    assert_eq!(labels(Axis::linear(0.0, 0.93, 5)), ["0", "0.2", "0.4", "0.6", "0.8", "1"]);
    assert_eq!(labels(Axis::linear(0.0, 1.0, 5).percent()), ["0%", "20%", "40%", "60%", "80%", "100%"]);
    assert_eq!(labels(Axis::linear(0.0, 0.7, 7).percent())[7], "70%");
    for a in [Axis::linear(0.0, 0.93, 9), Axis::linear(-1e-3, 7e-3, 9), Axis::linear(1e5, 3.3e5, 9)] {
        for l in labels(a) {
            assert!(l.len() <= 7, "label {l:?} too long");
        }
    }
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
fn palette_is_distinct_hex() {
    assert!(PALETTE.len() >= 8);
    for (i, c) in PALETTE.iter().enumerate() {
        assert!(c.len() == 7 && c.starts_with('#'), "{c}");
        assert!(c[1..].chars().all(|h| h.is_ascii_hexdigit() && !h.is_ascii_uppercase()), "{c}");
        assert!(!PALETTE[..i].contains(c), "{c} repeated");
    }
    assert_eq!(color(PALETTE.len()), PALETTE[0]);
}

#[test]
fn escape_handles_markup() {
    assert_eq!(escape(r#"a<b & "c" 'd'>"#), "a&lt;b &amp; &quot;c&quot; &#39;d&#39;&gt;");
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
        series,
    }
}

fn series(name: &str, points: &[(f64, f64)]) -> Series {
    Series { name: name.into(), points: points.to_vec() }
}

#[test]
fn line_chart_draws_every_point_with_a_tooltip() {
    let chart = line_chart(vec![
        series("megakernel", &[(1.0, 10.0), (2.0, 8.0), (4.0, 7.5)]),
        series("wavefront", &[(1.0, 12.0), (2.0, 7.0), (4.0, 5.0), (8.0, 4.2)]),
    ]);
    let svg = chart.to_svg();
    let nodes = check_svg(&svg);
    let points = with_class(&nodes, "point");
    assert_eq!(points.len(), 7);
    let tips: Vec<String> = points.iter().map(|p| tooltip(&nodes, p)).collect();
    assert!(tips.contains(&"wavefront: x = 8, y = 4.2".to_string()), "{tips:?}");
    assert!(tips.contains(&"megakernel: x = 1, y = 10".to_string()), "{tips:?}");
    assert_eq!(nodes.iter().filter(|n| n.name == "polyline").count(), 2);
    let shown = texts(&nodes);
    for want in ["time per frame", "pool size", "ms", "megakernel", "wavefront"] {
        assert!(shown.iter().any(|t| t == want), "{want:?} not shown: {shown:?}");
    }
    // Linear axes do not claim to be logarithmic.
    assert!(!svg.contains("log scale"));
}

#[test]
fn line_chart_markers_follow_the_data() {
    // y = 2x: marker positions must be collinear, and ordered as the data.
    let chart = line_chart(vec![series("s", &[(0.0, 0.0), (1.0, 2.0), (3.0, 6.0), (5.0, 10.0)])]);
    let nodes = check_svg(&chart.to_svg());
    let pts: Vec<(f64, f64)> = with_class(&nodes, "point").iter().map(|p| marker_centre(p)).collect();
    assert_eq!(pts.len(), 4);
    for w in pts.windows(2) {
        assert!(w[1].0 > w[0].0 && w[1].1 < w[0].1, "{pts:?}");
    }
    let slope = |a: (f64, f64), b: (f64, f64)| (b.1 - a.1) / (b.0 - a.0);
    assert!((slope(pts[0], pts[1]) - slope(pts[2], pts[3])).abs() < 0.01, "{pts:?}");
}

#[test]
fn log_axis_drops_nonpositive_and_nonfinite_points() {
    let mut chart = line_chart(vec![series(
        "err",
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
    let nodes = check_svg(&svg);
    let points = with_class(&nodes, "point");
    assert_eq!(points.len(), 3, "kept: (2, 0.5), (4, 0.05), (32, 0.001)");
    let tips: Vec<String> = points.iter().map(|p| tooltip(&nodes, p)).collect();
    assert_eq!(tips, ["err: x = 2, y = 0.5", "err: x = 4, y = 0.05", "err: x = 32, y = 0.001"]);
    // The line breaks at the dropped points: (2, 4) is one run, (32) alone draws no line.
    assert_eq!(nodes.iter().filter(|n| n.name == "polyline").count(), 1);
    let shown = texts(&nodes);
    assert!(shown.iter().any(|t| t == "pool size (log scale)"), "{shown:?}");
    assert!(shown.iter().any(|t| t == "ms (log scale)"), "{shown:?}");
    assert!(shown.iter().any(|t| t.starts_with("4 points not drawn")), "{shown:?}");
}

#[test]
fn nonfinite_points_on_linear_axes_are_dropped() {
    let chart =
        line_chart(vec![series("a", &[(0.0, 1.0), (1.0, f64::NAN), (2.0, 3.0), (f64::NEG_INFINITY, 0.0)])]);
    let nodes = check_svg(&chart.to_svg());
    assert_eq!(with_class(&nodes, "point").len(), 2);
    assert_eq!(nodes.iter().filter(|n| n.name == "polyline").count(), 0, "the gap is not bridged");
}

#[test]
fn names_and_titles_are_escaped() {
    let mut chart =
        line_chart(vec![series(r#"a<b & "c""#, &[(1.0, 1.0), (2.0, 2.0)]), series("x'y", &[(1.0, 3.0)])]);
    chart.title = "<script>alert(1)</script> & co".into();
    chart.x_label = "\"quoted\" & <x>".into();
    let svg = chart.to_svg();
    let nodes = check_svg(&svg);
    assert!(svg.contains("a&lt;b &amp; &quot;c&quot;"));
    assert!(!svg.contains("<script>") && !svg.contains("a<b"));
    let shown = texts(&nodes);
    assert!(shown.iter().any(|t| t == "<script>alert(1)</script> & co"), "{shown:?}");
    assert!(shown.iter().any(|t| t == r#"a<b & "c""#), "{shown:?}");
    let tips: Vec<String> = with_class(&nodes, "point").iter().map(|p| tooltip(&nodes, p)).collect();
    assert!(tips.contains(&r#"a<b & "c": x = 2, y = 2"#.to_string()), "{tips:?}");
}

#[test]
fn single_point_and_constant_series_render() {
    // (chart, whether x is degenerate too); a degenerate coordinate must land mid-plot, not on
    // an edge produced by a zero-width range.
    for (chart, x_degenerate) in [
        (line_chart(vec![series("one", &[(3.0, 7.0)])]), true),
        (line_chart(vec![series("flat", &[(1.0, 5.0), (2.0, 5.0), (3.0, 5.0)])]), false),
        (line_chart(vec![series("zero", &[(0.0, 0.0), (0.0, 0.0)])]), true),
        (LineChart { x_log: true, y_log: true, ..line_chart(vec![series("one", &[(100.0, 1e-3)])]) }, true),
    ] {
        let nodes = check_svg(&chart.to_svg());
        let points = with_class(&nodes, "point");
        assert!(!points.is_empty());
        for p in points {
            let (x, y) = marker_centre(p);
            assert!(y > 100.0 && y < 320.0, "y = {y}");
            if x_degenerate {
                assert!(x > 200.0 && x < 600.0, "x = {x}");
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
        let nodes = check_svg(&svg);
        let shown = texts(&nodes);
        assert!(shown.contains(&"no data".to_string()), "{svg}");
        assert!(shown.contains(&"time per frame".to_string()), "{svg}");
        assert!(with_class(&nodes, "point").is_empty() && with_class(&nodes, "bar").is_empty());
    }
}

#[test]
fn many_series_keep_the_legend_outside_the_plot() {
    let many: Vec<Series> = (0..30)
        .map(|i| {
            series(
                &format!("a rather long series name number {i}"),
                &[(0.0, i as f64), (1.0, i as f64 + 1.0)],
            )
        })
        .collect();
    let nodes = check_svg(&line_chart(many).to_svg());
    assert_eq!(with_class(&nodes, "point").len(), 60);
    let max_marker_x = with_class(&nodes, "point").iter().map(|p| marker_centre(p).0).fold(0.0, f64::max);
    let legend_x = nodes
        .iter()
        .filter(|n| n.name == "text" && n.text.starts_with("a rather"))
        .map(|n| num_attr(n, "x"))
        .fold(f64::INFINITY, f64::min);
    assert!(legend_x > max_marker_x + 10.0, "legend at {legend_x}, data up to {max_marker_x}");
    assert!(texts(&nodes).iter().any(|t| t.ends_with(" more")), "overflowing legend is summarised");
}

// ---------------------------------------------------------------------------------------------
// Bar charts.

/// (tooltip, fill, top y, height) of every bar.
fn bars(nodes: &[Node]) -> Vec<(String, String, f64, f64)> {
    with_class(nodes, "bar")
        .iter()
        .map(|b| {
            (tooltip(nodes, b), b.attr("fill").unwrap().to_string(), num_attr(b, "y"), num_attr(b, "height"))
        })
        .collect()
}

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

#[test]
fn stacked_bar_colours_are_consistent_across_bars() {
    let svg = stacked().to_svg();
    let nodes = check_svg(&svg);
    let bars = bars(&nodes);
    assert_eq!(bars.len(), 8, "NaN segment not drawn");
    let segment = |tip: &str| tip.split(": ").nth(1).unwrap().split(" = ").next().unwrap().to_string();
    let mut colour_of: Vec<(String, String)> = Vec::new();
    for (tip, fill, _, _) in &bars {
        let name = segment(tip);
        match colour_of.iter().find(|(n, _)| *n == name) {
            Some((_, f)) => assert_eq!(f, fill, "{name} changes colour"),
            None => colour_of.push((name, fill.clone())),
        }
    }
    assert_eq!(colour_of.len(), 4);
    for (i, (_, a)) in colour_of.iter().enumerate() {
        assert!(colour_of[..i].iter().all(|(_, b)| b != a), "two segments share {a}");
    }
    // The legend lists each segment once, with the same colour.
    let shown = texts(&nodes);
    for (name, fill) in &colour_of {
        assert_eq!(shown.iter().filter(|t| *t == name).count(), 1, "{name} in legend");
        let swatches = nodes.iter().filter(|n| n.name == "rect" && n.attr("class").is_none()).count();
        assert!(swatches >= 4);
        assert!(nodes
            .iter()
            .any(|n| n.name == "rect" && n.attr("class").is_none() && n.attr("fill") == Some(fill)));
    }
    assert!(shown.iter().any(|t| t == "1 value not drawn (not finite)"), "{shown:?}");
}

#[test]
fn stacked_segments_are_proportional_and_stack() {
    let nodes = check_svg(&stacked().to_svg());
    let bars = bars(&nodes);
    // Bar "pool 1M": generate 1, intersect 4, shade 2, stacked bottom-up without gaps.
    let b1: Vec<_> = bars.iter().filter(|b| b.0.starts_with("pool 1M:")).collect();
    assert_eq!(b1.len(), 3);
    let unit = b1[0].3;
    assert!((b1[1].3 - 4.0 * unit).abs() < 0.05 && (b1[2].3 - 2.0 * unit).abs() < 0.05, "{b1:?}");
    assert!((b1[0].2 - (b1[1].2 + b1[1].3)).abs() < 0.02, "generate sits under intersect");
    assert!((b1[1].2 - (b1[2].2 + b1[2].3)).abs() < 0.02, "intersect sits under shade");
    assert!(b1[0].0.ends_with("(total 7)"), "{}", b1[0].0);
    // All bars share the zero baseline.
    let base = b1[0].2 + b1[0].3;
    for b in bars.iter().filter(|b| b.0.contains("= ")) {
        if b.0.starts_with("pool 16M") {
            assert!((b.2 + b.3 - base).abs() < 0.02);
        }
    }
}

#[test]
fn sixty_bars_with_long_labels_render_without_overlap() {
    let bars: Vec<Bar> = (0..60)
        .map(|i| Bar {
            label: format!("configuration with a very long descriptive name #{i}"),
            segments: vec![("a".into(), 1.0 + i as f64), ("b".into(), 2.0)],
        })
        .collect();
    let chart = StackedBarChart { title: "many".into(), y_label: "ms".into(), bars };
    let svg = chart.to_svg();
    let nodes = check_svg(&svg);
    assert_eq!(with_class(&nodes, "bar").len(), 120);
    let labels: Vec<&Node> =
        nodes.iter().filter(|n| n.name == "text" && n.text.starts_with("configuration")).collect();
    assert!(!labels.is_empty());
    for l in &labels {
        assert!(l.attr("transform").is_some_and(|t| t.starts_with("rotate(")), "long labels are rotated");
        assert!(l.text.ends_with('…'), "long labels are cut: {}", l.text);
    }
    // Rotated labels anchored at distinct x, at least one line height apart.
    let mut xs: Vec<f64> = labels.iter().map(|l| num_attr(l, "x")).collect();
    xs.sort_by(f64::total_cmp);
    let font: f64 = labels[0].attr("font-size").unwrap().parse().unwrap();
    for w in xs.windows(2) {
        assert!(w[1] - w[0] >= font, "labels {} and {} overlap", w[0], w[1]);
    }
    // Bars do not overlap each other either.
    let mut lefts: Vec<(f64, f64)> =
        with_class(&nodes, "bar").iter().map(|b| (num_attr(b, "x"), num_attr(b, "width"))).collect();
    lefts.sort_by(|a, b| a.0.total_cmp(&b.0));
    lefts.dedup_by(|a, b| a.0 == b.0);
    assert_eq!(lefts.len(), 60);
    for w in lefts.windows(2) {
        assert!(w[0].0 + w[0].1 <= w[1].0 + 0.01);
    }
}

#[test]
fn rotated_labels_stay_on_the_canvas() {
    let bars: Vec<Bar> = (0..20)
        .map(|i| Bar { label: format!("scene-{i}-variant"), segments: vec![("t".into(), 1.0)] })
        .collect();
    let nodes = check_svg(&StackedBarChart { title: "t".into(), y_label: "ms".into(), bars }.to_svg());
    let labels: Vec<&Node> =
        nodes.iter().filter(|n| n.name == "text" && n.text.starts_with("scene-")).collect();
    assert_eq!(labels.len(), 20);
    for l in labels {
        assert!(l.attr("transform").is_some_and(|t| t.starts_with("rotate(-45 ")), "{:?}", l.attrs);
        // Right-anchored at x and running down-left at 45°: its left end, at a generous 0.6 em
        // per character, must be on the canvas.
        let font: f64 = l.attr("font-size").unwrap().parse().unwrap();
        let run = l.text.chars().count() as f64 * font * 0.6 * std::f64::consts::FRAC_1_SQRT_2;
        assert!(num_attr(l, "x") - run >= 0.0, "{} starts off the canvas", l.text);
    }
}

#[test]
fn short_labels_stay_horizontal() {
    let bars: Vec<Bar> = ["a", "b", "c"]
        .iter()
        .map(|l| Bar { label: l.to_string(), segments: vec![("t".into(), 1.0)] })
        .collect();
    let nodes = check_svg(&StackedBarChart { title: "t".into(), y_label: String::new(), bars }.to_svg());
    let label = nodes.iter().find(|n| n.name == "text" && n.text == "b").unwrap();
    assert!(label.attr("transform").is_none());
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
    let nodes = check_svg(&svg);
    let shown = texts(&nodes);
    for want in ["0%", "20%", "100%", "megakernel", "wavefront", "intersect", "shade", "compact"] {
        assert!(shown.iter().any(|t| t == want), "{want:?} not in {shown:?}");
    }
    // y_max 1.0 with values below it: the axis ends at 100%, not at the data's 93%.
    assert!(!shown.iter().any(|t| t == "120%"));
    let bars = bars(&nodes);
    assert_eq!(bars.len(), 4, "the infinite value is not drawn");
    let get = |tip: &str| bars.iter().find(|b| b.0 == tip).unwrap_or_else(|| panic!("{tip} not in {bars:?}"));
    let (quarter, half) = (get("megakernel — intersect: 25%"), get("wavefront — intersect: 50%"));
    assert!((half.3 - 2.0 * quarter.3).abs() < 0.05, "heights proportional to values");
    assert!((half.2 + half.3 - (quarter.2 + quarter.3)).abs() < 0.01, "common baseline");
    // Each series keeps its colour in every group.
    assert_eq!(get("megakernel — shade: 40%").1, quarter.1);
    assert_eq!(get("wavefront — compact: 93%").1, half.1);
    assert_ne!(quarter.1, half.1);
}

#[test]
fn grouped_axis_extends_past_y_max_rather_than_cut_bars() {
    let mut chart = efficiency();
    chart.groups[0].1[1].1 = 1.3;
    let nodes = check_svg(&chart.to_svg());
    let shown = texts(&nodes);
    // [0, 1.3] in about 5 steps: step 0.5, so the axis ends at 150%.
    assert!(shown.iter().any(|t| t == "150%"), "{shown:?}");
    let top = nodes
        .iter()
        .filter(|n| n.attr("class") == Some("bar"))
        .map(|b| num_attr(b, "y"))
        .fold(f64::MAX, f64::min);
    assert!(top >= 40.0, "bar top {top} above the plot");
}

#[test]
fn negative_values_hang_below_zero() {
    let chart = GroupedBarChart {
        title: "speedup change".into(),
        y_label: "%".into(),
        y_max: None,
        percent: false,
        groups: vec![("a".into(), vec![("s".into(), -2.0)]), ("b".into(), vec![("s".into(), 3.0)])],
    };
    let nodes = check_svg(&chart.to_svg());
    let bars = bars(&nodes);
    let (neg, pos) = (&bars[0], &bars[1]);
    // The negative bar starts where the positive one ends: at zero.
    assert!((neg.2 - (pos.2 + pos.3)).abs() < 0.01, "{bars:?}");
    assert!((neg.3 / pos.3 - 2.0 / 3.0).abs() < 0.01);
}
