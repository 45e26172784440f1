//! The scene's BVH in the layout its traversals read (`--bvh`), what it cost to build and what
//! it occupies: what `PackedScene` holds beside the binary build's nodes, and what the GPU's
//! node binding (`shaders/shared/bvh.wgsl`) receives.

use super::aila_laine::AilaLaineNode;
use super::wide::WideNode;
use super::BvhLayout;
use crate::layout::BvhNode;

/// The layout's nodes (only the chosen layout's vector is filled) and its statistics.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneBvh {
    pub layout: BvhLayout,
    pub aila_laine: Vec<AilaLaineNode>,
    pub wide: Vec<WideNode>,
    /// Host seconds of the binary build plus the conversion to the layout.
    pub build_seconds: f64,
    /// Levels of the layout's nodes from the root to the deepest leaf.
    pub depth: u32,
    /// Where the GPU's traversals keep their stack (`--stack`).
    pub stack: super::stack::BvhStack,
}

/// What a report records of the BVH a render traversed (its build time apart, as a timing).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BvhSummary {
    pub layout: BvhLayout,
    /// Nodes of the layout.
    pub nodes: u64,
    /// Bytes of those nodes: what the traversals read from (the GPU binding adds a 32-byte
    /// header to the layouts other than binary).
    pub bytes: u64,
    /// Levels from the root to the deepest leaf, in the layout's nodes.
    pub depth: u32,
}

/// A layout's nodes, for the traversal that reads them.
#[derive(Clone, Copy, Debug)]
pub enum BvhRef<'a> {
    Binary(&'a [BvhNode]),
    AilaLaine(&'a [AilaLaineNode]),
    Wide(&'a [WideNode]),
}

impl SceneBvh {
    /// The nodes traversals read; `binary` is the binary build's (`PackedScene::nodes`).
    pub fn nodes<'a>(&'a self, binary: &'a [BvhNode]) -> BvhRef<'a> {
        match self.layout {
            BvhLayout::Binary => BvhRef::Binary(binary),
            BvhLayout::AilaLaine => BvhRef::AilaLaine(&self.aila_laine),
            BvhLayout::Wide => BvhRef::Wide(&self.wide),
        }
    }

    /// The words of the GPU's node binding, as 16-byte units: the binary nodes as they are
    /// (the root's box in the first two units); for the other layouts a header of two units
    /// holding the scene's box in the same places (`bvh_root_min`/`bvh_root_max` read it
    /// alike), then their nodes.
    pub fn gpu_words(&self, binary: &[BvhNode]) -> Vec<[u32; 4]> {
        let header = || -> Vec<[u32; 4]> {
            let root = binary.first().copied().unwrap_or_default();
            bytemuck::cast_slice(&[root]).to_vec()
        };
        match self.layout {
            BvhLayout::Binary => bytemuck::cast_slice(binary).to_vec(),
            BvhLayout::AilaLaine => [header(), bytemuck::cast_slice(&self.aila_laine).to_vec()].concat(),
            BvhLayout::Wide => [header(), bytemuck::cast_slice(&self.wide).to_vec()].concat(),
        }
    }

    /// Bytes the layout's nodes occupy (what traversals read; the header aside).
    pub fn bytes(&self, binary: &[BvhNode]) -> u64 {
        self.node_count(binary) * self.layout.node_bytes()
    }

    fn node_count(&self, binary: &[BvhNode]) -> u64 {
        (match self.layout {
            BvhLayout::Binary => binary.len(),
            BvhLayout::AilaLaine => self.aila_laine.len(),
            BvhLayout::Wide => self.wide.len(),
        }) as u64
    }

    pub fn summary(&self, binary: &[BvhNode]) -> BvhSummary {
        BvhSummary {
            layout: self.layout,
            nodes: self.node_count(binary),
            bytes: self.bytes(binary),
            depth: self.depth,
        }
    }
}
