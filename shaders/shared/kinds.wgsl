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
