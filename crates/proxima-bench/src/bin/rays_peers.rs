//! The Rust peers of the rays benchmark: parry3d and obvhs cast a rays file
//! at a mesh on one thread; `peers/rays_peers.py` runs this beside
//! `proxima raycast`, Embree and Open3D.
//!
//! ```text
//! cargo run --release -p proxima-bench --bin rays_peers -- MESH RAYS [--rounds R]
//! ```
//!
//! `MESH` is read by proxima's loader (or named as [`load_named`] takes it),
//! `RAYS` by [`proxima::io::load_rays`] (`ox oy oz dx dy dz` per line; the
//! directions are used as given, so `t` is in units of their length, as
//! proxima's). Each peer builds its structure and casts every ray for its
//! first hit, `R` rounds (default 3), and the best build and the best cast are
//! kept (each round builds anew, so that the build timing is warm as well):
//!
//! - parry3d: [`TriMesh::new`] (its BVH) over the faces fanned into
//!   triangles; the cast is [`parry_ray`] (`cast_local_ray`, hollow, first
//!   time of impact).
//! - obvhs: the compressed wide BVH (CWBVH, 8-wide) from
//!   `build_cwbvh_from_tris` with `BvhBuildParams::medium_build()` (PLOC with
//!   reinsertion, no pre-splits), the preset of its README example, "around
//!   the same build time as Embree but with faster traversal"; the triangles
//!   are then laid out in the tree's primitive order, as its `obj_cwbvh`
//!   example does (part of the build time). The cast is
//!   `CwBvh::ray_traverse` with obvhs' own `Triangle::intersect`
//!   (Möller–Trumbore). Built without obvhs' `parallel` feature: one thread.
//!
//! Building the peers' input (parry3d's vertex and index arrays, obvhs'
//! triangles) is left out of the build time, as `compare` leaves it out.
//!
//! Output, one JSON line per peer on stdout:
//! `{"peer":"parry3d","rays":N,"seconds":S,"rays_per_second":R,"build_seconds":B,"t":[...]}`
//! where `t` holds the hit distance of each ray in input order, `null` for a
//! miss.

use obvhs::BvhBuildParams;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::ray::RayHit;
use parry3d::shape::TriMesh;
use proxima::{Mesh, Vec3A};
use proxima_bench::{Ray, load_named, parry_input, parry_ray};
use std::fmt::Write as _;
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// Runs `f`, returning its value and its time in seconds.
fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let start = Instant::now();
    let v = f();
    (v, start.elapsed().as_secs_f64())
}

/// One peer's measurements: best build and cast times over the rounds, and
/// the first-hit distance of each ray (`None` for a miss).
struct Measured {
    build_seconds: f64,
    seconds: f64,
    t: Vec<Option<f32>>,
}

impl Measured {
    fn new() -> Self {
        Self {
            build_seconds: f64::INFINITY,
            seconds: f64::INFINITY,
            t: Vec::new(),
        }
    }

    /// Keeps the better of each time and the latest answers.
    fn keep(&mut self, build_seconds: f64, seconds: f64, t: Vec<Option<f32>>) {
        self.build_seconds = self.build_seconds.min(build_seconds);
        self.seconds = self.seconds.min(seconds);
        self.t = t;
    }

    /// The JSON line of `peer`.
    fn json(&self, peer: &str) -> String {
        let n = self.t.len();
        let mut line = format!(
            "{{\"peer\":\"{peer}\",\"rays\":{n},\"seconds\":{},\"rays_per_second\":{},\"build_seconds\":{},\"t\":[",
            self.seconds,
            n as f64 / self.seconds,
            self.build_seconds
        );
        for (i, t) in self.t.iter().enumerate() {
            if i > 0 {
                line.push(',');
            }
            match t {
                // `{}` on an f32 prints the shortest decimal that reads back
                // to the same f32.
                Some(t) => write!(line, "{t}").expect("writing to a String"),
                None => line.push_str("null"),
            }
        }
        line.push_str("]}");
        line
    }
}

/// parry3d: build its `TriMesh`, cast every ray, `rounds` times.
fn parry(mesh: &Mesh, rays: &[Ray], rounds: usize) -> Result<Measured, String> {
    let mut measured = Measured::new();
    for _ in 0..rounds {
        let (vertices, indices) = parry_input(mesh);
        let (trimesh, build) = timed(|| TriMesh::new(vertices, indices));
        let trimesh = trimesh.map_err(|e| format!("parry3d refuses the mesh: {e}"))?;
        let (t, cast) = timed(|| rays.iter().map(|&ray| parry_ray(&trimesh, ray)).collect());
        measured.keep(build, cast, t);
    }
    Ok(measured)
}

/// obvhs: build its CWBVH, lay the triangles out in its order, cast every
/// ray for the closest hit, `rounds` times.
fn obvhs(mesh: &Mesh, rays: &[Ray], rounds: usize) -> Measured {
    let positions = mesh.positions();
    let mut triangles = Vec::with_capacity(mesh.triangle_count());
    for face in mesh.faces() {
        for w in face[1..].windows(2) {
            triangles.push(obvhs::triangle::Triangle {
                v0: Vec3A::from(positions[face[0] as usize]),
                v1: Vec3A::from(positions[w[0] as usize]),
                v2: Vec3A::from(positions[w[1] as usize]),
            });
        }
    }
    let rays: Vec<obvhs::ray::Ray> = rays
        .iter()
        .map(|&(origin, direction)| obvhs::ray::Ray::new_inf(origin.into(), direction.into()))
        .collect();
    let mut measured = Measured::new();
    for _ in 0..rounds {
        let ((bvh, ordered), build) = timed(|| {
            let bvh = build_cwbvh_from_tris(&triangles, BvhBuildParams::medium_build(), &mut Duration::default());
            let ordered: Vec<_> = bvh.primitive_indices.iter().map(|&i| triangles[i as usize]).collect();
            (bvh, ordered)
        });
        let (t, cast) = timed(|| {
            rays.iter()
                .map(|&ray| {
                    let mut hit = RayHit::none();
                    bvh.ray_traverse(ray, &mut hit, |ray, id| ordered[id].intersect(ray))
                        .then_some(hit.t)
                })
                .collect()
        });
        measured.keep(build, cast, t);
    }
    measured
}

fn main() -> ExitCode {
    let mut positional = Vec::new();
    let mut rounds = 3;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--rounds" => match args.next().and_then(|v| v.parse().ok()) {
                Some(r) if r >= 1 => rounds = r,
                _ => {
                    eprintln!("rays_peers: --rounds takes a whole number of at least 1");
                    return ExitCode::from(2);
                }
            },
            _ => positional.push(a),
        }
    }
    let [mesh_name, rays_path] = positional.as_slice() else {
        eprintln!("usage: rays_peers MESH RAYS [--rounds R]");
        return ExitCode::from(2);
    };
    let mesh = match load_named(mesh_name) {
        Ok(mesh) => mesh,
        Err(e) => {
            eprintln!("rays_peers: {e}");
            return ExitCode::FAILURE;
        }
    };
    let rays = match proxima::io::load_rays(rays_path, &Default::default()) {
        Ok(rays) => rays,
        Err(e) => {
            eprintln!("rays_peers: {e}");
            return ExitCode::FAILURE;
        }
    };
    match parry(&mesh, &rays, rounds) {
        Ok(measured) => println!("{}", measured.json("parry3d")),
        Err(e) => {
            eprintln!("rays_peers: {e}");
            return ExitCode::FAILURE;
        }
    }
    println!("{}", obvhs(&mesh, &rays, rounds).json("obvhs"));
    ExitCode::SUCCESS
}
