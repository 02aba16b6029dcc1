//! Differential test against parry3d's point projection on triangle meshes:
//! distances agree within 1e-5 of the bounding-box diagonal.

use crate::common::{bumpy_sphere, queries, random_soup, shared_meshes};
use parry3d::query::PointQuery;
use parry3d::shape::TriMesh;
use proxima::prelude::*;
use proxima::{AabbTree, BuildConfig, Mesh};

fn parry_mesh(mesh: &Mesh) -> TriMesh {
    let mut indices = Vec::new();
    for face in mesh.faces() {
        for w in face[1..].windows(2) {
            indices.push([face[0], w[0], w[1]]);
        }
    }
    TriMesh::new(mesh.positions().to_vec(), indices).expect("parry3d accepts the mesh")
}

fn agree(name: &str, mesh: &Mesh, n: usize) {
    let tree = AabbTree::build_set(mesh.triangles(), &BuildConfig::default()).unwrap();
    let parry = parry_mesh(mesh);
    let tolerance = 1e-5 * mesh.bounds().diagonal();
    let mut worst = 0f32;
    for p in queries(mesh, n, 5) {
        let ours = tree.closest(p).unwrap();
        let projection = parry.project_local_point(p, false);
        let theirs = (projection.point - p).length();
        worst = worst.max((ours.distance - theirs).abs());
        assert!(
            (ours.distance - theirs).abs() <= tolerance,
            "{name}: at {p} proxima says {} (face {}), parry3d says {theirs}",
            ours.distance,
            ours.source
        );
    }
    println!(
        "{name}: worst difference {:.2e} of the diagonal",
        worst / mesh.bounds().diagonal()
    );
}

#[test]
fn generated_meshes_agree_with_parry3d() {
    agree("bumpy sphere", &bumpy_sphere(20, 9), 300);
    agree("random soup", &random_soup(500, 4), 300);
}

#[test]
fn real_meshes_agree_with_parry3d() {
    for path in shared_meshes() {
        let mesh = proxima::io::load(&path).unwrap();
        agree(&path.display().to_string(), &mesh, 300);
    }
}
