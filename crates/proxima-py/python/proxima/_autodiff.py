"""The numpy side of the autograd adapters (:mod:`proxima.torch`,
:mod:`proxima.jax`): the values and the vector-Jacobian products, computed
by the Rust library; the adapters only move arrays.

Convention (the library's ``proxima::sdf`` gradient):

- signed distance ``s(p) = sign * |p - c|``: ``ds/dp = sign * (p - c) / |p - c|``,
  the closest feature's pseudonormal on the surface;
- unsigned distance ``d(p) = |p - c|``: ``dd/dp = (p - c) / |p - c|``, 0 on the
  surface (where it has no gradient);
- with respect to the closest triangle's corners ``v_k``, the feature held
  fixed: ``-w_k`` times the gradient with respect to ``p`` (``w`` the closest
  point's barycentric weights; the envelope theorem).
"""

import numpy as np

KINDS = ("signed", "unsigned")


def evaluate(mesh, points, kind, sign="winding"):
    """``(value (N,), grad_points (N, 3), corners (N, 3), weights (N, 3))``
    for ``points`` (N, 3) as float64 numpy arrays: the distance of ``kind``
    and what its vector-Jacobian products need."""
    if kind not in KINDS:
        raise ValueError(f"kind: {kind!r} is not one of {KINDS}")
    points = np.asarray(points)
    answers = mesh.closest_points(points, return_barycentric=True)
    if kind == "signed":
        value, grad = mesh.signed_distance(points, sign=sign, return_gradient=True)
    else:
        value = answers.distance
        away = points.astype(np.float32).astype(np.float64) - answers.closest
        length = np.linalg.norm(away, axis=1, keepdims=True)
        grad = np.divide(away, length, out=np.zeros_like(away), where=length > 0)
    return value, grad, answers.corners, answers.barycentric


def vertex_vjp(cotangent, grad, corners, weights, vertex_count):
    """The gradient with respect to the mesh's vertices (V, 3) of
    ``sum(cotangent * value)``: ``-w_k * cotangent * grad`` added to corner
    ``k``'s vertex."""
    per_point = cotangent[:, None] * grad
    out = np.zeros((vertex_count, 3))
    for k in range(3):
        np.add.at(out, corners[:, k], -weights[:, k : k + 1] * per_point)
    return out


def check_vertices(mesh, vertices):
    """Refuses ``vertices`` that are not the mesh's own (gradients would be
    routed to the wrong positions)."""
    if vertices.shape != mesh.vertices.shape:
        raise ValueError(f"vertices: shape {vertices.shape} is not the mesh's {mesh.vertices.shape}")
    if not np.array_equal(np.asarray(vertices, dtype=np.float32), mesh.vertices):
        raise ValueError("vertices: not the mesh's vertices (build the Mesh from these positions first)")
