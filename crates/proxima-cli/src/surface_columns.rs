//! The CSV columns of `--attributes` (`closest`, `raycast --rays`): where an
//! answer lies on the surface, written once for both commands.

use proxima::surface::{Feature, SurfacePoint};
use proxima::{Mesh, Vec3};
use std::io::Write;

/// The header of the columns, each after a comma.
pub const HEADER: &str = ",triangle,u,v,feature,fa,fb,nx,ny,nz,fnx,fny,fnz,tu,tv";

/// The columns of an answer without a surface point (a missed ray).
pub const EMPTY: &str = ",,,,,,,,,,,,,,";

/// What the columns read: a mesh and its vertex normals.
pub struct SurfaceColumns<'a> {
    /// The mesh the answers are on.
    pub mesh: &'a Mesh,
    /// Its vertex normals ([`proxima::surface::vertex_normals`]).
    pub normals: &'a [Vec3],
}

impl SurfaceColumns<'_> {
    /// Writes `at`'s columns: the fan triangle, the barycentric weights u, v
    /// of its second and third corners, the feature (`face`, `edge` or
    /// `vertex`) and its vertices (empty where it has fewer than two), the
    /// interpolated shading normal (the file's corner normals, else the
    /// vertex normals), the triangle's unit normal, and the interpolated
    /// texture coordinates (empty when the mesh has none).
    pub fn write(&self, text: &mut Vec<u8>, at: &SurfacePoint) -> std::io::Result<()> {
        let [_, u, v] = at.barycentric;
        let n = at.interpolated_normal(self.mesh, self.normals);
        let f = at.face_normal(self.mesh);
        let feature = match at.feature {
            Feature::Face => "face",
            Feature::Edge(_) => "edge",
            Feature::Vertex(_) => "vertex",
        };
        let vertex = |v: u32| if v == u32::MAX { String::new() } else { v.to_string() };
        let [a, b] = at.feature.vertices().map(vertex);
        write!(
            text,
            ",{},{u},{v},{feature},{a},{b},{},{},{},{},{},{}",
            at.triangle, n.x, n.y, n.z, f.x, f.y, f.z
        )?;
        match at.uv(self.mesh) {
            Some([tu, tv]) => write!(text, ",{tu},{tv}"),
            None => write!(text, ",,"),
        }
    }
}
