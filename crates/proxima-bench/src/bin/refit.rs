//! A mesh that moves: refitting every structure against building it
//! anew, and the queries' speed after the refit against a fresh build's,
//! measured in one run.
//!
//! ```text
//! cargo run --release -p proxima-bench --bin refit -- MESH [--threads T] [--rounds R] [--queries N] [--amplitude A]
//! ```
//!
//! `MESH` as [`load_named`] takes it (a file, `ico1m`, `ico100k`). On a
//! pool of `T` threads (default 1): the structures of a mesh index that
//! answer closest points, signed distances and rays (the faces' 4-wide
//! tree, the winding-number and pseudonormal fields on it, the 8-wide ray
//! tree) built over the moved mesh, against `update_vertices` refitting
//! them (policy `Refit`) from the previous positions; then each piece alone.
//! The motion is a wave of amplitude `A` (default 0.01) times the box
//! diagonal, alternating with the rest pose so that every round moves the
//! vertices. Then `N` (default 100,000) closest-point queries near the
//! surface and `N` rays, on the refit index and on a fresh one, after the
//! wave and after a swirl of half a turn (refit, then with the default
//! policy's rebuild). Rounds alternate between variants; the best of `R`
//! (default 5) is kept. Prints one markdown table. With `--updates K`,
//! only `K` updates of the index, each timed (for a profiler).

use proxima::index::{IndexConfig, MeshIndex, RefitPolicy};
use proxima::prelude::*;
use proxima::sdf::{Pseudonormals, Sign, WindingNumbers};
use proxima::{RayTree, WideTree};
use proxima_bench::load_named;
use proxima_bench::timing::{flag_value, timed};

/// The wave: every vertex moved along y by `amplitude` × diagonal × a
/// sine of its x.
fn wave(mesh: &Mesh, amplitude: f32) -> Vec<Vec3> {
    let b = mesh.bounds();
    let d = b.diagonal();
    mesh.positions()
        .iter()
        .map(|p| *p + Vec3::Y * amplitude * d * (8.0 * (p.x - b.min.x) / d).sin())
        .collect()
}

/// Half a turn about the vertical axis from bottom to top: the boxes of a
/// tree built for the rest pose then overlap everywhere.
fn swirl(mesh: &Mesh) -> Vec<Vec3> {
    let b = mesh.bounds();
    let c = b.center();
    mesh.positions()
        .iter()
        .map(|p| {
            let t = (p.z - b.min.z) / (b.max.z - b.min.z).max(1e-6);
            let (s, co) = (std::f32::consts::PI * t).sin_cos();
            let q = *p - c;
            c + Vec3::new(co * q.x - s * q.y, s * q.x + co * q.y, q.z)
        })
        .collect()
}

/// Builds what the per-frame loop needs: closest points, both fields, rays.
fn build_all(index: &MeshIndex) {
    index.tree::<Triangle>().unwrap();
    index.field(Sign::WindingNumber).unwrap();
    index.field(Sign::Pseudonormal).unwrap();
    index.ray_tree().unwrap();
}

/// Best of `rounds` of each variant, alternating; seconds.
fn best(rounds: usize, variants: &mut [&mut dyn FnMut() -> f64]) -> Vec<f64> {
    let mut out = vec![f64::INFINITY; variants.len()];
    for _ in 0..rounds {
        for (k, v) in variants.iter_mut().enumerate() {
            out[k] = out[k].min(v());
        }
    }
    out
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args.first().expect("MESH").clone();
    let threads = flag_value(&args, "--threads", 1.0) as usize;
    let rounds = flag_value(&args, "--rounds", 5.0) as usize;
    let queries = flag_value(&args, "--queries", 100_000.0) as usize;
    let amplitude = flag_value(&args, "--amplitude", 0.01) as f32;
    let mesh = load_named(&name).expect("mesh");
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        let rest = mesh.positions().to_vec();
        let waved = wave(&mesh, amplitude);
        let mut moved = mesh.clone();
        moved.set_positions(&waved).unwrap();
        println!(
            "{name}: {} triangles, {threads} thread(s), wave {amplitude} × diagonal, best of {rounds}\n",
            mesh.triangle_count()
        );
        println!("| step | build (s) | refit (s) | build / refit |\n|---|---|---|---|");
        // Everything, through the index.
        let refit_config = IndexConfig {
            refit: RefitPolicy::Refit,
            ..Default::default()
        };
        let mut index = MeshIndex::with_config(mesh.clone(), refit_config.clone());
        build_all(&index);
        // `--updates K`: only K updates of the index, for a profiler.
        let updates = flag_value(&args, "--updates", 0.0) as usize;
        if updates > 0 {
            for k in 0..updates {
                let to = if k % 2 == 0 { &waved } else { &rest };
                let seconds = timed(|| drop(index.update_vertices(to).unwrap()));
                println!("update {k}: {seconds:.4} s");
            }
            return;
        }
        let mut flip = false;
        let [build, refit] = best(
            rounds,
            &mut [&mut || timed(|| build_all(&MeshIndex::new(moved.clone()))), &mut || {
                flip = !flip;
                let to = if flip { &waved } else { &rest };
                timed(|| {
                    index.update_vertices(to).unwrap();
                })
            }],
        )[..] else {
            unreachable!()
        };
        println!(
            "| all four structures | {build:.4} | {refit:.4} | {:.1} |",
            build / refit
        );
        // Piece by piece.
        let (set, moved_set) = (mesh.triangles(), moved.triangles());
        let mut wide = WideTree::build_set(set.clone(), &Default::default()).unwrap();
        let mut flip = false;
        let r = best(
            rounds,
            &mut [
                &mut || timed(|| drop(WideTree::build_set(moved_set.clone(), &Default::default()).unwrap())),
                &mut || {
                    flip = !flip;
                    let to = if flip { &moved_set } else { &set };
                    timed(|| wide.refit(to).unwrap())
                },
            ],
        );
        println!(
            "| faces' 4-wide tree | {:.4} | {:.4} | {:.1} |",
            r[0],
            r[1],
            r[0] / r[1]
        );
        let mut rays = RayTree::build(&mesh).unwrap();
        let mut flip = false;
        let r = best(
            rounds,
            &mut [&mut || timed(|| drop(RayTree::build(&moved).unwrap())), &mut || {
                flip = !flip;
                let to = if flip { &moved_set } else { &set };
                timed(|| rays.refit(to).unwrap())
            }],
        );
        println!("| 8-wide ray tree | {:.4} | {:.4} | {:.1} |", r[0], r[1], r[0] / r[1]);
        let tree = WideTree::build_set(moved_set.clone(), &Default::default()).unwrap();
        let r = best(
            rounds,
            &mut [
                &mut || timed(|| drop(WindingNumbers::new(&tree, proxima::sdf::DEFAULT_BETA))),
                &mut || timed(|| drop(Pseudonormals::new(&moved))),
            ],
        );
        println!("| winding expansions (computed either way) | {:.4} | | |", r[0]);
        println!("| pseudonormals (computed either way) | {:.4} | | |", r[1]);

        // Queries after the wave, and after a swirl.
        println!("\n| queries ({queries} each) | refit (s) | fresh build (s) | refit / fresh |\n|---|---|---|---|");
        let run_queries = |label: &str, positions: &[Vec3], policy: RefitPolicy| {
            let mut index = MeshIndex::with_config(
                mesh.clone(),
                IndexConfig {
                    refit: policy,
                    ..Default::default()
                },
            );
            build_all(&index);
            let updated = index.update_vertices(positions).unwrap();
            let faces = updated.iter().find(|u| u.structure == "faces").unwrap();
            let fresh = MeshIndex::new(index.mesh().clone());
            build_all(&fresh);
            let points = proxima::sample::near_surface(index.mesh(), queries, 0.01, 7);
            let ray_set = proxima::sample::rays_at_box(&index.mesh().bounds(), queries, 8);
            let closest = |ix: &MeshIndex| timed(|| drop(ix.closest(PrimitiveKind::Faces, &points).unwrap()));
            let cast =
                |ix: &MeshIndex| timed(|| drop(ix.ray_tree().unwrap().first_hit_batch(&ray_set, 0.0, f32::INFINITY)));
            assert_eq!(
                index.closest(PrimitiveKind::Faces, &points),
                fresh.closest(PrimitiveKind::Faces, &points)
            );
            let r = best(
                rounds,
                &mut [
                    &mut || closest(&index),
                    &mut || closest(&fresh),
                    &mut || cast(&index),
                    &mut || cast(&fresh),
                ],
            );
            let what = if faces.rebuilt { "rebuilt" } else { "refit" };
            println!(
                "| {label}, closest ({what}, cost ratio {:.2}) | {:.4} | {:.4} | {:.2} |",
                faces.cost_ratio,
                r[0],
                r[1],
                r[0] / r[1]
            );
            println!("| {label}, rays | {:.4} | {:.4} | {:.2} |", r[2], r[3], r[2] / r[3]);
        };
        run_queries("wave", &waved, RefitPolicy::Refit);
        let swirled = swirl(&mesh);
        run_queries("swirl", &swirled, RefitPolicy::Refit);
        run_queries("swirl", &swirled, RefitPolicy::default());
    });
}
