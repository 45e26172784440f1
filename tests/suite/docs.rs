//! The documentation cannot go stale: every results page under docs/results/ is what
//! `wavetrace experiment report DIR --markdown` writes from the committed report, and every
//! committed report has its page.

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
        let report = ExperimentReport::read(&root.join(&source)).unwrap();
        let want = markdown::page(&report, &source, &format!("../../../{source}/"));
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
