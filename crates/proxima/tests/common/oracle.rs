//! Independent oracles shared by the tests: `f64` point-to-primitive
//! distances by plane projection plus edges (not the Voronoi-region walk under
//! test), and Sutherland–Hodgman clipping of a convex polygon by the six
//! closed half-spaces of a box, in `f64` or in exact rationals.

use proxima::{Aabb, Triangle, Vec3};

/// A point or vector in `f64`.
pub type D3 = [f64; 3];

pub fn d3(v: Vec3) -> D3 {
    [v.x as f64, v.y as f64, v.z as f64]
}
pub fn sub(a: D3, b: D3) -> D3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub fn dot(a: D3, b: D3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub fn cross(a: D3, b: D3) -> D3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
pub fn dist(a: D3, b: D3) -> f64 {
    dot(sub(a, b), sub(a, b)).sqrt()
}

/// Distance from `p` to the segment `ab` (a point when `a == b`).
pub fn segment_distance(a: D3, b: D3, p: D3) -> f64 {
    let ab = sub(b, a);
    let len2 = dot(ab, ab);
    let t = if len2 > 0.0 {
        (dot(sub(p, a), ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dist([a[0] + ab[0] * t, a[1] + ab[1] * t, a[2] + ab[2] * t], p)
}

/// Distance from `p` to a triangle: the plane projection if it falls inside
/// (signed areas in `f64`), else the nearest edge. Degenerate triangles are
/// their edges.
pub fn triangle_distance(t: &Triangle, p: D3) -> f64 {
    let (a, b, c) = (d3(t.a), d3(t.b), d3(t.c));
    let edges = segment_distance(a, b, p)
        .min(segment_distance(b, c, p))
        .min(segment_distance(c, a, p));
    let n = cross(sub(b, a), sub(c, a));
    let nn = dot(n, n);
    if nn <= 1e-30 * dot(sub(b, a), sub(b, a)).max(dot(sub(c, a), sub(c, a))).powi(2) {
        return edges;
    }
    let h = dot(sub(p, a), n) / nn;
    let q = [p[0] - n[0] * h, p[1] - n[1] * h, p[2] - n[2] * h];
    let inside = [(a, b), (b, c), (c, a)]
        .iter()
        .all(|&(u, v)| dot(cross(sub(v, u), sub(q, u)), n) >= 0.0);
    if inside { dist(q, p).min(edges) } else { edges }
}

/// The arithmetic of the clipping oracle: `f64`, or exact rationals.
pub trait Num: Copy {
    fn of(x: f32) -> Self;
    fn of64(x: f64) -> Self;
    fn sub(self, o: Self) -> Self;
    fn mul(self, o: Self) -> Self;
    fn div(self, o: Self) -> Self;
    fn le_zero(self) -> bool;
}

impl Num for f64 {
    fn of(x: f32) -> Self {
        x as f64
    }
    fn of64(x: f64) -> Self {
        x
    }
    fn sub(self, o: Self) -> Self {
        self - o
    }
    fn mul(self, o: Self) -> Self {
        self * o
    }
    fn div(self, o: Self) -> Self {
        self / o
    }
    fn le_zero(self) -> bool {
        self <= 0.0
    }
}

/// An exact rational `n / d`, `d > 0`, kept reduced; built from floats that
/// are multiples of 2^-10 (small integers included).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Q(pub i128, pub i128);

impl Q {
    pub fn new(n: i128, d: i128) -> Q {
        assert!(d != 0, "division by zero in the exact oracle");
        let (n, d) = if d < 0 { (-n, -d) } else { (n, d) };
        let (mut a, mut b) = (n.abs(), d);
        while b != 0 {
            (a, b) = (b, a % b);
        }
        let g = a.max(1);
        Q(n / g, d / g)
    }
}

impl Num for Q {
    fn of(x: f32) -> Self {
        Q::of64(x as f64)
    }
    fn of64(x: f64) -> Self {
        let scaled = x * 1024.0;
        assert!(
            scaled == scaled.trunc() && scaled.abs() < 1e15,
            "the exact oracle takes multiples of 2^-10, got {x}"
        );
        Q::new(scaled as i128, 1024)
    }
    fn sub(self, o: Self) -> Self {
        Q::new(self.0 * o.1 - o.0 * self.1, self.1 * o.1)
    }
    fn mul(self, o: Self) -> Self {
        Q::new(self.0 * o.0, self.1 * o.1)
    }
    fn div(self, o: Self) -> Self {
        Q::new(self.0 * o.1, self.1 * o.0)
    }
    fn le_zero(self) -> bool {
        self.0 <= 0
    }
}

/// Most vertices a clipped polygon can have: 8 input vertices plus one per
/// clipping plane.
const CLIP_CAPACITY: usize = 8 + 6;

/// `true` when the convex planar polygon (1 to 8 points: a point, a segment, a
/// triangle or a polygon) meets the closed box: Sutherland–Hodgman clipping by
/// the six closed half-spaces leaves something. Fixed arrays, no allocation
/// (the grid tests call it for every cell of every triangle's box).
pub fn clip_by_box<N: Num>(points: &[Vec3], b: &Aabb) -> bool {
    clip_by_bounds::<N>(points, d3(b.min), d3(b.max))
}

/// [`clip_by_box`] for a box with `f64` bounds (a grid's exact cells).
pub fn clip_by_bounds<N: Num>(points: &[Vec3], lo: D3, hi: D3) -> bool {
    assert!(!points.is_empty() && points.len() <= 8);
    let mut poly = [[N::of(0.0); 3]; CLIP_CAPACITY];
    let mut n = points.len();
    for (slot, p) in poly.iter_mut().zip(points) {
        *slot = [N::of(p.x), N::of(p.y), N::of(p.z)];
    }
    for axis in 0..3 {
        for (plane, upper) in [(N::of64(lo[axis]), false), (N::of64(hi[axis]), true)] {
            let side = |p: &[N; 3]| if upper { p[axis].sub(plane) } else { plane.sub(p[axis]) };
            let mut out = [[N::of(0.0); 3]; CLIP_CAPACITY];
            let mut m = 0;
            for i in 0..n {
                let (prev, cur) = (&poly[(i + n - 1) % n], &poly[i]);
                let (dp, dc) = (side(prev), side(cur));
                if dp.le_zero() != dc.le_zero() {
                    // x = (prev · dc − cur · dp) / (dc − dp), exact on the plane's axis.
                    let mut x = [plane; 3];
                    for k in (0..3).filter(|&k| k != axis) {
                        x[k] = prev[k].mul(dc).sub(cur[k].mul(dp)).div(dc.sub(dp));
                    }
                    out[m] = x;
                    m += 1;
                }
                if dc.le_zero() {
                    out[m] = *cur;
                    m += 1;
                }
            }
            if m == 0 {
                return false;
            }
            (poly, n) = (out, m);
        }
    }
    true
}
