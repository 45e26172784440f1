//! The scene's two arrays that grow with it, its primitives and its BVH nodes, spread over as
//! many storage bindings as the adapter's per-binding limit needs (`shaders/shared/scene.wgsl`
//! declares [`MAX_BINDINGS`] of each; four, as lavapipe allows 32 storage buffers a stage and
//! the wavefront's passes bind 14 of their own): lavapipe binds at most 128 MiB, and 10⁷
//! triangles take 458 MiB of primitives. Each binding holds a whole number of elements; element `i` lives in
//! binding `i / per_binding` at `i % per_binding`. A scene that fits one binding takes the one
//! binding and compiles the shaders' loads as before (the `*_BINDINGS` pipeline constants).

/// Bindings declared for each split array in `shaders/shared/scene.wgsl` (`primitives`,
/// `primitives_1` … `primitives_3`, and the same for `nodes`).
pub const MAX_BINDINGS: u64 = 4;

/// One array's split: `bindings` buffers of `per_binding` elements (the last one shorter).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Split {
    /// Elements in the array.
    pub elements: u64,
    /// Elements per binding: as many whole elements as the per-binding limit holds, whatever
    /// the array's length (the last binding holds the rest). So a scene that fits one binding
    /// compiles with the same constants whatever its size, and scenes of the same kinds share
    /// their pipelines (the test suite created 1,719 pipelines instead of 1,854 on the software
    /// driver, when this was the array's length).
    pub per_binding: u64,
    /// Bindings the array takes, 1..=[`MAX_BINDINGS`].
    pub bindings: u64,
}

impl Split {
    /// `elements` of `element_bytes` each under a per-binding `limit` in bytes; None when even
    /// [`MAX_BINDINGS`] bindings cannot hold them.
    pub fn new(elements: u64, element_bytes: u64, limit: u64) -> Option<Split> {
        let most = (limit / element_bytes).max(1);
        // An empty array binds one (zeroed) element.
        let bindings = elements.div_ceil(most).max(1);
        (bindings <= MAX_BINDINGS).then_some(Split { elements, per_binding: most, bindings })
    }

    /// The elements binding `b` holds (empty past the last binding).
    pub fn range(&self, b: u64) -> std::ops::Range<usize> {
        let start = (b * self.per_binding).min(self.elements);
        let end = ((b + 1) * self.per_binding).min(self.elements);
        start as usize..end as usize
    }

    /// The most bytes the array can take under `limit`: [`MAX_BINDINGS`] bindings of the whole
    /// elements that fit in one.
    pub fn capacity(element_bytes: u64, limit: u64) -> u64 {
        MAX_BINDINGS * (limit / element_bytes) * element_bytes
    }

    /// The pipeline constants the shaders read it by: `{prefix}_BINDINGS` and `{prefix}_PER_BINDING`.
    pub fn constants(&self, names: [&'static str; 2]) -> [(&'static str, f64); 2] {
        [(names[0], self.bindings as f64), (names[1], self.per_binding.min(u32::MAX as u64) as f64)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Scenes that fit one binding compile with the same constants whatever their size; a split
    /// one names its bindings and their length.
    #[test]
    fn one_binding_s_constants_do_not_depend_on_the_array() {
        let names = ["B", "PER"];
        for elements in [0, 1, 10] {
            let s = Split::new(elements, 48, 480).unwrap();
            assert_eq!(s.constants(names), [("B", 1.0), ("PER", 10.0)], "{elements} elements");
        }
        assert_eq!(Split::new(10, 48, 470).unwrap().constants(names), [("B", 2.0), ("PER", 9.0)]);
    }

    #[test]
    fn one_binding_when_it_fits_and_whole_elements_per_binding_when_not() {
        assert_eq!(Split::new(10, 48, 480), Some(Split { elements: 10, per_binding: 10, bindings: 1 }));
        // 470 bytes hold 9 whole 48-byte elements: 10 take two bindings, the second with one.
        let s = Split::new(10, 48, 470).unwrap();
        assert_eq!((s.per_binding, s.bindings), (9, 2));
        assert_eq!((s.range(0), s.range(1)), (0..9, 9..10));
        // Every element in exactly one binding, in order.
        let s = Split::new(500, 16, 16 * 130).unwrap();
        assert_eq!(s.bindings, 4);
        let all: Vec<usize> = (0..s.bindings).flat_map(|b| s.range(b)).collect();
        assert_eq!(all, (0..500).collect::<Vec<_>>());
        // One element more than eight bindings hold is refused.
        assert!(Split::new(4 * 130 + 1, 16, 16 * 130).is_none());
        assert_eq!(Split::capacity(16, 16 * 130 + 15), 4 * 130 * 16);
        // An empty array binds its one padding element.
        assert_eq!(Split::new(0, 48, 480).unwrap().bindings, 1);
    }

    /// lavapipe's 128 MiB: 10⁷ triangles' primitives take four bindings.
    #[test]
    fn ten_million_triangles_fit_lavapipe() {
        let s = Split::new(10_000_003, 48, 128 << 20).unwrap();
        assert_eq!(s.bindings, 4);
    }
}
