"""proxima: exact, fast spatial queries on triangle meshes.

Closest points, k nearest elements, signed distances with winding-number
signs, ray casts, voxels and frustum culling, on numpy arrays; distances, collisions and
self-intersections of meshes placed by rigid poses. Every batch
call releases the GIL and runs on all cores (``threads=1`` for one).

>>> import proxima
>>> mesh = proxima.noisy_icosphere(8)
>>> points = mesh.sample_near_surface(1000, seed=1)
>>> closest, distance, face = mesh.closest_points(points)
>>> inside = mesh.signed_distance(points) < 0
"""

from ._proxima import (
    Answers,
    Hausdorff,
    Mesh,
    PairDistance,
    Points,
    Scene,
    VoxelGrid,
    __version__,
    chamfer,
    check_fits,
    distance,
    hausdorff,
    load,
    max_threads,
    memory_budget,
    mesh_suffixes,
    noisy_icosphere,
    training_sample_counts,
    traverse,
)

__all__ = [
    "Answers",
    "Hausdorff",
    "Mesh",
    "PairDistance",
    "Points",
    "Scene",
    "VoxelGrid",
    "__version__",
    "chamfer",
    "check_fits",
    "distance",
    "hausdorff",
    "load",
    "max_threads",
    "memory_budget",
    "mesh_suffixes",
    "noisy_icosphere",
    "training_sample_counts",
    "traverse",
]
