//! Grid traversal against brute force: every cell whose box the ray segment
//! meets for a positive length (closed boxes along moving axes, half-open
//! along axes the ray does not move along), ordered by entry parameter. The
//! oracle decides positive length and order in exact rationals, cell by cell,
//! reports parameters by the documented formula `(b(n) − o) · (1/d)` in f64,
//! and knows nothing of the walk.

use num_rational::BigRational;
use proxima::grid::{Cell, GridLayout};
use proxima::grid::{GridTraversal, TraversalConfig, TraversalStep};
use proxima::sample::Rng;
use proxima::{GridError, Vec3};
use std::time::Instant;

/// The cells of `layout` the ray spends positive length in, within
/// `[t_min, t_max]`, by entry. Which cells, and their order, are decided in
/// exact rationals (every `f32` is one); the reported parameters follow the
/// documented formula: each cell's exit is its earliest rounded crossing
/// `(b(n) − o) · (1/d)` (capped at `t_max`), its entry the previous exit.
fn brute_walk(layout: &GridLayout, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> Vec<TraversalStep> {
    let (o64, inv) = (o.to_array().map(|x| x as f64), d.to_array().map(|x| 1.0 / x as f64));
    let (s, g) = (layout.cell_size(), layout.origin());
    // The planes g + n · s: exact rationals for the decisions, and `f64`
    // (exact for these grids) in the documented formula of the parameters.
    let plane64 = |a: usize, n: i64| g[a] as f64 + n as f64 * s[a] as f64;
    let crossing = |a: usize, n: i64| (plane64(a, n) - o64[a]) * inv[a];
    let q = |x: f32| BigRational::from_float(x as f64).expect("finite");
    let plane = |a: usize, n: i64| q(g[a]) + BigRational::from_integer(n.into()) * q(s[a]);
    let exact_crossing = |a: usize, n: i64| (plane(a, n) - q(o[a])) / q(d[a]);
    let (p0, p1) = (o + d * t_min, o + d * t_max);
    let lo: [i64; 3] = std::array::from_fn(|a| ((p0[a].min(p1[a]) - g[a]) / s[a]).floor() as i64 - 2);
    let hi: [i64; 3] = std::array::from_fn(|a| ((p0[a].max(p1[a]) - g[a]) / s[a]).floor() as i64 + 2);
    let mut out = Vec::new();
    for k in lo[2]..=hi[2] {
        for j in lo[1]..=hi[1] {
            for i in lo[0]..=hi[0] {
                let cell: Cell = [i, j, k];
                // Rounded first: most cells are clearly outside, and the exact
                // rationals are only needed near a tie.
                let (mut r0, mut r1) = (t_min as f64, t_max as f64);
                let mut inside = true;
                for a in 0..3 {
                    if d[a] == 0.0 {
                        let (b0, b1) = (plane(a, cell[a]), plane(a, cell[a] + 1));
                        inside &= b0 <= q(o[a]) && q(o[a]) < b1;
                    } else {
                        let (c0, c1) = (crossing(a, cell[a]), crossing(a, cell[a] + 1));
                        r0 = r0.max(c0.min(c1));
                        r1 = r1.min(c0.max(c1));
                    }
                }
                if !inside || r1 < r0 - 1e-9 * (1.0 + r0.abs()) {
                    continue;
                }
                let (mut t0, mut t1) = (q(t_min), q(t_max));
                for a in (0..3).filter(|&a| d[a] != 0.0) {
                    let (c0, c1) = (exact_crossing(a, cell[a]), exact_crossing(a, cell[a] + 1));
                    let (near, far) = if c0 <= c1 { (c0, c1) } else { (c1, c0) };
                    t0 = t0.max(near);
                    t1 = t1.min(far);
                }
                if t1 > t0 {
                    out.push((t0, cell, r1));
                }
            }
        }
    }
    out.sort_by(|a, b| a.0.cmp(&b.0));
    let mut enter = t_min;
    out.into_iter()
        .map(|(_, cell, exit)| {
            let step = TraversalStep {
                cell,
                t_enter: enter,
                t_exit: exit as f32,
            };
            enter = step.t_exit;
            step
        })
        .collect()
}

fn walk(layout: &GridLayout, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> Vec<TraversalStep> {
    GridTraversal::in_layout(layout, o, d, t_min, t_max).unwrap().collect()
}

#[test]
fn worked_example() {
    let dir = Vec3::new(0.3, 0.5, 1.0).normalize();
    let steps: Vec<_> = GridTraversal::new(Vec3::new(1.0, 0.2, 0.5), dir, &TraversalConfig::cubic(0.3))
        .unwrap()
        .take(4)
        .collect();
    for s in &steps {
        println!("{:?} enter {:.4} exit {:.4}", s.cell, s.t_enter, s.t_exit);
    }
    let cells: Vec<Cell> = steps.iter().map(|s| s.cell).collect();
    assert_eq!(cells, [[3, 0, 1], [3, 0, 2], [3, 1, 2], [3, 1, 3]]);
    assert_eq!(steps[0].t_enter, 0.0);
    assert!((steps[0].t_exit - 0.1158).abs() < 5e-5, "{}", steps[0].t_exit);
    assert!((steps[1].t_exit - 0.2315).abs() < 5e-5, "{}", steps[1].t_exit);
    // Exact values: z = 0.6 at t = 0.1 / dz, y = 0.3 at t = 0.1 / dy.
    assert!((steps[0].t_exit - (0.6 - 0.5) / dir.z).abs() < 1e-6);
    assert!((steps[1].t_exit - (0.3 - 0.2) / dir.y).abs() < 1e-6);
}

#[test]
fn matches_brute_force_on_random_rays() {
    let mut rng = Rng::new(21);
    let mut total = 0;
    for q in 0..3000 {
        let cell = Vec3::new(rng.range(0.1, 1.0), rng.range(0.1, 1.0), rng.range(0.1, 1.0));
        let cell = if q % 3 == 0 { Vec3::splat(cell.x) } else { cell };
        let origin_grid = if q % 2 == 0 {
            Vec3::ZERO
        } else {
            Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0))
        };
        let layout = GridLayout::new(origin_grid, cell).unwrap();
        let mut o = Vec3::new(rng.range(-5.0, 5.0), rng.range(-5.0, 5.0), rng.range(-5.0, 5.0));
        let mut d = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        // The f32 nearest a plane: on it when the plane is an f32, within
        // half an f32 step otherwise (either side).
        let near = |a: usize, n: i64| layout.boundary(a, n) as f32;
        match q % 8 {
            // Origin on (or next to) boundary planes, edges and corners.
            1 => o = Vec3::new(near(0, 3), near(1, -2), o.z),
            2 => o = Vec3::new(near(0, -1), near(1, 1), near(2, 0)),
            // Zero direction components.
            3 => d.y = 0.0,
            4 => (d.x, d.z) = (0.0, 0.0),
            // Zero components with the origin in (or next to) a boundary plane.
            5 => (d.x, o.x) = (0.0, near(0, 2)),
            // Axis-aligned diagonals through (or next to) cell corners.
            6 => {
                o = Vec3::new(near(0, 1), near(1, 1), near(2, 1));
                d = cell * Vec3::new(1.0, -1.0, 1.0);
            }
            _ => {}
        }
        if d == Vec3::ZERO {
            continue;
        }
        let d = if q % 5 == 0 { d.normalize() } else { d };
        let (t_min, t_max) = if q % 4 == 0 {
            (rng.range(-2.0, 0.0), rng.range(0.0, 12.0))
        } else {
            (0.0, rng.range(0.0, 12.0))
        };
        let got = walk(&layout, o, d, t_min, t_max);
        let want = brute_walk(&layout, o, d, t_min, t_max);
        assert_eq!(
            got, want,
            "ray {q}: o {o:?} d {d:?} t [{t_min}, {t_max}] layout {layout:?}"
        );
        total += got.len();
    }
    println!("{total} cells compared");
}

#[test]
fn ties_at_edges_and_corners() {
    let layout = GridLayout::cubic(1.0).unwrap();
    // Through the corners (1,1,1), (2,2,2): the three axes step together.
    let cells: Vec<Cell> = walk(&layout, Vec3::splat(0.5), Vec3::ONE, 0.0, 2.0)
        .iter()
        .map(|s| s.cell)
        .collect();
    assert_eq!(cells, [[0, 0, 0], [1, 1, 1], [2, 2, 2]]);
    // Through the edge x = 1, y = 1: x and y step together.
    let cells: Vec<Cell> = walk(&layout, Vec3::new(0.5, 0.5, 0.2), Vec3::new(1.0, 1.0, 0.0), 0.0, 1.0)
        .iter()
        .map(|s| s.cell)
        .collect();
    assert_eq!(cells, [[0, 0, 0], [1, 1, 0]]);
    // Origin on a boundary: the walk starts in the cell the ray enters.
    assert_eq!(
        walk(&layout, Vec3::new(1.0, 0.5, 0.5), Vec3::X, 0.0, 0.5)[0].cell,
        [1, 0, 0]
    );
    assert_eq!(
        walk(&layout, Vec3::new(1.0, 0.5, 0.5), -Vec3::X, 0.0, 0.5)[0].cell,
        [0, 0, 0]
    );
    // In a boundary plane, not moving across it: the cell above.
    assert_eq!(
        walk(&layout, Vec3::new(0.5, 1.0, 0.5), Vec3::X, 0.0, 0.4)[0].cell,
        [0, 1, 0]
    );
    // An empty range yields nothing; a range ending on a boundary stops there.
    assert!(walk(&layout, Vec3::splat(0.5), Vec3::X, 1.0, 1.0).is_empty());
    let steps = walk(&layout, Vec3::splat(0.5), Vec3::X, 0.0, 0.5);
    assert_eq!(steps.len(), 1);
    assert_eq!((steps[0].t_enter, steps[0].t_exit), (0.0, 0.5));
}

#[test]
fn negative_coordinates_and_directions() {
    let steps: Vec<_> = GridTraversal::new(Vec3::new(-1.5, 0.5, 0.5), -Vec3::X, &TraversalConfig::cubic(1.0))
        .unwrap()
        .take(3)
        .collect();
    let cells: Vec<Cell> = steps.iter().map(|s| s.cell).collect();
    assert_eq!(cells, [[-2, 0, 0], [-3, 0, 0], [-4, 0, 0]]);
    assert_eq!(
        steps.iter().map(|s| (s.t_enter, s.t_exit)).collect::<Vec<_>>(),
        [(0.0, 0.5), (0.5, 1.5), (1.5, 2.5)]
    );
    let config = TraversalConfig {
        grid_origin: Vec3::splat(-0.25),
        ..TraversalConfig::cubic(0.5)
    };
    let first = GridTraversal::new(Vec3::new(-0.3, -0.2, -1.0), Vec3::new(-0.2, 1.0, 0.3), &config)
        .unwrap()
        .next()
        .unwrap();
    assert_eq!(first.cell, [-1, 0, -2]);
}

#[test]
fn huge_ranges_end() {
    // A step limit ends an infinite ray.
    let config = TraversalConfig {
        max_steps: 1000,
        ..TraversalConfig::cubic(0.01)
    };
    let n = GridTraversal::new(Vec3::ZERO, Vec3::new(1.0, 0.3, -0.2), &config)
        .unwrap()
        .count();
    assert_eq!(n, 1000);
    // t_max ends a long finite ray; parameters keep increasing at large t.
    let config = TraversalConfig {
        t_min: 1e6,
        t_max: 1e6 + 50.0,
        ..TraversalConfig::cubic(1.0)
    };
    let steps: Vec<_> = GridTraversal::new(Vec3::ZERO, Vec3::new(0.6, 0.8, 0.0), &config)
        .unwrap()
        .collect();
    assert!(steps.len() > 60 && steps.len() < 80, "{}", steps.len());
    assert!(
        steps
            .windows(2)
            .all(|w| w[0].t_exit == w[1].t_enter && w[0].t_enter <= w[1].t_enter)
    );
    // Far from the origin, f32 cannot separate all boundaries (zero-width
    // cells): the walk skips them and still ends.
    let config = TraversalConfig {
        t_max: 1e4,
        ..TraversalConfig::cubic(1.0)
    };
    let steps: Vec<_> = GridTraversal::new(Vec3::new(1e8, 0.5, 0.5), Vec3::new(1.0, 0.001, 0.0), &config)
        .unwrap()
        .collect();
    assert!(!steps.is_empty() && steps.len() < 12_000, "{}", steps.len());
    assert!(
        steps
            .windows(2)
            .all(|w| w[1].cell[0] > w[0].cell[0] || w[1].cell[1] > w[0].cell[1])
    );
    // An index beyond the supported range is an error, not a wrap-around.
    let far = TraversalConfig::cubic(1e-20);
    assert_eq!(
        GridTraversal::new(Vec3::splat(1e20), Vec3::X, &far).unwrap_err(),
        GridError::OutOfRange
    );
}

#[test]
fn bad_rays_are_errors() {
    let config = TraversalConfig::cubic(1.0);
    for d in [
        Vec3::ZERO,
        Vec3::new(f32::NAN, 1.0, 0.0),
        Vec3::new(f32::INFINITY, 0.0, 0.0),
    ] {
        assert_eq!(
            GridTraversal::new(Vec3::ZERO, d, &config).unwrap_err(),
            GridError::Ray(proxima::RayError::Direction)
        );
    }
    assert_eq!(
        GridTraversal::new(Vec3::splat(f32::INFINITY), Vec3::X, &config).unwrap_err(),
        GridError::Ray(proxima::RayError::Origin)
    );
    let reversed = TraversalConfig {
        t_min: 2.0,
        t_max: 1.0,
        ..config
    };
    assert!(matches!(
        GridTraversal::new(Vec3::ZERO, Vec3::X, &reversed),
        Err(GridError::Ray(proxima::RayError::Range { .. }))
    ));
    let nan = TraversalConfig {
        t_min: f32::NAN,
        ..config
    };
    assert!(matches!(
        GridTraversal::new(Vec3::ZERO, Vec3::X, &nan),
        Err(GridError::Ray(proxima::RayError::Range { .. }))
    ));
    assert!(matches!(
        GridTraversal::new(Vec3::ZERO, Vec3::X, &TraversalConfig::cubic(0.0)),
        Err(GridError::CellSize { .. })
    ));
}

/// 3D Bresenham between two cells (integer steps along the driving axis).
fn bresenham(from: Cell, to: Cell) -> Vec<Cell> {
    let d: [i64; 3] = std::array::from_fn(|a| (to[a] - from[a]).abs());
    let s: [i64; 3] = std::array::from_fn(|a| (to[a] - from[a]).signum());
    let drive = (0..3).max_by_key(|&a| (d[a], std::cmp::Reverse(a))).unwrap();
    let (o1, o2) = ((drive + 1) % 3, (drive + 2) % 3);
    let mut p = from;
    let (mut e1, mut e2) = (2 * d[o1] - d[drive], 2 * d[o2] - d[drive]);
    let mut out = vec![p];
    for _ in 0..d[drive] {
        if e1 >= 0 {
            p[o1] += s[o1];
            e1 -= 2 * d[drive];
        }
        if e2 >= 0 {
            p[o2] += s[o2];
            e2 -= 2 * d[drive];
        }
        e1 += 2 * d[o1];
        e2 += 2 * d[o2];
        p[drive] += s[drive];
        out.push(p);
    }
    out
}

/// The docs/grid.md example: from the centre of cell (0,0,0) to the centre
/// of cell (5,2,1), cell size 1.
#[test]
fn amanatides_woo_versus_bresenham() {
    let layout = GridLayout::cubic(1.0).unwrap();
    let (a, b) = (Vec3::splat(0.5), Vec3::new(5.5, 2.5, 1.5));
    let steps = walk(&layout, a, b - a, 0.0, 1.0);
    let aw: Vec<Cell> = steps.iter().map(|s| s.cell).collect();
    let br = bresenham([0, 0, 0], [5, 2, 1]);
    println!("Amanatides-Woo ({} cells):", aw.len());
    for s in &steps {
        println!("  {:?}  t {:.2} .. {:.2}", s.cell, s.t_enter, s.t_exit);
    }
    println!("Bresenham ({} cells): {br:?}", br.len());
    assert_eq!(
        aw,
        [
            [0, 0, 0],
            [1, 0, 0],
            [1, 1, 0],
            [2, 1, 0],
            [3, 1, 1],
            [4, 1, 1],
            [4, 2, 1],
            [5, 2, 1]
        ]
    );
    assert_eq!(br, [[0, 0, 0], [1, 0, 0], [2, 1, 0], [3, 1, 1], [4, 2, 1], [5, 2, 1]]);
    // Bresenham: one cell per step of the driving axis, neighbours may differ
    // in several axes (26-connected), and it misses cells the line crosses.
    assert!(br.iter().all(|c| aw.contains(c)));
    let missed: Vec<Cell> = aw.iter().filter(|c| !br.contains(c)).copied().collect();
    assert_eq!(missed, [[1, 1, 0], [4, 1, 1]]);
    // Amanatides-Woo: every cell the segment passes through; consecutive cells
    // share a face, except at the exact corner tie t = 0.5 where x and z are
    // crossed together ((2,1,0) -> (3,1,1) share only an edge).
    let jumps: Vec<usize> = aw
        .windows(2)
        .map(|w| (0..3).filter(|&k| w[0][k] != w[1][k]).count())
        .collect();
    assert_eq!(jumps, [1, 1, 1, 2, 1, 1, 1]);
    assert_eq!(steps[3].t_exit, 0.5);
}

/// Throughput, printed (not asserted: the test profile keeps overflow checks
/// and the machine is shared). 2000 random rays of 10,000 steps in cells of
/// 0.001 near the origin, where f32 resolves every boundary.
#[test]
fn steps_per_second() {
    let config = TraversalConfig {
        max_steps: 10_000,
        ..TraversalConfig::cubic(0.001)
    };
    let mut rng = Rng::new(3);
    let rays: Vec<(Vec3, Vec3)> = (0..2000)
        .map(|_| {
            let o = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
            (
                o,
                Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)).normalize_or(Vec3::X),
            )
        })
        .collect();
    let start = Instant::now();
    let (mut n, mut acc) = (0u64, 0i64);
    for &(o, d) in &rays {
        for s in GridTraversal::new(o, d, &config).unwrap() {
            acc = acc.wrapping_add(s.cell[0] ^ s.cell[1] ^ s.cell[2]);
            n += 1;
        }
    }
    let secs = start.elapsed().as_secs_f64();
    assert_eq!(n, 20_000_000);
    println!("{:.0}M steps/s (checksum {acc})", n as f64 / secs / 1e6);
}

/// Rays from lattice points along lattice directions `(k1, k2, k3)` cells
/// per unit, whose reciprocals round (1/3, 1/5, 1/7): they pass exactly
/// through cell edges and corners where the rounded crossing parameters
/// differ. The walk must step tied axes together, as the exact oracle does.
#[test]
fn lattice_rays_through_edges_and_corners() {
    let layouts = [
        GridLayout::cubic(0.25).unwrap(),
        // An origin of 24 significant bits, planes 2^-9 apart: still f32 values.
        GridLayout::new(Vec3::splat(-0.05), Vec3::splat(1.0 / 512.0)).unwrap(),
        GridLayout::new(Vec3::new(1.0, -3.0, 0.5), Vec3::new(0.5, 0.25, 1.0)).unwrap(),
    ];
    let mut ties = 0;
    let mut rays = 0;
    for layout in &layouts {
        let cell = layout.cell_size();
        for k1 in -3i32..=3 {
            for k2 in -3i32..=5 {
                for k3 in [-7i32, 0, 1, 3] {
                    let d = Vec3::new(k1 as f32 * cell.x, k2 as f32 * cell.y, k3 as f32 * cell.z);
                    if d == Vec3::ZERO {
                        continue;
                    }
                    let on = |a: usize, n: i64| {
                        let b = layout.boundary(a, n);
                        assert_eq!(b as f32 as f64, b, "these layouts' planes are f32 values");
                        b as f32
                    };
                    let o = Vec3::new(on(0, 2), on(1, -1), on(2, 3));
                    let got = walk(layout, o, d, 0.0, 4.0);
                    let want = brute_walk(layout, o, d, 0.0, 4.0);
                    assert_eq!(got, want, "o {o:?} d {d:?} layout {layout:?}");
                    // Cells skipped at edges or corners: fewer cells than crossings.
                    let crossings: usize = (0..3).map(|a| (4 * [k1, k2, k3][a].unsigned_abs()) as usize).sum();
                    ties += (crossings + 1).saturating_sub(got.len());
                    rays += 1;
                }
            }
        }
    }
    println!("{rays} rays, {ties} crossings shared with another axis");
    assert!(
        ties > 1000,
        "the rays should pass through many edges and corners, got {ties}"
    );
}

/// Rays from points a few `f32` steps beside the grid's exact planes (on
/// either side, every combination of −3..+3 steps on the three axes), along
/// lattice directions and a few others, on grids whose planes are not `f32`
/// values (the voxelization grid of ±0.05 at 32 cells, as in the issue that
/// found the rounded planes): the walk crosses exactly the planes the exact
/// oracle does.
#[test]
fn rays_a_few_steps_off_the_planes() {
    let layouts = [
        GridLayout::new(Vec3::splat(-0.05), Vec3::splat(0.1 / 32.0)).unwrap(),
        GridLayout::new(Vec3::new(0.1, -0.3, 0.7), Vec3::new(0.3, 0.7, 0.11)).unwrap(),
    ];
    let step = |x: f32, n: i32| {
        let mut y = x;
        for _ in 0..n.unsigned_abs() {
            y = if n > 0 { y.next_up() } else { y.next_down() };
        }
        y
    };
    let mut compared = 0;
    for layout in &layouts {
        let s = layout.cell_size();
        // These grids' planes are not all f32 values: "on a plane" is a few steps beside one.
        assert!((0..3).any(|a| (1..8).any(|n| layout.boundary(a, n) as f32 as f64 != layout.boundary(a, n))));
        // In cells per unit of t, so that the walks (and the oracle's box of
        // candidate cells) stay a few cells long.
        let directions = [
            s,
            s * Vec3::new(1.0, -2.0, 3.0),
            s * Vec3::new(-3.0, 1.0, 0.0),
            s * Vec3::new(0.3, 0.5, 1.0) * 3.7,
            s * Vec3::new(-1.0, 0.0, 0.0),
        ];
        for combo in 0..343 {
            let moves = [combo % 7, combo / 7 % 7, combo / 49].map(|m| m - 3);
            let o = Vec3::from_array(std::array::from_fn(|a| {
                step(layout.boundary(a, [2, -1, 3][a]) as f32, moves[a])
            }));
            for d in directions {
                let got = walk(layout, o, d, -1.0, 3.0);
                assert_eq!(
                    got,
                    brute_walk(layout, o, d, -1.0, 3.0),
                    "o {o:?} d {d:?} layout {layout:?}"
                );
                compared += got.len();
            }
        }
    }
    println!("{compared} cells compared");
}
