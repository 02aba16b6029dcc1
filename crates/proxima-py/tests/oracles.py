"""Independent numpy oracles for the proxima tests (float64, brute force).

Nothing here calls proxima: every function is the textbook computation over
all elements, vectorized with numpy, used as the reference answer.
"""

import numpy as np

CHUNK = 256  # query rows per block (keeps the (n, m, 3) temporaries small)


def f32(a):
    """The float32 rounding of ``a``, back in float64 (what proxima stores)."""
    return np.asarray(a, dtype=np.float64).astype(np.float32).astype(np.float64)


# --- mesh pieces -----------------------------------------------------------------


def face_list(faces):
    """Faces as a list of int arrays, from an (F, k) array or a list."""
    if isinstance(faces, np.ndarray) and faces.ndim == 2:
        return [np.asarray(f, dtype=np.int64) for f in faces]
    return [np.asarray(f, dtype=np.int64) for f in faces]


def fan_triangles(faces):
    """Fan triangulation (v0, vi, vi+1) of every face: (T, 3) indices and the
    source face of each triangle."""
    tris, src = [], []
    for fi, f in enumerate(face_list(faces)):
        for i in range(1, len(f) - 1):
            tris.append((f[0], f[i], f[i + 1]))
            src.append(fi)
    return np.array(tris, dtype=np.int64).reshape(-1, 3), np.array(src, dtype=np.int64)


def unique_edges(faces):
    """Unique undirected edges [low, high] numbered in order of first
    appearance, walking faces in order and each face's edges (v0,v1), ...,
    (vk-1,v0); an edge from a vertex to itself is skipped."""
    seen = {}
    for f in face_list(faces):
        k = len(f)
        for i in range(k):
            a, b = int(f[i]), int(f[(i + 1) % k])
            if a == b:
                continue
            key = (min(a, b), max(a, b))
            if key not in seen:
                seen[key] = len(seen)
    out = np.zeros((len(seen), 2), dtype=np.int64)
    for key, i in seen.items():
        out[i] = key
    return out


# --- distances ---------------------------------------------------------------------


def _dot(x, y):
    return np.sum(x * y, axis=-1)


def seg_dist(p, a, b):
    """Distances from points p to segments a-b (all (..., 3), broadcast)."""
    ab = b - a
    ap = p - a
    den = _dot(ab, ab)
    num = _dot(ap, ab)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(den > 0, num / np.where(den > 0, den, 1.0), 0.0)
    t = np.clip(t, 0.0, 1.0)
    d = ap - t[..., None] * ab
    return np.sqrt(_dot(d, d))


def tri_dist(p, a, b, c):
    """Distances from points p to triangles (a, b, c) (all (..., 3), broadcast):
    the nearest of the three edges, or the plane when p projects inside."""
    d = np.minimum(np.minimum(seg_dist(p, a, b), seg_dist(p, b, c)), seg_dist(p, c, a))
    n = np.cross(b - a, c - a)
    nn = np.sqrt(_dot(n, n))
    ok = nn > 0
    # sign of ((edge) x (p - start)) . n for the three edges: inside when all >= 0
    s0 = _dot(np.cross(b - a, p - a), n)
    s1 = _dot(np.cross(c - b, p - b), n)
    s2 = _dot(np.cross(a - c, p - c), n)
    inside = (s0 >= 0) & (s1 >= 0) & (s2 >= 0) & ok
    with np.errstate(divide="ignore", invalid="ignore"):
        plane = np.abs(_dot(p - a, n)) / np.where(ok, nn, 1.0)
    return np.where(inside, np.minimum(plane, d), d)


def _seg_dist(p, a, b):
    return seg_dist(p[:, None, :], a[None], b[None])


def _tri_dist(p, a, b, c):
    return tri_dist(p[:, None, :], a[None], b[None], c[None])


def _blocks(points, fn):
    points = np.asarray(points, dtype=np.float64)
    out = [fn(points[i : i + CHUNK]) for i in range(0, len(points), CHUNK)]
    return np.concatenate(out, axis=0) if out else np.zeros((0, 0))


def triangle_distances(points, vertices, triangles):
    """(n, T) distances from each point to each triangle."""
    v = np.asarray(vertices, dtype=np.float64)
    a, b, c = v[triangles[:, 0]], v[triangles[:, 1]], v[triangles[:, 2]]
    return _blocks(points, lambda p: _tri_dist(p, a, b, c))


def face_distances(points, vertices, faces):
    """(n, F) distances to each face (a polygon is its fan of triangles)."""
    tris, src = fan_triangles(faces)
    d = triangle_distances(points, vertices, tris)
    nf = len(face_list(faces))
    out = np.full((d.shape[0], nf), np.inf)
    for t, f in enumerate(src):
        np.minimum(out[:, f], d[:, t], out=out[:, f])
    return out


def edge_distances(points, vertices, edges):
    v = np.asarray(vertices, dtype=np.float64)
    a, b = v[edges[:, 0]], v[edges[:, 1]]
    return _blocks(points, lambda p: _seg_dist(p, a, b))


def vertex_distances(points, vertices):
    v = np.asarray(vertices, dtype=np.float64)

    def fn(p):
        d = p[:, None, :] - v[None]
        return np.sqrt(np.einsum("nmj,nmj->nm", d, d))

    return _blocks(points, fn)


def element_distances(points, vertices, faces, primitives):
    """(n, elements) distances for primitives 'faces', 'polygons', 'vertices', 'edges'."""
    if primitives in ("faces", "polygons"):
        return face_distances(points, vertices, faces)
    if primitives == "edges":
        return edge_distances(points, vertices, unique_edges(faces))
    if primitives == "vertices":
        return vertex_distances(points, vertices)
    raise ValueError(primitives)


# --- rays --------------------------------------------------------------------------


def moller_trumbore(origins, directions, vertices, triangles):
    """(n, T) ray parameters t >= 0 (along the given directions) of the hits of
    each ray with each triangle, inf where the ray misses (float64)."""
    v = np.asarray(vertices, dtype=np.float64)
    a, b, c = v[triangles[:, 0]], v[triangles[:, 1]], v[triangles[:, 2]]
    e1, e2 = b - a, c - a
    out = []
    for i in range(0, len(origins), CHUNK):
        o = origins[i : i + CHUNK][:, None, :]
        d = directions[i : i + CHUNK][:, None, :]
        pvec = np.cross(d, e2[None])
        det = np.einsum("nmj,mj->nm", pvec, e1)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / det
            tvec = o - a[None]
            u = np.einsum("nmj,nmj->nm", tvec, pvec) * inv
            qvec = np.cross(tvec, e1[None])
            w = np.einsum("nmj,nmj->nm", d, qvec) * inv
            t = np.einsum("nmj,mj->nm", qvec, e2) * inv
        hit = (det != 0) & (u >= 0) & (w >= 0) & (u + w <= 1) & (t >= 0) & np.isfinite(t)
        out.append(np.where(hit, t, np.inf))
    return np.concatenate(out, axis=0)


# --- boxes -------------------------------------------------------------------------


def tri_box_separation(lo, hi, a, b, c):
    """Separating-axis test of triangles against boxes, float64.

    lo, hi: (n, 3) boxes; a, b, c: (m, 3) triangles. Returns (n, m): the
    largest gap over the 13 axes divided by the axis length (> 0: separated,
    <= 0: the closed box and the triangle share a point). Degenerate axes (zero
    cross products) are skipped, which is right for the closed sets."""
    center = (lo + hi) / 2
    half = (hi - lo) / 2
    n_, m_ = len(lo), len(a)
    best = np.full((n_, m_), -np.inf)
    A = a[None] - center[:, None]
    B = b[None] - center[:, None]
    C = c[None] - center[:, None]
    e = [b - a, c - b, a - c]
    axes = [np.broadcast_to(np.eye(3)[k], (m_, 3)) for k in range(3)]
    axes.append(np.cross(e[0], e[1]))
    for i in range(3):
        for k in range(3):
            axes.append(np.cross(np.eye(3)[k][None], e[i]))
    for ax in axes:
        length = np.sqrt(np.einsum("mj,mj->m", ax, ax))
        ok = length > 0
        pa = np.einsum("nmj,mj->nm", A, ax)
        pb = np.einsum("nmj,mj->nm", B, ax)
        pc = np.einsum("nmj,mj->nm", C, ax)
        r = np.einsum("nj,mj->nm", half, np.abs(ax))
        gap = np.maximum(np.minimum(np.minimum(pa, pb), pc) - r, -r - np.maximum(np.maximum(pa, pb), pc))
        with np.errstate(divide="ignore", invalid="ignore"):
            gap = np.where(ok[None], gap / np.where(ok, length, 1.0)[None], -np.inf)
        best = np.maximum(best, gap)
    return best


def slab(origin, direction, lo, hi):
    """Ray/box slab test in float64: (t_near, t_far) per box (lo, hi (n, 3)).
    Along an axis where the direction is zero the ray is inside when the
    origin lies in the half-open [lo, hi)."""
    origin = np.asarray(origin, dtype=np.float64)
    direction = np.asarray(direction, dtype=np.float64)
    t0 = np.full(len(lo), -np.inf)
    t1 = np.full(len(lo), np.inf)
    for ax in range(3):
        if direction[ax] == 0:
            inside = (lo[:, ax] <= origin[ax]) & (origin[ax] < hi[:, ax])
            t0 = np.where(inside, t0, np.inf)
            t1 = np.where(inside, t1, -np.inf)
        else:
            a = (lo[:, ax] - origin[ax]) / direction[ax]
            b = (hi[:, ax] - origin[ax]) / direction[ax]
            t0 = np.maximum(t0, np.minimum(a, b))
            t1 = np.minimum(t1, np.maximum(a, b))
    return t0, t1


# --- cameras -----------------------------------------------------------------------


def look_at(eye, target, up):
    eye, target, up = (np.asarray(x, dtype=np.float64) for x in (eye, target, up))
    f = target - eye
    f /= np.linalg.norm(f)
    s = np.cross(f, up)
    s /= np.linalg.norm(s)
    u = np.cross(s, f)
    m = np.eye(4)
    m[0, :3], m[1, :3], m[2, :3] = s, u, -f
    m[:3, 3] = -m[:3, :3] @ eye
    return m


def perspective(fovy_deg, aspect, near, far):
    f = 1.0 / np.tan(np.radians(fovy_deg) / 2)
    m = np.zeros((4, 4))
    m[0, 0] = f / aspect
    m[1, 1] = f
    m[2, 2] = (far + near) / (near - far)
    m[2, 3] = 2 * far * near / (near - far)
    m[3, 2] = -1.0
    return m


def clip_planes(matrix):
    """The six closed half-spaces (a, b, c, d) . (x, y, z, 1) >= 0 of
    -w <= x, y, z <= w for clip = M @ (x, y, z, 1)."""
    m = np.asarray(matrix, dtype=np.float64)
    w = m[3]
    return np.array([w + m[0], w - m[0], w + m[1], w - m[1], w + m[2], w - m[2]])


def frustum_margins(matrix, points):
    """(n, 6) plane values of points (>= 0 on the inside of each plane), float64."""
    p = np.asarray(points, dtype=np.float64)
    planes = clip_planes(matrix)
    return p @ planes[:, :3].T + planes[:, 3][None]
