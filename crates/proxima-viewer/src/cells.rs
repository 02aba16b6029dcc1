//! Grid cells to draw: the occupied cells of a hash grid over one kind of
//! primitive, and the cells a ray walks through. Plain data, no window.

use crate::model::Model;
use crate::scene::{BoxSet, Overlay, colors};
use proxima::grid::{Cell, FastHash, GridConfig, GridStats, HashGrid, InsertMethod};
use proxima::grid::{GridTraversal, TraversalConfig};
use proxima::kind::{KindFamily, KindGeneric, PerKind};
use proxima::prelude::*;
use proxima::primitive::polygon::DEFAULT_PLANARITY_TOLERANCE;
use std::sync::Arc;
use std::time::Instant;

/// At most this many cell–primitive pairs in a viewer grid: beyond it the
/// build stops with an error asking for larger cells (keeps memory and
/// drawing bounded).
pub const MAX_ENTRIES: u64 = 1 << 23;
/// At most this many cells under one primitive's bounding box.
pub const MAX_CELLS_PER_PRIMITIVE: u64 = 1 << 20;

/// A grid per primitive type, of which one is built. Grids use the fast
/// hasher: on the dragon at cell size 0.001 (107k occupied cells) the
/// classic hash takes many times longer to build.
struct Grids;

impl KindFamily for Grids {
    type Of<T: MeshPrimitive> = Option<HashGrid<T, FastHash>>;
}

/// Builds the grid over one kind into `grids`: its statistics and its
/// occupied cells.
struct BuildGrid<'a> {
    mesh: &'a Mesh,
    config: &'a GridConfig,
    grids: &'a mut PerKind<Grids>,
}

impl KindGeneric for BuildGrid<'_> {
    type Output = Result<(GridStats, Vec<Cell>), String>;

    fn call<T: MeshPrimitive>(self) -> Self::Output {
        let set = T::extract(self.mesh, DEFAULT_PLANARITY_TOLERANCE);
        let grid = HashGrid::<T, FastHash>::build(set, self.config).map_err(|e| e.to_string())?;
        let cells = grid.occupied().map(|(c, _)| c).collect();
        let stats = grid.stats();
        *self.grids.get_mut::<T>() = Some(grid);
        Ok((stats, cells))
    }
}

/// Whether a cell of the grid over one kind holds a primitive.
struct Occupied<'a>(&'a PerKind<Grids>, &'a Cell);

impl KindGeneric for Occupied<'_> {
    type Output = bool;

    fn call<T: MeshPrimitive>(self) -> bool {
        self.0
            .get::<T>()
            .as_ref()
            .is_some_and(|grid| !grid.cell(self.1).is_empty())
    }
}

/// A hash grid over one kind of primitive, with its occupied cells as boxes.
pub struct CellGrid {
    /// Kind of primitive in the grid.
    pub kind: PrimitiveKind,
    /// Side of the cubic cells.
    pub cell_size: f32,
    /// The occupied cells.
    pub boxes: Arc<BoxSet>,
    /// Occupancy and memory.
    pub stats: GridStats,
    /// Seconds the build took.
    pub build_seconds: f64,
    grids: PerKind<Grids>,
}

impl CellGrid {
    /// Builds the grid of cubic cells of side `cell_size` over the primitives
    /// of `kind`. The error is one line (bad size, too many cells).
    pub fn build(model: &Model, kind: PrimitiveKind, cell_size: f32) -> Result<CellGrid, String> {
        let config = GridConfig {
            insert: InsertMethod::Scanline,
            max_entries: MAX_ENTRIES,
            max_cells_per_primitive: MAX_CELLS_PER_PRIMITIVE,
            ..GridConfig::cubic(cell_size)
        };
        let layout = config.layout().map_err(|e| e.to_string())?;
        let start = Instant::now();
        let mut grids = PerKind::default();
        let build = BuildGrid {
            mesh: &model.mesh,
            config: &config,
            grids: &mut grids,
        };
        let (stats, cells) = kind.dispatch(build)?;
        let boxes = Arc::new(BoxSet::new(cells.iter().map(|&c| layout.cell_box(c))));
        Ok(CellGrid {
            kind,
            cell_size,
            boxes,
            stats,
            build_seconds: start.elapsed().as_secs_f64(),
            grids,
        })
    }

    /// Number of occupied cells.
    pub fn occupied_count(&self) -> usize {
        self.stats.occupied_cells
    }

    /// `true` when `cell` holds at least one primitive.
    pub fn is_occupied(&self, cell: &Cell) -> bool {
        self.kind.dispatch(Occupied(&self.grids, cell))
    }

    /// The first face hit by the ray (only for a grid over faces; the grid has no ray query over polygons).
    pub fn first_hit(&self, origin: Vec3, direction: Vec3) -> Option<Vec3> {
        let faces = self.grids.faces.as_ref()?;
        let hit = faces.first_hit(origin, direction, 0.0, f32::INFINITY).ok().flatten()?;
        Some(hit.point)
    }
}

/// A ray and the cells it walks through.
#[derive(Debug)]
pub struct RayWalk {
    /// Start of the ray.
    pub origin: Vec3,
    /// Unit direction.
    pub direction: Vec3,
    /// The cells, in order.
    pub cells: Vec<Cell>,
    /// Boxes of the cells that hold no primitive of the grid (all of them
    /// when there is no grid).
    pub empty_boxes: Arc<BoxSet>,
    /// Boxes of the cells that hold primitives of the grid.
    pub occupied_boxes: Arc<BoxSet>,
    /// Where the drawn ray ends: the exit from the last cell.
    pub end: Vec3,
    /// First face the ray hits (grids over faces only).
    pub hit: Option<Vec3>,
}

/// Walks `origin + t · direction` through cubic cells of side `cell_size`
/// (grid origin at the world origin, as the hash grid) for at most `steps`
/// cells. Cells occupied in `grid` (when given, with the same cell size) are
/// set apart. The error is one line (zero direction, bad cell size, …).
pub fn walk_ray(
    origin: Vec3,
    direction: Vec3,
    cell_size: f32,
    steps: u32,
    grid: Option<&CellGrid>,
) -> Result<RayWalk, String> {
    let direction = direction.normalize_or_zero();
    let config = TraversalConfig {
        max_steps: steps as u64,
        ..TraversalConfig::cubic(cell_size)
    };
    let walk = GridTraversal::new(origin, direction, &config).map_err(|e| e.to_string())?;
    let layout = *walk.layout();
    let mut cells = Vec::new();
    let mut t_end = 0.0f32;
    for step in walk {
        cells.push(step.cell);
        t_end = step.t_exit;
    }
    let grid = grid.filter(|g| g.cell_size == cell_size);
    let occupied = |c: &Cell| grid.is_some_and(|g| g.is_occupied(c));
    let empty_boxes = BoxSet::new(cells.iter().filter(|c| !occupied(c)).map(|&c| layout.cell_box(c)));
    let occupied_boxes = BoxSet::new(cells.iter().filter(|c| occupied(c)).map(|&c| layout.cell_box(c)));
    let hit = grid.and_then(|g| g.first_hit(origin, direction));
    Ok(RayWalk {
        origin,
        direction,
        cells,
        empty_boxes: Arc::new(empty_boxes),
        occupied_boxes: Arc::new(occupied_boxes),
        end: origin + t_end * direction,
        hit,
    })
}

impl RayWalk {
    /// The ray as a line with a marker at its origin (and at the first hit).
    pub fn overlay(&self) -> Overlay {
        let mut overlay = Overlay::default();
        overlay.line(self.origin, self.end, colors::RAY);
        overlay.point(self.origin, colors::RAY, crate::scene::VERTEX_SIZE);
        if let Some(hit) = self.hit {
            overlay.marker(hit, colors::RAY_HIT, crate::scene::VERTEX_SIZE + 2.0);
        }
        overlay
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::ModelSource;
    use proxima::Mesh;

    fn model() -> Model {
        // One triangle in the plane z = 0.5, spanning cells (0..2, 0..2, 0) of size 1.
        let mesh = Mesh::from_triangles(
            vec![
                Vec3::new(0.1, 0.1, 0.5),
                Vec3::new(1.8, 0.1, 0.5),
                Vec3::new(0.1, 1.8, 0.5),
            ],
            &[[0, 1, 2]],
        )
        .unwrap();
        Model::load(
            ModelSource::Mesh {
                mesh,
                name: "tri".into(),
            },
            &|_| {},
        )
        .unwrap()
    }

    #[test]
    fn occupied_cells_become_unit_boxes() {
        let m = model();
        let g = CellGrid::build(&m, PrimitiveKind::Faces, 1.0).unwrap();
        assert_eq!(g.occupied_count(), 3);
        assert_eq!(g.boxes.len(), 3);
        for b in &g.boxes.boxes {
            assert_eq!(b.size, [1.0; 3]);
            assert_eq!(b.min[2], 0.0);
        }
        assert!(g.is_occupied(&[1, 0, 0]) && !g.is_occupied(&[1, 1, 0]));
        let v = CellGrid::build(&m, PrimitiveKind::Vertices, 1.0).unwrap();
        assert_eq!(v.occupied_count(), 3);
        let e = CellGrid::build(&m, PrimitiveKind::Edges, 0.5).unwrap();
        assert!(e.occupied_count() > 3);
    }

    #[test]
    fn bad_sizes_and_huge_grids_are_errors_not_panics() {
        let m = model();
        for h in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            assert!(CellGrid::build(&m, PrimitiveKind::Faces, h).is_err(), "{h}");
        }
        let error = CellGrid::build(&m, PrimitiveKind::Faces, 1e-5).err().unwrap();
        assert!(error.contains("cells"), "{error}");
    }

    #[test]
    fn the_ray_walks_cells_and_finds_the_face() {
        let m = model();
        let g = CellGrid::build(&m, PrimitiveKind::Faces, 1.0).unwrap();
        // Down through the triangle at (0.5, 0.5).
        let w = walk_ray(Vec3::new(0.5, 0.5, 2.5), Vec3::new(0.0, 0.0, -2.0), 1.0, 4, Some(&g)).unwrap();
        assert_eq!(w.cells, [[0, 0, 2], [0, 0, 1], [0, 0, 0], [0, 0, -1]]);
        assert_eq!(w.direction, -Vec3::Z);
        assert_eq!(w.end, Vec3::new(0.5, 0.5, -1.0));
        assert_eq!(w.occupied_boxes.len(), 1);
        assert_eq!(w.empty_boxes.len(), 3);
        assert_eq!(w.hit, Some(Vec3::new(0.5, 0.5, 0.5)));
        let overlay = w.overlay();
        assert_eq!(overlay.lines.len(), 2);
        assert_eq!(overlay.markers.len(), 1);
        // Without a grid (or with another cell size) every cell is "empty".
        let w = walk_ray(Vec3::new(0.5, 0.5, 2.5), -Vec3::Z, 0.5, 10, Some(&g)).unwrap();
        assert_eq!((w.empty_boxes.len(), w.occupied_boxes.len(), w.hit), (10, 0, None));
        assert!(walk_ray(Vec3::ZERO, Vec3::ZERO, 1.0, 10, None).is_err());
        assert!(walk_ray(Vec3::ZERO, Vec3::X, 0.0, 10, None).is_err());
        let none = walk_ray(Vec3::ZERO, Vec3::X, 1.0, 0, None).unwrap();
        assert!(none.cells.is_empty() && none.end == Vec3::ZERO);
    }
}
