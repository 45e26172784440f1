//! `--collapse`: how the wide layout (`wide.rs`) turns the binary build into nodes of up to 8
//! children. `greedy` (tinybvh's rule): a node adopts the children of its largest child while
//! they fit. `sah` (Ylitie, Karras & Laine 2017; jan-van-bergen's `BVH8Converter`): dynamic
//! programming over the binary tree, bottom up, for each subtree the least SAH cost of
//! representing it as a forest of at most i = 1..=7 subtrees (a leaf of at most 3 primitives,
//! an 8-wide node over a forest of at most 8, or the children's forests shared out), then top
//! down the choices that reach it. Both take the binary build's subtrees whole, so the leaves
//! hold the same primitives in the same order and films stay bit-identical.

use super::wide::MAX_LEAF;
use super::Aabb;
use crate::layout::BvhNode;
use glam::Vec3;

/// A wide-collapse rule.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum Collapse {
    /// tinybvh's rule: a node adopts the children of its largest (by area) child while fewer
    /// than 8.
    Greedy,
    /// SAH-optimal (Ylitie et al. 2017): the forests of least SAH cost, by dynamic programming.
    /// The default by measurement on the software driver: half the greedy tree's nodes and
    /// 4–6% fewer BVH bytes per ray on the 10⁶-triangle terrain and mesh-room.
    #[default]
    Sah,
}

/// SAH costs of the collapse, those of the binary build (`bvh.rs`): a node visit 1, a
/// primitive test 1, each weighted by the box's area.
const NODE_COST: f32 = 1.0;
const PRIMITIVE_COST: f32 = 1.0;
/// Most subtrees in a forest: a wide node's 8 children are two forests of 1..=7.
const FOREST: usize = 7;

/// A subtree of the binary build: an inner node, or a run of primitive slots.
#[derive(Clone, Copy, Debug)]
pub(super) enum Part {
    Node(u32),
    Range(u32, u32),
}

#[derive(Clone, Copy, Debug)]
pub(super) struct Sub {
    pub part: Part,
    pub bounds: Aabb,
}

/// The binary build seen as subtrees to collapse, with the SAH tables of `--collapse sah`.
pub(super) struct Tree<'a> {
    binary: &'a [BvhNode],
    /// Each primitive's box, by slot in the binary order.
    boxes: &'a [Aabb],
    /// Per binary node: primitives under it (sah only).
    counts: Vec<u32>,
    /// Per binary node: the least cost of a forest of at most i + 1 subtrees (sah only).
    costs: Vec<[f32; FOREST]>,
}

impl<'a> Tree<'a> {
    pub fn new(binary: &'a [BvhNode], boxes: &'a [Aabb], collapse: Collapse) -> Self {
        let mut tree = Tree { binary, boxes, counts: Vec::new(), costs: Vec::new() };
        if collapse == Collapse::Sah && binary.len() > 1 {
            tree.fill_tables();
        }
        tree
    }

    pub fn sub(&self, i: u32) -> Sub {
        let n = &self.binary[i as usize];
        // A lone root is a leaf even with no primitive (an empty scene).
        let leaf = n.count > 0 || self.binary.len() == 1;
        let part = if leaf { Part::Range(n.left_or_first, n.count) } else { Part::Node(i) };
        Sub { part, bounds: Aabb { min: Vec3::from(n.min), max: Vec3::from(n.max) } }
    }

    fn range(&self, first: u32, count: u32) -> Sub {
        let bounds =
            self.boxes[first as usize..(first + count) as usize].iter().fold(Aabb::EMPTY, |a, b| a.union(*b));
        Sub { part: Part::Range(first, count), bounds }
    }

    /// The two halves of a subtree that cannot be one child: an inner node's children, or a
    /// run of more than `MAX_LEAF` primitives cut in two (the binary build's big leaves: those
    /// of identical boxes, or at its depth limit).
    fn split(&self, s: &Sub) -> Option<[Sub; 2]> {
        match s.part {
            Part::Node(i) => Some([self.sub(i + 1), self.sub(self.binary[i as usize].left_or_first)]),
            Part::Range(first, count) if count > MAX_LEAF => {
                let half = count / 2;
                Some([self.range(first, half), self.range(first + half, count - half)])
            }
            Part::Range(..) => None,
        }
    }

    /// The children of the wide node over `s` (none for an empty scene's root; `s` itself for a
    /// root that is one small leaf). A child that is a run of at most `MAX_LEAF` primitives is a
    /// leaf; any other is an inner node.
    pub fn collapse(&self, s: &Sub) -> Vec<Sub> {
        let Some(halves) = self.split(s) else {
            return if matches!(s.part, Part::Range(_, 0)) { Vec::new() } else { vec![*s] };
        };
        if self.costs.is_empty() {
            return self.greedy(halves);
        }
        let mut kids = Vec::with_capacity(8);
        let k = best_share(&self.forest_costs(&halves[0]), &self.forest_costs(&halves[1]), 8);
        self.forest(&halves[0], k, &mut kids);
        self.forest(&halves[1], 8 - k, &mut kids);
        kids
    }

    /// tinybvh's rule: while fewer than 8, the largest child that splits is replaced by its halves.
    fn greedy(&self, halves: [Sub; 2]) -> Vec<Sub> {
        let mut kids = halves.to_vec();
        while kids.len() < 8 {
            let largest = (0..kids.len())
                .filter(|&k| self.split(&kids[k]).is_some())
                .max_by(|&a, &b| kids[a].bounds.area().total_cmp(&kids[b].bounds.area()));
            let Some(k) = largest else { break };
            let [a, b] = self.split(&kids[k]).unwrap();
            kids[k] = a;
            kids.push(b);
        }
        kids
    }
}

/// `--collapse sah`'s tables and choices.
impl Tree<'_> {
    /// Bottom up: a binary node's children come after it (`bvh.rs` builds depth first).
    fn fill_tables(&mut self) {
        let n = self.binary.len();
        self.counts = vec![0; n];
        self.costs = vec![[0.0; FOREST]; n];
        for i in (0..n).rev() {
            let node = &self.binary[i];
            self.counts[i] = if node.count > 0 {
                node.count
            } else {
                self.counts[i + 1] + self.counts[node.left_or_first as usize]
            };
            self.costs[i] = self.compute(&self.sub(i as u32));
        }
    }

    fn count(&self, s: &Sub) -> u32 {
        match s.part {
            Part::Node(i) => self.counts[i as usize],
            Part::Range(_, count) => count,
        }
    }

    /// The cost of `s` as one leaf (infinite past `MAX_LEAF` primitives).
    fn leaf_cost(&self, s: &Sub) -> f32 {
        let count = self.count(s);
        if count <= MAX_LEAF {
            s.bounds.area() * PRIMITIVE_COST * count as f32
        } else {
            f32::INFINITY
        }
    }

    /// The least cost of `s` as a forest of at most i + 1 subtrees, for each i.
    fn forest_costs(&self, s: &Sub) -> [f32; FOREST] {
        match s.part {
            Part::Node(i) => self.costs[i as usize],
            Part::Range(..) => self.compute(s),
        }
    }

    /// [`Tree::forest_costs`] from the halves' (a run of primitives has no table entry: runs
    /// are the binary build's big leaves, few and small).
    fn compute(&self, s: &Sub) -> [f32; FOREST] {
        let leaf = self.leaf_cost(s);
        let Some([a, b]) = self.split(s) else { return [leaf; FOREST] };
        let (l, r) = (self.forest_costs(&a), self.forest_costs(&b));
        let mut c = [0.0; FOREST];
        c[0] = leaf.min(s.bounds.area() * NODE_COST + share_cost(&l, &r, 8));
        for i in 1..FOREST {
            c[i] = c[i - 1].min(share_cost(&l, &r, i + 1));
        }
        c
    }

    /// Appends to `out` the forest of at most `i` subtrees of least cost over `s`.
    fn forest(&self, s: &Sub, i: usize, out: &mut Vec<Sub>) {
        let c = self.forest_costs(s);
        if i > 1 && c[i - 1] < c[i - 2] {
            let [a, b] = self.split(s).expect("only a subtree that splits gains from more roots");
            let k = best_share(&self.forest_costs(&a), &self.forest_costs(&b), i);
            self.forest(&a, k, out);
            self.forest(&b, i - k, out);
        } else if i > 1 {
            self.forest(s, i - 1, out);
        } else if self.leaf_cost(s) <= c[0] {
            out.push(self.as_leaf(s));
        } else {
            out.push(*s);
        }
    }

    /// `s` as one run of primitives: a binary subtree's primitives are contiguous (the build
    /// partitions in place), starting at its leftmost leaf's.
    fn as_leaf(&self, s: &Sub) -> Sub {
        let Part::Node(mut i) = s.part else { return *s };
        let count = self.counts[i as usize];
        while self.binary[i as usize].count == 0 {
            i += 1;
        }
        Sub { part: Part::Range(self.binary[i as usize].left_or_first, count), bounds: s.bounds }
    }
}

/// The least cost of `j` roots shared between two forests: k from the first, j − k from the
/// second, each at least one.
fn share_cost(l: &[f32; FOREST], r: &[f32; FOREST], j: usize) -> f32 {
    (1..j)
        .filter(|&k| k <= FOREST && j - k <= FOREST)
        .map(|k| l[k - 1] + r[j - k - 1])
        .fold(f32::INFINITY, f32::min)
}

/// The k of [`share_cost`]'s least sum (the smallest k of equal sums).
fn best_share(l: &[f32; FOREST], r: &[f32; FOREST], j: usize) -> usize {
    (1..j)
        .filter(|&k| k <= FOREST && j - k <= FOREST)
        .min_by(|&a, &b| (l[a - 1] + r[j - a - 1]).total_cmp(&(l[b - 1] + r[j - b - 1])))
        .expect("j ≥ 2")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::Bvh;

    /// The SAH cost of the wide tree `tree` collapses `s` into, as the DP counts it.
    fn cost(tree: &Tree, s: &Sub) -> f64 {
        let node = s.bounds.area() as f64 * NODE_COST as f64;
        node + tree
            .collapse(s)
            .iter()
            .map(|k| match k.part {
                Part::Range(_, count) if count <= MAX_LEAF => {
                    k.bounds.area() as f64 * (PRIMITIVE_COST * count as f32) as f64
                }
                _ => cost(tree, k),
            })
            .sum::<f64>()
    }

    fn scene(n: usize, seed: u32) -> (Bvh, Vec<Aabb>) {
        let mut s = crate::rng::Stream::new(seed);
        let unordered: Vec<Aabb> = (0..n)
            .map(|_| {
                let c = Vec3::new(s.range(-50.0, 50.0), s.range(-5.0, 5.0), s.range(-50.0, 50.0));
                let r = Vec3::new(s.range(0.1, 2.0), s.range(0.01, 0.5), s.range(0.1, 3.0));
                Aabb { min: c - r, max: c + r }
            })
            .collect();
        let bvh = Bvh::build(&unordered);
        let boxes = bvh.order.iter().map(|&i| unordered[i as usize]).collect();
        (bvh, boxes)
    }

    /// The tree the SAH collapse builds costs what its table says (it is the optimum found),
    /// and never more than the greedy collapse's, which it beats on a real scene.
    #[test]
    fn sah_collapse_reaches_its_table_and_beats_greedy() {
        for (n, seed) in [(3000, 5), (40, 6), (5, 7)] {
            let (bvh, boxes) = scene(n, seed);
            let greedy = Tree::new(&bvh.nodes, &boxes, Collapse::Greedy);
            let sah = Tree::new(&bvh.nodes, &boxes, Collapse::Sah);
            let root = sah.sub(0);
            let (g, s) = (cost(&greedy, &root), cost(&sah, &root));
            // The table's root entry is the best forest of one: the root as one inner node.
            let table = root.bounds.area() as f64
                + share_cost(
                    &sah.forest_costs(&sah.split(&root).unwrap()[0]),
                    &sah.forest_costs(&sah.split(&root).unwrap()[1]),
                    8,
                ) as f64;
            assert!((s - table).abs() <= 1e-4 * table, "n {n}: built {s}, table {table}");
            assert!(s <= g * (1.0 + 1e-6), "n {n}: sah {s} > greedy {g}");
            if n == 3000 {
                assert!(s < 0.99 * g, "sah {s} vs greedy {g}");
            }
        }
    }
}
