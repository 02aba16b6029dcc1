"""JAX differentiation for proxima's distances (needs ``jax``; CPU).

>>> import jax, jax.numpy as jnp, proxima, proxima.jax
>>> mesh = proxima.noisy_icosphere(8)
>>> points = jnp.zeros((4, 3))
>>> jax.grad(lambda p: proxima.jax.signed_distance(mesh, p).sum())(points).shape
(4, 3)

The values come from the Rust library through ``jax.pure_callback`` (so
the functions work under ``jit``), with a ``custom_vjp`` for ``grad``:
gradients with respect to the points and, through the ``vertices``
variants, the mesh's vertices (:mod:`proxima._autodiff` states the
convention). Forward-mode (``jvp``) and higher derivatives are not
available.
"""

import functools

import jax
import jax.numpy as jnp
import numpy as np

from . import _autodiff


def _host(mesh, kind, sign, points):
    value, grad, corners, weights = _autodiff.evaluate(mesh, np.asarray(points), kind, sign)
    dtype = np.asarray(points).dtype
    return (
        np.asarray(value, dtype=dtype),
        np.asarray(grad, dtype=dtype),
        corners.astype(np.int32),
        np.asarray(weights, dtype=dtype),
    )


def _evaluate(mesh, kind, sign, points):
    n, dtype = points.shape[0], points.dtype
    shapes = (
        jax.ShapeDtypeStruct((n,), dtype),
        jax.ShapeDtypeStruct((n, 3), dtype),
        jax.ShapeDtypeStruct((n, 3), jnp.int32),
        jax.ShapeDtypeStruct((n, 3), dtype),
    )
    return jax.pure_callback(functools.partial(_host, mesh, kind, sign), shapes, points)


@functools.partial(jax.custom_vjp, nondiff_argnums=(0, 1, 2))
def _distance(mesh, kind, sign, points, vertices):
    return _evaluate(mesh, kind, sign, points)[0]


def _forward(mesh, kind, sign, points, vertices):
    value, grad, corners, weights = _evaluate(mesh, kind, sign, points)
    return value, (grad, corners, weights, vertices)


def _backward(mesh, kind, sign, saved, cotangent):
    grad, corners, weights, vertices = saved
    per_point = cotangent[:, None] * grad
    grad_vertices = jnp.zeros_like(vertices)
    for k in range(3):
        grad_vertices = grad_vertices.at[corners[:, k]].add((-weights[:, k : k + 1] * per_point).astype(vertices.dtype))
    return per_point.astype(grad.dtype), grad_vertices


_distance.defvjp(_forward, _backward)


def _run(mesh, points, vertices, kind, sign):
    points = jnp.asarray(points)
    if points.ndim != 2 or points.shape[1] != 3:
        raise ValueError(f"points: expected shape (N, 3), got {points.shape}")
    if vertices is None:
        vertices = jnp.asarray(mesh.vertices, dtype=points.dtype)
    elif not isinstance(vertices, jax.core.Tracer):
        _autodiff.check_vertices(mesh, np.asarray(vertices))
    return _distance(mesh, kind, sign, points, jnp.asarray(vertices))


def signed_distance(mesh, points, vertices=None, sign="winding"):
    """The signed distance (negative inside) of each of ``points`` (N, 3)
    to ``mesh``; differentiable with respect to ``points`` and ``vertices``
    (the mesh's own positions, as an array)."""
    return _run(mesh, points, vertices, "signed", sign)


def distance(mesh, points, vertices=None):
    """The unsigned distance of each of ``points`` (N, 3) to ``mesh``'s
    faces; differentiable with respect to ``points`` and ``vertices``."""
    return _run(mesh, points, vertices, "unsigned", "winding")
