//! `experiment merge`: shard outputs of one config → one report, as if run unsharded: runs
//! united by plan index, environments kept per shard, images and reference previews copied,
//! charts and HTML re-drawn.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

use super::outputs;
use super::report::{ExperimentReport, ReportStatus};

pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<ExperimentReport> {
    let Some(first_dir) = dirs.first() else { bail!("name at least one shard directory to merge") };
    let reports: Vec<ExperimentReport> =
        dirs.iter().map(|d| ExperimentReport::read(d)).collect::<Result<_>>()?;
    let first = &reports[0];
    for (dir, r) in dirs.iter().zip(&reports).skip(1) {
        if r.config != first.config {
            bail!(
                "{} and {} come from different configs (their \"config\" fields differ); merge only shards of one config",
                first_dir.display(),
                dir.display()
            );
        }
    }
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;

    let mut merged = first.clone();
    merged.environments.clear();
    merged.runs.clear();
    merged.references.clear();
    merged.charts.clear();
    let mut runs = BTreeMap::new();
    let mut refs = BTreeMap::new();
    for (dir, r) in dirs.iter().zip(&reports) {
        if r.status == ReportStatus::Running {
            log::warn!("{}: that experiment did not finish; merging the runs it finished", dir.display());
        }
        let offset = merged.environments.len();
        merged.environments.extend(r.environments.iter().cloned());
        for run in &r.runs {
            let mut run = run.clone();
            run.environment += offset;
            if let Some(earlier) = runs.insert(run.index, (dir.clone(), run)) {
                bail!(
                    "run {} ({}) is in both {} and {}",
                    earlier.1.index,
                    earlier.1.id,
                    earlier.0.display(),
                    dir.display()
                );
            }
        }
        for reference in &r.references {
            refs.entry(reference.key.clone()).or_insert_with(|| reference.clone());
        }
        copy_tree(&dir.join("images"), &out.join("images"))?;
        copy_tree(&dir.join("references"), &out.join("references"))?;
    }
    merged.runs = runs.into_values().map(|(_, r)| r).collect();
    merged.references = refs.into_values().collect();
    merged.runs_selected = merged.runs_planned;
    merged.missing_runs =
        (0..merged.runs_planned).filter(|i| merged.runs.iter().all(|r| r.index != *i)).collect();
    merged.status =
        if merged.missing_runs.is_empty() { ReportStatus::Complete } else { ReportStatus::Incomplete };
    outputs::draw(&mut merged, out)?;
    merged.write(out)?;
    Ok(merged)
}

/// Copies the files of `from` (one level) into `to`; a missing `from` copies nothing, and a file
/// onto itself (merging into a shard's own directory) is left as it is.
fn copy_tree(from: &Path, to: &Path) -> Result<()> {
    let Ok(entries) = std::fs::read_dir(from) else { return Ok(()) };
    std::fs::create_dir_all(to).with_context(|| format!("creating {}", to.display()))?;
    for entry in entries.flatten() {
        let target = to.join(entry.file_name());
        let same = match (entry.path().canonicalize(), target.canonicalize()) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        };
        if entry.path().is_file() && !same {
            std::fs::copy(entry.path(), &target)
                .with_context(|| format!("copying {} to {}", entry.path().display(), target.display()))?;
        }
    }
    Ok(())
}
