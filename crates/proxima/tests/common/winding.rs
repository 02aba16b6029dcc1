//! The winding number oracle of the tests: each triangle's solid angle as
//! the excess of its spherical triangle (Girard's theorem) in `f64`,
//! written here and not shared with the library's Van Oosterom–Strackee
//! formula.

use glam::DVec3;
use proxima::{Mesh, Triangle, Vec3};

/// The signed solid angle of a triangle seen from `p` by Girard's theorem:
/// the spherical triangle's excess (sum of its angles minus π), signed by
/// the orientation. A triangle in a plane through `p` (or with a vertex on
/// `p`) sees 0, the library's convention on the surface.
pub fn girard_solid_angle(t: &Triangle, p: Vec3) -> f64 {
    let p = p.as_dvec3();
    let [a, b, c] = [t.a, t.b, t.c].map(|v| v.as_dvec3() - p);
    let det = a.dot(b.cross(c));
    if det == 0.0 || a.length() == 0.0 || b.length() == 0.0 || c.length() == 0.0 {
        return 0.0;
    }
    let [a, b, c] = [a, b, c].map(DVec3::normalize);
    // The angle at vertex `u` between the great circles to `v` and `w`.
    let corner = |u: DVec3, v: DVec3, w: DVec3| {
        let (n1, n2) = (u.cross(v), u.cross(w));
        n1.angle_between(n2)
    };
    let excess = corner(a, b, c) + corner(b, c, a) + corner(c, a, b) - std::f64::consts::PI;
    if excess.is_finite() {
        excess.abs() * det.signum()
    } else {
        0.0
    }
}

/// The winding number by Girard's theorem over every triangle.
pub fn oracle(triangles: &[Triangle], p: Vec3) -> f64 {
    triangles.iter().map(|t| girard_solid_angle(t, p)).sum::<f64>() / (4.0 * std::f64::consts::PI)
}

/// Mesh from triangles given as corner positions (unwelded: each triangle
/// its own three vertices).
pub fn mesh_of(triangles: &[[Vec3; 3]]) -> Mesh {
    let positions: Vec<Vec3> = triangles.iter().flatten().copied().collect();
    let faces: Vec<[u32; 3]> = (0..triangles.len() as u32)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    Mesh::from_triangles(positions, &faces).unwrap()
}

/// The corners of each of `mesh`'s triangles.
pub fn corners(mesh: &Mesh) -> Vec<[Vec3; 3]> {
    mesh.triangles().primitives.iter().map(|t| [t.a, t.b, t.c]).collect()
}
