//! Extraction of convex polygon primitives from a mesh, with fan
//! triangulation for the faces that are not convex and planar within
//! tolerance (see `primitive::polygon` for the criteria).

use super::Mesh;
use crate::error::PolygonError;
use crate::math::Vec3;
use crate::primitive::polygon::{
    DEFAULT_PLANARITY_TOLERANCE, MAX_POLYGON_VERTICES, check_convex_planar, check_with_normal,
};
use crate::primitive::{ConvexPolygon, PrimitiveSet, Triangle};

/// The polygons of a mesh and how its faces were turned into them
/// ([`Mesh::extract_polygons`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PolygonExtraction {
    /// The polygons; the source of each is its face index.
    pub set: PrimitiveSet<ConvexPolygon>,
    /// Faces of three vertices (each one polygon).
    pub triangles: usize,
    /// Faces of four or more vertices kept as one polygon, or as several when
    /// they have more than [`MAX_POLYGON_VERTICES`] vertices.
    pub polygons: usize,
    /// Of those, the faces cut into several pieces.
    pub split: usize,
    /// Faces of four or more vertices that were fan-triangulated: the sum of
    /// the three counts below.
    pub fan_triangulated: usize,
    /// Fan-triangulated because they are not planar within the tolerance.
    pub not_planar: usize,
    /// Fan-triangulated because they are not strictly convex.
    pub not_convex: usize,
    /// Fan-triangulated because they have no area.
    pub degenerate: usize,
}

impl PolygonExtraction {
    /// Number of faces of four or more vertices.
    pub fn polygon_faces(&self) -> usize {
        self.polygons + self.fan_triangulated
    }

    /// The one-line note front ends print when faces were fan-triangulated
    /// (`None` when none was), for an extraction made with `tolerance`.
    ///
    /// ```
    /// use proxima::{Mesh, Vec3};
    /// let bent = Mesh::from_faces(
    ///     vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 1.0), Vec3::Y],
    ///     &[vec![0, 1, 2, 3]],
    /// )
    /// .unwrap();
    /// let note = bent.extract_polygons(1e-5).fan_note(1e-5).unwrap();
    /// assert_eq!(note, "1 of 1 faces with more than 3 vertices are not planar/convex within tolerance 1e-5; fan-triangulated");
    /// ```
    pub fn fan_note(&self, tolerance: f32) -> Option<String> {
        (self.fan_triangulated > 0).then(|| {
            format!(
                "{} of {} faces with more than 3 vertices are not planar/convex within tolerance {tolerance:e}; fan-triangulated",
                self.fan_triangulated,
                self.polygon_faces(),
            )
        })
    }
}

impl Mesh {
    /// The faces as convex polygons with the default planarity tolerance
    /// ([`DEFAULT_PLANARITY_TOLERANCE`]); the source of each is its face. See
    /// [`Mesh::extract_polygons`].
    ///
    /// ```
    /// use proxima::{Mesh, Vec3};
    /// let mesh = Mesh::from_faces(
    ///     vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y, Vec3::new(0.5, 0.5, 1.0)],
    ///     &[vec![0, 1, 2, 3], vec![0, 1, 4, 3]], // a square, and a bent quad
    /// )
    /// .unwrap();
    /// let polygons = mesh.polygons();
    /// assert_eq!(polygons.sources, [0, 1, 1]); // the bent quad became two triangles
    /// assert_eq!(polygons.primitives[0].len(), 4);
    /// ```
    pub fn polygons(&self) -> PrimitiveSet<ConvexPolygon> {
        self.extract_polygons(DEFAULT_PLANARITY_TOLERANCE).set
    }

    /// The faces as convex polygons, in face order, with counts of what
    /// became of them. A face of three vertices is one (triangle) polygon. A
    /// face of more vertices that is strictly convex and planar within
    /// `tolerance` (relative to its bounding box diagonal) is one polygon, or,
    /// beyond [`MAX_POLYGON_VERTICES`] vertices, several convex pieces sharing
    /// its first vertex. Any other face is fan-triangulated `(v0, vᵢ, vᵢ₊₁)`
    /// into 3-vertex polygons, exactly as [`Mesh::triangles`] does.
    pub fn extract_polygons(&self, tolerance: f32) -> PolygonExtraction {
        let p = &self.positions;
        let mut out = PolygonExtraction::default();
        let set = &mut out.set;
        let mut corners = Vec::new();
        for (f, face) in self.faces().enumerate() {
            let source = f as u32;
            if face.len() == 3 {
                let tri = Triangle::new(p[face[0] as usize], p[face[1] as usize], p[face[2] as usize]);
                set.primitives.push(ConvexPolygon::from_triangle(&tri));
                set.sources.push(source);
                out.triangles += 1;
                continue;
            }
            corners.clear();
            corners.extend(face.iter().map(|&v| p[v as usize]));
            let checked = check_convex_planar(&corners, tolerance)
                .and_then(|normal| check_pieces(&corners, normal, tolerance).map(|()| normal));
            match checked {
                Ok(normal) => {
                    let count = push_pieces(set, &corners, normal, source);
                    out.polygons += 1;
                    out.split += usize::from(count > 1);
                }
                Err(e) => {
                    match e {
                        PolygonError::NotPlanar { .. } => out.not_planar += 1,
                        PolygonError::NotConvex { .. } => out.not_convex += 1,
                        _ => out.degenerate += 1,
                    }
                    out.fan_triangulated += 1;
                    for w in corners[1..].windows(2) {
                        set.primitives
                            .push(ConvexPolygon::from_triangle(&Triangle::new(corners[0], w[0], w[1])));
                        set.sources.push(source);
                    }
                }
            }
        }
        out
    }
}

/// Number of vertices added per piece after the first: piece `k` is
/// `v0, v(1 + STEP k), …, v(1 + STEP (k + 1))`.
const STEP: usize = MAX_POLYGON_VERTICES - 2;

/// Checks each piece of an accepted face against the face's normal. A piece
/// is a sub-polygon of a convex polygon, so this fails only by rounding, and
/// then the whole face is fan-triangulated.
fn check_pieces(corners: &[Vec3], normal: Vec3, tolerance: f32) -> Result<(), PolygonError> {
    if corners.len() <= MAX_POLYGON_VERTICES {
        return Ok(()); // the face itself, already checked
    }
    for_each_piece(corners, |piece| {
        if piece.len() > 3 {
            check_with_normal(piece, normal, tolerance)
        } else {
            Ok(())
        }
    })
}

/// Pushes the pieces of an accepted face (with the face's normal, which the
/// checks used); returns how many.
fn push_pieces(set: &mut PrimitiveSet<ConvexPolygon>, corners: &[Vec3], normal: Vec3, source: u32) -> usize {
    let mut count = 0;
    let pushed = for_each_piece(corners, |piece| {
        let polygon = match piece {
            [a, b, c] => ConvexPolygon::from_triangle(&Triangle::new(*a, *b, *c)),
            _ => ConvexPolygon::from_parts(piece, normal),
        };
        set.primitives.push(polygon);
        set.sources.push(source);
        count += 1;
        Ok(())
    });
    debug_assert!(pushed.is_ok());
    count
}

/// Calls `f` with each piece's vertices (one piece when the face fits).
fn for_each_piece(
    corners: &[Vec3],
    mut f: impl FnMut(&[Vec3]) -> Result<(), PolygonError>,
) -> Result<(), PolygonError> {
    if corners.len() <= MAX_POLYGON_VERTICES {
        return f(corners);
    }
    let mut piece = [Vec3::ZERO; MAX_POLYGON_VERTICES];
    piece[0] = corners[0];
    let mut start = 1;
    while start + 1 < corners.len() {
        let end = (start + STEP + 1).min(corners.len());
        let len = 1 + end - start;
        piece[1..len].copy_from_slice(&corners[start..end]);
        f(&piece[..len])?;
        start = end - 1;
    }
    Ok(())
}
