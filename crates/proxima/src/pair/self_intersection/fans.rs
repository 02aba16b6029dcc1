//! Vertices whose ring of triangles certifies, by itself, that any two of
//! those triangles meet only where they share vertices.
//!
//! Most candidate pairs of a self-intersection walk are neighbours, and
//! nearly all of them sit in a flat-enough closed fan. A fan around `v` is
//! **certified** when
//!
//! 1. its triangles, each rotated to start at `v` as `(v, from, to)`, have
//!    edges `from → to` in which every ring vertex is once a start and once
//!    an end, none of them `v` (a manifold, consistently oriented fan with
//!    no repeated index: a set of cycles), and
//! 2. projected by dropping one coordinate (exact), every triangle is
//!    strictly counter-clockwise around `v` (exact `orient2d`), and the
//!    edges wind exactly once around `v` in all (exact crossing count).
//!    A closed chain of such edges winds at least once, so the edges form
//!    one cycle `w₁ → w₂ → … → w_k → w₁`, `k ≥ 3`: the fan is closed.
//!
//! **Why that suffices.** By 2 the projected triangles lie in angular
//! sectors around `P(v)`, each less than a half-turn, that go around once:
//! they tile the plane, so the closed sectors of two triangles that are not
//! consecutive meet only at `P(v)`, and consecutive ones only on their common
//! ray. A triangle projecting without degeneracy, the projection is a
//! bijection from it onto its image. A point `z` common to non-consecutive
//! triangles projects to `P(v)`, over which each has only `v`: `z = v`. A
//! point common to consecutive triangles `(v, wᵢ₋₁, wᵢ)` and `(v, wᵢ, wᵢ₊₁)`
//! projects onto the common ray, where each projected triangle holds only
//! the projected edge `P(v)P(wᵢ)` (its third corner is strictly to one side):
//! `z` lies on the shared edge `vwᵢ`. So two triangles of a certified fan
//! meet only at what they share, and since by 1 the fan holds every
//! triangle that has `v`, **any pair of triangles sharing a certified vertex
//! is settled** without a test.

use crate::Vec3;
use crate::math::DVec3;
use rayon::prelude::*;
use robust::{Coord, orient2d};

/// Fans of more triangles than this are left to the pair tests.
const MOST_TRIANGLES: usize = 32;

/// For each vertex, whether its fan is certified (see the module doc), from
/// the vertex positions and each triangle's vertex indices.
pub(super) fn certified_vertices(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<bool> {
    let vertices = positions.len();
    // Each vertex's triangles as the edges `from → to` opposite it (the
    // triangle rotated to start there), one list per vertex: filled
    // triangle by triangle, so that the certificates below read each list
    // in one piece rather than chase triangles.
    let mut offsets = vec![0u32; vertices + 1];
    for t in triangles {
        for &v in t {
            if let Some(count) = offsets.get_mut(v as usize + 1) {
                *count += 1;
            }
        }
    }
    for v in 0..vertices {
        offsets[v + 1] += offsets[v];
    }
    let mut fill = offsets.clone();
    let mut ring = vec![[0u32; 2]; offsets[vertices] as usize];
    for &[a, b, c] in triangles {
        for (v, edge) in [(a, [b, c]), (b, [c, a]), (c, [a, b])] {
            if let Some(at) = fill.get_mut(v as usize) {
                ring[*at as usize] = edge;
                *at += 1;
            }
        }
    }
    drop(fill);
    (0..vertices)
        .into_par_iter()
        .with_min_len(4096)
        .map(|v| {
            let own = &ring[offsets[v] as usize..offsets[v + 1] as usize];
            fan_certified(v as u32, own, positions)
        })
        .collect()
}

/// Whether the fan of `v`, given as the edges opposite it, is certified.
fn fan_certified(v: u32, own: &[[u32; 2]], positions: &[Vec3]) -> bool {
    let k = own.len();
    if !(3..=MOST_TRIANGLES).contains(&k) {
        return false;
    }
    // Each triangle rotated to (v, from, to). The edges are a permutation
    // of the ring's vertices (each vertex once as a start and once as an
    // end) and none touches v; that it is one cycle, not several, follows
    // from the winding below: each cycle would wind at least once.
    for &[from, to] in own {
        let starts = own.iter().filter(|e| e[0] == from).count();
        let ends = own.iter().filter(|e| e[0] == to).count();
        if from == v || to == v || from == to || starts != 1 || ends != 1 {
            return false;
        }
    }
    let p = |i: u32| positions[i as usize].as_dvec3();
    let apex = p(v);
    // Drop the coordinate along which the fan's area-weighted normal is
    // largest, and mirror so that the fan turns counter-clockwise.
    let mut normal = DVec3::ZERO;
    for &[a, b] in own {
        normal += (p(a) - apex).cross(p(b) - apex);
    }
    let axis = normal.abs().max_position();
    let flip = normal[axis] < 0.0;
    let project = |q: DVec3| {
        let (x, y) = match axis {
            0 => (q.y, q.z),
            1 => (q.z, q.x),
            _ => (q.x, q.y),
        };
        if flip { Coord { x: y, y: x } } else { Coord { x, y } }
    };
    let centre = project(apex);
    let mut winding = 0u32;
    for &[a, b] in own {
        let (a, b) = (project(p(a)), project(p(b)));
        if orient2d(centre, a, b) <= 0.0 {
            return false;
        }
        // Sunday's winding rule on the ray from the centre towards +x, with
        // half-open ends: every edge has the centre strictly to its left,
        // so an upward edge crosses the ray and a downward one never does.
        if a.y <= centre.y && b.y > centre.y {
            winding += 1;
        }
    }
    winding == 1
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed fan of `k` triangles around the origin, ring at height
    /// `heights[i]`, radius 1.
    fn fan(k: usize, heights: &[f32]) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let mut positions = vec![Vec3::ZERO];
        for i in 0..k {
            let angle = std::f32::consts::TAU * i as f32 / k as f32;
            positions.push(Vec3::new(angle.cos(), angle.sin(), heights[i % heights.len()]));
        }
        let triangles = (0..k as u32).map(|i| [0, 1 + i, 1 + (i + 1) % k as u32]).collect();
        (positions, triangles)
    }

    #[test]
    fn flat_and_bumpy_closed_fans_are_certified_open_and_folded_ones_not() {
        let (p, t) = fan(6, &[0.0]);
        assert!(certified_vertices(&p, &t)[0]);
        let (p, t) = fan(7, &[0.3, -0.2, 0.5]);
        assert!(certified_vertices(&p, &t)[0]);
        // Reversed orientation: still one cycle, turning the other way.
        let (p, mut t) = fan(5, &[0.1]);
        for tri in &mut t {
            tri.swap(1, 2);
        }
        assert!(certified_vertices(&p, &t)[0]);
        // Open fan (one triangle removed): not closed.
        let (p, mut t) = fan(6, &[0.0]);
        t.pop();
        assert!(!certified_vertices(&p, &t)[0]);
        // One triangle flipped: not consistently oriented.
        let (p, mut t) = fan(6, &[0.0]);
        t[2].swap(1, 2);
        assert!(!certified_vertices(&p, &t)[0]);
        // A ring going around twice (a fan folded over itself): winding 2.
        let mut p = vec![Vec3::ZERO];
        for i in 0..8 {
            let angle = std::f32::consts::TAU * 2.0 * i as f32 / 8.0 + 0.1;
            p.push(Vec3::new(angle.cos(), angle.sin(), i as f32 * 0.01));
        }
        let t: Vec<[u32; 3]> = (0..8u32).map(|i| [0, 1 + i, 1 + (i + 1) % 8]).collect();
        assert!(!certified_vertices(&p, &t)[0]);
        // A triangle degenerate in every projection (a ring point on the apex).
        let (mut p, t) = fan(6, &[0.0]);
        p[3] = Vec3::ZERO;
        assert!(!certified_vertices(&p, &t)[0]);
    }
}
