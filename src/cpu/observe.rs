//! What a path does, step by step, for the lockstep SIMD replay (`src/replay/`): the integrator
//! and the BVH traversal report each block they run to a [`PathObserver`]. Rendering passes `()`,
//! whose methods are empty and compile away.

/// The blocks of one path, in the order the GPU's instrumented points meet them.
pub trait PathObserver {
    /// A traversal starts: the closest hit of a bounce's ray, or a shadow ray's any hit.
    fn traversal(&mut self, _shadow: bool) {}
    /// One iteration of the traversal loop at an inner node.
    fn inner(&mut self) {}
    /// One iteration at a leaf; `tested` has bit p set for each position p of the leaf whose
    /// primitive was tested (the skipped light and those after an any-hit return are not).
    fn leaf(&mut self, _tested: u32) {}
    /// The traversal's stack holds `entries` after a push (its deepest use is the largest).
    fn stack(&mut self, _entries: usize) {}
    /// The bounce's ray hit a primitive of this material kind.
    fn hit(&mut self, _material_kind: u32) {}
}

impl PathObserver for () {}
