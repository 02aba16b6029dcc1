//! What comes with an answer: the `return_*` options of `closest_points`
//! and `cast_rays`, the arrays they add, and `proxima.Answers`, the named
//! result that holds them.

use crate::arrays::{self, value_error};
use numpy::PyUntypedArrayMethods;
use proxima::index::MeshIndex;
use proxima::surface::SurfacePoint;
use pyo3::IntoPyObjectExt;
use pyo3::exceptions::PyAttributeError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use rayon::prelude::*;

/// The `return_*` options of a query: which surface arrays to add.
#[derive(Clone, Copy, Debug, Default)]
pub struct SurfaceOptions {
    /// `triangle`, `corners` and `barycentric`.
    pub barycentric: bool,
    /// `feature` and `feature_vertices`.
    pub feature: bool,
    /// `normal` (interpolated shading normals) and `face_normal`.
    pub normal: bool,
    /// `uv` (interpolated texture coordinates).
    pub uv: bool,
}

impl SurfaceOptions {
    /// The options of a query's `return_barycentric`, `return_feature`,
    /// `return_normal` and `return_uv`; refuses `return_uv` on a mesh
    /// without texture coordinates.
    pub fn asked(mesh: &proxima::Mesh, [barycentric, feature, normal, uv]: [bool; 4]) -> PyResult<Self> {
        if uv && mesh.corner_uvs().is_none() {
            return Err(value_error(
                "return_uv",
                "the mesh has no texture coordinates (OBJ vt with every face corner naming one, PLY u v or s t)",
            ));
        }
        Ok(Self {
            barycentric,
            feature,
            normal,
            uv,
        })
    }

    /// Whether any array is asked for (the query then returns [`Answers`]).
    pub fn any(self) -> bool {
        self.barycentric || self.feature || self.normal || self.uv
    }
}

/// One column: its values row after row, and its width.
enum Column {
    Int(Vec<i64>, usize),
    Code(Vec<i8>),
    Real(Vec<f64>, usize),
}

/// The arrays `options` asks for, of the surface points `at` (computed
/// without the GIL, each column in one pass over the answers; the normals
/// on all cores of the current pool): named, ready for [`Answers`].
pub struct SurfaceColumns {
    columns: Vec<(&'static str, Column)>,
}

impl SurfaceColumns {
    /// The columns of `at` on `index`'s mesh; -1 and NaN for a query
    /// without an answer.
    pub fn new(index: &MeshIndex, at: &[Option<SurfacePoint>], options: SurfaceOptions) -> Self {
        let mesh = index.mesh();
        let ints = |width: usize, f: &dyn Fn(&SurfacePoint) -> [i64; 3]| {
            let mut out = Vec::with_capacity(width * at.len());
            for a in at {
                let values = a.as_ref().map_or([-1; 3], f);
                out.extend_from_slice(&values[..width]);
            }
            Column::Int(out, width)
        };
        let reals = |width: usize, f: &(dyn Fn(&SurfacePoint) -> [f64; 3] + Sync)| {
            // Written in place, row by row: no array of whole rows first.
            let mut out = vec![0.0; width * at.len()];
            out.par_chunks_mut(width)
                .zip(at.par_iter())
                .with_min_len(4096)
                .for_each(|(row, a)| row.copy_from_slice(&a.as_ref().map_or([f64::NAN; 3], f)[..width]));
            Column::Real(out, width)
        };
        let mut columns = Vec::new();
        if options.barycentric {
            columns.push(("triangle", ints(1, &|a| [i64::from(a.triangle), 0, 0])));
            columns.push(("corners", ints(3, &|a| a.corners.map(i64::from))));
            columns.push(("barycentric", reals(3, &|a| a.barycentric)));
        }
        if options.feature {
            let codes = at
                .iter()
                .map(|a| a.as_ref().map_or(-1, |a| a.feature.code() as i8))
                .collect();
            columns.push(("feature", Column::Code(codes)));
            let vertex = |v: u32| if v == u32::MAX { -1 } else { i64::from(v) };
            let vertices = move |a: &SurfacePoint| {
                let [x, y] = a.feature.vertices().map(vertex);
                [x, y, 0]
            };
            columns.push(("feature_vertices", ints(2, &vertices)));
        }
        if options.normal {
            // Not computed for a query of no points.
            let normals = if at.is_empty() { &[][..] } else { index.vertex_normals() };
            columns.push(("normal", reals(3, &|a| a.interpolated_normal(mesh, normals).to_array())));
            columns.push(("face_normal", reals(3, &|a| a.face_normal(mesh).to_array())));
        }
        if options.uv {
            let uv = |a: &SurfacePoint| a.uv(mesh).map_or([f64::NAN; 3], |[u, v]| [u, v, 0.0]);
            columns.push(("uv", reals(2, &uv)));
        }
        Self { columns }
    }

    /// No rows (a query of no points).
    pub fn empty(options: SurfaceOptions, index: &MeshIndex) -> Self {
        Self::new(index, &[], options)
    }

    /// The named arrays.
    pub fn into_fields(self, py: Python<'_>) -> PyResult<Vec<(&'static str, Py<PyAny>)>> {
        self.columns
            .into_iter()
            .map(|(name, column)| {
                let array = match column {
                    Column::Int(values, 1) => arrays::vector(py, values).into_py_any(py)?,
                    Column::Int(values, width) => arrays::matrix(py, values, width)?.into_py_any(py)?,
                    Column::Code(values) => arrays::vector(py, values).into_py_any(py)?,
                    Column::Real(values, width) => arrays::matrix(py, values, width)?.into_py_any(py)?,
                };
                Ok((name, array))
            })
            .collect()
    }
}

/// Refuses surface options on a query of another kind than faces.
pub fn require_faces(options: SurfaceOptions, primitives: &str) -> PyResult<()> {
    if options.any() && primitives != "faces" {
        return Err(value_error(
            "primitives",
            format!("'{primitives}': the return_* options need primitives='faces'"),
        ));
    }
    Ok(())
}

/// A query's arrays by name, as attributes (`answers.barycentric`) or
/// items (`answers["barycentric"]`); unpacks as the query's plain tuple,
/// so `closest, distance, face = mesh.closest_points(p, return_normal=True)`
/// still works.
#[pyclass(module = "proxima", name = "Answers", frozen)]
pub struct Answers {
    fields: Vec<(&'static str, Py<PyAny>)>,
    /// How many leading fields unpacking gives.
    unpacked: usize,
}

impl Answers {
    /// The query's plain arrays `leading` (what unpacking gives), then
    /// `extra`.
    pub fn new(leading: Vec<(&'static str, Py<PyAny>)>, extra: Vec<(&'static str, Py<PyAny>)>) -> Self {
        let unpacked = leading.len();
        let mut fields = leading;
        fields.extend(extra);
        Self { fields, unpacked }
    }

    fn field(&self, py: Python<'_>, name: &str) -> Option<Py<PyAny>> {
        self.fields
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, v)| v.clone_ref(py))
    }
}

#[pymethods]
impl Answers {
    fn __getattr__(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyAny>> {
        self.field(py, name).ok_or_else(|| {
            PyAttributeError::new_err(format!("'Answers' has no array '{name}' (it has {})", self.names()))
        })
    }

    fn __getitem__(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyAny>> {
        self.__getattr__(py, name)
    }

    /// The names of the arrays, in order.
    fn keys(&self) -> Vec<&'static str> {
        self.fields.iter().map(|(n, _)| *n).collect()
    }

    fn __iter__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let leading = self.fields[..self.unpacked].iter().map(|(_, v)| v.clone_ref(py));
        Ok(PyTuple::new(py, leading)?.as_any().try_iter()?.into_any())
    }

    fn __len__(&self) -> usize {
        self.unpacked
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let shapes: Vec<String> = self
            .fields
            .iter()
            .map(|(name, value)| {
                let shape = value
                    .bind(py)
                    .cast::<numpy::PyUntypedArray>()
                    .map(|a| match a.shape() {
                        [n] => format!("({n},)"),
                        shape => format!(
                            "({})",
                            shape.iter().map(usize::to_string).collect::<Vec<_>>().join(", ")
                        ),
                    })
                    .unwrap_or_default();
                format!("{name}{shape}")
            })
            .collect();
        format!("Answers({})", shapes.join(", "))
    }
}

impl Answers {
    fn names(&self) -> String {
        self.keys().join(", ")
    }
}
