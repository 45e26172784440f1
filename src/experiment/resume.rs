//! `experiment run --resume`: continues an interrupted experiment in its output directory. The
//! runs the earlier attempt finished (`ok`) are kept, records and images as they are, when they
//! provably come from the same config, build and shard; runs that failed or were never reached
//! are run now. Without `--resume` an earlier report is replaced, as before, with a note.

use std::collections::BTreeSet;
use std::path::Path;

use anyhow::{bail, Context, Result};
use serde_json::Value;

use super::plan::{RunSpec, Shard};
use super::report::{
    Environment, ExperimentReport, ReportStatus, ResumeRecord, RetriedRun, RunStatus, REPORT_FILE,
};

/// What `run` does with a report already in its output directory.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Resume {
    /// Start over, replacing it.
    #[default]
    Off,
    /// Keep its finished runs. `allow_other_build` keeps them even when their build cannot be
    /// shown to be this one (the report still names each run's build).
    On { allow_other_build: bool },
}

/// The report a run starts from: `fresh` (this process's single environment, no runs), or with
/// `--resume` and an earlier report in `out`, that report with its finished runs kept and this
/// process appended to its environments. The runs left to do are the selected runs it lacks.
pub fn start(
    fresh: ExperimentReport,
    planned: &[RunSpec],
    shard: Option<Shard>,
    out: &Path,
    mode: Resume,
) -> Result<ExperimentReport> {
    let exists = out.join(REPORT_FILE).is_file();
    match mode {
        Resume::Off => {
            if exists {
                note_replacing(out);
            }
            Ok(fresh)
        }
        // A requeued batch job runs the same command line whether or not the first attempt got
        // as far as writing a report, so an empty directory is a fresh start, not an error.
        Resume::On { .. } if !exists => {
            eprintln!(
                "note: --resume: no {REPORT_FILE} in {}: nothing to resume, starting afresh",
                out.display()
            );
            Ok(fresh)
        }
        Resume::On { allow_other_build } => {
            let earlier = ExperimentReport::read(out).with_context(|| {
                format!(
                    "--resume: cannot continue the attempt in {}; run without --resume to start over",
                    out.display()
                )
            })?;
            resume(earlier, fresh, planned, shard, out, allow_other_build)
        }
    }
}

fn resume(
    earlier: ExperimentReport,
    fresh: ExperimentReport,
    planned: &[RunSpec],
    shard: Option<Shard>,
    out: &Path,
    allow_other_build: bool,
) -> Result<ExperimentReport> {
    let dir = out.display();
    check_same_plan(&earlier, &fresh, planned, shard, &dir)?;
    let now = &fresh.environments[0];
    let (kept, failed): (Vec<_>, Vec<_>) =
        earlier.runs.iter().cloned().partition(|r| r.status == RunStatus::Ok);
    let sources: BTreeSet<usize> = kept.iter().map(|r| r.environment).collect();
    let other_build = check_builds(&earlier, now, &sources, allow_other_build, &dir)?;
    note_other_machines(&earlier, now, &sources);
    let left = fresh.runs_selected.saturating_sub(kept.len());
    let retried = if failed.is_empty() {
        String::new()
    } else {
        format!(" ({} failed before, run again)", failed.len())
    };
    eprintln!("resuming {dir}: keeping {} finished runs, running {left}{retried}", kept.len());
    let mut env = now.clone();
    env.resume = Some(ResumeRecord {
        kept: kept.iter().map(|r| r.index).collect(),
        retried: failed
            .iter()
            .map(|r| RetriedRun { index: r.index, id: r.id.clone(), error: r.error.clone() })
            .collect(),
        other_build,
    });
    let mut report = earlier;
    report.status = ReportStatus::Running;
    report.name = fresh.name;
    report.question = fresh.question;
    report.config_file = fresh.config_file;
    report.runs_planned = fresh.runs_planned;
    report.runs_selected = fresh.runs_selected;
    report.missing_runs.clear();
    report.environments.push(env);
    report.runs = kept
        .into_iter()
        .map(|mut r| {
            r.resumed = true;
            r
        })
        .collect();
    Ok(report)
}

/// What tells a resume to start over instead.
const START_OVER: &str = "run without --resume to start over, or choose another --out";

/// The earlier report was made with the same config and shard, and holds runs of this plan only.
fn check_same_plan(
    earlier: &ExperimentReport,
    fresh: &ExperimentReport,
    planned: &[RunSpec],
    shard: Option<Shard>,
    dir: &std::path::Display,
) -> Result<()> {
    if earlier.config != fresh.config {
        bail!(
            "cannot resume {dir}: the config differs from the one its report was made with \
             (changed: {}); {START_OVER}",
            changed_keys(&earlier.config, &fresh.config)
        );
    }
    if earlier.status == ReportStatus::Incomplete {
        bail!("cannot resume {dir}: it holds a merged report; resume the shards' directories instead");
    }
    let show = |s: Option<Shard>| s.map_or("no --shard".to_string(), |s| format!("--shard {s}"));
    if let Some(e) = earlier.environments.iter().find(|e| e.shard != shard) {
        bail!(
            "cannot resume {dir}: it was run with {}, this is {}; {START_OVER}",
            show(e.shard),
            show(shard)
        );
    }
    let mut seen = BTreeSet::new();
    for r in &earlier.runs {
        if !seen.insert(r.index) {
            bail!("cannot resume {dir}: its report holds run {} ({}) twice; {START_OVER}", r.index, r.id);
        }
        let spec = planned.get(r.index);
        if spec.is_none_or(|p| p.id != r.id || shard.is_some_and(|s| !s.takes(p))) {
            bail!("cannot resume {dir}: its run {} ({}) is not in this plan; {START_OVER}", r.index, r.id);
        }
    }

    Ok(())
}

/// The earlier runs were made by this build, or `allow_other_build` keeps them anyway (with a
/// warning); returns whether some were made by another.
fn check_builds(
    earlier: &ExperimentReport,
    now: &Environment,
    sources: &BTreeSet<usize>,
    allow_other_build: bool,
    dir: &std::path::Display,
) -> Result<bool> {
    let mut other_build = false;
    for &e in sources {
        let then = &earlier.environments.get(e).context("a run names an environment the report lacks")?.build;
        if same_build(then, &now.build) {
            continue;
        }
        if !allow_other_build {
            let unprovable = [then, &now.build].iter().any(|b| {
                b.get("git_commit")
                    .and_then(Value::as_str)
                    .is_none_or(|c| c == "unknown" || c.ends_with("-dirty"))
            });
            bail!(
                "cannot resume {dir}: its finished runs were made by another build ({}); this is {}.{} \
                 Resume with the build that made them, pass --allow-other-build to keep those runs anyway (each run's \
                 environment names its build), or {START_OVER}",
                describe(then),
                describe(&now.build),
                if unprovable {
                    " A build from a modified tree (-dirty) counts as the same only when its \
                     executable is byte-identical."
                } else {
                    ""
                }
            );
        }
        other_build = true;
        eprintln!(
            "warning: --allow-other-build: keeping runs made by {}; this is {}",
            describe(then),
            describe(&now.build)
        );
    }
    Ok(other_build)
}

/// Kept runs timed on another machine are compared with care: a note says so.
fn note_other_machines(earlier: &ExperimentReport, now: &Environment, sources: &BTreeSet<usize>) {
    let host = |v: &Value| v.get("hostname").and_then(Value::as_str).unwrap_or("").to_string();
    for &e in sources {
        let then = &earlier.environments[e].machine;
        if host(then) != host(&now.machine) || then.get("cpu") != now.machine.get("cpu") {
            eprintln!(
                "note: kept runs were timed on {} ({}); this process runs on {} ({}): compare times across \
                 machines with care",
                host(then),
                then.get("cpu").and_then(Value::as_str).unwrap_or("?"),
                host(&now.machine),
                now.machine.get("cpu").and_then(Value::as_str).unwrap_or("?")
            );
        }
    }
}

/// Whether runs made by build `then` can be trusted to be this build's: byte-identical
/// executables, or one commit of a clean tree (a `-dirty` or `unknown` commit says nothing about
/// the code; the profile and compiler are not compared).
pub fn same_build(then: &Value, now: &Value) -> bool {
    let s = |v: &Value, k: &str| v.get(k).and_then(Value::as_str).map(str::to_owned);
    let digest = s(now, "executable_digest");
    if digest.is_some() && digest == s(then, "executable_digest") {
        return true;
    }
    let commit = s(now, "git_commit");
    s(then, "version") == s(now, "version")
        && commit == s(then, "git_commit")
        && commit.is_some_and(|c| c != "unknown" && !c.ends_with("-dirty"))
}

fn describe(build: &Value) -> String {
    let s = |k: &str| build.get(k).and_then(Value::as_str).unwrap_or("?");
    format!("version {}, commit {}, executable {}", s("version"), s("git_commit"), s("executable_digest"))
}

/// The top-level fields of two configs whose values differ, for the refusal.
fn changed_keys(a: &Value, b: &Value) -> String {
    let (Some(a), Some(b)) = (a.as_object(), b.as_object()) else { return "the whole config".into() };
    let mut keys: Vec<&str> = a.keys().chain(b.keys()).map(String::as_str).collect();
    keys.sort_unstable();
    keys.dedup();
    keys.retain(|k| a.get(*k) != b.get(*k));
    keys.join(", ")
}

/// Says what an earlier report in `out` was before it is replaced.
fn note_replacing(out: &Path) {
    let path = out.join(REPORT_FILE);
    match ExperimentReport::read(out) {
        Ok(r) => {
            let what = match r.status {
                ReportStatus::Running => format!(
                    "an unfinished attempt of {} ({} of {} runs recorded)",
                    r.name,
                    r.runs.len(),
                    r.runs_selected
                ),
                ReportStatus::Complete => format!("a complete report of {} ({} runs)", r.name, r.runs.len()),
                ReportStatus::Incomplete => format!("a merged report of {}", r.name),
            };
            eprintln!(
                "note: {} holds {what}; starting over and replacing it (--resume would keep its finished runs)",
                path.display()
            );
        }
        Err(e) => eprintln!("note: replacing {}: {e:#}", path.display()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn a_dirty_commit_is_the_same_build_only_with_the_same_executable() {
        let b = |commit: &str, digest: &str| json!({"version": "0.1.0", "git_commit": commit, "executable_digest": digest});
        assert!(same_build(&b("abc", "x"), &b("abc", "y")), "one clean commit");
        assert!(!same_build(&b("abc", "x"), &b("def", "y")));
        assert!(!same_build(&b("abc-dirty", "x"), &b("abc-dirty", "y")), "dirty: the commit proves nothing");
        assert!(same_build(&b("abc-dirty", "x"), &b("abc-dirty", "x")), "dirty: byte-identical executable");
        assert!(!same_build(&b("unknown", "x"), &b("unknown", "y")));
        let no_digest = json!({"version": "0.1.0", "git_commit": "abc-dirty"});
        assert!(!same_build(&no_digest, &no_digest), "nothing to compare");
    }

    #[test]
    fn changed_keys_names_what_differs() {
        let a = json!({"spp": [1, 2], "question": "q", "warmup": 1});
        let b = json!({"question": "q", "spp": [1, 4], "repetitions": 2});
        assert_eq!(changed_keys(&a, &b), "repetitions, spp, warmup");
        // Key order and layout are not content.
        let c: Value = serde_json::from_str(r#"{"warmup": 1, "question": "q", "spp": [1, 2]}"#).unwrap();
        assert_eq!(a, c);
    }
}
