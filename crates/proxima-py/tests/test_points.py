"""proxima.Points, chamfer and hausdorff against brute force in numpy
(float64, and exact fractions on the sphere) and scipy's cKDTree as a second
oracle; bad input raises ValueError naming the argument."""

from fractions import Fraction

import numpy as np
import pytest
from scipy.spatial import cKDTree

import proxima


def clouds():
    rng = np.random.default_rng(5)
    uniform = rng.uniform(-1, 1, (2000, 3)).astype(np.float32)
    clustered = (np.repeat(np.arange(4), 500)[:, None] * 3.0 + rng.normal(0, 0.01, (2000, 3))).astype(np.float32)
    lattice = np.stack(np.meshgrid(np.arange(8), np.arange(8), np.arange(8), indexing="ij"), -1).reshape(-1, 3)
    return {"uniform": uniform, "clustered": clustered, "lattice": lattice.astype(np.float32)}


def exact_inside(p, q, r):
    """|q - p| <= r in exact fractions of the float32 coordinates."""
    s = sum((Fraction(float(b)) - Fraction(float(a))) ** 2 for a, b in zip(p, q))
    return s <= Fraction(r) ** 2


@pytest.mark.parametrize("name", ["uniform", "clustered", "lattice"])
def test_k_nearest_matches_brute_force_and_scipy(name):
    points = clouds()[name]
    queries = np.concatenate([points[::97], np.random.default_rng(1).uniform(-1, 8, (50, 3))]).astype(np.float32)
    cloud = proxima.Points(points)
    assert len(cloud) == len(points)
    for k in (1, 8, 32):
        distance, index = cloud.k_nearest(queries, k)
        assert distance.shape == index.shape == (len(queries), k)
        d2 = ((queries[:, None, :] - points[None, :, :]).astype(np.float32) ** 2).sum(-1, dtype=np.float32)
        expected = np.lexsort((np.broadcast_to(np.arange(len(points)), d2.shape), d2), axis=-1)[:, :k]
        np.testing.assert_array_equal(index, expected)
        # scipy agrees on the distances (its own float64 arithmetic).
        sd, _ = cKDTree(points.astype(np.float64)).query(queries.astype(np.float64), k)
        np.testing.assert_allclose(distance, np.asarray(sd).reshape(len(queries), k), rtol=1e-5, atol=1e-6)


def test_k_beyond_the_cloud_is_padded():
    cloud = proxima.Points(np.eye(3, dtype=np.float32))
    distance, index = cloud.k_nearest(np.zeros((2, 3)), 5)
    np.testing.assert_array_equal(index[:, 3:], -1)
    assert np.isinf(distance[:, 3:]).all()
    np.testing.assert_array_equal(index[:, :3], [[0, 1, 2], [0, 1, 2]])


@pytest.mark.parametrize("name", ["uniform", "lattice"])
def test_within_matches_scipy_as_sets_and_is_exact_on_the_sphere(name):
    points = clouds()[name]
    queries = points[::41]
    cloud = proxima.Points(points)
    tree = cKDTree(points.astype(np.float64))
    radii = [0.3, 1.0, np.nextafter(1.0, 2.0), np.nextafter(1.0, 0.0), 2.0]
    for r in radii:
        offsets, index, distance = cloud.within(queries, r)
        assert offsets.shape == (len(queries) + 1,) and offsets[0] == 0 and offsets[-1] == len(index)
        counts = cloud.count_within(queries, r)
        np.testing.assert_array_equal(np.diff(offsets), counts)
        for i, (q, theirs) in enumerate(zip(queries, tree.query_ball_point(queries.astype(np.float64), r))):
            ours = index[offsets[i] : offsets[i + 1]]
            # Nearest first.
            assert np.all(np.diff(distance[offsets[i] : offsets[i + 1]]) >= 0)
            # The exact oracle decides; scipy (float64, rounded) agrees off the sphere.
            expected = {j for j in range(len(points)) if exact_inside(q, points[j], r)} if name == "lattice" else set(theirs)
            assert set(ours.tolist()) == expected, (name, r, i)
        capped_offsets, capped, _ = cloud.within(queries, r, max_neighbors=4)
        for i in range(len(queries)):
            full = index[offsets[i] : offsets[i + 1]]
            np.testing.assert_array_equal(capped[capped_offsets[i] : capped_offsets[i + 1]], full[:4])


def test_pairs_within_match_scipy():
    points = clouds()["clustered"][:800]
    for r in (0.0, 0.01, 0.05):
        pairs = proxima.Points(points).pairs_within(r)
        expected = np.array(sorted(cKDTree(points.astype(np.float64)).query_pairs(r)), dtype=np.int64).reshape(-1, 2)
        np.testing.assert_array_equal(pairs, expected)


def test_chamfer_and_hausdorff_match_brute_force():
    c = clouds()
    a, b = c["uniform"][:700], c["clustered"][:900]
    # Distances in float64 from the float32 coordinates, as proxima measures them.
    d = np.sqrt(((a.astype(np.float64)[:, None, :] - b.astype(np.float64)[None, :, :]) ** 2).sum(-1))
    forward, backward = d.min(1), d.min(0)
    assert proxima.chamfer(a, b) == pytest.approx((forward**2).mean() + (backward**2).mean(), rel=1e-12)
    assert proxima.chamfer(a, b, squared=False) == pytest.approx(forward.mean() + backward.mean(), rel=1e-12)
    assert proxima.hausdorff(a, b) == pytest.approx(max(forward.max(), backward.max()), rel=1e-15)
    assert proxima.hausdorff(proxima.Points(a), b, one_sided=True) == pytest.approx(forward.max(), rel=1e-15)
    assert proxima.chamfer(a, a) == 0.0


def test_bad_input_names_the_argument():
    cloud = proxima.Points(np.eye(3))
    with pytest.raises(ValueError, match="^points: the point cloud is empty"):
        proxima.Points(np.zeros((0, 3)))
    with pytest.raises(ValueError, match=r"^points\[1\]"):
        proxima.Points([[0, 0, 0], [np.nan, 0, 0]])
    with pytest.raises(ValueError, match="^k"):
        cloud.k_nearest(np.zeros((1, 3)), 0)
    with pytest.raises(ValueError, match="^k"):
        cloud.k_nearest(np.zeros((1, 3)), -2)
    with pytest.raises(ValueError, match="^r = -1"):
        cloud.within(np.zeros((1, 3)), -1.0)
    with pytest.raises(ValueError, match="^r = NaN"):
        cloud.count_within(np.zeros((1, 3)), float("nan"))
    with pytest.raises(ValueError, match="^max_neighbors"):
        cloud.within(np.zeros((1, 3)), 1.0, max_neighbors=0)
    with pytest.raises(ValueError, match=r"^queries\[1\]"):
        cloud.within([[0, 0, 0], [np.inf, 0, 0]], 1.0)
    with pytest.raises(ValueError, match="^k 1073741824: needs about"):
        cloud.k_nearest(np.zeros((1 << 20, 3), np.float32), 1 << 30)
    with pytest.raises(ValueError, match="^a: the point cloud is empty"):
        proxima.chamfer(np.zeros((0, 3)), np.eye(3))
