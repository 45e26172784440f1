//! `--stack`: where the GPU's BVH traversal keeps its stack (`shaders/shared/bvh_stack.wgsl`).
//! The CPU reference keeps its own; the films are the same either way.

/// Where the traversal stack lives.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum BvhStack {
    /// A 64-entry array per thread in function memory (per-thread local memory on NVIDIA).
    #[default]
    Function,
    /// A short stack of 8 entries a thread in workgroup memory, deeper entries spilled to the
    /// function array (tinybvh's tiny8.comp; Vaidyanathan et al. 2019: short stacks come close
    /// to a full one).
    Workgroup,
}

impl BvhStack {
    /// Its value in the `BVH_STACK_WORKGROUP` pipeline constant.
    pub fn constant(self) -> u32 {
        self as u32
    }
}
