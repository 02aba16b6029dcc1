"""The autograd adapters (proxima.jax, proxima.torch): their gradients
against central finite differences of the distances themselves, JAX's
check_grads and torch's gradcheck (float64), and the vertex gradients
against finite differences of meshes rebuilt from moved vertices."""

import numpy as np
import pytest

import proxima

jax = pytest.importorskip("jax")
jax.config.update("jax_enable_x64", True)
import jax.numpy as jnp  # noqa: E402
from jax.test_util import check_grads  # noqa: E402

import proxima.jax  # noqa: E402

SPHERE = proxima.noisy_icosphere(5, seed=4)


def away_from_surface_and_axis(mesh, n, seed):
    """Points at |distance| > 0.1 whose distance is smooth around them (the
    finite differences at two step sizes agree)."""
    rng = np.random.default_rng(seed)
    points = rng.random((4 * n, 3)) * 3.0 - 1.5
    d = mesh.signed_distance(points)
    keep = []
    for i, p in enumerate(points):
        if abs(d[i]) < 0.1:
            continue
        g = [central(lambda q: mesh.signed_distance(q[None])[0], p, h) for h in (1e-2, 2.5e-3)]
        if np.abs(g[0] - g[1]).max() < 1e-3:
            keep.append(p)
        if len(keep) == n:
            break
    return np.array(keep)


def central(f, p, h):
    out = np.zeros(3)
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        out[k] = (f(p + e) - f(p - e)) / (2 * h)
    return out


@pytest.mark.parametrize("kind", ["signed", "unsigned"])
def test_jax_point_gradients_match_finite_differences(kind):
    points = away_from_surface_and_axis(SPHERE, 40, 1)
    f = proxima.jax.signed_distance if kind == "signed" else proxima.jax.distance
    grad = jax.grad(lambda p: f(SPHERE, p).sum())(jnp.asarray(points))
    values = np.asarray(f(SPHERE, jnp.asarray(points)))
    plain = SPHERE.signed_distance(points)
    assert np.array_equal(values, plain if kind == "signed" else np.abs(plain))
    for p, g in zip(points, np.asarray(grad)):
        fd = central(lambda q: float(f(SPHERE, jnp.asarray(q[None]))[0]), p, 2.5e-3)
        assert np.abs(fd - g).max() < 5e-3, (p, fd, g)
    # jit compiles the callback in.
    jitted = jax.jit(lambda p: f(SPHERE, p))(jnp.asarray(points))
    assert np.array_equal(np.asarray(jitted), values)
    check_grads(lambda p: f(SPHERE, p), (jnp.asarray(points[:8]),), order=1, modes=["rev"], eps=1e-3, atol=5e-3, rtol=5e-3)


def test_jax_vertex_gradients_match_rebuilt_meshes():
    faces = np.asarray(SPHERE.faces)
    vertices = SPHERE.vertices.astype(np.float64)
    points = away_from_surface_and_axis(SPHERE, 10, 2)
    grad = jax.grad(lambda v: proxima.jax.signed_distance(SPHERE, jnp.asarray(points), v).sum())(jnp.asarray(vertices))
    grad = np.asarray(grad)
    # Finite differences: move one vertex, rebuild the mesh, sum the distances.
    def total(v):
        return proxima.Mesh(v, faces).signed_distance(points).sum()

    moved = np.argsort(-np.abs(grad).sum(axis=1))[:6]
    assert np.abs(grad[moved]).max() > 0.05
    for v in moved:
        fd = np.zeros(3)
        for k in range(3):
            up, down = vertices.copy(), vertices.copy()
            up[v, k] += 1e-3
            down[v, k] -= 1e-3
            fd[k] = (total(up) - total(down)) / 2e-3
        assert np.abs(fd - grad[v]).max() < 2e-2, (v, fd, grad[v])
    with pytest.raises(ValueError, match="vertices"):
        proxima.jax.signed_distance(SPHERE, jnp.asarray(points), jnp.asarray(vertices[:5]))


def test_torch_gradients_where_torch_is_installed():
    torch = pytest.importorskip("torch")
    import proxima.torch

    points = torch.tensor(away_from_surface_and_axis(SPHERE, 12, 3), dtype=torch.float64, requires_grad=True)
    vertices = torch.tensor(SPHERE.vertices.astype(np.float64), requires_grad=True)
    for f in (proxima.torch.signed_distance, proxima.torch.distance):
        values = f(SPHERE, points, vertices)
        values.sum().backward()
        expected = jax.grad(lambda p: (proxima.jax.signed_distance if f is proxima.torch.signed_distance else proxima.jax.distance)(SPHERE, p).sum())(jnp.asarray(points.detach().numpy()))
        assert np.allclose(points.grad.numpy(), np.asarray(expected))
        assert vertices.grad is not None and torch.isfinite(vertices.grad).all()
        points.grad = None
        vertices.grad = None
    assert torch.autograd.gradcheck(lambda p: proxima.torch.signed_distance(SPHERE, p), (points,), eps=1e-3, atol=5e-3)


def test_jax_arrays_are_accepted_as_input():
    points = away_from_surface_and_axis(SPHERE, 5, 4).astype(np.float32)
    plain = SPHERE.closest_points(points)
    from_jax = SPHERE.closest_points(jnp.asarray(points))
    for a, b in zip(plain, from_jax):
        assert np.array_equal(a, b)
    assert np.array_equal(SPHERE.signed_distance(jnp.asarray(points)), SPHERE.signed_distance(points))
