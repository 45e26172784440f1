//! Built-in scenes. TODO: being written.
use super::Scene;
pub fn by_name(_name: &str) -> Option<Scene> {
    None
}
