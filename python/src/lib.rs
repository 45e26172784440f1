//! `wavetrace._wavetrace`: the extension module under the Python package `wavetrace`
//! (python/wavetrace/). Each function calls the library the command line uses; the Python
//! sources beside it shape the results (numpy images, report dicts, DataFrames) and document
//! them. Long work runs on a worker thread with the GIL released (`background.rs`), and every
//! error, a panic included, reaches Python as an exception of `wavetrace.errors`.

mod background;
mod errors;
mod experiment;
mod image;
mod metrics;
mod render;
mod scene;
mod value;

use pyo3::prelude::*;

#[pymodule]
fn _wavetrace(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // As the binary's main does: no Wayland session, no Mesa device-selection layer (its
    // complaint on every instance). At import, before any render opens Vulkan.
    wavetrace::gpu::headless::quiet_headless_vulkan();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<scene::Scene>()?;
    m.add_function(wrap_pyfunction!(scene::load_scene, m)?)?;
    m.add_function(wrap_pyfunction!(scene::scene_from_json, m)?)?;
    m.add_function(wrap_pyfunction!(scene::builtin_scenes, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(render::option_names, m)?)?;
    m.add_function(wrap_pyfunction!(render::option_help, m)?)?;
    m.add_function(wrap_pyfunction!(render::option_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(render::info, m)?)?;
    m.add_function(wrap_pyfunction!(experiment::run_experiment, m)?)?;
    m.add_function(wrap_pyfunction!(experiment::load_report, m)?)?;
    m.add_function(wrap_pyfunction!(image::read_exr, m)?)?;
    m.add_function(wrap_pyfunction!(metrics::compare, m)?)?;
    m.add_function(wrap_pyfunction!(metrics::flip_map, m)?)?;
    m.add_function(wrap_pyfunction!(background::panic_for_tests, m)?)?;
    Ok(())
}
