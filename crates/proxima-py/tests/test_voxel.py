"""voxelize against an independent numpy separating-axis triangle/box test."""

import numpy as np
import pytest

import oracles as o
import proxima
from conftest import cube_arrays, quad_grid_arrays, random_soup


def brute_cells(vertices, triangles, origin, cell, n):
    """Occupied cells by a float64 SAT test of every cell box against every
    triangle whose bounding box reaches it: (occupied (n,n,n) bool, margin
    (n,n,n) = the smallest separation found, ~0 where the decision is close)."""
    v = np.asarray(vertices, dtype=np.float64)
    a, b, c = v[triangles[:, 0]], v[triangles[:, 1]], v[triangles[:, 2]]
    idx = np.stack(np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij"), -1).reshape(-1, 3)
    lo = origin + idx * cell
    hi = origin + (idx + 1) * cell
    sep = np.full(len(idx), np.inf)
    for i in range(0, len(idx), 512):
        s = o.tri_box_separation(lo[i : i + 512], hi[i : i + 512], a, b, c)
        sep[i : i + 512] = s.min(axis=1)
    return (sep <= 0).reshape(n, n, n), sep.reshape(n, n, n)


def check_grid(mesh, vertices, triangles, n):
    grid = mesh.voxelize(n)
    assert isinstance(grid, proxima.VoxelGrid)
    assert grid.resolution == n
    origin = np.asarray(grid.origin)
    assert origin.shape == (3,) and origin.dtype == np.float64
    cell = float(grid.cell_size)
    assert cell > 0
    v = np.asarray(vertices, dtype=np.float64)
    # the grid covers the bounds
    bounds = mesh.bounds
    np.testing.assert_allclose(bounds, [v.min(0), v.max(0)])
    assert np.all(origin <= bounds[0]), (origin, bounds)
    assert np.all(origin + n * cell >= bounds[1]), f"grid ends at {origin + n * cell}, bounds max {bounds[1]}"
    cells = grid.cells
    assert cells.dtype == np.int64 and cells.ndim == 2 and cells.shape[1] == 3
    assert len(grid) == len(cells)
    assert cells.min() >= 0 and cells.max() < n
    # increasing order of storage, x fastest: sorted by (k, j, i)
    key = (cells[:, 2] * n + cells[:, 1]) * n + cells[:, 0]
    assert np.all(np.diff(key) > 0), "cells not in increasing (x fastest) order, or repeated"
    dense = grid.dense()
    assert dense.shape == (n, n, n) and dense.dtype == np.bool_
    expect = np.zeros((n, n, n), bool)
    expect[cells[:, 0], cells[:, 1], cells[:, 2]] = True
    np.testing.assert_array_equal(dense, expect, err_msg="dense() disagrees with cells")
    # every triangle vertex's cell is occupied (clipped into the grid)
    vc = np.clip(np.floor((v[np.unique(triangles)] - origin) / cell).astype(np.int64), 0, n - 1)
    assert dense[vc[:, 0], vc[:, 1], vc[:, 2]].all(), "a vertex's cell is empty"
    # the exact test: same cells as a float64 SAT, except decisions within rounding
    occ, sep = brute_cells(v, triangles, origin, cell, n)
    close = np.abs(sep) <= 1e-6 * cell
    diff = (occ != dense) & ~close
    assert not diff.any(), (
        f"{diff.sum()} cells differ from SAT (extra {np.sum(dense & ~occ & ~close)}, missing {np.sum(occ & ~dense & ~close)}), "
        f"e.g. cell {np.argwhere(diff)[0].tolist()}"
    )
    return grid, close.sum()


@pytest.mark.parametrize("n", [1, 7, 16])
def test_voxelize_icosphere(icosphere, n):
    check_grid(icosphere, icosphere.vertices, icosphere.faces, n)


@pytest.mark.parametrize("n", [5, 12])
def test_voxelize_soup(n):
    v, f = random_soup(60, 31)
    check_grid(proxima.Mesh(v, f), v, f, n)


def test_voxelize_cube():
    """The axis-aligned unit cube: its faces lie on grid planes."""
    v, f = cube_arrays()
    grid, _ = check_grid(proxima.Mesh(v, f), v, f, 4)
    d = grid.dense()
    if not (np.array_equal(grid.origin, [0, 0, 0]) and grid.cell_size == 0.25):
        return  # a padded grid: check_grid's SAT comparison is the whole test
    # the shell: every cell with an index 0 or 3 on some axis, and no interior cell
    assert d.sum() == 64 - 8
    assert not d[1:3, 1:3, 1:3].any()


def test_voxelize_quads():
    v, f = quad_grid_arrays(n=3)
    tris, _ = o.fan_triangles(f)
    check_grid(proxima.Mesh(v, f), v, tris, 9)


def test_voxelize_threads_agree(icosphere):
    a = icosphere.voxelize(24, threads=1)
    b = icosphere.voxelize(24)
    np.testing.assert_array_equal(a.cells, b.cells)
    assert a.cell_size == b.cell_size and np.array_equal(a.origin, b.origin)
