//! Scene files. TODO: being written.
use super::{Scene, SceneError};
pub fn from_file(path: &std::path::Path) -> Result<Scene, SceneError> {
    Err(SceneError { file: path.display().to_string(), path: String::new(), reason: "not yet".into() })
}
