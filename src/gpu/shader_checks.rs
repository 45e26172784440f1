//! `--shader-checks`: whether wgpu compiles our WGSL with its runtime checks (bounds checks on
//! every array access, loops forced to be bounded) or without them (`unchecked`,
//! `create_shader_module_trusted`). The checks sit inside every traversal loop of both methods,
//! so what they cost is a fair knob to measure (issue 44); the default keeps them. Unchecked is
//! safe only because every method's films match the checked ones (tests/suite/megakernel.rs,
//! wavefront.rs): an out-of-bounds access there would be undefined behaviour on the GPU.

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShaderChecks {
    /// wgpu's default: bounds checks and bounded loops.
    #[default]
    Checked,
    /// No runtime checks: wgpu's trusted shader modules, without bounds checks or forced loop
    /// bounds.
    Unchecked,
}

impl ShaderChecks {
    /// As the CLI and configs spell it.
    pub fn name(self) -> &'static str {
        match self {
            ShaderChecks::Checked => "checked",
            ShaderChecks::Unchecked => "unchecked",
        }
    }
}
