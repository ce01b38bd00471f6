"""Small dense products for the compiled kernels.

numba sends `@` on float64 arrays to BLAS, whose call overhead dwarfs a 3 x 3
product; these plain loops compile to a few instructions instead.
"""
import numpy as np
from numba import njit


@njit(cache=True)
def matvec(m, v):
    """m @ v for a small (r, c) matrix."""
    r, c = m.shape
    out = np.zeros(r)
    for i in range(r):
        acc = 0.0
        for j in range(c):
            acc += m[i, j] * v[j]
        out[i] = acc
    return out


@njit(cache=True)
def matvec_t(m, v):
    """m.T @ v for a small (r, c) matrix, without forming the transpose."""
    r, c = m.shape
    out = np.zeros(c)
    for i in range(r):
        for j in range(c):
            out[j] += m[i, j] * v[i]
    return out


@njit(cache=True)
def cross(a, b):
    out = np.empty(3)
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]
    return out


@njit(cache=True)
def inv3(m):
    """Inverse of a 3 x 3 matrix by the adjugate (the inertia changes with
    propellant inside the RK4 stages, so it is inverted there)."""
    a, b, c = m[0, 0], m[0, 1], m[0, 2]
    d, e, f = m[1, 0], m[1, 1], m[1, 2]
    g, h, i = m[2, 0], m[2, 1], m[2, 2]
    A, B, C = e * i - f * h, -(d * i - f * g), d * h - e * g
    det = a * A + b * B + c * C
    out = np.empty((3, 3))
    out[0, 0], out[1, 0], out[2, 0] = A / det, B / det, C / det
    out[0, 1] = -(b * i - c * h) / det
    out[1, 1] = (a * i - c * g) / det
    out[2, 1] = -(a * h - b * g) / det
    out[0, 2] = (b * f - c * e) / det
    out[1, 2] = -(a * f - c * d) / det
    out[2, 2] = (a * e - b * d) / det
    return out
