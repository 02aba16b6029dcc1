//! Oriented boxes of a triangle tree's children, for bounds that do not
//! depend on how the mesh is turned.
//!
//! An axis-aligned box of a tilted patch of surface is as thick as the patch
//! is wide; a box along the patch's own normal is as thick as the patch is
//! curved. Two meshes far apart are closest where two such patches face each
//! other, and a distance query must rule out every nearby pair of patches to
//! prove its answer: along the line of the best pair so far, axis-aligned
//! boxes of neighbouring patches overlap the answer by their width, oriented
//! ones by their curvature, so far fewer pairs stay open
//! ([`pair::distance`](crate::pair::distance), docs/perf-log.md).
//!
//! [`OrientedBounds`] holds one [`OrientedBox`] per lane of every node of a
//! [`WideTree`] of triangles, fitted to that child's triangles: the third
//! axis along their area-weighted normal, the first two along the principal
//! directions of their corners in the plane across it.

use super::{WideChild, WideTree};
use crate::math::{DVec3, Vec3};
use crate::primitive::Triangle;
use crate::query::SpatialIndex;
use rayon::prelude::*;
use std::ops::Range;

/// A box with its own axes: the points `centre + Σ s_k axes[k]` with
/// `|s_k| <= half[k]`. The axes are orthonormal within rounding.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrientedBox {
    /// The centre.
    pub centre: DVec3,
    /// The three axes (unit, orthogonal).
    pub axes: [DVec3; 3],
    /// Half the extent along each axis.
    pub half: DVec3,
    /// A corner of one of the triangles in the box (the one nearest its
    /// centre): a point of the surface, so the distance between the
    /// witnesses of two boxes bounds the distance between their triangles
    /// from above.
    pub witness: Vec3,
}

impl OrientedBox {
    /// A box of no extent at the origin (the lanes without a child).
    const EMPTY: Self = Self {
        centre: DVec3::ZERO,
        axes: [DVec3::X, DVec3::Y, DVec3::Z],
        half: DVec3::ZERO,
        witness: Vec3::ZERO,
    };

    /// The smallest box with axes along `normal` (the third) and the
    /// principal directions of `points` across it that holds every point.
    /// A zero `normal` takes the z axis.
    ///
    /// ```
    /// use proxima::{DVec3, Vec3};
    /// use proxima::wide_tree::OrientedBox;
    /// // A square tilted 45° about x: its axis-aligned box is 0.7 thick, this one is flat.
    /// let points = [Vec3::ZERO, Vec3::X, Vec3::new(0.0, 0.5, 0.5), Vec3::new(1.0, 0.5, 0.5)];
    /// let normal = DVec3::new(0.0, -1.0, 1.0);
    /// let b = OrientedBox::fit(&points, normal);
    /// assert!(b.half.z < 1e-15);
    /// assert!(b.radius_along(normal.normalize()) < 1e-15);
    /// assert!(points.contains(&b.witness));
    /// ```
    pub fn fit(points: &[Vec3], normal: DVec3) -> Self {
        if points.is_empty() {
            return Self::EMPTY;
        }
        let axes = Self::axes(points, normal);
        let mut extents = Extents::new(axes);
        for p in points {
            extents.add(*p);
        }
        extents.finish(points)
    }

    /// The axes [`fit`](Self::fit) takes for points like `sample` (a few of
    /// them do: they only steer how tight the box is).
    fn axes(sample: &[Vec3], normal: DVec3) -> [DVec3; 3] {
        let third = normal.try_normalize().unwrap_or(DVec3::Z);
        let (u, v) = third.any_orthonormal_pair();
        // The principal direction of the points across the normal: the
        // angle of the 2x2 covariance's larger eigenvector in (u, v).
        let n = sample.len() as f64;
        let mean = sample.iter().fold(DVec3::ZERO, |s, p| s + p.as_dvec3()) / n;
        let (mut uu, mut vv, mut uv) = (0.0, 0.0, 0.0);
        for p in sample {
            let p = p.as_dvec3();
            let (x, y) = ((p - mean).dot(u), (p - mean).dot(v));
            uu += x * x;
            vv += y * y;
            uv += x * y;
        }
        let angle = 0.5 * (2.0 * uv).atan2(uu - vv);
        let (sin, cos) = angle.sin_cos();
        let first = u * cos + v * sin;
        let second = third.cross(first);
        [first, second, third]
    }
}

/// The extents of points along three axes, gathered one point at a time.
struct Extents {
    axes: [DVec3; 3],
    lo: DVec3,
    hi: DVec3,
}

impl Extents {
    fn new(axes: [DVec3; 3]) -> Self {
        Self {
            axes,
            lo: DVec3::splat(f64::INFINITY),
            hi: DVec3::splat(f64::NEG_INFINITY),
        }
    }

    #[inline]
    fn add(&mut self, p: Vec3) {
        let p = p.as_dvec3();
        let s = DVec3::new(self.axes[0].dot(p), self.axes[1].dot(p), self.axes[2].dot(p));
        self.lo = self.lo.min(s);
        self.hi = self.hi.max(s);
    }

    /// The box of the points added, its witness the point of `sample`
    /// nearest its centre.
    fn finish(self, sample: &[Vec3]) -> OrientedBox {
        let Self { axes, lo, hi } = self;
        let middle = (lo + hi) * 0.5;
        let centre = axes[0] * middle.x + axes[1] * middle.y + axes[2] * middle.z;
        let witness = sample
            .iter()
            .copied()
            .min_by(|p, q| {
                let (dp, dq) = (
                    p.as_dvec3().distance_squared(centre),
                    q.as_dvec3().distance_squared(centre),
                );
                dp.total_cmp(&dq)
            })
            .unwrap_or(Vec3::ZERO);
        OrientedBox {
            centre,
            axes,
            half: (hi - lo) * 0.5,
            witness,
        }
    }
}

impl OrientedBox {
    /// Half the box's extent along the unit direction `u`:
    /// `Σ |axes[k]·u| half[k]`.
    #[inline]
    pub fn radius_along(&self, u: DVec3) -> f64 {
        self.axes[0].dot(u).abs() * self.half.x
            + self.axes[1].dot(u).abs() * self.half.y
            + self.axes[2].dot(u).abs() * self.half.z
    }
}

/// How many triangles of a subtree choose its box's axes and witness.
const SAMPLE: usize = 64;

/// An [`OrientedBox`] for every lane of every node of a [`WideTree`] of
/// triangles (lanes without a child get an empty box at the origin).
#[derive(Clone, Debug, Default)]
pub struct OrientedBounds {
    boxes: Vec<OrientedBox>,
}

impl OrientedBounds {
    /// The boxes of `tree`'s children, fitted to their triangles' corners
    /// (in the tree's frame), on all the threads of the current rayon pool.
    pub fn build(tree: &WideTree<Triangle>) -> Self {
        let ranges = node_ranges(tree);
        let primitives = tree.leaves().primitives();
        let boxes = (0..tree.nodes().len())
            .into_par_iter()
            .map_init(Vec::new, |sample: &mut Vec<Vec3>, node| {
                std::array::from_fn::<_, 4, _>(|lane| {
                    let slots = match tree.child(node, lane) {
                        WideChild::Empty => return OrientedBox::EMPTY,
                        WideChild::Inner(child) => ranges[child].clone(),
                        WideChild::Leaf(range) => range,
                    };
                    let triangles = &primitives[slots];
                    // The axes from at most SAMPLE triangles spread over
                    // the subtree; the extents from all of them.
                    let step = triangles.len().div_ceil(SAMPLE).max(1);
                    let sampled = || triangles.iter().step_by(step);
                    let normal = sampled().fold(DVec3::ZERO, |sum, t| {
                        let [a, b, c] = [t.a, t.b, t.c].map(|p| p.as_dvec3());
                        sum + (b - a).cross(c - a)
                    });
                    sample.clear();
                    sample.extend(sampled().flat_map(|t| [t.a, t.b, t.c]));
                    let mut extents = Extents::new(OrientedBox::axes(sample, normal));
                    for t in triangles {
                        extents.add(t.a);
                        extents.add(t.b);
                        extents.add(t.c);
                    }
                    extents.finish(sample)
                })
            })
            .flat_map_iter(|lanes| lanes)
            .collect();
        Self { boxes }
    }

    /// The box of lane `lane` of wide node `node`.
    #[inline]
    pub fn child(&self, node: usize, lane: usize) -> &OrientedBox {
        &self.boxes[node * 4 + lane]
    }

    /// The bytes the boxes take.
    pub fn memory_bytes(&self) -> usize {
        self.boxes.len() * size_of::<OrientedBox>()
    }
}

/// The leaf-order slots below each wide node (a contiguous range, as below
/// every binary node it was collapsed from).
fn node_ranges(tree: &WideTree<Triangle>) -> Vec<Range<usize>> {
    let nodes = tree.nodes().len();
    let mut ranges: Vec<Option<Range<usize>>> = vec![None; nodes];
    // Children are listed after their parents: fill from the back, and
    // fall back to a recursive fill where that order does not hold.
    fn fill(tree: &WideTree<Triangle>, node: usize, ranges: &mut [Option<Range<usize>>]) -> Range<usize> {
        if let Some(range) = &ranges[node] {
            return range.clone();
        }
        let mut out: Option<Range<usize>> = None;
        for lane in 0..4 {
            let range = match tree.child(node, lane) {
                WideChild::Empty => continue,
                WideChild::Inner(child) => fill(tree, child, ranges),
                WideChild::Leaf(range) => range,
            };
            out = Some(match out {
                None => range,
                Some(o) => o.start.min(range.start)..o.end.max(range.end),
            });
        }
        let out = out.unwrap_or(0..0);
        ranges[node] = Some(out.clone());
        out
    }
    for node in (0..nodes).rev() {
        fill(tree, node, &mut ranges);
    }
    ranges.into_iter().map(|r| r.unwrap_or(0..0)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::Rng;

    /// Every triangle corner below a child lies in that child's box, and
    /// its witness is one of them.
    #[test]
    fn every_corner_lies_in_its_childs_box() {
        let mesh = crate::mesh::generate::noisy_icosphere(12, 3);
        let tree = WideTree::build_set(mesh.triangles(), &Default::default()).unwrap();
        let bounds = OrientedBounds::build(&tree);
        let ranges = node_ranges(&tree);
        let primitives = tree.leaves().primitives();
        let mut checked = 0;
        for node in 0..tree.nodes().len() {
            for lane in 0..4 {
                let slots = match tree.child(node, lane) {
                    WideChild::Empty => continue,
                    WideChild::Inner(child) => ranges[child].clone(),
                    WideChild::Leaf(range) => range,
                };
                let b = bounds.child(node, lane);
                let corners = || primitives[slots.clone()].iter().flat_map(|t| [t.a, t.b, t.c]);
                assert!(
                    corners().any(|p| p == b.witness),
                    "the witness is a corner below the child"
                );
                for t in &primitives[slots.clone()] {
                    for p in [t.a, t.b, t.c] {
                        let d = p.as_dvec3() - b.centre;
                        for k in 0..3 {
                            assert!(b.axes[k].dot(d).abs() <= b.half[k] * (1.0 + 1e-12) + 1e-12);
                        }
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked > 3 * primitives.len());
    }

    /// A random unit vector.
    fn unit(rng: &mut Rng) -> DVec3 {
        DVec3::new(
            rng.range(-1.0, 1.0).into(),
            rng.range(-1.0, 1.0).into(),
            rng.range(-1.0, 1.0).into(),
        )
        .normalize()
    }

    /// A flat patch gets a flat box however it is turned, and the box's
    /// extent along any direction bounds every point's projection.
    #[test]
    fn a_flat_patch_gets_a_flat_box() {
        let mut rng = Rng::new(5);
        for _ in 0..50 {
            let normal = unit(&mut rng);
            let (u, v) = normal.any_orthonormal_pair();
            // Points of the plane rounded to f32: flat within their rounding.
            let points: Vec<Vec3> = (0..20)
                .map(|_| {
                    (u * rng.range(-1.0, 1.0) as f64 + v * rng.range(-3.0, 3.0) as f64 + DVec3::splat(7.0)).as_vec3()
                })
                .collect();
            let b = OrientedBox::fit(&points, normal);
            assert!(b.half.z < 1e-6, "{:?}", b.half);
            for _ in 0..10 {
                let dir = unit(&mut rng);
                let r = b.radius_along(dir);
                for p in &points {
                    assert!((dir.dot(p.as_dvec3()) - dir.dot(b.centre)).abs() <= r + 1e-12);
                }
            }
        }
    }
}
