//! `--specialize`: whether the shaders are compiled for the scene, with only the primitive,
//! material and texture kinds it has (`scene`, the default), or with every kind (`none`). As
//! Cycles compiles its kernels with only the features a scene uses: the kinds are bitmask
//! pipeline constants (`PRIM_KINDS`, `MATERIAL_KINDS`, `TEXTURE_KINDS`,
//! `PackedScene::pipeline_constants`), so the driver's compiler drops the code of the kinds a
//! scene lacks, in every pass of both methods alike. `none` is the unspecialized baseline for
//! measuring what that is worth; the films are the same either way (tests/suite/specialize.rs).

pub use crate::options::Specialize;

#[cfg(test)]
mod tests {
    use super::Specialize;
    use crate::layout::{material_kind as m, primitive_kind as p, texture_kind as t};
    use crate::packed_scene::PackedScene;
    use crate::scene::Scene;
    use crate::settings::{Accel, RenderSettings};

    /// The three kind masks the scene's shaders are compiled with: (PRIM_KINDS, MATERIAL_KINDS,
    /// TEXTURE_KINDS).
    fn masks(scene: &str, specialize: Specialize) -> (u32, u32, u32) {
        let packed = PackedScene::new(&Scene::resolve(scene).unwrap(), Accel::Bvh);
        let constants = packed.pipeline_constants(&RenderSettings::default(), specialize);
        let get = |name| constants.iter().find(|(n, _)| *n == name).unwrap().1 as u32;
        (get("PRIM_KINDS"), get("MATERIAL_KINDS"), get("TEXTURE_KINDS"))
    }

    #[test]
    fn scene_masks_hold_exactly_the_kinds_the_scene_has() {
        let bit = |k: u32| 1u32 << k;
        // One diffuse sphere, untextured.
        assert_eq!(masks("furnace", Specialize::Scene), (bit(p::SPHERE), bit(m::LAMBERTIAN), bit(t::SOLID)));
        // Quads, diffuse walls and an emitter.
        assert_eq!(
            masks("cornell", Specialize::Scene),
            (bit(p::QUAD), bit(m::LAMBERTIAN) | bit(m::EMISSIVE), bit(t::SOLID))
        );
        // Spheres; diffuse, metal and glass; every albedo solid.
        assert_eq!(
            masks("rtiow-final", Specialize::Scene),
            (bit(p::SPHERE), bit(m::LAMBERTIAN) | bit(m::METAL) | bit(m::DIELECTRIC), bit(t::SOLID))
        );
        // Every texture: the checker ground, noise and marble spheres, the solid metal.
        assert_eq!(
            masks("rtiow-heavy-2", Specialize::Scene),
            (
                bit(p::SPHERE),
                bit(m::LAMBERTIAN) | bit(m::METAL) | bit(m::DIELECTRIC),
                bit(t::SOLID) | bit(t::CHECKER) | bit(t::NOISE) | bit(t::MARBLE)
            )
        );
        // The checker ground and exactly the first K patterns.
        for k in [1u32, 3, 8] {
            let patterns = (0..k).fold(0, |m, i| m | bit(t::NOISE + i));
            assert_eq!(
                masks(&format!("rtiow-kinds-{k}"), Specialize::Scene).2,
                bit(t::SOLID) | bit(t::CHECKER) | patterns,
                "rtiow-kinds-{k}"
            );
        }
        // Every shape and material, but no noise; the emitters' and the glass's records carry
        // no texture anyone looks up.
        let room = concat!(env!("CARGO_MANIFEST_DIR"), "/experiments/scenes/mesh-room.json");
        assert_eq!(
            masks(room, Specialize::Scene),
            (
                bit(p::SPHERE) | bit(p::QUAD) | bit(p::TRIANGLE),
                bit(m::LAMBERTIAN) | bit(m::METAL) | bit(m::DIELECTRIC) | bit(m::EMISSIVE),
                bit(t::SOLID) | bit(t::CHECKER) | bit(t::MARBLE)
            )
        );
    }

    #[test]
    fn none_compiles_every_kind_in_whatever_the_scene() {
        for scene in ["furnace", "cornell", "rtiow-heavy-2"] {
            assert_eq!(masks(scene, Specialize::None), (0b111, 0b1111, 0b111_1111_1111), "{scene}");
        }
    }

    /// The WGSL defaults of the masks (what a pipeline without the constant compiles) are every
    /// kind, as `none` passes them.
    #[test]
    fn the_shaders_default_masks_are_every_kind() {
        let shared = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders/shared/");
        for (file, decl, every) in [
            ("primitive.wgsl", "override PRIM_KINDS: u32 = ", crate::packed_scene::EVERY_PRIMITIVE_KIND),
            ("material.wgsl", "override MATERIAL_KINDS: u32 = ", crate::packed_scene::EVERY_MATERIAL_KIND),
            ("texture.wgsl", "override TEXTURE_KINDS: u32 = ", crate::packed_scene::EVERY_TEXTURE_KIND),
        ] {
            let src = std::fs::read_to_string(format!("{shared}{file}")).unwrap();
            let line =
                src.lines().find_map(|l| l.strip_prefix(decl)).unwrap_or_else(|| panic!("{file}: {decl}"));
            assert_eq!(line, format!("{every}u;"), "{file}");
        }
    }
}
