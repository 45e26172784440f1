//! Scenes: a built-in name or a scene file (`Scene::resolve`, as `--scene`), or the JSON scene
//! format's text (`scene::load`, as a file's), and back to that text (`scene::export`, as
//! `wavetrace scene export`).

use std::sync::Arc;

use pyo3::prelude::*;
use wavetrace::scene::{builtin, export, load, Scene as LibScene};

use crate::errors::{guarded, input};

/// A scene, loaded and validated: pass it to `render` as often as you like.
#[pyclass(module = "wavetrace", frozen)]
pub struct Scene {
    pub inner: Arc<LibScene>,
}

#[pymethods]
impl Scene {
    /// The scene's name: the built-in name or the file's stem.
    #[getter]
    fn name(&self) -> String {
        self.inner.name.clone()
    }

    /// Spheres, quads and mesh triangles (what the BVH is built over).
    #[getter]
    fn primitives(&self) -> usize {
        self.inner.primitive_count()
    }

    /// The scene in the JSON scene format (wavetrace-scene/1), as text.
    fn export_json(&self) -> String {
        export::to_json(&self.inner)
    }

    /// The scene as a dict in the JSON scene format (what `wavetrace scene export` prints);
    /// `wavetrace.render` takes it back.
    fn export<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py.import("json")?.call_method1("loads", (export::to_json(&self.inner),))
    }

    fn __repr__(&self) -> String {
        format!("<wavetrace.Scene {:?}: {} primitives>", self.inner.name, self.inner.primitive_count())
    }
}

/// A built-in scene by name, or a scene file (.json, .gltf, .glb) by path.
#[pyfunction]
pub fn load_scene(py: Python<'_>, spec: String) -> PyResult<Scene> {
    let scene = guarded(py, || LibScene::resolve(&spec).map_err(|e| input(e.to_string())))?;
    Ok(Scene { inner: Arc::new(scene) })
}

/// A scene from the JSON scene format's text; `name` names it, mesh paths are relative to the
/// working directory.
#[pyfunction]
pub fn scene_from_json(py: Python<'_>, text: String, name: String) -> PyResult<Scene> {
    let scene = guarded(py, || load::from_str(&text, "<dict>", &name).map_err(|e| input(e.to_string())))?;
    Ok(Scene { inner: Arc::new(scene) })
}

/// The built-in scenes: (name, description) pairs, as `wavetrace scene list`.
#[pyfunction]
pub fn builtin_scenes() -> Vec<(&'static str, &'static str)> {
    builtin::list()
}
