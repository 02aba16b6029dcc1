//! The winding number's side from the closest query alone, where a
//! certificate computed once per mesh proves it.
//!
//! Cap every boundary loop of the mesh `S` with a fan `T` from the loop's
//! centroid. Then `S − T` (the caps turned over) has no boundary, so its
//! winding number is an integer, constant between its sheets, and one more
//! behind a sheet than in front of it; and `w_S = w_(S−T) + w_T`. A triangle
//! is **certified** when it has an area, meets no other triangle of `S − T`
//! beyond what it shares, and each of its vertices has one disk of
//! consistently oriented faces around it, none on a boundary. Certified
//! triangles joined by their edges share the integer in front of them: it is
//! measured once per such component, at a point in front of its largest
//! triangle.
//!
//! At a query `p` whose closest point `c` lies on a certified triangle, the
//! open segment from `p` to `c` meets no triangle of `S`; when no cap lies
//! within the closest distance either, it meets none of `T`, so `p` has the
//! integer of the side of `c`'s sheet it is on, and that side is the
//! pseudonormal's (Bærentzen and Aanæs: exact on a disk of faces). So
//! `w_S(p)` is that integer plus `w_T(p)`, the caps' winding number, a
//! small tree's walk (none for a closed mesh). Elsewhere, and where `p` is
//! too near the feature's tangent plane for `f32` to tell its side, the
//! field falls back to the whole winding number. `docs/sdf.md` has the
//! proof and the measurements.

use super::pseudonormal::{NOT_CERTIFIED as UNCERTIFIED, Pseudonormals, half_edges, welded_triangles};
use super::winding::{REFINE_MARGIN, WindingNumbers};
use crate::Triangle;
use crate::build::BuildConfig;
use crate::math::{DVec3, Vec3};
use crate::mesh::Mesh;
use crate::pair::{Report, meeting_pairs};
use crate::primitive::PrimitiveSet;
use crate::query::{ClosestHit, NearestQuery, SpatialIndex};
use crate::wide_tree::WideTree;
use rayon::prelude::*;

/// The accuracy parameter of the one winding number per component.
const LABEL_BETA: f32 = 4.0;

/// How far a component's winding number may lie from an integer before the
/// component is left uncertified (the caps' and the mesh's evaluations at
/// β = 4 are far closer: about 0.01).
const LABEL_TOLERANCE: f64 = 0.2;

/// Below this fraction of the distance, a point's height over its feature's
/// tangent plane is not trusted to give its side (the pseudonormals are
/// stored in `f32`).
const SIDE_RELATIVE: f64 = 1e-4;

/// What a certificate holds, counted when it is built.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CertificateStats {
    /// Triangles of the mesh.
    pub triangles: usize,
    /// Triangles whose side the certificate decides.
    pub certified: usize,
    /// Components of certified triangles (one winding number each).
    pub components: usize,
    /// Boundary loops of the mesh, each capped by a fan.
    pub boundary_loops: usize,
    /// Triangles that meet another triangle or a cap beyond what they share.
    pub meeting: usize,
}

/// The caps of the boundary loops: their tree, for the test that no cap
/// lies between a query and its closest point, and their winding numbers.
#[derive(Debug)]
struct Caps {
    tree: WideTree<Triangle>,
    winding: WindingNumbers,
}

/// Decides the winding number's side from a closest-point answer where the
/// mesh around it is proven regular enough (see the module doc).
///
/// ```
/// use proxima::mesh::generate::noisy_icosphere;
/// use proxima::sdf::{SdfConfig, SignedDistanceField};
/// use proxima::Vec3;
/// let field = SignedDistanceField::new(&noisy_icosphere(6, 1), &SdfConfig::default()).unwrap();
/// let stats = field.certificate().unwrap().stats();
/// assert_eq!(stats.certified, stats.triangles); // closed, manifold, not self-crossing
/// assert_eq!(field.signed_distance(Vec3::ZERO).unwrap().winding_number, Some(1.0));
/// ```
#[derive(Debug)]
pub struct SignCertificate {
    /// The pseudonormals, each triangle's record holding the integer
    /// winding number of `S − T` in front of it (or none): the one record a
    /// certified query reads.
    normals: Pseudonormals,
    caps: Option<Caps>,
    /// Distances below this (2^-20 of the largest coordinate) are within
    /// the `f32` walk's rounding.
    slack: f32,
    stats: CertificateStats,
}

impl SignCertificate {
    /// The certificate of `mesh`'s triangles, `tree` built over
    /// [`Mesh::triangles`] and `winding` its winding numbers. A mesh whose
    /// crossings cannot be listed within the memory budget gets a
    /// certificate that decides nothing.
    pub fn new(mesh: &Mesh, tree: &WideTree<Triangle>, winding: &WindingNumbers) -> Self {
        let (positions, corners) = welded_triangles(mesh);
        let edges = half_edges(&corners, positions.len());
        let mut normals = Pseudonormals::from_welded(&positions, &corners, &edges);
        let bounds = tree.bounds();
        let scale = bounds.min.abs().max(bounds.max.abs()).max_element();
        let slack = scale * (1.0 / (1u32 << 20) as f32);
        let (fronts, caps, stats) = certify(&positions, &corners, &edges, tree, winding);
        normals.set_fronts(&fronts);
        Self {
            normals,
            caps,
            slack,
            stats,
        }
    }

    /// The pseudonormals that give the certified sides.
    pub fn pseudonormals(&self) -> &Pseudonormals {
        &self.normals
    }

    /// What the certificate holds.
    pub fn stats(&self) -> CertificateStats {
        self.stats
    }

    /// Asks the cache for what [`winding_number`](Self::winding_number)
    /// reads of `triangle`, a few queries ahead in a batch.
    #[inline]
    pub(crate) fn prefetch(&self, triangle: u32) {
        self.normals.prefetch(triangle);
    }

    /// The winding number at `p` whose closest answer is `closest`, when
    /// the certificate decides it: an integer plus the caps' winding number,
    /// never within [`REFINE_MARGIN`] of ½. `None` where the field must
    /// walk the whole winding number.
    #[inline]
    pub fn winding_number(&self, closest: &ClosestHit, p: Vec3) -> Option<f32> {
        let (front, height, length) = self.normals.front_and_side(closest.primitive, p);
        if front == UNCERTIFIED {
            return None;
        }
        let margin = (SIDE_RELATIVE * closest.distance as f64).max(self.slack as f64) * length;
        // NaN (a degenerate feature) falls back too.
        if height.abs().partial_cmp(&margin) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let k = front + i32::from(height < 0.0);
        let Some(caps) = &self.caps else {
            return Some(k as f32);
        };
        let reach = closest.distance * (1.0 + SIDE_RELATIVE as f32) + self.slack;
        if caps.tree.closest_within(p, reach).is_some() {
            return None;
        }
        let w = k as f32 + caps.winding.winding_number(p);
        ((w - 0.5).abs() > REFINE_MARGIN).then_some(w)
    }
}

/// Each triangle's front ([`UNCERTIFIED`] where the rule does not hold),
/// the caps and the counts: the module doc's rule on welded triangles.
fn certify(
    positions: &[DVec3],
    corners: &[[u32; 3]],
    edges: &[(u64, u32)],
    tree: &WideTree<Triangle>,
    winding: &WindingNumbers,
) -> (Vec<i32>, Option<Caps>, CertificateStats) {
    let n = corners.len();
    let mut stats = CertificateStats {
        triangles: n,
        ..CertificateStats::default()
    };
    let nothing = |stats: CertificateStats| (vec![UNCERTIFIED; n], None, stats);
    let topology = Topology::new(positions, corners, edges);
    let Some(loops) = topology.boundary_loops(positions.len()) else {
        return nothing(stats);
    };
    stats.boundary_loops = loops.len();

    // S − T: the mesh and its caps turned over, for the crossings.
    let mut all_positions: Vec<Vec3> = positions.iter().map(|p| p.as_vec3()).collect();
    let mut all_corners = corners.to_vec();
    let mut caps = Vec::new();
    for ring in &loops {
        let centre = ring.iter().map(|&v| positions[v as usize]).sum::<DVec3>() / ring.len() as f64;
        let o = all_positions.len() as u32;
        all_positions.push(centre.as_vec3());
        for (k, &u) in ring.iter().enumerate() {
            let v = ring[(k + 1) % ring.len()];
            all_corners.push([o, v, u]);
            let p = |i: u32| all_positions[i as usize];
            caps.push(Triangle::new(p(o), p(u), p(v)));
        }
    }
    let config = BuildConfig::default();
    let caps = if caps.is_empty() {
        None
    } else {
        let Ok(tree) = WideTree::build_set(PrimitiveSet::from_primitives(caps), &config) else {
            return nothing(stats);
        };
        let winding = WindingNumbers::new(&tree, winding.beta());
        Some(Caps { tree, winding })
    };
    let meeting = match &caps {
        None => meeting_pairs(tree, &all_positions, &all_corners, Report::Triangles),
        Some(_) => {
            let triangles: Vec<Triangle> = all_corners
                .iter()
                .map(|c| {
                    let p = |i: u32| all_positions[i as usize];
                    Triangle::new(p(c[0]), p(c[1]), p(c[2]))
                })
                .collect();
            match WideTree::build_set(PrimitiveSet::from_primitives(triangles), &config) {
                Ok(whole) => meeting_pairs(&whole, &all_positions, &all_corners, Report::Triangles),
                Err(_) => return nothing(stats),
            }
        }
    };
    let Ok(meeting) = meeting else {
        return nothing(stats);
    };
    let mut crossed = vec![false; n];
    for t in meeting.into_iter().flatten() {
        if let Some(c) = crossed.get_mut(t as usize) {
            *c = true;
        }
    }
    stats.meeting = crossed.iter().filter(|&&c| c).count();

    let certified: Vec<bool> = (0..n)
        .map(|t| !crossed[t] && !topology.degenerate[t] && corners[t].iter().all(|&v| !topology.bad[v as usize]))
        .collect();
    stats.certified = certified.iter().filter(|&&c| c).count();

    // Components of certified triangles through their shared edges,
    // each measured at its largest triangle.
    let mut components = UnionFind::new(n);
    for &[s, t] in &topology.neighbours {
        if certified[s as usize] && certified[t as usize] {
            components.union(s, t);
        }
    }
    let area = |t: usize| {
        let [a, b, c] = corners[t].map(|v| positions[v as usize]);
        (b - a).cross(c - a).length()
    };
    let mut largest: Vec<(u32, f64)> = vec![(u32::MAX, 0.0); n];
    for t in (0..n).filter(|&t| certified[t]) {
        let root = components.find(t as u32) as usize;
        let a = area(t);
        if largest[root].0 == u32::MAX || a > largest[root].1 {
            largest[root] = (t as u32, a);
        }
    }
    let representatives: Vec<(usize, u32)> = largest
        .iter()
        .enumerate()
        .filter(|(_, r)| r.0 != u32::MAX)
        .map(|(root, r)| (root, r.0))
        .collect();
    let labels: Vec<(usize, Option<i32>)> = representatives
        .par_iter()
        .map(|&(root, t)| (root, front_of(t, positions, corners, tree, winding, caps.as_ref())))
        .collect();
    let mut label_of = vec![UNCERTIFIED; n];
    for (root, label) in labels {
        if let Some(label) = label {
            label_of[root] = label;
            stats.components += 1;
        }
    }
    let fronts: Vec<i32> = (0..n)
        .map(|t| {
            if certified[t] {
                label_of[components.find_const(t as u32) as usize]
            } else {
                UNCERTIFIED
            }
        })
        .collect();
    stats.certified = fronts.iter().filter(|&&f| f != UNCERTIFIED).count();
    (fronts, caps, stats)
}

/// The integer winding number of `S − T` in front of triangle `t`,
/// measured at a point a quarter of its inradius above its centroid, when
/// that point's closest triangle is `t` itself, no cap is nearer, and the
/// measure lies near an integer.
fn front_of(
    t: u32,
    positions: &[DVec3],
    corners: &[[u32; 3]],
    tree: &WideTree<Triangle>,
    winding: &WindingNumbers,
    caps: Option<&Caps>,
) -> Option<i32> {
    let [a, b, c] = corners[t as usize].map(|v| positions[v as usize]);
    let normal = (b - a).cross(c - a);
    let length = normal.length();
    let perimeter = (b - a).length() + (c - b).length() + (a - c).length();
    let inradius = length / perimeter;
    let probe = ((a + b + c) / 3.0 + normal / length * (0.25 * inradius)).as_vec3();
    let height = (probe.as_dvec3() - a).dot(normal) / length;
    if height.partial_cmp(&(0.1 * inradius)) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let hit = tree.closest(probe)?;
    if hit.primitive != t {
        return None;
    }
    let mut w = winding.winding_number_at(probe, LABEL_BETA) as f64;
    if let Some(caps) = caps {
        if caps.tree.closest_within(probe, 2.0 * hit.distance).is_some() {
            return None;
        }
        w -= caps.winding.winding_number_at(probe, LABEL_BETA) as f64;
    }
    let k = w.round();
    ((w - k).abs() < LABEL_TOLERANCE).then_some(k as i32)
}

/// The mesh's edges and vertices, as the certificate needs them.
struct Topology {
    /// Triangles with no area (their corners on one line).
    degenerate: Vec<bool>,
    /// Vertices without one disk of consistently oriented faces around them:
    /// on a boundary or a non-manifold edge, with a zero-length edge or a
    /// degenerate face, or with more than one fan.
    bad: Vec<bool>,
    /// The two triangles of each edge shared by exactly two, in opposite
    /// directions.
    neighbours: Vec<[u32; 2]>,
    /// The boundary as directed edges: an edge run more times one way than
    /// the other, once per surplus, in the surplus's direction.
    boundary: Vec<(u32, u32)>,
}

impl Topology {
    fn new(positions: &[DVec3], corners: &[[u32; 3]], half_edges: &[(u64, u32)]) -> Self {
        let n = corners.len();
        let degenerate: Vec<bool> = corners
            .par_iter()
            .map(|c| {
                let [a, b, c] = c.map(|v| positions[v as usize]);
                let (ab, ac) = (b - a, c - a);
                let cross = ab.cross(ac).length_squared();
                // Corners on one line up to rounding: sin² of the angle at a.
                cross.partial_cmp(&(1e-20 * ab.length_squared() * ac.length_squared()))
                    != Some(std::cmp::Ordering::Greater)
            })
            .collect();
        let mut bad = vec![false; positions.len()];
        for (t, c) in corners.iter().enumerate() {
            if degenerate[t] {
                for &v in c {
                    bad[v as usize] = true;
                }
            }
        }
        // Corner `h = 3t + k` is corner k of triangle t; half-edge h runs
        // from it to the next corner.
        let vertex = |h: u32| corners[h as usize / 3][h as usize % 3];
        let next = |h: u32| 3 * (h / 3) + (h % 3 + 1) % 3;
        let mut fans = UnionFind::new(3 * n);
        let mut neighbours = Vec::with_capacity(3 * n / 2);
        let mut boundary = Vec::new();
        for run in half_edges.chunk_by(|x, y| x.0 == y.0) {
            let (lo, hi) = ((run[0].0 >> 32) as u32, run[0].0 as u32);
            if lo == hi {
                bad[lo as usize] = true;
                continue;
            }
            let surplus: i64 = run.iter().map(|&(_, h)| if vertex(h) == lo { 1 } else { -1 }).sum();
            let (h1, h2) = (run[0].1, run.get(1).map_or(0, |r| r.1));
            if run.len() == 2 && surplus == 0 && h1 / 3 != h2 / 3 {
                // h1 runs u → v and h2 runs v → u: the corners at u are h1
                // and next(h2), at v next(h1) and h2.
                fans.union(h1, next(h2));
                fans.union(next(h1), h2);
                neighbours.push([h1 / 3, h2 / 3]);
            } else {
                bad[lo as usize] = true;
                bad[hi as usize] = true;
            }
            let edge = if surplus > 0 { (lo, hi) } else { (hi, lo) };
            boundary.extend(std::iter::repeat_n(edge, surplus.unsigned_abs() as usize));
        }
        // One fan per vertex: all its corners joined through its edges.
        let mut fan_of = vec![u32::MAX; positions.len()];
        for h in 0..3 * n as u32 {
            let (v, root) = (vertex(h) as usize, fans.find(h));
            if fan_of[v] == u32::MAX {
                fan_of[v] = root;
            } else if fan_of[v] != root {
                bad[v] = true;
            }
        }
        Self {
            degenerate,
            bad,
            neighbours,
            boundary,
        }
    }

    /// The boundary's closed loops, each as its vertices in order (edge `k`
    /// from vertex `k` to vertex `k + 1`, the last back to the first);
    /// `None` if the directed edges do not close (they always do: the
    /// boundary of a sum of triangles enters each vertex as often as it
    /// leaves it).
    fn boundary_loops(&self, vertices: usize) -> Option<Vec<Vec<u32>>> {
        let mut edges = self.boundary.clone();
        edges.sort_unstable();
        // Each vertex's outgoing edges: edges[first[v]..first[v + 1]].
        let mut first = vec![0u32; vertices + 1];
        for &(u, _) in &edges {
            first[u as usize + 1] += 1;
        }
        for v in 0..vertices {
            first[v + 1] += first[v];
        }
        let mut cursor = first.clone();
        let mut used = vec![false; edges.len()];
        let mut loops = Vec::new();
        for start in 0..edges.len() {
            if used[start] {
                continue;
            }
            let origin = edges[start].0;
            let mut ring = Vec::new();
            let mut e = start;
            loop {
                used[e] = true;
                ring.push(edges[e].0);
                let v = edges[e].1;
                if v == origin {
                    break;
                }
                let (c, end) = (&mut cursor[v as usize], first[v as usize + 1]);
                while *c < end && used[*c as usize] {
                    *c += 1;
                }
                if *c == end {
                    return None;
                }
                e = *c as usize;
            }
            loops.push(ring);
        }
        Some(loops)
    }
}

/// Disjoint sets of `0..n` (union by size, path halving).
struct UnionFind {
    parent: Vec<u32>,
    size: Vec<u32>,
}

impl UnionFind {
    fn new(n: usize) -> Self {
        Self {
            parent: (0..n as u32).collect(),
            size: vec![1; n],
        }
    }

    fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let grand = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = grand;
            x = grand;
        }
        x
    }

    /// [`find`](Self::find) without shortening the paths.
    fn find_const(&self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            x = self.parent[x as usize];
        }
        x
    }

    fn union(&mut self, a: u32, b: u32) {
        let (mut a, mut b) = (self.find(a), self.find(b));
        if a == b {
            return;
        }
        if self.size[a as usize] < self.size[b as usize] {
            std::mem::swap(&mut a, &mut b);
        }
        self.parent[b as usize] = a;
        self.size[a as usize] += self.size[b as usize];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loops_of_an_open_box_close() {
        // A cube without its top: one boundary loop of four edges.
        let p = [
            [0, 0, 0],
            [1, 0, 0],
            [1, 1, 0],
            [0, 1, 0],
            [0, 0, 1],
            [1, 0, 1],
            [1, 1, 1],
            [0, 1, 1],
        ]
        .map(|c| DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64));
        let faces = [
            [0, 2, 1],
            [0, 3, 2],
            [0, 1, 5],
            [0, 5, 4],
            [1, 2, 6],
            [1, 6, 5],
            [2, 3, 7],
            [2, 7, 6],
            [3, 0, 4],
            [3, 4, 7],
        ];
        let topology = Topology::new(&p, &faces, &half_edges(&faces, p.len()));
        let loops = topology.boundary_loops(8).unwrap();
        assert_eq!(loops.len(), 1);
        let mut ring = loops[0].clone();
        ring.sort_unstable();
        assert_eq!(ring, [4, 5, 6, 7]);
        // The rim's vertices are bad, the bottom's are not.
        assert_eq!(topology.bad, [false, false, false, false, true, true, true, true]);
        assert_eq!(topology.neighbours.len(), 13);
    }

    #[test]
    fn a_bow_tie_vertex_has_two_fans() {
        // Two tetrahedra meeting at vertex 0 only.
        let p: Vec<DVec3> = [
            (0.0, 0.0, 0.0),
            (1.0, 0.0, 0.0),
            (0.0, 1.0, 0.0),
            (0.0, 0.0, 1.0),
            (-1.0, 0.0, 0.0),
            (0.0, -1.0, 0.0),
            (0.0, 0.0, -1.0),
        ]
        .map(|(x, y, z)| DVec3::new(x, y, z))
        .to_vec();
        let tetrahedron = |a: u32, b: u32, c: u32, d: u32| [[a, c, b], [a, b, d], [a, d, c], [b, c, d]];
        let mut faces = tetrahedron(0, 1, 2, 3).to_vec();
        faces.extend(tetrahedron(0, 4, 5, 6));
        let topology = Topology::new(&p, &faces, &half_edges(&faces, p.len()));
        assert!(topology.bad[0]);
        assert!(topology.bad[1..].iter().all(|&b| !b));
        assert!(topology.boundary.is_empty());
    }
}
