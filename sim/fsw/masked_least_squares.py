"""Least squares over the measurements the flight software trusts: the common
core of IRU rate selection (seed 001 "Hardware complement": "the failure
detection and correction (FDC) system is capable of reconfiguring rate
selection autonomously") and the CSS Sun vector.

Solves min |H x - y|^2 over the rows flagged in `use`, through the normal
matrix N = H^T H. Directions the used rows do not see (eigenvalues of N
below rel_tol times the largest) get no component: the minimum-norm
solution, and the returned rank says how many directions were seen.

Every cycle takes the 3 x 3 case with all directions well seen: that is
solved by the adjugate, and the eigen-decomposition (a LAPACK call, about
1 us) is kept for the rank-deficient case.
"""
import numpy as np
from numba import njit

from sim.linalg import inv3, matvec

WELL_CONDITIONED = 1e-3  # det(N) / (trace(N) / 3)^3 above this: all three directions are well seen


@njit(cache=True, inline="always")
def masked_least_squares(H, y, use, rel_tol):
    """(x, rank): minimum-norm least-squares solution over rows with use[k]."""
    n = H.shape[1]
    normal = np.zeros((n, n))
    rhs = np.zeros(n)
    for k in range(H.shape[0]):
        if not use[k]:
            continue
        for i in range(n):
            rhs[i] += H[k, i] * y[k]
            for j in range(n):
                normal[i, j] += H[k, i] * H[k, j]
    if n == 3:
        tr = normal[0, 0] + normal[1, 1] + normal[2, 2]
        det = (normal[0, 0] * (normal[1, 1] * normal[2, 2] - normal[1, 2] * normal[2, 1])
               - normal[0, 1] * (normal[1, 0] * normal[2, 2] - normal[1, 2] * normal[2, 0])
               + normal[0, 2] * (normal[1, 0] * normal[2, 1] - normal[1, 1] * normal[2, 0]))
        if tr > 0.0 and det > WELL_CONDITIONED * (tr / 3.0) ** 3:
            return matvec(inv3(normal), rhs), 3
    lam, vec = np.linalg.eigh(normal)   # ascending eigenvalues
    x = np.zeros(n)
    rank = 0
    for i in range(n):
        if lam[i] <= rel_tol * lam[n - 1] or lam[i] <= 0.0:
            continue
        rank += 1
        c = 0.0
        for j in range(n):
            c += vec[j, i] * rhs[j]
        for j in range(n):
            x[j] += c / lam[i] * vec[j, i]
    return x, rank
