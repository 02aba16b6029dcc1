//! Criterion benches of the AABB tree: build, closest and k-nearest queries,
//! view frustum queries (a camera seeing about 10% of the faces),
//! against brute force and parry3d on the same meshes and queries.
//!
//! Meshes: the seeded 1M-triangle bumpy icosphere `ico1m` (always available) and the dragon from
//! ../shared/data when present. `cargo bench -p proxima-bench --bench bvh`.

use criterion::{BatchSize, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use parry3d::shape::TriMesh;
use proxima::frustum::Frustum;
use proxima::prelude::*;
use proxima::{AabbTree, BuildConfig, LinearSearch, Mesh, SphereTree, Vec3};
use proxima_bench::{load_named, parry_distance, parry_input, parry_trimesh};
use std::hint::black_box;
use std::time::Duration;

fn meshes() -> Vec<(&'static str, Mesh)> {
    let mut out = vec![("ico1m", load_named("ico1m").unwrap())];
    if let Ok(dragon) = load_named("dragon_vrip.ply.gz") {
        out.push(("dragon", dragon));
    } else {
        println!("skipped: dragon (../shared/data not found)");
    }
    out
}

fn build(c: &mut Criterion) {
    let mut group = c.benchmark_group("build");
    group.sample_size(10).measurement_time(Duration::from_secs(4));
    let one_thread = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    for (name, mesh) in meshes() {
        let triangles = mesh.triangles();
        group.throughput(Throughput::Elements(triangles.len() as u64));
        for (label, config) in [
            ("median", BuildConfig::fast_build()),
            ("sah", BuildConfig::fast_queries()),
        ] {
            // Each library's input is made untimed (`iter_batched`): only the build calls count.
            group.bench_function(BenchmarkId::new(format!("proxima-{label}-1thread"), name), |b| {
                b.iter_batched(
                    || triangles.clone(),
                    |input| one_thread.install(|| AabbTree::build_set(input, &config).unwrap()),
                    BatchSize::LargeInput,
                )
            });
            group.bench_function(BenchmarkId::new(format!("proxima-{label}-all-threads"), name), |b| {
                b.iter_batched(
                    || triangles.clone(),
                    |input| AabbTree::build_set(input, &config).unwrap(),
                    BatchSize::LargeInput,
                )
            });
        }
        // The 4-wide tree that answers the queries: its binary tree and the collapse.
        group.bench_function(BenchmarkId::new("proxima-wide-1thread", name), |b| {
            b.iter_batched(
                || triangles.clone(),
                |input| one_thread.install(|| WideTree::build_set(input, &BuildConfig::default()).unwrap()),
                BatchSize::LargeInput,
            )
        });
        group.bench_function(BenchmarkId::new("parry3d", name), |b| {
            b.iter_batched(
                || parry_input(&mesh),
                |(vertices, indices)| TriMesh::new(vertices, indices).unwrap(),
                BatchSize::LargeInput,
            )
        });
    }
    group.finish();
}

fn closest(c: &mut Criterion) {
    let mut group = c.benchmark_group("closest-face");
    group.sample_size(10).measurement_time(Duration::from_secs(4));
    let one_thread = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    for (name, mesh) in meshes() {
        let tree = AabbTree::build_set(mesh.triangles(), &BuildConfig::default()).unwrap();
        let sah = AabbTree::build_set(mesh.triangles(), &BuildConfig::fast_queries()).unwrap();
        let wide = WideTree::from_tree(tree.clone());
        let trimesh = parry_trimesh(&mesh);
        for (set, points) in [
            ("near", proxima::sample::near_surface(&mesh, 5_000, 0.01, 1)),
            ("uniform", proxima::sample::uniform_in_box(&mesh, 2_000, 2)),
        ] {
            group.throughput(Throughput::Elements(points.len() as u64));
            let id = |who: &str| BenchmarkId::new(who.to_string(), format!("{name}/{set}"));
            group.bench_function(id("proxima-median"), |b| {
                b.iter(|| points.iter().map(|&p| tree.closest(p).unwrap().distance).sum::<f32>())
            });
            group.bench_function(id("proxima-sah"), |b| {
                b.iter(|| points.iter().map(|&p| sah.closest(p).unwrap().distance).sum::<f32>())
            });
            group.bench_function(id("proxima-batch-1thread"), |b| {
                b.iter(|| one_thread.install(|| tree.closest_batch_with(&points, BatchOptions::default())))
            });
            group.bench_function(id("proxima-wide"), |b| {
                b.iter(|| points.iter().map(|&p| wide.closest(p).unwrap().distance).sum::<f32>())
            });
            group.bench_function(id("proxima-wide-batch-1thread"), |b| {
                b.iter(|| one_thread.install(|| wide.closest_batch(&points)))
            });
            group.bench_function(id("proxima-wide-batch-all-threads"), |b| {
                b.iter(|| wide.closest_batch(&points))
            });
            group.bench_function(id("parry3d"), |b| {
                b.iter(|| points.iter().map(|&p| parry_distance(&trimesh, p)).sum::<f32>())
            });
        }
    }
    group.finish();
}

fn versus_linear(c: &mut Criterion) {
    let mut group = c.benchmark_group("tree-vs-linear");
    group.sample_size(10).measurement_time(Duration::from_secs(3));
    let mesh = load_named("ico100k").unwrap();
    let points: Vec<Vec3> = proxima::sample::near_surface(&mesh, 100, 0.01, 3);
    let tree = AabbTree::build_set(mesh.triangles(), &BuildConfig::default()).unwrap();
    let linear = LinearSearch::new(mesh.triangles());
    group.throughput(Throughput::Elements(points.len() as u64));
    group.bench_function("tree/ico100k", |b| {
        b.iter(|| points.iter().map(|&p| tree.closest(p).unwrap().distance).sum::<f32>())
    });
    group.bench_function("linear/ico100k", |b| {
        b.iter(|| points.iter().map(|&p| linear.closest(p).unwrap().distance).sum::<f32>())
    });
    group.bench_function("tree-k8/ico100k", |b| {
        b.iter(|| points.iter().map(|&p| tree.k_nearest(p, 8).len()).sum::<usize>())
    });
    group.finish();
}

/// A camera in front of the mesh whose field of view is narrowed (bisection)
/// until it sees about `fraction` of the faces.
fn camera_seeing(mesh: &Mesh, tree: &AabbTree<proxima::Triangle>, fraction: f64) -> Frustum {
    let b = mesh.bounds();
    let (center, diagonal) = (b.center(), b.diagonal());
    let eye = center + Vec3::new(0.1, 0.05, 2.0) * diagonal;
    let frustum = |fov: f32| Frustum::look_at(eye, center, Vec3::Y, fov, 1.0, 0.01 * diagonal, 4.0 * diagonal).unwrap();
    let (mut lo, mut hi) = (0.1f32, 90.0f32);
    for _ in 0..30 {
        let mid = 0.5 * (lo + hi);
        if (tree.frustum(&frustum(mid)).len() as f64) < fraction * tree.len() as f64 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    frustum(hi)
}

fn frustum_queries(c: &mut Criterion) {
    let mut group = c.benchmark_group("frustum");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    let mut meshes = meshes();
    if let Ok(nefertiti) = load_named("nefertiti.obj") {
        meshes.push(("nefertiti", nefertiti));
    }
    for (name, mesh) in meshes {
        let tree = AabbTree::build_set(mesh.triangles(), &BuildConfig::default()).unwrap();
        let linear = LinearSearch::new(mesh.triangles());
        let camera = camera_seeing(&mesh, &tree, 0.1);
        let (found, stats) = tree.frustum_with_stats(&camera);
        println!(
            "frustum/{name}: {} of {} faces seen, {} nodes visited, {} faces tested",
            found.len(),
            tree.len(),
            stats.nodes_visited,
            stats.primitives_tested
        );
        let mut out = Vec::new();
        group.bench_function(BenchmarkId::new("tree", name), |b| {
            b.iter(|| {
                tree.frustum_into(black_box(&camera), &mut out);
                out.len()
            })
        });
        group.bench_function(BenchmarkId::new("linear", name), |b| {
            b.iter(|| {
                linear.frustum_into(black_box(&camera), &mut out);
                out.len()
            })
        });
    }
    group.finish();
}

/// The sphere tree beside the AABB tree it is converted from: build on one
/// thread, and closest-face queries on the same points.
fn spheres_versus_boxes(c: &mut Criterion) {
    let mut group = c.benchmark_group("sphere-tree");
    group.sample_size(10).measurement_time(Duration::from_secs(4));
    let one_thread = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    for (name, mesh) in meshes() {
        let config = BuildConfig::default();
        let triangles = mesh.triangles();
        group.throughput(Throughput::Elements(triangles.len() as u64));
        group.bench_function(BenchmarkId::new("build-aabb-1thread", name), |b| {
            b.iter(|| one_thread.install(|| AabbTree::build_set(black_box(triangles.clone()), &config).unwrap()))
        });
        group.bench_function(BenchmarkId::new("build-spheres-1thread", name), |b| {
            b.iter(|| one_thread.install(|| SphereTree::build_set(black_box(triangles.clone()), &config).unwrap()))
        });
        let boxes = AabbTree::build_set(triangles.clone(), &config).unwrap();
        let spheres = SphereTree::build_set(triangles, &config).unwrap();
        for (set, points) in [
            ("near", proxima::sample::near_surface(&mesh, 5_000, 0.01, 1)),
            ("uniform", proxima::sample::uniform_in_box(&mesh, 2_000, 2)),
        ] {
            group.throughput(Throughput::Elements(points.len() as u64));
            let id = |who: &str| BenchmarkId::new(who.to_string(), format!("{name}/{set}"));
            group.bench_function(id("closest-aabb"), |b| {
                b.iter(|| points.iter().map(|&p| boxes.closest(p).unwrap().distance).sum::<f32>())
            });
            group.bench_function(id("closest-spheres"), |b| {
                b.iter(|| {
                    points
                        .iter()
                        .map(|&p| spheres.closest(p).unwrap().distance)
                        .sum::<f32>()
                })
            });
        }
    }
    group.finish();
}

criterion_group!(
    benches,
    build,
    closest,
    versus_linear,
    frustum_queries,
    spheres_versus_boxes
);
criterion_main!(benches);
