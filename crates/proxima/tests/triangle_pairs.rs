//! The triangle-pair primitives of pair/ against exact rational oracles
//! (tests/pair_oracle): intersection of closed triangles (two independent
//! formulations: barycentric feasibility and separating axes), the neighbour
//! rule for faces sharing vertices, and the triangle-pair distance.
//!
//! Touching cases are built exactly: integer coordinates (multiples of 4)
//! times a power of two between 2^-10 and 2^10, so that midpoints and quarter
//! points are exact, then nudged 1 to 3 ulps either way; the oracle decides
//! every case.

use crate::pair_oracle;

use crate::pair_oracle::{distance_squared, meet, neighbours_meet, q3, separated, to_f64};
use proxima::math::DVec3;
use proxima::pair::{neighbours_intersect, segment_meets_triangle, triangle_distance, triangles_intersect};
use proxima::sample::Rng;

type Tri = [DVec3; 3];

/// A point of integer coordinates in `[-range, range]`, multiples of 4.
fn lattice(rng: &mut Rng, range: i64) -> DVec3 {
    let mut c = || ((rng.below((2 * range + 1) as usize) as i64 - range) * 4) as f64;
    DVec3::new(c(), c(), c())
}

fn scaled(t: &Tri, scale: f64, offset: DVec3) -> Tri {
    t.map(|p| p * scale + offset)
}

/// A power of two between 2^-10 and 2^10 (about 1e-3 to 1e3), so that
/// scaling keeps lattice constructions exact.
fn power_scale(rng: &mut Rng) -> f64 {
    2f64.powi(rng.below(21) as i32 - 10)
}

/// Moves one coordinate of one vertex by 1 to 3 ulps up or down.
fn nudge(t: &Tri, rng: &mut Rng) -> Tri {
    let mut out = *t;
    let v = rng.below(3);
    let k = rng.below(3);
    let steps = 1 + rng.below(3);
    let up = rng.below(2) == 0;
    for _ in 0..steps {
        out[v][k] = if up { out[v][k].next_up() } else { out[v][k].next_down() };
    }
    out
}

fn degenerate(t: &Tri) -> bool {
    let n = pair_oracle::cross(
        &pair_oracle::sub(&q3(t[1]), &q3(t[0])),
        &pair_oracle::sub(&q3(t[2]), &q3(t[0])),
    );
    pair_oracle::is_zero(&n)
}

/// Checks one pair (both orders, all vertex rotations of the arguments give
/// the same answer) against the oracles; returns the answer.
fn check_pair(a: &Tri, b: &Tri) -> bool {
    let expected = meet(a, b);
    if !degenerate(a) && !degenerate(b) {
        assert_eq!(!separated(a, b), expected, "the two oracles disagree on {a:?} {b:?}");
    }
    assert_eq!(triangles_intersect(a, b), expected, "{a:?} {b:?}");
    assert_eq!(triangles_intersect(b, a), expected, "swapped {a:?} {b:?}");
    let rotated = [b[1], b[2], b[0]];
    assert_eq!(triangles_intersect(a, &rotated), expected, "rotated {a:?} {b:?}");
    expected
}

/// Random pair near each other at one scale and offset.
fn random_pair(rng: &mut Rng) -> (Tri, Tri) {
    let scale = [1e-3, 1.0, 1e3][rng.below(3)] * (0.5 + rng.unit());
    let offset = DVec3::new(rng.gaussian(), rng.gaussian(), rng.gaussian()) * [0.0, 1.0, 1e3][rng.below(3)];
    let mut point = || offset + DVec3::new(rng.unit(), rng.unit(), rng.unit()) * scale;
    let a = [point(), point(), point()];
    let b = [point(), point(), point()];
    (a, b)
}

#[test]
fn random_pairs_match_the_exact_oracles() {
    let mut rng = Rng::new(36);
    let mut hits = 0;
    for _ in 0..250 {
        let (a, b) = random_pair(&mut rng);
        hits += check_pair(&a, &b) as usize;
    }
    // Both answers are well represented.
    assert!((25..=225).contains(&hits), "{hits} of 250 intersect");
}

#[test]
fn crossing_pairs_match_the_exact_oracles() {
    // Pairs in which each triangle crosses the other's plane with no vertex
    // on it (the most common case left after the plane tests): random, and
    // edge through edge exactly (touching at one point), then nudged.
    let mut rng = Rng::new(38);
    let (mut crossing, mut hits) = (0, 0);
    for i in 0..900 {
        let (a, b) = if i % 3 == 0 {
            touching_case(1, &mut rng)
        } else {
            random_pair(&mut rng)
        };
        let b = if i % 6 == 3 { nudge(&b, &mut rng) } else { b };
        let sides = |t: &Tri, of: &Tri| t.map(|p| pair_oracle::side(of, p));
        let (sa, sb) = (sides(&a, &b), sides(&b, &a));
        let straddles = |s: [i32; 3]| !s.contains(&0) && s.iter().any(|&x| x != s[0]);
        if straddles(sa) && straddles(sb) {
            crossing += 1;
            hits += check_pair(&a, &b) as usize;
        }
    }
    assert!(
        crossing > 300 && hits > 150 && crossing - hits > 60,
        "{crossing} crossing, {hits} meet"
    );
}

/// Exactly touching constructions on the lattice, and each nudged by 1..3 ulps.
fn touching_case(kind: usize, rng: &mut Rng) -> (Tri, Tri) {
    let a = [lattice(rng, 16), lattice(rng, 16), lattice(rng, 16)];
    let quarter = |p: DVec3, q: DVec3, r: DVec3, i: f64, j: f64| p + (q - p) * (i / 4.0) + (r - p) * (j / 4.0);
    let b = match kind {
        // A vertex of b inside a (quarter point).
        0 => [quarter(a[0], a[1], a[2], 1.0, 1.0), lattice(rng, 16), lattice(rng, 16)],
        // An edge of b through the midpoint of an edge of a.
        1 => {
            let m = (a[0] + a[1]) * 0.5;
            let d = lattice(rng, 8);
            [m + d, m - d, lattice(rng, 16)]
        }
        // Coplanar, sharing an edge (the third vertex anywhere in the plane).
        2 => {
            let (i, j) = (rng.below(9) as f64 - 4.0, rng.below(9) as f64 - 4.0);
            [a[0], a[1], quarter(a[0], a[1], a[2], i, j)]
        }
        // Coplanar, anywhere in the plane (overlapping or not).
        3 => {
            let mut point = || quarter(a[0], a[1], a[2], rng.below(13) as f64 - 4.0, rng.below(13) as f64 - 4.0);
            [point(), point(), point()]
        }
        // Vertex on vertex.
        4 => [a[2], lattice(rng, 16), lattice(rng, 16)],
        // An edge of b ending on an edge of a (midpoint), in a's plane or not.
        5 => [(a[1] + a[2]) * 0.5, lattice(rng, 16), lattice(rng, 16)],
        // Edge on edge, collinear and overlapping in part.
        _ => [
            quarter(a[0], a[1], a[2], 2.0, 0.0),
            quarter(a[0], a[1], a[2], 6.0, 0.0),
            lattice(rng, 16),
        ],
    };
    let scale = power_scale(rng);
    let offset = lattice(rng, 64) * scale * 16.0;
    (scaled(&a, scale, offset), scaled(&b, scale, offset))
}

#[test]
fn touching_pairs_and_their_nudges_match_the_oracle() {
    let mut rng = Rng::new(7);
    let mut touching = [0usize; 7];
    for (kind, count) in touching.iter_mut().enumerate() {
        for _ in 0..50 {
            let (a, b) = touching_case(kind, &mut rng);
            *count += check_pair(&a, &b) as usize;
            let nudged = nudge(&b, &mut rng);
            check_pair(&a, &nudged);
            check_pair(&nudge(&a, &mut rng), &b);
        }
    }
    // The constructions touch (kinds 0, 1, 2, 4, 5, 6 always; 3 when the
    // sampled points overlap a).
    for kind in [0, 1, 2, 4, 5, 6] {
        assert_eq!(touching[kind], 50, "kind {kind}");
    }
}

/// The same point a few ulps off the plane: lifted above never touches,
/// below always crosses (a's plane is z = 0, b's other vertices above).
#[test]
fn a_vertex_on_the_face_decides_by_one_ulp() {
    let a = [
        DVec3::new(-1.0, -1.0, 0.0),
        DVec3::new(3.0, -1.0, 0.0),
        DVec3::new(-1.0, 3.0, 0.0),
    ];
    let mut on = [
        DVec3::new(0.1, 0.3, 0.0),
        DVec3::new(0.2, 0.1, 1.0),
        DVec3::new(-0.3, 0.2, 2.0),
    ];
    assert!(triangles_intersect(&a, &on));
    on[0].z = 0f64.next_up();
    assert!(!triangles_intersect(&a, &on));
    on[0].z = 0f64.next_down();
    assert!(triangles_intersect(&a, &on));
    // On a's edge x = -1 exactly, and one ulp outside it.
    on[0] = DVec3::new(-1.0, 0.5, 0.0);
    assert!(triangles_intersect(&a, &on));
    on[0].x = (-1f64).next_down();
    assert!(!check_pair(&a, &on));
}

#[test]
fn degenerate_triangles_match_the_oracle() {
    let mut rng = Rng::new(11);
    for round in 0..300 {
        let (a, b) = touching_case(round % 7, &mut rng);
        let p = b[0];
        let d = lattice(&mut rng, 4) * power_scale(&mut rng);
        let degenerate_b: Tri = match round % 4 {
            0 => [p, p + d, p + d * 2.0], // collinear, distinct
            1 => [p, p, b[1]],            // repeated vertex
            2 => [p, p, p],               // a point
            _ => [p + d, p, p - d],       // collinear, middle vertex first
        };
        check_pair(&a, &degenerate_b);
        check_pair(&a, &nudge(&degenerate_b, &mut rng));
        // Degenerate against degenerate.
        let degenerate_a: Tri = [a[0], (a[0] + a[1]) * 0.5, a[1]];
        check_pair(&degenerate_a, &degenerate_b);
        check_pair(
            &degenerate_a,
            &[a[0] + (a[1] - a[0]) * 0.25, a[0] + (a[1] - a[0]) * 0.25, b[2]],
        );
    }
}

#[test]
fn hand_built_degenerate_cases() {
    let o = DVec3::ZERO;
    let (x, y, z) = (DVec3::X, DVec3::Y, DVec3::Z);
    let face = [o, x * 2.0, y * 2.0];
    // A point inside, on an edge, on a vertex, outside by one ulp.
    assert!(triangles_intersect(&face, &[x * 0.5; 3].map(|p| p + y * 0.5)));
    assert!(triangles_intersect(&face, &[x; 3]));
    assert!(triangles_intersect(&face, &[o; 3]));
    assert!(!triangles_intersect(
        &face,
        &[DVec3::new(0f64.next_down(), 0.5, 0.0); 3]
    ));
    // A segment through the face, one ending on it, one parallel above it.
    assert!(triangles_intersect(
        &face,
        &[z * -1.0 + x * 0.5, z + x * 0.5, z + x * 0.5]
    ));
    assert!(triangles_intersect(&face, &[x * 0.5, z + x * 0.5, z]));
    assert!(!triangles_intersect(&face, &[z, z + x, z + x * 2.0]));
    // Collinear segments: overlapping, touching end to end, disjoint.
    assert!(triangles_intersect(&[o, x, x * 2.0], &[x * 1.5, x * 3.0, x * 3.0]));
    assert!(triangles_intersect(&[o, x, x * 2.0], &[x * 2.0, x * 3.0, x * 3.0]));
    assert!(!triangles_intersect(
        &[o, x, x * 2.0],
        &[x * 2.0f64.next_up(), x * 3.0, x * 3.0]
    ));
    // Two points.
    assert!(triangles_intersect(&[z; 3], &[z; 3]));
    assert!(!triangles_intersect(
        &[z; 3],
        &[DVec3::new(0.0, 0.0, 1f64.next_up()); 3]
    ));
    // Non-finite input is refused quietly.
    assert!(!triangles_intersect(&face, &[DVec3::NAN; 3]));
    assert!(!segment_meets_triangle(DVec3::INFINITY, o, &face));
}

#[test]
fn segment_meets_triangle_matches_the_oracle() {
    let mut rng = Rng::new(5);
    for round in 0..300 {
        let (a, b) = touching_case(round % 7, &mut rng);
        for (p, q) in [(b[0], b[1]), (b[0], b[0]), (b[1], b[2])] {
            let (p, q) = if round % 2 == 0 { (p, q) } else { (p.next_up_all(), q) };
            assert_eq!(
                segment_meets_triangle(p, q, &a),
                meet(&a, &[p, q, q]),
                "{p:?} {q:?} {a:?}"
            );
        }
    }
}

trait NextUp {
    fn next_up_all(self) -> Self;
}

impl NextUp for DVec3 {
    fn next_up_all(self) -> Self {
        DVec3::new(self.x.next_up(), self.y.next_up(), self.z.next_up())
    }
}

// ---------------------------------------------------------------------------
// Neighbours: faces of one mesh sharing a vertex or an edge.

fn check_neighbours(a: &Tri, ia: [u32; 3], b: &Tri, ib: [u32; 3]) -> bool {
    let expected = neighbours_meet(a, ia, b, ib);
    assert_eq!(
        neighbours_intersect(a, ia, b, ib),
        expected,
        "{a:?} {ia:?} {b:?} {ib:?}"
    );
    assert_eq!(
        neighbours_intersect(b, ib, a, ia),
        expected,
        "swapped {a:?} {ia:?} {b:?} {ib:?}"
    );
    let ra = [a[1], a[2], a[0]];
    let ria = [ia[1], ia[2], ia[0]];
    assert_eq!(
        neighbours_intersect(&ra, ria, b, ib),
        expected,
        "rotated {a:?} {ia:?} {b:?} {ib:?}"
    );
    expected
}

#[test]
fn fans_around_a_vertex_match_the_oracle() {
    let mut rng = Rng::new(3);
    let mut reported = 0;
    for round in 0..400 {
        let apex = lattice(&mut rng, 8);
        let (u, v) = (lattice(&mut rng, 8), lattice(&mut rng, 8));
        let in_plane =
            |rng: &mut Rng| apex + u * (rng.below(9) as f64 - 4.0) / 4.0 + v * (rng.below(9) as f64 - 4.0) / 4.0;
        let a = [apex, apex + u, apex + v];
        let b: Tri = match round % 4 {
            // Anywhere: crossing or not.
            0 => [apex, lattice(&mut rng, 8), lattice(&mut rng, 8)],
            // Coplanar fans: folded onto a, beside it, or opposite.
            1 => [apex, in_plane(&mut rng), in_plane(&mut rng)],
            // One edge along a's edge direction (folded partly onto it).
            2 => [apex, apex + u * 0.5, lattice(&mut rng, 8)],
            // Coplanar, then nudged off the plane.
            _ => nudge(&[apex, in_plane(&mut rng), in_plane(&mut rng)], &mut rng),
        };
        let b = if round % 4 == 3 && b[0] != apex {
            [apex, b[1], b[2]]
        } else {
            b
        };
        let scale = power_scale(&mut rng);
        let (a, b) = (scaled(&a, scale, DVec3::ZERO), scaled(&b, scale, DVec3::ZERO));
        reported += check_neighbours(&a, [0, 1, 2], &b, [0, 3, 4]) as usize;
        // The shared vertex in another slot of b.
        check_neighbours(&a, [0, 1, 2], &[b[1], b[0], b[2]], [3, 0, 4]);
    }
    assert!((40..=360).contains(&reported), "{reported} of 400 fans reported");
}

#[test]
fn edge_neighbours_are_reported_only_when_folded_flat_onto_each_other() {
    let mut rng = Rng::new(4);
    for round in 0..300 {
        let (p, q, c) = (lattice(&mut rng, 8), lattice(&mut rng, 8), lattice(&mut rng, 8));
        let a = [p, q, c];
        let (i, j) = (rng.below(9) as f64 - 4.0, rng.below(9) as f64 - 4.0);
        let flat = p + (q - p) * (i / 4.0) + (c - p) * (j / 4.0);
        let d = match round % 3 {
            0 => flat,                           // coplanar: same side or opposite
            1 => lattice(&mut rng, 8),           // any dihedral angle
            _ => nudge(&[flat; 3], &mut rng)[0], // a few ulps off flat
        };
        let b = [q, p, d];
        let got = check_neighbours(&a, [0, 1, 2], &b, [1, 0, 3]);
        if round % 3 == 0 && j > 0.0 && !degenerate(&a) {
            assert!(got, "folded onto the same side: {a:?} {b:?}");
        }
        if round % 3 == 0 && j < 0.0 && !degenerate(&a) {
            assert!(!got, "opposite sides: {a:?} {b:?}");
        }
    }
}

#[test]
fn neighbour_rules_by_hand() {
    let (o, x, y, z) = (DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z);
    let a = [o, x, y];
    // A hinge at any dihedral angle: not reported; folded flat onto a: reported;
    // flat on the other side: not.
    assert!(!neighbours_intersect(&a, [0, 1, 2], &[o, x, z], [0, 1, 3]));
    assert!(neighbours_intersect(
        &a,
        [0, 1, 2],
        &[o, x, y * 0.5 + x * 0.5],
        [0, 1, 3]
    ));
    assert!(!neighbours_intersect(&a, [0, 1, 2], &[o, x, -y], [0, 1, 3]));
    assert!(!neighbours_intersect(
        &a,
        [0, 1, 2],
        &[o, x, DVec3::new(0.5, 0.5, 1e-300)],
        [0, 1, 3]
    ));
    // Fans: beside each other (only the vertex), folded onto each other, crossing.
    assert!(!neighbours_intersect(&a, [0, 1, 2], &[o, -x, -y], [0, 3, 4]));
    assert!(neighbours_intersect(
        &a,
        [0, 1, 2],
        &[o, x + y * 0.1, x * 0.1 + y],
        [0, 3, 4]
    ));
    assert!(neighbours_intersect(
        &a,
        [0, 1, 2],
        &[o, DVec3::new(0.2, 0.2, -1.0), DVec3::new(0.2, 0.2, 1.0)],
        [0, 3, 4]
    ));
    assert!(!neighbours_intersect(&a, [0, 1, 2], &[o, z, z - x], [0, 3, 4]));
    // Duplicate faces, in any order; a face degenerate by its indices.
    assert!(neighbours_intersect(&a, [0, 1, 2], &a, [0, 1, 2]));
    assert!(neighbours_intersect(&a, [0, 1, 2], &[y, x, o], [2, 1, 0]));
    assert!(!neighbours_intersect(&[o, o, x], [0, 0, 1], &a, [0, 1, 2]));
    // Far apart faces with no shared index: the plain test; touching counts.
    assert!(neighbours_intersect(&a, [0, 1, 2], &[x, x + z, x - z], [5, 6, 7]));
    // The same position under two indices is not shared: touching there counts.
    assert!(neighbours_intersect(&a, [0, 1, 2], &[o, -x, -y], [9, 3, 4]));
    // A face that is a segment through the shared vertex A (A between B and C)
    // against a fan face: reported only where it enters beyond A.
    let seg = [o, -x, x];
    assert!(check_neighbours(&seg, [0, 5, 6], &a, [0, 1, 2]));
    assert!(!check_neighbours(&seg, [0, 5, 6], &[o, y, z], [0, 1, 2]));
    assert!(!check_neighbours(&[o, -z, z], [0, 5, 6], &a, [0, 1, 2]));
    // Edge neighbours that are segments on the shared edge's line.
    assert!(check_neighbours(
        &[o, x, x * 2.0],
        [0, 1, 2],
        &[x, o, x * 3.0],
        [1, 0, 3]
    ));
    assert!(!check_neighbours(&[o, x, x * 2.0], [0, 1, 2], &[x, o, -x], [1, 0, 3]));
    assert!(!check_neighbours(
        &[o, x, x * 0.5],
        [0, 1, 2],
        &[x, o, x * 3.0],
        [1, 0, 3]
    ));
    assert!(!check_neighbours(&[o, x, x * 2.0], [0, 1, 2], &[x, o, y], [1, 0, 3]));
    // The shared edge of zero length (two indices at one point).
    assert!(check_neighbours(&[o, o, x], [0, 1, 2], &[o, o, x * 2.0], [1, 0, 3]));
    assert!(!check_neighbours(&[o, o, x], [0, 1, 2], &[o, o, y], [1, 0, 3]));
    assert!(!check_neighbours(&[o, o, x], [0, 1, 2], &[o, o, -x], [1, 0, 3]));
    // Segments ending at the shared vertex, along one line: beyond it only
    // when they leave it the same way.
    assert!(!check_neighbours(&[o, -x, o], [0, 5, 6], &[o, o, x], [0, 7, 8]));
    assert!(check_neighbours(&[o, -x, o], [0, 5, 6], &[o, o, -x * 0.5], [0, 7, 8]));
    assert!(!check_neighbours(&[o, -x, o], [0, 5, 6], &[o, x, y], [0, 7, 8]));
}

#[test]
fn degenerate_neighbours_match_the_oracle() {
    let mut rng = Rng::new(9);
    for round in 0..300 {
        let apex = lattice(&mut rng, 4);
        let d = lattice(&mut rng, 4);
        let mut point = || lattice(&mut rng, 4);
        let (b1, c1, e1) = (point(), point(), point());
        // a: proper, a segment through A, a segment ending at A, or the point A.
        let a: Tri = match round % 5 {
            0 => [apex, b1, c1],
            1 => [apex, apex + d, apex - d * 0.5],
            2 => [apex, apex + d, apex + d * 2.0],
            3 => [apex, apex - d, apex],
            _ => [apex, apex, apex],
        };
        let b: Tri = match (round / 5) % 4 {
            0 => [apex, e1, apex + d * 0.25],
            1 => [apex, apex - d, e1],
            2 => [apex, apex, apex + d * (rng.below(5) as f64 - 2.0)],
            _ => [apex, apex + d * 0.5, apex - d],
        };
        check_neighbours(&a, [0, 1, 2], &b, [0, 3, 4]);
        // As edge neighbours (indices 0 and 1 shared).
        let b_edge = [a[1], a[0], b[2]];
        check_neighbours(&a, [0, 1, 2], &b_edge, [1, 0, 3]);
    }
}

// ---------------------------------------------------------------------------
// Distance.

fn check_distance(a: &Tri, b: &Tri) {
    let got = triangle_distance(a, b);
    let exact = to_f64(&distance_squared(a, b)).sqrt();
    let size = a.iter().chain(b).map(|p| p.abs().max_element()).fold(0.0, f64::max);
    let tolerance = 1e-12 * size.max(1e-300) + 1e-12 * exact;
    assert!(
        (got.distance - exact).abs() <= tolerance,
        "{} vs exact {exact} ({a:?} {b:?})",
        got.distance
    );
    if exact == 0.0 {
        assert_eq!(got.distance, 0.0);
        assert_eq!(got.point_a, got.point_b);
    }
    let diff = (got.point_a - got.point_b).length();
    assert!(
        (diff - got.distance).abs() <= 1e-12 * got.distance.max(f64::MIN_POSITIVE),
        "{diff} {}",
        got.distance
    );
    for (point, bary, t) in [(got.point_a, got.barycentric_a, a), (got.point_b, got.barycentric_b, b)] {
        assert!(bary.iter().all(|&w| w >= -1e-12), "{bary:?}");
        assert!((bary.iter().sum::<f64>() - 1.0).abs() <= 1e-12, "{bary:?}");
        let rebuilt = t[0] * bary[0] + t[1] * bary[1] + t[2] * bary[2];
        assert!(
            (rebuilt - point).length() <= 1e-11 * size.max(1e-300),
            "{rebuilt:?} {point:?} {a:?} {b:?} {got:?}"
        );
    }
}

#[test]
fn random_distances_match_the_exact_sub_distances() {
    let mut rng = Rng::new(21);
    for _ in 0..300 {
        let (a, b) = random_pair(&mut rng);
        check_distance(&a, &b);
        // Apart: b moved away along a random direction, at a far offset too.
        let shift = DVec3::new(rng.gaussian(), rng.gaussian(), rng.gaussian()) * (a[0] - a[1]).length() * 2.0;
        check_distance(&a, &b.map(|p| p + shift));
    }
}

#[test]
fn touching_and_degenerate_distances_match_the_exact_sub_distances() {
    let mut rng = Rng::new(22);
    for round in 0..200 {
        let (a, b) = touching_case(round % 7, &mut rng);
        check_distance(&a, &b);
        check_distance(&a, &nudge(&b, &mut rng));
        let p = b[0];
        let d = lattice(&mut rng, 4) * power_scale(&mut rng);
        check_distance(&a, &[p, p + d, p + d * 2.0]);
        check_distance(&a, &[p, p, p]);
        check_distance(&[p, p, p], &[p + d, p + d, p + d]);
        check_distance(&[a[0], a[0], a[1]], &[p, p + d, p]);
    }
}

#[test]
fn distance_ties_and_witnesses_by_hand() {
    let (o, x, y, z) = (DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z);
    let a = [o, x, y];
    // Parallel copies: every vertex ties; the first minimum is vertex a_0.
    let d = triangle_distance(&a, &a.map(|p| p + z * 3.0));
    assert_eq!((d.distance, d.point_a, d.point_b), (3.0, o, z * 3.0));
    assert_eq!((d.barycentric_a, d.barycentric_b), ([1.0, 0.0, 0.0], [1.0, 0.0, 0.0]));
    // Crossed edges above each other: the edge-edge pair.
    let d = triangle_distance(
        &[o, x * 2.0, DVec3::new(1.0, -1.0, 0.0)],
        &[
            DVec3::new(1.0, -1.0, 1.0),
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(3.0, 0.0, 1.0),
        ],
    );
    assert_eq!(d.distance, 1.0);
    // Piercing triangles: 0 at a common point.
    let d = triangle_distance(
        &a,
        &[
            DVec3::new(0.25, 0.25, -1.0),
            DVec3::new(0.25, 0.25, 1.0),
            DVec3::new(5.0, 5.0, 0.5),
        ],
    );
    assert_eq!(d.distance, 0.0);
    let common = d.point_a;
    assert!(
        common.z.abs() < 1e-15 && (common.x - common.y).abs() < 1e-15,
        "{common:?} is in both planes"
    );
    // Degenerate everything: finite answers.
    let d = triangle_distance(&[z; 3], &[x, x, x * 2.0]);
    assert_eq!(d.distance, 2f64.sqrt());
    assert!(d.barycentric_a.iter().chain(&d.barycentric_b).all(|w| w.is_finite()));
}
