//! Exact decisions of the triangle / box separating axis test, for the rare
//! comparisons that `f64` cannot settle.
//!
//! The fast tests ([`TriangleBoxTest`](super::TriangleBoxTest) and the grid's
//! 2D test) evaluate each axis in `f64` together with a bound on its rounding
//! error ([`rounding_bound`]). When the computed gap between the shadows is
//! within that bound of zero — a vertex exactly on a cell plane, a triangle in
//! a cell face, an edge along a cell edge, as in lattice-aligned meshes — the
//! axis is decided here instead, in integers: every finite `f32` is a
//! multiple of `2^-149`, so at the scale of the smallest bit among the inputs
//! every coordinate, edge, axis and shadow is an exact integer, and touching
//! is decided with no rounding. The integers are `i128` when the inputs span
//! few enough bits (coordinates of one mesh and one grid nearly always do),
//! [`BigInt`] otherwise.

use crate::exact::{Exact, common_scale, integers};
use num_bigint::BigInt;
use std::cmp::Ordering;

/// The rounding bound of the fast tests: `|computed gap − exact gap| ≤
/// ROUNDING_FACTOR · M`, where `M` is the gap's expression evaluated on the
/// absolute values of its inputs (see [`rounding_bound`]). The expressions
/// are at most 9 operations deep, so `γ_9 ≈ 9 u` (`u = 2^-53`) would do;
/// `32 u` leaves room for the rounding of `M` itself.
pub(crate) const ROUNDING_FACTOR: f64 = 16.0 * f64::EPSILON;

/// The largest magnitude of the box's bounds, `max |lo_k|, |hi_k|`, which
/// bounds `|center_k| + half_k` on every axis (bounds that are unused
/// placeholders hold 0 and change nothing).
#[inline(always)]
pub(crate) fn box_magnitude(lo: &[f64; 3], hi: &[f64; 3]) -> f64 {
    let m = |a: f64, b: f64| if a > b { a } else { b };
    m(
        m(m(lo[0].abs(), hi[0].abs()), m(lo[1].abs(), hi[1].abs())),
        m(lo[2].abs(), hi[2].abs()),
    )
}

/// The error bound of a gap on an axis whose components' absolute forms sum
/// to `axis_magnitude` and on which the triangle's absolute shadow reaches
/// `triangle_magnitude`, against a box of magnitude `box_magnitude`:
/// `M ≤ 2 · box · axis + triangle` (center and half extent each contribute
/// `(|lo| + |hi|) / 2`).
#[inline(always)]
pub(crate) fn rounding_bound(box_magnitude: f64, axis_magnitude: f64, triangle_magnitude: f64) -> f64 {
    ROUNDING_FACTOR * (2.0 * box_magnitude * axis_magnitude + triangle_magnitude)
}

/// Does the axis `edge_i × unit_j` (components `axis` at `(j + 1) % 3` and
/// `(j + 2) % 3`) separate the box `c ± h` (bounds `lo`, `hi`) from the shape
/// with vertices `v`, whose shadow on it is `shadow`? Decided in `f64` when
/// the gap between the shadows exceeds `bound`, exactly otherwise. Shared by
/// the triangle, polygon and 2D tests.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn edge_axis_gap_separates(
    j: usize,
    axis: (f64, f64),
    shadow: (f64, f64),
    bound: f64,
    (c, h): (&[f64; 3], &[f64; 3]),
    (lo, hi): (&[f64; 3], &[f64; 3]),
    v: &[[f64; 3]],
    i: usize,
) -> bool {
    let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
    let p = c[j1] * axis.0 + c[j2] * axis.1;
    let r = h[j1] * axis.0.abs() + h[j2] * axis.1.abs();
    let gap = (p - r - shadow.1).max(shadow.0 - p - r);
    gap > bound || (gap >= -bound && edge_axis_separates(v, i, j, lo, hi))
}

/// The rounding bounds of every edge axis and of the normal of a shape of
/// `count` vertices whose coordinates are at most `shape` in absolute value,
/// against boxes of magnitude at most `boxes`: one number each, from the
/// coordinates' magnitude instead of per axis (computing those cost more than
/// the tests they guard). An edge axis's components have absolute forms of at
/// most `2 · shape` each (`4 · shape` in all) and its shadow at most
/// `4 · shape²`; the normal, a sum of `count − 2` cross products, at most
/// `24 (count − 2) shape²` and its shadow `24 (count − 2) shape³`.
#[inline]
pub(crate) fn shape_bounds(shape: f64, boxes: f64, count: usize) -> (f64, f64) {
    let edge = rounding_bound(boxes, 4.0 * shape, 4.0 * shape * shape);
    let fan = 24.0 * (count - 2) as f64 * shape * shape;
    (edge, rounding_bound(boxes, fan, fan * shape))
}

/// `true` when the closed intervals `[a_min, a_max]` and `[b_min, b_max]` are disjoint.
fn disjoint<T: Exact>(a: (&T, &T), b: (&T, &T)) -> bool {
    a.1 < b.0 || b.1 < a.0
}

/// The box's shadow on `axis` (only the components in `components` are non-zero).
fn box_shadow<T: Exact>(lo: &[T; 3], hi: &[T; 3], axis: &[T; 3], components: &[usize]) -> (T, T) {
    let mut min = T::zero();
    let mut max = T::zero();
    for &k in components {
        let (p, q) = (lo[k].clone() * axis[k].clone(), hi[k].clone() * axis[k].clone());
        if p <= q {
            (min, max) = (min + p, max + q);
        } else {
            (min, max) = (min + q, max + p);
        }
    }
    (min, max)
}

/// Most vertices of a polygon (a triangle has 3).
const MAX_VERTICES: usize = crate::primitive::polygon::MAX_POLYGON_VERTICES;

/// The inputs of a polygon / box decision, flattened for [`common_scale`]
/// (unused slots hold 0, which changes no scale); `None` when one is not finite.
fn polygon_box_values(v: &[[f64; 3]], lo: &[f64; 3], hi: &[f64; 3]) -> Option<[f64; 3 * MAX_VERTICES + 6]> {
    let mut all = [0.0; 3 * MAX_VERTICES + 6];
    for (k, x) in v.iter().flatten().chain(lo).chain(hi).enumerate() {
        all[k] = *x;
    }
    all.iter().all(|x| x.is_finite()).then_some(all)
}

/// Exactly: does the axis `edge_i × unit_j` separate the convex polygon (or
/// triangle) `v` from the closed box `[lo, hi]`? Edge `i` runs from vertex
/// `i` to vertex `i + 1` (cyclically); the box's bounds along `j` are not read.
#[cold]
#[inline(never)]
pub(crate) fn edge_axis_separates(v: &[[f64; 3]], i: usize, j: usize, lo: &[f64; 3], hi: &[f64; 3]) -> bool {
    let Some(values) = polygon_box_values(v, lo, hi) else {
        // Cell bounds beyond f32 (huge cells far out): keep the cell.
        return false;
    };
    let (low, bits) = common_scale(&values);
    // Shadows are sums of two products of a coordinate (`bits`) and an edge
    // component (`bits + 1`): at most 2 · bits + 3 bits with the sign.
    if bits <= 60 {
        edge_axis_separates_in::<i128>(v, i, j, lo, hi, low)
    } else {
        edge_axis_separates_in::<BigInt>(v, i, j, lo, hi, low)
    }
}

fn edge_axis_separates_in<T: Exact>(
    v: &[[f64; 3]],
    i: usize,
    j: usize,
    lo: &[f64; 3],
    hi: &[f64; 3],
    low: i32,
) -> bool {
    let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
    let (from, to): ([T; 3], [T; 3]) = (integers(&v[i], low), integers(&v[(i + 1) % v.len()], low));
    let mut axis = [T::zero(), T::zero(), T::zero()];
    axis[j1] = to[j2].clone() - from[j2].clone();
    axis[j2] = from[j1].clone() - to[j1].clone();
    let (shape_min, shape_max) = shadow(v, &axis, low);
    let (box_min, box_max) = box_shadow(&integers(lo, low), &integers(hi, low), &axis, &[j1, j2]);
    disjoint((&shape_min, &shape_max), (&box_min, &box_max))
}

/// The shadow of the vertices `v` on `axis`.
fn shadow<T: Exact>(v: &[[f64; 3]], axis: &[T; 3], low: i32) -> (T, T) {
    let mut projections = v.iter().map(|p| {
        let p: [T; 3] = integers(p, low);
        p[0].clone() * axis[0].clone() + p[1].clone() * axis[1].clone() + p[2].clone() * axis[2].clone()
    });
    let first = projections.next().expect("at least one vertex");
    projections.fold((first.clone(), first), |(min, max), x| (min.min(x.clone()), max.max(x)))
}

/// Exactly: does the normal `Σ (v_i − v_0) × (v_{i+1} − v_0)` (Newell's, for
/// a triangle `(v1 − v0) × (v2 − v0)`) separate the polygon from the closed
/// box `[lo, hi]`? (A zero normal separates nothing.)
#[cold]
#[inline(never)]
pub(crate) fn normal_separates(v: &[[f64; 3]], lo: &[f64; 3], hi: &[f64; 3]) -> bool {
    let Some(values) = polygon_box_values(v, lo, hi) else {
        return false;
    };
    let (low, bits) = common_scale(&values);
    // Normal components: a sum of up to 6 cross products, 2 · bits + 6;
    // shadows: three products with a coordinate, 3 · bits + 10 at most.
    if bits <= 38 {
        normal_separates_in::<i128>(v, lo, hi, low)
    } else {
        normal_separates_in::<BigInt>(v, lo, hi, low)
    }
}

fn normal_separates_in<T: Exact>(v: &[[f64; 3]], lo: &[f64; 3], hi: &[f64; 3], low: i32) -> bool {
    let origin: [T; 3] = integers(&v[0], low);
    let mut normal = [T::zero(), T::zero(), T::zero()];
    for pair in v[1..].windows(2) {
        let a: [T; 3] = integers(&pair[0], low);
        let b: [T; 3] = integers(&pair[1], low);
        let e0: [T; 3] = std::array::from_fn(|k| a[k].clone() - origin[k].clone());
        let e1: [T; 3] = std::array::from_fn(|k| b[k].clone() - origin[k].clone());
        for (k, n) in normal.iter_mut().enumerate() {
            let (k1, k2) = ((k + 1) % 3, (k + 2) % 3);
            *n = n.clone() + e0[k1].clone() * e1[k2].clone() - e0[k2].clone() * e1[k1].clone();
        }
    }
    let (shape_min, shape_max) = shadow(v, &normal, low);
    let (box_min, box_max) = box_shadow(&integers(lo, low), &integers(hi, low), &normal, &[0, 1, 2]);
    disjoint((&shape_min, &shape_max), (&box_min, &box_max))
}

/// Exactly: does the segment `a`–`b` meet the closed box `[lo, hi]`? Along
/// each axis where it moves, the segment is inside the slab for parameters
/// between two fractions `(plane − a) / (b − a)`; it meets the box when every
/// such entry (and 0) is at most every exit (and 1), compared as integers.
#[cold]
#[inline(never)]
pub(crate) fn segment_overlaps(a: [f64; 3], b: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> bool {
    let mut all = [0.0; 12];
    for (k, x) in a.iter().chain(&b).chain(&lo).chain(&hi).enumerate() {
        all[k] = *x;
    }
    if !all.iter().all(|x| x.is_finite()) {
        return true;
    }
    let (low, bits) = common_scale(&all);
    // Cross products of two differences: 2 · bits + 3 at most.
    if bits <= 60 {
        segment_overlaps_in::<i128>(&a, &b, &lo, &hi, low)
    } else {
        segment_overlaps_in::<BigInt>(&a, &b, &lo, &hi, low)
    }
}

fn segment_overlaps_in<T: Exact>(a: &[f64; 3], b: &[f64; 3], lo: &[f64; 3], hi: &[f64; 3], low: i32) -> bool {
    let (a, b, lo, hi): ([T; 3], [T; 3], [T; 3], [T; 3]) =
        (integers(a, low), integers(b, low), integers(lo, low), integers(hi, low));
    // Fractions as (numerator, positive denominator); the parameter's scale cancels.
    let one = T::shifted(1, 0);
    let mut entries = vec![(T::zero(), one.clone())];
    let mut exits = vec![(one.clone(), one)];
    for k in 0..3 {
        let d = b[k].clone() - a[k].clone();
        let (to_lo, to_hi) = (lo[k].clone() - a[k].clone(), hi[k].clone() - a[k].clone());
        match d.cmp(&T::zero()) {
            Ordering::Equal => {
                if to_lo > T::zero() || to_hi < T::zero() {
                    return false;
                }
            }
            Ordering::Greater => {
                entries.push((to_lo, d.clone()));
                exits.push((to_hi, d));
            }
            Ordering::Less => {
                entries.push((-to_hi, -d.clone()));
                exits.push((-to_lo, -d));
            }
        }
    }
    entries.iter().all(|(n0, d0)| {
        exits
            .iter()
            .all(|(n1, d1)| n0.clone() * d1.clone() <= n1.clone() * d0.clone())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::{integer, parts};

    #[test]
    fn integers_are_exact_at_the_extremes() {
        assert_eq!(parts(1.0), Some((1, 0)));
        assert_eq!(parts(-0.75), Some((-3, -2)));
        assert_eq!(parts(f32::from_bits(1) as f64), Some((1, -149)));
        assert_eq!(parts(0.0), None);
        assert_eq!(parts(f64::from_bits(1)), Some((1, -1074)));
        assert_eq!(parts(1.0 + f64::EPSILON), Some(((1 << 52) + 1, -52)));
        assert_eq!(parts(f32::MAX as f64), Some((0xff_ffff, 104)));
        let (low, bits) = common_scale(&[f32::MAX as f64, f32::from_bits(1) as f64]);
        assert_eq!((low, bits), (-149, 128 + 149));
        let big: BigInt = integer(f32::MAX as f64, low);
        assert_eq!(big, BigInt::from(0xff_ffff) << (104 + 149) as u32);
        assert_eq!(integer::<i128>(-0.75, -3), -6);
    }

    /// The i128 and BigInt paths agree, including at the bit limits.
    #[test]
    fn both_arithmetics_agree() {
        let mut rng = crate::sample::Rng::new(5);
        for round in 0..2000 {
            // Coordinates spread over 2^(round % 70) to exercise both paths.
            let spread = round % 70;
            let mut value = || {
                let x = rng.range(-1.0, 1.0) as f64 * 2f64.powi(-(rng.range(0.0, spread as f32 + 1.0) as i32));
                (x as f32) as f64
            };
            let v = [
                [value(), value(), value()],
                [value(), value(), value()],
                [value(), value(), value()],
            ];
            let lo = [value(), value(), value()];
            let hi: [f64; 3] = std::array::from_fn(|k| lo[k].max(value()));
            let (low, bits) = common_scale(&polygon_box_values(&v, &lo, &hi).unwrap());
            if bits > 60 {
                continue;
            }
            for i in 0..3 {
                for j in 0..3 {
                    assert_eq!(
                        edge_axis_separates_in::<i128>(&v, i, j, &lo, &hi, low),
                        edge_axis_separates_in::<BigInt>(&v, i, j, &lo, &hi, low)
                    );
                }
            }
            if bits <= 38 {
                assert_eq!(
                    normal_separates_in::<i128>(&v, &lo, &hi, low),
                    normal_separates_in::<BigInt>(&v, &lo, &hi, low)
                );
            }
        }
    }

    #[test]
    fn touching_is_not_separated() {
        // The triangle lies in the plane z = 1, the box's top face.
        let v = [[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]];
        assert!(!normal_separates(&v, &[0.0; 3], &[1.0; 3]));
        assert!(normal_separates(&v, &[0.0; 3], &[1.0, 1.0, 0.75]));
        // Hypotenuse x + y = 1 against a box whose corner (0.5, 0.5) lies on it.
        let corner = [0.5, 0.5, 0.0];
        for j in 0..3 {
            assert!(!edge_axis_separates(&v, 1, j, &corner, &[2.0; 3]));
        }
        // One f32 step beyond: separated along the hypotenuse's axis only.
        let beyond = f32::from_bits(0.5f32.to_bits() + 1) as f64;
        assert!(edge_axis_separates(&v, 1, 2, &[0.5, beyond, 0.0], &[2.0; 3]));
    }

    #[test]
    fn segments_through_corners_touch() {
        // The diagonal of the unit square passes exactly through the corner (1, 1).
        let (a, b) = ([0.0, 0.0, 0.5], [2.0, 2.0, 0.5]);
        assert!(segment_overlaps(a, b, [1.0, 1.0, 0.0], [3.0, 3.0, 1.0]));
        assert!(segment_overlaps(a, b, [-1.0, 1.0, 0.0], [1.0, 3.0, 1.0]));
        let beyond = f32::from_bits(1.0f32.to_bits() + 1) as f64;
        assert!(!segment_overlaps(a, b, [-1.0, beyond, 0.0], [1.0, 3.0, 1.0]));
        // A point (zero-length segment) on a face.
        assert!(segment_overlaps([1.0, 0.5, 0.5], [1.0, 0.5, 0.5], [0.0; 3], [1.0; 3]));
        assert!(!segment_overlaps(
            [beyond, 0.5, 0.5],
            [beyond, 0.5, 0.5],
            [0.0; 3],
            [1.0; 3]
        ));
    }
}
