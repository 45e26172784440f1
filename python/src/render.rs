//! `wavetrace.render`: one render as `wavetrace render` makes it (`wavetrace::render_job`), its
//! options by the knob table's names; and what documents them (`option_help`: the command
//! line's own help for each flag) and `wavetrace.info()`.

use std::sync::OnceLock;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde_json::Value;
use wavetrace::cancel;
use wavetrace::progress::Progress;
use wavetrace::render_job::{self, Phase, RenderJob};

use crate::background;
use crate::errors::{guarded, input, Failure};
use crate::image::to_numpy;
use crate::scene::Scene;
use crate::value::to_json;

/// Renders `scene`; returns the image (float32 H×W×3) and the report as `--report` writes it
/// (JSON text). `options` maps option names ([`option_names`]) to values.
#[pyfunction]
#[pyo3(signature = (scene, method, width, height, spp, options, progress = true))]
#[allow(clippy::too_many_arguments)] // the Python call's own parameters
pub fn render<'py>(
    py: Python<'py>,
    scene: &Scene,
    method: &str,
    width: &Bound<'py, PyAny>,
    height: &Bound<'py, PyAny>,
    spp: &Bound<'py, PyAny>,
    options: &Bound<'py, PyDict>,
    progress: bool,
) -> PyResult<(Bound<'py, PyAny>, String)> {
    let job = guarded(py, || {
        let method = RenderJob::method(method).map_err(input)?;
        let size = |name: &str, v: &Bound<'py, PyAny>| {
            let v = to_json(v, name).map_err(input)?;
            v.as_u64().and_then(|x| u32::try_from(x).ok()).ok_or_else(|| {
                input(format!("{name}: expected a whole number in 0..={}, found {v}", u32::MAX))
            })
        };
        let mut job =
            RenderJob::new(method, size("width", width)?, size("height", height)?, size("spp", spp)?);
        for (k, v) in options.iter() {
            let name: String =
                k.extract().map_err(|_| input(format!("an option name is not a string: {k}")))?;
            let value = to_json(&v, &name).map_err(input)?;
            let known = render_job::option_names().contains(&name.as_str());
            job.set(&name, &value).map_err(|e| if known { input(e) } else { Failure::UnknownOption(e) })?;
        }
        job.check().map_err(input)?;
        Ok(job)
    })?;
    let scene = scene.inner.clone();
    let rendered = background::run(py, move || {
        let bar = OnceLock::new();
        let what = format!("{} {}", job.method.name(), scene.name);
        let rendered = render_job::render(&scene, &job, &|phase, done| {
            cancel::checkpoint();
            if progress && phase == Phase::Render {
                bar.get_or_init(|| Progress::new(job.settings.sample_count(), &what)).set(done);
            }
        })
        .map_err(Failure::of)?;
        if let Some(bar) = bar.get() {
            bar.finish();
        }
        let report = serde_json::to_string(&rendered.report).map_err(|e| Failure::Failed(e.to_string()))?;
        Ok((rendered.image, report))
    })?;
    Ok((to_numpy(py, rendered.0)?, rendered.1))
}

/// Every option name `render` takes: the render settings and measurement flags, then the knob
/// table's names (`wavetrace::options::knobs`), in order.
#[pyfunction]
pub fn option_names() -> Vec<&'static str> {
    render_job::option_names()
}

/// Every option's default, by name, as JSON text: `wavetrace render`'s defaults, typed as
/// `render` takes them (the knob table's values).
#[pyfunction]
pub fn option_defaults() -> String {
    let job = RenderJob::new(wavetrace::options::Method::Megakernel, 1, 1, 1);
    Value::Object(job.values()).to_string()
}

/// `(name, help, default, values)` for `method`, `width`, `height`, `spp` and each option: the
/// help, default and possible values of the `wavetrace render` flag of the same name
/// (`compaction`'s values are the knob's: the flag is `--compaction on|off` beside
/// `--compaction-method`).
#[pyfunction]
pub fn option_help() -> Vec<(String, String, Option<String>, Vec<String>)> {
    use clap::{Args, ValueEnum};
    use wavetrace::options::Named;
    let command = wavetrace::cli::render::RenderArgs::augment_args(clap::Command::new("render"));
    ["method", "width", "height", "spp"]
        .into_iter()
        .chain(render_job::option_names())
        .map(|name| {
            let flag = name.replace('_', "-");
            let arg = command.get_arguments().find(|a| a.get_long() == Some(flag.as_str()));
            let help =
                arg.and_then(|a| a.get_long_help().or(a.get_help())).map_or(String::new(), |h| h.to_string());
            let default = arg
                .map(|a| {
                    a.get_default_values()
                        .iter()
                        .map(|v| v.to_string_lossy().into_owned())
                        .collect::<Vec<_>>()
                })
                .filter(|d| !d.is_empty())
                .map(|d| d.join(","));
            let mut values: Vec<String> = arg
                .map(|a| a.get_possible_values().iter().map(|p| p.get_name().to_owned()).collect())
                .unwrap_or_default();
            let mut default = default;
            if arg.is_some_and(|a| matches!(a.get_action(), clap::ArgAction::SetTrue)) {
                // A switch (`--instrument`): a bool here.
                values.clear();
                default = Some("false".into());
            }
            if name == "compaction" {
                values = wavetrace::options::Compaction::value_variants()
                    .iter()
                    .filter_map(|v| v.to_possible_value())
                    .map(|p| p.get_name().to_owned())
                    .collect();
                default = Some(wavetrace::options::MethodOptions::requested().wavefront.compaction.name());
            }
            (name.to_owned(), help, default, values)
        })
        .collect()
}

/// What `wavetrace info` prints: the adapters, the one chosen and why, its features and limits.
#[pyfunction]
#[pyo3(signature = (adapter = None))]
pub fn info(py: Python<'_>, adapter: Option<String>) -> PyResult<String> {
    background::run(py, move || wavetrace::cli::info::text(adapter.as_deref()).map_err(Failure::of))
}
