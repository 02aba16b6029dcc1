"""PyTorch autograd for proxima's distances (needs ``torch``; CPU tensors).

>>> import torch, proxima, proxima.torch
>>> mesh = proxima.noisy_icosphere(8)
>>> points = torch.rand(100, 3, dtype=torch.float64, requires_grad=True)
>>> proxima.torch.signed_distance(mesh, points).sum().backward()
>>> points.grad.shape
torch.Size([100, 3])

Gradients flow to ``points`` and, when given, to ``vertices`` (a tensor
holding the mesh's own positions, for optimizing a mesh through the
distance: rebuild the :class:`proxima.Mesh` from the new positions each
step). The values are computed by the Rust library in float32 and returned
in the points' dtype; the gradient convention is :mod:`proxima._autodiff`'s.
Higher derivatives are not available (the backward pass is not itself
differentiable).
"""

import numpy as np
import torch

from . import _autodiff


class _Distance(torch.autograd.Function):
    @staticmethod
    def forward(ctx, points, vertices, mesh, kind, sign):
        value, grad, corners, weights = _autodiff.evaluate(mesh, points.detach().cpu().numpy(), kind, sign)
        ctx.save_for_backward(torch.from_numpy(grad), torch.from_numpy(corners), torch.from_numpy(weights))
        ctx.vertex_count = len(mesh.vertices)
        ctx.dtypes = (points.dtype, vertices.dtype)
        return torch.from_numpy(np.asarray(value)).to(points.dtype)

    @staticmethod
    def backward(ctx, cotangent):
        grad, corners, weights = ctx.saved_tensors
        cotangent = cotangent.detach().to(torch.float64)
        grad_points = grad_vertices = None
        if ctx.needs_input_grad[0]:
            grad_points = cotangent[:, None] * grad
        if ctx.needs_input_grad[1]:
            grad_vertices = torch.from_numpy(
                _autodiff.vertex_vjp(cotangent.numpy(), grad.numpy(), corners.numpy(), weights.numpy(), ctx.vertex_count)
            )
        return (
            None if grad_points is None else grad_points.to(ctx.dtypes[0]),
            None if grad_vertices is None else grad_vertices.to(ctx.dtypes[1]),
            None,
            None,
            None,
        )


def _run(mesh, points, vertices, kind, sign):
    if not isinstance(points, torch.Tensor) or points.ndim != 2 or points.shape[1] != 3:
        raise ValueError("points: expected a (N, 3) torch tensor")
    if vertices is None:
        vertices = torch.zeros(0)
    else:
        _autodiff.check_vertices(mesh, vertices.detach().cpu().numpy())
    return _Distance.apply(points, vertices, mesh, kind, sign)


def signed_distance(mesh, points, vertices=None, sign="winding"):
    """The signed distance (negative inside) of each of ``points`` (N, 3)
    to ``mesh``, differentiable with respect to ``points`` and ``vertices``."""
    return _run(mesh, points, vertices, "signed", sign)


def distance(mesh, points, vertices=None):
    """The unsigned distance of each of ``points`` (N, 3) to ``mesh``'s
    faces, differentiable with respect to ``points`` and ``vertices``."""
    return _run(mesh, points, vertices, "unsigned", "winding")
