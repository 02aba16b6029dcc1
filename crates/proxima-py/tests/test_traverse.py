"""proxima.traverse against an independent float64 slab test of each cell."""

import numpy as np
import pytest

import oracles as o
import proxima


def slab_cells(origin, direction, cell, t_end):
    """The cells in which origin + t * direction spends a parameter interval of
    positive length within [0, t_end], by slab-testing every cell of the
    segment's bounding box: {cell: (t_enter, t_exit)}, plus the cells whose
    interval length is within rounding of zero (undecidable here)."""
    origin, direction, cell = (np.asarray(x, dtype=np.float64) for x in (origin, direction, cell))
    end = origin + t_end * direction
    lo = np.floor(np.minimum(origin, end) / cell).astype(np.int64) - 1
    hi = np.floor(np.maximum(origin, end) / cell).astype(np.int64) + 1
    grid = np.stack(
        np.meshgrid(*[np.arange(lo[a], hi[a] + 1) for a in range(3)], indexing="ij"), -1
    ).reshape(-1, 3)
    t0, t1 = o.slab(origin, direction, grid * cell, (grid + 1) * cell)
    t0, t1 = np.maximum(t0, 0.0), np.minimum(t1, t_end)
    length = t1 - t0
    eps = 1e-6 * (1 + t_end)  # the walk reports float32 parameters
    sure = {tuple(c): (a, b) for c, a, b, ln in zip(grid.tolist(), t0, t1, length) if ln > eps}
    unsure = {tuple(c) for c, ln in zip(grid.tolist(), length) if abs(ln) <= eps}
    return sure, unsure


def check_walk(origin, direction, cell, steps):
    cells, t_enter, t_exit = proxima.traverse(origin, direction, cell, steps)
    assert cells.dtype == np.int64 and cells.shape == (len(cells), 3)
    assert t_enter.dtype == np.float64 and t_exit.dtype == np.float64
    assert t_enter.shape == t_exit.shape == (len(cells),)
    assert len(cells) == steps
    assert t_enter[0] == 0
    np.testing.assert_array_equal(t_enter[1:], t_exit[:-1])
    assert np.all(t_exit > t_enter)
    # each cell once
    assert len({tuple(c) for c in cells.tolist()}) == len(cells)
    # consecutive cells are neighbors (share a face, an edge or a corner)
    assert np.all(np.abs(np.diff(cells, axis=0)).max(axis=1) == 1)
    # the slab test over the walked stretch: the same cells, the same parameters
    o32, d32 = o.f32(origin), o.f32(direction)
    c32 = o.f32(np.broadcast_to(np.asarray(cell, dtype=np.float64), (3,)))
    sure, unsure = slab_cells(o32, d32, c32, float(t_exit[-1]))
    got = {tuple(c) for c in cells.tolist()}
    missing = set(sure) - got
    extra = got - set(sure) - unsure
    assert not missing and not extra, f"missing {sorted(missing)[:5]}, extra {sorted(extra)[:5]}"
    for c, a, b in zip(cells.tolist(), t_enter, t_exit):
        if tuple(c) in sure:
            ea, eb = sure[tuple(c)]
            tol = 1e-5 * (1 + abs(eb))
            assert abs(a - ea) <= tol and (abs(b - eb) <= tol or c == cells[-1].tolist()), (c, a, b, ea, eb)
    return cells, t_enter, t_exit


def test_stub_example():
    cells, t0, t1 = proxima.traverse([0.5, 0.5, 0.5], [1, 0, 0], 1.0, 3)
    assert cells.tolist() == [[0, 0, 0], [1, 0, 0], [2, 0, 0]]
    np.testing.assert_allclose(t0, [0, 0.5, 1.5])
    np.testing.assert_allclose(t1, [0.5, 1.5, 2.5])


def test_library_worked_example():
    """The library's documented walk (cell 0.3, origin (1, 0.2, 0.5))."""
    d = np.array([0.3, 0.5, 1.0])
    d /= np.linalg.norm(d)
    cells, t0, t1 = proxima.traverse([1, 0.2, 0.5], d, 0.3, 4)
    assert cells.tolist() == [[3, 0, 1], [3, 0, 2], [3, 1, 2], [3, 1, 3]]
    assert abs(t1[0] - 0.1158) < 1e-4 and abs(t1[1] - 0.2315) < 1e-4


def test_t_in_units_of_direction_length():
    """t is the parameter of origin + t * direction: a longer direction gives
    proportionally smaller t, the same cells."""
    c1, a1, b1 = proxima.traverse([0.5, 0.5, 0.5], [1, 0, 0], 1.0, 3)
    c2, a2, b2 = proxima.traverse([0.5, 0.5, 0.5], [4, 0, 0], 1.0, 3)
    assert c1.tolist() == c2.tolist()
    np.testing.assert_allclose(b2, b1 / 4)


@pytest.mark.parametrize("seed", range(12))
def test_random_walks(seed):
    rng = np.random.default_rng(seed)
    origin = rng.normal(0, 3, 3)
    direction = rng.normal(size=3) * rng.uniform(0.2, 5)
    if seed % 4 == 1:
        direction[rng.integers(3)] = 0.0  # a ray parallel to a plane of cells
    cell = rng.uniform(0.1, 2) if seed % 2 else rng.uniform(0.1, 2, 3)
    check_walk(origin, direction, cell, int(rng.integers(1, 60)))


def test_negative_directions_and_axis_rays():
    check_walk([0.25, -3.5, 7.75], [-1, 0, 0], 0.5, 20)
    check_walk([0.25, 0.5, 0.75], [0, 0, -2], [0.1, 0.2, 0.3], 15)
    check_walk([-0.3, 0.7, 1.1], [-1, -1, -1], 0.25, 25)


def test_origin_on_boundary_goes_to_the_entered_cell():
    cells, _, _ = proxima.traverse([1.0, 0.5, 0.5], [-1, 0, 0], 1.0, 2)
    assert cells.tolist() == [[0, 0, 0], [-1, 0, 0]]
    cells, _, _ = proxima.traverse([1.0, 0.5, 0.5], [1, 0, 0], 1.0, 2)
    assert cells.tolist() == [[1, 0, 0], [2, 0, 0]]


def test_diagonal_through_corners_steps_axes_together():
    """A ray through cell corners does not visit the cells it only grazes at a point."""
    cells, t0, t1 = proxima.traverse([0.5, 0.5, 0.5], [1, 1, 1], 1.0, 4)
    assert cells.tolist() == [[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]]
    np.testing.assert_allclose(t1, [0.5, 1.5, 2.5, 3.5])


def test_zero_steps():
    cells, t0, t1 = proxima.traverse([0, 0, 0], [1, 0, 0], 1.0, 0)
    assert cells.shape == (0, 3) and cells.dtype == np.int64
    assert t0.shape == (0,) and t1.shape == (0,)
