//! Criterion benches of the AABB tree: build, closest and k-nearest queries,
//! against brute force and parry3d on the same meshes and queries.
//!
//! Meshes: the seeded bumpy icospheres (always available) and the dragon from
//! ../shared/data when present. `cargo bench -p proxima-bench --bench bvh`.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use proxima::bvh::BatchOptions;
use proxima::{AabbTree, BuildConfig, LinearSearch, Mesh, SphereTree, Vec3};
use proxima_bench::{load_named, parry_distance, parry_trimesh};
use std::hint::black_box;
use std::time::Duration;

fn meshes() -> Vec<(&'static str, Mesh)> {
    let mut out = vec![("ico100k", load_named("ico100k").unwrap())];
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
            group.bench_function(BenchmarkId::new(format!("proxima-{label}-1thread"), name), |b| {
                b.iter(|| one_thread.install(|| AabbTree::build_set(black_box(triangles.clone()), &config).unwrap()))
            });
            group.bench_function(BenchmarkId::new(format!("proxima-{label}-all-threads"), name), |b| {
                b.iter(|| AabbTree::build_set(black_box(triangles.clone()), &config).unwrap())
            });
        }
        group.bench_function(BenchmarkId::new("parry3d", name), |b| {
            b.iter(|| parry_trimesh(black_box(&mesh)))
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
            group.bench_function(id("proxima-best-first"), |b| {
                b.iter(|| {
                    points
                        .iter()
                        .map(|&p| tree.closest_best_first(p).unwrap().distance)
                        .sum::<f32>()
                })
            });
            group.bench_function(id("proxima-batch-1thread"), |b| {
                b.iter(|| one_thread.install(|| tree.closest_batch_with(&points, BatchOptions { reorder: true })))
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

criterion_group!(benches, build, closest, versus_linear, spheres_versus_boxes);
criterion_main!(benches);
