//! The table of degenerate inputs every structure is tested on
//! (`tests/degenerate.rs`). Each case is a triangle soup with the query points
//! that stress it: every vertex, every edge midpoint, every centroid, the
//! lattice points (cell corners) of its box, and a few far points.
//!
//! To test a new structure, loop over [`cases`] and compare its answers with
//! brute force; to add a kind of degeneracy, add a [`Case`] here and every
//! structure's suite picks it up.

use proxima::{LineSegment, Point, PrimitiveSet, Triangle, Vec3};

/// One degenerate input.
#[derive(Clone, Debug)]
pub struct Case {
    /// Short name, printed on failure.
    pub name: &'static str,
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Triangles as vertex index triples (may repeat vertices).
    pub triangles: Vec<[u32; 3]>,
    /// A natural cell size for grids over this case.
    pub cell: f32,
    /// Every coordinate, cell boundary and query is a small dyadic value, so
    /// overlap tests carry no rounding and grids must equal brute force exactly.
    pub exact: bool,
    /// Coordinates beyond [`proxima::build::MAX_COORDINATE`]: trees refuse to build.
    pub beyond_tree_bound: bool,
}

impl Case {
    /// The faces as triangles.
    pub fn triangle_set(&self) -> PrimitiveSet<Triangle> {
        let p = &self.positions;
        PrimitiveSet::from_primitives(
            self.triangles
                .iter()
                .map(|t| Triangle::new(p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]))
                .collect(),
        )
    }

    /// The three edges of every face, as segments (shared edges repeat).
    pub fn segment_set(&self) -> PrimitiveSet<LineSegment> {
        let p = &self.positions;
        PrimitiveSet::from_primitives(
            self.triangles
                .iter()
                .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
                .map(|(a, b)| LineSegment::new(p[a as usize], p[b as usize]))
                .collect(),
        )
    }

    /// Every position, as points.
    pub fn point_set(&self) -> PrimitiveSet<Point> {
        PrimitiveSet::from_primitives(self.positions.iter().map(|&v| Point(v)).collect())
    }

    /// Queries exactly on vertices, edges (midpoints) and faces (centroids), on
    /// the cell corners around the case, and far away.
    pub fn queries(&self) -> Vec<Vec3> {
        let p = &self.positions;
        let mut out: Vec<Vec3> = p.clone();
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| p[i as usize]);
            out.extend([(a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5, (a + b + c) / 3.0]);
        }
        if let Some(first) = p.first() {
            let (lo, hi) = p.iter().fold((*first, *first), |(lo, hi), &v| (lo.min(v), hi.max(v)));
            let corner = |v: Vec3| (v / self.cell).floor() * self.cell;
            let (lo, hi) = (corner(lo), corner(hi) + self.cell);
            for k in 0..3 {
                for j in 0..3 {
                    for i in 0..3 {
                        let f = Vec3::new(i as f32, j as f32, k as f32) * 0.5;
                        out.push(lo + (hi - lo) * f);
                    }
                }
            }
            let size = (hi - lo).max_element();
            out.extend([lo - size * 10.0, hi + Vec3::new(size * 7.0, 0.0, -size * 3.0)]);
        } else {
            out.extend([Vec3::ZERO, Vec3::ONE]);
        }
        out
    }
}

fn case(name: &'static str, positions: Vec<Vec3>, triangles: Vec<[u32; 3]>, cell: f32, exact: bool) -> Case {
    Case {
        name,
        positions,
        triangles,
        cell,
        exact,
        beyond_tree_bound: false,
    }
}

/// The quarter lattice points of a small box, used by several cases.
fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

/// Every case of the table.
pub fn cases() -> Vec<Case> {
    let unit = [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0), v(0.0, 0.0, 1.0)];
    let small_features =
        |offset: f32, size: f32| -> Vec<Vec3> { unit.iter().map(|&p| Vec3::splat(offset) + p * size).collect() };
    let mut out = vec![
        case("empty", vec![], vec![], 1.0, true),
        case("one triangle", unit[..3].to_vec(), vec![[0, 1, 2]], 0.5, true),
        case("all identical", unit[..3].to_vec(), vec![[0, 1, 2]; 12], 0.5, true),
        case(
            "zero-area and collinear",
            vec![
                v(0.0, 0.0, 0.0),
                v(1.0, 1.0, 0.0),
                v(0.5, 0.5, 0.0),
                v(2.0, 2.0, 0.0),
                v(0.25, 0.75, 0.5),
            ],
            vec![[0, 1, 2], [0, 1, 3], [2, 3, 1], [4, 4, 4], [0, 3, 2]],
            0.5,
            true,
        ),
        case(
            "repeated vertices and zero-length edges",
            vec![
                v(0.25, 0.25, 0.25),
                v(0.25, 0.25, 0.25),
                v(0.75, 0.25, 0.25),
                v(0.75, 0.25, 0.25),
            ],
            vec![[0, 1, 2], [0, 0, 2], [1, 2, 3], [0, 1, 1], [2, 3, 2]],
            0.25,
            true,
        ),
        case(
            "axis-aligned on cell boundaries",
            vec![
                v(0.0, 0.0, 1.0),
                v(2.0, 0.0, 1.0),
                v(0.0, 2.0, 1.0),
                v(1.0, 0.0, 0.0),
                v(1.0, 2.0, 0.0),
                v(1.0, 0.0, 2.0),
                v(0.0, 1.0, 0.0),
                v(2.0, 1.0, 2.0),
            ],
            // Faces in the planes z = 1 and x = 1, a diagonal through cell corners,
            // and an edge lying along a cell edge.
            vec![[0, 1, 2], [3, 4, 5], [6, 7, 3], [3, 4, 4]],
            1.0,
            true,
        ),
        case(
            "tiny (1e-30)",
            small_features(0.0, 1e-30),
            vec![[0, 1, 2], [0, 1, 3], [1, 2, 3], [0, 0, 3]],
            1e-30,
            false,
        ),
        case(
            "far from the origin (1e7) with small features",
            small_features(1e7, 0.01),
            vec![[0, 1, 2], [0, 1, 3], [1, 2, 3], [0, 0, 3]],
            0.25,
            false,
        ),
        case(
            "large (1e17), within the tree bound",
            small_features(-3e17, 1e17),
            vec![[0, 1, 2], [0, 1, 3], [1, 2, 3], [0, 0, 3]],
            1e17,
            false,
        ),
        case(
            "long thin triangle (1e16 by 1e-3)",
            vec![
                v(0.0, 0.0, 0.0),
                v(1e16, 0.0, 0.0),
                v(0.0, 1e-3, 0.0),
                v(5e15, 1.0, 1.0),
            ],
            vec![[0, 1, 2], [1, 2, 3]],
            1e15,
            false,
        ),
    ];
    out.push(Case {
        beyond_tree_bound: true,
        ..case(
            "huge (1e30)",
            small_features(0.0, 1e30),
            vec![[0, 1, 2], [0, 1, 3]],
            1e30,
            false,
        )
    });
    out
}
