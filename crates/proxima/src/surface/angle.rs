//! Triangles' unit normals and their angles at each corner, in `f64`, four
//! triangles at a time: the angle-weighted normals take three arc cosines
//! per triangle, and on a moving mesh one `acos` call per corner was the
//! largest part of refitting the pseudonormals (docs/perf-log.md).

use crate::math::DVec3;
use wide::f64x4;

/// Four triangles' corners, one lane each.
struct Lanes {
    x: f64x4,
    y: f64x4,
    z: f64x4,
}

impl Lanes {
    fn corner(triangles: &[[DVec3; 3]; 4], k: usize) -> Self {
        Self {
            x: f64x4::new(triangles.map(|t| t[k].x)),
            y: f64x4::new(triangles.map(|t| t[k].y)),
            z: f64x4::new(triangles.map(|t| t[k].z)),
        }
    }

    fn sub(&self, o: &Self) -> Self {
        Self {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }

    fn dot(&self, o: &Self) -> f64x4 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    fn cross(&self, o: &Self) -> Self {
        Self {
            x: self.y * o.z - self.z * o.y,
            y: self.z * o.x - self.x * o.z,
            z: self.x * o.y - self.y * o.x,
        }
    }
}

/// For each of four triangles, its unit normal (zero where it has no area)
/// and its angle at each corner, in `[0, π]`: NaN at a corner one of whose
/// sides has no length. The angles are `acos(u·v / √(|u|²|v|²))`, within a
/// few ulps of the C library's arc cosine of the same cosine (so that an
/// angle below about 1e-8 is 0, as from any cosine).
pub(crate) fn normals_and_angles(triangles: &[[DVec3; 3]; 4]) -> ([DVec3; 4], [[f64; 3]; 4]) {
    let [p0, p1, p2] = [0, 1, 2].map(|k| Lanes::corner(triangles, k));
    let (e01, e02, e12) = (p1.sub(&p0), p2.sub(&p0), p2.sub(&p1));
    let (l01, l02, l12) = (e01.dot(&e01), e02.dot(&e02), e12.dot(&e12));
    let angle = |dot: f64x4, lu: f64x4, lv: f64x4| {
        let den = (lu * lv).sqrt();
        // |u·v| ≤ |u||v| up to rounding: the clamp only trims that.
        let cos = (dot / den).max(f64x4::splat(-1.0)).min(f64x4::ONE);
        den.simd_eq(f64x4::ZERO).select(f64x4::splat(f64::NAN), cos.acos())
    };
    // At corner 0 the sides are e01 and e02; at 1, e12 and −e01; at 2, −e02 and −e12.
    let angles = [
        angle(e01.dot(&e02), l01, l02),
        angle(-(e12.dot(&e01)), l12, l01),
        angle(e02.dot(&e12), l02, l12),
    ]
    .map(f64x4::to_array);
    let n = e01.cross(&e02);
    let length = n.dot(&n).sqrt();
    // As `normalize_or_zero`: zero where the length is 0 (or overflowed).
    let scale = (length.simd_eq(f64x4::ZERO) | !length.is_finite()).select(f64x4::ZERO, f64x4::ONE / length);
    let [x, y, z] = [n.x * scale, n.y * scale, n.z * scale].map(f64x4::to_array);
    (
        std::array::from_fn(|lane| DVec3::new(x[lane], y[lane], z[lane])),
        std::array::from_fn(|lane| angles.map(|a| a[lane])),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::Rng;

    /// The distance in ulps between two doubles of the same sign.
    fn ulps(a: f64, b: f64) -> u64 {
        a.to_bits().abs_diff(b.to_bits())
    }

    /// Each lane against the scalar formulas with the C library's `acos`,
    /// over random triangles, thin ones (a corner of 1e-5 down to 1e-9)
    /// and ones with a side of no length.
    #[test]
    fn lanes_agree_with_the_scalar_formulas() {
        let mut rng = Rng::new(5);
        let mut point = |scale: f64| {
            DVec3::new(
                rng.range(-1.0, 1.0) as f64,
                rng.range(-1.0, 1.0) as f64,
                rng.range(-1.0, 1.0) as f64,
            ) * scale
        };
        let mut triangles = Vec::new();
        for k in 0..4000 {
            let (a, b) = (point(1.0), point(1.0));
            let c = match k % 4 {
                0 | 1 => point(1.0),
                // Nearly on the line a–b: two angles near 0, one near π.
                2 => a.lerp(b, 0.3) + point(10f64.powi(-5 - (k / 4 % 5))),
                _ => a,
            };
            triangles.push([a, b, c]);
        }
        let mut worst = 0;
        for four in triangles.chunks_exact(4) {
            let four: [[DVec3; 3]; 4] = four.try_into().unwrap();
            let (normals, angles) = normals_and_angles(&four);
            for (lane, t) in four.iter().enumerate() {
                let expected = |k: usize| {
                    let (u, v) = (t[(k + 1) % 3] - t[k], t[(k + 2) % 3] - t[k]);
                    let den = (u.length_squared() * v.length_squared()).sqrt();
                    (u.dot(v) / den).clamp(-1.0, 1.0).acos()
                };
                for (k, &ours) in angles[lane].iter().enumerate() {
                    let theirs = expected(k);
                    if theirs.is_nan() {
                        assert!(ours.is_nan(), "{t:?} corner {k}: {ours}");
                    } else {
                        worst = worst.max(ulps(ours, theirs));
                        assert!(ulps(ours, theirs) <= 4, "{t:?} corner {k}: {ours:e} against {theirs:e}");
                    }
                }
                let normal = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
                assert!((normals[lane] - normal).length() <= 4.0 * f64::EPSILON, "{t:?}");
            }
        }
        println!("worst angle: {worst} ulps");
    }

    #[test]
    fn angles_of_known_triangles() {
        use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
        let right = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let flat = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0];
        let point = [DVec3::ONE; 3];
        let (normals, angles) = normals_and_angles(&[right, flat, point, right]);
        let close = |a: f64, b: f64| (a - b).abs() <= 4.0 * f64::EPSILON;
        assert!(close(angles[0][0], FRAC_PI_2) && close(angles[0][1], FRAC_PI_4) && close(angles[0][2], FRAC_PI_4));
        assert_eq!(normals[0], DVec3::Z);
        assert_eq!((angles[1], normals[1]), ([0.0, PI, 0.0], DVec3::ZERO));
        assert!(angles[2].iter().all(|a| a.is_nan()) && normals[2] == DVec3::ZERO);
    }
}
