//! An 8-wide bounding volume hierarchy of triangles, laid out for rays.
//!
//! [`RayTree`] answers the same ray queries as the other trees
//! ([`RayQuery`](crate::query::RayQuery): first hit, any hit, batches), with the same answers, but is
//! built and laid out for rays alone:
//!
//! - the binary tree under it is split by the surface area heuristic (rays
//!   enter a box with a probability that grows with its area), with leaves of
//!   up to four triangles, and subtrees of up to eight triangles are leaves
//!   of the wide tree: one 8-lane SIMD packet each (two 4-lane halves);
//! - it is collapsed into nodes of eight children, opening first the child of
//!   largest area, so a ray's path has about a third of the binary levels;
//! - a node's eight child boxes are slab tested at once, on 256-bit lanes
//!   where the CPU has AVX2 (detected at run time, `avx2.rs`), else on two
//!   128-bit halves with the same operations in the same order, so both give
//!   the same bits (tested);
//! - children are visited nearest entry first; a leaf's four triangles are
//!   tested at once by the watertight test (Woop et al. 2013) that every
//!   structure uses, repeated lane by lane bit for bit.
//!
//! The box test is the binary tree's (`aabb_tree/ray.rs`): boxes widened per ray,
//! so that no computed hit lies outside a box the ray was found to miss.
//! The answers therefore equal brute force's, field for field: the smallest
//! `t`, ties to the lowest input index, and no ray slips between the
//! triangles around a shared edge or vertex.
//!
//! ```
//! use proxima::prelude::*;
//! let mesh = Mesh::from_triangles(
//!     vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(0.0, 0.0, 3.0), Vec3::new(1.0, 0.0, 3.0), Vec3::new(0.0, 1.0, 3.0)],
//!     &[[3, 4, 5], [0, 1, 2]],
//! )
//! .unwrap();
//! let tree = RayTree::build(&mesh).unwrap();
//! let hit = tree.first_hit(Vec3::new(0.2, 0.2, -1.0), Vec3::Z, 0.0, f32::INFINITY).unwrap().unwrap();
//! assert_eq!((hit.source, hit.t), (1, 1.0));
//! assert!(!tree.any_hit(Vec3::new(0.2, 0.2, -1.0), Vec3::Z, 0.0, 0.5).unwrap());
//! ```

#[cfg(target_arch = "x86_64")]
mod avx2;
mod batch;
mod collapse;
mod refit;
mod slabs;
mod walk;

use crate::aabb::Aabb;
use crate::aabb_tree::AabbTree;
use crate::build::BuildConfig;
use crate::error::BuildError;
use crate::memory::HugePageArray;
use crate::mesh::Mesh;
use crate::primitive::{PrimitiveSet, Triangle};
use crate::query::{Leaves, SpatialIndex};
use crate::simd::{Avx2, TrianglePacket};

/// Marks a leaf lane in [`RayNode::children`]: the bits below [`PAIR`] are
/// the index of its first packet.
const LEAF: u32 = 1 << 31;

/// Marks a leaf of two packets (five to eight triangles), tested at once on
/// eight lanes where the CPU has AVX2.
const PAIR: u32 = 1 << 30;

/// The packet index of a leaf lane.
const PACKET_INDEX: u32 = PAIR - 1;

/// Children of one node.
pub const WIDTH: usize = 8;

/// One node of a [`RayTree`]: the boxes of up to eight children, each bound
/// of each axis in its own row of eight lanes, and what each child is.
/// Four cache lines.
///
/// Rows: `bounds[2 k]` holds the smallest coordinate along axis `k` of each
/// child's box, `bounds[2 k + 1]` the largest, so that a ray picks its near
/// and far rows by index, without a branch. A lane without a child has an
/// empty box (`+inf` to `-inf`), which no ray enters.
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(64))]
pub struct RayNode {
    /// `[min x, max x, min y, max y, min z, max z]`, one lane per child.
    pub bounds: [[f32; WIDTH]; 6],
    /// Inner child: its node index. Leaf child: `LEAF`, `PAIR` for two
    /// packets, and the index of its first packet.
    children: [u32; WIDTH],
    /// Unused: keeps a node on whole cache lines.
    _padding: [u32; WIDTH],
}

// PERF: four whole cache lines; a change of layout must be measured.
const _: () = assert!(std::mem::size_of::<RayNode>() == 256 && std::mem::align_of::<RayNode>() == 64);

/// What one lane of a [`RayNode`] holds ([`RayTree::child`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RayChild {
    /// No child in this lane.
    Empty,
    /// The node of that index.
    Inner(usize),
    /// A leaf: these leaf-order slots (one to eight triangles).
    Leaf(std::ops::Range<usize>),
}

impl RayNode {
    const EMPTY: Self = Self {
        bounds: [
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
        ],
        children: [LEAF; WIDTH],
        _padding: [0; WIDTH],
    };

    /// The box of lane `lane` (empty for an empty lane).
    pub fn child_bounds(&self, lane: usize) -> Aabb {
        let b = &self.bounds;
        Aabb::new(
            crate::Vec3::new(b[0][lane], b[2][lane], b[4][lane]),
            crate::Vec3::new(b[1][lane], b[3][lane], b[5][lane]),
        )
    }

    fn set_child(&mut self, lane: usize, bounds: Aabb, child: u32) {
        let (min, max) = (bounds.min.to_array(), bounds.max.to_array());
        for axis in 0..3 {
            self.bounds[2 * axis][lane] = min[axis];
            self.bounds[2 * axis + 1][lane] = max[axis];
        }
        self.children[lane] = child;
    }
}

/// An 8-wide tree of triangles for ray queries (see the module notes).
#[derive(Clone, Debug)]
pub struct RayTree {
    leaves: Leaves<Triangle>,
    /// Node 0 is the root; empty for an empty tree.
    nodes: HugePageArray<RayNode>,
    /// The leaves' triangles, four to a packet; every leaf is one packet or
    /// two consecutive ones.
    packets: HugePageArray<TrianglePacket>,
    bounds: Aabb,
    /// Depth of the deepest node (the root has depth 0).
    depth: u32,
    /// Present when nodes are tested on 256-bit lanes.
    avx2: Option<Avx2>,
}

impl RayTree {
    /// The build for rays: binned SAH, leaves of up to four triangles.
    pub fn config() -> BuildConfig {
        BuildConfig::fast_queries()
    }

    /// Builds the tree over the faces of `mesh` (sources are face indices),
    /// with [`config`](Self::config).
    ///
    /// Fails as [`AabbTree::build`] does: non-finite or too large coordinates,
    /// 2^32 or more triangles.
    pub fn build(mesh: &Mesh) -> Result<Self, BuildError> {
        Self::build_set(mesh.triangles(), &Self::config())
    }

    /// Builds the binary tree of `config` over `set` ([`AabbTree::build_set`])
    /// and collapses it ([`from_tree`](Self::from_tree)).
    pub fn build_set(set: PrimitiveSet<Triangle>, config: &BuildConfig) -> Result<Self, BuildError> {
        AabbTree::build_set(set, config).map(Self::from_tree)
    }

    /// Collapses a binary tree into 8-wide nodes; its leaves of more than
    /// four triangles become nodes of packets. Linear in the number of nodes.
    pub fn from_tree(tree: AabbTree<Triangle>) -> Self {
        collapse::collapse(tree, crate::simd::detect_avx2())
    }

    /// The leaf-order triangles, their input indices and sources.
    pub fn leaves(&self) -> &Leaves<Triangle> {
        &self.leaves
    }

    /// The nodes, root first (empty for an empty tree).
    pub fn nodes(&self) -> &[RayNode] {
        &self.nodes
    }

    /// What lane `lane` of node `node` holds.
    pub fn child(&self, node: usize, lane: usize) -> RayChild {
        let child = self.nodes[node].children[lane];
        if child & LEAF == 0 {
            return RayChild::Inner(child as usize);
        }
        let bounds = self.nodes[node].child_bounds(lane);
        if bounds.min.x > bounds.max.x {
            return RayChild::Empty;
        }
        let first = (child & PACKET_INDEX) as usize;
        let packets = &self.packets[first..first + 1 + usize::from(child & PAIR != 0)];
        let count: u32 = packets.iter().map(|p| (p.fast | p.slow).count_ones()).sum();
        let start = packets[0].first as usize;
        RayChild::Leaf(start..start + count as usize)
    }

    /// Depth of the deepest node (0 when the root is the only one).
    pub fn depth(&self) -> u32 {
        self.depth
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.leaves.len()
    }

    /// `true` when the tree holds no triangle.
    pub fn is_empty(&self) -> bool {
        self.leaves.is_empty()
    }

    /// Bytes of the nodes, packets and leaf arrays.
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of_val(&self.nodes[..]) + std::mem::size_of_val(&self.packets[..]) + self.leaves.memory_bytes()
    }

    /// Whether nodes are tested on 256-bit AVX2 lanes (on CPUs that have it).
    pub fn uses_avx2(&self) -> bool {
        self.avx2.is_some()
    }

    /// Turns the AVX2 node test off, or back on where the CPU has it (on by
    /// default), to compare the two: the answers are identical.
    pub fn set_avx2(&mut self, enabled: bool) {
        self.avx2 = if enabled { crate::simd::detect_avx2() } else { None };
    }
}

impl SpatialIndex<Triangle> for RayTree {
    #[inline(always)]
    fn leaves(&self) -> &Leaves<Triangle> {
        &self.leaves
    }
    fn bounds(&self) -> Aabb {
        self.bounds
    }
}

#[cfg(test)]
mod tests {
    use super::slabs::NodeSlabs;
    use super::walk::{Lanes, Portable};
    use super::*;
    use crate::aabb_tree::RaySlabs;
    use crate::math::Vec3;
    use crate::primitive::WatertightRay;
    use crate::query::RayQuery;
    use crate::sample::Rng;

    fn vec(rng: &mut Rng, scale: f32) -> Vec3 {
        Vec3::new(
            rng.range(-scale, scale),
            rng.range(-scale, scale),
            rng.range(-scale, scale),
        )
    }

    /// Directions with zero components of either sign (infinite reciprocals),
    /// origins on box planes (0 · ∞), and ordinary ones.
    fn ray(rng: &mut Rng, k: usize, planes: &[f32]) -> (Vec3, Vec3) {
        let mut o = vec(rng, 2.0);
        let mut d = vec(rng, 1.0);
        if k.is_multiple_of(3) {
            d[(k / 3) % 3] = if k.is_multiple_of(2) { 0.0 } else { -0.0 };
        }
        if k.is_multiple_of(5) {
            o[(k / 5) % 3] = planes[k % planes.len()];
        }
        if d.abs().max_element() < 1e-3 {
            d = Vec3::Z;
        }
        (o, d)
    }

    /// The 256-bit node and leaf tests give the bits of the portable ones,
    /// lane for lane: entry parameters and crossed lanes of random nodes
    /// (some lanes empty), and hits of random triangle pairs (slivers,
    /// degenerate, tiny and huge ones among them).
    #[test]
    fn avx2_lanes_equal_portable_lanes() {
        let Some(avx2) = crate::simd::detect_avx2() else {
            eprintln!("note: this CPU has no AVX2; the 256-bit path is not used here and not tested");
            return;
        };
        let mut rng = Rng::new(41);
        let mut node = RayNode::EMPTY;
        let mut planes = Vec::new();
        let (mut crossed, mut hits) = (0, 0);
        for k in 0..20_000 {
            if k % 50 == 0 {
                node = RayNode::EMPTY;
                planes.clear();
                for lane in 0..WIDTH - k % 3 {
                    let (a, b) = (vec(&mut rng, 1.5), vec(&mut rng, 1.5));
                    let bounds = Aabb::new(a.min(b), a.max(b));
                    planes.extend([bounds.min.x, bounds.max.y, bounds.min.z]);
                    node.set_child(lane, bounds, lane as u32);
                }
            }
            let (o, d) = ray(&mut rng, k, &planes);
            let root = Aabb::new(Vec3::splat(-2.0), Vec3::splat(2.0));
            let slabs = NodeSlabs::new(&RaySlabs::new(o, d, root.min, root.max));
            let (t_lo, t_hi) = if k % 4 == 0 { (0.0, f32::INFINITY) } else { (-0.5, 1.5) };
            let (t, mask) = Portable.entries(&slabs, &node, t_lo, t_hi);
            let (t8, mask8) = avx2.entries(&slabs, &node, t_lo, t_hi);
            assert_eq!(mask, mask8, "ray ({o}, {d})");
            assert_eq!(t.map(f32::to_bits), t8.map(f32::to_bits), "ray ({o}, {d})");
            crossed += mask.count_ones();
        }
        let triangles = crate::simd::triangles(&mut rng, 8000);
        for (k, chunk) in triangles.chunks(8).enumerate() {
            let lo = TrianglePacket::new(&chunk[..4], &[0, 1, 2, 3], 0);
            let n = 1 + k % 4;
            let hi = TrianglePacket::new(&chunk[4..4 + n], &[4, 5, 6, 7][..n], 4);
            for j in 0..20 {
                let target = chunk[j % 8].a.lerp(chunk[(j + 1) % 8].b, 0.5);
                let o = target + vec(&mut rng, 2.0) * (1.0 + target.abs().max_element());
                let Some(ray) = WatertightRay::new(o, target - o) else {
                    continue;
                };
                let (t_min, t_max) = if j % 3 == 0 { (0.0, f32::INFINITY) } else { (0.5, 1.2) };
                let (bits, lane_hits, scalar) = Portable.pair_hits(&lo, &hi, &ray, t_min, t_max);
                let (bits8, lane_hits8, scalar8) = avx2.pair_hits(&lo, &hi, &ray, t_min, t_max);
                assert_eq!((bits, scalar), (bits8, scalar8));
                for lane in 0..8 {
                    if bits >> lane & 1 == 1 {
                        let (a, b) = (lane_hits[lane], lane_hits8[lane]);
                        assert_eq!(
                            (a.t.to_bits(), a.u.to_bits(), a.v.to_bits()),
                            (b.t.to_bits(), b.u.to_bits(), b.v.to_bits())
                        );
                    }
                }
                hits += bits.count_ones();
            }
        }
        assert!(
            crossed > 5000 && hits > 500,
            "{crossed} lanes crossed, {hits} triangle hits"
        );
    }

    /// Trees too deep for the small stack walk with the full one, and their
    /// batches take rays one at a time: the answers are the same. No real
    /// mesh makes such a tree, so a shallow one is marked deep.
    #[test]
    fn deep_trees_walk_alike() {
        let mesh = crate::mesh::generate::noisy_icosphere(30, 2);
        let tree = RayTree::build(&mesh).unwrap();
        let mut deep = tree.clone();
        assert!(tree.depth < super::walk::SHALLOW);
        deep.depth = super::walk::SHALLOW + 5;
        let mut rng = Rng::new(43);
        let rays: Vec<(Vec3, Vec3)> = (0..2000).map(|_| (vec(&mut rng, 2.0), vec(&mut rng, 1.0))).collect();
        let batch = tree.first_hit_batch(&rays, 0.0, f32::INFINITY);
        assert_eq!(batch, deep.first_hit_batch(&rays, 0.0, f32::INFINITY));
        let any = tree.any_hit_batch(&rays, 0.0, f32::INFINITY);
        assert_eq!(any, deep.any_hit_batch(&rays, 0.0, f32::INFINITY));
        let mut hits = 0;
        for (k, &(o, d)) in rays.iter().enumerate() {
            let single = tree.first_hit(o, d, 0.0, f32::INFINITY);
            assert_eq!(single, deep.first_hit(o, d, 0.0, f32::INFINITY));
            assert_eq!(batch[k], single);
            assert_eq!(any[k], tree.any_hit(o, d, 0.0, f32::INFINITY));
            hits += usize::from(matches!(single, Ok(Some(_))));
        }
        assert!(hits > 200, "{hits}");
    }
}
