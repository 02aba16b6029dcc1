//! The signed solid angle of a triangle seen from a point (Van Oosterom and
//! Strackee, 1983): `tan(Ω / 2) = a · (b × c) / (|a||b||c| + (a · b)|c| +
//! (a · c)|b| + (b · c)|a|)`, with `a`, `b`, `c` the vertices relative to the
//! point. Positive when the triangle's normal `(B − A) × (C − A)` points away
//! from the point, so every face of an outward-oriented closed mesh adds up
//! to 4π seen from inside.
//!
//! A point in the triangle's plane (`a · (b × c) = 0` exactly) sees a solid
//! angle of 0: outside the triangle that is the true value, and on the
//! triangle it is the mean of the two sides' limits (±2π), so a point on the
//! surface gets a defined winding number, never NaN.

use crate::Triangle;
use crate::math::{DVec3, Vec3};
use wide::f32x4;

/// The signed solid angle of `triangle` seen from `p`, in `f64` (the exact
/// mode and the tests' oracle).
///
/// ```
/// use proxima::{Triangle, Vec3};
/// use proxima::sdf::solid_angle;
/// // The faces of a tetrahedron, normals outward: 4π seen from inside, 0 from outside.
/// let v = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
/// let faces = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
/// let total = |p: Vec3| -> f64 {
///     faces.iter().map(|f| solid_angle(&Triangle::new(v[f[0]], v[f[1]], v[f[2]]), p)).sum()
/// };
/// assert!((total(Vec3::splat(0.1)) - 4.0 * std::f64::consts::PI).abs() < 1e-12);
/// assert!(total(Vec3::splat(2.0)).abs() < 1e-12);
/// ```
pub fn solid_angle(triangle: &Triangle, p: Vec3) -> f64 {
    let p = p.as_dvec3();
    let a = triangle.a.as_dvec3() - p;
    let b = triangle.b.as_dvec3() - p;
    let c = triangle.c.as_dvec3() - p;
    solid_angle_f64(a, b, c)
}

/// [`solid_angle`] from the vertices relative to the point.
#[inline]
pub(crate) fn solid_angle_f64(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let det = a.dot(b.cross(c));
    if det == 0.0 {
        return 0.0;
    }
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    // `+ 0.0` turns a -0 denominator into +0, whose atan2 is ±π/2 as for +0.
    2.0 * det.atan2(denominator + 0.0)
}

/// Four triangles' solid angles at once in `f32`, the vertices relative to
/// the point given per axis. Lanes whose triangle is degenerate give 0.
#[inline(always)]
pub(crate) fn solid_angle_x4(a: [f32x4; 3], b: [f32x4; 3], c: [f32x4; 3]) -> f32x4 {
    let dot = |u: [f32x4; 3], v: [f32x4; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    let bc = [
        b[1] * c[2] - b[2] * c[1],
        b[2] * c[0] - b[0] * c[2],
        b[0] * c[1] - b[1] * c[0],
    ];
    let det = dot(a, bc);
    let (la, lb, lc) = (dot(a, a).sqrt(), dot(b, b).sqrt(), dot(c, c).sqrt());
    let denominator = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la + f32x4::ZERO;
    let omega = det.atan2(denominator) * f32x4::splat(2.0);
    det.simd_eq(f32x4::ZERO).select(f32x4::ZERO, omega)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::Rng;

    #[test]
    fn four_lanes_equal_the_f64_routine_within_f32_rounding() {
        let mut rng = Rng::new(3);
        let mut v = || Vec3::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
        for _ in 0..2000 {
            let t: Vec<Triangle> = (0..4).map(|_| Triangle::new(v(), v(), v())).collect();
            let p = v();
            let axis = |f: &dyn Fn(&Triangle) -> Vec3, k: usize| f32x4::new([0, 1, 2, 3].map(|i| (f(&t[i]) - p)[k]));
            let corner = |f: &dyn Fn(&Triangle) -> Vec3| [axis(f, 0), axis(f, 1), axis(f, 2)];
            let got = solid_angle_x4(corner(&|t| t.a), corner(&|t| t.b), corner(&|t| t.c)).to_array();
            for i in 0..4 {
                let want = solid_angle(&t[i], p);
                assert!((got[i] as f64 - want).abs() < 1e-4, "{} vs {want}", got[i]);
            }
        }
    }

    #[test]
    fn closed_tetrahedron_sums_to_the_full_sphere_inside_and_zero_outside() {
        let v = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        let faces = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        let total = |p: Vec3| -> f64 {
            faces
                .iter()
                .map(|f| solid_angle(&Triangle::new(v[f[0]], v[f[1]], v[f[2]]), p))
                .sum()
        };
        let four_pi = 4.0 * std::f64::consts::PI;
        assert!((total(Vec3::splat(0.1)) - four_pi).abs() < 1e-12);
        assert!(total(Vec3::splat(2.0)).abs() < 1e-12);
        // On a vertex, an edge and a face: defined, between the two sides.
        for p in [Vec3::ZERO, Vec3::new(0.5, 0.0, 0.0), Vec3::new(0.2, 0.2, 0.0)] {
            let w = total(p) / four_pi;
            assert!(w.is_finite() && (0.0..=1.0).contains(&w), "{p}: {w}");
        }
    }
}
