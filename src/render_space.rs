//! Where a scene is rendered (`--render-space`): in its own coordinates (`world`), or moved on
//! the host, in f64, so that the camera sits at the origin (`camera`, pbrt-v4's
//! `RenderingCoordinateSystem::CameraWorld`) before anything is stored in f32. A scene far from
//! the origin (real-world coordinates, or `--translate`) keeps in `camera` space the f32 spacing
//! of a scene near it: the f32 spacing at 2e6 is 0.25, at 8e6 1.0, wider than small spheres.

use glam::DVec3;

use crate::scene::stress::StressTransform;
use crate::scene::CameraSpec;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RenderSpace {
    /// The scene's own coordinates (after `--scale`/`--translate`), rounded to f32.
    World,
    /// Moved in f64 so that the camera is at the origin, then rounded to f32.
    #[default]
    Camera,
}

impl RenderSpace {
    /// As the CLI and configs spell it.
    pub fn name(self) -> &'static str {
        match self {
            RenderSpace::World => "world",
            RenderSpace::Camera => "camera",
        }
    }

    /// The one transform from the scene as stored to the space it is rendered in: `stress`
    /// (p ↦ s·p + t), then, in camera space, minus the camera's position c = s·l + t, all in
    /// f64: p ↦ s·p + (t − c). Textures undo it as they undo `stress`, so they stay put.
    pub fn transform(self, stress: StressTransform, camera: &CameraSpec) -> StressTransform {
        match self {
            RenderSpace::World => stress,
            RenderSpace::Camera => {
                let c = stress.point(camera.lookfrom);
                let t = DVec3::from(stress.translate) - c;
                StressTransform { scale: stress.scale, translate: t.to_array() }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::builtin;

    #[test]
    fn camera_space_puts_the_camera_at_the_origin_whatever_the_translation() {
        let scene = builtin::by_name("rtiow-final").unwrap();
        for translate in [[0.0; 3], [1e7; 3], [3e6, -2e6, 1e6]] {
            let stress = StressTransform { scale: 2.0, translate };
            let t = RenderSpace::Camera.transform(stress, &scene.camera);
            let moved = t.apply(&scene).unwrap();
            assert_eq!(moved.camera.lookfrom, glam::Vec3::ZERO, "{translate:?}");
            // The same relative geometry as the scene scaled about its camera, to f32 rounding.
            let expect = (scene.spheres[1].center - scene.camera.lookfrom) * 2.0;
            assert!((moved.spheres[1].center - expect).length() <= 1e-5 * expect.length(), "{translate:?}");
            assert_eq!(RenderSpace::World.transform(stress, &scene.camera), stress);
        }
    }
}
