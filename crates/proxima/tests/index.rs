//! The mesh index: every query by a kind chosen at run time equals brute
//! force over that kind's primitives, structures are built on first use
//! only, once, and meshes without the kind asked are refused.

use proxima::frustum::Frustum;
use proxima::index::{IndexError, MeshIndex, check_not_empty};
use proxima::prelude::*;
use proxima::sample::Rng;
use std::collections::BTreeMap;

/// A grid of `n` × `n` quads (some split in two triangles by the fan),
/// lifted by a bump so that it is not planar, and a few triangles: faces
/// of several parts next to faces of one.
fn quads_and_triangles(n: u32) -> Mesh {
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f32 / n as f32, j as f32 / n as f32);
            positions.push(Vec3::new(x, y, 0.2 * (3.0 * x).sin() * (2.0 * y).cos()));
        }
    }
    let at = |i: u32, j: u32| j * (n + 1) + i;
    let mut faces = Vec::new();
    for j in 0..n {
        for i in 0..n {
            if (i + j) % 3 == 0 {
                faces.push(vec![at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                faces.push(vec![at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            } else {
                faces.push(vec![at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
    }
    Mesh::from_faces(positions, &faces).unwrap()
}

fn queries(n: usize, seed: u64) -> Vec<Vec3> {
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|_| Vec3::new(rng.range(-0.3, 1.3), rng.range(-0.3, 1.3), rng.range(-0.5, 0.5)))
        .collect()
}

/// The `k` nearest sources by brute force: each source at its nearest
/// part's distance, sorted by (squared distance, part index).
fn brute_k_nearest_sources<T: MeshPrimitive>(set: &PrimitiveSet<T>, p: Vec3, k: usize) -> Vec<(u32, f32)> {
    let mut best: BTreeMap<u32, (f32, usize)> = BTreeMap::new();
    for (i, (primitive, &source)) in set.primitives.iter().zip(&set.sources).enumerate() {
        // Squared, as the structures compare them (equal roots may hide unequal squares).
        let d = (primitive.closest_point(p.into()) - Vec3A::from(p)).length_squared();
        let entry = best.entry(source).or_insert((d, i));
        if d < entry.0 {
            *entry = (d, i);
        }
    }
    let mut sorted: Vec<(u32, f32, usize)> = best.into_iter().map(|(s, (d, i))| (s, d, i)).collect();
    sorted.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.2.cmp(&b.2)));
    sorted.into_iter().take(k).map(|(s, d, _)| (s, d.sqrt())).collect()
}

struct Check<'a> {
    index: &'a MeshIndex,
    points: &'a [Vec3],
}

impl proxima::kind::KindGeneric for Check<'_> {
    type Output = ();
    fn call<T: MeshPrimitive>(self) {
        let kind = T::KIND;
        let set = T::extract(self.index.mesh(), self.index.config().planarity);
        let linear = LinearSearch::new(set.clone());
        let closest = self.index.closest(kind, self.points).unwrap();
        for (p, hit) in self.points.iter().zip(&closest) {
            assert_eq!(*hit, linear.closest(*p), "{kind} closest at {p}");
        }
        for k in [1, 2, 5] {
            let answers = self.index.k_nearest(kind, self.points, k).unwrap();
            let mut chunked = Vec::new();
            self.index
                .k_nearest_chunks::<IndexError>(kind, self.points, k, |chunk| {
                    chunked.extend((0..chunk.len()).map(|i| chunk.hits(i).to_vec()));
                    Ok(())
                })
                .unwrap();
            assert_eq!(chunked, answers, "{kind} k = {k}: chunks and batch");
            for (p, hits) in self.points.iter().zip(&answers) {
                let got: Vec<(u32, f32)> = hits.iter().map(|h| (h.source, h.distance)).collect();
                assert_eq!(got, brute_k_nearest_sources(&set, *p, k), "{kind} k = {k} at {p}");
            }
        }
        // A camera above the sheet that sees its middle only.
        let frustum = Frustum::look_at(
            Vec3::new(0.5, 0.4, 1.5),
            Vec3::new(0.5, 0.5, 0.0),
            Vec3::Y,
            30.0,
            1.2,
            0.1,
            10.0,
        )
        .unwrap();
        let mut expected: Vec<u32> = linear
            .frustum(&frustum)
            .iter()
            .map(|&i| set.sources[i as usize])
            .collect();
        expected.sort_unstable();
        expected.dedup();
        assert!(!expected.is_empty() && expected.len() < set.len());
        assert_eq!(self.index.frustum(kind, &frustum).unwrap(), expected, "{kind} frustum");
    }
}

#[test]
fn every_kind_answers_as_brute_force() {
    let index = MeshIndex::new(quads_and_triangles(12));
    assert!(index.built().is_empty());
    let points = queries(300, 7);
    for kind in PrimitiveKind::ALL {
        kind.dispatch(Check {
            index: &index,
            points: &points,
        });
    }
    assert_eq!(index.built(), ["vertices", "edges", "faces", "polygons"]);
}

#[test]
fn structures_are_built_on_first_use_once() {
    let index = MeshIndex::new(proxima::mesh::generate::noisy_icosphere(8, 3));
    let first = std::thread::scope(|s| {
        let a = s.spawn(|| index.shared_tree::<Triangle>().unwrap() as *const _ as usize);
        let b = s.spawn(|| index.shared_tree::<Triangle>().unwrap() as *const _ as usize);
        (a.join().unwrap(), b.join().unwrap())
    });
    assert_eq!(first.0, first.1, "two threads got two trees");
    assert_eq!(index.built(), ["faces"]);
    let field = index.field(Sign::WindingNumber).unwrap();
    let inside = field.signed_distance(Vec3::ZERO).unwrap();
    assert!(inside.distance < 0.0);
    assert_eq!(index.built(), ["faces", "winding"]);
    let rays = index.ray_tree().unwrap();
    let hit = rays
        .first_hit(Vec3::ZERO, Vec3::X, 0.0, f32::INFINITY)
        .unwrap()
        .unwrap();
    let brute = LinearSearch::new(index.mesh().triangles())
        .first_hit(Vec3::ZERO, Vec3::X, 0.0, f32::INFINITY)
        .unwrap()
        .unwrap();
    assert_eq!((hit.t, hit.source), (brute.t, brute.source));
    assert_eq!(index.built(), ["faces", "winding", "rays"]);
}

#[test]
fn kinds_the_mesh_lacks_are_refused() {
    let cloud = Mesh::from_faces(vec![Vec3::ZERO, Vec3::X], &[]).unwrap();
    let index = MeshIndex::new(cloud);
    assert_eq!(
        index.closest(PrimitiveKind::Vertices, &[Vec3::Y]).unwrap()[0]
            .unwrap()
            .source,
        0
    );
    for kind in [PrimitiveKind::Edges, PrimitiveKind::Faces, PrimitiveKind::Polygons] {
        let error = index.closest(kind, &[Vec3::Y]).unwrap_err();
        assert_eq!(
            error,
            IndexError::NoPrimitives {
                kind,
                vertices: 2,
                faces: 0
            }
        );
        assert_eq!(
            error.to_string(),
            format!("the mesh has no {kind} to search (2 vertices, 0 faces)")
        );
    }
    assert!(matches!(index.ray_tree(), Err(IndexError::NoPrimitives { .. })));
    assert!(matches!(
        index.field(Sign::Pseudonormal),
        Err(IndexError::NoPrimitives { .. })
    ));
    assert_eq!(index.built(), ["vertices"]);
    let empty = Mesh::from_faces(Vec::new(), &[]).unwrap();
    assert_eq!(check_not_empty(&empty), Err(IndexError::EmptyMesh));
    assert_eq!(check_not_empty(index.mesh()), Ok(()));
}
