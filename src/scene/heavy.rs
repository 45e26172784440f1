//! `rtiow-heavy`: the book's final scene made expensive to shade, the case where divergent,
//! costly shading should favour the wavefront (Laine et al.'s speed-ups grew with material
//! cost). Same layout as `rtiow-final`; the ground becomes a checker, and each small diffuse
//! sphere and the big brown one get a layered-noise albedo: turbulence sums `octaves` layers of
//! Perlin noise, so the octave count sets the shading cost (`rtiow-heavy-O` for O octaves,
//! 1..=16; `rtiow-heavy` has 8). Noise and marble alternate at random, so neighbouring threads
//! of a megakernel take different texture branches.

use glam::Vec3;

use super::{Material, Scene, Texture};
use crate::rng::Stream;

/// Octaves of plain `rtiow-heavy`.
pub const DEFAULT_OCTAVES: u32 = 8;
/// The stream id of the texture choices. Changing it changes the scene.
const HEAVY_SEED: u32 = 2;

/// `rtiow-heavy` with `octaves` layers of noise (checked by the caller: 1..=MAX_OCTAVES), made
/// from `rtiow-final`, which builtin.rs hands in (so this module does not depend on it).
pub fn rtiow_heavy(rtiow_final: Scene, octaves: u32) -> Scene {
    let mut scene = rtiow_final;
    scene.name =
        if octaves == DEFAULT_OCTAVES { "rtiow-heavy".into() } else { format!("rtiow-heavy-{octaves}") };
    let mut rng = Stream::new(HEAVY_SEED);
    for (i, m) in scene.materials.iter_mut().enumerate() {
        let Material::Lambertian { albedo: Texture::Solid(color) } = m.material else { continue };
        m.material = Material::Lambertian {
            albedo: if i == 0 {
                // The ground: The Next Week's checker.
                Texture::Checker { scale: 0.32, even: Vec3::new(0.2, 0.3, 0.1), odd: Vec3::splat(0.9) }
            } else if rng.next_f32() < 0.5 {
                Texture::noise(4.0, octaves, color)
            } else {
                Texture::marble(4.0, octaves, color)
            },
        };
    }
    scene
}

/// The octave count of a `rtiow-heavy-O` name, if it is one (O in 1..=16, no leading zeros).
pub fn parse_name(name: &str) -> Option<u32> {
    if name == "rtiow-heavy" {
        return Some(DEFAULT_OCTAVES);
    }
    super::family_number(name, "rtiow-heavy-", 1..=super::texture::MAX_OCTAVES)
}

#[cfg(test)]
mod tests {
    use super::super::builtin;
    use super::*;
    use crate::scene::Pattern;

    #[test]
    fn names_parse_to_octaves_in_range() {
        assert_eq!(parse_name("rtiow-heavy"), Some(8));
        assert_eq!(parse_name("rtiow-heavy-1"), Some(1));
        assert_eq!(parse_name("rtiow-heavy-16"), Some(16));
        for bad in ["rtiow-heavy-0", "rtiow-heavy-17", "rtiow-heavy-01", "rtiow-heavy-x", "rtiow-heavy-"] {
            assert_eq!(parse_name(bad), None, "{bad}");
        }
    }

    #[test]
    fn every_diffuse_material_is_textured_and_the_layout_is_the_final_scenes() {
        let fin = builtin::by_name("rtiow-final").unwrap();
        let heavy = rtiow_heavy(fin.clone(), 5);
        assert_eq!(heavy.spheres, fin.spheres);
        assert_eq!(heavy.camera, fin.camera);
        let mut kinds = [0; 4];
        for m in &heavy.materials {
            if let Material::Lambertian { albedo } = m.material {
                match albedo {
                    Texture::Solid(_) | Texture::Image { .. } => {
                        panic!("{} is untextured or an image", m.name)
                    }
                    Texture::Checker { .. } => kinds[1] += 1,
                    Texture::Procedural { pattern, octaves, .. } => {
                        assert_eq!(octaves, 5);
                        match pattern {
                            Pattern::Noise => kinds[2] += 1,
                            Pattern::Marble => kinds[3] += 1,
                            other => panic!("{other:?}"),
                        }
                    }
                }
            }
        }
        assert_eq!(kinds[1], 1, "one checker ground");
        assert!(kinds[2] > 100 && kinds[3] > 100, "noise and marble both common: {kinds:?}");
        assert_eq!(rtiow_heavy(fin, 5), heavy, "deterministic");
        heavy.validate().unwrap();
    }
}
