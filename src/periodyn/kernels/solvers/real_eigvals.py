"""Eigenvalues of a small real matrix by LAPACK's double-shift QR (``eigvals_small``).

LAPACK dgeev reduces to Hessenberg form and then runs dhseqr, which from order 75 on
(its NMIN) switches to the multishift QR with aggressive early deflation (dlaqr0), built for
large matrices. At the orders of a mid-size orbit's monodromy (d ~ 50-150) the plain
double-shift QR (dlahqr) finds the same eigenvalues (backward stable as well) in about
half the time. ``eigvals_small`` does dgeev's steps itself: dgebal (permute and scale, as
dgeev), dgehrd, dlahqr on rows ILO..IHI, the eigenvalues isolated by the balancing from the
diagonal (as dhseqr does); where dlahqr does not converge (its INFO > 0) it falls back to
dgeev (:func:`periodyn.kernels.solvers.magnus_ladder._eigvals`).

The LAPACK routines come from SciPy's ``cython_lapack`` (the library NumPy's and Numba's own
bindings use) and are registered as named symbols, so that the compiled callers cache.
"""

from __future__ import annotations

import numpy as np
from llvmlite import binding
from numba import njit, types
from numba.extending import get_cython_function_address

from .magnus_ladder import _eigvals


def _external(name: str, count: int):
    """The cython_lapack routine ``name`` (Fortran calling convention, ``count`` pointer
    arguments) as a Numba external function under the symbol ``periodyn_<name>``."""
    symbol = f"periodyn_{name}"
    binding.add_symbol(symbol, get_cython_function_address("scipy.linalg.cython_lapack", name))
    return types.ExternalFunction(symbol, types.void(*([types.voidptr] * count)))


_DGEBAL = _external("dgebal", 8)
_DGEHRD = _external("dgehrd", 9)
_DLAHQR = _external("dlahqr", 14)

#: largest order sent to dlahqr (below order 75 dgeev runs dlahqr itself: the same time; from
#: 80 to 160 measured 1.2-1.9x faster than dgeev on one core; above, dgeev's multishift QR)
LARGEST_QR = 160


@njit(cache=True)
def eigvals_small(X):
    """Eigenvalues (d,) complex of a real square matrix X (not changed), as dgeev gives them
    (conjugate pairs exact) but by the double-shift QR up to order LARGEST_QR (module
    docstring); NaN where LAPACK fails."""
    d = X.shape[0]
    if d > LARGEST_QR:
        return _eigvals(X)
    a = np.empty((d, d)).T  # Fortran order, as LAPACK reads it
    a[:, :] = X
    job = np.array([ord("B")], np.uint8)
    n = np.array([d], np.int32)
    ilo, ihi, info = np.zeros(1, np.int32), np.zeros(1, np.int32), np.zeros(1, np.int32)
    scale = np.empty(d)
    _DGEBAL(job.ctypes, n.ctypes, a.ctypes, n.ctypes, ilo.ctypes, ihi.ctypes, scale.ctypes, info.ctypes)
    if info[0] != 0:
        return _eigvals(X)
    lwork = np.array([32 * d], np.int32)
    tau, work = np.empty(d), np.empty(32 * d)
    _DGEHRD(n.ctypes, ilo.ctypes, ihi.ctypes, a.ctypes, n.ctypes, tau.ctypes, work.ctypes, lwork.ctypes,
            info.ctypes)
    if info[0] != 0:
        return _eigvals(X)
    for j in range(d):  # the reflectors below the subdiagonal are not part of H
        for i in range(j + 2, d):
            a[i, j] = 0.0
    wr, wi = np.zeros(d), np.zeros(d)
    for i in range(ilo[0] - 1):  # isolated by the balancing (1-based ILO, IHI)
        wr[i] = a[i, i]
    for i in range(ihi[0], d):
        wr[i] = a[i, i]
    no, one, z = np.zeros(1, np.int32), np.ones(1, np.int32), np.empty(1)
    _DLAHQR(no.ctypes, no.ctypes, n.ctypes, ilo.ctypes, ihi.ctypes, a.ctypes, n.ctypes, wr.ctypes, wi.ctypes,
            one.ctypes, one.ctypes, z.ctypes, one.ctypes, info.ctypes)
    if info[0] != 0:
        return _eigvals(X)
    mu = np.empty(d, np.complex128)
    for i in range(d):
        mu[i] = complex(wr[i], wi[i])
    return mu
