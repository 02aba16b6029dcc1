//! Generalized winding numbers (Jacobson, Kavan and Sorkine-Hornung 2013),
//! fast by a tree of dipole expansions (Barill, Dickson, Schmidt, Levin and
//! Jacobson 2018).
//!
//! `w(p) = Σ Ω_t(p) / 4π` over the triangles `t`, `Ω_t` the signed solid
//! angle ([`solid_angle`](super::solid_angle)). It is 1 inside and 0 outside
//! a closed outward-oriented surface, `k` where `k` such surfaces overlap,
//! and varies smoothly across the holes of an open one; `p` is inside when
//! `w > ½`.
//!
//! A subtree of triangles seen from far away acts like a dipole: with `p̃`
//! its area-weighted centroid, `N = Σ aₜnₜ` its vector area and `M = Σ
//! aₜnₜ(cₜ − p̃)ᵀ` its first moment, its solid angle is, to second order,
//! `r·N/|r|³ + tr M/|r|³ − 3 rᵀMr/|r|⁵` with `r = p̃ − p`. The expansion
//! is used for a subtree whose bounding radius `ρ` (around `p̃`) satisfies
//! `|r| > β ρ`; nearer subtrees are opened, and the triangles of the leaves
//! reached are summed exactly. The remainder of one subtree's expansion is at
//! most `3 A ρ² / (4π (|r| − ρ)⁴)` (`A` its unsigned area; the third
//! derivatives of `1/|r|` are bounded by `3!/|r|⁴`), a worst case that the
//! cancellations of real surfaces keep far from: the measured errors are in
//! `docs/sdf.md`.
//!
//! The nodes and leaves are those of the [`WideTree`] that answers the closest
//! queries: four children's expansions are evaluated at once in `f32x4`, and
//! a leaf's triangles four at a time. Coordinates are first moved to the
//! mesh's centre and scaled by a power of two to a unit size, so that the
//! powers of `|r|` stay well inside `f32` on meshes of any scale.

#[cfg(test)]
use super::solid_angle::solid_angle;
use super::solid_angle::{solid_angle_f64, solid_angle_x4};
use crate::Triangle;
use crate::aabb::Aabb;
use crate::math::{DMat3, DVec3, Vec3, Vec3A};
use crate::memory::{HugePageArray, prefetch};
use crate::query::SpatialIndex;
#[cfg(target_arch = "x86_64")]
use crate::simd::{Avx2, Avx2Task};
use crate::wide_tree::{WideChild, WideTree};
use rayon::prelude::*;
use std::ops::Range;
use wide::{f32x4, f64x4};

/// Half the width of the band around ½ where a winding number is evaluated
/// again, more accurately, before its side is decided: three times the
/// largest error measured at the default β on the shared meshes (0.03, on
/// the thin triangles of blade.off; 0.008 at β = 2).
pub const REFINE_MARGIN: f32 = 0.1;

/// The default accuracy parameter β: a subtree is replaced by its expansion
/// when the query is farther than β times its radius. Barill et al. use 2;
/// 1.5 opens about half as many nodes near the surface, and the sides stay
/// exact by the second evaluation near ½ ([`REFINE_MARGIN`]).
pub const DEFAULT_BETA: f32 = 1.5;

/// `count` of an inner lane (a leaf lane holds its number of packets, an
/// empty lane 0).
const INNER: u32 = u32::MAX;

/// Marks a leaf lane on a walk's stack.
const LEAF_ENTRY: u32 = 1 << 31;

/// Deepest stack a walk can need: three pushes per level of a tree at most
/// [`MAX_DEPTH`](crate::build::MAX_DEPTH) deep, plus the root.
const STACK: usize = 3 * crate::build::MAX_DEPTH as usize + 4;

/// The expansions of a wide node's four children, structure of arrays.
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(64))]
struct WindingNode {
    /// Area-weighted centroid `p̃` per axis.
    centre: [[f32; 4]; 3],
    /// Vector area `N` per axis.
    normal: [[f32; 4]; 3],
    /// Symmetric part of `M`: xx, yy, zz, xy, xz, yz.
    moment: [[f32; 4]; 6],
    /// Of the second moments `T_jkl = Σ nⱼ ∫ sₖ sₗ` (`s = x − p̃`): the
    /// vector `2 Σⱼ T_jjl + Σₖ T_lkk`, per axis.
    trace2: [[f32; 4]; 3],
    /// Of the same `T`, the coefficients of the cubic form `Σ T_jkl uⱼuₖuₗ`:
    /// xxx, yyy, zzz, xxy, xxz, yyx, yyz, zzx, zzy, xyz.
    cubic: [[f32; 4]; 10],
    /// `ρ²`, `ρ` the largest distance from `p̃` to a vertex of the subtree;
    /// `+inf` for an empty lane, which is then never expanded.
    radius_squared: [f32; 4],
    /// Inner lane: the child node. Leaf lane: its first packet.
    child: [u32; 4],
    /// [`INNER`], the number of packets of a leaf, or 0 for no child.
    count: [u32; 4],
}

const _: () = assert!(std::mem::size_of::<WindingNode>() == 448);

/// Asks for all seven cache lines of a node about to be visited.
#[inline(always)]
fn prefetch_node(node: &WindingNode) {
    let bytes: &[u8] = bytemuck::bytes_of(node);
    for line in (0..std::mem::size_of::<WindingNode>()).step_by(64) {
        prefetch(&bytes[line]);
    }
}

impl WindingNode {
    const EMPTY: Self = Self {
        centre: [[0.0; 4]; 3],
        normal: [[0.0; 4]; 3],
        moment: [[0.0; 4]; 6],
        trace2: [[0.0; 4]; 3],
        cubic: [[0.0; 4]; 10],
        radius_squared: [f32::INFINITY; 4],
        child: [0; 4],
        count: [0; 4],
    };
}

/// Four leaf triangles, vertices per axis (unused lanes are all zero, a
/// degenerate triangle whose solid angle is exactly 0).
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(16))]
struct Packet {
    a: [[f32; 4]; 3],
    b: [[f32; 4]; 3],
    c: [[f32; 4]; 3],
}

/// Sums over a subtree's triangles, in `f64`, from which its expansion is made.
#[derive(Clone, Copy, Debug)]
struct Sums {
    area: f64,
    /// `Σ aₜ cₜ`.
    weighted_centre: DVec3,
    /// `N = Σ aₜ nₜ`.
    normal: DVec3,
    /// `Σ (aₜ nₜ) cₜᵀ` (column `k` holds the products with `cₜ[k]`).
    second: DMat3,
    /// `Σ nₜⱼ ∫ x xᵀ` over triangle `t`, one matrix per `j`.
    third: [DMat3; 3],
}

// Not derived: `DMat3::default()` is the identity.
impl Default for Sums {
    fn default() -> Self {
        Self {
            area: 0.0,
            weighted_centre: DVec3::ZERO,
            normal: DVec3::ZERO,
            second: DMat3::ZERO,
            third: [DMat3::ZERO; 3],
        }
    }
}

impl Sums {
    /// The sums of `triangles`, four at a time in `f64` lanes (each lane
    /// summing every fourth triangle, the lanes added at the end): the
    /// same terms as [`triangle`](Self::triangle), summed in another order.
    fn of_triangles(triangles: &[Triangle], frame: &Frame) -> Self {
        let mut lanes = LaneSums::default();
        for four in triangles.chunks(4) {
            lanes.add(four, frame);
        }
        lanes.total()
    }

    /// The sums of one triangle, one at a time (the reference the lanes
    /// are tested against).
    #[cfg(test)]
    fn triangle(t: &Triangle, frame: &Frame) -> Self {
        let [a, b, c] = [t.a, t.b, t.c].map(|v| frame.local_f64(v));
        let vector_area = 0.5 * (b - a).cross(c - a);
        let area = vector_area.length();
        let centre = (a + b + c) / 3.0;
        // ∫ x xᵀ over a triangle = (area / 12) (Σ vᵢvᵢᵀ + s sᵀ), s = Σ vᵢ;
        // times the unit normal, the area cancels.
        let outer = |v: DVec3| DMat3::from_cols(v * v.x, v * v.y, v * v.z);
        let sum = a + b + c;
        let moments = (outer(a) + outer(b) + outer(c) + outer(sum)) * (1.0 / 12.0);
        Self {
            area,
            weighted_centre: area * centre,
            normal: vector_area,
            second: outer_product(vector_area, centre),
            third: [0, 1, 2].map(|j| moments * vector_area[j]),
        }
    }

    fn add(&mut self, o: &Self) {
        self.area += o.area;
        self.weighted_centre += o.weighted_centre;
        self.normal += o.normal;
        self.second += o.second;
        for j in 0..3 {
            self.third[j] += o.third[j];
        }
    }
}

/// [`Sums`] in four lanes, the third moments kept as their six distinct
/// entries (`xx, yy, zz, xy, xz, yz`): a leaf's triangles summed four at a
/// time, with a third fewer third-moment products than the full matrices.
#[derive(Default)]
struct LaneSums {
    area: f64x4,
    weighted_centre: [f64x4; 3],
    normal: [f64x4; 3],
    /// `second[k][j]`: column `k`, row `j`.
    second: [[f64x4; 3]; 3],
    /// `third[j]`: the six entries of `Σ nⱼ ∫ x xᵀ`.
    third: [[f64x4; 6]; 3],
}

/// The entries of a symmetric 3×3 matrix that [`LaneSums`] keeps, as (row, column).
const SYMMETRIC: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];

impl LaneSums {
    /// Adds one to four triangles (a short group's last lanes are masked).
    fn add(&mut self, triangles: &[Triangle], frame: &Frame) {
        let last = triangles.len() - 1;
        let four: [&Triangle; 4] = std::array::from_fn(|lane| &triangles[lane.min(last)]);
        let real = f64x4::new(std::array::from_fn(|lane| if lane <= last { 1.0 } else { 0.0 }));
        let corner = |vertex: fn(&Triangle) -> Vec3| -> [f64x4; 3] {
            let local = four.map(|t| frame.local_f64(vertex(t)));
            [0, 1, 2].map(|axis| f64x4::new(local.map(|v| v[axis])))
        };
        let (a, b, c) = (corner(|t| t.a), corner(|t| t.b), corner(|t| t.c));
        let (ab, ac) = ([0, 1, 2].map(|i| b[i] - a[i]), [0, 1, 2].map(|i| c[i] - a[i]));
        let half = f64x4::splat(0.5) * real;
        let vector_area = [
            (ab[1] * ac[2] - ab[2] * ac[1]) * half,
            (ab[2] * ac[0] - ab[0] * ac[2]) * half,
            (ab[0] * ac[1] - ab[1] * ac[0]) * half,
        ];
        let area =
            (vector_area[0] * vector_area[0] + vector_area[1] * vector_area[1] + vector_area[2] * vector_area[2])
                .sqrt();
        let sum = [0, 1, 2].map(|i| a[i] + b[i] + c[i]);
        let centre = sum.map(|s| s * f64x4::splat(1.0 / 3.0));
        self.area += area;
        for i in 0..3 {
            self.weighted_centre[i] += area * centre[i];
            self.normal[i] += vector_area[i];
            for (second, n) in self.second[i].iter_mut().zip(vector_area) {
                *second += n * centre[i];
            }
        }
        // ∫ x xᵀ over a triangle = (area / 12) (Σ vᵢvᵢᵀ + s sᵀ); times the unit normal, the area cancels.
        let twelfth = f64x4::splat(1.0 / 12.0);
        let moments = SYMMETRIC.map(|(r, q)| (a[r] * a[q] + b[r] * b[q] + c[r] * c[q] + sum[r] * sum[q]) * twelfth);
        for (third, n) in self.third.iter_mut().zip(vector_area) {
            for (entry, m) in third.iter_mut().zip(&moments) {
                *entry += *m * n;
            }
        }
    }

    /// The lanes added up.
    fn total(&self) -> Sums {
        let sum = |v: f64x4| v.reduce_add();
        let vector = |v: &[f64x4; 3]| DVec3::new(sum(v[0]), sum(v[1]), sum(v[2]));
        let symmetric = |m: &[f64x4; 6]| {
            let mut out = DMat3::ZERO;
            for (&(r, q), &v) in SYMMETRIC.iter().zip(m) {
                let v = sum(v);
                out.col_mut(q)[r] = v;
                out.col_mut(r)[q] = v;
            }
            out
        };
        Sums {
            area: sum(self.area),
            weighted_centre: vector(&self.weighted_centre),
            normal: vector(&self.normal),
            second: DMat3::from_cols(
                vector(&self.second[0]),
                vector(&self.second[1]),
                vector(&self.second[2]),
            ),
            third: [0, 1, 2].map(|j| symmetric(&self.third[j])),
        }
    }
}

/// `u vᵀ` (column `k` is `u v[k]`).
fn outer_product(u: DVec3, v: DVec3) -> DMat3 {
    DMat3::from_cols(u * v.x, u * v.y, u * v.z)
}

/// The similarity that maps the mesh's box to a box of unit size centred
/// on the origin, by a power-of-two scale.
#[derive(Clone, Copy, Debug)]
struct Frame {
    centre: Vec3A,
    scale: f32,
}

impl Frame {
    fn new(bounds: &Aabb) -> Self {
        if bounds.is_empty() {
            return Self {
                centre: Vec3A::ZERO,
                scale: 1.0,
            };
        }
        let extent = bounds.size().max_element().max(f32::MIN_POSITIVE);
        // 2^-ceil(log2(extent)): exact, and the local box fits in [-1, 1]³.
        let scale = 2f32.powi(-(extent.log2().ceil() as i32).clamp(-126, 126));
        Self {
            centre: Vec3A::from(bounds.center()),
            scale,
        }
    }

    fn local(&self, p: Vec3) -> Vec3A {
        (Vec3A::from(p) - self.centre) * self.scale
    }

    fn local_f64(&self, p: Vec3) -> DVec3 {
        (p.as_dvec3() - Vec3::from(self.centre).as_dvec3()) * self.scale as f64
    }
}

/// Work of one winding-number query (for profiles and tests).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WindingStats {
    /// Wide nodes visited.
    pub nodes: u32,
    /// Subtrees replaced by their expansion.
    pub expansions: u32,
    /// Leaf triangles summed exactly (in packets of four, padding included).
    pub triangles: u32,
    /// Queries evaluated again at the refined accuracy, being near ½.
    pub refined: u32,
}

/// Winding numbers of a triangle mesh, fast (the tree of expansions, with
/// accuracy parameter β) or exact (every triangle, in `f64`).
///
/// ```
/// use proxima::prelude::*;
/// use proxima::mesh::generate::noisy_icosphere;
/// use proxima::sdf::WindingNumbers;
/// let mesh = noisy_icosphere(8, 1); // closed, normals outward, around the origin
/// let tree = WideTree::build_set(mesh.triangles(), &Default::default()).unwrap();
/// let winding = WindingNumbers::new(&tree, 2.0);
/// assert!(winding.winding_number(Vec3::ZERO) > 0.5); // inside
/// assert!(winding.winding_number(Vec3::splat(3.0)) < 0.5); // outside
/// let exact = proxima::sdf::winding_number_exact(tree.leaves().primitives(), Vec3::ZERO);
/// assert!((exact - 1.0).abs() < 1e-9);
/// ```
#[derive(Clone, Debug)]
pub struct WindingNumbers {
    /// One per wide node (same indices); on huge pages when large, as the
    /// wide tree's: a query's loads are mostly cache and TLB misses.
    nodes: HugePageArray<WindingNode>,
    packets: HugePageArray<Packet>,
    /// Where the lanes' expansions and packets lie, for a refit.
    layout: Layout,
    frame: Frame,
    beta: f32,
    /// Present when the walk runs compiled for AVX2 (VEX encodings of the
    /// same four-lane arithmetic: the same answers).
    #[cfg(target_arch = "x86_64")]
    avx2: Option<Avx2>,
}

impl WindingNumbers {
    /// The expansions of every subtree of `tree`, for accuracy parameter
    /// `beta` (β; [`DEFAULT_BETA`]; larger is more accurate and slower;
    /// not finite or below 1 counts as 1).
    pub fn new(tree: &WideTree<Triangle>, beta: f32) -> Self {
        let frame = Frame::new(&tree.bounds());
        // A walk's stack names a leaf lane by 4 · node + lane below bit 31;
        // a tree with 2^29 wide nodes would hold billions of triangles.
        assert!(tree.node_count() < 1 << 29, "too many wide nodes for the winding walk");
        let (layout, mut nodes) = Layout::new(tree);
        let mut packets = vec![Packet::default(); layout.slots.len()];
        fill(tree, &frame, &layout, &mut nodes, &mut packets);
        Self {
            nodes: HugePageArray::new(nodes),
            packets: HugePageArray::new(packets),
            layout,
            frame,
            beta: if beta.is_finite() { beta.max(1.0) } else { 1.0 },
            #[cfg(target_arch = "x86_64")]
            avx2: Avx2::detect(),
        }
    }

    /// The expansions again over `tree`, the tree they were made on, refit
    /// to moved triangles ([`WideTree::refit`]): equal to
    /// [`new`](Self::new) on the refit tree, without laying the tree out
    /// again or allocating.
    ///
    /// ```
    /// use proxima::prelude::*;
    /// use proxima::sdf::WindingNumbers;
    /// let mesh = proxima::mesh::generate::noisy_icosphere(6, 1);
    /// let mut tree = WideTree::build_set(mesh.triangles(), &Default::default()).unwrap();
    /// let mut winding = WindingNumbers::new(&tree, 1.5);
    /// let mut moved = mesh.clone();
    /// moved.set_positions(&mesh.positions().iter().map(|p| *p * 2.0 + Vec3::X).collect::<Vec<_>>()).unwrap();
    /// tree.refit(&moved.triangles()).unwrap();
    /// winding.refit(&tree);
    /// let p = Vec3::new(0.9, 0.3, 0.2);
    /// assert_eq!(winding.winding_number(p), WindingNumbers::new(&tree, 1.5).winding_number(p));
    /// ```
    ///
    /// # Panics
    /// When `tree`'s shape is not the one the expansions were made on.
    pub fn refit(&mut self, tree: &WideTree<Triangle>) {
        assert!(
            tree.node_count() == self.nodes.len()
                && self.layout.slots.last().map_or(0, |s| s.end as usize) <= tree.len(),
            "winding numbers refit on another tree"
        );
        self.frame = Frame::new(&tree.bounds());
        fill(
            tree,
            &self.frame,
            &self.layout,
            self.nodes.as_mut_slice(),
            self.packets.as_mut_slice(),
        );
    }

    /// Runs the walk compiled for AVX2 or not (on by default where the CPU
    /// has it), to compare the two; the answers are the same.
    pub fn set_avx2(&mut self, enabled: bool) {
        #[cfg(target_arch = "x86_64")]
        {
            self.avx2 = if enabled { Avx2::detect() } else { None };
        }
        let _ = enabled;
    }

    /// The accuracy parameter β ([`DEFAULT_BETA`] is 1.5).
    pub fn beta(&self) -> f32 {
        self.beta
    }

    /// The winding number at `p` by the tree of expansions; 0 for a mesh
    /// without triangles or a `p` that is not finite. Where the value at
    /// accuracy β lies within [`REFINE_MARGIN`] of ½, it is evaluated again
    /// at accuracy [`refined_beta`](Self::refined_beta), so that the side
    /// (`w > ½`) is right wherever `|w − ½| > 0.01`.
    pub fn winding_number(&self, p: Vec3) -> f32 {
        self.winding_number_with_stats(p, &mut WindingStats::default())
    }

    /// The accuracy parameter of the second evaluation near ½: `max(2β, 4)`.
    pub fn refined_beta(&self) -> f32 {
        (2.0 * self.beta).max(4.0)
    }

    /// [`winding_number`](Self::winding_number), adding its work to `stats`.
    #[inline]
    pub fn winding_number_with_stats(&self, p: Vec3, stats: &mut WindingStats) -> f32 {
        let w = self.walk(p, self.beta, stats);
        if (w - 0.5).abs() < REFINE_MARGIN {
            stats.refined += 1;
            return self.walk(p, self.refined_beta(), stats);
        }
        w
    }

    /// The winding number at `p` by the tree, at accuracy `beta` alone.
    pub fn winding_number_at(&self, p: Vec3, beta: f32) -> f32 {
        self.walk(p, beta, &mut WindingStats::default())
    }

    #[inline]
    fn walk(&self, p: Vec3, beta: f32, stats: &mut WindingStats) -> f32 {
        if self.nodes.is_empty() || !p.is_finite() {
            return 0.0;
        }
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = self.avx2 {
            return avx2.run(WalkTask {
                numbers: self,
                p,
                beta,
                stats,
            });
        }
        self.walk_body(p, beta, stats)
    }

    /// The walk itself; `p` finite, the tree not empty.
    #[inline(always)]
    fn walk_body(&self, p: Vec3, beta: f32, stats: &mut WindingStats) -> f32 {
        let q = self.frame.local(p);
        let (qx, qy, qz) = (f32x4::splat(q.x), f32x4::splat(q.y), f32x4::splat(q.z));
        let beta_squared = f32x4::splat(beta * beta);
        let mut far_sum = f32x4::ZERO;
        let mut near_sum = f32x4::ZERO;
        // Entries: a node's index, or `LEAF_ENTRY | 4 · node + lane` for a
        // leaf lane. Leaves wait on the stack like nodes, so that their
        // packets, prefetched when pushed, arrive while other work goes on.
        let mut stack = [0u32; STACK];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let entry = stack[top];
            if entry & LEAF_ENTRY != 0 {
                let lane_id = (entry & !LEAF_ENTRY) as usize;
                let node = &self.nodes[lane_id / 4];
                let (child, count) = (node.child[lane_id % 4] as usize, node.count[lane_id % 4] as usize);
                stats.triangles += 4 * count as u32;
                for packet in &self.packets[child..child + count] {
                    let rel = |v: &[[f32; 4]; 3]| [f32x4::new(v[0]) - qx, f32x4::new(v[1]) - qy, f32x4::new(v[2]) - qz];
                    near_sum += solid_angle_x4(rel(&packet.a), rel(&packet.b), rel(&packet.c));
                }
                continue;
            }
            let node = &self.nodes[entry as usize];
            stats.nodes += 1;
            let rx = f32x4::new(node.centre[0]) - qx;
            let ry = f32x4::new(node.centre[1]) - qy;
            let rz = f32x4::new(node.centre[2]) - qz;
            let d2 = rx * rx + ry * ry + rz * rz;
            let far = d2.simd_gt(beta_squared * f32x4::new(node.radius_squared));
            let far_bits = far.to_bitmask();
            if far_bits != 0 {
                stats.expansions += far_bits.count_ones();
                far_sum += far.select(expansion(node, [rx, ry, rz], d2), f32x4::ZERO);
            }
            let mut near = !far_bits & 0xf;
            while near != 0 {
                let lane = near.trailing_zeros() as usize;
                near &= near - 1;
                let (child, count) = (node.child[lane], node.count[lane]);
                if count == INNER {
                    prefetch_node(&self.nodes[child as usize]);
                    stack[top] = child;
                    top += 1;
                } else if count > 0 {
                    for packet in &self.packets[child as usize..(child + count) as usize] {
                        prefetch(&packet.a);
                        prefetch(&packet.c);
                    }
                    stack[top] = LEAF_ENTRY | (4 * entry + lane as u32);
                    top += 1;
                }
            }
        }
        (far_sum + near_sum).reduce_add() * (1.0 / (4.0 * std::f32::consts::PI))
    }
}

/// Where each lane's expansion and packets lie, depth first (a leaf
/// lane's packets follow those of the lanes before it, so that a subtree's
/// packets are contiguous): the tree's shape alone.
#[derive(Clone, Debug)]
struct Layout {
    /// Each packet's leaf-order slots.
    slots: Vec<Range<u32>>,
    /// Per node and lane, the packets of the lane's subtree.
    subtrees: Vec<[Range<u32>; 4]>,
}

impl Layout {
    /// The layout of `tree`, and its nodes with `child` and `count` set.
    fn new(tree: &WideTree<Triangle>) -> (Self, Vec<WindingNode>) {
        let mut nodes = vec![WindingNode::EMPTY; tree.node_count()];
        let mut layout = Self {
            slots: Vec::with_capacity(tree.len() / 3 + 1),
            subtrees: vec![[0..0, 0..0, 0..0, 0..0]; tree.node_count()],
        };
        if !nodes.is_empty() {
            layout.visit(tree, 0, &mut nodes);
        }
        (layout, nodes)
    }

    fn visit(&mut self, tree: &WideTree<Triangle>, index: usize, nodes: &mut [WindingNode]) {
        for lane in 0..4 {
            let first = self.slots.len() as u32;
            match tree.child(index, lane) {
                WideChild::Empty => {}
                WideChild::Inner(child) => {
                    nodes[index].child[lane] = child as u32;
                    nodes[index].count[lane] = INNER;
                    self.visit(tree, child, nodes);
                }
                WideChild::Leaf(leaf) => {
                    nodes[index].child[lane] = first;
                    nodes[index].count[lane] = leaf.len().div_ceil(4) as u32;
                    let (start, end) = (leaf.start as u32, leaf.end as u32);
                    self.slots.extend((start..end).step_by(4).map(|s| s..(s + 4).min(end)));
                }
            }
            self.subtrees[index][lane] = first..self.slots.len() as u32;
        }
    }
}

/// Fills the expansions and packets laid out in `layout` from `tree`'s
/// triangles, as they are now: the packets and leaf lanes in parallel,
/// the inner lanes' sums from their children's, children before parents
/// (a node's children come after it in the array), then the inner lanes'
/// expansions and every lane's radius in parallel. A refit runs it again
/// on the same layout, so that it gives what a build over the refit tree
/// gives.
fn fill(tree: &WideTree<Triangle>, frame: &Frame, layout: &Layout, nodes: &mut [WindingNode], packets: &mut [Packet]) {
    let triangles = tree.leaves().primitives();
    let slots = |r: &Range<u32>| r.start as usize..r.end as usize;
    packets
        .par_iter_mut()
        .zip(&layout.slots)
        .with_min_len(1024)
        .for_each(|(packet, range)| {
            *packet = Packet::default();
            for (i, t) in triangles[slots(range)].iter().enumerate() {
                for (corner, v) in [(&mut packet.a, t.a), (&mut packet.b, t.b), (&mut packet.c, t.c)] {
                    let local = frame.local(v);
                    for axis in 0..3 {
                        corner[axis][i] = local[axis];
                    }
                }
            }
        });
    // Each node's sums over its whole subtree: its leaf lanes' first.
    let mut totals = vec![Sums::default(); nodes.len()];
    nodes
        .par_iter_mut()
        .zip(&mut totals)
        .enumerate()
        .with_min_len(64)
        .for_each(|(index, (node, total))| {
            for lane in 0..4 {
                if matches!(node.count[lane], 0 | INNER) {
                    continue;
                }
                // The lane's slots from its packets' (not from the tree's
                // packet, one more read at random per leaf).
                let packets = slots(&layout.subtrees[index][lane]);
                let leaf =
                    &triangles[layout.slots[packets.start].start as usize..layout.slots[packets.end - 1].end as usize];
                let sums = Sums::of_triangles(leaf, frame);
                set_lane(node, lane, &sums, centre(&sums, tree, index, lane, frame));
                total.add(&sums);
            }
        });
    // Then the totals of inner lanes, children before parents (a node's
    // children come after it): only additions, on one core.
    for index in (0..nodes.len()).rev() {
        for lane in 0..4 {
            if nodes[index].count[lane] == INNER {
                let child = totals[nodes[index].child[lane] as usize];
                totals[index].add(&child);
            }
        }
    }
    // Each inner lane's expansion from its child's total, and each lane's
    // radius: the largest distance from its centre, as the walk reads it,
    // to the vertices of its subtree's packets (in `f32`, each difference
    // rounded once: relative errors of about 1e-7, which the radius's
    // rounding up covers).
    let (packets, totals) = (&*packets, &totals);
    nodes
        .par_iter_mut()
        .enumerate()
        .with_min_len(16)
        .for_each(|(index, node)| {
            for lane in 0..4 {
                if node.count[lane] == INNER {
                    let sums = &totals[node.child[lane] as usize];
                    set_lane(node, lane, sums, centre(sums, tree, index, lane, frame));
                }
            }
            for lane in 0..4 {
                if node.count[lane] == 0 {
                    continue;
                }
                let [cx, cy, cz] = node.centre.map(|axis| f32x4::splat(axis[lane]));
                let range = slots(&layout.subtrees[index][lane]);
                let mut farthest = f32x4::ZERO;
                for (packet, filled) in packets[range.clone()].iter().zip(&layout.slots[range]) {
                    let valid = f32x4::new([0, 1, 2, 3].map(|i| if i < filled.len() { 1.0 } else { 0.0 }));
                    for v in [&packet.a, &packet.b, &packet.c] {
                        let (dx, dy, dz) = (f32x4::new(v[0]) - cx, f32x4::new(v[1]) - cy, f32x4::new(v[2]) - cz);
                        farthest = farthest.max((dx * dx + dy * dy + dz * dz) * valid);
                    }
                }
                let radius_squared = farthest.to_array().into_iter().fold(0.0f32, f32::max);
                set_radius(node, lane, radius_squared as f64);
            }
        });
}

/// The expansion centre of lane `lane` of node `index` with sums `sums`:
/// its area-weighted centroid, or its box's centre where it has no area.
fn centre(sums: &Sums, tree: &WideTree<Triangle>, index: usize, lane: usize, frame: &Frame) -> DVec3 {
    if sums.area > 0.0 {
        sums.weighted_centre / sums.area
    } else {
        frame.local_f64(tree.nodes()[index].child_bounds(lane).center())
    }
}

/// [`WindingNumbers::walk_body`] as a task compiled for AVX2.
#[cfg(target_arch = "x86_64")]
struct WalkTask<'a> {
    numbers: &'a WindingNumbers,
    p: Vec3,
    beta: f32,
    stats: &'a mut WindingStats,
}

#[cfg(target_arch = "x86_64")]
impl Avx2Task for WalkTask<'_> {
    type Output = f32;
    #[inline(always)]
    fn call(self, _: Avx2) -> f32 {
        self.numbers.walk_body(self.p, self.beta, self.stats)
    }
}

/// Writes lane `lane` of `node`: the expansion about `centre` of the
/// triangles summed in `sums` (its radius is [`set_radius`]'s).
fn set_lane(node: &mut WindingNode, lane: usize, sums: &Sums, centre: DVec3) {
    let n = sums.normal;
    // First moment about the centre: M = Σ aₜnₜ(cₜ − p̃)ᵀ = second − N p̃ᵀ,
    // m(j, k) = M[j][k]; only its symmetric part reaches the expansion.
    let first = sums.second - outer_product(n, centre);
    let m = |j: usize, k: usize| first.col(k)[j];
    let sym = |j: usize, k: usize| 0.5 * (m(j, k) + m(k, j));
    // Second moments about the centre: T_j = Σ nⱼ ∫ (x − p̃)(x − p̃)ᵀ
    //   = third_j − p̃ S_jᵀ − S_j p̃ᵀ + Nⱼ p̃ p̃ᵀ, with S_j[l] = second[j][l].
    let t: [DMat3; 3] = [0, 1, 2].map(|j| {
        let s_j = DVec3::new(m(j, 0), m(j, 1), m(j, 2)) + n[j] * centre;
        sums.third[j] - outer_product(centre, s_j) - outer_product(s_j, centre) + outer_product(centre, centre) * n[j]
    });
    let tt = |j: usize, k: usize, l: usize| t[j].col(l)[k];
    let trace2 =
        [0, 1, 2].map(|l| 2.0 * (0..3).map(|j| tt(j, j, l)).sum::<f64>() + (0..3).map(|k| tt(l, k, k)).sum::<f64>());
    let (x, y, z) = (0, 1, 2);
    // Coefficient of uₐ²u_b: 2 T_a(ab) + T_b(aa); of uₓu_yu_z: 2 (T_x(yz) + T_y(xz) + T_z(xy)).
    let square_times = |a: usize, b: usize| 2.0 * tt(a, a, b) + tt(b, a, a);
    let cubic = [
        tt(x, x, x),
        tt(y, y, y),
        tt(z, z, z),
        square_times(x, y),
        square_times(x, z),
        square_times(y, x),
        square_times(y, z),
        square_times(z, x),
        square_times(z, y),
        2.0 * (tt(x, y, z) + tt(y, x, z) + tt(z, x, y)),
    ];
    for axis in 0..3 {
        node.centre[axis][lane] = centre[axis] as f32;
        node.normal[axis][lane] = n[axis] as f32;
        node.trace2[axis][lane] = trace2[axis] as f32;
    }
    let moment = [sym(0, 0), sym(1, 1), sym(2, 2), sym(0, 1), sym(0, 2), sym(1, 2)];
    for (k, value) in moment.into_iter().enumerate() {
        node.moment[k][lane] = value as f32;
    }
    for (k, value) in cubic.into_iter().enumerate() {
        node.cubic[k][lane] = value as f32;
    }
}

/// Sets lane `lane`'s squared radius: rounded up a little, so that `f32`
/// rounding never expands a subtree the query is too near to.
fn set_radius(node: &mut WindingNode, lane: usize, radius_squared: f64) {
    node.radius_squared[lane] = (radius_squared * (1.0 + 1e-5)) as f32;
}

/// The winding number at `p` of `triangles`, every solid angle in `f64`
/// (Van Oosterom–Strackee); 0 for a `p` that is not finite.
///
/// ```
/// use proxima::{Triangle, Vec3};
/// use proxima::sdf::winding_number_exact;
/// let v = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
/// let faces = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
/// let tetrahedron: Vec<Triangle> = faces.iter().map(|f| Triangle::new(v[f[0]], v[f[1]], v[f[2]])).collect();
/// assert!((winding_number_exact(&tetrahedron, Vec3::splat(0.1)) - 1.0).abs() < 1e-12);
/// // An open mesh: one face alone, seen from near its middle.
/// let w = winding_number_exact(&tetrahedron[3..], Vec3::splat(0.3));
/// assert!(w > 0.0 && w < 0.5);
/// ```
pub fn winding_number_exact(triangles: &[Triangle], p: Vec3) -> f64 {
    if !p.is_finite() {
        return 0.0;
    }
    let q = p.as_dvec3();
    let sum: f64 = triangles
        .iter()
        .map(|t| solid_angle_f64(t.a.as_dvec3() - q, t.b.as_dvec3() - q, t.c.as_dvec3() - q))
        .sum();
    sum / (4.0 * std::f64::consts::PI)
}

/// Four subtrees' expansions of the solid angle at offsets `r` (`p̃ − p`)
/// of squared length `d2`, to second order in `ρ / |r|`. Written over the
/// unit vector `u = r / |r|` so that a `d2` overflowing to infinity gives 0,
/// not NaN.
#[inline(always)]
fn expansion(node: &WindingNode, r: [f32x4; 3], d2: f32x4) -> f32x4 {
    // A true division: `recip` is an approximation good to 12 bits only.
    let inv_d = f32x4::ONE / d2.sqrt();
    let inv_d2 = inv_d * inv_d;
    let inv_d3 = inv_d2 * inv_d;
    let u = [r[0] * inv_d, r[1] * inv_d, r[2] * inv_d];
    let n = |k: usize| f32x4::new(node.normal[k]);
    let m = |k: usize| f32x4::new(node.moment[k]);
    let e = |k: usize| f32x4::new(node.trace2[k]);
    let c = |k: usize| f32x4::new(node.cubic[k]);
    // Order 0: the dipole, N·r/|r|³.
    let dipole = (u[0] * n(0) + u[1] * n(1) + u[2] * n(2)) * inv_d2;
    // Order 1: Σ ∂ₖFⱼ Mⱼₖ = (tr M − 3 uᵀMu) / |r|³.
    let trace = m(0) + m(1) + m(2);
    let quadratic = u[0] * u[0] * m(0)
        + u[1] * u[1] * m(1)
        + u[2] * u[2] * m(2)
        + f32x4::splat(2.0) * (u[0] * u[1] * m(3) + u[0] * u[2] * m(4) + u[1] * u[2] * m(5));
    let first = (trace - f32x4::splat(3.0) * quadratic) * inv_d3;
    // Order 2: ½ Σ ∂ₖ∂ₗFⱼ T_jkl = (15 Σ T_jkl uⱼuₖuₗ − 3 e·u) / (2 |r|⁴).
    let (xx, yy, zz) = (u[0] * u[0], u[1] * u[1], u[2] * u[2]);
    let cubic = u[0] * (xx * c(0) + yy * c(5) + zz * c(7))
        + u[1] * (yy * c(1) + xx * c(3) + zz * c(8))
        + u[2] * (zz * c(2) + xx * c(4) + yy * c(6))
        + u[0] * u[1] * u[2] * c(9);
    let trace2 = u[0] * e(0) + u[1] * e(1) + u[2] * e(2);
    let second = (f32x4::splat(7.5) * cubic - f32x4::splat(1.5) * trace2) * inv_d2 * inv_d2;
    dipole + first + second
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::Rng;

    /// Refit over a refit tree, the expansions and packets are a build's on
    /// that tree, bit for bit, after noise, a swirl and faces collapsed to
    /// a point.
    #[test]
    fn refit_equals_a_build_on_the_refit_tree() {
        let mesh = crate::mesh::generate::noisy_icosphere(7, 2);
        let mut tree = WideTree::build_set(mesh.triangles(), &Default::default()).unwrap();
        let mut numbers = WindingNumbers::new(&tree, DEFAULT_BETA);
        let mut rng = Rng::new(8);
        let mut moved = mesh.clone();
        for how in 0..3 {
            let positions: Vec<Vec3> = mesh
                .positions()
                .iter()
                .enumerate()
                .map(|(k, &p)| match how {
                    0 => p + Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * 0.05,
                    1 => Vec3::new(
                        p.x * p.z.cos() - p.y * p.z.sin(),
                        p.x * p.z.sin() + p.y * p.z.cos(),
                        p.z * 3.0,
                    ),
                    _ if k % 4 == 0 => Vec3::ONE,
                    _ => p,
                })
                .collect();
            moved.set_positions(&positions).unwrap();
            tree.refit(&moved.triangles()).unwrap();
            numbers.refit(&tree);
            let fresh = WindingNumbers::new(&tree, DEFAULT_BETA);
            let bytes = |n: &WindingNumbers| {
                let nodes: &[u8] = bytemuck::cast_slice(&n.nodes[..]);
                let packets: &[u8] = bytemuck::cast_slice(&n.packets[..]);
                [nodes.to_vec(), packets.to_vec()]
            };
            assert!(bytes(&numbers) == bytes(&fresh), "deformation {how}");
            for _ in 0..50 {
                let p = Vec3::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
                assert_eq!(numbers.winding_number(p).to_bits(), fresh.winding_number(p).to_bits());
            }
        }
    }

    /// The lanes sum the terms of the triangles one at a time, in another
    /// order: equal to rounding for every leaf size up to two packets and
    /// beyond, degenerate triangles included.
    #[test]
    fn lane_sums_equal_the_sums_one_at_a_time() {
        let mut rng = Rng::new(8);
        let frame = Frame::new(&Aabb::new(Vec3::splat(-3.0), Vec3::splat(5.0)));
        let flat = |s: &Sums| {
            let mut v = vec![s.area];
            v.extend(s.weighted_centre.to_array());
            v.extend(s.normal.to_array());
            v.extend(s.second.to_cols_array());
            for t in &s.third {
                v.extend(t.to_cols_array());
            }
            v
        };
        for n in 1..=11 {
            let mut v = || Vec3::new(rng.range(-3.0, 5.0), rng.range(-3.0, 5.0), rng.range(-3.0, 5.0));
            let mut triangles: Vec<Triangle> = (0..n).map(|_| Triangle::new(v(), v(), v())).collect();
            // From three on, a triangle with no area and one whose corners meet.
            if n >= 3 {
                triangles[n / 2].c = triangles[n / 2].a.lerp(triangles[n / 2].b, 0.25);
                triangles[n - 1].b = triangles[n - 1].a;
            }
            let one_by_one = triangles.iter().fold(Sums::default(), |mut sums, t| {
                sums.add(&Sums::triangle(t, &frame));
                sums
            });
            let (lanes, expected) = (flat(&Sums::of_triangles(&triangles, &frame)), flat(&one_by_one));
            for (k, (x, y)) in lanes.iter().zip(&expected).enumerate() {
                assert!(
                    (x - y).abs() <= 1e-14 * (1.0 + y.abs()),
                    "{n} triangles, term {k}: {x:e} against {y:e}"
                );
            }
            assert!(expected.iter().any(|&y| y != 0.0));
        }
    }

    /// The expansion of a patch of triangles converges to the exact solid
    /// angle as the third power of `ρ / |r|`: doubling the distance divides
    /// the error (relative to the patch's area over `|r|²`) by about 8,
    /// until it reaches the `f32` evaluation's rounding (a few times 1e-6).
    #[test]
    fn expansion_error_falls_as_the_cube_of_the_distance() {
        let mut rng = Rng::new(5);
        let frame = Frame {
            centre: Vec3A::ZERO,
            scale: 1.0,
        };
        for _ in 0..20 {
            let mut v = || Vec3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), rng.range(-0.3, 0.3));
            let triangles: Vec<Triangle> = (0..4).map(|_| Triangle::new(v(), v(), v())).collect();
            let sums = Sums::of_triangles(&triangles, &frame);
            let centre = sums.weighted_centre / sums.area;
            let mut node = WindingNode::EMPTY;
            set_lane(&mut node, 0, &sums, centre);
            set_radius(&mut node, 0, 1.0);
            let direction = DVec3::new(0.6, 0.7, 0.39).normalize();
            let mut errors = Vec::new();
            for d in [2.0, 4.0, 8.0] {
                let p = centre + direction * d;
                let r = (centre - p).as_vec3();
                let lanes = |x: f32| f32x4::new([x, 1.0, 1.0, 1.0]);
                let d2 = lanes(r.length_squared());
                let approx = expansion(&node, [lanes(r.x), lanes(r.y), lanes(r.z)], d2).to_array()[0] as f64;
                let exact = triangles.iter().map(|t| solid_angle(t, p.as_vec3())).sum::<f64>();
                errors.push(((approx - exact) / sums.area * d * d).abs());
            }
            let floor = 5e-6;
            assert!(
                errors[1] < (errors[0] / 6.0).max(floor) && errors[2] < (errors[1] / 6.0).max(floor),
                "{errors:?}"
            );
        }
    }
}
