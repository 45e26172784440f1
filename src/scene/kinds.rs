//! `rtiow-kinds-K`: the book's final scene with its diffuse spheres spread over K distinct costly
//! procedural patterns (K in 1..=8, `Pattern::ALL`'s first K), each at the same octave count: the
//! axis the wavefront's per-material shade passes exist for. A megakernel's neighbouring lanes
//! take K different costly code paths; the wavefront, shading each pattern in a pass of its own
//! (`--shade per-texture`), runs each coherently. The patterns cost about the same per octave,
//! so K changes the divergence, not the total cost. Same layout as `rtiow-final` and
//! `rtiow-heavy`: checker ground, metal and glass spheres kept.

use glam::Vec3;

use super::{Material, Pattern, Scene, Texture};
use crate::rng::Stream;

/// Octaves of every pattern (as `rtiow-heavy`).
pub const OCTAVES: u32 = super::heavy::DEFAULT_OCTAVES;
/// Most kinds: every pattern.
pub const MAX_KINDS: u32 = Pattern::ALL.len() as u32;
/// The stream id of the pattern choices. Changing it changes the scenes.
const KINDS_SEED: u32 = 3;

/// `rtiow-kinds-K` (K checked by the caller: 1..=MAX_KINDS): each diffuse sphere draws one of the
/// first K patterns uniformly, in the same order for every K. Made from `rtiow-final`, which
/// builtin.rs hands in (so this module does not depend on it).
pub fn rtiow_kinds(rtiow_final: Scene, kinds: u32) -> Scene {
    let mut scene = rtiow_final;
    scene.name = format!("rtiow-kinds-{kinds}");
    let mut rng = Stream::new(KINDS_SEED);
    for (i, m) in scene.materials.iter_mut().enumerate() {
        let Material::Lambertian { albedo: Texture::Solid(color) } = m.material else { continue };
        m.material = Material::Lambertian {
            albedo: if i == 0 {
                // The ground: The Next Week's checker, as rtiow-heavy's.
                Texture::Checker { scale: 0.32, even: Vec3::new(0.2, 0.3, 0.1), odd: Vec3::splat(0.9) }
            } else {
                let k = ((rng.next_f32() * kinds as f32) as usize).min(kinds as usize - 1);
                Texture::Procedural { pattern: Pattern::ALL[k], scale: 4.0, octaves: OCTAVES, color }
            },
        };
    }
    scene
}

/// K of a `rtiow-kinds-K` name, if it is one (K in 1..=8, no leading zeros).
pub fn parse_name(name: &str) -> Option<u32> {
    super::family_number(name, "rtiow-kinds-", 1..=MAX_KINDS)
}

/// Why a `rtiow-kinds-…` name names no scene.
pub fn family_hint(name: &str) -> Option<String> {
    let digits = name.strip_prefix("rtiow-kinds-")?;
    parse_name(name).is_none().then(|| {
        format!("{name:?} is not a built-in scene: rtiow-kinds-K takes K in 1..={MAX_KINDS} (got {digits:?})")
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    #[test]
    fn names_parse_to_kinds_in_range() {
        assert_eq!(parse_name("rtiow-kinds-1"), Some(1));
        assert_eq!(parse_name("rtiow-kinds-8"), Some(8));
        for bad in ["rtiow-kinds-0", "rtiow-kinds-9", "rtiow-kinds-01", "rtiow-kinds-x", "rtiow-kinds-"] {
            assert_eq!(parse_name(bad), None, "{bad}");
            assert!(family_hint(bad).unwrap().contains("1..=8"), "{bad}");
        }
    }

    /// Each scene has exactly its K patterns, each on a fair share of the diffuse spheres, at
    /// one octave count, on the final scene's layout.
    #[test]
    fn every_diffuse_sphere_takes_one_of_k_patterns_in_fair_shares() {
        let fin = super::super::builtin::rtiow_final();
        for k in 1..=MAX_KINDS {
            let scene = rtiow_kinds(fin.clone(), k);
            assert_eq!(scene.spheres, fin.spheres);
            assert_eq!(scene.camera, fin.camera);
            let mut counts: BTreeMap<&str, usize> = BTreeMap::new();
            for m in &scene.materials[1..] {
                match m.material {
                    Material::Lambertian { albedo: Texture::Procedural { pattern, octaves, .. } } => {
                        assert_eq!(octaves, OCTAVES);
                        *counts.entry(pattern.name()).or_default() += 1;
                    }
                    Material::Lambertian { albedo } => panic!("{}: {albedo:?}", m.name),
                    _ => {}
                }
            }
            let names: Vec<&str> = Pattern::ALL[..k as usize].iter().map(|p| p.name()).collect();
            assert_eq!(
                counts.keys().copied().collect::<std::collections::BTreeSet<_>>(),
                names.into_iter().collect()
            );
            let total: usize = counts.values().sum();
            for (name, &n) in &counts {
                // Binomial shares: within 5 standard deviations of total / k.
                let (mean, p) = (total as f64 / k as f64, 1.0 / k as f64);
                let sd = (total as f64 * p * (1.0 - p)).sqrt();
                assert!((n as f64 - mean).abs() <= 5.0 * sd + 1e-9, "K={k}: {name} on {n} of {total}");
            }
            assert_eq!(rtiow_kinds(fin.clone(), k), scene, "deterministic");
            scene.validate().unwrap();
        }
    }
}
