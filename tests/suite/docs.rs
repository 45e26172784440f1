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

fn read(rel: &str) -> String {
    std::fs::read_to_string(crate::common::root().join(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// Tokens that read as measured figures: `1.36×`, `1.335e-2`.
fn figures(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for word in text.split(|c: char| c.is_whitespace() || "(),;".contains(c)) {
        let w = word.trim_end_matches(['.', ':']);
        let number = w.trim_end_matches('×');
        let is_ratio = w.ends_with('×') && number.parse::<f64>().is_ok() && number.contains('.');
        let is_sci = w.contains('e') && w.parse::<f64>().is_ok() && w.contains('.');
        if is_ratio || is_sci {
            out.push(w.to_string());
        }
    }
    out
}

/// The README's findings are quoted from generated pages: each figure in a bullet appears on a
/// page the bullet links, so a regenerated page that changes them fails here.
#[test]
fn readme_findings_quote_the_pages_they_link() {
    let readme = read("README.md");
    let start = readme.find("## What it has found so far").expect("the findings section");
    let section = &readme[start..readme[start + 3..].find("\n## ").map_or(readme.len(), |e| start + 3 + e)];
    let bullets: Vec<&str> = section.split("\n- ").skip(1).collect();
    assert_eq!(bullets.len(), 6, "six findings");
    for b in bullets {
        let pages: Vec<String> = b
            .split("](")
            .skip(1)
            .filter_map(|s| s.split(')').next())
            .filter(|l| l.starts_with("docs/results/"))
            .map(read)
            .collect();
        assert!(!pages.is_empty(), "a finding without a results page: {b}");
        let figs = figures(b);
        assert!(!figs.is_empty(), "a finding without a figure: {b}");
        for f in figs {
            assert!(
                pages.iter().any(|p| p.contains(&format!(" {f} "))),
                "{f} is on no page this finding links:\n{b}"
            );
        }
    }
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
    assert!(rows.iter().any(|r| r.contains("| 1.00× |")), "the fastest megakernel is the unit: {page}");
}

/// CI runs the README's test command.
#[test]
fn ci_runs_the_readmes_test_command() {
    let readme = read("README.md");
    assert!(readme.contains("./scripts/test.sh     # the test suite"));
    assert!(read(".ci/run").lines().any(|l| l.trim() == "bash scripts/test.sh"));
}
