//! `report.html` on a real page (issue 29): labels, the question and a failed run's error text
//! that carry markup reach the page through the binary (`experiment run`, then `experiment
//! report`) as text, never as markup. (Escaping itself is unit-tested in src/experiment/html.rs.)

use crate::experiment::{scratch, small_config, wavetrace, write_config};

use std::collections::BTreeSet;
use std::path::Path;

const LABEL: &str = "<script>alert(1)</script>&\"'";
const LABEL_2: &str = "<b onmouseover=alert(2)>mk</b>";
const ADAPTER: &str = "<img src=x onerror=alert(3)>";
const QUESTION: &str = "Is <iframe src=javascript:alert(4)> & \"co\" safe?";

/// Every element the page may hold: its own and the inline charts' (SVG).
const TAGS: [&str; 44] = [
    "!DOCTYPE",
    "html",
    "head",
    "meta",
    "title",
    "style",
    "body",
    "h1",
    "h2",
    "h3",
    "p",
    "b",
    "code",
    "pre",
    "table",
    "tr",
    "th",
    "td",
    "div",
    "span",
    "sup",
    "figure",
    "figcaption",
    "a",
    "img",
    "details",
    "summary",
    "br",
    "svg",
    "g",
    "rect",
    "text",
    "path",
    "polyline",
    "line",
    "circle",
    "polygon",
    "defs",
    "clipPath",
    "tspan",
    "section",
    "ul",
    "li",
    "i",
];

/// The element names of every tag in `html` (`<name` and `</name`).
fn tags(html: &str) -> BTreeSet<String> {
    let mut names = BTreeSet::new();
    let mut rest = html;
    while let Some(i) = rest.find('<') {
        rest = &rest[i + 1..];
        let name: String = rest
            .trim_start_matches('/')
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '!')
            .collect();
        names.insert(name);
    }
    names
}

fn assert_no_markup_from_inputs(page: &Path) {
    let html = std::fs::read_to_string(page).unwrap();
    let unknown: Vec<String> = tags(&html).into_iter().filter(|t| !TAGS.contains(&t.as_str())).collect();
    assert!(unknown.is_empty(), "{}: elements the page does not write: {unknown:?}", page.display());
    for raw in [LABEL, LABEL_2, ADAPTER, QUESTION, "<script", "<iframe", "<img src=x", "<b onmouseover"] {
        assert!(!html.contains(raw), "{}: {raw:?} unescaped", page.display());
    }
    // Every image is the page's own preview, inline.
    for (i, _) in html.match_indices("<img ") {
        assert!(html[i..].starts_with("<img src=\"data:image/png;base64,"), "{}", &html[i..i + 60]);
    }
    // And the inputs did reach it, as text.
    let esc = wavetrace::experiment::escape::esc;
    for text in [LABEL, LABEL_2, ADAPTER, QUESTION] {
        assert!(html.contains(&esc(text)), "{}: {text:?} is not on the page as text", page.display());
    }
    assert!(html.contains("FAILED: "), "the failed run is on the page");
}

/// A config with hostile labels, question and adapter name (which every GPU run's error
/// repeats): the page written by `experiment run` and the one `experiment report` redraws from
/// report.json show them as text only.
#[test]
fn hostile_labels_and_error_text_are_text_on_the_page() {
    let dir = scratch("report-page-hostile");
    let mut config = small_config(serde_json::json!([
        {"method": "cpu", "label": LABEL},
        {"method": "megakernel", "label": LABEL_2},
    ]));
    config["question"] = QUESTION.into();
    // No adapter has this name, so the GPU run fails on any machine, its error naming it.
    config["adapter"] = ADAPTER.into();
    config["resolutions"] = serde_json::json!(["16x9"]);
    config["spp"] = serde_json::json!([1, 2]);
    config["repetitions"] = 1.into();
    config["warmup"] = 0.into();
    config["reference"] = serde_json::json!({"method": "cpu", "spp": 2});
    let config = write_config(&dir, "hostile", &config);
    let out = dir.join("out");
    let s = |p: &Path| p.to_str().unwrap().to_owned();
    let o =
        wavetrace(&["experiment", "run", &s(&config), "--out", &s(&out), "--cache", &s(&dir.join("cache"))]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && stderr.contains("2 of 4 runs failed"), "{stderr}");
    let report = wavetrace::experiment::ExperimentReport::read(&out).unwrap();
    let error = report.runs.iter().find_map(|r| r.error.clone()).expect("a failed run");
    assert!(error.contains(ADAPTER), "the error text carries the markup: {error}");
    assert_no_markup_from_inputs(&out.join("report.html"));

    std::fs::remove_file(out.join("report.html")).unwrap();
    let o = wavetrace(&["experiment", "report", &s(&out)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_no_markup_from_inputs(&out.join("report.html"));
}
