//! What comes with an answer: the `return_*` options of `closest_points`
//! and `cast_rays`, the arrays they add, and `proxima.Answers`, the named
//! result that holds them.

use crate::arrays::{self, value_error};
use numpy::PyUntypedArrayMethods;
use proxima::surface::{Attributes, SurfaceAnswer, TriangleOrdered};
use pyo3::IntoPyObjectExt;
use pyo3::exceptions::PyAttributeError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

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

    /// The attributes the library computes for these options.
    pub fn attributes(self) -> Attributes {
        Attributes {
            normals: self.normal,
            uv: self.uv,
        }
    }

    /// Whether any array is asked for (the query then returns [`Answers`]).
    pub fn any(self) -> bool {
        self.barycentric || self.feature || self.normal || self.uv
    }
}

/// The arrays `options` asks for: each a column of rows of its width,
/// -1 or NaN for a query without an answer. The library computes the
/// answers in the order of their triangles
/// ([`MeshIndex::closest_surface`](proxima::MeshIndex::closest_surface));
/// here they are read once, in input order, into every column.
#[derive(Default)]
pub struct SurfaceColumns {
    triangle: Option<Vec<i64>>,
    corners: Option<Vec<i64>>,
    barycentric: Option<Vec<f64>>,
    feature: Option<Vec<i8>>,
    feature_vertices: Option<Vec<i64>>,
    normal: Option<Vec<f64>>,
    face_normal: Option<Vec<f64>>,
    uv: Option<Vec<f64>>,
}

impl SurfaceColumns {
    /// The columns `options` asks for, of the answers `at`.
    pub fn new(at: &TriangleOrdered<Option<SurfaceAnswer>>, options: SurfaceOptions) -> Self {
        let mut columns = Self::empty(at.len(), options);
        for answer in at.iter() {
            columns.push(answer.as_ref());
        }
        columns
    }

    /// The columns `options` asks for, with room for `n` rows and none yet.
    pub fn empty(n: usize, options: SurfaceOptions) -> Self {
        fn column<T>(on: bool, n: usize, width: usize) -> Option<Vec<T>> {
            on.then(|| Vec::with_capacity(n * width))
        }
        Self {
            triangle: column(options.barycentric, n, 1),
            corners: column(options.barycentric, n, 3),
            barycentric: column(options.barycentric, n, 3),
            feature: column(options.feature, n, 1),
            feature_vertices: column(options.feature, n, 2),
            normal: column(options.normal, n, 3),
            face_normal: column(options.normal, n, 3),
            uv: column(options.uv, n, 2),
        }
    }

    /// Appends the row of `a`, or of no answer.
    #[inline]
    fn push(&mut self, a: Option<&SurfaceAnswer>) {
        fn row<T: Copy, const W: usize>(column: &mut Option<Vec<T>>, values: Option<[T; W]>, none: T) {
            if let Some(column) = column {
                column.extend_from_slice(&values.unwrap_or([none; W]));
            }
        }
        let vertex = |v: u32| if v == u32::MAX { -1 } else { i64::from(v) };
        row(&mut self.triangle, a.map(|a| [i64::from(a.at.triangle)]), -1);
        row(&mut self.corners, a.map(|a| a.at.corners.map(i64::from)), -1);
        row(&mut self.barycentric, a.map(|a| a.at.barycentric), f64::NAN);
        row(&mut self.feature, a.map(|a| [a.at.feature.code() as i8]), -1);
        row(
            &mut self.feature_vertices,
            a.map(|a| a.at.feature.vertices().map(vertex)),
            -1,
        );
        row(&mut self.normal, a.map(|a| a.normal.to_array()), f64::NAN);
        row(&mut self.face_normal, a.map(|a| a.face_normal.to_array()), f64::NAN);
        row(&mut self.uv, a.and_then(|a| a.uv), f64::NAN);
    }

    /// The named arrays, in a fixed order.
    pub fn into_fields(self, py: Python<'_>) -> PyResult<Vec<(&'static str, Py<PyAny>)>> {
        fn matrix<T: numpy::Element>(py: Python<'_>, values: Vec<T>, width: usize) -> PyResult<Py<PyAny>> {
            match width {
                1 => arrays::vector(py, values).into_py_any(py),
                _ => arrays::matrix(py, values, width)?.into_py_any(py),
            }
        }
        let mut fields = Vec::new();
        let mut add = |name: &'static str, array: Option<PyResult<Py<PyAny>>>| -> PyResult<()> {
            if let Some(array) = array {
                fields.push((name, array?));
            }
            Ok(())
        };
        add("triangle", self.triangle.map(|v| matrix(py, v, 1)))?;
        add("corners", self.corners.map(|v| matrix(py, v, 3)))?;
        add("barycentric", self.barycentric.map(|v| matrix(py, v, 3)))?;
        add("feature", self.feature.map(|v| matrix(py, v, 1)))?;
        add("feature_vertices", self.feature_vertices.map(|v| matrix(py, v, 2)))?;
        add("normal", self.normal.map(|v| matrix(py, v, 3)))?;
        add("face_normal", self.face_normal.map(|v| matrix(py, v, 3)))?;
        add("uv", self.uv.map(|v| matrix(py, v, 2)))?;
        Ok(fields)
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
