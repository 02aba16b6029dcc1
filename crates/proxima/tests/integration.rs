//! Every integration test of the library in one test binary: each file of
//! this folder is a module (`cargo test -p proxima --test integration
//! sdf::` runs one file's tests). One binary instead of one per file
//! compiles the library's generic structures once, not once per file, and
//! links once: the largest part of a clean test build.

#[path = "../../../fuzz/bodies.rs"]
mod bodies;
mod common;
#[path = "pair_oracle/mod.rs"]
mod pair_oracle;
#[path = "common/wide_shape.rs"]
mod wide_shape;

mod bvh;
mod degenerate;
mod draco;
mod errors;
mod frustum;
mod fuzz_smoke;
mod glb;
mod grid;
mod hausdorff;
mod index;
mod io;
mod lattice;
mod limits;
mod overlap;
mod pair;
mod parry;
mod points;
mod polygons;
mod pose;
mod primitives;
mod ray;
mod refit;
mod scene;
mod sdf;
mod sdf_certificate;
mod sphere_tree;
mod structures;
mod surface;
mod traversal;
mod triangle_pairs;
mod wide;
