//! Every command the documentation shows runs: each `wavetrace …` line of a fenced code block in
//! README.md and docs/**/*.md, and each example of every subcommand's `--help`, through the
//! built binary, at a tiny size. The commands of one code block, or of one `--help` text, run in
//! order in a fresh copy of the fixtures they name, as a reader trying that block would. Any other
//! command line in a shell block must be listed in [`NOT_RUN`] with the reason, so a new command
//! is either run or left out on purpose.
//!
//! Plain `std::process::Command` and `bash -c` rather than `trycmd`/`snapbox`: the commands'
//! output is timings and paths that change every run, so a snapshot would hold little beyond
//! "it ran"; what is checked is the exit status, the figures a comment states (asserted below)
//! and the shape of the one console transcript (docs/outputs.md), and the rewrites to a tiny
//! size are code either way. The commands come from the Markdown and from clap itself, so no
//! second copy of them is kept in `.toml`/`.trycmd` files, and no dev-dependency is added.
//!
//! Rewrites applied to each `wavetrace` command before it runs (nothing else is changed):
//! - `target/release/wavetrace` → `wavetrace`, which is the binary cargo built (on `PATH`);
//! - variables set by an earlier line of the same block (`S="…"`, docs/numerics.md) are
//!   substituted, so the sizes they hold are seen;
//! - `render`, `replay` and `intersect-cost`: `--width 24 --height 16 --spp 2`, replacing the command's own sizes
//!   or added where it has none, unless the command is a CPU render of at most 64×36×16
//!   samples (seconds): those run as written, so that the figures their comments state can be
//!   checked at the documented size;
//! - `--adapter NAME` → the first word of the adapter the suite opened (the examples name
//!   `nvidia`, `llvmpipe`);
//! - experiment configs: `experiments/*.json` are copied into the scratch tree shrunk as
//!   `docs::the_readme_own_scene_commands_run` does (one resolution of 24×16, 1 spp, one
//!   repetition, no warm-up, a reference of 4 spp), and `sweep.json`, which the examples name
//!   without shipping it, is a tiny CPU-only config of four runs;
//! - the environment: `WAVETRACE_CACHE` in the scratch directory (references rendered once),
//!   and the Slurm array variables of task 3 of 4 (the `$SLURM_ARRAY_TASK_ID` example);
//! - `bandwidth` and `dispatch-cost`: `--mib 4`, `--dispatches 50`, `--repetitions 2`.
//!
//! A command shown in several places runs once when the commands before it in its group are
//! the same too (so it meets the same files): the output is checked against each place.
//!
//! Fixtures: `test.exr`, `truth.exr`, `reference.exr`, `gpu.exr` (24×16 CPU renders),
//! `my_scene.json`, `experiments/scenes/`, shards 0–3 of `sweep.json` in `shards/`, and the
//! committed `quick` report as `out/quick` and at its committed path.
//!
//! A comment after a command that states a figure (`# relMSE 2.762e-2`) is checked against the
//! output, in docs only: the `--help` comments describe options (`--trim 0.001  # drop the top
//! 0.1%`), they do not report output.

use std::collections::BTreeSet;
use std::path::Path;

use crate::common;

/// Command lines the docs show that CI does not run, by their start, and why.
const NOT_RUN: &[(&str, &str)] = &[
    ("./scripts/main.sh", "a release build and the full main job, minutes; its config runs here shrunk"),
    ("./scripts/test.sh", "this suite itself, which CI's .ci/run runs"),
    ("cargo build", "builds the binary these tests already run"),
    ("cargo bench", "timing measurements, minutes each"),
    ("scripts/measure_core.sh", "timing measurements"),
    ("benches/mitsuba/compare.sh", "needs Mitsuba 3 installed, and times it"),
    ("scripts/device_prepare.sh", "the GPU device run's set-up: a release build and a download"),
    (
        "scripts/device_figures.sh",
        "the GPU device run, minutes of rendering; CI runs scripts/device_dry_run.sh",
    ),
    ("scripts/slurm/submit.sh", "needs Slurm's sbatch; tests/suite/slurm.rs runs the job scripts' bodies"),
    (
        "pip install .",
        "builds and installs the Python package; scripts/test.sh builds it with maturin develop",
    ),
    ("maturin develop", "what scripts/test.sh runs before the Python package's tests (python/tests)"),
];

/// `wavetrace` commands another test runs, with sharper checks than an exit status.
const RUN_ELSEWHERE: &[(&str, &str)] = &[
    (
        r#"wavetrace experiment run experiments/my_scene.json --set 'scenes=["scenes/mine.json"]' --out out/mine"#,
        "docs::the_readme_own_scene_commands_run",
    ),
    ("wavetrace experiment report out/mine --markdown", "docs::the_readme_own_scene_commands_run"),
];

/// One command as the docs show it.
#[derive(Clone, Debug)]
struct Shown {
    /// Where: `docs/numerics.md:44`, or `wavetrace experiment run --help`.
    source: String,
    /// Its code block, or its `--help` text: the commands of one group run in order, in one
    /// directory of their own.
    group: String,
    /// The command, continuation lines joined, without its comment.
    line: String,
    /// The trailing `# …` comment, if any.
    comment: String,
    /// Variable assignments (`S="…"`) earlier in the same block.
    assignments: Vec<String>,
    /// For a `$ ` line of a console transcript: the output lines shown after it.
    transcript: Vec<String>,
    /// Whether the comment may state output (docs; not `--help`).
    check_comment: bool,
}

/// `cmd  # comment` → (`cmd`, `comment`): a `#` after whitespace starts a comment.
fn split_comment(line: &str) -> (String, String) {
    match line.find(" #") {
        Some(i) => (line[..i].trim().to_string(), line[i + 2..].trim().to_string()),
        None => (line.trim().to_string(), String::new()),
    }
}

/// Lines with trailing `\` joined to the next, each with the indices of its first and last line.
fn joined(lines: &[&str]) -> Vec<(usize, usize, String)> {
    let mut out: Vec<(usize, usize, String)> = Vec::new();
    let mut open = false;
    for (i, l) in lines.iter().enumerate() {
        if open {
            let last = out.last_mut().unwrap();
            last.1 = i;
            last.2.push(' ');
            last.2.push_str(l.trim());
        } else {
            out.push((i, i, l.trim().to_string()));
        }
        let last = &mut out.last_mut().unwrap().2;
        open = last.ends_with('\\');
        if open {
            last.pop();
            *last = last.trim_end().to_string();
        }
    }
    out
}

/// A shell variable assignment alone on its line (`S="…"`).
fn is_assignment(line: &str) -> bool {
    let Some((name, _)) = line.split_once('=') else { return false };
    !name.is_empty()
        && name.chars().all(|c| c.is_ascii_uppercase() || c == '_')
        && !line.contains(" wavetrace")
}

/// The command lines of a Markdown page's fenced blocks: every line of a `sh`/`bash` block
/// (comments aside), and in an unlabelled or `console` block the `$ ` lines and their output.
fn markdown_commands(rel: &str, text: &str) -> Vec<Shown> {
    let mut out = Vec::new();
    let lines: Vec<&str> = text.lines().collect();
    let mut i = 0;
    while i < lines.len() {
        let Some(info) = lines[i].trim_start().strip_prefix("```") else {
            i += 1;
            continue;
        };
        let info = info.trim().to_string();
        let start = i + 1;
        let mut end = start;
        while end < lines.len() && !lines[end].trim_start().starts_with("```") {
            end += 1;
        }
        let body = &lines[start..end];
        i = end + 1;
        let shell = matches!(info.as_str(), "sh" | "bash" | "shell");
        if !shell && !matches!(info.as_str(), "" | "console") {
            continue;
        }
        let mut assignments = Vec::new();
        for (first, last, line) in joined(body) {
            let (prompted, line) = match line.strip_prefix("$ ") {
                Some(l) => (true, l.to_string()),
                None => (false, line),
            };
            let command = shell || prompted || line.starts_with("wavetrace ");
            if !command || line.is_empty() || line.starts_with('#') {
                continue;
            }
            let (cmd, comment) = split_comment(&line);
            if is_assignment(&cmd) {
                assignments.push(cmd);
                continue;
            }
            let transcript = if prompted {
                body[last + 1..].iter().take_while(|l| !l.starts_with("$ ")).map(|l| l.to_string()).collect()
            } else {
                Vec::new()
            };
            out.push(Shown {
                source: format!("{rel}:{}", start + first + 1),
                group: format!("{rel}:{start}"),
                line: cmd,
                comment,
                assignments: assignments.clone(),
                transcript,
                check_comment: true,
            });
        }
    }
    out
}

/// The examples in every (sub)command's `--help`: lines starting `wavetrace ` or `VAR=… wavetrace `.
fn help_commands() -> Vec<Shown> {
    use clap::CommandFactory;
    fn walk(c: &clap::Command, path: String, out: &mut Vec<Shown>) {
        if let Some(help) = c.get_after_help() {
            let text = help.to_string();
            let lines: Vec<&str> = text.lines().collect();
            for (_, _, line) in joined(&lines) {
                let program = line.split_whitespace().find(|w| !is_assignment(w));
                if program != Some("wavetrace") {
                    continue;
                }
                let (cmd, comment) = split_comment(&line);
                out.push(Shown {
                    source: format!("{path} --help"),
                    group: format!("{path} --help"),
                    line: cmd,
                    comment,
                    assignments: Vec::new(),
                    transcript: Vec::new(),
                    check_comment: false,
                });
            }
        }
        for s in c.get_subcommands() {
            walk(s, format!("{path} {}", s.get_name()), out);
        }
    }
    let mut out = Vec::new();
    walk(&wavetrace::cli::Cli::command(), "wavetrace".into(), &mut out);
    out
}

/// Every command the docs show, Markdown first (README.md, then docs/ in path order).
fn shown_commands() -> Vec<Shown> {
    let root = common::root();
    let mut pages = vec![root.join("README.md")];
    let mut stack = vec![root.join("docs")];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "md") {
                pages.push(p);
            }
        }
    }
    pages[1..].sort();
    let mut out = Vec::new();
    for p in pages {
        let rel = p.strip_prefix(&root).unwrap().to_string_lossy().into_owned();
        out.extend(markdown_commands(&rel, &std::fs::read_to_string(&p).unwrap()));
    }
    out.extend(help_commands());
    out
}

/// What happens to a shown command.
enum Plan {
    Run,
    Skip(&'static str),
}

/// Run it, skip it with a reason, or fail: a command nobody has decided about.
fn plan(c: &Shown) -> Result<Plan, String> {
    let words: Vec<&str> = c.line.split_whitespace().skip_while(|w| is_assignment(w)).collect();
    let program = words.first().copied().unwrap_or("");
    if program == "wavetrace" || program == "target/release/wavetrace" {
        let normalized = c.line.replacen("target/release/wavetrace", "wavetrace", 1);
        if let Some((_, why)) = RUN_ELSEWHERE.iter().find(|(cmd, _)| normalized == *cmd) {
            return Ok(Plan::Skip(why));
        }
        return Ok(Plan::Run);
    }
    match NOT_RUN.iter().find(|(start, _)| c.line.starts_with(start)) {
        Some((_, why)) => Ok(Plan::Skip(why)),
        None => Err(format!("{}: `{}` is neither run nor listed in NOT_RUN", c.source, c.line)),
    }
}

/// `$NAME` and `${NAME}` replaced by the values of `assignments` (`NAME="value"`).
fn substitute(line: &str, assignments: &[String]) -> String {
    let mut out = line.to_string();
    for a in assignments {
        let (name, value) = a.split_once('=').unwrap();
        let value = value.trim_matches('"').trim_matches('\'');
        out = out.replace(&format!("${{{name}}}"), value).replace(&format!("${name}"), value);
    }
    out
}

/// The value after `--flag` in `words`.
fn flag<'a>(words: &[&'a str], name: &str) -> Option<&'a str> {
    words.iter().position(|w| *w == name).and_then(|i| words.get(i + 1).copied())
}

/// `--name value` in `words`: the value replaced, or the flag added before any redirection
/// (`> file`), which ends the arguments.
fn set_flag(words: &mut Vec<String>, name: &str, value: &str) {
    match words.iter().position(|x| x == name) {
        Some(i) => words[i + 1] = value.to_string(),
        None => {
            let end = words.iter().position(|x| x.starts_with('>')).unwrap_or(words.len());
            words.insert(end, value.to_string());
            words.insert(end, name.to_string());
        }
    }
}

/// The command as it runs here (see the module comment for the rewrites).
fn rewrite(line: &str, adapter: &str) -> String {
    let line = line.replacen("target/release/wavetrace", "wavetrace", 1);
    let mut words: Vec<String> = line.split_whitespace().map(str::to_string).collect();
    let at = words.iter().position(|w| w == "wavetrace").unwrap();
    let sub = words.get(at + 1).cloned().unwrap_or_default();
    if let Some(i) = words.iter().position(|w| w == "--adapter") {
        words[i + 1] = adapter.to_string();
    }
    if sub == "render" || sub == "replay" || sub == "intersect-cost" {
        let w: Vec<&str> = words.iter().map(String::as_str).collect();
        let (defaults, method) = match sub.as_str() {
            "render" => ((400, 225, 16), "megakernel"),
            "replay" => ((160, 90, 16), ""),
            _ => ((1920, 1080, 64), ""),
        };
        let size = |name: &str, d: u64| flag(&w, name).map_or(d, |v| v.parse().unwrap_or(u64::MAX));
        let samples = size("--width", defaults.0) * size("--height", defaults.1) * size("--spp", defaults.2);
        let cpu = sub == "render" && flag(&w, "--method").unwrap_or(method).starts_with("cpu");
        if !(cpu && samples <= 64 * 36 * 16) {
            for (name, value) in [("--width", "24"), ("--height", "16"), ("--spp", "2")] {
                set_flag(&mut words, name, value);
            }
        }
    }
    // The measuring commands time many repetitions of big transfers or long chains: a few small
    // ones show that the command runs.
    let shrink: &[(&str, &str)] = match sub.as_str() {
        "bandwidth" => &[("--mib", "4"), ("--repetitions", "2")],
        "dispatch-cost" => &[("--dispatches", "50"), ("--repetitions", "2")],
        _ => &[],
    };
    for (name, value) in shrink {
        set_flag(&mut words, name, value);
    }
    words.join(" ")
}

/// An experiment config shrunk to seconds, as `docs::the_readme_own_scene_commands_run` does.
fn shrink(config: &str) -> String {
    let mut c: serde_json::Value = serde_json::from_str(config).unwrap();
    c["resolutions"] = serde_json::json!(["24x16"]);
    c["spp"] = serde_json::json!([1]);
    c["repetitions"] = serde_json::json!(1);
    // One scene and one value of each method's swept knob: the command runs every method's
    // code path; the configs' full run lists are `experiment run --list`'s tests.
    if let Some(scenes) = c["scenes"].as_array_mut() {
        scenes.truncate(1);
    }
    for m in c["methods"].as_array_mut().into_iter().flatten() {
        for (_, v) in m.as_object_mut().into_iter().flatten() {
            if let Some(values) = v.as_array_mut() {
                values.truncate(1);
            }
        }
    }
    c["warmup"] = serde_json::json!(0);
    if c["reference"]["spp"].is_number() {
        c["reference"]["spp"] = serde_json::json!(4);
    }
    serde_json::to_string_pretty(&c).unwrap()
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap().flatten() {
        let (src, dst) = (e.path(), to.join(e.file_name()));
        if src.is_dir() {
            copy_dir(&src, &dst);
        } else {
            std::fs::copy(&src, &dst).unwrap();
        }
    }
}

/// Runs `script` in `dir` with the built binary on `PATH` and the fixed environment; `scratch`
/// holds the binary's link and the reference cache the groups share.
fn bash(scratch: &Path, dir: &Path, script: &str) -> std::process::Output {
    let path = format!("{}:{}", scratch.join("bin").display(), std::env::var("PATH").unwrap_or_default());
    std::process::Command::new("bash")
        .arg("-c")
        .arg(format!("set -eo pipefail\n{script}"))
        .current_dir(dir)
        .env("PATH", path)
        .env("WAVETRACE_CACHE", scratch.join("cache"))
        .env("SLURM_ARRAY_TASK_ID", "3")
        .env("SLURM_ARRAY_TASK_COUNT", "4")
        .output()
        .unwrap()
}

/// `scratch/fixtures`: every fixture the commands name, copied for each group.
fn fixtures(scratch: &Path) -> std::path::PathBuf {
    let root = common::root();
    let _ = std::fs::remove_dir_all(scratch);
    std::fs::create_dir_all(scratch.join("bin")).unwrap();
    std::os::unix::fs::symlink(common::bin(), scratch.join("bin/wavetrace")).unwrap();
    let dir = scratch.join("fixtures");
    std::fs::create_dir_all(dir.join("experiments")).unwrap();
    for e in std::fs::read_dir(root.join("experiments")).unwrap().flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name.ends_with(".json") && name != "report.schema.json" {
            let text = std::fs::read_to_string(e.path()).unwrap();
            std::fs::write(dir.join("experiments").join(&name), shrink(&text)).unwrap();
        }
    }
    copy_dir(&root.join("experiments/scenes"), &dir.join("experiments/scenes"));
    std::fs::copy(root.join("experiments/scenes/my_scene.json"), dir.join("my_scene.json")).unwrap();
    let quick = "experiments/results/llvmpipe-2core/quick";
    copy_dir(&root.join(quick), &dir.join(quick));
    copy_dir(&root.join(quick), &dir.join("out/quick"));
    let sweep = serde_json::json!({
        "schema": "wavetrace-experiment/1",
        "question": "The examples' sweep.json: a config to shard and merge.",
        "scenes": ["three-spheres"],
        "resolutions": ["24x16"],
        "spp": [1, 2],
        "max_depth": [2, 4],
        "repetitions": 1,
        "warmup": 0,
        "methods": [{"method": "cpu"}]
    });
    std::fs::write(dir.join("sweep.json"), sweep.to_string()).unwrap();
    let mut script = String::from(
        "wavetrace render --scene three-spheres --method cpu --width 24 --height 16 --spp 2 --out truth.exr\n\
         wavetrace render --scene three-spheres --method cpu --width 24 --height 16 --spp 2 --seed 1 --out test.exr\n\
         cp truth.exr reference.exr; cp test.exr gpu.exr\n",
    );
    for i in 0..4 {
        script.push_str(&format!("wavetrace experiment run sweep.json --out shards/{i} --shard {i}/4\n"));
    }
    let o = bash(scratch, &dir, &script);
    assert!(o.status.success(), "fixtures: {}", String::from_utf8_lossy(&o.stderr));
    dir
}

/// A figure a comment states is in the output: on a line holding the comment's first word that
/// is not a figure (`relMSE`, `paths`), as a number that rounds to it at its precision.
fn states(comment: &str, output: &str) -> Result<(), String> {
    let figures = crate::docs::quoted_figures(comment);
    let label = comment.split_whitespace().find(|w| !figures.iter().any(|f| f == w)).unwrap_or("");
    for f in &figures {
        let rounds = |v: f64| match f.split_once('e') {
            Some((m, _)) => format!("{:.*e}", m.split_once('.').map_or(0, |(_, d)| d.len()), v) == *f,
            None => format!("{:.*}", f.split_once('.').map_or(0, |(_, d)| d.len()), v) == *f,
        };
        let found = output.lines().filter(|l| l.contains(label)).any(|l| {
            l.split(|c: char| c.is_whitespace() || c == ',' || c == ':')
                .filter_map(|w| w.parse::<f64>().ok())
                .any(rounds)
        });
        if !found {
            return Err(format!("`{f}` ({label}) is not in the output:\n{output}"));
        }
    }
    Ok(())
}

/// Each line a transcript shows starts (its first word) a line of the real output: the format
/// the page shows is the one the command prints.
fn same_shape(transcript: &[String], output: &str) -> Result<(), String> {
    let starts: BTreeSet<&str> = output.lines().filter_map(|l| l.split_whitespace().next()).collect();
    for l in transcript {
        let Some(first) = l.split_whitespace().next() else { continue };
        if first != "..." && !starts.contains(first) {
            return Err(format!("the transcript's line `{l}` starts no line of the output:\n{output}"));
        }
    }
    Ok(())
}

/// Every command line shown is either run below or consciously not run.
#[test]
fn every_command_shown_is_run_or_listed() {
    let shown = shown_commands();
    let errors: Vec<String> = shown.iter().filter_map(|c| plan(c).err()).collect();
    assert!(errors.is_empty(), "{}", errors.join("\n"));
    // The lists stay honest: each entry still matches a command shown.
    for (start, why) in NOT_RUN {
        assert!(
            shown.iter().any(|c| c.line.starts_with(start)),
            "NOT_RUN's {start:?} ({why}) is shown nowhere"
        );
    }
    for (cmd, _) in RUN_ELSEWHERE {
        assert!(shown.iter().any(|c| c.line == *cmd), "RUN_ELSEWHERE's {cmd:?} is shown nowhere");
    }
    // Both kinds of source were found (a parser that finds nothing passes nothing).
    assert!(shown.iter().any(|c| c.source.starts_with("docs/numerics.md")), "{shown:?}");
    assert!(shown.iter().any(|c| c.source == "wavetrace experiment merge --help"), "{shown:?}");
}

#[test]
fn every_command_shown_runs() {
    let Some(gpu) = common::gpu() else { return };
    let adapter = gpu.adapter.get_info().name.split_whitespace().next().unwrap_or("").to_string();
    let scratch = common::tmp().join("doc-commands");
    let fixtures = fixtures(&scratch);
    let mut groups = Vec::new();
    let mut ran = 0;
    let mut failures = Vec::new();
    // The same command after the same commands of its group meets the same files (every group
    // starts from a fresh copy of the fixtures): it runs once, and its output is checked
    // against each place that shows it. The key is the group's commands so far.
    let mut outputs: std::collections::HashMap<Vec<String>, Result<String, String>> = Default::default();
    let mut history: Vec<String> = Vec::new();
    for c in shown_commands() {
        match plan(&c) {
            Ok(Plan::Run) => {}
            Ok(Plan::Skip(why)) => {
                eprintln!("not run: {}: `{}`: {why}", c.source, c.line);
                continue;
            }
            Err(e) => panic!("{e}"),
        }
        // A group's first command gets a fresh copy of the fixtures, as a reader starting on
        // that block or that help text would have.
        if groups.last() != Some(&c.group) {
            groups.push(c.group.clone());
            history.clear();
        }
        let dir = scratch.join(format!("group-{}", groups.len()));
        let line = rewrite(&substitute(&c.line, &c.assignments), &adapter);
        history.push(line.clone());
        let result = outputs.entry(history.clone()).or_insert_with(|| {
            if !dir.exists() {
                copy_dir(&fixtures, &dir);
                // The group's earlier commands were served from another group's runs: they run
                // here too (checked there), so this one meets the files they leave.
                for earlier in &history[..history.len() - 1] {
                    bash(&scratch, &dir, earlier);
                }
            }
            ran += 1;
            let started = std::time::Instant::now();
            let o = bash(&scratch, &dir, &line);
            // Each command's cost, for whoever keeps the suite within its time budget (cargo
            // shows it with --nocapture).
            eprintln!("{:7.2} s  {}: `{line}`", started.elapsed().as_secs_f64(), c.source);
            let output =
                format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
            if o.status.success() {
                Ok(output)
            } else {
                Err(format!("exit status {}:\n{output}", o.status))
            }
        });
        let checked = match result {
            Ok(output) if c.check_comment => {
                states(&c.comment, output).and_then(|_| same_shape(&c.transcript, output))
            }
            Ok(_) => Ok(()),
            Err(e) => Err(e.clone()),
        };
        if let Err(e) = checked {
            failures.push(format!("{}: `{}`\nran as `{line}`: {e}", c.source, c.line));
        }
    }
    assert!(ran >= 40, "only {ran} commands ran");
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// The rewrites themselves: tiny sizes where the job is not a small CPU render, sizes added
/// where a render has none, the adapter swapped, everything else left as written.
#[test]
fn commands_are_shrunk_as_the_module_says() {
    let r = |l: &str| rewrite(l, "llvmpipe");
    assert_eq!(
        r("target/release/wavetrace render --scene a --width 1200 --height 675 --spp 16 --out x.exr"),
        "wavetrace render --scene a --width 24 --height 16 --spp 2 --out x.exr"
    );
    assert_eq!(
        r("wavetrace render --scene a --method cpu-f64 --spp 256 --out t.exr"),
        "wavetrace render --scene a --method cpu-f64 --spp 2 --out t.exr --width 24 --height 16"
    );
    let small_cpu = "wavetrace render --scene a --width 64 --height 36 --spp 16 --method cpu --out t.exr";
    assert_eq!(r(small_cpu), small_cpu);
    assert_eq!(
        r("WGPU_BACKEND=vulkan wavetrace info --adapter nvidia"),
        "WGPU_BACKEND=vulkan wavetrace info --adapter llvmpipe"
    );
    assert_eq!(r("wavetrace scene export x > final.json"), "wavetrace scene export x > final.json");
    assert_eq!(
        r("wavetrace intersect-cost --json i.json"),
        "wavetrace intersect-cost --json i.json --width 24 --height 16 --spp 2"
    );
    assert_eq!(
        substitute("wavetrace render $S --out a.exr", &["S=\"--scene x --spp 4\"".to_string()]),
        "wavetrace render --scene x --spp 4 --out a.exr"
    );
    assert_eq!(
        r("wavetrace bandwidth --adapter nvidia --repetitions 21"),
        "wavetrace bandwidth --adapter llvmpipe --repetitions 2 --mib 4"
    );
    assert_eq!(r("wavetrace dispatch-cost"), "wavetrace dispatch-cost --dispatches 50 --repetitions 2");
    assert_eq!(split_comment("wavetrace info   # adapters"), ("wavetrace info".into(), "adapters".into()));
    assert!(states("relMSE 2.762e-2", "relMSE       2.762051e-2\n").is_ok());
    assert!(states("relMSE 2.762e-2", "relMSE       2.763051e-2\n").is_err());
    assert!(states("2147 paths cut", "numerics: 0 self-hits, 2147 paths cut at depth 50").is_ok());
    assert!(states("untransformed, f64", "anything").is_ok());
}
