//! Signed distance, winding numbers and inside tests against independent
//! oracles: the winding number as a sum of spherical excesses (Girard's
//! theorem, in `f64`, written here and not shared with the library's
//! Van Oosterom–Strackee formula), the closest query's distance, and
//! generated meshes whose winding numbers are known (closed spheres, overlaps,
//! flips, duplicates, holes, open fans).

use crate::common::winding::{corners, mesh_of, oracle};
use crate::common::{bumpy_sphere, data_dir, random_soup, shared_meshes};
use proptest::prelude::*;
use proxima::prelude::*;
use proxima::sample::Rng;
use proxima::sdf::{SdfGrid, winding_number_exact};
use proxima::{SdfError, Sign};
use rayon::prelude::*;

/// The side is right wherever the exact winding number is farther than this
/// from ½ (the promise; the library re-evaluates near ½).
const TOLERANCE: f64 = 0.01;

/// The accuracy of the values at the default β (docs/sdf.md): 0.03 is the
/// largest error measured on the shared meshes.
const VALUE_TOLERANCE: f64 = 0.04;

fn field(mesh: &Mesh, sign: Sign) -> SignedDistanceField {
    SignedDistanceField::new(
        mesh,
        &SdfConfig {
            sign,
            ..Default::default()
        },
    )
    .unwrap()
}

/// Near-surface and uniform points of `mesh`.
fn points(mesh: &Mesh, n: usize, seed: u64) -> Vec<Vec3> {
    let mut out = proxima::sample::near_surface(mesh, n, 0.01, seed);
    out.extend(proxima::sample::uniform_in_box(mesh, n, seed + 1));
    out
}

/// The fast winding number is within [`VALUE_TOLERANCE`] of the oracle at every
/// point, the exact mode within 1e-9, and the side (field and batch) is the
/// oracle's wherever |w − ½| > 0.01. Returns the largest error.
fn check_winding(mesh: &Mesh, points: &[Vec3], what: &str) -> f64 {
    let triangles = mesh.triangles().primitives;
    let field = field(mesh, Sign::WindingNumber);
    let expected: Vec<f64> = points.par_iter().map(|&p| oracle(&triangles, p)).collect();
    let fast = field.winding_number_batch(points);
    let inside = field.contains_batch(points);
    let signed = field.signed_distance_batch(points);
    let mut worst = 0f64;
    for (i, &p) in points.iter().enumerate() {
        let (w, e) = (fast[i] as f64, expected[i]);
        assert!(w.is_finite(), "{what}: w({p}) = {w}");
        assert_eq!(
            fast[i].to_bits(),
            field.winding_number(p).to_bits(),
            "{what}: batch = single at {p}"
        );
        worst = worst.max((w - e).abs());
        assert!((w - e).abs() < VALUE_TOLERANCE, "{what}: w({p}) = {w}, oracle {e}");
        let exact = winding_number_exact(&triangles, p);
        // Girard's excess loses digits on slivers: 1e-6 is far below the tolerance.
        assert!((exact - e).abs() < 1e-6, "{what}: exact w({p}) = {exact}, oracle {e}");
        let s = signed[i].expect("finite query");
        assert_eq!(s.closest, field.tree().closest(p).unwrap(), "{what}: closest at {p}");
        assert_eq!(s.distance.abs(), s.closest.distance);
        assert_eq!(Some(s), field.signed_distance(p));
        // The certificate's value where it decided (an integer plus the
        // caps' winding number), else the tree's.
        let v = s.winding_number.expect("winding sign") as f64;
        assert!(
            (v - e).abs() < VALUE_TOLERANCE,
            "{what}: signed w({p}) = {v}, oracle {e}"
        );
        if (e - 0.5).abs() > TOLERANCE {
            assert_eq!(inside[i], e > 0.5, "{what}: contains({p}) with oracle {e}");
            assert_eq!(
                s.is_inside() || s.distance == 0.0 && e > 0.5,
                e > 0.5,
                "{what}: sign at {p}, w = {e}"
            );
        }
    }
    worst
}

#[test]
fn winding_numbers_equal_the_oracle_on_every_shared_mesh() {
    for path in shared_meshes() {
        let mesh = proxima::io::load(&path).unwrap();
        let n = if mesh.triangle_count() > 300_000 { 40 } else { 150 };
        let worst = check_winding(&mesh, &points(&mesh, n, 7), &path.display().to_string());
        println!(
            "{}: largest |w - oracle| {worst:.2e} on {} points",
            path.display(),
            2 * n
        );
    }
}

#[test]
fn closed_sphere_is_one_inside_and_zero_outside() {
    let mesh = bumpy_sphere(12, 3);
    let field = field(&mesh, Sign::WindingNumber);
    for p in [Vec3::ZERO, Vec3::new(0.3, -0.2, 0.1), Vec3::new(0.0, 0.0, 0.6)] {
        assert!((field.winding_number(p) - 1.0).abs() < VALUE_TOLERANCE as f32, "{p}");
        assert!(field.contains(p) && field.signed_distance(p).unwrap().distance < 0.0);
    }
    for p in [Vec3::splat(2.0), Vec3::new(0.0, 0.0, 1.6), Vec3::new(-40.0, 3.0, 1.0)] {
        assert!(field.winding_number(p).abs() < VALUE_TOLERANCE as f32, "{p}");
        assert!(!field.contains(p) && field.signed_distance(p).unwrap().distance > 0.0);
    }
    check_winding(&mesh, &points(&mesh, 200, 1), "closed sphere");
}

/// Two overlapping closed spheres: w = 2 in the overlap (inside). Where a
/// point inside one sphere lies nearest to the other's surface from
/// outside it, the pseudonormal says outside: the winding number is right.
#[test]
fn overlapping_spheres_are_inside_where_the_pseudonormal_is_wrong() {
    let a = bumpy_sphere(10, 1);
    let shifted: Vec<[Vec3; 3]> = corners(&a)
        .into_iter()
        .map(|t| t.map(|v| v + Vec3::new(0.5, 0.0, 0.0)))
        .collect();
    let mut all = corners(&a);
    all.extend(shifted);
    let mesh = mesh_of(&all);
    let winding = field(&mesh, Sign::WindingNumber);
    let pseudo = field(&mesh, Sign::Pseudonormal);
    let overlap = Vec3::new(0.25, 0.0, 0.0);
    assert!((winding.winding_number(overlap) - 2.0).abs() < VALUE_TOLERANCE as f32);
    assert!(winding.signed_distance(overlap).unwrap().is_inside());
    // Inside the first sphere, just outside the second: nearest to the second's surface.
    let p = Vec3::new(-0.6, 0.0, 0.0);
    let (w, pn) = (winding.signed_distance(p).unwrap(), pseudo.signed_distance(p).unwrap());
    assert!((w.winding_number.unwrap() - 1.0).abs() < VALUE_TOLERANCE as f32);
    assert!(
        w.is_inside() && !pn.is_inside(),
        "the pseudonormal's documented failure"
    );
    assert_eq!(w.distance, -pn.distance);
    check_winding(&mesh, &points(&mesh, 150, 2), "two spheres");
}

#[test]
fn flipped_orientation_is_minus_one_and_outside() {
    let flipped: Vec<[Vec3; 3]> = corners(&bumpy_sphere(8, 2))
        .into_iter()
        .map(|[a, b, c]| [a, c, b])
        .collect();
    let mesh = mesh_of(&flipped);
    let field = field(&mesh, Sign::WindingNumber);
    assert!((field.winding_number(Vec3::ZERO) + 1.0).abs() < VALUE_TOLERANCE as f32);
    assert!(!field.contains(Vec3::ZERO), "w = -1 is outside by the rule w > 1/2");
    assert!(field.signed_distance(Vec3::ZERO).unwrap().distance > 0.0);
    check_winding(&mesh, &points(&mesh, 100, 3), "flipped sphere");
}

#[test]
fn duplicated_faces_count_twice() {
    let mut twice = corners(&bumpy_sphere(8, 4));
    twice.extend(twice.clone());
    let mesh = mesh_of(&twice);
    let field = field(&mesh, Sign::WindingNumber);
    assert!((field.winding_number(Vec3::ZERO) - 2.0).abs() < VALUE_TOLERANCE as f32);
    assert!(field.contains(Vec3::ZERO));
    check_winding(&mesh, &points(&mesh, 100, 4), "duplicated faces");
}

#[test]
fn meshes_with_holes_and_open_fans_follow_the_oracle() {
    let mut rng = Rng::new(9);
    let holed: Vec<[Vec3; 3]> = corners(&bumpy_sphere(10, 5))
        .into_iter()
        .filter(|_| rng.below(10) != 0)
        .collect();
    let mesh = mesh_of(&holed);
    check_winding(
        &mesh,
        &points(&mesh, 200, 5),
        "sphere with a tenth of its faces removed",
    );

    // A curved fan of 12 triangles around one vertex: a cap, open all round.
    let rim = |k: u32| {
        let a = k as f32 * std::f32::consts::TAU / 12.0;
        Vec3::new(a.cos(), a.sin(), 0.3)
    };
    let fan: Vec<[Vec3; 3]> = (0..12).map(|k| [Vec3::ZERO, rim(k), rim(k + 1)]).collect();
    let mesh = mesh_of(&fan);
    let mut probes = points(&mesh, 200, 6);
    probes.extend([
        Vec3::new(0.0, 0.0, 0.15),
        Vec3::new(0.0, 0.0, -0.5),
        Vec3::new(0.2, 0.1, 0.29),
    ]);
    check_winding(&mesh, &probes, "open fan");
}

#[test]
fn degenerate_triangles_and_soups_follow_the_oracle() {
    let soup = random_soup(300, 11);
    check_winding(&soup, &points(&soup, 200, 7), "soup with degenerate triangles");
}

/// On vertices, edges and faces the winding number is defined (finite,
/// between the two sides' values on a closed mesh) and never NaN.
#[test]
fn queries_on_the_surface_are_defined() {
    let mesh = bumpy_sphere(8, 6);
    let field = field(&mesh, Sign::WindingNumber);
    let pseudo = field_pseudo(&mesh);
    // On a vertex its own triangles see it in their planes (0): the rest of
    // the closed surface gives a value between the two sides'.
    for &p in mesh.positions() {
        let w = field.winding_number(p);
        assert!((-0.01..=1.01).contains(&w), "w({p}) = {w}");
    }
    // Edge midpoints and centroids rounded to f32 lie a rounding off the
    // surface, on either side: finite, near one side's value or the other's.
    let mut on_surface: Vec<Vec3> = mesh.positions().to_vec();
    for t in mesh.triangles().primitives {
        on_surface.push((t.a + t.b) * 0.5);
        on_surface.push((t.a + t.b + t.c) / 3.0);
    }
    for p in on_surface {
        let w = field.winding_number(p);
        assert!(w.is_finite() && (-0.6..=1.6).contains(&w), "w({p}) = {w}");
        let s = field.signed_distance(p).unwrap();
        assert!(s.distance.is_finite() && s.distance.abs() < 1e-5, "{p}: {s:?}");
        assert!(pseudo.signed_distance(p).unwrap().distance.is_finite());
    }
}

fn field_pseudo(mesh: &Mesh) -> SignedDistanceField {
    field(mesh, Sign::Pseudonormal)
}

/// On closed manifold meshes that do not cross themselves, the pseudonormal
/// side equals the winding number's, also where the closest feature is an
/// edge or a vertex of a sharp crease (points offset from vertices and edge
/// midpoints in random directions).
#[test]
fn pseudonormal_sign_equals_the_winding_sign_on_closed_meshes() {
    let Some(dir) = data_dir() else { return };
    let closed = [
        "fandisk.obj",
        "rocker-arm.obj",
        "bunny-npm.obj",
        "spot_quadrangulated.obj",
        "nefertiti.obj",
    ];
    for name in closed {
        let mesh = proxima::io::load(dir.join(name)).unwrap();
        let pseudo = field_pseudo(&mesh);
        let winding = field(&mesh, Sign::WindingNumber);
        let mut rng = Rng::new(21);
        let scale = mesh.bounds().diagonal() * 2e-3;
        let mut probes = points(&mesh, 300, 8);
        let positions = mesh.positions();
        let edges = mesh.edge_indices();
        for _ in 0..600 {
            let offset = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * scale;
            probes.push(positions[rng.below(positions.len())] + offset);
            let [a, b] = edges[rng.below(edges.len())];
            probes.push((positions[a as usize] + positions[b as usize]) * 0.5 + offset);
        }
        let triangles = mesh.triangles().primitives;
        let normals = proxima::sdf::Pseudonormals::new(&mesh);
        let (mut edge_or_vertex, mut checked) = (0, 0);
        for p in probes {
            let s = pseudo.signed_distance(p).unwrap();
            let w = winding.winding_number(p) as f64;
            if (w - 0.5).abs() <= TOLERANCE || s.distance == 0.0 {
                continue;
            }
            if normals.feature(s.closest.primitive, p) != proxima::sdf::Feature::Face {
                edge_or_vertex += 1;
            }
            checked += 1;
            if s.is_inside() != (w > 0.5) {
                let exact = oracle(&triangles, p);
                panic!(
                    "{name}: pseudonormal side at {p} is {}, winding number {w} (oracle {exact})",
                    s.is_inside()
                );
            }
        }
        println!("{name}: {checked} points agree, {edge_or_vertex} of them nearest an edge or a vertex");
        assert!(edge_or_vertex > 100, "{name}: the probes reach edges and vertices");
    }
}

#[test]
fn grid_values_are_the_signed_distances_at_cell_centres() {
    let mesh = bumpy_sphere(6, 7);
    let field = field(&mesh, Sign::WindingNumber);
    let grid = SdfGrid::around(&field.bounds(), 9, 0.05).unwrap();
    let mut reports = Vec::new();
    let values = field
        .sdf_grid(&grid, |done, total| reports.push((done, total)))
        .unwrap();
    assert_eq!(values.len(), 729);
    for k in 0..9 {
        for j in 0..9 {
            for i in 0..9 {
                let expected = field.signed_distance(grid.point(i, j, k)).unwrap().distance;
                assert_eq!(
                    values[i + 9 * (j + 9 * k)].to_bits(),
                    expected.to_bits(),
                    "cell {i},{j},{k}"
                );
            }
        }
    }
    assert!(reports.windows(2).all(|w| w[0].0 < w[1].0));
    assert_eq!(reports.last(), Some(&(729, 729)));
    let b = field.bounds();
    assert_eq!(grid.min, b.min - b.size() * 0.05);
    assert!((grid.origin() - (grid.min + grid.cell * 0.5)).length() < 1e-6);
}

#[test]
fn grids_and_samples_refuse_what_they_cannot_hold() {
    let field = field(&bumpy_sphere(4, 8), Sign::WindingNumber);
    assert_eq!(
        SdfGrid::around(&field.bounds(), 0, 0.05),
        Err(SdfError::Zero { option: "resolution" })
    );
    let huge = SdfGrid::around(&field.bounds(), 100_000, 0.05).unwrap();
    let start = std::time::Instant::now();
    assert!(matches!(
        field.sdf_grid(&huge, |_, _| {}),
        Err(SdfError::MemoryBudget {
            option: "resolution",
            ..
        })
    ));
    assert!(start.elapsed().as_secs() < 1, "refused before any work");
    assert!(matches!(
        field.sample_near_surface(0, 0.01, 1),
        Err(SdfError::Zero { .. })
    ));
    assert!(matches!(
        field.sample_uniform(usize::MAX, 0.05, 1),
        Err(SdfError::MemoryBudget { .. })
    ));
    assert!(matches!(
        field.sample_near_surface(10, -1.0, 1),
        Err(SdfError::Parameter { option: "sigma", .. })
    ));
    assert!(matches!(
        field.sample_uniform(10, f32::NAN, 1),
        Err(SdfError::Parameter { option: "margin", .. })
    ));
    assert_eq!(
        SignedDistanceField::new(&Mesh::default(), &SdfConfig::default()).err(),
        Some(SdfError::NoFaces)
    );
}

#[test]
fn samples_are_reproducible_and_carry_their_signed_distances() {
    let mesh = bumpy_sphere(8, 9);
    let field = field(&mesh, Sign::WindingNumber);
    let near = field.sample_near_surface(500, 0.02, 3).unwrap();
    assert_eq!(near, field.sample_near_surface(500, 0.02, 3).unwrap());
    assert_ne!(near, field.sample_near_surface(500, 0.02, 4).unwrap());
    let uniform = field.sample_uniform(500, 0.05, 3).unwrap();
    for s in [&near, &uniform] {
        assert_eq!(s.points.len(), 500);
        for (p, d) in s.points.iter().zip(&s.signed_distances) {
            assert_eq!(d.to_bits(), field.signed_distance(*p).unwrap().distance.to_bits());
        }
    }
    let grown = field.bounds();
    let grow = grown.size() * 0.05;
    assert!(
        uniform
            .points
            .iter()
            .all(|p| p.cmpge(grown.min - grow).all() && p.cmple(grown.max + grow).all())
    );
    // Near-surface samples: mostly within a few sigma of the surface.
    let close = near.signed_distances.iter().filter(|d| d.abs() < 0.1).count();
    assert!(close > 450, "{close} of 500 within 5 sigma");
    // About as many inside as outside.
    let inside = near.signed_distances.iter().filter(|d| **d < 0.0).count();
    assert!((150..350).contains(&inside), "{inside}");
}

#[test]
fn exact_mode_sums_every_triangle() {
    let mesh = bumpy_sphere(6, 10);
    let exact = SignedDistanceField::new(
        &mesh,
        &SdfConfig {
            exact: true,
            ..Default::default()
        },
    )
    .unwrap();
    let triangles = mesh.triangles().primitives;
    for p in points(&mesh, 50, 11) {
        // The same sum in another order (the tree's leaf order).
        assert!((exact.winding_number(p) as f64 - winding_number_exact(&triangles, p)).abs() < 1e-6);
        assert!((exact.winding_number(p) as f64 - oracle(&triangles, p)).abs() < 1e-6);
    }
}

#[test]
fn non_finite_points_have_no_signed_distance() {
    let field = field(&bumpy_sphere(4, 12), Sign::WindingNumber);
    for bad in [
        Vec3::NAN,
        Vec3::new(f32::INFINITY, 0.0, 0.0),
        Vec3::new(0.0, f32::NEG_INFINITY, 1.0),
    ] {
        assert_eq!(field.signed_distance(bad), None);
        assert_eq!(field.winding_number(bad), 0.0);
        assert!(!field.contains(bad));
        assert_eq!(field.signed_distance_batch(&[Vec3::ZERO, bad])[1], None);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Random soups of up to 60 triangles (some tiny, some degenerate):
    /// the fast winding number within the tolerance of the oracle, batches
    /// equal to single queries.
    #[test]
    fn random_soups_follow_the_oracle(seed in 0u64..1_000_000, n in 1usize..60) {
        let soup = random_soup(n, seed);
        let mut probes = points(&soup, 20, seed);
        probes.push(soup.positions()[0]);
        check_winding(&soup, &probes, "proptest soup");
    }

    /// Exactly on a lattice: vertices on integer coordinates and queries on
    /// cell planes give finite answers equal to the oracle off the surface.
    #[test]
    fn lattice_meshes_follow_the_oracle(seed in 0u64..1_000_000) {
        let mut rng = Rng::new(seed);
        let mut v = || Vec3::new(rng.below(5) as f32, rng.below(5) as f32, rng.below(5) as f32);
        let triangles: Vec<[Vec3; 3]> = (0..20).map(|_| [v(), v(), v()]).collect();
        let mesh = mesh_of(&triangles);
        let mut rng = Rng::new(seed + 1);
        let probes: Vec<Vec3> = (0..30)
            .map(|_| Vec3::new(rng.below(9) as f32 * 0.5, rng.below(9) as f32 * 0.5, rng.below(9) as f32 * 0.5 + 0.25))
            .collect();
        check_winding(&mesh, &probes, "lattice");
    }
}

#[test]
fn meshes_of_every_scale_give_the_same_winding_numbers() {
    let base = bumpy_sphere(6, 13);
    for scale in [1e-6f32, 1e-3, 1.0, 1e4] {
        let scaled: Vec<[Vec3; 3]> = corners(&base).into_iter().map(|t| t.map(|v| v * scale)).collect();
        let mesh = mesh_of(&scaled);
        let field = field(&mesh, Sign::WindingNumber);
        assert!(
            (field.winding_number(Vec3::ZERO) - 1.0).abs() < VALUE_TOLERANCE as f32,
            "scale {scale}"
        );
        assert!(
            field.winding_number(Vec3::splat(2.0 * scale)).abs() < VALUE_TOLERANCE as f32,
            "scale {scale}"
        );
    }
}

/// Near ½ the winding number is evaluated again at the refined accuracy:
/// at the opening of a half sphere (w ≈ ½ across the disc) the answers
/// are refined and within 2e-3 of the oracle.
#[test]
fn winding_numbers_near_one_half_are_refined() {
    let half: Vec<[Vec3; 3]> = corners(&bumpy_sphere(12, 14))
        .into_iter()
        .filter(|t| t.iter().all(|v| v.z >= 0.0))
        .collect();
    let mesh = mesh_of(&half);
    let winding = proxima::sdf::WindingNumbers::new(
        &WideTree::build_set(mesh.triangles(), &Default::default()).unwrap(),
        proxima::sdf::DEFAULT_BETA,
    );
    let triangles = mesh.triangles().primitives;
    let mut rng = Rng::new(15);
    let mut stats = proxima::sdf::WindingStats::default();
    for _ in 0..200 {
        let p = Vec3::new(rng.range(-0.6, 0.6), rng.range(-0.6, 0.6), rng.range(-0.05, 0.05));
        let w = winding.winding_number_with_stats(p, &mut stats) as f64;
        let e = oracle(&triangles, p);
        if (e - 0.5).abs() < 0.04 {
            assert!((w - e).abs() < 2e-3, "w({p}) = {w}, oracle {e}");
        }
    }
    assert!(stats.refined > 100, "{stats:?}");
}

/// The walk compiled for AVX2 and the baseline one give the same bits.
#[test]
fn avx2_and_baseline_walks_agree_bit_for_bit() {
    let mesh = bumpy_sphere(16, 16);
    let tree = WideTree::build_set(mesh.triangles(), &Default::default()).unwrap();
    let mut winding = proxima::sdf::WindingNumbers::new(&tree, proxima::sdf::DEFAULT_BETA);
    let probes = points(&mesh, 300, 17);
    let with: Vec<u32> = probes.iter().map(|&p| winding.winding_number(p).to_bits()).collect();
    winding.set_avx2(false);
    let without: Vec<u32> = probes.iter().map(|&p| winding.winding_number(p).to_bits()).collect();
    assert_eq!(with, without);
}

/// Fields made on one shared tree ([`SignedDistanceField::with_tree`], as
/// the Python package keeps them) answer as fields that build their own,
/// for both signs, bit for bit.
#[test]
fn fields_sharing_one_tree_answer_as_their_own() {
    let mesh = proxima::mesh::generate::noisy_icosphere(12, 3);
    let tree = std::sync::Arc::new(WideTree::build_set(mesh.triangles(), &BuildConfig::default()).unwrap());
    let queries = points(&mesh, 2000, 5);
    for sign in [Sign::WindingNumber, Sign::Pseudonormal] {
        let config = SdfConfig {
            sign,
            ..SdfConfig::default()
        };
        let shared = SignedDistanceField::with_tree(tree.clone(), &mesh, &config);
        let own = SignedDistanceField::new(&mesh, &config).unwrap();
        assert_eq!(
            shared.signed_distance_batch(&queries),
            own.signed_distance_batch(&queries),
            "{sign:?}"
        );
        assert_eq!(
            shared.winding_number_batch(&queries),
            own.winding_number_batch(&queries),
            "{sign:?}"
        );
        assert!(std::ptr::eq(shared.tree(), tree.as_ref()));
    }
}
