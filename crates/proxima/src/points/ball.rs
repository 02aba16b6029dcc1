//! Which points lie within a radius: the exact test, and the visitors that
//! collect them over any structure's nearest-first walk.

use crate::exact::{Exact, common_scale, integers};
use crate::math::{Vec3, Vec3A};
use crate::primitive::Point;
use crate::query::NearestVisitor;
use crate::query::knn::{Candidate, KBest};
use num_bigint::BigInt;

/// `|q - p| <= r`, decided exactly for the `f32` points and the `f64`
/// radius: in `f64` when rounding cannot change the answer (nearly always),
/// else in integers at the common scale of the inputs.
///
/// Each coordinate difference of two `f32`s is exact in `f64` or off by at
/// most half an ulp of itself; its square and the two sums add three more
/// roundings, and `r * r` one: `8ε (d² + r²)` covers them all.
#[inline]
pub(crate) fn within_exact(p: Vec3, q: Vec3, r: f64) -> bool {
    let d2 = (q.as_dvec3() - p.as_dvec3()).length_squared();
    let r2 = r * r;
    if r2 == f64::INFINITY {
        // r beyond 1e154: far past any distance between f32 points.
        return true;
    }
    let slack = 8.0 * f64::EPSILON * (d2 + r2);
    if d2 + slack < r2 {
        return true;
    }
    if d2 - slack > r2 {
        return false;
    }
    let values = [p.x, p.y, p.z, q.x, q.y, q.z].map(f64::from);
    let all = [values[0], values[1], values[2], values[3], values[4], values[5], r];
    let (low, bits) = common_scale(&all);
    // Squares of integers of `bits` bits, three summed: 2 bits + 2.
    if 2 * bits + 3 < 127 {
        decide::<i128>(&values, r, low)
    } else {
        decide::<BigInt>(&values, r, low)
    }
}

/// `Σ (q_k - p_k)² <= r²` in integers at the scale `2^-low`.
fn decide<T: Exact>(values: &[f64; 6], r: f64, low: i32) -> bool {
    let p: [T; 3] = integers(&[values[0], values[1], values[2]], low);
    let q: [T; 3] = integers(&[values[3], values[4], values[5]], low);
    let [radius]: [T; 1] = [crate::exact::integer(r, low)];
    let mut d2 = T::zero();
    for k in 0..3 {
        let d = q[k].clone() - p[k].clone();
        d2 = d2 + d.clone() * d;
    }
    d2 <= radius.clone() * radius
}

/// The squared pruning radius of a ball query in the walks' `f32`: above
/// `r²` by more than the rounding of a point's `f32` squared distance (a
/// few parts in 10⁷), and never subnormal, so that every point within `r`
/// is handed to the exact test.
pub(crate) fn walk_bound(r: f64) -> f32 {
    ((r * r) as f32 * (1.0 + 1e-5)).max(1e-30)
}

/// Collects every point within `r` of `centre` (as candidates, unsorted).
pub(crate) struct Ball<'a> {
    pub(crate) centre: Vec3,
    pub(crate) r: f64,
    pub(crate) bound: f32,
    pub(crate) indices: &'a [u32],
    pub(crate) out: &'a mut Vec<Candidate>,
}

impl NearestVisitor<Point> for Ball<'_> {
    #[inline(always)]
    fn bound(&self) -> f32 {
        self.bound
    }

    #[inline(always)]
    fn visit(&mut self, slot: usize, primitive: &Point, p: Vec3A) {
        let q = Vec3A::from(primitive.0);
        let d2 = (q - p).length_squared();
        if d2 <= self.bound {
            NearestVisitor::<Point>::offer(self, slot, self.indices[slot], q, d2);
        }
    }

    #[inline(always)]
    fn offer(&mut self, slot: usize, index: u32, q: Vec3A, d2: f32) {
        if d2 <= self.bound && within_exact(self.centre, q.into(), self.r) {
            self.out.push(Candidate {
                distance_squared: d2,
                index,
                slot: slot as u32,
                point: q,
            });
        }
    }
}

/// The nearest `k` points within `r` of `centre` (the ball query of
/// PointNet++): k-nearest whose reach starts at `r`, each candidate
/// admitted by the exact test.
pub(crate) struct CappedBall<'a> {
    pub(crate) centre: Vec3,
    pub(crate) r: f64,
    pub(crate) best: KBest<'a>,
}

impl NearestVisitor<Point> for CappedBall<'_> {
    #[inline(always)]
    fn bound(&self) -> f32 {
        self.best.bound
    }

    #[inline(always)]
    fn visit(&mut self, slot: usize, primitive: &Point, p: Vec3A) {
        let q = Vec3A::from(primitive.0);
        let d2 = (q - p).length_squared();
        if d2 <= self.best.bound {
            NearestVisitor::<Point>::offer(self, slot, self.best.indices[slot], q, d2);
        }
    }

    #[inline(always)]
    fn offer(&mut self, slot: usize, index: u32, q: Vec3A, d2: f32) {
        if d2 <= self.best.bound && within_exact(self.centre, q.into(), self.r) {
            self.best.offer(Candidate {
                distance_squared: d2,
                index,
                slot: slot as u32,
                point: q,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_rational::BigRational;

    /// `|q - p|² <= r²` in exact rationals.
    fn oracle(p: Vec3, q: Vec3, r: f64) -> bool {
        let x = |v: f64| BigRational::from_float(v).unwrap();
        let mut d2 = x(0.0);
        for k in 0..3 {
            let d = x(f64::from(q[k])) - x(f64::from(p[k]));
            d2 += &d * &d;
        }
        d2 <= x(r) * x(r)
    }

    #[test]
    fn points_on_the_sphere_and_ulps_off_it_match_exact_rationals() {
        let mut rng = crate::sample::Rng::new(39);
        let mut decided = [0usize; 2];
        for case in 0..4000 {
            let scale = 2f32.powi(rng.below(40) as i32 - 20);
            let p = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * scale;
            // Pythagorean offsets put q exactly at distance r (3-4-12-13,
            // 2-3-6-7, 1-4-8-9), then nudged by a few ulps either way.
            let [a, b, c, d] = [[3.0, 4.0, 12.0, 13.0], [2.0, 3.0, 6.0, 7.0], [1.0, 4.0, 8.0, 9.0]][case % 3];
            let unit = scale / 64.0;
            let mut q = p + Vec3::new(a, b, c) * unit;
            let mut r = f64::from(d * unit);
            match case % 5 {
                1 => q.x = q.x.next_up(),
                2 => q.x = q.x.next_down(),
                3 => r = r.next_up(),
                4 => r = r.next_down(),
                _ => {}
            }
            let expected = oracle(p, q, r);
            assert_eq!(within_exact(p, q, r), expected, "{p:?} {q:?} {r}");
            assert_eq!(within_exact(q, p, r), expected);
            decided[expected as usize] += 1;
        }
        assert!(decided[0] > 500 && decided[1] > 500, "{decided:?}");
        // A radius far below the points' scale, and a huge one.
        let p = Vec3::new(1.0, 2.0, 3.0);
        assert!(within_exact(p, p, 0.0));
        assert!(!within_exact(p, Vec3::new(1.0f32.next_up(), 2.0, 3.0), 1e-300));
        assert!(within_exact(p, Vec3::new(-1e18, 0.0, 0.0), 1e300));
        assert!(within_exact(p, Vec3::new(-1e18, 0.0, 0.0), f64::INFINITY));
        assert!(!within_exact(p, Vec3::new(-1e18, 0.0, 0.0), 9e17));
    }
}
