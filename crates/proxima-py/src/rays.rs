//! `Mesh.cast_rays`: rays from numpy arrays, cast on the ray tree.

use crate::arrays::{self, Check, Points, value_error};
use proxima::prelude::*;
use pyo3::prelude::*;
use rayon::prelude::*;

/// The origins and directions of `cast_rays`, checked: both (N, 3), finite,
/// origins within the trees' range.
pub fn ray_arrays<'py>(
    origins: &Bound<'py, PyAny>,
    directions: &Bound<'py, PyAny>,
) -> PyResult<(Points<'py>, Points<'py>)> {
    let origins = arrays::points(origins, "origins", Check::QueryPoint)?;
    let directions = arrays::points(directions, "directions", Check::Finite)?;
    let (n, m) = (origins.as_slice().len(), directions.as_slice().len());
    if n != m {
        return Err(value_error("directions", format!("{m} directions for {n} origins")));
    }
    if let Some(row) = directions.as_slice().iter().position(|d| *d == Vec3::ZERO) {
        return Err(value_error(&format!("directions[{row}]"), "the direction is zero"));
    }
    Ok((origins, directions))
}

/// The rays, each direction normalized (in `f64`, then rounded) so that a
/// hit's `t` is a distance; on the current pool (the conversion is a
/// noticeable part of a batch on several threads).
pub fn rays(origins: &[Vec3], directions: &[Vec3]) -> Vec<(Vec3, Vec3)> {
    origins
        .par_iter()
        .zip(directions)
        .with_min_len(4096)
        .map(|(&o, &d)| {
            let d = d.as_dvec3();
            (o, (d / d.length()).as_vec3())
        })
        .collect()
}

/// The hit of each ray: the first, or with `any_hit` some hit.
pub fn cast(tree: &RayTree, rays: &[(Vec3, Vec3)], any_hit: bool) -> PyResult<Vec<Option<RayHit>>> {
    let hits = if any_hit {
        tree.some_hit_batch(rays, 0.0, f32::INFINITY)
    } else {
        tree.first_hit_batch(rays, 0.0, f32::INFINITY)
    };
    if let Some((row, Err(e))) = hits.iter().enumerate().find(|(_, hit)| hit.is_err()) {
        return Err(value_error(&format!("rays[{row}]"), e));
    }
    Ok(hits.into_iter().map(|hit| hit.ok().flatten()).collect())
}

/// The hit distance and face of each ray (`inf` and -1 for a miss).
pub fn columns(hits: &[Option<RayHit>]) -> (Vec<f64>, Vec<i64>) {
    hits.par_iter()
        .with_min_len(4096)
        .map(|hit| match hit {
            Some(hit) => (hit.t as f64, hit.source as i64),
            None => (f64::INFINITY, -1),
        })
        .unzip()
}
