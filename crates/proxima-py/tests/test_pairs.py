"""Two meshes placed by rigid poses, and one mesh against itself:
proxima.distance, Mesh.intersects, intersecting_pairs, pairs_within,
self_intersections. Oracles: numpy brute force over all triangle pairs
(an independent triangle-triangle crossing test for random triangles in
general position; point-triangle and segment-segment distances), exact
offsets of unit cubes, and batch == one pose at a time."""

import numpy as np
import pytest

import oracles as o
import proxima
from conftest import assert_not_panic, cube_arrays, random_soup

V, F = cube_arrays()
CUBE = proxima.Mesh(V, F)


def shift(x, y=0.0, z=0.0):
    m = np.eye(4)
    m[:3, 3] = [x, y, z]
    return m


def rotation(rng):
    """A random rotation matrix (QR of a gaussian matrix, determinant +1)."""
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q


def random_pose(rng, reach):
    m = np.eye(4)
    m[:3, :3] = rotation(rng)
    m[:3, 3] = rng.uniform(-reach, reach, 3)
    return m


def placed(vertices, faces, pose):
    """The triangles (T, 3, 3) in float64, placed by pose as R p + t."""
    v = np.asarray(vertices, dtype=np.float64)
    w = v @ pose[:3, :3].T + pose[:3, 3]
    return w[np.asarray(faces)]


def orient(a, b, c, d):
    """Sign of the volume of (a, b, c, d)."""
    return np.sign(np.dot(np.cross(b - a, c - a), d - a))


def segment_crosses(p, q, tri):
    """The segment p-q crosses triangle tri (general position: no zeros)."""
    a, b, c = tri
    if orient(a, b, c, p) == orient(a, b, c, q):
        return False
    s = [orient(p, q, a, b), orient(p, q, b, c), orient(p, q, c, a)]
    return s[0] == s[1] == s[2]


def triangles_meet(t, u):
    """Two triangles in general position meet iff an edge of one crosses the other."""
    for x, y in ((t, u), (u, t)):
        for i in range(3):
            if segment_crosses(x[i], x[(i + 1) % 3], y):
                return True
    return False


def segment_distance(p1, q1, p2, q2):
    """Distance between segments p1-q1 and p2-q2 (Ericson, clamped)."""
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a, e, f = d1 @ d1, d2 @ d2, d2 @ r
    c, b = d1 @ r, d1 @ d2
    den = a * e - b * b
    s = np.clip((b * f - c * e) / den, 0.0, 1.0) if den > 0 else 0.0
    t = (b * s + f) / e
    if t < 0.0:
        t, s = 0.0, np.clip(-c / a, 0.0, 1.0)
    elif t > 1.0:
        t, s = 1.0, np.clip((b - c) / a, 0.0, 1.0)
    return float(np.linalg.norm((p1 + d1 * s) - (p2 + d2 * t)))


def triangle_distance(t, u):
    """Distance between two triangles: 0 when they meet, else the nearest of
    the six vertex-triangle and nine edge-edge distances."""
    if triangles_meet(t, u):
        return 0.0
    best = min(
        min(float(o.tri_dist(p, *u)) for p in t),
        min(float(o.tri_dist(p, *t)) for p in u),
    )
    for i in range(3):
        for j in range(3):
            best = min(best, segment_distance(t[i], t[(i + 1) % 3], u[j], u[(j + 1) % 3]))
    return best


def brute(ta, tb, within=None):
    """Sorted meeting (or within) face pairs and the distance, over all pairs."""
    pairs, best = [], np.inf
    for i, t in enumerate(ta):
        for j, u in enumerate(tb):
            d = triangle_distance(t, u)
            best = min(best, d)
            if (d == 0.0) if within is None else (d <= within):
                pairs.append((i, j))
    return np.array(sorted(pairs), dtype=np.int64).reshape(-1, 2), best


@pytest.mark.parametrize("seed", range(12))
def test_random_soups_match_brute_force(seed):
    rng = np.random.default_rng(seed)
    va, fa = random_soup(12, seed)
    vb, fb = random_soup(10, 100 + seed)
    a, b = proxima.Mesh(va, fa), proxima.Mesh(vb, fb)
    pose_a, pose_b = random_pose(rng, 0.3), random_pose(rng, 0.6)
    ta, tb = placed(va, fa, pose_a), placed(vb, fb, pose_b)
    pairs, best = brute(ta, tb)
    got = a.intersecting_pairs(b, pose_b, pose_self=pose_a)
    assert got.dtype == np.int64 and got.shape == pairs.shape
    np.testing.assert_array_equal(got, pairs)
    assert a.intersects(b, pose_b, pose_self=pose_a) is bool(len(pairs))
    d = proxima.distance(a, b, pose_a, pose_b)
    assert d.distance == pytest.approx(best, rel=1e-9, abs=1e-12)
    # The reported points lie on the reported faces and are that far apart.
    assert np.linalg.norm(d.point_a - d.point_b) == pytest.approx(d.distance, rel=1e-9, abs=1e-12)
    assert float(o.tri_dist(d.point_a, *ta[d.face_a])) < 1e-12
    assert float(o.tri_dist(d.point_b, *tb[d.face_b])) < 1e-12
    # Barycentric coordinates rebuild the points.
    np.testing.assert_allclose(d.barycentric_a @ ta[d.triangle_a], d.point_a, atol=1e-12)
    np.testing.assert_allclose(d.barycentric_b @ tb[d.triangle_b], d.point_b, atol=1e-12)
    distance, point_a, point_b, face_a, face_b = d
    assert (distance, face_a, face_b) == (d.distance, d.face_a, d.face_b)
    # pairs_within against the same brute force, at a margin from the pairs' distances.
    margin = 0.05
    within, _ = brute(ta, tb, within=margin)
    np.testing.assert_array_equal(a.pairs_within(b, margin, pose_b, pose_self=pose_a), within)


@pytest.mark.parametrize("seed", range(6))
def test_self_intersections_match_brute_force(seed):
    v, f = random_soup(16, 200 + seed)
    mesh = proxima.Mesh(v, f)
    t = placed(v, f, np.eye(4))
    expected = sorted((i, j) for i in range(len(t)) for j in range(i + 1, len(t)) if triangles_meet(t[i], t[j]))
    got = mesh.self_intersections(threads=2)
    assert got.dtype == np.int64
    np.testing.assert_array_equal(got, np.array(expected, dtype=np.int64).reshape(-1, 2))


def test_cubes_touch_exactly_and_apart_by_one_ulp():
    for x, meets in [(1.0, True), (np.nextafter(1.0, 0), True), (np.nextafter(1.0, 2), False), (-1.0, True)]:
        assert CUBE.intersects(CUBE, shift(x)) is meets, x
        d = proxima.distance(CUBE, CUBE, pose_b=shift(x))
        assert d.distance == max(x - 1.0, 0.0), x
    # float32 poses are read as float64 (the same values).
    assert CUBE.intersects(CUBE, shift(1.0).astype(np.float32))
    d = proxima.distance(CUBE, CUBE, pose_b=shift(3.0))
    # Any pair of points facing each other across the gap (ties go to the lowest triangles).
    assert d.distance == 2.0 and (d.point_a[0], d.point_b[0]) == (1.0, 3.0)
    assert d.point_a[1:].tolist() == d.point_b[1:].tolist()
    assert d.point_a.shape == (3,) and d.point_a.dtype == np.float64
    # pose_a moves a: the same gap.
    assert proxima.distance(CUBE, CUBE, shift(-3.0)).distance == 2.0


def test_max_distance_answers_below_it_only():
    far = shift(3.0)  # two apart
    assert proxima.distance(CUBE, CUBE, pose_b=far, max_distance=2.0) is None
    assert proxima.distance(CUBE, CUBE, pose_b=far, max_distance=np.nextafter(2.0, 3)).distance == 2.0
    assert proxima.distance(CUBE, CUBE, pose_b=far, max_distance=np.inf).distance == 2.0
    # pairs_within: at exactly the gap, and one ulp below it.
    assert len(CUBE.pairs_within(CUBE, 2.0, far)) > 0
    assert CUBE.pairs_within(CUBE, np.nextafter(2.0, 0), far).shape == (0, 2)


def test_batches_equal_one_pose_at_a_time():
    rng = np.random.default_rng(7)
    poses = np.stack([random_pose(rng, 2.0) for _ in range(40)] + [shift(1.0), shift(5.0)])
    distance, point_a, point_b, face_a, face_b = proxima.distance(CUBE, CUBE, pose_b=poses, threads=2)
    assert distance.shape == (42,) and point_a.shape == (42, 3) and face_a.dtype == np.int64
    hits = CUBE.intersects(CUBE, poses)
    assert hits.shape == (42,) and hits.dtype == np.bool_
    assert hits.any() and not hits.all()
    for i, pose in enumerate(poses):
        d = proxima.distance(CUBE, CUBE, pose_b=pose)
        assert distance[i] == d.distance
        assert point_a[i].tolist() == d.point_a.tolist() and point_b[i].tolist() == d.point_b.tolist()
        assert (face_a[i], face_b[i]) == (d.face_a, d.face_b)
        assert hits[i] == CUBE.intersects(CUBE, pose) == (d.distance == 0.0)
    # With max_distance: inf, NaN points and -1 faces beyond it.
    below = proxima.distance(CUBE, CUBE, pose_b=poses, max_distance=1.0)
    beyond = distance >= 1.0
    assert np.all(np.isinf(below[0][beyond])) and np.all(below[3][beyond] == -1)
    assert np.all(np.isnan(below[1][beyond]))
    np.testing.assert_array_equal(below[0][~beyond], distance[~beyond])
    # An identity pose_a is allowed with a stack.
    np.testing.assert_array_equal(proxima.distance(CUBE, CUBE, np.eye(4), poses)[0], distance)


def test_empty_answers_have_their_shapes():
    far = shift(10.0)
    assert CUBE.intersecting_pairs(CUBE, far).shape == (0, 2)
    assert CUBE.intersecting_pairs(CUBE, far).dtype == np.int64
    assert CUBE.self_intersections().shape == (0, 2)


def _not_rigid(scale):
    m = np.eye(4)
    m[0, 0] = scale
    return m


def _nan_pose():
    m = np.eye(4)
    m[1, 3] = np.nan
    return m


def _far_pose():
    return shift(0.0, 2e38)


POINTS_ONLY = proxima.Mesh(V, np.zeros((0, 3), dtype=np.int64))

# (id, callable, words the ValueError message must start with or contain)
BAD = [
    ("pose_b scaled", lambda: proxima.distance(CUBE, CUBE, pose_b=_not_rigid(2.0)), ["pose_b: the pose is not a rotation"]),
    ("pose_b just beyond the tolerance", lambda: proxima.distance(CUBE, CUBE, pose_b=_not_rigid(1 + 6e-7)), ["pose_b: the pose is not a rotation"]),
    ("pose_b mirrored", lambda: proxima.distance(CUBE, CUBE, pose_b=_not_rigid(-1.0)), ["pose_b: the pose is a reflection"]),
    ("pose_b NaN", lambda: proxima.distance(CUBE, CUBE, pose_b=_nan_pose()), ["pose_b: the pose has an entry that is not a finite"]),
    ("pose_b (3, 3)", lambda: proxima.distance(CUBE, CUBE, pose_b=np.eye(3)), ["pose_b: expected shape (4, 4) or (P, 4, 4)"]),
    ("pose_b strings", lambda: proxima.distance(CUBE, CUBE, pose_b=np.eye(4).astype(str)), ["pose_b"]),
    ("pose_b transposed", lambda: proxima.distance(CUBE, CUBE, pose_b=shift(1.0).T), ["pose_b: the bottom row"]),
    ("pose_b beyond 1e38", lambda: proxima.distance(CUBE, CUBE, pose_b=_far_pose()), ["pose_b: a translation coordinate of 2e38"]),
    ("pose_b[1] of a stack", lambda: proxima.distance(CUBE, CUBE, pose_b=np.stack([np.eye(4), _not_rigid(2.0)])), ["pose_b[1]: the pose is not a rotation"]),
    ("pose_a stack", lambda: proxima.distance(CUBE, CUBE, pose_a=np.stack([np.eye(4)] * 2)), ["pose_a: expected one pose"]),
    ("pose_a moved with a stack", lambda: proxima.distance(CUBE, CUBE, shift(1.0), np.stack([np.eye(4)] * 2)), ["pose_a: a stack of poses"]),
    ("a without faces", lambda: proxima.distance(POINTS_ONLY, CUBE), ["a: "]),
    ("b without faces", lambda: proxima.distance(CUBE, POINTS_ONLY), ["b: "]),
    ("max_distance negative", lambda: proxima.distance(CUBE, CUBE, max_distance=-1.0), ["max_distance: must be at least 0"]),
    ("max_distance NaN", lambda: proxima.distance(CUBE, CUBE, max_distance=np.nan), ["max_distance: must be at least 0"]),
    ("threads 0", lambda: proxima.distance(CUBE, CUBE, threads=0), ["threads: 0"]),
    ("pose mirrored", lambda: CUBE.intersects(CUBE, _not_rigid(-1.0)), ["pose: the pose is a reflection"]),
    ("pose_self NaN", lambda: CUBE.intersecting_pairs(CUBE, pose_self=_nan_pose()), ["pose_self: the pose has an entry"]),
    ("pose_self moved with a stack", lambda: CUBE.intersects(CUBE, np.stack([np.eye(4)] * 2), pose_self=shift(1.0)), ["pose_self: a stack"]),
    ("pairs of a stack", lambda: CUBE.intersecting_pairs(CUBE, np.stack([np.eye(4)] * 2)), ["pose: expected one pose"]),
    ("pose beyond 1e38", lambda: CUBE.intersects(CUBE, shift(-2e38)), ["pose: a translation coordinate of -2e38"]),
    ("other without faces", lambda: CUBE.intersects(POINTS_ONLY), ["other: "]),
    ("self without faces", lambda: POINTS_ONLY.self_intersections(), ["self: "]),
    ("distance negative", lambda: CUBE.pairs_within(CUBE, -0.5), ["distance: must be at least 0"]),
    ("distance infinite", lambda: CUBE.pairs_within(CUBE, np.inf), ["distance: must be finite"]),
]


@pytest.mark.parametrize("case", BAD, ids=[c[0] for c in BAD])
def test_bad_input_is_a_value_error_naming_the_argument(case):
    _, call, words = case
    with pytest.raises(BaseException) as info:
        call()
    assert_not_panic(info.value)
    assert isinstance(info.value, ValueError), repr(info.value)
    message = str(info.value)
    assert any(w in message for w in words), message


def test_translation_at_the_bound_is_answered():
    assert not CUBE.intersects(CUBE, shift(1e38))
    assert proxima.distance(CUBE, CUBE, pose_b=shift(0.0, 0.0, -1e38)).distance == pytest.approx(1e38 - 1.0)


def test_a_stack_beyond_the_memory_budget_is_refused_before_it_is_read(monkeypatch):
    monkeypatch.setenv("PROXIMA_MEMORY_BUDGET", "1000")
    # A broadcast view: two million poses that take 128 bytes of memory.
    poses = np.broadcast_to(np.eye(4), (2_000_000, 4, 4))
    with pytest.raises(ValueError, match=r"^pose_b 2000000: needs about .* more than the memory budget of 1000 bytes"):
        proxima.distance(CUBE, CUBE, pose_b=poses)
    with pytest.raises(ValueError, match=r"^pose 2000000: needs about"):
        CUBE.intersects(CUBE, poses)


def surface_samples(v, f, n, rng):
    """n points uniform in barycentric coordinates on random triangles."""
    t = rng.integers(0, len(f), n)
    u, w = rng.random(n), rng.random(n)
    flip = u + w > 1
    u[flip], w[flip] = 1 - u[flip], 1 - w[flip]
    a, b, c = (v[f[t, i]].astype(np.float64) for i in range(3))
    return a + (b - a) * u[:, None] + (c - a) * w[:, None]


@pytest.mark.parametrize("seed", [1, 2])
def test_hausdorff_between_meshes_brackets_brute_force(seed):
    """The bounds bracket brute force over every triangle (oracles.py): the
    lower one is at least every vertex's distance and is the distance of
    the pair of points it returns; the upper one is at least every sample's."""
    va, fa = random_soup(30, seed)
    vb, fb = random_soup(40, seed + 10)
    a, b = proxima.Mesh(va, fa), proxima.Mesh(vb, fb)
    h = proxima.hausdorff(a, b, tolerance=1e-4)
    assert isinstance(h, proxima.Hausdorff)
    assert 0 <= h.upper - h.lower <= 1e-4 and float(h) == h.upper
    rng = np.random.default_rng(seed)
    forward = o.triangle_distances(np.concatenate([va, surface_samples(va, fa, 3000, rng)]), vb, fb).min(1)
    backward = o.triangle_distances(np.concatenate([vb, surface_samples(vb, fb, 3000, rng)]), va, fa).min(1)
    vertices = max(forward[: len(va)].max(), backward[: len(vb)].max())
    assert h.lower >= vertices - 1e-12
    assert h.upper >= max(forward.max(), backward.max()) - 1e-12
    # The pair realizes the lower bound, each point on its face.
    assert np.linalg.norm(h.point_a - h.point_b) == pytest.approx(h.lower, rel=1e-9)
    assert o.triangle_distances(h.point_a[None], va, fa[h.face_a][None])[0, 0] < 1e-9
    assert o.triangle_distances(h.point_b[None], vb, fb[h.face_b][None])[0, 0] < 1e-9
    far = h.point_a if h.from_a else h.point_b
    other = (vb, fb) if h.from_a else (va, fa)
    assert o.triangle_distances(far[None], *other).min() == pytest.approx(h.lower, rel=1e-9)
    one = proxima.hausdorff(a, b, one_sided=True, tolerance=1e-4)
    assert one.from_a and one.upper - one.lower <= 1e-4
    assert one.lower >= forward[: len(va)].max() - 1e-12 and one.upper >= forward.max() - 1e-12


def test_hausdorff_between_meshes_exact_cases_and_libigl():
    # The cube against itself, and against a copy lifted by 0.25: every
    # point of the top face is 0.25 from the lifted cube's surface, and
    # the bottom face of the lifted cube is 0.25 from the cube's.
    assert (proxima.hausdorff(CUBE, CUBE).lower, proxima.hausdorff(CUBE, CUBE).upper) == (0.0, 0.0)
    lifted = proxima.Mesh(V + np.float32([0, 0, 0.25]), F)
    h = proxima.hausdorff(CUBE, lifted, tolerance=1e-6)
    assert h.lower == 0.25 and 0.25 <= h.upper <= 0.25 + 1e-6
    # libigl's point-to-mesh distance as a second oracle on the samples.
    import igl

    rng = np.random.default_rng(3)
    samples = surface_samples(V, F, 2000, rng)
    lifted_v = (V + np.float32([0, 0, 0.25])).astype(np.float64)
    d2, _, _ = igl.point_mesh_squared_distance(samples, lifted_v, np.asarray(F))
    assert np.sqrt(d2).max() <= h.upper + 1e-9


def test_hausdorff_bad_input_names_the_argument():
    for bad in (0.0, -1.0, float("nan"), 1e-12):
        with pytest.raises(ValueError, match="^tolerance: must be positive"):
            proxima.hausdorff(CUBE, CUBE, tolerance=bad)
    with pytest.raises(ValueError, match="^b: a is a Mesh, so b must be a Mesh too"):
        proxima.hausdorff(CUBE, V)
    with pytest.raises(ValueError, match="^a: b is a Mesh"):
        proxima.hausdorff(V, CUBE)
    with pytest.raises(ValueError, match="^tolerance: applies to meshes"):
        proxima.hausdorff(V, V, tolerance=0.1)
    with pytest.raises(ValueError, match="^a: "):
        proxima.hausdorff(proxima.Mesh(V, np.zeros((0, 3), np.int64)), CUBE)
