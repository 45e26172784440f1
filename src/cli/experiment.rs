//! `wavetrace experiment`: run a config, merge shards, re-draw a report.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

use crate::experiment::overrides::Override;
use crate::experiment::plan::{self, Shard};
use crate::experiment::report::{ExperimentReport, RunStatus};
use crate::experiment::resume::Resume;
use crate::experiment::runner::{self, RunnerOptions};
use crate::experiment::{markdown, merge, outputs, ExperimentConfig};

/// `wavetrace experiment --help`: one line per subcommand.
pub const EXAMPLES: &str = "\
Examples:
  wavetrace experiment run experiments/quick.json                 # -> out/quick/report.html
  wavetrace experiment run experiments/quick.json --list          # the runs, without running
  wavetrace experiment merge shards/* --out results/sweep         # shards of one config -> one report
  wavetrace experiment report out/quick --markdown                # the results as a Markdown page

Configs: docs/cli-and-configs.md. Outputs (report.json, runs.csv, passes.csv): docs/outputs.md.
Each subcommand's --help has its own examples.";

const RUN_EXAMPLES: &str = "\
Examples:
  wavetrace experiment run experiments/quick.json                 # -> out/quick/report.html
  wavetrace experiment run experiments/my_scene.json --out out/my_scene
  wavetrace experiment run experiments/quick.json --list          # the runs, without running
  wavetrace experiment run experiments/quick.json --set 'scenes=[\"cornell\"]' --set spp=[4] --out out/cornell
  wavetrace experiment run sweep.json --out results/sweep --resume  # after a kill or preemption
  wavetrace experiment run sweep.json --out shards/$SLURM_ARRAY_TASK_ID \\
      --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT --resume   # see scripts/slurm/

Writes into the output directory: report.json (schema wavetrace-experiment-report/1, described in
docs/outputs.md and experiments/report.schema.json), runs.csv and passes.csv (tidy tables of it),
report.html, charts/*.svg, images/RUN.exr|.png|-error.png, references/*.png|.exr (the references
themselves, so the directory is self-contained).
--resume keeps the runs an interrupted attempt in --out finished (same config, build and shard,
else it refuses and says what differs), runs failed runs again and renders the rest; with no
report.json there yet it starts afresh, so a requeued batch job can always pass it.
Exits with status 1 when any run failed (the report records why).";

const MERGE_EXAMPLES: &str = "\
Examples:
  wavetrace experiment merge shards/* --out results/sweep
  wavetrace experiment merge shards/0 shards/1 --out results/partial --allow-incomplete  # missing runs listed

The shards must come from one config; a run found in two shards is refused. The merged report
keeps each shard's environment, lists runs no shard had in missing_runs (status incomplete),
copies the images and re-draws charts, report.html, runs.csv and passes.csv. scripts/slurm/
submits a sharded job array and this merge after it.";

const REPORT_EXAMPLES: &str = "\
Examples:
  wavetrace experiment report out/quick                           # re-draw charts, HTML and CSV
  wavetrace experiment report out/quick --markdown                # results page on stdout
  wavetrace experiment report experiments/results/llvmpipe-2core/quick --markdown \\
      --out docs/results/llvmpipe-2core/quick.md

--markdown writes a results page (tables of every run, the build and device from the report's own
environment records) and leaves the directory untouched; without it, charts/*.svg, report.html,
runs.csv and passes.csv are re-drawn from report.json.";

#[derive(clap::Subcommand, Debug)]
pub enum ExperimentCommand {
    /// Run every combination in a config (or one shard's share) and write the report.
    Run(RunArgs),
    /// Merge the output directories of shards of one config into one report.
    Merge(MergeArgs),
    /// Re-draw charts, report.html, runs.csv and passes.csv from a directory's report.json.
    Report(ReportArgs),
}

#[derive(clap::Args, Debug)]
#[command(after_help = RUN_EXAMPLES)]
pub struct RunArgs {
    /// Experiment config (JSON, "schema": "wavetrace-experiment/1").
    pub config: PathBuf,
    /// Output directory [default: out/CONFIG_STEM].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Run only the runs whose index is I modulo N (I from 0), e.g. a Slurm array task's share.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<Shard>,
    /// Where rendered references are cached [default: $WAVETRACE_CACHE, else .cache/ beside the
    /// config].
    #[arg(long, env = "WAVETRACE_CACHE", hide_env_values = true)]
    pub cache: Option<PathBuf>,
    /// Print the planned runs (index and id; with --shard, the shard's) and exit.
    #[arg(long)]
    pub list: bool,
    /// Continue an interrupted attempt in the output directory: keep its finished runs (records
    /// and images), run its failed runs again and render the rest. Refused, naming what differs,
    /// when the config, the build or the shard differs. Without a report.json there, starts
    /// afresh (a requeued batch job can always pass --resume).
    #[arg(long)]
    pub resume: bool,
    /// With --resume: keep the finished runs even when their build cannot be shown to be this
    /// one (another commit, or a modified "-dirty" tree whose executable differs). Each run's
    /// environment still names its build.
    #[arg(long, requires = "resume")]
    pub allow_other_build: bool,
    /// Change the config from the command line, without copying it (repeatable, applied in
    /// order): KEY is a dotted path into its JSON (`spp`, `warmup.max_frames`,
    /// `methods.1.threads`), VALUE is JSON (`[4, 16]`, `true`) or else a string. Validated as the
    /// file's fields are; the report records the overrides.
    #[arg(long = "set", value_name = "KEY=VALUE", value_parser = Override::parse)]
    pub set: Vec<Override>,
}

#[derive(clap::Args, Debug)]
#[command(after_help = MERGE_EXAMPLES)]
pub struct MergeArgs {
    /// Output directories of `experiment run --shard`.
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// Where the merged report goes.
    #[arg(long)]
    pub out: PathBuf,
    /// Exit 0 even when some of the config's runs are in no shard (unfinished or lost shards):
    /// without it such a merge still writes its report (status "incomplete") but fails, so that
    /// a job script checking the exit status does not go on too early.
    #[arg(long)]
    pub allow_incomplete: bool,
}

#[derive(clap::Args, Debug)]
#[command(after_help = REPORT_EXAMPLES)]
pub struct ReportArgs {
    /// A directory holding report.json.
    pub dir: PathBuf,
    /// Write a Markdown results page from report.json (to stdout, or --out) instead of
    /// re-drawing the directory's charts, HTML and CSV.
    #[arg(long)]
    pub markdown: bool,
    /// With --markdown: the page's file (links to charts are made relative to it).
    #[arg(long, requires = "markdown", value_name = "FILE")]
    pub out: Option<PathBuf>,
}

pub fn run(c: ExperimentCommand) -> Result<()> {
    match c {
        ExperimentCommand::Run(a) => run_config(a),
        ExperimentCommand::Merge(a) => {
            let report = merge::merge(&a.dirs, &a.out)?;
            finish(&report, &a.out)?;
            if !report.missing_runs.is_empty() && !a.allow_incomplete {
                bail!(
                    "the merge is incomplete: {} of {} runs are in no shard (by index: {:?}); \
                     wait for the shards to finish, or pass --allow-incomplete",
                    report.missing_runs.len(),
                    report.runs_planned,
                    report.missing_runs
                );
            }
            Ok(())
        }
        ExperimentCommand::Report(a) if a.markdown => markdown_page(&a),
        ExperimentCommand::Report(a) => {
            let report = outputs::redraw(&a.dir)?;
            println!("{}", a.dir.join(outputs::HTML_FILE).display());
            let _ = report;
            Ok(())
        }
    }
}

/// `experiment report DIR --markdown [--out FILE]`: the results page, from report.json alone.
fn markdown_page(a: &ReportArgs) -> Result<()> {
    let mut report = ExperimentReport::read(&a.dir)?;
    markdown::keep_present_charts(&mut report, &a.dir);
    let source = a.dir.to_string_lossy().trim_end_matches('/').to_string();
    match &a.out {
        None => {
            let charts = format!("{source}/");
            print!("{}", markdown::page(&report, &source, &markdown::Links { charts: &charts, docs: None }));
            Ok(())
        }
        Some(file) => {
            let from = file.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
            std::fs::create_dir_all(from).with_context(|| format!("creating {}", from.display()))?;
            let prefix = relative_path(from, &a.dir)
                .with_context(|| format!("relating {} to {}", a.dir.display(), file.display()))?;
            let docs = docs_dir(from).and_then(|d| relative_path(from, &d).ok());
            let links = markdown::Links { charts: &prefix, docs: docs.as_deref() };
            let text = markdown::page(&report, &source, &links);
            crate::image_io::write_file_atomically(file, text.as_bytes())
                .with_context(|| format!("writing {}", file.display()))?;
            println!("{}", file.display());
            Ok(())
        }
    }
}

/// The repository's `docs/` above (or beside) `dir`, where a page written there can link to it:
/// the nearest ancestor's `docs/` that holds methods.md.
fn docs_dir(dir: &Path) -> Option<std::path::PathBuf> {
    let dir = std::fs::canonicalize(dir).ok()?;
    dir.ancestors().map(|a| a.join("docs")).find(|d| d.join("methods.md").is_file())
}

/// The path from directory `from` to directory `to`, with a trailing `/` ("" when they are one).
fn relative_path(from: &Path, to: &Path) -> Result<String> {
    let (from, to) = (std::fs::canonicalize(from)?, std::fs::canonicalize(to)?);
    let (a, b): (Vec<_>, Vec<_>) = (from.components().collect(), to.components().collect());
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut out = String::new();
    for _ in common..a.len() {
        out.push_str("../");
    }
    for c in &b[common..] {
        out.push_str(&c.as_os_str().to_string_lossy());
        out.push('/');
    }
    Ok(out)
}

fn run_config(a: RunArgs) -> Result<()> {
    let config = ExperimentConfig::from_file_with(&a.config, &a.set)?;
    if a.list {
        for r in plan::plan(&config).iter().filter(|r| a.shard.is_none_or(|s| s.takes(r))) {
            println!("{:>4} {}", r.index, r.id);
        }
        return Ok(());
    }
    let opts = runner_options(&a, &config);
    let report = runner::run(&config, &opts)?;
    finish(&report, &opts.out_dir)
}

/// Where `experiment run` writes (`--out`, else out/CONFIG_STEM), where it caches references
/// (`--cache`, else .cache/ beside the config) and whether it resumes; the Python package's
/// `wavetrace.run` asks here too.
pub fn runner_options(a: &RunArgs, config: &ExperimentConfig) -> RunnerOptions {
    let out = a.out.clone().unwrap_or_else(|| Path::new("out").join(&config.name));
    let cache_dir =
        a.cache.clone().unwrap_or_else(|| a.config.parent().unwrap_or(Path::new("")).join(".cache"));
    let resume = if a.resume { Resume::On { allow_other_build: a.allow_other_build } } else { Resume::Off };
    RunnerOptions { out_dir: out, shard: a.shard, cache_dir, resume }
}

/// The error `experiment run` exits with when runs failed (None when none did).
pub fn failures(report: &ExperimentReport) -> Option<String> {
    let failed = report.runs.iter().filter(|r| r.status == RunStatus::Failed).count();
    (failed > 0).then(|| {
        format!("{failed} of {} runs failed; report.json and report.html say why", report.runs.len())
    })
}

/// Says where the report is, and fails when a run failed.
fn finish(report: &ExperimentReport, out: &Path) -> Result<()> {
    let failed = report.runs.iter().filter(|r| r.status == RunStatus::Failed).count();
    println!(
        "{} runs, {failed} failed -> {} ({})",
        report.runs.len(),
        out.join(outputs::HTML_FILE).display(),
        out.join(crate::experiment::report::REPORT_FILE).display()
    );
    match failures(report) {
        Some(e) => bail!("{e}"),
        None => Ok(()),
    }
}
