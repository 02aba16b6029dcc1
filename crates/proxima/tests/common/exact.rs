//! Exact oracles for lattice-aligned input: every `f32` is a dyadic rational
//! `m · 2^e` with `e ≥ -149`, so scaling by `2^149` turns every coordinate
//! into an integer and the separating axis test into integer arithmetic
//! (`BigInt`, no rounding anywhere). A second, independent oracle clips the
//! triangle by the box's six closed half-spaces in exact rationals
//! (`BigRational`, Sutherland–Hodgman). Both decide touching exactly.

#![allow(dead_code)]

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{Signed, Zero};
use proxima::{Aabb, Triangle, Vec3};

/// `x · 2^149` as an exact integer.
pub fn scaled(x: f32) -> BigInt {
    let bits = x.to_bits();
    let negative = bits >> 31 == 1;
    let exponent = ((bits >> 23) & 0xff) as i32;
    let fraction = (bits & 0x7f_ffff) as i64;
    // Subnormals: fraction · 2^-149; normals: (2^23 + fraction) · 2^(exponent - 150).
    let (mantissa, shift) = if exponent == 0 {
        (fraction, 0)
    } else {
        (fraction | 0x80_0000, exponent - 1)
    };
    let value = BigInt::from(mantissa) << shift as usize;
    if negative { -value } else { value }
}

fn big3(v: Vec3) -> [BigInt; 3] {
    [scaled(v.x), scaled(v.y), scaled(v.z)]
}

fn sub(a: &[BigInt; 3], b: &[BigInt; 3]) -> [BigInt; 3] {
    [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]]
}

fn dot(a: &[BigInt; 3], b: &[BigInt; 3]) -> BigInt {
    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
}

fn cross(a: &[BigInt; 3], b: &[BigInt; 3]) -> [BigInt; 3] {
    [
        &a[1] * &b[2] - &a[2] * &b[1],
        &a[2] * &b[0] - &a[0] * &b[2],
        &a[0] * &b[1] - &a[1] * &b[0],
    ]
}

/// A closed box with exact bounds, as integers at the scale `2^149` (every
/// `f32`, and every grid plane `origin + i · size` of `f32` origin and size,
/// is one).
#[derive(Clone, Debug, PartialEq)]
pub struct ExactBox {
    pub lo: [BigInt; 3],
    pub hi: [BigInt; 3],
}

impl ExactBox {
    /// The box itself.
    pub fn of_aabb(b: &Aabb) -> Self {
        Self {
            lo: big3(b.min),
            hi: big3(b.max),
        }
    }

    /// The closed cell `cell` of the grid with minimum corner `origin` and
    /// extents `size`: planes `origin + i · size` exactly, computed here from
    /// the definition (not from the library's planes).
    pub fn of_cell(origin: Vec3, size: Vec3, cell: [i64; 3]) -> Self {
        let plane = |a: usize, i: i64| scaled(origin[a]) + BigInt::from(i) * scaled(size[a]);
        Self {
            lo: std::array::from_fn(|a| plane(a, cell[a])),
            hi: std::array::from_fn(|a| plane(a, cell[a] + 1)),
        }
    }
}

/// Exact separating axis test of a triangle (possibly degenerate) and a
/// closed box: the 13 axes of Akenine-Möller in integer arithmetic.
pub fn triangle_touches_box(t: &Triangle, b: &Aabb) -> bool {
    // The three box normals first: comparisons of floats are exact, and
    // they reject most candidates without big integers.
    let (lo, hi) = (Aabb::from_points(t.vertices()).min, Aabb::from_points(t.vertices()).max);
    if (0..3).any(|k| hi[k] < b.min[k] || b.max[k] < lo[k]) {
        return false;
    }
    triangle_touches_exact_box(t, &ExactBox::of_aabb(b))
}

/// [`triangle_touches_box`] against a box with exact bounds.
pub fn triangle_touches_exact_box(t: &Triangle, b: &ExactBox) -> bool {
    let v = [big3(t.a), big3(t.b), big3(t.c)];
    let (lo, hi) = (&b.lo, &b.hi);
    // The box normals first: cheap, and they reject most candidates.
    for k in 0..3 {
        let coordinates = || v.iter().map(|p| &p[k]);
        if coordinates().max().unwrap() < &lo[k] || &hi[k] < coordinates().min().unwrap() {
            return false;
        }
    }
    let e = [sub(&v[1], &v[0]), sub(&v[2], &v[1]), sub(&v[0], &v[2])];
    let mut axes: Vec<[BigInt; 3]> = Vec::with_capacity(13);
    for j in 0..3 {
        let mut unit = [BigInt::zero(), BigInt::zero(), BigInt::zero()];
        unit[j] = BigInt::from(1);
        for edge in &e {
            axes.push(cross(edge, &unit));
        }
        axes.push(unit);
    }
    axes.push(cross(&e[0], &sub(&v[2], &v[0])));
    for a in &axes {
        let projections = v.iter().map(|p| dot(p, a));
        let tri_min = projections.clone().min().unwrap();
        let tri_max = projections.max().unwrap();
        let mut box_min = BigInt::zero();
        let mut box_max = BigInt::zero();
        for k in 0..3 {
            let (p, q) = (&lo[k] * &a[k], &hi[k] * &a[k]);
            if p <= q {
                box_min += p;
                box_max += q;
            } else {
                box_min += q;
                box_max += p;
            }
        }
        if tri_max < box_min || box_max < tri_min {
            return false;
        }
    }
    true
}

fn rational(x: f32) -> BigRational {
    BigRational::new(scaled(x), BigInt::from(1) << 149usize)
}

/// Exact Sutherland–Hodgman clipping of the triangle by the closed box:
/// `true` when something (a point at least) is left.
pub fn triangle_touches_box_by_clipping(t: &Triangle, b: &Aabb) -> bool {
    points_touch_box_by_clipping(&t.vertices(), b)
}

/// [`triangle_touches_box_by_clipping`] against a box with exact bounds.
pub fn triangle_touches_exact_box_by_clipping(t: &Triangle, b: &ExactBox) -> bool {
    points_touch_exact_box_by_clipping(&t.vertices(), b)
}

/// Exact clipping of the convex hull of 1 to 3 points (a point, a segment, a
/// triangle) by the closed box.
pub fn points_touch_box_by_clipping(points: &[Vec3], b: &Aabb) -> bool {
    points_touch_exact_box_by_clipping(points, &ExactBox::of_aabb(b))
}

/// Exact clipping of a convex planar polygon (or a point, a segment) by a
/// closed box with exact bounds.
pub fn points_touch_exact_box_by_clipping(points: &[Vec3], b: &ExactBox) -> bool {
    let unscale = |x: &BigInt| BigRational::new(x.clone(), BigInt::from(1) << 149usize);
    let mut poly: Vec<[BigRational; 3]> = points
        .iter()
        .map(|p| [rational(p.x), rational(p.y), rational(p.z)])
        .collect();
    for axis in 0..3 {
        for (plane, upper) in [(unscale(&b.lo[axis]), false), (unscale(&b.hi[axis]), true)] {
            let side = |p: &[BigRational; 3]| if upper { &p[axis] - &plane } else { &plane - &p[axis] };
            let n = poly.len();
            let mut out = Vec::with_capacity(n + 1);
            for i in 0..n {
                let (prev, cur) = (&poly[(i + n - 1) % n], &poly[i]);
                let (dp, dc) = (side(prev), side(cur));
                let (inside_prev, inside_cur) = (!dp.is_positive(), !dc.is_positive());
                if inside_prev != inside_cur {
                    let denominator = &dc - &dp;
                    let x: [BigRational; 3] = std::array::from_fn(|k| {
                        if k == axis {
                            plane.clone()
                        } else {
                            (&prev[k] * &dc - &cur[k] * &dp) / &denominator
                        }
                    });
                    out.push(x);
                }
                if inside_cur {
                    out.push(cur.clone());
                }
            }
            if out.is_empty() {
                return false;
            }
            poly = out;
        }
    }
    true
}
