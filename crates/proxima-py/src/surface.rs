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
    /// Whether any array is asked for (the query then returns [`Answers`]).
    pub fn any(self) -> bool {
        self.barycentric || self.feature || self.normal || self.uv
    }
}

/// One answer's surface values, flattened.
#[derive(Clone, Copy)]
struct Row {
    triangle: i64,
    corners: [i64; 3],
    barycentric: [f64; 3],
    feature: i8,
    feature_vertices: [i64; 2],
    normal: [f64; 3],
    face_normal: [f64; 3],
    uv: [f64; 2],
}

/// A query without an answer: -1 and NaN.
const MISSING: Row = Row {
    triangle: -1,
    corners: [-1; 3],
    barycentric: [f64::NAN; 3],
    feature: -1,
    feature_vertices: [-1; 2],
    normal: [f64::NAN; 3],
    face_normal: [f64::NAN; 3],
    uv: [f64::NAN; 2],
};

/// The arrays `options` asks for, of the surface points `at` (on all
/// cores of the current pool, without the GIL): named, ready for
/// [`Answers`].
pub struct SurfaceColumns {
    options: SurfaceOptions,
    rows: Vec<Row>,
}

impl SurfaceColumns {
    /// The rows of `at` on `index`'s mesh.
    pub fn new(index: &MeshIndex, at: &[Option<SurfacePoint>], options: SurfaceOptions) -> Self {
        let mesh = index.mesh();
        let normals = options.normal.then(|| index.vertex_normals());
        let rows = at
            .par_iter()
            .with_min_len(1024)
            .map(|at| {
                let Some(at) = at else { return MISSING };
                let (normal, face_normal) = match normals {
                    Some(normals) => (
                        at.interpolated_normal(mesh, normals).to_array(),
                        at.face_normal(mesh).to_array(),
                    ),
                    None => ([f64::NAN; 3], [f64::NAN; 3]),
                };
                let vertex = |v: u32| if v == u32::MAX { -1 } else { i64::from(v) };
                Row {
                    triangle: i64::from(at.triangle),
                    corners: at.corners.map(i64::from),
                    barycentric: at.barycentric,
                    feature: at.feature.code() as i8,
                    feature_vertices: at.feature.vertices().map(vertex),
                    normal,
                    face_normal,
                    uv: match options.uv {
                        true => at.uv(mesh).unwrap_or([f64::NAN; 2]),
                        false => [f64::NAN; 2],
                    },
                }
            })
            .collect();
        Self { options, rows }
    }

    /// No rows (a query of no points).
    pub fn empty(options: SurfaceOptions) -> Self {
        Self {
            options,
            rows: Vec::new(),
        }
    }

    /// The named arrays.
    pub fn into_fields(self, py: Python<'_>) -> PyResult<Vec<(&'static str, Py<PyAny>)>> {
        let rows = &self.rows;
        let mut fields = Vec::new();
        let column = |f: fn(&Row) -> i64| rows.iter().map(f).collect::<Vec<_>>();
        let flat = |f: fn(&Row) -> &[f64]| rows.iter().flat_map(f).copied().collect::<Vec<_>>();
        let flat_i = |f: fn(&Row) -> &[i64]| rows.iter().flat_map(f).copied().collect::<Vec<_>>();
        if self.options.barycentric {
            fields.push(("triangle", arrays::vector(py, column(|r| r.triangle)).into_py_any(py)?));
            fields.push((
                "corners",
                arrays::matrix(py, flat_i(|r| &r.corners), 3)?.into_py_any(py)?,
            ));
            fields.push((
                "barycentric",
                arrays::matrix(py, flat(|r| &r.barycentric), 3)?.into_py_any(py)?,
            ));
        }
        if self.options.feature {
            let codes: Vec<i8> = rows.iter().map(|r| r.feature).collect();
            fields.push(("feature", arrays::vector(py, codes).into_py_any(py)?));
            let vertices = flat_i(|r| &r.feature_vertices);
            fields.push(("feature_vertices", arrays::matrix(py, vertices, 2)?.into_py_any(py)?));
        }
        if self.options.normal {
            fields.push(("normal", arrays::matrix(py, flat(|r| &r.normal), 3)?.into_py_any(py)?));
            fields.push((
                "face_normal",
                arrays::matrix(py, flat(|r| &r.face_normal), 3)?.into_py_any(py)?,
            ));
        }
        if self.options.uv {
            fields.push(("uv", arrays::matrix(py, flat(|r| &r.uv), 2)?.into_py_any(py)?));
        }
        Ok(fields)
    }
}

/// Refuses `return_uv` on a mesh without texture coordinates.
pub fn require_uvs(options: SurfaceOptions, mesh: &proxima::Mesh) -> PyResult<()> {
    if options.uv && mesh.corner_uvs().is_none() {
        return Err(value_error(
            "return_uv",
            "the mesh has no texture coordinates (OBJ vt with every face corner naming one, PLY u v or s t)",
        ));
    }
    Ok(())
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
