//! Which primitive types the wide tree tests in SIMD packets.

use super::WideTree;
use crate::primitive::Triangle;

/// What the wide tree needs to know of a primitive type: whether its leaves
/// are tested in SIMD packets ([`Triangle`]s, on x86-64) or one primitive at
/// a time (the default), and whether its tree is a tree of triangles.
/// Chosen at compile time, per type.
///
/// ```
/// use proxima::prelude::*;
/// use proxima::wide_tree::WidePrimitive;
/// #[derive(Clone, Copy, Debug)]
/// struct Marker(Vec3);
/// impl WidePrimitive for Marker {}
/// assert!(!Marker::PACKED);
/// ```
pub trait WidePrimitive: Sized {
    /// `true` when leaves of this type are tested as triangle packets.
    const PACKED: bool = false;
    /// The primitives as triangles, when [`PACKED`](Self::PACKED).
    #[inline(always)]
    fn as_triangles(_primitives: &[Self]) -> Option<&[Triangle]> {
        None
    }
    /// The tree as a tree of triangles, for triangles: a mesh index refits
    /// it by reading each triangle from the moved mesh's faces, without
    /// extracting them all again.
    #[inline(always)]
    fn as_triangle_tree(_tree: &mut WideTree<Self>) -> Option<&mut WideTree<Triangle>> {
        None
    }
}

impl WidePrimitive for Triangle {
    /// On x86-64, where the packet arithmetic is known to repeat `Vec3A`'s bit for bit.
    const PACKED: bool = cfg!(target_arch = "x86_64");
    #[inline(always)]
    fn as_triangles(primitives: &[Self]) -> Option<&[Triangle]> {
        Self::PACKED.then_some(primitives)
    }
    #[inline(always)]
    fn as_triangle_tree(tree: &mut WideTree<Self>) -> Option<&mut WideTree<Triangle>> {
        Some(tree)
    }
}

impl WidePrimitive for crate::Point {}
impl WidePrimitive for crate::LineSegment {}
impl WidePrimitive for crate::ConvexPolygon {}
