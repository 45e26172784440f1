//! `wavetrace.run` and `wavetrace.load_report`: `wavetrace experiment run` (the config read
//! with its `--set`s, `cli::experiment::runner_options`, `experiment::runner::run`) and the
//! report it leaves (`ExperimentReport::read`, `tidy::runs_csv`).

use std::path::PathBuf;

use pyo3::prelude::*;
use wavetrace::cli::experiment::{failures, runner_options, RunArgs};
use wavetrace::experiment::overrides::Override;
use wavetrace::experiment::report::REPORT_FILE;
use wavetrace::experiment::{runner, tidy, ExperimentConfig, ExperimentReport};

use crate::background;
use crate::errors::{guarded, input, Failure};

/// Runs a config: the file at `config_path`, or `config_text` (a dict's JSON) read as if it were
/// that file (relative paths in it are relative to the file's folder). Returns the output
/// directory and, when runs failed, the command line's message about it.
#[pyfunction]
#[pyo3(signature = (config_path, config_text, out, set, resume, shard, cache, allow_other_build))]
#[allow(clippy::too_many_arguments)]
pub fn run_experiment(
    py: Python<'_>,
    config_path: PathBuf,
    config_text: Option<String>,
    out: Option<PathBuf>,
    set: Vec<String>,
    resume: bool,
    shard: Option<String>,
    cache: Option<PathBuf>,
    allow_other_build: bool,
) -> PyResult<(String, Option<String>)> {
    let (config, args) = guarded(py, || {
        let set: Vec<Override> = set
            .iter()
            .map(|s| Override::parse(s).map_err(|e| input(format!("set: {e}"))))
            .collect::<Result<_, _>>()?;
        let shard = shard.map(|s| s.parse().map_err(|e| input(format!("shard: {e}")))).transpose()?;
        let config = match &config_text {
            Some(text) => ExperimentConfig::from_str_with(text, &config_path, &set),
            None => ExperimentConfig::from_file_with(&config_path, &set),
        }
        .map_err(|e| input(e.to_string()))?;
        let cache = cache.or_else(|| std::env::var_os("WAVETRACE_CACHE").map(PathBuf::from));
        let args =
            RunArgs { config: config_path, out, shard, cache, list: false, resume, allow_other_build, set };
        Ok((config, args))
    })?;
    background::run(py, move || {
        let opts = runner_options(&args, &config);
        let report = runner::run(&config, &opts).map_err(Failure::of)?;
        Ok((opts.out_dir.display().to_string(), failures(&report)))
    })
}

/// A finished (or interrupted) experiment's report.json as text, checked to be one this build
/// reads, and its runs.csv table (made from it, so an interrupted report has one too).
#[pyfunction]
pub fn load_report(py: Python<'_>, dir: PathBuf) -> PyResult<(String, String)> {
    guarded(py, || {
        let report = ExperimentReport::read(&dir).map_err(|e| input(format!("{e:#}")))?;
        let path = dir.join(REPORT_FILE);
        let text = std::fs::read_to_string(&path).map_err(|e| input(format!("{}: {e}", path.display())))?;
        Ok((text, tidy::runs_csv(&report)))
    })
}
