//! A scene of rigid instances against the same triangles merged into one
//! mesh, and the cost of moving an instance, measured in one run.
//!
//! ```text
//! cargo run --release -p proxima-bench --bin scene -- [--instances N] [--meshes M] [--queries Q] [--rounds R] [--threads T]
//! ```
//!
//! `M` (default 10) bumpy spheres of 320 to 5,120 triangles, placed `N`
//! (default 1,000) times by seeded random rigid poses in a cube of side
//! 10·∛N (about one sphere diameter apart on average). `Q` (default
//! 100,000) closest-point queries near the placed surfaces and `Q` rays
//! from the cube's sides through it, on a pool of `T` threads (default 1);
//! the merged mesh's index answers the same queries (the merged triangles
//! placed in `f64`, rounded to `f32`). Then `set_pose` on random instances,
//! 10,000 times. Rounds alternate; the best of `R` (default 5) is kept.

use proxima::index::MeshIndex;
use proxima::pair::RigidPose;
use proxima::prelude::*;
use proxima::sample::Rng;
use proxima::scene::Scene;
use proxima_bench::timing::{flag_value, timed};
use std::sync::Arc;

fn pose(rng: &mut Rng, spread: f32) -> RigidPose {
    let q = [rng.gaussian(), rng.gaussian(), rng.gaussian(), rng.gaussian()];
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    RigidPose::from_quaternion(q.map(|x| x / n), [0, 1, 2].map(|_| rng.range(-spread, spread) as f64)).unwrap()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let count = flag_value(&args, "--instances", 1000.0) as usize;
    let kinds = flag_value(&args, "--meshes", 10.0) as usize;
    let queries = flag_value(&args, "--queries", 100_000.0) as usize;
    let rounds = flag_value(&args, "--rounds", 5.0) as usize;
    let threads = flag_value(&args, "--threads", 1.0) as usize;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        let meshes: Vec<Arc<MeshIndex>> = (0..kinds)
            .map(|k| Arc::new(MeshIndex::new(proxima::mesh::generate::noisy_icosphere(4 + (k as u32 * 12) / kinds as u32, k as u64))))
            .collect();
        let mut rng = Rng::new(1);
        let spread = 5.0 * (count as f32).cbrt();
        let instances: Vec<(Arc<MeshIndex>, RigidPose)> = (0..count).map(|k| (meshes[k % kinds].clone(), pose(&mut rng, spread))).collect();
        // The merged mesh: every placed triangle.
        let (mut positions, mut faces) = (Vec::new(), Vec::new());
        for (mesh, pose) in &instances {
            let base = positions.len() as u32;
            positions.extend(mesh.mesh().positions().iter().map(|p| pose.apply(*p).as_vec3()));
            faces.extend(mesh.mesh().triangle_vertex_indices().iter().map(|t| t.map(|v| v + base)));
        }
        let merged = MeshIndex::new(Mesh::from_triangles(positions, &faces).unwrap());
        let build_scene = timed(|| drop(Scene::new(instances.clone()).unwrap()));
        let mut scene = Scene::new(instances.clone()).unwrap();
        for m in &meshes {
            m.tree::<Triangle>().unwrap();
            m.ray_tree().unwrap();
        }
        merged.tree::<Triangle>().unwrap();
        merged.ray_tree().unwrap();
        let points = proxima::sample::near_surface(merged.mesh(), queries, 0.002, 2);
        let rays = proxima::sample::rays_at_box(&merged.mesh().bounds(), queries, 3);
        let (mut best, mut best_merged, mut best_rays, mut best_rays_merged) =
            (f64::INFINITY, f64::INFINITY, f64::INFINITY, f64::INFINITY);
        let (mut one, mut one_merged) = (f64::INFINITY, f64::INFINITY);
        for _ in 0..rounds {
            best = best.min(timed(|| drop(scene.closest_batch(&points))));
            best_merged = best_merged.min(timed(|| drop(merged.closest(PrimitiveKind::Faces, &points).unwrap())));
            best_rays = best_rays.min(timed(|| drop(scene.first_hit_batch(&rays, 0.0, f32::INFINITY))));
            best_rays_merged = best_rays_merged.min(timed(|| drop(merged.ray_tree().unwrap().first_hit_batch(&rays, 0.0, f32::INFINITY))));
            // One ray at a time, in input order: the merged tree's batch
            // sorts rays by Morton code and interleaves their walks, which
            // the scene's batch does not (yet).
            one = one.min(timed(|| {
                for &(o, d) in &rays {
                    std::hint::black_box(scene.first_hit(o, d, 0.0, f32::INFINITY).unwrap());
                }
            }));
            let tree = merged.ray_tree().unwrap();
            one_merged = one_merged.min(timed(|| {
                for &(o, d) in &rays {
                    std::hint::black_box(tree.first_hit(o, d, 0.0, f32::INFINITY).unwrap());
                }
            }));
        }
        let hits = scene.first_hit_batch(&rays, 0.0, f32::INFINITY).iter().filter(|h| matches!(h, Ok(Some(_)))).count();
        // Small moves (each instance nudged by up to 1% of the cube), then
        // teleports anywhere in the cube, which wear the top level until
        // the policy rebuilds it.
        let moves = 10_000;
        let nudges: Vec<(usize, RigidPose)> = (0..moves)
            .map(|_| {
                let i = rng.below(count);
                let step = RigidPose::translation_only(proxima::DVec3::new(
                    rng.range(-0.01, 0.01) as f64 * spread as f64,
                    rng.range(-0.01, 0.01) as f64 * spread as f64,
                    rng.range(-0.01, 0.01) as f64 * spread as f64,
                ))
                .unwrap();
                (i, step)
            })
            .collect();
        let nudge = timed(|| {
            for (i, step) in &nudges {
                let moved = scene.instances()[*i].pose().then(step);
                scene.set_pose(*i, moved).unwrap();
            }
        });
        let new_poses: Vec<(usize, RigidPose)> = (0..moves).map(|_| (rng.below(count), pose(&mut rng, spread))).collect();
        let set = timed(|| {
            for (i, p) in &new_poses {
                scene.set_pose(*i, *p).unwrap();
            }
        });
        println!(
            "{count} instances of {kinds} meshes ({} triangles placed), {threads} thread(s), best of {rounds}, {queries} queries ({hits} rays hit)\n",
            merged.mesh().triangle_count()
        );
        println!("| | scene (s) | merged mesh (s) | scene / merged |\n|---|---|---|---|");
        println!("| closest points | {best:.4} | {best_merged:.4} | {:.2} |", best / best_merged);
        println!("| first hits, batch | {best_rays:.4} | {best_rays_merged:.4} | {:.2} |", best_rays / best_rays_merged);
        println!("| first hits, one at a time | {one:.4} | {one_merged:.4} | {:.2} |", one / one_merged);
        println!(
            "\nscene build (top level and hulls): {:.1} µs; set_pose: {:.2} µs each nudging, {:.2} µs teleporting (means of {moves})",
            build_scene * 1e6,
            nudge / moves as f64 * 1e6,
            set / moves as f64 * 1e6
        );
    });
}
