//! The kinds of primitive a mesh gives, and generic code run on one kind.
//!
//! A command or a view that works on "vertices, edges, faces or polygons, as
//! the user chose" writes its work once, generic over the primitive type, as
//! a [`KindTask`]; [`PrimitiveKind::run`] extracts that kind's primitives
//! and calls it with the concrete type. No virtual call per query: the task
//! is monomorphized for each of the four types.

use crate::frustum::FrustumOverlap;
use crate::grid::GridInsert;
use crate::mesh::Mesh;
use crate::primitive::{BoundingPoints, ClosestPoint, ConvexPolygon, LineSegment, Point, PrimitiveSet, Triangle};
use crate::wide_tree::WidePrimitive;
use std::fmt;
use std::str::FromStr;

/// Which primitives of a mesh a query works on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PrimitiveKind {
    /// The mesh's vertices, as [`Point`]s (source: vertex index).
    Vertices,
    /// The mesh's unique undirected edges, as [`LineSegment`]s (source: edge index).
    Edges,
    /// The mesh's faces as [`Triangle`]s, polygons fan-triangulated (source:
    /// face index). The default.
    #[default]
    Faces,
    /// The mesh's faces as [`ConvexPolygon`]s where convex and planar within
    /// a tolerance, fan-triangulated otherwise (source: face index).
    Polygons,
}

impl PrimitiveKind {
    /// Every kind, in display order.
    pub const ALL: [PrimitiveKind; 4] = [Self::Vertices, Self::Edges, Self::Faces, Self::Polygons];

    /// The lowercase names, in the order of [`ALL`](Self::ALL).
    pub const NAMES: [&'static str; 4] = ["vertices", "edges", "faces", "polygons"];

    /// The lowercase name, as on the command line and in output.
    ///
    /// ```
    /// use proxima::PrimitiveKind;
    /// assert_eq!(PrimitiveKind::Edges.name(), "edges");
    /// assert_eq!("edges".parse::<PrimitiveKind>(), Ok(PrimitiveKind::Edges));
    /// ```
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// What this kind is, in one line (the command line's `--help`).
    pub fn description(self) -> &'static str {
        match self {
            Self::Vertices => "Mesh vertices as points",
            Self::Edges => "Unique undirected edges as segments",
            Self::Faces => "Faces as triangles (polygons fan-triangulated)",
            Self::Polygons => {
                "Faces as convex polygons, as they are when convex and planar within tolerance \
                 (the others fan-triangulated; a note on stderr says how many)"
            }
        }
    }

    /// How many primitives of this kind `mesh` gives, at most (edges and
    /// polygons come from faces: 0 faces, none of them).
    pub fn available(self, mesh: &Mesh) -> usize {
        match self {
            Self::Vertices => mesh.vertex_count(),
            Self::Edges | Self::Faces | Self::Polygons => mesh.face_count(),
        }
    }

    /// Runs `task` on this kind's primitives of `mesh`; polygons are taken
    /// with the relative planarity tolerance `planarity` (see
    /// [`Mesh::extract_polygons`]).
    ///
    /// ```
    /// use proxima::kind::{KindTask, MeshPrimitive};
    /// use proxima::{Mesh, PrimitiveKind, PrimitiveSet, Vec3};
    /// struct Count;
    /// impl KindTask for Count {
    ///     type Output = usize;
    ///     fn run<T: MeshPrimitive>(self, set: PrimitiveSet<T>) -> usize {
    ///         set.primitives.len()
    ///     }
    /// }
    /// let mesh = Mesh::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]]).unwrap();
    /// assert_eq!(PrimitiveKind::Edges.run(&mesh, 0.0, Count), 3);
    /// ```
    pub fn run<F: KindTask>(self, mesh: &Mesh, planarity: f32, task: F) -> F::Output {
        struct OnSet<'a, F> {
            mesh: &'a Mesh,
            planarity: f32,
            task: F,
        }
        impl<F: KindTask> KindGeneric for OnSet<'_, F> {
            type Output = F::Output;
            fn call<T: MeshPrimitive>(self) -> F::Output {
                self.task.run(T::extract(self.mesh, self.planarity))
            }
        }
        self.dispatch(OnSet { mesh, planarity, task })
    }

    /// Calls `generic` with this kind's primitive type: the one place where
    /// a kind chosen at run time becomes a type.
    ///
    /// ```
    /// use proxima::kind::{KindGeneric, MeshPrimitive};
    /// use proxima::PrimitiveKind;
    /// struct Size;
    /// impl KindGeneric for Size {
    ///     type Output = usize;
    ///     fn call<T: MeshPrimitive>(self) -> usize {
    ///         std::mem::size_of::<T>()
    ///     }
    /// }
    /// assert_eq!(PrimitiveKind::Vertices.dispatch(Size), 12);
    /// ```
    pub fn dispatch<G: KindGeneric>(self, generic: G) -> G::Output {
        match self {
            Self::Vertices => generic.call::<Point>(),
            Self::Edges => generic.call::<LineSegment>(),
            Self::Faces => generic.call::<Triangle>(),
            Self::Polygons => generic.call::<ConvexPolygon>(),
        }
    }
}

impl fmt::Display for PrimitiveKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is not one of [`PrimitiveKind::NAMES`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("'{0}' is not a primitive kind (vertices, edges, faces or polygons)")]
pub struct UnknownKind(pub String);

impl FromStr for PrimitiveKind {
    type Err = UnknownKind;
    fn from_str(text: &str) -> Result<Self, UnknownKind> {
        Self::NAMES
            .iter()
            .position(|name| name.eq_ignore_ascii_case(text))
            .map(|i| Self::ALL[i])
            .ok_or_else(|| UnknownKind(text.to_string()))
    }
}

/// Everything each of the four primitive types can do: the bound of generic
/// code over kinds. Implemented for [`Point`], [`LineSegment`], [`Triangle`]
/// and [`ConvexPolygon`]. `Copy` because every tree build needs it.
pub trait MeshPrimitive:
    ClosestPoint + BoundingPoints + FrustumOverlap + GridInsert + WidePrimitive + Copy + fmt::Debug + Send + Sync + 'static
{
    /// The kind of primitive this type is.
    const KIND: PrimitiveKind;

    /// This kind's primitives of `mesh`, polygons taken with the relative
    /// planarity tolerance `planarity` (the other kinds ignore it).
    fn extract(mesh: &Mesh, planarity: f32) -> PrimitiveSet<Self>;

    /// This type's value in `values`.
    fn of_kind<F: KindFamily>(values: &PerKind<F>) -> &F::Of<Self>;

    /// This type's value in `values`, to change it.
    fn of_kind_mut<F: KindFamily>(values: &mut PerKind<F>) -> &mut F::Of<Self>;
}

impl MeshPrimitive for Point {
    const KIND: PrimitiveKind = PrimitiveKind::Vertices;
    fn extract(mesh: &Mesh, _: f32) -> PrimitiveSet<Self> {
        mesh.vertices()
    }
    fn of_kind<F: KindFamily>(values: &PerKind<F>) -> &F::Of<Self> {
        &values.vertices
    }
    fn of_kind_mut<F: KindFamily>(values: &mut PerKind<F>) -> &mut F::Of<Self> {
        &mut values.vertices
    }
}
impl MeshPrimitive for LineSegment {
    const KIND: PrimitiveKind = PrimitiveKind::Edges;
    fn extract(mesh: &Mesh, _: f32) -> PrimitiveSet<Self> {
        mesh.edges()
    }
    fn of_kind<F: KindFamily>(values: &PerKind<F>) -> &F::Of<Self> {
        &values.edges
    }
    fn of_kind_mut<F: KindFamily>(values: &mut PerKind<F>) -> &mut F::Of<Self> {
        &mut values.edges
    }
}
impl MeshPrimitive for Triangle {
    const KIND: PrimitiveKind = PrimitiveKind::Faces;
    fn extract(mesh: &Mesh, _: f32) -> PrimitiveSet<Self> {
        mesh.triangles()
    }
    fn of_kind<F: KindFamily>(values: &PerKind<F>) -> &F::Of<Self> {
        &values.faces
    }
    fn of_kind_mut<F: KindFamily>(values: &mut PerKind<F>) -> &mut F::Of<Self> {
        &mut values.faces
    }
}
impl MeshPrimitive for ConvexPolygon {
    const KIND: PrimitiveKind = PrimitiveKind::Polygons;
    fn extract(mesh: &Mesh, planarity: f32) -> PrimitiveSet<Self> {
        mesh.extract_polygons(planarity).set
    }
    fn of_kind<F: KindFamily>(values: &PerKind<F>) -> &F::Of<Self> {
        &values.polygons
    }
    fn of_kind_mut<F: KindFamily>(values: &mut PerKind<F>) -> &mut F::Of<Self> {
        &mut values.polygons
    }
}

/// Work generic over the primitive type, called with the type of a kind
/// chosen at run time by [`PrimitiveKind::dispatch`].
pub trait KindGeneric {
    /// What the work gives.
    type Output;
    /// Does the work for primitive type `T`.
    fn call<T: MeshPrimitive>(self) -> Self::Output;
}

/// A value type for each primitive type: `Of<Point>`, `Of<Triangle>`, ...
/// (for example a lazily built tree of that primitive), so that
/// [`PerKind`] holds one typed value per kind without type erasure.
pub trait KindFamily {
    /// The value held for primitive type `T`.
    type Of<T: MeshPrimitive>;
}

/// One value per primitive kind, each typed by its primitive:
/// `F::Of<Point>` for vertices, `F::Of<Triangle>` for faces, and so on.
///
/// ```
/// use proxima::kind::{KindFamily, MeshPrimitive, PerKind};
/// use proxima::Triangle;
/// struct Counts;
/// impl KindFamily for Counts {
///     type Of<T: MeshPrimitive> = usize;
/// }
/// let counts = PerKind::<Counts> { vertices: 4, edges: 6, faces: 4, polygons: 4 };
/// assert_eq!(*counts.get::<Triangle>(), 4);
/// ```
pub struct PerKind<F: KindFamily> {
    /// The value for [`PrimitiveKind::Vertices`].
    pub vertices: F::Of<Point>,
    /// The value for [`PrimitiveKind::Edges`].
    pub edges: F::Of<LineSegment>,
    /// The value for [`PrimitiveKind::Faces`].
    pub faces: F::Of<Triangle>,
    /// The value for [`PrimitiveKind::Polygons`].
    pub polygons: F::Of<ConvexPolygon>,
}

impl<F: KindFamily> PerKind<F> {
    /// The value for primitive type `T`.
    pub fn get<T: MeshPrimitive>(&self) -> &F::Of<T> {
        T::of_kind(self)
    }

    /// The value for primitive type `T`, to change it.
    pub fn get_mut<T: MeshPrimitive>(&mut self) -> &mut F::Of<T> {
        T::of_kind_mut(self)
    }
}

impl<F: KindFamily> Default for PerKind<F>
where
    F::Of<Point>: Default,
    F::Of<LineSegment>: Default,
    F::Of<Triangle>: Default,
    F::Of<ConvexPolygon>: Default,
{
    fn default() -> Self {
        Self {
            vertices: Default::default(),
            edges: Default::default(),
            faces: Default::default(),
            polygons: Default::default(),
        }
    }
}

/// Work written once for every primitive type, run by [`PrimitiveKind::run`].
pub trait KindTask {
    /// What the work gives.
    type Output;
    /// Does the work on the primitives of one kind.
    fn run<T: MeshPrimitive>(self, primitives: PrimitiveSet<T>) -> Self::Output;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_refused() {
        for kind in PrimitiveKind::ALL {
            assert_eq!(kind.name().parse::<PrimitiveKind>(), Ok(kind));
            assert_eq!(kind.to_string(), kind.name());
        }
        assert_eq!("FACES".parse::<PrimitiveKind>(), Ok(PrimitiveKind::Faces));
        assert!("face".parse::<PrimitiveKind>().is_err());
        assert!("".parse::<PrimitiveKind>().is_err());
    }

    #[test]
    fn each_type_names_its_kind() {
        struct Kind;
        impl KindTask for Kind {
            type Output = PrimitiveKind;
            fn run<T: MeshPrimitive>(self, _: PrimitiveSet<T>) -> PrimitiveKind {
                T::KIND
            }
        }
        let mesh =
            crate::mesh::Mesh::from_triangles(vec![crate::Vec3::ZERO, crate::Vec3::X, crate::Vec3::Y], &[[0, 1, 2]])
                .unwrap();
        for kind in PrimitiveKind::ALL {
            assert_eq!(kind.run(&mesh, 0.0, Kind), kind);
        }
    }
}
