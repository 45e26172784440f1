//! Stress transforms (`--scale S`, `--translate X,Y,Z`): any scene scaled about the origin, then
//! moved, with its camera and its textures' space moved alike, so that in exact arithmetic it
//! renders *the same image*. Whatever differs from the untransformed render is numerical error:
//! the README's "Where methods fail — numerically" measures it.

use glam::{DVec3, Vec3};

use super::Scene;

/// p ↦ scale · p + translate, applied to geometry and camera; textures are looked up at
/// (p − translate) / scale, so they stay on the surfaces they were on.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct StressTransform {
    pub scale: f64,
    pub translate: [f64; 3],
}

impl Default for StressTransform {
    fn default() -> Self {
        Self { scale: 1.0, translate: [0.0; 3] }
    }
}

impl StressTransform {
    pub fn is_identity(&self) -> bool {
        *self == Self::default()
    }

    /// |translate|: how far the scene's origin moves.
    pub fn distance(&self) -> f64 {
        DVec3::from(self.translate).length()
    }

    /// Refuses a scale that is not a positive finite number, and a translation that is not
    /// finite or does not fit in f32 (where every method stores the scene).
    pub fn validate(&self) -> Result<(), String> {
        let s = self.scale;
        if !(s.is_finite() && s > 0.0) {
            return Err(format!("scale must be a finite number > 0, found {s}"));
        }
        if s as f32 == 0.0 || !(s as f32).is_finite() {
            return Err(format!("scale {s:e} is outside f32's range (about 1.2e-38 to 3.4e38)"));
        }
        for (axis, &t) in ["x", "y", "z"].iter().zip(&self.translate) {
            if !t.is_finite() {
                return Err(format!("translate {axis} must be finite, found {t}"));
            }
            if !(t as f32).is_finite() {
                return Err(format!("translate {axis} = {t:e} overflows f32 (largest {:e})", f32::MAX));
            }
        }
        Ok(())
    }

    /// Reads `S` (a positive number).
    pub fn parse_scale(s: &str) -> Result<f64, String> {
        let v: f64 = s.trim().parse().map_err(|_| format!("expected a number, found {s:?}"))?;
        let t = StressTransform { scale: v, ..Default::default() };
        t.validate()?;
        Ok(v)
    }

    /// Reads `X,Y,Z`, or one number `D` for (D, D, D).
    pub fn parse_translate(s: &str) -> Result<[f64; 3], String> {
        let parts: Vec<&str> = s.split(',').map(str::trim).collect();
        let nums: Vec<f64> = parts
            .iter()
            .map(|p| p.parse::<f64>().map_err(|_| format!("expected X,Y,Z or one number, found {s:?}")))
            .collect::<Result<_, _>>()?;
        let translate = match nums[..] {
            [d] => [d; 3],
            [x, y, z] => [x, y, z],
            _ => return Err(format!("expected X,Y,Z or one number, found {s:?}")),
        };
        StressTransform { translate, ..Default::default() }.validate()?;
        Ok(translate)
    }

    /// The point moved: scale · p + translate, in f64.
    pub fn point(&self, p: Vec3) -> DVec3 {
        p.as_dvec3() * self.scale + DVec3::from(self.translate)
    }

    /// The scene moved. Every coordinate is computed in f64 and rounded once to f32, as the
    /// scene is stored; fails where one overflows f32.
    pub fn apply(&self, scene: &Scene) -> Result<Scene, String> {
        self.validate()?;
        if self.is_identity() {
            return Ok(scene.clone());
        }
        let mut out = scene.clone();
        let what = std::cell::RefCell::new(None::<String>);
        let to32 = |v: DVec3, name: &str| -> Vec3 {
            let f = v.as_vec3();
            if !f.is_finite() && what.borrow().is_none() {
                *what.borrow_mut() = Some(format!("{name} at {v} overflows f32 (largest {:e})", f32::MAX));
            }
            f
        };
        let len = |v: Vec3, name: &str| to32(v.as_dvec3() * self.scale, name);
        let s = self.scale;
        for sp in &mut out.spheres {
            sp.center = to32(self.point(sp.center), "a sphere's centre");
            sp.radius = (sp.radius as f64 * s) as f32;
            if !sp.radius.is_finite() || sp.radius <= 0.0 {
                return Err(format!("a sphere's radius scaled by {s:e} leaves f32's range"));
            }
        }
        for q in &mut out.quads {
            q.corner = to32(self.point(q.corner), "a quad's corner");
            q.u = len(q.u, "a quad's edge");
            q.v = len(q.v, "a quad's edge");
        }
        for m in &mut out.meshes {
            for t in &mut m.triangles {
                for v in t.iter_mut() {
                    *v = to32(self.point(*v), "a triangle's vertex");
                }
            }
        }
        let c = &mut out.camera;
        c.lookfrom = to32(self.point(c.lookfrom), "the camera");
        c.lookat = to32(self.point(c.lookat), "the camera's look-at point");
        c.focus_dist = (c.focus_dist as f64 * s) as f32;
        if !c.focus_dist.is_finite() || c.focus_dist <= 0.0 {
            return Err(format!("the focus distance scaled by {s:e} leaves f32's range"));
        }
        match what.into_inner() {
            Some(e) => Err(e),
            None => Ok(out),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_values_are_refused() {
        for s in ["0", "-1", "nan", "inf", "1e39", "1e-46", "x"] {
            assert!(StressTransform::parse_scale(s).is_err(), "scale {s} accepted");
        }
        for t in ["1e39,0,0", "nan", "1,2", "1,2,3,4", "inf,0,0", ""] {
            assert!(StressTransform::parse_translate(t).is_err(), "translate {t} accepted");
        }
        assert_eq!(StressTransform::parse_translate("5"), Ok([5.0; 3]));
        assert_eq!(StressTransform::parse_translate("1, -2,3e5"), Ok([1.0, -2.0, 3e5]));
    }

    #[test]
    fn a_translation_that_overflows_a_scene_point_is_refused() {
        let mut scene = crate::scene::builtin::by_name("three-spheres").unwrap();
        scene.spheres[0].center.x = 1e38;
        let t = StressTransform { scale: 1.0, translate: [3e38, 0.0, 0.0] };
        let err = t.apply(&scene).unwrap_err();
        assert!(err.contains("overflows f32"), "{err}");
    }

    #[test]
    fn scale_and_translate_move_geometry_and_camera_alike() {
        let scene = crate::scene::builtin::by_name("three-spheres").unwrap();
        let t = StressTransform { scale: 2.0, translate: [1.0, 2.0, 3.0] };
        let moved = t.apply(&scene).unwrap();
        let (a, b) = (&scene.spheres[0], &moved.spheres[0]);
        assert_eq!(b.center, a.center * 2.0 + Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(b.radius, a.radius * 2.0);
        assert_eq!(moved.camera.lookfrom, scene.camera.lookfrom * 2.0 + Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(moved.camera.focus_dist, scene.camera.focus_dist * 2.0);
        assert_eq!(StressTransform::default().apply(&scene).unwrap(), scene);
    }
}
