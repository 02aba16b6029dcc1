//! One suite run over every structure through the shared query interface
//! (`NearestQuery`, `FrustumQuery`, and `RayQuery` where the structure has
//! it), as regex-automata runs one suite over all its engines. Every answer
//! must equal brute force (`LinearSearch`, a scan of every primitive) on
//! every field: closest, closest-within, with statistics, k-nearest (fresh
//! and with reused scratch), batches in every configuration, frustums,
//! rays; for every primitive type, build configuration and kind of input
//! (random soups, a bumpy sphere inside and out, a mesh large enough for the
//! parallel build, degenerate and non-finite inputs, bad parameters, the real
//! meshes of ../shared/data, proptest sets).
//!
//! A new structure gets the whole suite by one line: implement [`Structure`]
//! for it and add `suite!(its_name, ItsType)` at the end of this file (with
//! `, rays` when it answers rays). Tests of one structure's own shape
//! (parallel build, median halves, wide lanes, spheres holding their points,
//! node visits) stay in its own file: `bvh.rs`, `wide.rs`, `sphere_tree.rs`.

use crate::wide_shape;

use crate::common::{batch_options, bumpy_sphere, mixed_with, queries, random_soup, shared_meshes};
use proptest::prelude::*;
use proxima::build::SplitMethod;
use proxima::prelude::*;
use proxima::{BuildError, Frustum, RayError};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, OnceLock};

// ---------------------------------------------------------------- the structures

/// One structure over primitives of type `T`, as the suite sees it: the
/// shared query interface, a build, and the structure's own invariants.
trait Structure<T: MeshPrimitive>: NearestQuery<T> + FrustumQuery<T> + Sync + Sized {
    /// Printed on failure.
    const NAME: &'static str;

    /// Builds the structure over `set` with `config`.
    fn build(set: PrimitiveSet<T>, config: &BuildConfig) -> Result<Self, BuildError>;

    /// Asserts the structure's own invariants, knowing what it was built from.
    fn check_invariants(&self, set: &PrimitiveSet<T>, config: &BuildConfig);

    /// Number of nodes (0 for an empty structure, 1 for a single leaf).
    fn node_count(&self) -> usize;

    /// Other forms of this structure that must give the same closest
    /// answers (checked for their own invariants here).
    fn other_forms(&self) -> Vec<(&'static str, Self)> {
        Vec::new()
    }
}

/// One kind of structure over every primitive type: what `suite!` runs on.
trait Family {
    type Of<T: MeshPrimitive>: Structure<T>;
}

impl<T: MeshPrimitive> Structure<T> for AabbTree<T> {
    const NAME: &'static str = "AabbTree";

    fn build(set: PrimitiveSet<T>, config: &BuildConfig) -> Result<Self, BuildError> {
        AabbTree::build_set(set, config)
    }

    fn check_invariants(&self, _: &PrimitiveSet<T>, _: &BuildConfig) {
        self.validate().unwrap();
    }

    fn node_count(&self) -> usize {
        self.stats().nodes
    }
}

impl<T: MeshPrimitive> Structure<T> for WideTree<T> {
    const NAME: &'static str = "WideTree";

    fn build(set: PrimitiveSet<T>, config: &BuildConfig) -> Result<Self, BuildError> {
        WideTree::build_set(set, config)
    }

    fn check_invariants(&self, _: &PrimitiveSet<T>, _: &BuildConfig) {
        wide_shape::check_structure(self, self.uses_avx2());
    }

    fn node_count(&self) -> usize {
        WideTree::node_count(self)
    }

    /// As on a CPU without AVX2; and AVX2's eight-triangle leaves tested four
    /// at a time (the same as the default where this CPU lacks AVX2).
    fn other_forms(&self) -> Vec<(&'static str, Self)> {
        let portable = WideTree::from_tree_portable(self.tree().clone());
        let mut four_at_a_time = self.clone();
        four_at_a_time.set_avx2(false);
        assert!(!portable.uses_avx2() && !four_at_a_time.uses_avx2());
        wide_shape::check_structure(&portable, false);
        wide_shape::check_structure(&four_at_a_time, self.uses_avx2());
        vec![("portable", portable), ("four at a time", four_at_a_time)]
    }
}

impl<T: MeshPrimitive> Structure<T> for SphereTree<T> {
    const NAME: &'static str = "SphereTree";

    fn build(set: PrimitiveSet<T>, config: &BuildConfig) -> Result<Self, BuildError> {
        SphereTree::build_set(set, config)
    }

    fn check_invariants(&self, set: &PrimitiveSet<T>, config: &BuildConfig) {
        self.validate().unwrap();
        let boxes = AabbTree::build_set(set.clone(), config).unwrap();
        assert_eq!(self.stats(), boxes.stats(), "same hierarchy as the AABB tree");
    }

    fn node_count(&self) -> usize {
        self.stats().nodes
    }
}

// ---------------------------------------------------------------- the checks

/// The build configurations every structure is checked with (the union of
/// those each structure's own file used): both splits with leaves of 1, 4
/// and 7 and with depth limits 1 and 3, and a shallow median tree with
/// leaves of 2.
fn configs() -> Vec<BuildConfig> {
    let d = BuildConfig::default();
    let mut out = Vec::new();
    for split in [SplitMethod::Median, SplitMethod::BinnedSah] {
        for min_size in [1, 4, 7] {
            out.push(BuildConfig { min_size, split, ..d });
        }
        for max_depth in [1, 3] {
            out.push(BuildConfig { max_depth, split, ..d });
        }
    }
    out.push(BuildConfig {
        max_depth: 3,
        min_size: 2,
        split: SplitMethod::Median,
    });
    assert!(out.contains(&d) && out.contains(&BuildConfig::fast_queries()));
    out
}

/// Cameras about a box: from outside looking at it (wide and narrow), from
/// its center, with near and far planes cutting through it; those the box's
/// scale makes invalid are left out.
fn cameras(bounds: &Aabb) -> Vec<Frustum> {
    let (c, d) = (bounds.center(), bounds.diagonal());
    let mut out = Vec::new();
    for dir in [Vec3::X, -Vec3::Y, Vec3::Z, Vec3::new(1.0, 1.0, 1.0).normalize()] {
        let up = if dir.y.abs() > 0.9 { Vec3::Z } else { Vec3::Y };
        for (eye, fov, near, far) in [
            (c - dir * 2.0 * d, 40.0, 0.01 * d, 10.0 * d),
            (c - dir * 2.0 * d, 4.0, 0.01 * d, 10.0 * d),
            (c, 70.0, 0.001 * d, 2.0 * d),
            (c - dir * 0.6 * d, 50.0, 0.45 * d, 0.75 * d),
        ] {
            if let Ok(f) = Frustum::look_at(eye, eye + dir, up, fov, 1.3, near, far) {
                out.push(f);
            }
        }
    }
    out
}

/// Brute force's answers over one set at some points: computed once, then
/// compared with every build configuration (and, through [`cached`], every
/// structure). Answers only, not the set, so that a cache of them stays small.
struct Expected {
    points: Vec<Vec3>,
    ks: Vec<usize>,
    /// Number of primitives.
    len: usize,
    /// Per point: the closest primitive, then the closest within each of
    /// [`radii`] of it.
    closest: Vec<(Option<ClosestHit>, Vec<Option<ClosestHit>>)>,
    /// Per point, per `k` of `ks`: the `k` nearest.
    k_nearest: Vec<Vec<Vec<ClosestHit>>>,
    /// Cameras about the set, each with the number of primitives it sees and
    /// a hash of their indices (a mismatch is then shown against brute force
    /// run again).
    frustums: Vec<(Frustum, usize, u64)>,
}

/// The radii around a closest answer at which `closest_within` is checked:
/// beyond it, just beyond (rounding), inside it, zero.
fn radii(hit: &Option<ClosestHit>) -> Vec<f32> {
    hit.map_or_else(Vec::new, |e| {
        vec![e.distance * 2.0, e.distance * 1.000001, e.distance * 0.5, 0.0]
    })
}

fn hash_of(indices: &[u32]) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    indices.hash(&mut hasher);
    hasher.finish()
}

impl Expected {
    fn new<T: MeshPrimitive>(set: &PrimitiveSet<T>, points: &[Vec3], ks: &[usize]) -> Self {
        let linear = LinearSearch::new(set.clone());
        let closest = points
            .par_iter()
            .map(|&p| {
                let hit = linear.closest(p);
                let within = radii(&hit).iter().map(|&r| linear.closest_within(p, r)).collect();
                (hit, within)
            })
            .collect();
        let k_nearest = points
            .par_iter()
            .map(|&p| ks.iter().map(|&k| linear.k_nearest(p, k)).collect())
            .collect();
        let frustums = cameras(&linear.bounds())
            .into_iter()
            .map(|f| {
                let seen = linear.frustum(&f);
                assert!(seen.windows(2).all(|w| w[0] < w[1]));
                let (len, hash) = (seen.len(), hash_of(&seen));
                (f, len, hash)
            })
            .collect();
        Self {
            points: points.to_vec(),
            ks: ks.to_vec(),
            len: linear.len(),
            closest,
            k_nearest,
            frustums,
        }
    }

    /// How many cameras see part of the set, but not all of it.
    fn partial_views(&self) -> usize {
        self.frustums
            .iter()
            .filter(|&&(_, seen, _)| seen > 0 && seen < self.len)
            .count()
    }

    /// Builds `S` over `set` (the set these answers are for) with `config`
    /// and checks every query of the shared interface against them.
    fn check<S: Structure<T>, T: MeshPrimitive>(&self, set: &PrimitiveSet<T>, config: &BuildConfig) {
        let name = S::NAME;
        assert_eq!(set.len(), self.len);
        let structure = S::build(set.clone(), config).unwrap();
        structure.check_invariants(set, config);
        let forms = structure.other_forms();
        let points = &self.points[..];
        points.par_iter().zip(&self.closest).zip(&self.k_nearest).for_each_init(
            || (KnnScratch::new(), Vec::new()),
            |(scratch, out), ((&p, (e, within)), k_nearest)| {
                let e = *e;
                assert_eq!(structure.closest(p), e, "{name}: closest at {p}, config {config:?}");
                for (form, other) in &forms {
                    assert_eq!(
                        other.closest(p),
                        e,
                        "{name} ({form}): closest at {p}, config {config:?}"
                    );
                }
                let (hit, stats) = structure.closest_with_stats(p);
                assert_eq!(hit, e, "{name}: closest with stats at {p}");
                assert!(stats.primitives_tested >= e.is_some() as u64 && stats.nodes_visited >= 1);
                for (max, want) in radii(&e).into_iter().zip(within) {
                    assert_eq!(structure.closest_within(p, max), *want, "{name}: within {max} at {p}");
                }
                for (&k, want) in self.ks.iter().zip(k_nearest) {
                    assert_eq!(structure.k_nearest(p, k), *want, "{name}: k = {k} at {p}");
                    structure.k_nearest_into(p, k, scratch, out);
                    assert_eq!(out, want, "{name}: k = {k} at {p}, reused scratch");
                }
            },
        );
        let expected: Vec<Option<ClosestHit>> = self.closest.iter().map(|(e, _)| *e).collect();
        assert_eq!(structure.closest_batch(points), expected, "{name}: batch");
        // Every batch configuration gives the same answers.
        for options in batch_options() {
            assert_eq!(
                structure.closest_batch_with(points, options),
                expected,
                "{name}: {options:?}"
            );
        }
        if let Some((last, &k)) = self.ks.iter().enumerate().max_by_key(|&(_, k)| k) {
            let want: Vec<&Vec<ClosestHit>> = self.k_nearest.iter().map(|per_k| &per_k[last]).collect();
            let got = structure.k_nearest_batch(points, k);
            assert!(got.iter().eq(want), "{name}: k = {k} batch, config {config:?}");
        }
        let mut reused = Vec::new();
        for (f, seen, hash) in &self.frustums {
            let same = |got: &[u32]| got.len() == *seen && hash_of(got) == *hash;
            let got = structure.frustum(f);
            structure.frustum_into(f, &mut reused);
            let (with_stats, stats) = structure.frustum_with_stats(f);
            if !(same(&got) && same(&reused) && same(&with_stats)) {
                let want = LinearSearch::new(set.clone()).frustum(f);
                assert_eq!(got, want, "{name}: camera {:?}", f.matrix());
                assert_eq!(reused, want, "{name}: reused output, camera {:?}", f.matrix());
                assert_eq!(with_stats, want, "{name}: with stats, camera {:?}", f.matrix());
                panic!("{name}: brute force changed its answer, camera {:?}", f.matrix());
            }
            assert!(stats.primitives_tested <= self.len as u64);
        }
    }
}

/// Brute force's answers for the input named `key` (which must say
/// everything the answers depend on) over primitives `T`: computed by the
/// first structure's test that asks, then shared with the others, which run
/// in the same process.
fn cached<T: MeshPrimitive>(key: String, make: impl FnOnce() -> Expected) -> Arc<Expected> {
    type Cell = Arc<OnceLock<Arc<Expected>>>;
    static CACHE: Mutex<BTreeMap<(String, PrimitiveKind), Cell>> = Mutex::new(BTreeMap::new());
    let cell = CACHE.lock().unwrap().entry((key, T::KIND)).or_default().clone();
    cell.get_or_init(|| Arc::new(make())).clone()
}

/// Checks `S` over `set` at `points` with `config` (k-nearest for each of
/// `ks`); returns how many cameras saw part of the set.
fn check<S: Structure<T>, T: MeshPrimitive>(
    set: PrimitiveSet<T>,
    points: &[Vec3],
    config: &BuildConfig,
    ks: &[usize],
) -> usize {
    let expected = Expected::new(&set, points, ks);
    expected.check::<S, T>(&set, config);
    expected.partial_views()
}

/// Checks the vertices, edges and triangles of `mesh` (polygons: see
/// `polygons.rs`), at its query points ([`queries`]), with each of
/// `configs`; returns how many cameras saw part of a set. `name` names the
/// mesh: brute force's answers are shared through [`cached`].
fn check_mesh<F: Family>(name: &str, mesh: &Mesh, n_queries: usize, configs: &[BuildConfig], ks: &[usize]) -> usize {
    fn each<S: Structure<T>, T: MeshPrimitive>(
        key: String,
        set: PrimitiveSet<T>,
        points: &[Vec3],
        configs: &[BuildConfig],
        ks: &[usize],
    ) -> usize {
        let expected = cached::<T>(key, || Expected::new(&set, points, ks));
        for config in configs {
            expected.check::<S, T>(&set, config);
        }
        expected.partial_views()
    }
    let points = queries(mesh, n_queries, 7);
    let key = format!("{name}, {n_queries} queries, k in {ks:?}");
    each::<F::Of<Point>, _>(key.clone(), mesh.vertices(), &points, configs, ks)
        + each::<F::Of<LineSegment>, _>(key.clone(), mesh.edges(), &points, configs, ks)
        + each::<F::Of<Triangle>, _>(key, mesh.triangles(), &points, configs, ks)
}

// ---------------------------------------------------------------- the suite

fn random_soups_match_brute_force<F: Family>() {
    let mut partial = 0;
    for seed in 0..4 {
        let mesh = random_soup(300 + 50 * seed as usize, seed);
        partial += check_mesh::<F>(&format!("soup {seed}"), &mesh, 60, &configs(), &[0, 1, 5, 10_000]);
    }
    // Some cameras see part of a soup: the frustum answers are not trivial.
    assert!(partial > 0);
}

fn bumpy_sphere_matches_brute_force_inside_and_out<F: Family>() {
    let mesh = bumpy_sphere(12, 3);
    assert_eq!(mesh.triangle_count(), 20 * 144);
    check_mesh::<F>(
        "bumpy sphere",
        &mesh,
        200,
        &[BuildConfig::default(), BuildConfig::fast_queries()],
        &[3],
    );
    // Deep inside a closed mesh every primitive is far: the hardest case.
    let inside: Vec<Vec3> = (0..20).map(|i| Vec3::splat(i as f32 * 0.01)).collect();
    check::<F::Of<Triangle>, _>(mesh.triangles(), &inside, &BuildConfig::default(), &[2]);
}

fn large_meshes_use_the_parallel_build_and_stay_exact<F: Family>() {
    // Above 32k primitives subtrees are built in parallel and joined.
    let mesh = bumpy_sphere(60, 5);
    assert!(mesh.triangle_count() > 70_000);
    // Near the surface, in the box, on vertices and edges, far off, at the center.
    let points = queries(&mesh, 40, 11);
    let triangles = mesh.triangles();
    let expected = cached::<Triangle>("large bumpy sphere".into(), || Expected::new(&triangles, &points, &[2]));
    for split in [SplitMethod::Median, SplitMethod::BinnedSah] {
        let config = BuildConfig {
            split,
            ..BuildConfig::default()
        };
        expected.check::<F::Of<Triangle>, _>(&triangles, &config);
    }
}

fn degenerate_inputs<F: Family>() {
    // Empty.
    let config = BuildConfig::default();
    let empty = F::Of::<Triangle>::build(PrimitiveSet::default(), &config).unwrap();
    empty.check_invariants(&PrimitiveSet::default(), &config);
    assert_eq!(empty.node_count(), 0);
    assert_eq!(empty.closest(Vec3::ZERO), None);
    assert!(empty.k_nearest(Vec3::ZERO, 3).is_empty());
    assert_eq!(empty.closest_batch(&[Vec3::ZERO]), vec![None]);
    // One point: the root is a single leaf.
    let one = F::Of::<Point>::build(PrimitiveSet::from_primitives(vec![Point(Vec3::ONE)]), &config).unwrap();
    assert_eq!(one.node_count(), 1);
    let hit = one.closest(Vec3::ZERO).unwrap();
    assert_eq!((hit.primitive, hit.point, hit.distance), (0, Vec3::ONE, 3f32.sqrt()));
    // One triangle, and many identical ones: ties everywhere, to the lowest index.
    let one = Mesh::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]]).unwrap();
    check_mesh::<F>("one triangle", &one, 20, &[config], &[0, 1, 2, 9]);
    let same = Mesh::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]; 50]).unwrap();
    check_mesh::<F>("same triangle", &same, 20, &[config], &[1, 7]);
    // All vertices equal: every triangle and edge is a point.
    let point = Mesh::from_triangles(vec![Vec3::ONE; 3], &[[0, 1, 2]; 9]).unwrap();
    check_mesh::<F>("point triangles", &point, 10, &[config], &[1, 4]);
    // Huge and far-offset coordinates with small features.
    for (scale, offset) in [(1e15f32, 0.0f32), (1e-30, 0.0), (1e-3, 1e7), (1.0, -3e5)] {
        let positions = (0..30)
            .map(|i| Vec3::new(i as f32 % 5.0, (i / 5) as f32, (i % 3) as f32) * scale + Vec3::splat(offset))
            .collect();
        let tris: Vec<[u32; 3]> = (0..28).map(|i| [i, i + 1, i + 2]).collect();
        let m = Mesh::from_triangles(positions, &tris).unwrap();
        check_mesh::<F>(&format!("scale {scale}, offset {offset}"), &m, 30, &[config], &[1, 3]);
    }
}

fn closest_within_matches_brute_force<F: Family>() {
    let mesh = random_soup(400, 9);
    let set = mesh.triangles();
    let structure = F::Of::<Triangle>::build(set.clone(), &BuildConfig::default()).unwrap();
    let linear = LinearSearch::new(set);
    for p in queries(&mesh, 60, 3) {
        for r in [0.0, 0.01, 0.05, 0.3, f32::INFINITY] {
            assert_eq!(
                structure.closest_within(p, r),
                linear.closest_within(p, r),
                "at {p} within {r}"
            );
        }
    }
}

fn non_finite_queries_answer_nothing<F: Family>() {
    let mesh = random_soup(50, 1);
    let structure = F::Of::<Triangle>::build(mesh.triangles(), &BuildConfig::default()).unwrap();
    for p in [
        Vec3::NAN,
        Vec3::new(f32::INFINITY, 0.0, 0.0),
        Vec3::new(0.0, f32::NAN, 1.0),
    ] {
        assert_eq!(structure.closest(p), None);
        assert!(structure.k_nearest(p, 3).is_empty());
        assert_eq!(structure.closest_batch(&[p]), vec![None]);
        // Between finite queries, whose answers seed the next search: the
        // bad point still answers nothing and does not disturb the others.
        let mixed = mixed_with(p);
        let expected: Vec<_> = mixed.iter().map(|&q| structure.closest(q)).collect();
        assert!(expected[0].is_some() && expected[1].is_none());
        for options in batch_options() {
            assert_eq!(structure.closest_batch_with(&mixed, options), expected, "{options:?}");
        }
    }
}

fn bad_build_parameters_are_errors<F: Family>() {
    let tris = random_soup(10, 2).triangles();
    for config in [
        BuildConfig {
            max_depth: 0,
            ..Default::default()
        },
        BuildConfig {
            max_depth: 1000,
            ..Default::default()
        },
        BuildConfig {
            min_size: 0,
            ..Default::default()
        },
    ] {
        assert!(F::Of::<Triangle>::build(tris.clone(), &config).is_err(), "{config:?}");
    }
    let bad = PrimitiveSet::from_primitives(vec![Point(Vec3::new(0.0, f32::NAN, 0.0))]);
    assert!(F::Of::<Point>::build(bad, &BuildConfig::default()).is_err());
}

/// The wide tree skips, in leaves whose box lies near the edge of the search
/// radius, the triangle pairs none of whose boxes is within reach. Far from
/// the origin, where a computed closest point can lie several ulps outside
/// its triangle's box, and with many exact ties (a grid of equal
/// triangles), every structure's answers must still be brute force's, bit
/// for bit.
fn far_offsets_and_exact_ties_match_brute_force<F: Family>() {
    for (scale, offset) in [(1.0f32, 0.0f32), (1e-2, 1e3), (1e-3, 3e5), (10.0, -1e6)] {
        let soup = random_soup(3000, 41);
        let positions: Vec<Vec3> = soup
            .positions()
            .iter()
            .map(|&p| p * scale + Vec3::splat(offset))
            .collect();
        let faces: Vec<[u32; 3]> = soup.faces().map(|f| [f[0], f[1], f[2]]).collect();
        let mesh = Mesh::from_triangles(positions, &faces).unwrap();
        let points = queries(&mesh, 300, 43);
        let structure = F::Of::<Triangle>::build(mesh.triangles(), &BuildConfig::default()).unwrap();
        let linear = LinearSearch::new(mesh.triangles());
        points.par_iter().for_each(|&p| {
            assert_eq!(
                structure.closest(p),
                linear.closest(p),
                "at {p}, scale {scale}, offset {offset}"
            );
        });
    }
    // A grid of unit right triangles, two per square, queried above and
    // between them: many triangles at exactly the same distance.
    let n = 40u32;
    let positions: Vec<Vec3> = (0..=n)
        .flat_map(|j| (0..=n).map(move |i| Vec3::new(i as f32, j as f32, 0.0)))
        .collect();
    let faces: Vec<[u32; 3]> = (0..n)
        .flat_map(|j| {
            (0..n).flat_map(move |i| {
                let v = j * (n + 1) + i;
                [[v, v + 1, v + n + 1], [v + 1, v + n + 2, v + n + 1]]
            })
        })
        .collect();
    let mesh = Mesh::from_triangles(positions, &faces).unwrap();
    let structure = F::Of::<Triangle>::build(mesh.triangles(), &BuildConfig::default()).unwrap();
    let linear = LinearSearch::new(mesh.triangles());
    for j in 0..2 * n {
        for i in 0..2 * n {
            let p = Vec3::new(i as f32 * 0.5, j as f32 * 0.5, [0.0, 0.25, 3.0][((i + j) % 3) as usize]);
            assert_eq!(structure.closest(p), linear.closest(p), "at {p}");
        }
    }
}

fn real_meshes_match_brute_force<F: Family>() {
    for path in shared_meshes() {
        let mesh = proxima::io::load(&path).unwrap();
        // Linear search is O(n) per query: fewer queries on big meshes.
        let n = (3_000_000 / mesh.triangle_count().max(1)).clamp(4, 150);
        println!(
            "{}: {} triangles, {n} queries per kind",
            path.display(),
            mesh.triangle_count()
        );
        check_mesh::<F>(
            &path.display().to_string(),
            &mesh,
            n,
            &[BuildConfig::default()],
            &[3, 4],
        );
    }
}

/// A random soup whose kind is chosen by `mode`: spread, all identical,
/// collinear, one primitive; coordinates scaled and offset.
fn soup(mode: u8, n: usize, scale: f32, offset: f32, seed: u64) -> Vec<Triangle> {
    let mut rng = proxima::sample::Rng::new(seed);
    let mut v = || Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
    let first = Triangle::new(v(), v(), v());
    let tris: Vec<Triangle> = match mode {
        0 => (0..n).map(|_| Triangle::new(v(), v(), v())).collect(),
        1 => vec![first; n],
        2 => {
            let dir = v();
            (0..n)
                .map(|i| {
                    let t = i as f32 * 0.37;
                    Triangle::new(dir * t, dir * (t + 0.5), dir * (t - 0.2))
                })
                .collect()
        }
        _ => vec![first],
    };
    let f = |p: Vec3| p * scale + Vec3::splat(offset);
    tris.into_iter()
        .map(|t| Triangle::new(f(t.a), f(t.b), f(t.c)))
        .collect()
}

/// The body of the proptest `random_and_degenerate_sets_match_brute_force`.
fn random_and_degenerate_set<F: Family>(
    (mode, n, scale, offset): (u8, usize, f32, f32),
    min_size: u32,
    seed: u64,
    queries: &[(f32, f32, f32)],
) {
    let tris = soup(mode, n, scale, offset, seed);
    let config = BuildConfig {
        min_size,
        ..BuildConfig::default()
    };
    let mut points: Vec<Vec3> = queries
        .iter()
        .map(|&(x, y, z)| Vec3::new(x, y, z) * scale + Vec3::splat(offset))
        .collect();
    points.push(tris[0].a);
    let segments: Vec<LineSegment> = tris.iter().map(|t| LineSegment::new(t.a, t.b)).collect();
    let vertices: Vec<Point> = tris.iter().map(|t| Point(t.c)).collect();
    check::<F::Of<Triangle>, _>(PrimitiveSet::from_primitives(tris), &points, &config, &[1, 3, 100]);
    check::<F::Of<LineSegment>, _>(PrimitiveSet::from_primitives(segments), &points, &config, &[2]);
    check::<F::Of<Point>, _>(PrimitiveSet::from_primitives(vertices), &points, &config, &[1, 5]);
}

// ---------------------------------------------------------------- rays

/// Rays about `mesh`: from its query points towards others, along the axes
/// (signed zeros included), in random directions; a zero direction and a
/// non-finite origin (errors); several t ranges.
fn rays(mesh: &Mesh, n: usize, seed: u64) -> Vec<(Vec3, Vec3, f32, f32)> {
    let points = queries(mesh, n, seed);
    let mut rng = proxima::sample::Rng::new(seed + 3);
    let mut out = Vec::new();
    for (k, &o) in points.iter().enumerate() {
        let d = match k % 5 {
            0 => Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)),
            1 => [Vec3::X, -Vec3::Y, Vec3::new(0.0, -0.0, 1.0)][k % 3],
            _ => points[rng.below(points.len())] - o,
        };
        let (t_min, t_max) = match k % 4 {
            0 => (rng.range(-1.0, 0.5), rng.range(0.5, 2.0)),
            1 => (-f32::MAX, f32::INFINITY),
            _ => (0.0, f32::INFINITY),
        };
        out.push((o, d, t_min, t_max));
    }
    out.push((Vec3::ZERO, Vec3::ZERO, 0.0, 1.0));
    out.push((Vec3::NAN, Vec3::X, 0.0, 1.0));
    out
}

/// Checks first hit (with and without statistics), any hit and their
/// batches of the structure over `set`, built with each of `configs`,
/// against brute force; returns the number of rays that hit.
fn check_rays<S: Structure<T> + RayQuery<T>, T: MeshPrimitive + RayIntersect>(
    set: PrimitiveSet<T>,
    rays: &[(Vec3, Vec3, f32, f32)],
    configs: &[BuildConfig],
) -> usize {
    let name = S::NAME;
    let linear = LinearSearch::new(set.clone());
    let want: Vec<_> = rays
        .par_iter()
        .map(|&(o, d, t_min, t_max)| (linear.first_hit(o, d, t_min, t_max), linear.any_hit(o, d, t_min, t_max)))
        .collect();
    // Batches take one t range for all rays.
    let batch: Vec<(Vec3, Vec3)> = rays.iter().map(|&(o, d, _, _)| (o, d)).collect();
    let ranges = [(0.0, f32::INFINITY), (-1.0, 0.5)];
    let want_batches: Vec<_> = ranges
        .iter()
        .map(|&(t_min, t_max)| {
            let first: Vec<Result<Option<RayHit>, RayError>> = batch
                .iter()
                .map(|&(o, d)| linear.first_hit(o, d, t_min, t_max))
                .collect();
            let any: Vec<Result<bool, RayError>> =
                batch.iter().map(|&(o, d)| linear.any_hit(o, d, t_min, t_max)).collect();
            (first, any)
        })
        .collect();
    for config in configs {
        let structure = S::build(set.clone(), config).unwrap();
        rays.par_iter()
            .zip(&want)
            .for_each(|(&(o, d, t_min, t_max), (first, any))| {
                let at = format!("{name}: ray ({o}, {d}, [{t_min}, {t_max}]), config {config:?}");
                assert_eq!(structure.first_hit(o, d, t_min, t_max), *first, "{at}");
                let with_stats = structure.first_hit_with_stats(o, d, t_min, t_max).map(|(hit, _)| hit);
                assert_eq!(with_stats, *first, "{at}, with stats");
                assert_eq!(structure.any_hit(o, d, t_min, t_max), *any, "{at}, any hit");
            });
        for (&(t_min, t_max), (first, any)) in ranges.iter().zip(&want_batches) {
            assert_eq!(
                structure.first_hit_batch(&batch, t_min, t_max),
                *first,
                "{name}: first hit batch"
            );
            assert_eq!(
                structure.any_hit_batch(&batch, t_min, t_max),
                *any,
                "{name}: any hit batch"
            );
        }
    }
    want.iter().filter(|(first, _)| matches!(first, Ok(Some(_)))).count()
}

fn rays_match_brute_force<F: Family>()
where
    F::Of<Triangle>: RayQuery<Triangle>,
    F::Of<ConvexPolygon>: RayQuery<ConvexPolygon>,
{
    let ray_configs = [
        BuildConfig::default(),
        BuildConfig::fast_queries(),
        BuildConfig {
            min_size: 1,
            split: SplitMethod::Median,
            ..BuildConfig::default()
        },
    ];
    let mut meshes = vec![bumpy_sphere(12, 3)];
    meshes.extend((0..3).map(|seed| random_soup(300 + 200 * seed as usize, seed)));
    meshes.push(Mesh::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]; 50]).unwrap());
    for (scale, offset) in [(1e15f32, 0.0f32), (1e-30, 0.0), (1e-3, 1e7), (1.0, -3e5)] {
        let positions = (0..30)
            .map(|i| Vec3::new(i as f32 % 5.0, (i / 5) as f32, (i % 3) as f32) * scale + Vec3::splat(offset))
            .collect();
        let tris: Vec<[u32; 3]> = (0..28).map(|i| [i, i + 1, i + 2]).collect();
        meshes.push(Mesh::from_triangles(positions, &tris).unwrap());
    }
    for (i, mesh) in meshes.iter().enumerate() {
        let rays = rays(mesh, 200, 20 + i as u64);
        let hits = check_rays::<F::Of<Triangle>, _>(mesh.triangles(), &rays, &ray_configs)
            + check_rays::<F::Of<ConvexPolygon>, _>(mesh.polygons(), &rays, &ray_configs);
        // Rays towards query points near the surface: some of them hit
        // (the sphere and the soups, at least).
        assert!(hits > 0 || i > 3, "mesh {i}: no ray hit");
    }
}

// ---------------------------------------------------------------- one line per structure

/// Runs the whole suite on `$structure` (a type constructor over the
/// primitive type), as the tests of module `$name`; each extra name is a
/// macro adding tests the structure can take (`rays`).
macro_rules! suite {
    ($name:ident, $structure:ident $(, $extra:ident)*) => {
        mod $name {
            use super::*;

            pub enum Family {}
            impl super::Family for Family {
                type Of<T: MeshPrimitive> = $structure<T>;
            }

            #[test]
            fn random_soups_match_brute_force() {
                super::random_soups_match_brute_force::<Family>();
            }
            #[test]
            fn bumpy_sphere_matches_brute_force_inside_and_out() {
                super::bumpy_sphere_matches_brute_force_inside_and_out::<Family>();
            }
            #[test]
            fn large_meshes_use_the_parallel_build_and_stay_exact() {
                super::large_meshes_use_the_parallel_build_and_stay_exact::<Family>();
            }
            #[test]
            fn degenerate_inputs() {
                super::degenerate_inputs::<Family>();
            }
            #[test]
            fn closest_within_matches_brute_force() {
                super::closest_within_matches_brute_force::<Family>();
            }
            #[test]
            fn non_finite_queries_answer_nothing() {
                super::non_finite_queries_answer_nothing::<Family>();
            }
            #[test]
            fn bad_build_parameters_are_errors() {
                super::bad_build_parameters_are_errors::<Family>();
            }
            #[test]
            fn far_offsets_and_exact_ties_match_brute_force() {
                super::far_offsets_and_exact_ties_match_brute_force::<Family>();
            }
            #[test]
            fn real_meshes_match_brute_force() {
                super::real_meshes_match_brute_force::<Family>();
            }

            proptest! {
                #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

                #[test]
                fn random_and_degenerate_sets_match_brute_force(
                    mode in 0u8..4,
                    n in 1usize..80,
                    scale in prop::sample::select(vec![1e-30f32, 1e-6, 1.0, 1e4, 1e15]),
                    offset in prop::sample::select(vec![0.0f32, 1.0, -1e4, 1e7]),
                    min_size in 1u32..6,
                    seed in 0u64..1000,
                    queries in prop::collection::vec((-3.0f32..3.0, -3.0f32..3.0, -3.0f32..3.0), 1..12),
                ) {
                    super::random_and_degenerate_set::<Family>((mode, n, scale, offset), min_size, seed, &queries);
                }
            }

            $($extra!();)*
        }
    };
}

/// The ray tests, for structures answering [`RayQuery`].
macro_rules! rays {
    () => {
        #[test]
        fn rays_match_brute_force() {
            super::rays_match_brute_force::<Family>();
        }
    };
}

suite!(aabb_tree, AabbTree, rays);
suite!(wide_tree, WideTree, rays);
suite!(sphere_tree, SphereTree);
