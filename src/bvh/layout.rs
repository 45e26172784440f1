//! `--bvh`: how the BVH's nodes are laid out for traversal. Every layout is made from the one
//! binned-SAH binary build (`Bvh::build`), so all hold the same leaves and every method finds
//! the same closest hits whichever it traverses (DESIGN.md §12).

/// A BVH node layout.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum BvhLayout {
    /// Binary, each 32-byte node holding its own box: a step fetches a node to learn whether
    /// to enter it.
    #[default]
    Binary,
    /// Binary with both child boxes in the parent (Aila & Laine 2009, 64-byte nodes): one fetch
    /// tests both children, and leaves are never fetched as nodes.
    AilaLaine,
    /// 8-wide compressed (Ylitie, Karras & Laine 2017, CWBVH, 80-byte nodes): child boxes
    /// quantized to 8 bits against a per-node frame, children stored contiguously, leaves of at
    /// most 3 primitives, octant-ordered children, collapsed from the binary build (`--collapse`).
    Wide,
}

impl BvhLayout {
    pub fn name(self) -> &'static str {
        match self {
            BvhLayout::Binary => "binary",
            BvhLayout::AilaLaine => "aila-laine",
            BvhLayout::Wide => "wide",
        }
    }

    /// Its value in the `BVH_LAYOUT` pipeline constant (`shaders/shared/bvh.wgsl`).
    pub fn constant(self) -> u32 {
        self as u32
    }

    /// Bytes of one node.
    pub fn node_bytes(self) -> u64 {
        match self {
            BvhLayout::Binary => 32,
            BvhLayout::AilaLaine => 64,
            BvhLayout::Wide => 80,
        }
    }
}
