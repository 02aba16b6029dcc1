//! What to draw, as plain data computed from the viewer state: the mesh's
//! vertex and index buffers, boxes (grid cells, tree nodes) as instances of
//! one unit cube, and an overlay of coloured lines, triangles and points
//! (query point, closest point, highlighted primitives, ray). The renderer in
//! `gl.rs` only uploads and draws these; everything here is unit-tested
//! without a window.

use proxima::math::{Mat4, Vec3};
use proxima::{Aabb, AabbTree, Mesh, RayQuery, Triangle};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// RGBA colours of everything drawn (8 bits per channel, not premultiplied;
/// all opaque). The screenshot test looks for some of them.
pub mod colors {
    /// Background of the 3D view.
    pub const BACKGROUND: [u8; 4] = [26, 28, 33, 255];
    /// Base colour of the shaded mesh (light blue).
    pub const MESH: [u8; 4] = [120, 160, 230, 255];
    /// Occupied grid cells.
    pub const CELLS: [u8; 4] = [235, 235, 235, 255];
    /// Tree node boxes.
    pub const NODES: [u8; 4] = [90, 220, 120, 255];
    /// Sphere tree node spheres.
    pub const SPHERES: [u8; 4] = [255, 140, 200, 255];
    /// The ray.
    pub const RAY: [u8; 4] = [255, 230, 0, 255];
    /// Cells the ray passes through.
    pub const RAY_CELLS: [u8; 4] = [0, 200, 90, 255];
    /// Cells the ray passes through that hold primitives.
    pub const RAY_CELLS_OCCUPIED: [u8; 4] = [255, 120, 0, 255];
    /// The first surface point the ray hits.
    pub const RAY_HIT: [u8; 4] = [0, 255, 255, 255];
    /// The line from the query point to its closest point.
    pub const QUERY_LINE: [u8; 4] = [255, 40, 40, 255];
    /// The query point marker.
    pub const QUERY: [u8; 4] = [255, 170, 0, 255];
    /// The closest-point marker (a colour nothing else uses).
    pub const CLOSEST: [u8; 4] = [255, 0, 255, 255];
    /// The closest primitive.
    pub const CLOSEST_PRIMITIVE: [u8; 4] = [255, 60, 60, 255];
    /// The other k-nearest primitives.
    pub const NEAREST: [u8; 4] = [255, 200, 40, 255];
    /// The edges of the second camera's frustum.
    pub const FRUSTUM: [u8; 4] = [200, 110, 255, 255];
    /// Primitives the frustum query selects (a colour nothing else uses).
    pub const FRUSTUM_SELECTED: [u8; 4] = [160, 255, 0, 255];
    /// The query point marker when the point is inside the mesh.
    pub const QUERY_INSIDE: [u8; 4] = [40, 110, 255, 255];
    /// The slice's colour far inside (the diverging map's blue end; red and
    /// green equal, unlike the mesh's blue, so the two can be told apart).
    pub const SLICE_INSIDE: [u8; 4] = [25, 25, 200, 255];
    /// The slice's colour far outside (the red end; green and blue equal).
    pub const SLICE_OUTSIDE: [u8; 4] = [200, 25, 25, 255];
    /// The slice's colour on the surface.
    pub const SLICE_ZERO: [u8; 4] = [255, 255, 255, 255];
    /// The zero contour of the slice: where the sign changes.
    pub const ZERO_CONTOUR: [u8; 4] = [10, 10, 10, 255];
    /// Faces of the model that meet the second mesh, or meet other faces of
    /// the model (self-intersections): hot pink, a colour nothing else uses.
    pub const PAIR_MEETING: [u8; 4] = [255, 0, 128, 255];
    /// Faces of the second mesh that meet the model (violet).
    pub const PAIR_MEETING_SECOND: [u8; 4] = [120, 40, 255, 255];
    /// The second mesh's face outlines (sand).
    pub const SECOND_MESH: [u8; 4] = [230, 200, 140, 255];
    /// The segment between the closest points of the two meshes and its ends.
    pub const PAIR_CLOSEST: [u8; 4] = [0, 255, 128, 255];
    /// The animation's fan rays that miss the mesh (a dim olive, so that the
    /// hits' yellow stands out).
    pub const FAN_MISS: [u8; 4] = [110, 110, 70, 255];
}

/// Diameter in pixels of the query and closest-point markers.
pub const MARKER_SIZE: f32 = 11.0;
/// Diameter in pixels of highlighted vertices.
pub const VERTEX_SIZE: f32 = 6.0;

static NEXT_ID: AtomicU64 = AtomicU64::new(1);

/// A fresh identity for a buffer: the renderer uploads a buffer again only
/// when the identity it holds changes.
pub fn next_id() -> u64 {
    NEXT_ID.fetch_add(1, Ordering::Relaxed)
}

/// One vertex of the shaded mesh.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct MeshVertex {
    /// Position.
    pub position: [f32; 3],
    /// Unit normal (area-weighted mean of the faces around the vertex).
    pub normal: [f32; 3],
}

/// The mesh as indexed triangles.
#[derive(Debug, Default)]
pub struct MeshBuffers {
    /// Identity for re-upload (see [`next_id`]).
    pub id: u64,
    /// One vertex per mesh vertex.
    pub vertices: Vec<MeshVertex>,
    /// Three indices per triangle (faces fan-triangulated).
    pub indices: Vec<u32>,
}

/// Vertex normals and triangle indices of `mesh`. A vertex no face uses gets
/// the normal +y; polygons are fan-triangulated as in [`Mesh::triangles`].
pub fn mesh_buffers(mesh: &Mesh) -> MeshBuffers {
    let positions = mesh.positions();
    let mut normals = vec![Vec3::ZERO; positions.len()];
    let mut indices = Vec::with_capacity(3 * mesh.triangle_count());
    for face in mesh.faces() {
        for i in 1..face.len() - 1 {
            let [a, b, c] = [face[0], face[i], face[i + 1]];
            let (pa, pb, pc) = (positions[a as usize], positions[b as usize], positions[c as usize]);
            // Twice the area times the unit normal: larger faces weigh more.
            let n = (pb - pa).cross(pc - pa);
            for v in [a, b, c] {
                normals[v as usize] += n;
            }
            indices.extend_from_slice(&[a, b, c]);
        }
    }
    let vertices = positions
        .iter()
        .zip(&normals)
        .map(|(p, n)| MeshVertex {
            position: p.to_array(),
            normal: n.normalize_or(Vec3::Y).to_array(),
        })
        .collect();
    MeshBuffers {
        id: next_id(),
        vertices,
        indices,
    }
}

/// Above this many triangles a mesh gets a coarse copy drawn while the
/// camera moves (see [`decimate`]).
pub const INTERACTIVE_TRIANGLE_LIMIT: usize = 200_000;

/// A coarse copy of `buffers` by vertex clustering: vertices are merged per
/// cell of a grid with `resolution` cells along the longest side of their
/// bounding box (at the mean position, with the summed normal), and
/// triangles that collapse are dropped. Linear time; used while the camera
/// moves, where a few hundred thousand triangles fewer keep software
/// rendering interactive.
pub fn decimate(buffers: &MeshBuffers, resolution: u32) -> MeshBuffers {
    let bounds = Aabb::from_points(buffers.vertices.iter().map(|v| Vec3::from_array(v.position)));
    let resolution = resolution.max(1) as f32;
    let cell = (bounds.size().max_element() / resolution).max(f32::MIN_POSITIVE);
    let mut clusters: std::collections::HashMap<[i32; 3], u32> = std::collections::HashMap::new();
    let mut sums: Vec<(Vec3, Vec3, u32)> = Vec::new();
    let remap: Vec<u32> = buffers
        .vertices
        .iter()
        .map(|v| {
            let p = Vec3::from_array(v.position);
            let c = ((p - bounds.min) / cell).floor();
            let key = [c.x as i32, c.y as i32, c.z as i32];
            let id = *clusters.entry(key).or_insert_with(|| {
                sums.push((Vec3::ZERO, Vec3::ZERO, 0));
                (sums.len() - 1) as u32
            });
            let s = &mut sums[id as usize];
            s.0 += p;
            s.1 += Vec3::from_array(v.normal);
            s.2 += 1;
            id
        })
        .collect();
    let vertices = sums
        .iter()
        .map(|(p, n, count)| MeshVertex {
            position: (*p / *count as f32).to_array(),
            normal: n.normalize_or(Vec3::Y).to_array(),
        })
        .collect();
    let mut indices = Vec::new();
    for t in buffers.indices.chunks_exact(3) {
        let [a, b, c] = [remap[t[0] as usize], remap[t[1] as usize], remap[t[2] as usize]];
        if a != b && b != c && a != c {
            indices.extend_from_slice(&[a, b, c]);
        }
    }
    MeshBuffers {
        id: next_id(),
        vertices,
        indices,
    }
}

/// One box drawn as an instance of the unit cube: `min + corner * size`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct BoxInstance {
    /// Minimum corner.
    pub min: [f32; 3],
    /// Extents.
    pub size: [f32; 3],
}

impl BoxInstance {
    /// The instance drawing `b`.
    pub fn from_aabb(b: &Aabb) -> Self {
        Self {
            min: b.min.to_array(),
            size: b.size().to_array(),
        }
    }

    /// The box it draws.
    pub fn aabb(&self) -> Aabb {
        let min = Vec3::from_array(self.min);
        Aabb::new(min, min + Vec3::from_array(self.size))
    }
}

/// A set of boxes drawn in one instanced call.
#[derive(Debug, Default)]
pub struct BoxSet {
    /// Identity for re-upload (see [`next_id`]).
    pub id: u64,
    /// The boxes.
    pub boxes: Vec<BoxInstance>,
}

impl BoxSet {
    /// A set with a fresh identity.
    pub fn new(boxes: impl IntoIterator<Item = Aabb>) -> Self {
        Self {
            id: next_id(),
            boxes: boxes.into_iter().map(|b| BoxInstance::from_aabb(&b)).collect(),
        }
    }

    /// Number of boxes.
    pub fn len(&self) -> usize {
        self.boxes.len()
    }

    /// `true` when there is no box.
    pub fn is_empty(&self) -> bool {
        self.boxes.is_empty()
    }
}

/// The 12 edges of the unit cube as 24 line end points.
pub fn unit_cube_lines() -> [[f32; 3]; 24] {
    let mut out = [[0.0; 3]; 24];
    let mut n = 0;
    // For each axis, the four edges parallel to it.
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        for (a, b) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
            for end in [0.0, 1.0] {
                let mut p = [0.0; 3];
                p[axis] = end;
                p[u] = a;
                p[v] = b;
                out[n] = p;
                n += 1;
            }
        }
    }
    out
}

/// The boxes of the nodes of `tree` at exactly `depth` (the root is depth
/// 0), in node order. Leaves above that depth are not included.
pub fn nodes_at_depth<T>(tree: &AabbTree<T>, depth: u32) -> Vec<Aabb> {
    let mut out = Vec::new();
    if tree.root().is_none() {
        return out;
    }
    let mut stack = vec![(0usize, 0u32)];
    while let Some((index, d)) = stack.pop() {
        let node = tree.node(index);
        if d == depth {
            out.push(node.bounds());
        } else if !node.is_leaf() {
            let [a, b] = node.children();
            // Pushed in reverse so the walk is left first.
            stack.push((b as usize, d + 1));
            stack.push((a as usize, d + 1));
        }
    }
    out
}

/// A primitive's geometry, for highlighting.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A vertex.
    Point(Vec3),
    /// An edge.
    Segment(Vec3, Vec3),
    /// A face, its vertices in order.
    Polygon(Vec<Vec3>),
}

impl Shape {
    /// Distance from `p` to the shape (a polygon counts as its fan triangles).
    pub fn distance_to(&self, p: Vec3) -> f32 {
        use proxima::ClosestPoint;
        let pa = p.into();
        match self {
            Shape::Point(v) => (p - *v).length(),
            Shape::Segment(a, b) => proxima::LineSegment::new(*a, *b).distance_squared(pa).sqrt(),
            Shape::Polygon(v) => (1..v.len().saturating_sub(1))
                .map(|i| Triangle::new(v[0], v[i], v[i + 1]).distance_squared(pa).sqrt())
                .fold(f32::INFINITY, f32::min),
        }
    }
}

/// One vertex of the overlay: position, colour and (for points) size in pixels.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ColorVertex {
    /// Position.
    pub position: [f32; 3],
    /// RGBA, 8 bits each.
    pub color: [u8; 4],
    /// Point diameter in pixels (ignored for lines and triangles).
    pub size: f32,
}

/// Coloured lines, triangles and points drawn over the mesh. `lines`,
/// `triangles` and `points` are depth-tested; `markers` are drawn last, on
/// top of everything.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overlay {
    /// Pairs of line end points.
    pub lines: Vec<ColorVertex>,
    /// Triples of triangle corners.
    pub triangles: Vec<ColorVertex>,
    /// Points, depth-tested.
    pub points: Vec<ColorVertex>,
    /// Points always visible.
    pub markers: Vec<ColorVertex>,
}

fn vertex(p: Vec3, color: [u8; 4], size: f32) -> ColorVertex {
    ColorVertex {
        position: p.to_array(),
        color,
        size,
    }
}

impl Overlay {
    /// Adds the segment `a`–`b`.
    pub fn line(&mut self, a: Vec3, b: Vec3, color: [u8; 4]) {
        self.lines.push(vertex(a, color, 1.0));
        self.lines.push(vertex(b, color, 1.0));
    }

    /// Adds a depth-tested point.
    pub fn point(&mut self, p: Vec3, color: [u8; 4], size: f32) {
        self.points.push(vertex(p, color, size));
    }

    /// Adds a point drawn on top of everything.
    pub fn marker(&mut self, p: Vec3, color: [u8; 4], size: f32) {
        self.markers.push(vertex(p, color, size));
    }

    /// Adds a primitive: a vertex as a point, an edge as a line, a face as its
    /// outline and (with `fill`) its fan triangles.
    pub fn shape(&mut self, shape: &Shape, color: [u8; 4], fill: bool) {
        match shape {
            Shape::Point(p) => self.point(*p, color, VERTEX_SIZE),
            Shape::Segment(a, b) => self.line(*a, *b, color),
            Shape::Polygon(v) => {
                for i in 0..v.len() {
                    self.line(v[i], v[(i + 1) % v.len()], color);
                }
                if fill {
                    for i in 1..v.len().saturating_sub(1) {
                        for p in [v[0], v[i], v[i + 1]] {
                            self.triangles.push(vertex(p, color, 1.0));
                        }
                    }
                }
            }
        }
    }

    /// `true` when nothing is drawn.
    pub fn is_empty(&self) -> bool {
        self.lines.is_empty() && self.triangles.is_empty() && self.points.is_empty() && self.markers.is_empty()
    }

    /// Adds `other` to this overlay.
    pub fn append(&mut self, other: Overlay) {
        self.lines.extend(other.lines);
        self.triangles.extend(other.triangles);
        self.points.extend(other.points);
        self.markers.extend(other.markers);
    }
}

/// A surface point under the mouse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pick {
    /// Where the ray meets the surface.
    pub point: Vec3,
    /// Unit normal of the face hit, turned towards the ray's origin.
    pub normal: Vec3,
    /// Ray parameter of the hit.
    pub t: f32,
    /// The face hit.
    pub face: u32,
}

impl Pick {
    /// The query point `offset` away from the surface, on the viewer's side.
    pub fn offset(&self, offset: f32) -> Vec3 {
        self.point + offset * self.normal
    }
}

/// The first face of `structure` that the ray `origin + t · direction`
/// (t ≥ 0) meets, by the library's [`RayQuery::first_hit`] (its ray
/// checks and its tie rule: the lowest input index at equal `t`), with the
/// normal of the face's triangle (`triangles` in build-input order) turned
/// towards the ray's origin. `None` for a miss or a ray the library
/// refuses (zero or non-finite direction, non-finite origin).
pub fn pick<S: RayQuery<Triangle>>(
    structure: &S,
    triangles: &[Triangle],
    origin: Vec3,
    direction: Vec3,
) -> Option<Pick> {
    let hit = structure.first_hit(origin, direction, 0.0, f32::INFINITY).ok()??;
    let triangle = triangles.get(hit.primitive as usize)?;
    let mut normal = triangle.scaled_normal().normalize_or(-direction);
    if normal.dot(direction) > 0.0 {
        normal = -normal;
    }
    Some(Pick {
        point: origin + hit.t * direction,
        normal,
        t: hit.t,
        face: hit.source,
    })
}

/// A picture laid on a rectangle in space: the signed-distance slice as a
/// texture of `size` texels, pixel `(i, j)` at `pixels[i + size[0] j]`,
/// stretched over the quad `corners` (texel rows along `corners[0] →
/// corners[1]`, columns along `corners[0] → corners[3]`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SliceImage {
    /// Identity for re-upload (see [`next_id`]).
    pub id: u64,
    /// Width and height in texels.
    pub size: [usize; 2],
    /// RGBA texels, rows first.
    pub pixels: Vec<[u8; 4]>,
    /// The quad's corners in order around it.
    pub corners: [Vec3; 4],
}

/// A set of boxes and the colour to draw them in.
#[derive(Clone, Debug)]
pub struct BoxLayer {
    /// The boxes.
    pub set: Arc<BoxSet>,
    /// Their colour.
    pub color: [u8; 4],
}

/// Everything the renderer needs for one frame of the 3D view.
#[derive(Clone, Debug, Default)]
pub struct DrawFrame {
    /// World → clip space.
    pub view_projection: Mat4,
    /// Eye position (for the head light).
    pub eye: Vec3,
    /// The shaded mesh, if shown.
    pub mesh: Option<Arc<MeshBuffers>>,
    /// Its coarse copy, drawn instead while the camera moves (large meshes only).
    pub mesh_lod: Option<Arc<MeshBuffers>>,
    /// Draw the mesh's vertices as points (a mesh without faces).
    pub mesh_points: bool,
    /// Boxes: grid cells, ray cells, tree nodes.
    pub boxes: Vec<BoxLayer>,
    /// Lines, triangles, points and markers.
    pub overlay: Overlay,
    /// The signed-distance slice, if shown.
    pub slice: Option<Arc<SliceImage>>,
    /// Mesh fragments where `clip · (x, y, z, 1) > 0` are not drawn (all
    /// zero: nothing is cut away).
    pub clip_plane: [f32; 4],
    /// The camera is moving: draw many boxes as points (one per box) to
    /// keep the frame rate up; the full picture follows when it stops.
    pub interactive: bool,
    /// Draw the picture even if it did not change (for measuring frame times).
    pub redraw: bool,
}

/// Above this many boxes in a frame, an interactive frame draws boxes as points.
pub const INTERACTIVE_BOX_LIMIT: usize = 20_000;

/// Everything that decides a frame's picture: two frames with equal keys
/// (at the same size) draw the same pixels, so the last one can be reused.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameKey {
    view_projection: [f32; 16],
    eye: [f32; 3],
    mesh: Option<u64>,
    mesh_points: bool,
    boxes: Vec<(u64, [u8; 4])>,
    overlay: Overlay,
    slice: Option<u64>,
    clip_plane: [f32; 4],
    boxes_as_points: bool,
}

impl DrawFrame {
    /// Number of boxes in all layers.
    pub fn box_count(&self) -> usize {
        self.boxes.iter().map(|l| l.set.len()).sum()
    }

    /// The mesh buffers drawn this frame: the coarse copy while the camera moves.
    pub fn mesh_drawn(&self) -> Option<&Arc<MeshBuffers>> {
        if self.interactive && self.mesh_lod.is_some() {
            self.mesh_lod.as_ref()
        } else {
            self.mesh.as_ref()
        }
    }

    /// `true` when the boxes are drawn as points this frame.
    pub fn boxes_as_points(&self) -> bool {
        self.interactive && self.box_count() > INTERACTIVE_BOX_LIMIT
    }

    /// What decides the picture (see [`FrameKey`]).
    pub fn key(&self) -> FrameKey {
        FrameKey {
            view_projection: self.view_projection.to_cols_array(),
            eye: self.eye.to_array(),
            mesh: self.mesh_drawn().map(|m| m.id),
            mesh_points: self.mesh_points,
            boxes: self.boxes.iter().map(|l| (l.set.id, l.color)).collect(),
            overlay: self.overlay.clone(),
            slice: self.slice.as_ref().map(|s| s.id),
            clip_plane: self.clip_plane,
            boxes_as_points: self.boxes_as_points(),
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use proxima::BuildConfig;
    use proxima::primitive::WatertightRay;

    /// A unit cube of six quads (shared with the model's tests).
    pub(crate) fn cube_mesh() -> Mesh {
        let p: Vec<Vec3> = (0..8)
            .map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32))
            .collect();
        let faces = vec![
            vec![0, 2, 3, 1],
            vec![4, 5, 7, 6],
            vec![0, 1, 5, 4],
            vec![2, 6, 7, 3],
            vec![0, 4, 6, 2],
            vec![1, 3, 7, 5],
        ];
        Mesh::from_faces(p, &faces).unwrap()
    }

    #[test]
    fn mesh_buffers_fan_triangulate_and_normals_point_out() {
        let mesh = cube_mesh();
        let b = mesh_buffers(&mesh);
        assert_eq!(b.vertices.len(), 8);
        assert_eq!(b.indices.len(), 6 * 2 * 3);
        assert!(b.indices.iter().all(|&i| (i as usize) < b.vertices.len()));
        let center = Vec3::splat(0.5);
        for v in &b.vertices {
            let n = Vec3::from_array(v.normal);
            assert!((n.length() - 1.0).abs() < 1e-5);
            // Each corner's normal points away from the center (the fan
            // triangulation weighs the three faces unevenly).
            let out = (Vec3::from_array(v.position) - center).normalize();
            assert!(n.dot(out) > 0.7, "{n} vs {out}");
        }
        assert_ne!(b.id, mesh_buffers(&mesh).id);
    }

    #[test]
    fn unused_vertices_get_a_unit_normal() {
        let mesh = Mesh::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ONE], &[[0, 1, 2]]).unwrap();
        let b = mesh_buffers(&mesh);
        assert_eq!(b.vertices[3].normal, [0.0, 1.0, 0.0]);
        assert_eq!(b.vertices[0].normal, [0.0, 0.0, 1.0]);
    }

    #[test]
    fn decimation_merges_vertices_and_drops_collapsed_triangles() {
        let mesh = proxima::mesh::generate::noisy_icosphere(40, 3);
        let full = mesh_buffers(&mesh);
        let coarse = decimate(&full, 16);
        assert!(
            coarse.vertices.len() < full.vertices.len() / 4,
            "{}",
            coarse.vertices.len()
        );
        assert!(coarse.indices.len() < full.indices.len() / 4);
        assert!(!coarse.indices.is_empty() && coarse.indices.len().is_multiple_of(3));
        assert!(coarse.indices.iter().all(|&i| (i as usize) < coarse.vertices.len()));
        for t in coarse.indices.chunks(3) {
            assert!(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
        }
        // Merged vertices stay near the surface (radius about 1).
        for v in &coarse.vertices {
            let r = Vec3::from_array(v.position).length();
            assert!((0.6..1.4).contains(&r), "{r}");
        }
        // A fine grid keeps everything.
        let same = decimate(&full, 100_000);
        assert_eq!(same.indices.len(), full.indices.len());
        assert_ne!(same.id, full.id);
        assert!(decimate(&MeshBuffers::default(), 10).indices.is_empty());
    }

    #[test]
    fn the_coarse_mesh_is_drawn_only_while_moving() {
        let full = Arc::new(mesh_buffers(&cube_mesh()));
        let coarse = Arc::new(decimate(&full, 1));
        let mut frame = DrawFrame {
            mesh: Some(full.clone()),
            mesh_lod: Some(coarse.clone()),
            ..DrawFrame::default()
        };
        assert_eq!(frame.mesh_drawn().unwrap().id, full.id);
        let still = frame.key();
        frame.interactive = true;
        assert_eq!(frame.mesh_drawn().unwrap().id, coarse.id);
        assert_ne!(frame.key(), still);
    }

    #[test]
    fn the_unit_cube_has_twelve_unit_edges_each_once() {
        let lines = unit_cube_lines();
        let mut edges: Vec<([i32; 3], [i32; 3])> = lines
            .chunks(2)
            .map(|e| {
                let a = e[0].map(|x| x as i32);
                let b = e[1].map(|x| x as i32);
                let d: i32 = (0..3).map(|k| (a[k] - b[k]).abs()).sum();
                assert_eq!(d, 1, "{e:?} is not a cube edge");
                (a.min(b), a.max(b))
            })
            .collect();
        edges.sort();
        edges.dedup();
        assert_eq!(edges.len(), 12);
    }

    #[test]
    fn box_instances_round_trip() {
        let b = Aabb::new(Vec3::new(-1.0, 2.0, 0.5), Vec3::new(0.0, 2.5, 3.0));
        let set = BoxSet::new([b, b]);
        assert_eq!(set.len(), 2);
        assert_eq!(set.boxes[0].aabb(), b);
        assert_eq!(set.boxes[0].size, [1.0, 0.5, 2.5]);
    }

    #[test]
    fn nodes_at_each_depth_cover_the_primitives_below() {
        let mesh = proxima::mesh::generate::noisy_icosphere(4, 1);
        let tree = AabbTree::build_set(mesh.triangles(), &BuildConfig::default()).unwrap();
        assert_eq!(nodes_at_depth(&tree, 0), vec![tree.root().unwrap().bounds()]);
        let two = nodes_at_depth(&tree, 2);
        assert_eq!(two.len(), 4);
        for b in &two {
            assert!(tree.root().unwrap().bounds().contains(b));
        }
        // Every node appears at exactly one depth.
        let total: usize = (0..=tree.depth()).map(|d| nodes_at_depth(&tree, d).len()).sum();
        assert_eq!(total, tree.node_count());
        assert!(nodes_at_depth(&tree, tree.depth() + 1).is_empty());
    }

    #[test]
    fn picking_finds_the_front_face_with_an_outward_normal() {
        let mesh = cube_mesh();
        let tree = AabbTree::build_set(mesh.triangles(), &BuildConfig::default()).unwrap();
        let triangles = mesh.triangles().primitives;
        let hit = pick(&tree, &triangles, Vec3::new(0.25, 0.5, 5.0), -Vec3::Z).unwrap();
        assert_eq!(hit.point, Vec3::new(0.25, 0.5, 1.0));
        assert_eq!(hit.normal, Vec3::Z);
        assert_eq!(hit.t, 4.0);
        assert_eq!(hit.face, 1);
        assert_eq!(hit.offset(0.5), Vec3::new(0.25, 0.5, 1.5));
        // From inside, the face in front, normal facing back to the origin.
        let inside = pick(&tree, &triangles, Vec3::splat(0.5), Vec3::X).unwrap();
        assert_eq!((inside.point.x, inside.normal), (1.0, -Vec3::X));
        assert!(pick(&tree, &triangles, Vec3::new(3.0, 3.0, 3.0), Vec3::Z).is_none());
        assert!(pick(&tree, &triangles, Vec3::ZERO, Vec3::ZERO).is_none());
        assert!(pick(&tree, &triangles, Vec3::new(f32::NAN, 0.0, 0.0), Vec3::Z).is_none());
    }

    #[test]
    fn picking_agrees_with_brute_force() {
        let mesh = proxima::mesh::generate::noisy_icosphere(6, 2);
        let set = mesh.triangles();
        let tree = AabbTree::build_set(set.clone(), &BuildConfig::default()).unwrap();
        for i in 0..50 {
            let a = i as f32 * 0.37;
            let origin = Vec3::new(3.0 * a.cos(), 0.3 * (i as f32 - 25.0) / 25.0, 3.0 * a.sin());
            let direction = (Vec3::new(0.1 * a.sin(), 0.2, 0.0) - origin).normalize();
            let ray = WatertightRay::new(origin, direction).unwrap();
            let brute = set
                .primitives
                .iter()
                .filter_map(|t| ray.intersect(t, 0.0, f32::INFINITY))
                .map(|h| h.t)
                .fold(f32::INFINITY, f32::min);
            let hit = pick(&tree, &set.primitives, origin, direction).unwrap();
            assert_eq!(hit.t, brute);
        }
    }

    #[test]
    fn frame_keys_change_with_the_picture_only() {
        let many = Arc::new(BoxSet::new(
            (0..INTERACTIVE_BOX_LIMIT + 1).map(|i| Aabb::new(Vec3::splat(i as f32), Vec3::splat(i as f32 + 1.0))),
        ));
        let mut frame = DrawFrame {
            boxes: vec![BoxLayer {
                set: many.clone(),
                color: colors::CELLS,
            }],
            ..DrawFrame::default()
        };
        let key = frame.key();
        assert_eq!(frame.clone().key(), key);
        assert!(!frame.boxes_as_points());
        frame.interactive = true;
        assert!(frame.boxes_as_points());
        assert_ne!(frame.key(), key);
        frame.interactive = false;
        frame.overlay.marker(Vec3::ZERO, colors::CLOSEST, MARKER_SIZE);
        assert_ne!(frame.key(), key);
        frame.overlay = Overlay::default();
        frame.boxes[0].color = colors::NODES;
        assert_ne!(frame.key(), key);
        frame.boxes[0].color = colors::CELLS;
        frame.clip_plane = [1.0, 0.0, 0.0, -0.5];
        assert_ne!(frame.key(), key);
        frame.clip_plane = [0.0; 4];
        frame.slice = Some(Arc::new(SliceImage::default()));
        assert_ne!(frame.key(), key);
        frame.slice = None;
        assert_eq!(frame.key(), key);
        frame.view_projection = Mat4::from_scale(Vec3::splat(2.0));
        assert_ne!(frame.key(), key);
        // A few boxes are always drawn in full.
        let few = DrawFrame {
            interactive: true,
            boxes: vec![BoxLayer {
                set: Arc::new(BoxSet::new([Aabb::new(Vec3::ZERO, Vec3::ONE)])),
                color: colors::CELLS,
            }],
            ..DrawFrame::default()
        };
        assert!(!few.boxes_as_points());
    }

    #[test]
    fn shapes_measure_distances() {
        let p = Vec3::new(0.0, 0.0, 2.0);
        assert_eq!(Shape::Point(Vec3::ZERO).distance_to(p), 2.0);
        assert_eq!(Shape::Segment(Vec3::X, -Vec3::X).distance_to(p), 2.0);
        let quad = Shape::Polygon(vec![Vec3::ZERO, Vec3::X, Vec3::ONE.with_z(0.0), Vec3::Y]);
        assert_eq!(quad.distance_to(Vec3::new(0.9, 0.9, 1.0)), 1.0);
    }
}
