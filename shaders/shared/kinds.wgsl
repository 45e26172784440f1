// Kinds compiled in per scene (`--specialize`, src/gpu/specialize.rs): a pipeline-constant mask
// with bit k set when the scene has kind k (PRIM_KINDS, MATERIAL_KINDS, TEXTURE_KINDS). Once
// naga substitutes the constant, the driver's compiler drops the code of every absent kind.

// Whether `value` is kind `k`, given that the values met are among the kinds in `kinds`: false
// without reading `value` when k is absent, true without reading it when k is the only kind.
fn kind_is(kinds: u32, value: u32, k: u32) -> bool {
    if (kinds & (1u << k)) == 0u {
        return false;
    }
    return kinds == (1u << k) || value == k;
}

// Material kinds as stored in `Material.kind` (twin of layout::material_kind), and how many
// there are: the wavefront's material queues, shade passes and every slot after them follow
// the count (wavefront/shared/path_state.wgsl).
const MATERIAL_LAMBERTIAN: u32 = 0u;
const MATERIAL_METAL: u32 = 1u;
const MATERIAL_DIELECTRIC: u32 = 2u;
const MATERIAL_EMISSIVE: u32 = 3u;
const MATERIAL_KIND_COUNT: u32 = 4u;
