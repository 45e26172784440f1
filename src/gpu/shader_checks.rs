//! `--shader-checks`: whether wgpu compiles our WGSL with its runtime checks (bounds checks on
//! every array access, loops forced to be bounded) or without them (`unchecked`,
//! `create_shader_module_trusted`). The checks sit inside every traversal loop of both methods,
//! so what they cost is a fair knob to measure (issue 44); the default keeps them. Unchecked is
//! safe only because every method's films match the checked ones (tests/suite/megakernel.rs,
//! wavefront.rs): an out-of-bounds access there would be undefined behaviour on the GPU.

pub use crate::options::ShaderChecks;
