//! Angle-weighted pseudonormals (Bærentzen and Aanæs 2005): the side of a
//! point from the normal of its closest feature.
//!
//! A face's pseudonormal is its normal; an edge's is the sum of its faces'
//! unit normals; a vertex's is the sum of its faces' unit normals weighted by
//! the faces' angles at the vertex. For a closed, consistently oriented
//! surface that does not cross itself, `(p − c) · n < 0` exactly when `p` is
//! inside, `c` the closest point and `n` the pseudonormal of the feature
//! (face, edge or vertex) `c` lies on. Elsewhere (holes, self-crossings,
//! flipped faces) the answer is only the side of the nearest sheet.
//!
//! Vertices are welded by exact position first, so meshes stored as
//! separate triangles (STL) get the normals of their shared edges.

use crate::grid::FastHash;
use crate::math::{DVec3, Vec3};
use crate::memory::prefetch;
use crate::mesh::Mesh;
use crate::surface::normals::AngleWeighted;
use rayon::prelude::*;
use std::collections::{HashMap, HashSet};

/// The feature of a triangle that a point's closest point lies on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feature {
    /// The interior of the face.
    Face,
    /// Edge `k` (from corner `k` to corner `(k + 1) % 3`).
    Edge(usize),
    /// Corner `k`.
    Vertex(usize),
}

/// The pseudonormals of a mesh's triangles (in the order of
/// [`Mesh::triangles`]).
///
/// ```
/// use proxima::prelude::*;
/// use proxima::sdf::Pseudonormals;
/// // A tetrahedron, faces outward.
/// let mesh = Mesh::from_triangles(
///     vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
///     &[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
/// )
/// .unwrap();
/// let normals = Pseudonormals::new(&mesh);
/// // Beyond the vertex at the origin (closest feature: corner 0 of face 0), and just inside it.
/// assert!(!normals.is_inside(0, Vec3::splat(-0.1)));
/// assert!(normals.is_inside(0, Vec3::splat(0.01)));
/// ```
#[derive(Clone, Debug)]
pub struct Pseudonormals {
    /// Per triangle, all a query reads: one record, about two cache lines.
    triangles: Vec<TriangleNormals>,
    /// Kept once the pseudonormals have been [refit](Self::refit).
    welding: Option<Box<Welding>>,
}

/// What a mesh's pseudonormals depend on besides its positions: the weld
/// and the edges. Pseudonormals refit to moved vertices keep it, and make
/// it again only where the weld no longer holds.
#[derive(Clone, Debug)]
struct Welding {
    /// Per vertex of the mesh, its welded vertex.
    weld: Vec<u32>,
    /// Per welded vertex, the first vertex welded to it.
    first: Vec<u32>,
    corners: Vec<[u32; 3]>,
    edges: Vec<(u64, u32)>,
    /// Per half-edge, its run of `edges` ([`edge_runs`]).
    runs: Vec<u32>,
    /// The arrays of the last refit, used again.
    positions: Vec<DVec3>,
    weighted: AngleWeighted,
}

impl Welding {
    fn new(mesh: &Mesh) -> Self {
        let (_, weld, corners) = welded(mesh);
        let mut first = Vec::new();
        for (v, &w) in weld.iter().enumerate() {
            if w as usize == first.len() {
                first.push(v as u32);
            }
        }
        let edges = half_edges(&corners, first.len());
        Self {
            runs: edge_runs(&edges),
            weld,
            first,
            corners,
            edges,
            positions: Vec::new(),
            weighted: AngleWeighted::default(),
        }
    }

    /// Whether welding `positions` gives this weld: each vertex at the
    /// position of the first vertex of its welded vertex, and those
    /// positions all different (bit for bit, with -0 and +0 alike).
    fn holds(&self, positions: &[Vec3]) -> bool {
        if positions.len() != self.weld.len() {
            return false;
        }
        let key = |v: u32| weld_key(positions[v as usize]);
        if !self
            .weld
            .par_iter()
            .enumerate()
            .with_min_len(4096)
            .all(|(v, &w)| key(v as u32) == key(self.first[w as usize]))
        {
            return false;
        }
        // The keys folded to 64 bits: equal folds of different keys only
        // make the weld again (a false "no"), never keep a wrong one.
        let fold =
            |k: [u32; 3]| ((k[0] as u64) << 32 | k[1] as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ (k[2] as u64);
        let mut seen = HashSet::with_capacity_and_hasher(self.first.len(), FastHash);
        self.first.iter().all(|&v| seen.insert(fold(key(v))))
    }
}

/// A triangle's corners and the pseudonormals of its edges and corners.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(16))]
struct TriangleNormals {
    corners: [[f32; 3]; 3],
    /// Edge `k` runs from corner `k` to corner `(k + 1) % 3`.
    edges: [[f32; 3]; 3],
    vertices: [[f32; 3]; 3],
    /// The sign certificate's integer in front of the triangle
    /// ([`SignCertificate`](super::SignCertificate)), [`NOT_CERTIFIED`] until
    /// one sets it: in the record's padding, so that a certified sign reads
    /// one record.
    front: i32,
}

/// The front of a triangle that no certificate has decided.
pub(crate) const NOT_CERTIFIED: i32 = i32::MIN;

impl Pseudonormals {
    /// The pseudonormals of `mesh`'s faces, fan-triangulated as
    /// [`Mesh::triangles`] does.
    pub fn new(mesh: &Mesh) -> Self {
        let (positions, corners) = welded_triangles(mesh);
        let edges = half_edges(&corners, positions.len());
        Self::from_welded(&positions, &corners, &edges)
    }

    /// The pseudonormals of `mesh`, whose vertices have moved since these
    /// were made (the same faces): equal to [`new`](Self::new)'s. The weld
    /// and the edges of the last refit are kept where the weld still holds,
    /// so that a mesh moved again and again is not welded and its edges
    /// are not sorted each time.
    pub(crate) fn refit(&mut self, mesh: &Mesh) {
        let positions = mesh.positions();
        let mut welding = match self.welding.take() {
            Some(welding) if welding.holds(positions) => welding,
            _ => Box::new(Welding::new(mesh)),
        };
        let Welding {
            first,
            corners,
            edges,
            runs,
            positions: welded,
            weighted,
            ..
        } = &mut *welding;
        welded.clear();
        welded.extend(first.iter().map(|&v| positions[v as usize].as_dvec3()));
        let topology = Topology { corners, edges, runs };
        self.fill(welded, &topology, weighted);
        self.welding = Some(welding);
    }

    /// The pseudonormals of triangles `corners` (vertex indices into
    /// `positions`, already welded: one index per position), `edges` their
    /// [`half_edges`].
    pub(crate) fn from_welded(positions: &[DVec3], corners: &[[u32; 3]], edges: &[(u64, u32)]) -> Self {
        let mut normals = Self {
            triangles: Vec::new(),
            welding: None,
        };
        let topology = Topology {
            corners,
            edges,
            runs: &edge_runs(edges),
        };
        normals.fill(positions, &topology, &mut AngleWeighted::default());
        normals
    }

    /// Writes the records of [`from_welded`](Self::from_welded) in place,
    /// `weighted` the arrays of the angle-weighted sums: a refit reuses
    /// both (fresh pages cost about as much as filling them). The records
    /// on all cores: each triangle sums its own edges (each edge twice, to
    /// the same bits: a sum of two commutes, a longer run is summed in the
    /// order of `edges`).
    fn fill(&mut self, positions: &[DVec3], topology: &Topology, weighted: &mut AngleWeighted) {
        let Topology { corners, edges, runs } = *topology;
        weighted.compute(positions, corners);
        let (normals, vertices) = (&weighted.normals, &weighted.sums);
        let to_f32 = |v: DVec3| v.as_vec3().to_array();
        // The sum of the normals of the triangles around half-edge `h`'s
        // edge: an edge of two faces, by its other half; any other, its run
        // of `edges` in order.
        let edge_normal = |h: usize| {
            let run = runs[h];
            let sum = if run & NOT_PAIRED == 0 {
                normals[h / 3] + normals[run as usize / 3]
            } else {
                let start = (run & !NOT_PAIRED) as usize;
                let key = edges[start].0;
                let run = edges[start..].iter().take_while(|e| e.0 == key);
                run.fold(DVec3::ZERO, |sum, &(_, h)| sum + normals[h as usize / 3])
            };
            to_f32(sum)
        };
        let record = |t: usize, c: &[u32; 3]| TriangleNormals {
            corners: c.map(|v| to_f32(positions[v as usize])),
            edges: [0, 1, 2].map(|k| edge_normal(3 * t + k)),
            vertices: c.map(|v| to_f32(vertices[v as usize])),
            front: NOT_CERTIFIED,
        };
        if self.triangles.len() == corners.len() {
            self.triangles
                .par_iter_mut()
                .zip(corners)
                .enumerate()
                .with_min_len(1024)
                .for_each(|(t, (record_t, c))| *record_t = record(t, c));
        } else {
            self.triangles = corners
                .par_iter()
                .enumerate()
                .with_min_len(1024)
                .map(|(t, c)| record(t, c))
                .collect();
        }
    }

    /// The feature of triangle `triangle` nearest to `p` (Voronoi regions, in `f64`).
    pub fn feature(&self, triangle: u32, p: Vec3) -> Feature {
        let [a, b, c] = self.triangles[triangle as usize]
            .corners
            .map(|v| Vec3::from(v).as_dvec3());
        nearest_feature(a, b, c, p.as_dvec3())
    }

    /// Whether `p` is inside by the pseudonormal of its closest feature on
    /// triangle `triangle` (the triangle's index in [`Mesh::triangles`], as
    /// [`ClosestHit::primitive`](crate::ClosestHit) gives it). A point on the
    /// feature's tangent plane counts as outside.
    #[inline]
    pub fn is_inside(&self, triangle: u32, p: Vec3) -> bool {
        let q = p.as_dvec3();
        let (on, normal) = self.feature_normal(triangle, q);
        (q - on).dot(normal) < 0.0
    }

    /// The certificate's front of triangle `triangle` ([`NOT_CERTIFIED`]
    /// where it has none), and which side of the triangle's nearest feature
    /// `p` lies on: `(p − c) · n` and `|n|` in `f64`, `c` a point of the
    /// feature and `n` its pseudonormal (not unit length).
    /// [`is_inside`](Self::is_inside) is the first below 0; the distance
    /// along the normal is their ratio. The height is not computed (0)
    /// where there is no front.
    #[inline]
    pub(crate) fn front_and_side(&self, triangle: u32, p: Vec3) -> (i32, f64, f64) {
        let Some(record) = self.triangles.get(triangle as usize) else {
            return (NOT_CERTIFIED, 0.0, 0.0);
        };
        if record.front == NOT_CERTIFIED {
            return (NOT_CERTIFIED, 0.0, 0.0);
        }
        let q = p.as_dvec3();
        let (on, normal) = self.feature_normal(triangle, q);
        (record.front, (q - on).dot(normal), normal.length())
    }

    /// Asks the cache for triangle `triangle`'s record (both of its lines),
    /// ahead of [`front_and_side`](Self::front_and_side).
    #[inline]
    pub(crate) fn prefetch(&self, triangle: u32) {
        if let Some(record) = self.triangles.get(triangle as usize) {
            prefetch(record);
            prefetch(&record.vertices[2]);
        }
    }

    /// Sets each triangle's certified front (`fronts` in triangle order).
    pub(crate) fn set_fronts(&mut self, fronts: &[i32]) {
        debug_assert_eq!(fronts.len(), self.triangles.len());
        for (record, &front) in self.triangles.iter_mut().zip(fronts) {
            record.front = front;
        }
    }

    /// The unit pseudonormal of the feature of triangle `triangle` nearest
    /// to `p`: the outward direction there of a closed, outward-oriented
    /// surface, and the gradient of its signed distance at a point on the
    /// surface. Zero where the feature's faces cancel.
    pub fn normal(&self, triangle: u32, p: Vec3) -> DVec3 {
        self.feature_normal(triangle, p.as_dvec3()).1.normalize_or_zero()
    }

    /// A point of the nearest feature of `triangle` to `q`, and the
    /// feature's pseudonormal (not unit length).
    #[inline]
    fn feature_normal(&self, triangle: u32, q: DVec3) -> (DVec3, DVec3) {
        let record = &self.triangles[triangle as usize];
        let d = |v: [f32; 3]| Vec3::from(v).as_dvec3();
        let [a, b, c] = record.corners.map(d);
        match nearest_feature(a, b, c, q) {
            Feature::Face => (a, (b - a).cross(c - a)),
            Feature::Edge(k) => ([a, b, c][k], d(record.edges[k])),
            Feature::Vertex(k) => ([a, b, c][k], d(record.vertices[k])),
        }
    }

    /// Bytes held.
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of_val(&self.triangles[..])
    }
}

/// What the records are made of besides the positions: the welded
/// triangles, their sorted [`half_edges`] and the runs of these
/// ([`edge_runs`]).
#[derive(Clone, Copy)]
struct Topology<'a> {
    corners: &'a [[u32; 3]],
    edges: &'a [(u64, u32)],
    runs: &'a [u32],
}

/// In [`edge_runs`], the mark of a half-edge whose edge does not have
/// exactly two.
const NOT_PAIRED: u32 = 1 << 31;

/// Per half-edge (of sorted `edges`, from [`half_edges`]), its edge's other
/// half-edge where the edge has two; otherwise [`NOT_PAIRED`] and where its
/// edge's run of `edges` starts. The pseudonormals read it in triangle
/// order, on all cores: an edge's sum is then one more triangle's normal,
/// where a scatter over the sorted runs wrote every triangle's record at
/// random, on one core.
fn edge_runs(edges: &[(u64, u32)]) -> Vec<u32> {
    debug_assert!(edges.len() < NOT_PAIRED as usize);
    let mut runs = vec![0u32; edges.len()];
    let mut start = 0;
    for run in edges.chunk_by(|x, y| x.0 == y.0) {
        if let [(_, a), (_, b)] = *run {
            (runs[a as usize], runs[b as usize]) = (b, a);
        } else {
            for &(_, h) in run {
                runs[h as usize] = NOT_PAIRED | start as u32;
            }
        }
        start += run.len();
    }
    runs
}

/// Every half-edge `3t + k` (triangle t's edge from corner k to corner
/// k + 1) with its edge's key (`min << 32 | max` of its two vertices),
/// sorted by key, for `vertices` vertices: a counting sort by the smaller
/// vertex, then each vertex's few edges sorted.
pub(crate) fn half_edges(corners: &[[u32; 3]], vertices: usize) -> Vec<(u64, u32)> {
    let key = |a: u32, b: u32| ((a.min(b) as u64) << 32) | a.max(b) as u64;
    let mut start = vec![0u32; vertices + 1];
    for c in corners {
        for k in 0..3 {
            start[c[k].min(c[(k + 1) % 3]) as usize + 1] += 1;
        }
    }
    for v in 0..vertices {
        start[v + 1] += start[v];
    }
    let mut next = start.clone();
    let mut out = vec![(0u64, 0u32); 3 * corners.len()];
    for (t, c) in corners.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (c[k], c[(k + 1) % 3]);
            let slot = &mut next[a.min(b) as usize];
            out[*slot as usize] = (key(a, b), (3 * t + k) as u32);
            *slot += 1;
        }
    }
    for v in 0..vertices {
        out[start[v] as usize..start[v + 1] as usize].sort_unstable();
    }
    out
}

/// `mesh`'s positions welded ([`weld`]) in `f64`, and its triangles'
/// vertex indices ([`Mesh::triangle_vertex_indices`]) into them.
pub(crate) fn welded_triangles(mesh: &Mesh) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let (positions, _, corners) = welded(mesh);
    (positions, corners)
}

/// [`welded_triangles`], with each vertex's welded index.
fn welded(mesh: &Mesh) -> (Vec<DVec3>, Vec<u32>, Vec<[u32; 3]>) {
    let (positions, weld) = weld(mesh.positions());
    let mut corners = mesh.triangle_vertex_indices();
    for c in &mut corners {
        *c = c.map(|v| weld[v as usize]);
    }
    (positions, weld, corners)
}

/// What the weld compares: the bits of a position, with -0 and +0 alike.
fn weld_key(p: Vec3) -> [u32; 3] {
    (p + Vec3::ZERO).to_array().map(f32::to_bits)
}

/// Positions without repeats (equal bit for bit, with -0 and +0 alike), and
/// for each input vertex its welded index.
fn weld(positions: &[Vec3]) -> (Vec<DVec3>, Vec<u32>) {
    let mut index: HashMap<[u32; 3], u32> = HashMap::with_capacity(positions.len());
    let mut welded = Vec::with_capacity(positions.len());
    let map = positions
        .iter()
        .map(|p| {
            *index.entry(weld_key(*p)).or_insert_with(|| {
                welded.push(p.as_dvec3());
                (welded.len() - 1) as u32
            })
        })
        .collect();
    (welded, map)
}

/// The feature of triangle `a`, `b`, `c` whose Voronoi region holds `p`
/// (the region tests of Ericson, *Real-Time Collision Detection*, 5.1.5).
/// A degenerate triangle is treated as its three edges.
fn nearest_feature(a: DVec3, b: DVec3, c: DVec3, p: DVec3) -> Feature {
    let (ab, ac) = (b - a, c - a);
    if ab.cross(ac).length_squared() <= f64::MIN_POSITIVE {
        return nearest_edge_feature([a, b, c], p);
    }
    let ap = p - a;
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return Feature::Vertex(0);
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return Feature::Vertex(1);
    }
    if d1 * d4 - d3 * d2 <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return Feature::Edge(0);
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return Feature::Vertex(2);
    }
    if d5 * d2 - d1 * d6 <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        // Edge a–c is edge 2 (from corner 2 to corner 0).
        return Feature::Edge(2);
    }
    if d3 * d6 - d5 * d4 <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return Feature::Edge(1);
    }
    Feature::Face
}

/// The nearest feature of a triangle with no area: the nearest of its edges,
/// or of their ends.
fn nearest_edge_feature(corners: [DVec3; 3], p: DVec3) -> Feature {
    let mut best = (f64::INFINITY, Feature::Vertex(0));
    for k in 0..3 {
        let (s, e) = (corners[k], corners[(k + 1) % 3]);
        let d = e - s;
        let length2 = d.length_squared();
        let t = if length2 > 0.0 {
            ((p - s).dot(d) / length2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let feature = if t <= 0.0 {
            Feature::Vertex(k)
        } else if t >= 1.0 {
            Feature::Vertex((k + 1) % 3)
        } else {
            Feature::Edge(k)
        };
        let distance = (s + d * t - p).length_squared();
        if distance < best.0 {
            best = (distance, feature);
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn features_of_a_right_triangle() {
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        let f = |x: f64, y: f64| nearest_feature(a, b, c, DVec3::new(x, y, 1.0));
        assert_eq!(f(0.2, 0.2), Feature::Face);
        assert_eq!(f(-1.0, -1.0), Feature::Vertex(0));
        assert_eq!(f(2.0, -0.5), Feature::Vertex(1));
        assert_eq!(f(-0.5, 2.0), Feature::Vertex(2));
        assert_eq!(f(0.5, -1.0), Feature::Edge(0));
        assert_eq!(f(1.0, 1.0), Feature::Edge(1));
        assert_eq!(f(-1.0, 0.5), Feature::Edge(2));
    }

    /// Refit after refit, the pseudonormals are those made anew: while the
    /// weld holds (noise), when vertices come to share a position (the weld
    /// merges them) and when they part again.
    #[test]
    fn refits_equal_new_pseudonormals_as_the_weld_changes() {
        let mesh = crate::mesh::generate::noisy_icosphere(6, 3);
        let mut normals = Pseudonormals::new(&mesh);
        let mut rng = crate::sample::Rng::new(4);
        let rest = mesh.positions().to_vec();
        let noise = |rng: &mut crate::sample::Rng| -> Vec<Vec3> {
            rest.iter()
                .map(|p| *p + Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * 0.01)
                .collect()
        };
        let mut collapsed = noise(&mut rng);
        for k in (0..collapsed.len()).step_by(5) {
            collapsed[k] = collapsed[1];
        }
        // Vertex 7 on vertex 8's position: weld unchanged at vertex 7 itself,
        // but two welded vertices now meet.
        let mut meeting = noise(&mut rng);
        meeting[7] = meeting[8];
        let steps = [
            noise(&mut rng),
            noise(&mut rng),
            noise(&mut rng),
            collapsed,
            noise(&mut rng),
            meeting,
            rest.clone(),
        ];
        let mut moved = mesh.clone();
        let mut kept = 0;
        for (step, positions) in steps.iter().enumerate() {
            moved.set_positions(positions).unwrap();
            let held = normals.welding.as_ref().is_some_and(|w| w.holds(positions));
            kept += held as usize;
            normals.refit(&moved);
            assert!(normals.triangles == Pseudonormals::new(&moved).triangles, "step {step}");
        }
        // Kept by the second and third noise steps only: the first makes
        // the weld, the others change it.
        assert_eq!(kept, 2);
    }

    /// Each edge's pseudonormal is the sum of the unit normals of the faces
    /// on that edge, found by brute force over all faces: edges of two
    /// faces, boundary edges, and an edge of three faces (a fin).
    #[test]
    fn edge_normals_sum_the_faces_on_the_edge() {
        let fin = Mesh::from_triangles(
            vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, Vec3::new(0.5, -1.0, 0.3)],
            &[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3], [0, 1, 4]],
        )
        .unwrap();
        let closed = crate::mesh::generate::noisy_icosphere(2, 5);
        let corners = closed.triangle_vertex_indices();
        let open = Mesh::from_triangles(closed.positions().to_vec(), &corners[..corners.len() / 2]).unwrap();
        for mesh in [fin, closed, open] {
            let normals = Pseudonormals::new(&mesh);
            let (positions, corners) = welded_triangles(&mesh);
            let unit = |c: &[u32; 3]| {
                let p = c.map(|v| positions[v as usize]);
                (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero()
            };
            let has_edge = |c: &[u32; 3], a: u32, b: u32| {
                (0..3).any(|j| [c[j], c[(j + 1) % 3]] == [a, b] || [c[j], c[(j + 1) % 3]] == [b, a])
            };
            for (t, c) in corners.iter().enumerate() {
                for k in 0..3 {
                    let (a, b) = (c[k], c[(k + 1) % 3]);
                    let expected: DVec3 = corners.iter().filter(|o| has_edge(o, a, b)).map(unit).sum();
                    let got = Vec3::from(normals.triangles[t].edges[k]).as_dvec3();
                    assert!(
                        (got - expected).length() <= 1e-6 * (1.0 + expected.length()),
                        "triangle {t} edge {k}: {got} against {expected}"
                    );
                }
            }
        }
    }

    #[test]
    fn degenerate_triangles_answer_by_their_edges() {
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::X * 2.0);
        assert_eq!(nearest_feature(a, b, c, DVec3::new(0.5, 1.0, 0.0)), Feature::Edge(0));
        assert_eq!(nearest_feature(a, b, c, DVec3::new(3.0, 1.0, 0.0)), Feature::Vertex(2));
        assert_eq!(nearest_feature(a, a, a, DVec3::ONE), Feature::Vertex(0));
    }
}
