//! Traversal counts per ray (`--instrument`): the BVH nodes a ray's traversal fetches, their
//! bytes, the primitives it tests, its loop iterations and its deepest stack, counted on the
//! CPU reference's paths (f32), whose traversal loops are the GPU's twins step for step, so the
//! counts are those of every device: what predicts a traversal's cost before any GPU confirms
//! it (DESIGN.md §12). Counted over a sample of the frame's path samples, spread evenly.

use super::camera::Camera;
use super::integrator::trace_path;
use super::observe::PathObserver;
use crate::bvh::BvhLayout;
use crate::camera::CameraFrame;
use crate::packed_scene::PackedScene;
use crate::settings::RenderSettings;

/// Path samples counted at most: enough for per-ray means to three figures.
pub const SAMPLED_PATHS: u64 = 16_384;

/// Means per ray of one kind of traversal (closest hit, or a shadow ray's any hit).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RayCounts {
    /// Traversals counted.
    pub rays: u64,
    /// Loop steps at an inner node (binary, aila-laine) or at a wide node.
    pub inner_steps: f64,
    /// Loop steps at a leaf (binary, aila-laine), or wide nodes whose leaves were tested.
    pub leaf_steps: f64,
    /// Iterations of the traversal loop (binary, aila-laine: inner + leaf steps; wide: nodes).
    pub iterations: f64,
    /// Nodes fetched (binary: the root, each step's node and an inner step's two children).
    pub node_fetches: f64,
    /// Bytes of BVH nodes fetched: node fetches × the layout's node size.
    pub bvh_bytes: f64,
    pub primitive_tests: f64,
    /// The deepest the stack got over every traversal counted (entries).
    pub deepest_stack: u32,
}

/// Counts of the closest-hit traversals, the shadow rays' and both together.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TraversalCounts {
    pub layout: BvhLayout,
    /// Path samples counted.
    pub paths: u64,
    pub closest_hit: RayCounts,
    pub shadow: RayCounts,
    pub all: RayCounts,
}

/// Running sums of one kind: (rays, inner, leaf, primitives, deepest).
#[derive(Clone, Copy, Default)]
struct Sums {
    rays: u64,
    inner: u64,
    leaf: u64,
    prims: u64,
    deepest: u32,
}

struct Counter {
    kinds: [Sums; 2],
    shadow: bool,
}

impl PathObserver for Counter {
    fn traversal(&mut self, shadow: bool) {
        self.shadow = shadow;
        self.kinds[shadow as usize].rays += 1;
    }
    fn inner(&mut self) {
        self.kinds[self.shadow as usize].inner += 1;
    }
    fn leaf(&mut self, tested: u32) {
        let k = &mut self.kinds[self.shadow as usize];
        k.leaf += 1;
        k.prims += tested.count_ones() as u64;
    }
    fn stack(&mut self, entries: usize) {
        let k = &mut self.kinds[self.shadow as usize];
        k.deepest = k.deepest.max(entries as u32);
    }
}

/// The means per ray of `s` in `layout`.
fn means(s: Sums, layout: BvhLayout) -> RayCounts {
    let n = s.rays.max(1) as f64;
    let (inner, leaf) = (s.inner as f64, s.leaf as f64);
    let (iterations, fetches) = match layout {
        BvhLayout::Binary => (inner + leaf, s.rays as f64 + inner + leaf + 2.0 * inner),
        BvhLayout::AilaLaine => (inner + leaf, inner),
        BvhLayout::Wide => (inner, inner),
    };
    RayCounts {
        rays: s.rays,
        inner_steps: inner / n,
        leaf_steps: leaf / n,
        iterations: iterations / n,
        node_fetches: fetches / n,
        bvh_bytes: fetches * layout.node_bytes() as f64 / n,
        primitive_tests: s.prims as f64 / n,
        deepest_stack: s.deepest,
    }
}

/// Counts the traversals of up to [`SAMPLED_PATHS`] of the render's path samples.
pub fn count(scene: &PackedScene, frame: &CameraFrame, settings: &RenderSettings) -> TraversalCounts {
    let camera = Camera::<f32>::new(frame);
    let total = settings.sample_count();
    let paths = total.min(SAMPLED_PATHS);
    let mut c = Counter { kinds: [Sums::default(); 2], shadow: false };
    let pixels = settings.width as u64 * settings.height as u64;
    for i in 0..paths {
        // Evenly over the frame's samples: sample index i·total/paths, pixel-major.
        let k = i * total / paths;
        let (pixel, sample) = (k % pixels, (k / pixels) as u32);
        let (x, y) = ((pixel % settings.width as u64) as u32, (pixel / settings.width as u64) as u32);
        trace_path(scene, &camera, settings, x, y, sample, &mut c);
    }
    let layout = scene.bvh.layout;
    let [a, b] = c.kinds;
    let both = Sums {
        rays: a.rays + b.rays,
        inner: a.inner + b.inner,
        leaf: a.leaf + b.leaf,
        prims: a.prims + b.prims,
        deepest: a.deepest.max(b.deepest),
    };
    TraversalCounts {
        layout,
        paths,
        closest_hit: means(a, layout),
        shadow: means(b, layout),
        all: means(both, layout),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;
    use crate::settings::Accel;

    /// The same paths in every layout: the Aila–Laine loop takes the binary loop's steps (it
    /// tests the same boxes from the parent; the root's, which the binary loop tests first, it
    /// does not), fetching a third of its nodes; the wide layout
    /// takes fewer steps and bytes; stacks stay within the 64 entries.
    #[test]
    fn layouts_trace_the_same_rays_with_their_own_fetches() {
        let scene = Scene::resolve("cornell").unwrap();
        let settings = RenderSettings { width: 16, height: 12, spp: 2, nee: true, ..Default::default() };
        let frame = CameraFrame::new(&scene.camera, settings.width, settings.height);
        let counts = |layout| {
            let packed = PackedScene::new(&scene, Accel::Bvh).with_bvh(layout, Default::default()).unwrap();
            count(&packed, &frame, &settings)
        };
        let (b, a, w) = (counts(BvhLayout::Binary), counts(BvhLayout::AilaLaine), counts(BvhLayout::Wide));
        assert_eq!(b.paths, 384);
        assert!(b.shadow.rays > 0 && b.closest_hit.rays >= 384);
        for k in [|t: &TraversalCounts| t.closest_hit, |t: &TraversalCounts| t.shadow] {
            let (b, a, w) = (k(&b), k(&a), k(&w));
            assert_eq!((a.rays, w.rays), (b.rays, b.rays));
            assert_eq!((a.leaf_steps, a.primitive_tests), (b.leaf_steps, b.primitive_tests));
            // Less only the binary loop's early out: a ray missing the root's box.
            assert!(a.inner_steps >= b.inner_steps && a.inner_steps <= b.inner_steps + 1.0);
            assert!(a.node_fetches < b.node_fetches / 3.0 + 1e-9, "{a:?} {b:?}");
            assert!(w.iterations < b.iterations && w.bvh_bytes < a.bvh_bytes, "{w:?} {a:?}");
            assert!(b.deepest_stack < 64 && w.deepest_stack <= b.deepest_stack);
        }
    }
}
