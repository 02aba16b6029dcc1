//! Exact rational oracles of the triangle-pair primitives (pair/), written
//! independently of the library's orientation tests:
//!
//! - [`common_vertices`]: the vertices of `A ∩ B` for closed triangles
//!   (degenerate ones too), as the basic feasible solutions of the barycentric
//!   system `Σλ_i a_i = Σμ_j b_j`, `Σλ = Σμ = 1`, `λ, μ ≥ 0`, solved in
//!   `BigRational` for every set of independent columns. The triangles meet iff
//!   there is one; `A ∩ B` is their convex hull, so it leaves a convex set `S`
//!   iff one of them lies outside `S` (the neighbour rule).
//! - [`separated`]: the separating-axis test in `BigRational` over
//!   `n_a, n_b, e_i × f_j, n_a × e_i, n_b × f_j` (non-degenerate triangles).
//! - [`distance_squared`]: the 6 point-triangle and 9 segment-segment squared
//!   distances, each as the least of its closed-form candidates (interior
//!   critical point when inside, then the boundary), in `BigRational`.
#![allow(dead_code)]

use num_rational::BigRational;
use num_traits::{Signed, ToPrimitive, Zero};
use proxima::math::DVec3;

/// An exact rational.
pub type Q = BigRational;
/// An exact rational point.
pub type Q3 = [Q; 3];

/// The exact value of an `f64`.
pub fn q(x: f64) -> Q {
    Q::from_float(x).expect("finite")
}

/// The exact point of a `DVec3`.
pub fn q3(p: DVec3) -> Q3 {
    [q(p.x), q(p.y), q(p.z)]
}

pub fn sub(a: &Q3, b: &Q3) -> Q3 {
    [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]]
}

pub fn add(a: &Q3, b: &Q3) -> Q3 {
    [&a[0] + &b[0], &a[1] + &b[1], &a[2] + &b[2]]
}

pub fn scale(a: &Q3, s: &Q) -> Q3 {
    [&a[0] * s, &a[1] * s, &a[2] * s]
}

pub fn dot(a: &Q3, b: &Q3) -> Q {
    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
}

pub fn cross(a: &Q3, b: &Q3) -> Q3 {
    [
        &a[1] * &b[2] - &a[2] * &b[1],
        &a[2] * &b[0] - &a[0] * &b[2],
        &a[0] * &b[1] - &a[1] * &b[0],
    ]
}

/// The side of `p` against the plane of `t`: the sign of
/// `((t1 - t0) × (t2 - t0)) · (p - t0)`, exact (0 when `t` is degenerate).
pub fn side(t: &[DVec3; 3], p: DVec3) -> i32 {
    let [t0, t1, t2] = t.map(q3);
    let n = cross(&sub(&t1, &t0), &sub(&t2, &t0));
    let d = dot(&n, &sub(&q3(p), &t0));
    if d.is_zero() {
        0
    } else if d.is_positive() {
        1
    } else {
        -1
    }
}

pub fn is_zero(a: &Q3) -> bool {
    a.iter().all(Zero::is_zero)
}

/// Unique solution of `m x = rhs` (rows of `m`), `None` when the columns are
/// dependent or the system inconsistent.
fn solve_unique(m: &[Vec<Q>], rhs: &[Q]) -> Option<Vec<Q>> {
    let cols = m[0].len();
    let mut rows: Vec<Vec<Q>> = m
        .iter()
        .zip(rhs)
        .map(|(r, b)| r.iter().cloned().chain([b.clone()]).collect())
        .collect();
    let mut pivot_row = 0;
    for col in 0..cols {
        let found = (pivot_row..rows.len()).find(|&r| !rows[r][col].is_zero())?;
        rows.swap(pivot_row, found);
        let pivot = rows[pivot_row][col].clone();
        for v in rows[pivot_row].iter_mut() {
            *v = &*v / &pivot;
        }
        let pivot_values = rows[pivot_row].clone();
        for (r, row) in rows.iter_mut().enumerate() {
            if r != pivot_row && !row[col].is_zero() {
                let factor = row[col].clone();
                for (v, p) in row.iter_mut().zip(&pivot_values) {
                    *v -= &factor * p;
                }
            }
        }
        pivot_row += 1;
    }
    // Rows beyond the pivots must read 0 = 0.
    if rows[pivot_row..].iter().any(|r| !r[cols].is_zero()) {
        return None;
    }
    Some((0..cols).map(|c| rows[c][cols].clone()).collect())
}

/// The vertices of the closed `A ∩ B` (with repetitions), empty when the
/// triangles do not meet.
pub fn common_vertices(a: &[DVec3; 3], b: &[DVec3; 3]) -> Vec<Q3> {
    vertices_of_intersection(a, b, usize::MAX)
}

/// The closed triangles share a point (barycentric feasibility, exact).
pub fn meet(a: &[DVec3; 3], b: &[DVec3; 3]) -> bool {
    !vertices_of_intersection(a, b, 1).is_empty()
}

/// Up to `limit` vertices of `A ∩ B`.
fn vertices_of_intersection(a: &[DVec3; 3], b: &[DVec3; 3], limit: usize) -> Vec<Q3> {
    let qa = a.map(q3);
    let qb = b.map(q3);
    // Columns: λ0..λ2 (a's vertices), μ0..μ2 (minus b's vertices).
    let column = |c: usize| -> [Q; 5] {
        let one = Q::from_integer(1.into());
        let zero = Q::zero();
        if c < 3 {
            [qa[c][0].clone(), qa[c][1].clone(), qa[c][2].clone(), one, zero]
        } else {
            let p = &qb[c - 3];
            [-p[0].clone(), -p[1].clone(), -p[2].clone(), zero, one]
        }
    };
    let columns: Vec<[Q; 5]> = (0..6).map(column).collect();
    let rhs: Vec<Q> = [0, 0, 0, 1, 1]
        .iter()
        .map(|&v: &i64| Q::from_integer(v.into()))
        .collect();
    let mut out = Vec::new();
    for subset in 1u32..64 {
        let chosen: Vec<usize> = (0..6).filter(|c| subset & (1 << c) != 0).collect();
        if chosen.len() > 5 {
            continue;
        }
        let m: Vec<Vec<Q>> = (0..5)
            .map(|r| chosen.iter().map(|&c| columns[c][r].clone()).collect())
            .collect();
        let Some(x) = solve_unique(&m, &rhs) else { continue };
        if x.iter().any(|v| v.is_negative()) {
            continue;
        }
        let mut point = [Q::zero(), Q::zero(), Q::zero()];
        for (&c, w) in chosen.iter().zip(&x) {
            if c < 3 {
                point = add(&point, &scale(&qa[c], w));
            }
        }
        out.push(point);
        if out.len() >= limit {
            break;
        }
    }
    out
}

/// `x` lies on the closed segment `pq` (a point when `p == q`).
pub fn on_segment(x: &Q3, p: &Q3, q: &Q3) -> bool {
    let d = sub(q, p);
    let v = sub(x, p);
    if is_zero(&d) {
        return is_zero(&v);
    }
    is_zero(&cross(&v, &d)) && !dot(&v, &d).is_negative() && dot(&v, &d) <= dot(&d, &d)
}

/// The neighbour rule by its definition: faces with the same index set meet;
/// otherwise they meet when `A ∩ B` reaches beyond the hull of the positions
/// of their shared indices.
pub fn neighbours_meet(a: &[DVec3; 3], ia: [u32; 3], b: &[DVec3; 3], ib: [u32; 3]) -> bool {
    let same_set = ia.iter().all(|i| ib.contains(i)) && ib.iter().all(|i| ia.contains(i));
    if same_set {
        return true;
    }
    let mut shared: Vec<Q3> = Vec::new();
    let mut seen = Vec::new();
    for (k, i) in ia.iter().enumerate() {
        if ib.contains(i) && !seen.contains(i) {
            seen.push(*i);
            shared.push(q3(a[k]));
        }
    }
    let vertices = common_vertices(a, b);
    match shared.len() {
        0 => !vertices.is_empty(),
        1 => vertices.iter().any(|x| *x != shared[0]),
        _ => vertices.iter().any(|x| !on_segment(x, &shared[0], &shared[1])),
    }
}

/// Exactly separated by one of the separating-axis candidates (both
/// triangles non-degenerate).
pub fn separated(a: &[DVec3; 3], b: &[DVec3; 3]) -> bool {
    let qa = a.map(q3);
    let qb = b.map(q3);
    let e: Vec<Q3> = (0..3).map(|i| sub(&qa[(i + 1) % 3], &qa[i])).collect();
    let f: Vec<Q3> = (0..3).map(|i| sub(&qb[(i + 1) % 3], &qb[i])).collect();
    let na = cross(&e[0], &e[1]);
    let nb = cross(&f[0], &f[1]);
    assert!(
        !is_zero(&na) && !is_zero(&nb),
        "separated() needs non-degenerate triangles"
    );
    let mut axes = vec![na.clone(), nb.clone()];
    for ei in &e {
        for fj in &f {
            axes.push(cross(ei, fj));
        }
        axes.push(cross(&na, ei));
    }
    for fj in &f {
        axes.push(cross(&nb, fj));
    }
    axes.iter().filter(|axis| !is_zero(axis)).any(|axis| {
        let pa: Vec<Q> = qa.iter().map(|p| dot(p, axis)).collect();
        let pb: Vec<Q> = qb.iter().map(|p| dot(p, axis)).collect();
        let (amin, amax) = (pa.iter().min().unwrap(), pa.iter().max().unwrap());
        let (bmin, bmax) = (pb.iter().min().unwrap(), pb.iter().max().unwrap());
        amax < bmin || bmax < amin
    })
}

/// `|p - x|²` for the point `x = p0 + t (p1 - p0)`, `t` clamped to `[0, 1]`
/// (the closed-form closest point of a segment).
pub fn point_segment_d2(x: &Q3, p0: &Q3, p1: &Q3) -> Q {
    let d = sub(p1, p0);
    let dd = dot(&d, &d);
    if dd.is_zero() {
        let v = sub(x, p0);
        return dot(&v, &v);
    }
    let mut t = dot(&sub(x, p0), &d) / &dd;
    let zero = Q::zero();
    let one = Q::from_integer(1.into());
    if t < zero {
        t = zero;
    } else if t > one {
        t = one;
    }
    let y = add(p0, &scale(&d, &t));
    let v = sub(x, &y);
    dot(&v, &v)
}

/// Squared distance from `x` to the closed triangle: the orthogonal
/// projection when its barycentric coordinates (Cramer on the Gram matrix)
/// are all non-negative, else the least over the three edges.
pub fn point_triangle_d2(x: &Q3, t: &[Q3; 3]) -> Q {
    let edges = (0..3)
        .map(|i| point_segment_d2(x, &t[i], &t[(i + 1) % 3]))
        .min()
        .unwrap();
    let u = sub(&t[1], &t[0]);
    let v = sub(&t[2], &t[0]);
    let w = sub(x, &t[0]);
    let (uu, uv, vv) = (dot(&u, &u), dot(&u, &v), dot(&v, &v));
    let (wu, wv) = (dot(&w, &u), dot(&w, &v));
    let det = &uu * &vv - &uv * &uv;
    if det.is_zero() {
        return edges;
    }
    let s = (&wu * &vv - &wv * &uv) / &det;
    let r = (&wv * &uu - &wu * &uv) / &det;
    if s.is_negative() || r.is_negative() || &s + &r > Q::from_integer(1.into()) {
        return edges;
    }
    let y = add(&t[0], &add(&scale(&u, &s), &scale(&v, &r)));
    let d = sub(x, &y);
    dot(&d, &d).min(edges)
}

/// Squared distance between closed segments: the interior critical point of
/// `|p(s) - q(t)|²` when it lies in the unit square, and the four
/// endpoint-against-segment distances.
pub fn segment_segment_d2(p0: &Q3, p1: &Q3, q0: &Q3, q1: &Q3) -> Q {
    let ends = [
        point_segment_d2(p0, q0, q1),
        point_segment_d2(p1, q0, q1),
        point_segment_d2(q0, p0, p1),
        point_segment_d2(q1, p0, p1),
    ]
    .into_iter()
    .min()
    .unwrap();
    let d1 = sub(p1, p0);
    let d2 = sub(q1, q0);
    let r = sub(p0, q0);
    let (a, b, e) = (dot(&d1, &d1), dot(&d1, &d2), dot(&d2, &d2));
    let (c, f) = (dot(&d1, &r), dot(&d2, &r));
    let det = &a * &e - &b * &b;
    if det.is_zero() {
        return ends;
    }
    // Stationary point of |r + s d1 - t d2|²: a s - b t = -c, b s - e t = -f.
    let s = (&b * &f - &c * &e) / &det;
    let t = (&a * &f - &b * &c) / &det;
    let (zero, one) = (Q::zero(), Q::from_integer(1.into()));
    if s < zero || s > one || t < zero || t > one {
        return ends;
    }
    let x = sub(&add(p0, &scale(&d1, &s)), &add(q0, &scale(&d2, &t)));
    dot(&x, &x).min(ends)
}

/// The exact squared distance of two closed triangles: 0 when they meet
/// (separating axes, or the barycentric system for degenerate triangles),
/// otherwise the least of the 15 sub-distances.
pub fn distance_squared(a: &[DVec3; 3], b: &[DVec3; 3]) -> Q {
    let qa = a.map(q3);
    let qb = b.map(q3);
    let proper = |t: &[Q3; 3]| !is_zero(&cross(&sub(&t[1], &t[0]), &sub(&t[2], &t[0])));
    // Separating axes are the cheaper exact test; the barycentric system
    // covers degenerate triangles.
    let touching = if proper(&qa) && proper(&qb) {
        !separated(a, b)
    } else {
        meet(a, b)
    };
    if touching {
        return Q::zero();
    }
    let mut best: Vec<Q> = Vec::new();
    for p in &qa {
        best.push(point_triangle_d2(p, &qb));
    }
    for p in &qb {
        best.push(point_triangle_d2(p, &qa));
    }
    for i in 0..3 {
        for j in 0..3 {
            best.push(segment_segment_d2(&qa[i], &qa[(i + 1) % 3], &qb[j], &qb[(j + 1) % 3]));
        }
    }
    best.into_iter().min().unwrap()
}

/// The nearest `f64` of an exact rational.
pub fn to_f64(x: &Q) -> f64 {
    x.to_f64().expect("representable")
}
