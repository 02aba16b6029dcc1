//! The Hausdorff distance between two meshes' surfaces: the time to bring
//! its bounds within a tolerance, and the work it took.
//!
//! ```text
//! cargo run --release -p proxima-bench --bin hausdorff -- A B [--tolerance T] [--threads N] [--rounds R]
//! ```
//!
//! `A` and `B` as [`load_named`] takes them. `T` (default 1e-4) is a
//! fraction of the larger bounding-box diagonal. On a pool of `N` threads
//! (default 1), after both faces' trees are built (timed apart), the
//! symmetric distance is computed `R` times (default 3) and the fastest is
//! kept. Prints one line per direction and one for the total.

use proxima::MeshIndex;
use proxima::Triangle;
use proxima::pair::hausdorff;
use proxima_bench::load_named;
use proxima_bench::timing::{flag_value, timed};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (a, b) = (load_named(&args[1]).unwrap(), load_named(&args[2]).unwrap());
    let relative = flag_value(&args, "--tolerance", 1e-4);
    let threads = flag_value(&args, "--threads", 1.0) as usize;
    let rounds = flag_value(&args, "--rounds", 3.0) as usize;
    let diagonal = f64::from(a.bounds().diagonal().max(b.bounds().diagonal()));
    let tolerance = relative * diagonal;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    let (a, b) = (MeshIndex::new(a), MeshIndex::new(b));
    let build = timed(|| {
        pool.install(|| {
            a.tree::<Triangle>().unwrap();
            b.tree::<Triangle>().unwrap();
        })
    });
    let mut best = f64::INFINITY;
    let mut answer = None;
    for _ in 0..rounds {
        let seconds = timed(|| answer = Some(pool.install(|| hausdorff(&a, &b, tolerance).unwrap())));
        best = best.min(seconds);
    }
    let h = answer.unwrap();
    println!(
        "{} ({} triangles) vs {} ({} triangles), tolerance {relative:e} x diagonal {diagonal:.6} = {tolerance:e}, {threads} thread(s)",
        args[1],
        a.mesh().triangle_count(),
        args[2],
        b.mesh().triangle_count()
    );
    println!("trees built: {build:.3} s");
    for (name, d) in [("a -> b", h.forward), ("b -> a", h.backward)] {
        println!(
            "{name}: lower {:.9} upper {:.9} (gap {:.2e} = {:.3} tolerance), pieces {}, unsettled {}, point {:?} face {}",
            d.lower,
            d.upper,
            d.upper - d.lower,
            (d.upper - d.lower) / tolerance,
            d.pieces,
            d.unsettled,
            d.point.to_array(),
            d.face
        );
    }
    println!(
        "symmetric: [{:.9}, {:.9}], best of {rounds}: {best:.3} s",
        h.lower(),
        h.upper()
    );
}
