//! Writes a self-intersecting mesh as OBJ: two closed, outward-oriented
//! spheres of radius about 1 whose centres are one radius apart, so each
//! crosses the other. The winding number is 2 in the overlap and 1 in the
//! rest of their union; pseudonormals call the part of one sphere that lies
//! near the other's buried surface outside. `scripts/sdf-pictures.sh` renders
//! it for docs/sdf.md.
//!
//! ```text
//! cargo run --release -p proxima-viewer --example overlapping_spheres -- OUT.obj
//! ```

use proxima::Vec3;
use proxima::mesh::generate::noisy_icosphere;
use std::fmt::Write as _;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args_os().nth(1).ok_or("usage: overlapping_spheres OUT.obj")?;
    let mut obj = String::from("# two overlapping closed spheres (proxima-viewer example overlapping_spheres)\n");
    let mut first_vertex = 1;
    for (seed, shift) in [(1, Vec3::new(-0.5, 0.0, 0.0)), (2, Vec3::new(0.5, 0.0, 0.0))] {
        let sphere = noisy_icosphere(12, seed);
        for p in sphere.positions() {
            let p = *p + shift;
            writeln!(obj, "v {} {} {}", p.x, p.y, p.z)?;
        }
        for f in 0..sphere.face_count() {
            obj.push('f');
            for &v in sphere.face(f) {
                write!(obj, " {}", v as usize + first_vertex)?;
            }
            obj.push('\n');
        }
        first_vertex += sphere.vertex_count();
    }
    std::fs::write(&path, obj)?;
    Ok(())
}
