//! The documentation cannot go stale: every results page under docs/results/ is what
//! `wavetrace experiment report DIR --markdown` writes from the committed report, and every
//! committed report has its page; and no figure in the README or in a page of docs/ is typed
//! by hand: each is quoted from a generated page (or an accepted committed output) that its
//! paragraph links.

use std::path::{Path, PathBuf};

use wavetrace::experiment::{markdown, ExperimentReport};

/// `experiments/results/<device>/<name>` for every committed report, relative to the root.
fn committed_reports(root: &Path) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for device in std::fs::read_dir(root.join("experiments/results")).unwrap().flatten() {
        if !device.path().is_dir() {
            continue;
        }
        for exp in std::fs::read_dir(device.path()).unwrap().flatten() {
            if exp.path().join("report.json").is_file() {
                out.push((
                    device.file_name().to_string_lossy().into_owned(),
                    exp.file_name().to_string_lossy().into_owned(),
                ));
            }
        }
    }
    out.sort();
    out
}

#[test]
fn every_results_page_is_generated_from_its_committed_report() {
    let root = crate::common::root();
    let reports = committed_reports(&root);
    assert!(reports.len() >= 10, "the committed reports went missing: {reports:?}");
    let mut stale = Vec::new();
    for (device, name) in &reports {
        let source = format!("experiments/results/{device}/{name}");
        let mut report = ExperimentReport::read(&root.join(&source)).unwrap();
        markdown::keep_present_charts(&mut report, &root.join(&source));
        let charts = format!("../../../{source}/");
        let want =
            markdown::page(&report, &source, &markdown::Links { charts: &charts, docs: Some("../../") });
        let page: PathBuf = root.join(format!("docs/results/{device}/{name}.md"));
        match std::fs::read_to_string(&page) {
            Ok(have) if have == want => {}
            Ok(_) => stale.push(format!("{} differs from its report", page.display())),
            Err(_) => stale.push(format!("{} is missing", page.display())),
        }
    }
    // And no page without a report.
    for device in
        std::fs::read_dir(root.join("docs/results")).unwrap().flatten().filter(|d| d.path().is_dir())
    {
        for page in std::fs::read_dir(device.path()).unwrap().flatten() {
            let file = page.file_name().to_string_lossy().into_owned();
            let Some(name) = file.strip_suffix(".md") else { continue };
            let d = device.file_name().to_string_lossy().into_owned();
            if name != "README" && !reports.contains(&(d.clone(), name.to_string())) {
                stale.push(format!(
                    "docs/results/{d}/{file} has no report in experiments/results/{d}/{name}/"
                ));
            }
        }
    }
    assert!(stale.is_empty(), "{}\nregenerate with scripts/results_pages.sh", stale.join("\n"));
}

#[test]
fn markdown_reports_come_from_the_command_line_too() {
    let root = crate::common::root();
    let dir = crate::common::tmp().join("docs-markdown");
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.join("pages/quick.md");
    let o = std::process::Command::new(crate::common::bin())
        .current_dir(&root)
        .args(["experiment", "report", "experiments/results/llvmpipe-2core/quick", "--markdown", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let page = std::fs::read_to_string(&out).unwrap();
    assert!(page.contains("# quick\n") && page.contains("| # | scene | job |"), "{page}");
    // The chart links lead from the page to the report's directory.
    let link = page.lines().find_map(|l| l.split("](").nth(1)).unwrap().trim_end_matches(')');
    assert!(out.parent().unwrap().join(link).is_file(), "chart link {link} does not resolve");
    // Stdout without --out; --out without --markdown is refused; a directory without a report too.
    let o = std::process::Command::new(crate::common::bin())
        .current_dir(&root)
        .args(["experiment", "report", "experiments/results/llvmpipe-2core/quick", "--markdown"])
        .output()
        .unwrap();
    assert_eq!(String::from_utf8_lossy(&o.stdout).lines().nth(1), Some("# quick"));
    let o = std::process::Command::new(crate::common::bin())
        .args(["experiment", "report", "x", "--out", "y.md"])
        .output()
        .unwrap();
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("--markdown"));
    let o = std::process::Command::new(crate::common::bin())
        .args(["experiment", "report"])
        .arg(&dir)
        .arg("--markdown")
        .output()
        .unwrap();
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("report.json"));
}

fn read(rel: &str) -> String {
    std::fs::read_to_string(crate::common::root().join(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// Tokens that read as measured figures: `1.36×`, `1.335e-2`, each end of a range (`0.74×–1.27×`).
fn figures(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for word in text.split(|c: char| c.is_whitespace() || "(),;–".contains(c)) {
        let w = word.trim_end_matches(['.', ':']);
        // A figure marked as a flagged run's (`0.07×⚠`) is one figure, mark included.
        let number = w.trim_end_matches('⚠').trim_end_matches('×');
        let bare = w.trim_end_matches('⚠');
        let is_ratio = bare.ends_with('×') && number.parse::<f64>().is_ok() && number.contains('.');
        let is_sci = bare.contains('e') && bare.parse::<f64>().is_ok() && bare.contains('.');
        if is_ratio || is_sci {
            out.push(w.to_string());
        }
    }
    out
}

/// Stricter than [`figures`], for pages of notes rather than headline bullets: any decimal
/// (`0.4890`, `2.762e-2`), ratio (`1.36×`, `2×`), percentage (`55.7%`) or count of three digits
/// or more (`6947`), each end of a range (`0.89–1.10×`) on its own, a signed one (`−1.5%`,
/// `+3%`) without its sign. Inline code is skipped
/// (options and commit hashes); a power such as `1e-3` without a decimal point reads as a
/// setting, not a figure.
pub fn quoted_figures(text: &str) -> Vec<String> {
    let mut prose = String::new();
    for (i, part) in text.split('`').enumerate() {
        if i % 2 == 0 {
            prose.push_str(part);
        }
        prose.push(' ');
    }
    let mut out = Vec::new();
    for word in prose.split(|c: char| c.is_whitespace() || "(),;[]/–→".contains(c)) {
        let w = word.trim_matches(['*', '_', '.', ':']).trim_start_matches(['+', '-', '−', '±', '~']);
        // A figure quoted with a flagged run's mark (`0.74×⚠`) is one figure, mark included: it
        // must be on the page with the mark, and says so to the reader.
        let number = w.trim_end_matches('⚠').trim_end_matches(['×', '%']);
        if !number.starts_with(|c: char| c.is_ascii_digit()) || number.parse::<f64>().is_err() {
            continue;
        }
        let count = number.len() >= 3 && number.chars().all(|c| c.is_ascii_digit());
        if number.contains('.') || w.ends_with('%') || w.ends_with('×') || count {
            out.push(w.to_string());
        }
    }
    out
}

/// Whether `figure` is on `page` as a whole number (not the start or end of a longer one) and
/// as a steady figure: results pages write ⚠ right after every figure of a run whose
/// repetitions spread beyond the threshold or that ran cold (`experiment/stability.rs`), and
/// such an occurrence does not count, so no finding can rest on one.
fn on_page(figure: &str, page: &str) -> bool {
    page.match_indices(figure).any(|(i, _)| {
        let flagged = page[i + figure.len()..].trim_start_matches(['×', '%']).starts_with('⚠');
        let before = page[..i].chars().next_back();
        let mut after = page[i + figure.len()..].chars();
        let (next, then) = (after.next(), after.next());
        let longer_before = before.is_some_and(|c| c.is_ascii_digit() || c == '.');
        let longer_after = next.is_some_and(|c| c.is_ascii_digit())
            || (next == Some('.') && then.is_some_and(|c| c.is_ascii_digit()));
        !longer_before && !longer_after && !flagged
    })
}

/// `dir/link` with `.` and `..` resolved (links in Markdown are relative to their page).
fn resolve(dir: &Path, link: &str) -> PathBuf {
    let mut out = PathBuf::new();
    for c in dir.join(link.split('#').next().unwrap_or("")).components() {
        match c {
            std::path::Component::ParentDir => {
                out.pop();
            }
            std::path::Component::CurDir => {}
            c => out.push(c),
        }
    }
    out
}

/// The generated results pages (`docs/results/<device>/<name>.md`, not a README) that `unit`
/// links, as text; `doc` is the page the unit is on, relative to the root.
fn linked_results_pages(doc: &str, unit: &str) -> Vec<String> {
    linked_sources(doc, unit).into_iter().filter(|(p, _)| is_results_page(p)).map(|(_, t)| t).collect()
}

/// Committed artefacts that are not results pages but that notes may quote as if they were,
/// each with the reason. Each is written whole by a committed script from a committed run, and
/// its directory has a row in the device's `PROVENANCE.md` naming the command and the build
/// (checked below); what it holds is the script's output, never edited by hand. So a figure
/// on it is as traceable as one on a results page, and a rerun that changes it fails here
/// until the text quoting it follows. The replay's summary writes ratios as `1.5x`: a quoted
/// `1.5×` matches it.
const ACCEPTED_SOURCES: &[(&str, &str)] = &[
    (
        "experiments/results/llvmpipe-2core/simd_width/summary.md",
        "scripts/simd_width.sh's table: the lockstep replay's predictions (deterministic, from \
         the CPU reference's paths) beside one llvmpipe render per method; the replay JSONs beside \
         it record the commit",
    ),
    (
        "experiments/results/llvmpipe-2core/simd_width/spheres-8-brute-every16.txt",
        "scripts/simd_width.sh's whole `wavetrace replay --every 16` output (deterministic)",
    ),
    (
        "experiments/results/llvmpipe-2core/state_traffic/comparison.md",
        "scripts/traffic_compare.py's table of two committed report.json files (before/ and \
         after/ beside it), each run's modelled path-state bytes from its queue counts; the \
         builds named in the file",
    ),
    (
        "experiments/results/llvmpipe-2core/state_traffic/comparison_inline.md",
        "scripts/traffic_compare.py's table of two committed report.json files (before/ and \
         inline/ beside it: the untrimmed state, and shadow rays traced in shade)",
    ),
    (
        "experiments/results/llvmpipe-2core/state_traffic/comparison_refill.md",
        "scripts/traffic_compare.py's table of two committed report.json files (refill_pass/ and \
         refill_in_place/ beside it: the refill pass, and samples started where paths end)",
    ),
    (
        "experiments/results/llvmpipe-2core/refill_in_place/interleave.txt",
        "scripts/interleave.py's summary tables (commands and builds in the file): this session's \
         build against its start, and --refill in-place against the refill pass",
    ),
    (
        "experiments/results/llvmpipe-2core/python_vs_cli/interleave.txt",
        "scripts/interleave.py's summary tables (commands and build in the file): the Python \
         package's render (scripts/python_render.py) against the binary's on the same job",
    ),
    (
        "experiments/results/llvmpipe-2core/python_vs_cli/test_cost.txt",
        "what the Python package adds to scripts/test.sh, timed: the venv's packages, the \
         extension's build after the main build, the Python tests (commands, build, load in the file)",
    ),
    (
        "experiments/results/llvmpipe-2core/decomposition_320x180/intersect_cost.txt",
        "`wavetrace intersect-cost`'s printed tables for rtiow-final and mesh-room at 320x180x16 \
         (the JSON files beside it hold the same figures)",
    ),
    (
        "experiments/results/llvmpipe-2core/decomposition_320x180/bandwidth.txt",
        "`wavetrace bandwidth --mib 64`'s printed table (bandwidth.json beside it)",
    ),
    (
        "experiments/results/llvmpipe-2core/own_scene/time.txt",
        "the README's own-scene commands timed by scripts/own_scene_time.sh: the commands, the \
         build, the machine and its load in the file",
    ),
    (
        "experiments/results/llvmpipe-2core/build_time/fresh_machine.txt",
        "the README's two commands timed on a fresh checkout with an empty cargo cache: the \
         commands, the build and the machine in the file",
    ),
    (
        "experiments/results/llvmpipe-2core/launch_shade/interleave.txt",
        "scripts/interleave.py's summary tables: two builds, and the launch and shade knobs, \
         each command and build in the file",
    ),
    (
        "experiments/results/llvmpipe-2core/build_time/profile_ab.txt",
        "scripts/interleave.py's summary tables: the release profile with and without thin LTO \
         and one codegen unit, each command and build in the file",
    ),
    (
        "experiments/results/nvidia-h200/dispatch_cost/table.txt",
        "the table `wavetrace dispatch-cost` printed in the device step dispatch-cost (its JSON, \
         dispatch_cost.json beside it, records the build and adapter)",
    ),
    (
        "experiments/results/nvidia-h200/simd_replay/comparison.md",
        "scripts/simd_replay_compare.py's table of the device step simd-replay (replay.json \
         beside it): the H200's counters beside the replay at 32 lanes, per slot",
    ),
];

/// The pages `unit` links that figures may be quoted from: generated results pages and
/// [`ACCEPTED_SOURCES`], as (path relative to the root, text).
fn linked_sources(doc: &str, unit: &str) -> Vec<(String, String)> {
    let dir = Path::new(doc).parent().unwrap_or(Path::new(""));
    unit.split("](")
        .skip(1)
        .filter_map(|s| s.split(')').next())
        .map(|link| resolve(dir, link).to_string_lossy().into_owned())
        .filter(|p| is_results_page(p) || ACCEPTED_SOURCES.iter().any(|(a, _)| a == p))
        .map(|p| (p.clone(), read(&p)))
        .collect()
}

/// Each of `figs` (found in `unit`) is on a results page or accepted source the unit links: a
/// regenerated page that changes a figure fails here until the text quoting it follows.
/// Returns what is not.
fn unquoted(doc: &str, unit: &str, figs: Vec<String>) -> Option<String> {
    if figs.is_empty() {
        return None;
    }
    let sources = linked_sources(doc, unit);
    let quoted = |f: &String| {
        sources.iter().any(|(path, text)| {
            on_page(f, text) || (!is_results_page(path) && on_page(&f.replace('×', "x"), text))
        })
    };
    let missing: Vec<String> = figs.into_iter().filter(|f| !quoted(f)).collect();
    (!missing.is_empty()).then(|| {
        let why = if sources.is_empty() { "links no results page" } else { "not on the pages it links" };
        format!("{doc}: {missing:?} {why}:\n{unit}\n")
    })
}

/// The README's findings are quoted from generated pages: each figure in a bullet appears on a
/// page the bullet links, so a regenerated page that changes them fails here.
#[test]
fn readme_findings_quote_the_pages_they_link() {
    let readme = read("README.md");
    let start = readme.find("## What it has found so far").expect("the findings section");
    let section = &readme[start..readme[start + 3..].find("\n## ").map_or(readme.len(), |e| start + 3 + e)];
    let bullets: Vec<&str> = section.split("\n- ").skip(1).collect();
    assert_eq!(bullets.len(), 9, "nine findings");
    for b in bullets {
        assert!(!linked_results_pages("README.md", b).is_empty(), "a finding without a results page: {b}");
        assert!(!figures(b).is_empty(), "a finding without a figure: {b}");
        let flagged: Vec<String> = figures(b).into_iter().filter(|f| f.ends_with('⚠')).collect();
        assert!(
            flagged.is_empty(),
            "a finding rests on a flagged run (unstable or cold): {flagged:?} in {b}"
        );
        if let Some(e) = unquoted("README.md", b, figures(b)) {
            panic!("{e}");
        }
    }
}

/// A page's units of text, each checked on its own: a paragraph, a list item, or a table with
/// the paragraph above it (its caption, which carries the links). Headings and code are left
/// out (docs/numerics.md's commands are run, their figures checked, by doc_commands.rs).
fn units(text: &str) -> Vec<String> {
    let mut blocks: Vec<Vec<&str>> = vec![Vec::new()];
    let mut fenced = false;
    for line in text.lines() {
        if line.starts_with("```") {
            fenced = !fenced;
            blocks.push(Vec::new());
        } else if fenced || line.trim().is_empty() || line.starts_with('#') {
            blocks.push(Vec::new());
        } else {
            blocks.last_mut().unwrap().push(line);
        }
    }
    let mut out = Vec::new();
    let mut caption = String::new();
    for b in blocks.into_iter().filter(|b| !b.is_empty()) {
        if b[0].starts_with('|') {
            out.push(format!("{caption}\n{}", b.join("\n")));
            continue;
        }
        let mut items: Vec<String> = Vec::new();
        for line in &b {
            match items.last_mut() {
                Some(item) if !line.starts_with("- ") => {
                    item.push('\n');
                    item.push_str(line);
                }
                _ => items.push(line.to_string()),
            }
        }
        out.extend(items);
        caption = b.join("\n");
    }
    out
}

/// Paragraphs the check below skips, each with the reason; an entry that no longer matches a
/// paragraph fails the test, so the list only shrinks.
const NOT_YET_QUOTED: &[(&str, &str, &str)] = &[];

/// Numbers the tokenizer takes for figures that are not measurements, per unit (page, how the
/// unit starts, the tokens, why): citation years, product and seed names, settings of a config.
/// Only the listed tokens are let through (each must still be in the unit); any other figure in
/// the same unit is checked. Constants of the code are written as inline code instead, which
/// the tokenizer skips.
type NotMeasured = (&'static str, &'static str, &'static [&'static str], &'static str);
const NOT_MEASURED: &[NotMeasured] = &[
    ("docs/architecture-and-file-map.md", "- **Sampling**", &["2020"], "a citation's year"),
    ("docs/methods.md", "**Regeneration** (Laine", &["2010"], "a citation's year"),
    ("docs/outputs.md", "`\"schema\": \"wavetrace-experiment-report/1\"`", &["3339"], "the name of RFC 3339"),
    ("docs/outputs.md", "Tidy tables of `report.json`", &["4180"], "the name of RFC 4180"),
    ("docs/testing-and-correctness.md", "- `tests/suite/tidy.rs`", &["4180"], "the name of RFC 4180"),
    ("docs/methods.md", "A wavefront that beats the seeds'", &["2009", "2010"], "citation years"),
    (
        "docs/methods.md",
        "*Predictions* from",
        &["002"],
        "the name of seed 002, whose setting the last row takes",
    ),
    (
        "docs/methods.md",
        "At 32 lanes the naive megakernel",
        &["002", "1070", "49.64%"],
        "names: seed 002 and the GTX 1070 it was profiled on; the seed report's own nvprof figure (a citation)",
    ),
    (
        "docs/cli-and-configs.md",
        "`experiments/` holds the configs",
        &["104", "324", "135", "100", "500", "512", "256", "135", "1024", "176", "756", "1024", "536", "108"],
        "each config's settings (spp, thread counts) and the runs it plans (what `--list` prints)",
    ),
];

/// The [`NOT_MEASURED`] entries for `unit` on page `doc`: those whose start it starts with
/// and whose every token it holds (a table's unit starts with its caption, as the caption does).
fn not_measured(doc: &str, unit: &str) -> Vec<&'static NotMeasured> {
    let figs = quoted_figures(unit);
    NOT_MEASURED
        .iter()
        .filter(|(d, start, tokens, _)| {
            *d == doc && unit.starts_with(start) && tokens.iter().all(|t| figs.iter().any(|f| f == t))
        })
        .collect()
}

/// The figures of `unit` (on page `doc`) the check below asks a source for: [`quoted_figures`]
/// less the tokens of the unit's [`NOT_MEASURED`] entries.
fn measured_figures(doc: &str, unit: &str) -> Vec<String> {
    let mut figs = quoted_figures(unit);
    for (_, _, tokens, _) in not_measured(doc, unit) {
        for t in *tokens {
            let i = figs.iter().position(|f| f == t).unwrap();
            figs.remove(i);
        }
    }
    figs
}

/// The pages of notes the check below reads: README.md and every Markdown page under docs/,
/// except the generated results pages themselves (`docs/results/<device>/<name>.md`, which are
/// the sources; each device's README there is notes and is read).
fn notes() -> Vec<String> {
    fn walk(root: &Path, rel: &str, out: &mut Vec<String>) {
        for e in std::fs::read_dir(root.join(rel)).unwrap().flatten() {
            let name = format!("{rel}/{}", e.file_name().to_string_lossy());
            if e.path().is_dir() {
                walk(root, &name, out);
            } else if name.ends_with(".md") {
                out.push(name);
            }
        }
    }
    let root = crate::common::root();
    let mut out = vec!["README.md".to_string()];
    walk(&root, "docs", &mut out);
    out.retain(|d| !is_results_page(d));
    out.sort();
    out
}

/// Whether `doc` (relative to the root) is a generated results page.
fn is_results_page(doc: &str) -> bool {
    doc.starts_with("docs/results/") && doc.ends_with(".md") && !doc.ends_with("/README.md")
}

/// No hand-typed figures in the notes: every figure in README.md and in each page under docs/
/// (see [`notes`]) is on a generated page, or an accepted source, that the paragraph (list
/// item, table caption) links.
#[test]
fn the_notes_quote_the_pages_they_link() {
    let docs = notes();
    for want in ["README.md", "docs/numerics.md", "docs/methods.md", "docs/results/llvmpipe-2core/README.md"]
    {
        assert!(docs.iter().any(|d| d == want), "{want} is not read: {docs:?}");
    }
    assert!(!docs.iter().any(|d| d == "docs/results/llvmpipe-2core/quick.md"), "{docs:?}");
    let mut errors = Vec::new();
    let mut skipped = Vec::new();
    let mut allowed = Vec::new();
    for doc in &docs {
        for unit in units(&read(doc)) {
            if let Some(s) = NOT_YET_QUOTED.iter().find(|(d, start, _)| d == doc && unit.starts_with(start)) {
                skipped.push(s.1);
                continue;
            }
            allowed.extend(not_measured(doc, &unit).into_iter().map(|e| e.1));
            errors.extend(unquoted(doc, &unit, measured_figures(doc, &unit)));
        }
    }
    for (doc, start, why) in NOT_YET_QUOTED {
        assert!(
            skipped.contains(start),
            "{doc}: no paragraph starts with {start:?} any more ({why}): drop it"
        );
    }
    for (doc, start, _, why) in NOT_MEASURED {
        assert!(
            allowed.contains(start),
            "{doc}: no unit starts with {start:?} and holds its tokens ({why}): fix it"
        );
    }
    assert!(errors.is_empty(), "figures not quoted from a linked results page:\n{}", errors.join("\n"));
}

/// Each accepted source is committed, lies in a device's results directory, and that
/// directory's row in the device's PROVENANCE.md names the script and the build.
#[test]
fn accepted_sources_record_their_provenance() {
    for (path, why) in ACCEPTED_SOURCES {
        assert!(!read(path).is_empty(), "{path}: empty");
        let rest = path.strip_prefix("experiments/results/").unwrap_or_else(|| panic!("{path} ({why})"));
        let mut parts = rest.split('/');
        let (device, dir) = (parts.next().unwrap(), parts.next().unwrap());
        let provenance = read(&format!("experiments/results/{device}/PROVENANCE.md"));
        let row = provenance
            .lines()
            .find(|l| l.starts_with(&format!("| `{dir}/` |")))
            .unwrap_or_else(|| panic!("{path}: no row for `{dir}/` in {device}'s PROVENANCE.md"));
        assert!(row.contains("scripts/") && row.contains("build of"), "{path}: {row}");
    }
}

/// The check fails on a hand-typed figure: one on no page, on a page the unit does not link,
/// or in a unit that links none; it passes on a figure the linked page or accepted source holds.
#[test]
fn a_hand_typed_figure_fails_the_check() {
    let quick = read("docs/results/llvmpipe-2core/quick.md");
    let figure = quoted_figures(&quick).into_iter().find(|f| f.ends_with('×')).expect("a ratio on quick.md");
    let link = "([quick](results/llvmpipe-2core/quick.md))";
    let check = |unit: &str| unquoted("docs/methods.md", unit, measured_figures("docs/methods.md", unit));
    assert_eq!(check(&format!("It ran at {figure} {link}.")), None);
    assert!(check(&format!("It ran at 0.123456× {link}.")).is_some_and(|e| e.contains("not on the pages")));
    let other = "([pool](results/llvmpipe-2core/pool_memory_640x360.md))";
    assert!(check(&format!("It ran at {figure} {other}, and −9.8765% {link}.")).is_some());
    assert!(check(&format!("It ran at {figure}.")).is_some_and(|e| e.contains("links no results page")));
    // A device's README of results is notes, not a source; a figure in inline code is not checked.
    assert!(check(&format!("It ran at {figure} ([notes](results/llvmpipe-2core/README.md)).")).is_some());
    assert_eq!(check(&format!("It ran at `{figure}`.")), None);
    // An accepted source: its `2.13x` is quoted as `2.13×`; not linked, it is no source.
    let summary = "([summary](../experiments/results/llvmpipe-2core/simd_width/summary.md))";
    assert_eq!(check(&format!("Predicted 2.13× and 21.33% {summary}.")), None);
    assert!(check(&format!("Predicted 2.13× and 21.34% {summary}.")).is_some());
    assert!(check("Predicted 2.13× and 21.33%.").is_some());
    // A NOT_MEASURED entry lets its own tokens through, in its own unit only.
    let unit = "A wavefront that beats the seeds' megakernel (Aila & Laine 2009; 2010) took 0.4321 s.";
    assert_eq!(measured_figures("docs/methods.md", unit), ["0.4321"]);
    assert_eq!(measured_figures("docs/numerics.md", unit), ["2009", "2010", "0.4321"]);
}

/// A figure that only a flagged run gives (unstable repetitions or no warm-up: written `…⚠` on
/// its page) cannot be quoted, though it is on the page.
#[test]
fn a_figure_from_a_flagged_run_fails_the_check() {
    let page = read("docs/results/nvidia-h200/regeneration.md");
    let flagged: Vec<&str> = page
        .split(|c: char| c.is_whitespace() || "|[]".contains(c))
        .filter_map(|w| w.strip_suffix('⚠'))
        .filter(|f| f.trim_end_matches('×').parse::<f64>().is_ok() && f.contains('.'))
        .filter(|f| !on_page(f, &page))
        .collect();
    assert!(!flagged.is_empty(), "regeneration ran without warm-up: its times are flagged");
    let link = "([regeneration](results/nvidia-h200/regeneration.md))";
    let check = |unit: &str| unquoted("docs/methods.md", unit, measured_figures("docs/methods.md", unit));
    let unit = format!("It took {} s {link}.", flagged[0]);
    assert!(check(&unit).is_some_and(|e| e.contains("not on the pages")), "{unit}");
    // The same page's counts (dispatches) are not timings and stay quotable.
    let steady = quoted_figures(&page).into_iter().find(|f| on_page(f, &page)).expect("a steady figure");
    assert_eq!(check(&format!("It took {steady} {link}.")), None);
}

/// The tokenizer catches what a hand-typed figure looks like and leaves settings alone.
#[test]
fn quoted_figures_are_told_from_settings() {
    let text = "took 0.4890 s (1.12×, 2× less; 55.7% busy, 6947 self-hits, 0.89–1.10×) at scale 1e-3, \
                16 spp, `d3800bd` and `--tail-threshold 0.05`, 2.762e-2 **2.450e-5**, −1.5% to +3%.";
    assert_eq!(
        quoted_figures(text),
        ["0.4890", "1.12×", "2×", "55.7%", "6947", "0.89", "1.10×", "2.762e-2", "2.450e-5", "1.5%", "3%"]
    );
    assert!(on_page("1.12×", "| 1.12× |") && !on_page("1.1", "| 1.12× |") && !on_page("12", "0.12"));
    assert!(on_page("100.0%", "lambertian 100.0%,") && !on_page("100", "lambertian 100.0%,"));
}

/// docs/cli-and-configs.md names every long option of every subcommand, and every option it
/// names exists (or is one of sbatch's, in the Slurm section).
#[test]
fn the_cli_page_matches_the_clap_definitions() {
    use clap::CommandFactory;
    let page = read("docs/cli-and-configs.md");
    let mut all = std::collections::BTreeSet::new();
    let mut missing = Vec::new();
    fn walk(
        c: &clap::Command,
        path: String,
        all: &mut std::collections::BTreeSet<String>,
        missing: &mut Vec<String>,
        page: &str,
    ) {
        for a in c.get_arguments() {
            if let Some(long) = a.get_long() {
                let flag = format!("--{long}");
                if !page.contains(&format!("`{flag}")) && !page.contains(&format!(" {flag}")) {
                    missing.push(format!("{path}: {flag}"));
                }
                all.insert(flag);
            }
        }
        for s in c.get_subcommands() {
            walk(s, format!("{path} {}", s.get_name()), all, missing, page);
        }
    }
    walk(&wavetrace::cli::Cli::command(), "wavetrace".into(), &mut all, &mut missing, &page);
    assert!(missing.is_empty(), "options not in docs/cli-and-configs.md:\n{}", missing.join("\n"));
    // sbatch's options (the Slurm section) and cargo's (building the binary).
    let sbatch = [
        "--array",
        "--requeue",
        "--open-mode",
        "--dependency",
        "--partition",
        "--gres",
        "--parsable",
        "--release",
        "--bench",
        "--locked",
    ];
    let mut unknown = Vec::new();
    for (i, _) in page.match_indices("--") {
        let name: String =
            page[i + 2..].chars().take_while(|c| c.is_ascii_lowercase() || *c == '-').collect();
        let flag = format!("--{name}");
        if name.len() > 1 && !all.contains(&flag) && !sbatch.contains(&flag.as_str()) && flag != "--help" {
            unknown.push(flag);
        }
    }
    unknown.sort();
    unknown.dedup();
    assert!(unknown.is_empty(), "docs/cli-and-configs.md names options that do not exist: {unknown:?}");
}

/// Every environment variable the code and scripts read is in the page's table.
#[test]
fn every_environment_variable_read_is_documented() {
    let root = crate::common::root();
    let page = read("docs/cli-and-configs.md");
    let mut names = std::collections::BTreeSet::new();
    let mut stack: Vec<PathBuf> =
        ["src", "scripts", "tests", "benches", "build.rs"].iter().map(|d| root.join(d)).collect();
    while let Some(p) = stack.pop() {
        if p.is_dir() {
            stack.extend(std::fs::read_dir(&p).unwrap().flatten().map(|e| e.path()));
            continue;
        }
        let Ok(text) = std::fs::read_to_string(&p) else { continue };
        for prefix in ["WAVETRACE_", "WGPU_"] {
            for (i, _) in text.match_indices(prefix) {
                let name: String =
                    text[i..].chars().take_while(|c| c.is_ascii_uppercase() || *c == '_').collect();
                if name.len() > prefix.len() && !name.ends_with('_') {
                    names.insert(name);
                }
            }
        }
    }
    let missing: Vec<&String> = names.iter().filter(|n| !page.contains(&format!("`{n}`"))).collect();
    assert!(missing.is_empty(), "environment variables not in docs/cli-and-configs.md: {missing:?}");
}

/// The README's "compare the methods on your own scene" commands run, at a tiny size: the export,
/// the committed example config (shrunk), and the Markdown table that says which was faster.
#[test]
fn the_readme_own_scene_commands_run() {
    let root = crate::common::root();
    let readme = read("README.md");
    let start = readme.find("## Compare the methods on your own scene").unwrap();
    let block = &readme[start..];
    let block = &block[block.find("```sh\n").unwrap() + 6..];
    let block = &block[..block.find("```").unwrap()];
    let commands: Vec<&str> = block.lines().map(|l| l.split(" #").next().unwrap().trim()).collect();
    assert_eq!(commands.len(), 3, "three commands: {commands:?}");
    assert!(commands[0].starts_with("wavetrace scene export ") && commands[0].contains(" > "));
    assert!(commands[1].starts_with("wavetrace experiment run experiments/my_scene.json"));
    assert!(commands[2].starts_with("wavetrace experiment report ") && commands[2].ends_with("--markdown"));

    let dir = crate::common::tmp().join("docs-own-scene");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("experiments/scenes")).unwrap();
    let sh = |cmd: &str| {
        let bin_dir = crate::common::bin().parent().unwrap().to_path_buf();
        let path = format!("{}:{}", bin_dir.display(), std::env::var("PATH").unwrap_or_default());
        let o = std::process::Command::new("bash")
            .arg("-c")
            .arg(cmd)
            .current_dir(&dir)
            .env("PATH", path)
            .output()
            .unwrap();
        assert!(o.status.success(), "{cmd}: {}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    // 1. As written (where `wavetrace` is the binary the tests built).
    sh(&commands[0].replacen("wavetrace", &crate::common::bin().display().to_string(), 1));
    // 2. The committed config and scene, shrunk to seconds: same methods, tiny job.
    let mut config: serde_json::Value = serde_json::from_str(&read("experiments/my_scene.json")).unwrap();
    std::fs::copy(
        root.join("experiments/scenes/my_scene.json"),
        dir.join("experiments/scenes/my_scene.json"),
    )
    .unwrap();
    config["resolutions"] = serde_json::json!(["24x16"]);
    config["spp"] = serde_json::json!([2]);
    config["repetitions"] = serde_json::json!(1);
    config["warmup"] = serde_json::json!(0);
    config["reference"]["spp"] = serde_json::json!(8);
    std::fs::write(dir.join("experiments/my_scene.json"), config.to_string()).unwrap();
    sh(&commands[1].replacen("wavetrace", &crate::common::bin().display().to_string(), 1));
    // 3. The page: one row per method variant, each with its speed-up over the fastest megakernel.
    let page = sh(&commands[2].replacen("wavetrace", &crate::common::bin().display().to_string(), 1));
    let table = &page[page.find("## Time and error").unwrap()..];
    let table = &table[..table[3..].find("\n## ").map_or(table.len(), |e| e + 3)];
    let rows: Vec<&str> = table.lines().filter(|l| l.contains("24×16×2")).collect();
    let methods = config["methods"].as_array().unwrap().len();
    assert_eq!(rows.len(), methods, "{page}");
    assert!(rows.iter().all(|r| r.contains('×') && r.ends_with("| ok |")), "{page}");
    assert!(rows.iter().any(|r| r.contains("| 1.00×")), "the fastest megakernel is the unit: {page}");
}

/// docs/outputs.md names every column runs.csv has, as the writer writes it for a committed
/// report of every method (`x_median|min|max` and `x_before|after` stand for several columns):
/// a column added to the writer fails here until the page says what it holds.
#[test]
fn every_runs_csv_column_is_documented() {
    let root = crate::common::root();
    let dir = crate::common::tmp().join("docs-runs-csv");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let report = root.join("experiments/results/llvmpipe-2core/quick/report.json");
    std::fs::copy(&report, dir.join("report.json")).unwrap();
    let o = std::process::Command::new(crate::common::bin())
        .args(["experiment", "report"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(dir.join("runs.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    assert!(header.contains(&"append") && header.contains(&"waits"), "{header:?}");
    let doc = read("docs/outputs.md");
    let documented = |c: &str| {
        doc.contains(&format!("`{c}`"))
            || ["_median", "_min", "_max"].iter().any(|s| {
                c.strip_suffix(s).is_some_and(|stem| doc.contains(&format!("`{stem}_median|min|max`")))
            })
            || ["_before", "_after"].iter().any(|s| {
                c.strip_suffix(s).is_some_and(|stem| doc.contains(&format!("`{stem}_before|after`")))
            })
    };
    let missing: Vec<&&str> = header.iter().filter(|c| !documented(c)).collect();
    assert!(missing.is_empty(), "runs.csv columns docs/outputs.md does not name: {missing:?}");
}

/// CI runs the README's test command.
#[test]
fn ci_runs_the_readmes_test_command() {
    let readme = read("README.md");
    assert!(readme.contains("./scripts/test.sh     # the test suite"));
    assert!(read(".ci/run").lines().any(|l| l.trim() == "bash scripts/test.sh"));
    // And checks the main job's report in a browser, after the test command (outside its budget).
    let ci = read(".ci/run");
    let line = |l: &str| ci.lines().position(|x| x.trim() == l);
    assert!(line("bash scripts/report_check.sh") > line("bash scripts/test.sh"), "{ci}");
    assert!(!read("scripts/test.sh").contains("report_check"), "outside the test command");
}

/// docs/cli-and-configs.md's table of the configs in `experiments/` gives each one's run count:
/// it is the count the config plans (what `experiment run --list` prints), and every shipped
/// config is in the table.
#[test]
fn the_config_table_counts_the_runs_each_config_plans() {
    let root = crate::common::root();
    let page = read("docs/cli-and-configs.md");
    let mut listed = Vec::new();
    let mut wrong = Vec::new();
    for line in page.lines().filter(|l| l.starts_with("| `") && l.contains(".json` |")) {
        let cells: Vec<&str> = line.trim_matches('|').split(" | ").map(str::trim).collect();
        let name = cells[0].trim_matches('`');
        let Some(runs) = cells.last().and_then(|c| c.trim_end_matches(" |").parse::<usize>().ok()) else {
            continue;
        };
        let config = wavetrace::experiment::ExperimentConfig::from_file(&root.join("experiments").join(name))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let planned = wavetrace::experiment::plan::plan(&config).len();
        if planned != runs {
            wrong.push(format!("{name}: the table says {runs} runs, the config plans {planned}"));
        }
        listed.push(name.to_string());
    }
    let mut missing = Vec::new();
    for e in std::fs::read_dir(root.join("experiments")).unwrap().flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name.ends_with(".json") && name != "report.schema.json" && !listed.contains(&name) {
            missing.push(name);
        }
    }
    assert!(wrong.is_empty() && missing.is_empty(), "{}\nnot in the table: {missing:?}", wrong.join("\n"));
}

/// A transcript line's shape: every number (and the `x` between image sizes) as `#`, a size in
/// B, KiB, MiB or GiB as `# bytes`, runs of spaces as one, and the output path dropped, so a
/// transcript from a large render matches a tiny one line for line while any change of wording,
/// field or order does not.
fn line_shape(line: &str) -> String {
    let line = line.split(" -> ").next().unwrap();
    let mut out = String::new();
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        if c.is_ascii_digit() {
            while chars.peek().is_some_and(|d| d.is_ascii_digit() || *d == '.') {
                chars.next();
            }
            out.push('#');
            let rest: String = chars.clone().take(5).collect();
            if let Some(unit) = [" B", " KiB", " MiB", " GiB"]
                .into_iter()
                .find(|u| rest.starts_with(u) && !rest[u.len()..].starts_with(char::is_alphabetic))
            {
                out.push_str(" bytes");
                chars.nth(unit.len() - 1);
            }
            // "1200x675": both sizes are numbers.
            if chars.peek() == Some(&'x') {
                out.push('x');
                chars.next();
            }
        } else if c == ' ' {
            if !out.ends_with(' ') {
                out.push(' ');
            }
        } else {
            out.push(c);
        }
    }
    out.trim_end().to_string()
}

/// docs/outputs.md opens with what `wavetrace render` prints: the same command, shrunk to a tiny
/// image, must print every line of that transcript in the same shape (the words, the fields and
/// their order, the pass table's rows), so a changed output fails here until the page shows it.
#[test]
fn the_render_transcript_in_outputs_matches_the_binary() {
    let Some(_gpu) = crate::common::gpu() else { return };
    let page = read("docs/outputs.md");
    let block = &page[page.find("```\n$ ").expect("a transcript block") + 4..];
    let block = &block[..block.find("```").unwrap()];
    let mut lines = block.lines();
    let command = lines.next().unwrap().strip_prefix("$ wavetrace ").expect("a wavetrace command");
    let transcript: Vec<&str> = lines.filter(|l| l.trim() != "...").collect();
    // The same arguments at 48×27 and 2 spp.
    let mut args: Vec<String> = command.split_whitespace().map(String::from).collect();
    for (flag, value) in [("--width", "48"), ("--height", "27"), ("--spp", "2")] {
        let i = args.iter().position(|a| a == flag).unwrap_or_else(|| panic!("the transcript sets {flag}"));
        args[i + 1] = value.into();
    }
    let dir = crate::common::tmp().join("docs-transcript");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let out =
        std::process::Command::new(crate::common::bin()).args(&args).current_dir(&dir).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let printed = String::from_utf8_lossy(&out.stdout);
    let shapes: Vec<String> = printed.lines().map(line_shape).collect();
    for line in transcript {
        assert!(
            shapes.contains(&line_shape(line)),
            "docs/outputs.md shows a line the binary no longer prints:\n  {line}\nshape {:?}; printed:\n{printed}",
            line_shape(line)
        );
    }
}

/// A generated page links docs/methods.md relative to where it is written, and names it without
/// a link where no docs/ is above the page (stdout, or a folder outside the repository): never
/// a link that leads nowhere.
#[test]
fn generated_links_to_the_docs_resolve_wherever_the_page_is() {
    let root = crate::common::root();
    let source = "experiments/results/llvmpipe-2core/dispatch_counts";
    let page = |out: Option<&Path>| {
        let mut c = std::process::Command::new(crate::common::bin());
        c.current_dir(&root).args(["experiment", "report", source, "--markdown"]);
        if let Some(out) = out {
            c.arg("--out").arg(out);
        }
        let o = c.output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        match out {
            Some(out) => std::fs::read_to_string(out).unwrap(),
            None => String::from_utf8_lossy(&o.stdout).into_owned(),
        }
    };
    let link = |md: &str| {
        md.split("](")
            .skip(1)
            .find(|l| l.contains("methods.md#"))
            .map(|l| l[..l.find(')').unwrap()].to_string())
    };
    assert_eq!(link(&page(None)), None, "stdout has no place to link from");
    assert!(page(None).contains("docs/methods.md"));
    let outside = std::env::temp_dir().join(format!("wavetrace-docs-link-{}", std::process::id()));
    let md = page(Some(&outside.join("page.md")));
    let _ = std::fs::remove_dir_all(&outside);
    assert_eq!(link(&md), None, "no docs/ above {}", outside.display());
    let inside = crate::common::tmp().join("docs-link/deeper/page.md");
    let md = page(Some(&inside));
    let target = link(&md).expect("a link from inside the repository");
    let file = target.split('#').next().unwrap();
    assert!(
        inside.parent().unwrap().join(file).is_file(),
        "{target} does not resolve from {}",
        inside.display()
    );
}

/// The runs.csv paragraph of docs/outputs.md names the columns in the writer's order (the first
/// mention of each; `x_median|min|max` and `x_before|after` stand for their columns in order).
#[test]
fn runs_csv_columns_are_documented_in_the_writers_order() {
    let report =
        ExperimentReport::read(&crate::common::root().join("experiments/results/llvmpipe-2core/quick"))
            .unwrap();
    let csv = wavetrace::experiment::tidy::runs_csv(&report);
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let doc = read("docs/outputs.md");
    let start = doc.find("`runs.csv`, one row per run").expect("the runs.csv paragraph");
    let paragraph = &doc[start..start + doc[start..].find("`passes.csv`, one row").unwrap()];
    let mut named: Vec<String> = Vec::new();
    for (i, span) in paragraph.split('`').enumerate().filter(|(i, _)| i % 2 == 1) {
        let _ = i;
        let expanded: Vec<String> = match span.split_once('_').map(|_| span) {
            Some(s) if s.ends_with("_median|min|max") => {
                let stem = s.trim_end_matches("_median|min|max");
                ["median", "min", "max"].iter().map(|x| format!("{stem}_{x}")).collect()
            }
            Some(s) if s.ends_with("_before|after") => {
                let stem = s.trim_end_matches("_before|after");
                ["before", "after"].iter().map(|x| format!("{stem}_{x}")).collect()
            }
            _ => vec![span.to_string()],
        };
        for c in expanded {
            if header.contains(&c.as_str()) && !named.contains(&c) {
                named.push(c);
            }
        }
    }
    let header: Vec<String> = header.iter().map(|s| s.to_string()).collect();
    let first_wrong = named.iter().zip(&header).position(|(a, b)| a != b);
    assert!(
        named == header,
        "docs/outputs.md's runs.csv columns are not the writer's, from column {first_wrong:?}:\n doc: {:?}\n csv: {:?}",
        first_wrong.map(|i| &named[i..(i + 5).min(named.len())]),
        first_wrong.map(|i| &header[i..(i + 5).min(header.len())])
    );
}

/// docs/outputs.md lists every chart kind the code draws, in report.json's `charts[].kind` and
/// in the output directory's charts/*.svg.
#[test]
fn every_chart_kind_is_documented() {
    let doc = read("docs/outputs.md");
    let kinds_row = doc.lines().find(|l| l.starts_with("| `charts[]`")).expect("the charts[] row");
    let block = &doc[doc.find("charts/*.svg       ").unwrap()..doc.find("images/RUN.exr").unwrap()];
    for kind in wavetrace::experiment::charts::CHART_KINDS {
        assert!(kinds_row.contains(&format!("`{kind}`")), "charts[].kind does not list {kind}");
        assert!(block.contains(kind), "charts/*.svg does not name {kind}");
    }
}

/// Wherever an options table lists an option's values (`--queue-order
/// auto|arrival|slot|slot-depth`), they are all the values the binary takes, no more, no fewer.
#[test]
fn listed_option_values_are_the_binarys() {
    let cmd = wavetrace::cli::command();
    let mut values: std::collections::BTreeMap<String, Vec<String>> = Default::default();
    fn walk(c: &clap::Command, values: &mut std::collections::BTreeMap<String, Vec<String>>) {
        for a in c.get_arguments() {
            let v: Vec<String> = a.get_possible_values().iter().map(|v| v.get_name().to_string()).collect();
            if let (Some(long), false) = (a.get_long(), v.is_empty()) {
                values.insert(format!("--{long}"), v);
            }
        }
        c.get_subcommands().for_each(|s| walk(s, values));
    }
    walk(&cmd, &mut values);
    let mut checked = 0;
    let mut wrong = Vec::new();
    for file in [
        "README.md",
        "docs/methods.md",
        "docs/cli-and-configs.md",
        "docs/numerics.md",
        "docs/outputs.md",
        "docs/run-on-a-gpu.md",
    ] {
        // The options tables' first cells, where a list of values means all of them (prose may
        // name a few: `--method megakernel|wavefront`).
        let text = read(file).replace("\\|", "\u{1}");
        let cells = text
            .lines()
            .filter_map(|l| l.strip_prefix("| `")?.split('`').next())
            .map(|c| c.replace('\u{1}', "|"));
        for span in cells {
            let span = span.as_str();
            let Some((flag, list)) = span.split_once(' ') else { continue };
            let Some(all) = values.get(flag) else { continue };
            if !list.contains('|') || list.contains(' ') {
                continue;
            }
            checked += 1;
            let mut listed: Vec<&str> = list.split('|').collect();
            let mut want: Vec<&str> = all.iter().map(String::as_str).collect();
            listed.sort();
            want.sort();
            if listed != want {
                wrong.push(format!("{file}: `{span}`: the binary takes {}", all.join("|")));
            }
        }
    }
    assert!(checked >= 20, "only {checked} value lists found");
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// Every field report.json's schema (validated against real reports) defines is named in the
/// report.json section of docs/outputs.md.
#[test]
fn every_report_json_field_is_documented() {
    let schema: serde_json::Value = serde_json::from_str(&read("experiments/report.schema.json")).unwrap();
    let doc = read("docs/outputs.md");
    let section = &doc[doc.find("## report.json").unwrap()..doc.find("## runs.csv and passes.csv").unwrap()];
    let named: std::collections::BTreeSet<&str> = section
        .split('`')
        .skip(1)
        .step_by(2)
        .flat_map(|s| s.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_')))
        .collect();
    let mut missing = Vec::new();
    let mut objects = vec![("report".to_string(), &schema)];
    for (name, def) in schema["$defs"].as_object().unwrap() {
        objects.push((name.clone(), def));
    }
    for (object, def) in objects {
        for field in def["properties"].as_object().into_iter().flat_map(|p| p.keys()) {
            if !named.contains(field.as_str()) {
                missing.push(format!("{object}.{field}"));
            }
        }
    }
    assert!(missing.is_empty(), "report.json fields docs/outputs.md does not name: {missing:?}");
}

/// Every results page is in docs/SUMMARY.md (the mdBook's table of contents).
#[test]
fn every_results_page_is_in_the_summary() {
    let root = crate::common::root();
    let summary = read("docs/SUMMARY.md");
    let mut missing = Vec::new();
    for device in
        std::fs::read_dir(root.join("docs/results")).unwrap().flatten().filter(|d| d.path().is_dir())
    {
        for page in std::fs::read_dir(device.path()).unwrap().flatten() {
            let link = format!(
                "(results/{}/{})",
                device.file_name().to_string_lossy(),
                page.file_name().to_string_lossy()
            );
            if link.ends_with(".md)") && !summary.contains(&link) {
                missing.push(link);
            }
        }
    }
    assert!(missing.is_empty(), "results pages not in docs/SUMMARY.md: {missing:?}");
}

/// What `RUST_LOG=info` is documented to show (docs/cli-and-configs.md and `wavetrace --help`)
/// is what a level of info prints: each item has its line in a small render's log (the loop cap
/// on llvmpipe only) or an experiment's (a reference from the cache), and the docs name no item
/// without one.
#[test]
fn the_documented_info_log_lines_are_printed() {
    // Each item the docs may name, and the start of the line that shows it.
    let lines = [
        ("adapter choice", "adapter: "),
        ("warm-up", "warm-up: "),
        ("llvmpipe loop cap", "llvmpipe loop cap: "),
        ("references taken from the cache", ": from the cache "),
    ];
    let doc = read("docs/cli-and-configs.md");
    let row = doc.lines().find(|l| l.starts_with("| `RUST_LOG`")).unwrap();
    let items = |text: &str, from: &str, to: char| -> Vec<String> {
        let i = text.find(from).unwrap_or_else(|| panic!("{from:?} not in {text:?}")) + from.len();
        text[i..i + text[i..].find(to).unwrap()].split(", ").map(str::to_string).collect()
    };
    let help = String::from_utf8_lossy(
        &std::process::Command::new(crate::common::bin()).arg("--help").output().unwrap().stdout,
    )
    .into_owned();
    let help_line = help.lines().find(|l| l.trim_start().starts_with("RUST_LOG=")).unwrap().to_string();
    let documented = [items(row, "(`info`: ", ';'), items(&help_line, "(info: ", ')')].concat();
    for item in &documented {
        assert!(lines.iter().any(|(i, _)| i == item), "the docs name {item:?}, which no info line shows");
    }
    let dir = crate::common::tmp().join("docs-info-log");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let o = std::process::Command::new(crate::common::bin())
        .env("RUST_LOG", "info")
        .args([
            "render",
            "--scene",
            "three-spheres",
            "--method",
            "megakernel",
            "--schedule",
            "regenerate",
            "--width",
            "16",
            "--height",
            "8",
        ])
        .args(["--spp", "1", "--out"])
        .arg(dir.join("x.exr"))
        .output()
        .unwrap();
    let mut log = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{log}");
    let config = serde_json::json!({"schema": "wavetrace-experiment/1", "question": "log", "scenes": ["three-spheres"],
        "resolutions": ["8x4"], "spp": [1], "max_depth": [4], "repetitions": 1, "methods": [{"method": "cpu"}],
        "reference": {"method": "cpu", "spp": 2}});
    let config = crate::experiment::write_config(&dir, "log", &config);
    for _ in 0..2 {
        let o = std::process::Command::new(crate::common::bin())
            .env("RUST_LOG", "info")
            .args(["experiment", "run"])
            .arg(&config)
            .arg("--out")
            .arg(dir.join("out"))
            .arg("--cache")
            .arg(dir.join("cache"))
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        log.push_str(&String::from_utf8_lossy(&o.stderr));
    }
    let llvmpipe = log.lines().any(|l| l.contains("adapter: llvmpipe"));
    for item in documented {
        let (_, start) = lines.iter().find(|(i, _)| *i == item).unwrap();
        if item.contains("llvmpipe") && !llvmpipe {
            continue;
        }
        assert!(log.contains(start), "RUST_LOG=info shows no {item:?} line ({start:?}):\n{log}");
    }
}

/// The README reads as a first hour: under 200 lines, what it is before the two commands, the
/// two commands before the own-scene comparison, and that before the findings.
#[test]
fn the_readme_puts_the_first_hour_first() {
    let readme = read("README.md");
    assert!(readme.lines().count() < 200, "README.md has {} lines", readme.lines().count());
    let at = |h: &str| readme.find(h).unwrap_or_else(|| panic!("no {h:?}"));
    assert!(at("## Two commands") < at("## Compare the methods on your own scene"));
    assert!(at("## Compare the methods on your own scene") < at("## What it has found so far"));
    assert!(at("`wavetrace` is `target/release/wavetrace`") < at("## Compare the methods on your own scene"));
    assert!(readme.contains("](docs/images/report-first-screen.png)"), "the report's screenshot");
}
