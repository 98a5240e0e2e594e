"""Campbell diagram: eigenvalues of a rotor at many spin speeds, in the stationary frame,
each labelled forward or backward whirl from its eigenvector orbit.

Whirl: an eigen-solution ``Re(phi e^{lambda t})`` moves every station centre on an
ellipse. With ``a, b`` the y and z components of phi, the complex position
``y + i z = 1/2 (a + i b) e^{lambda t} + 1/2 conj(a - i b) e^{conj(lambda) t}`` is the sum
of a forward circle (the spin sense, y towards z) of amplitude |a + i b| and a backward
one of amplitude |a - i b|, rotating at +Im(lambda) and -Im(lambda). In the co-rotating
frame the forward circle of each eigenvalue is seen from the stationary frame at
``lambda + i Omega``: taking, of each conjugate pair, the member whose forward content
dominates and adding i Omega converts the eigenvalue; a negative frequency then means
backward whirl (Schwab & Meijaard 2001, section 4.3). A real co-rotating eigenvalue
(overdamped; for an isotropic rotor they come in equal pairs) is a forward whirl at the
spin speed. In the stationary frame the member with positive frequency is kept and its
whirl is the dominant circle.
"""

from __future__ import annotations

import warnings

import numpy as np
import xarray as xr

from ..errors import ConvergenceError, InputError
from ..stability.floquet import STABILITY_TOL
from .element_rotor import ElementRotor
from .model import RotorModel

__all__ = ["campbell", "stability_threshold", "FORWARD", "BACKWARD"]

FORWARD, BACKWARD = "forward", "backward"
_CHUNK_ENTRIES = 4_000_000      # complex entries of state matrices per eig batch
#: an eigenvalue within RIGID_TOL times the largest |eigenvalue| of its speed is a rigid-body
#: (zero-frequency) mode: rounding moves a rigid coordinate's double zero by about
#: sqrt(eps) |lambda|_max (a 2x2 Jordan block), in any direction, so the sign of its imaginary
#: part means nothing; 64 sqrt(eps) ~ 1e-6 keeps a factor 64 over that rounding
RIGID_TOL = 64.0 * float(np.sqrt(np.finfo(float).eps))
#: a stiffness LU pivot below SINGULAR_PIVOT times the largest is a rigid-body direction:
#: rounding leaves it near eps times the largest (1.3e-17 measured on a free shaft, where
#: some LAPACK/SuperLU builds give an exact zero), a supported rotor's smallest is ~1e-4
SINGULAR_PIVOT = 1e3 * float(np.finfo(float).eps)


def _speeds(speeds) -> np.ndarray:
    try:
        s = np.atleast_1d(np.asarray(speeds, dtype=float))
    except (TypeError, ValueError):
        s = np.array([np.nan])
    if s.ndim != 1 or s.size == 0 or not np.all(np.isfinite(s)) or np.any(s < 0):
        raise InputError(f"speeds must be a non-empty 1-D array of finite spin speeds >= 0 in rad/s, got {speeds!r}")
    return s


def _state_inverse_terms(eq):
    """M^-1 times each damping/stiffness power, (n, n) each."""
    M = eq.mass
    try:
        L = np.linalg.cholesky(M)
    except np.linalg.LinAlgError:
        raise InputError("the rotor's mass matrix is not positive definite; every coordinate needs mass or inertia") from None
    solve = lambda A: np.linalg.solve(L.T, np.linalg.solve(L, A))  # noqa: E731
    return [solve(c) for c in eq.damping], [solve(k) for k in eq.stiffness]


def _eigen(eq, speeds: np.ndarray):
    """Eigenvalues (S, 2n) and the translational orbit contents (forward, backward)
    (S, 2n) of the state matrices at every speed, in batches."""
    n = eq.mass.shape[0]
    (C0, C1), (K0, K1, K2) = _state_inverse_terms(eq)
    lam = np.empty((speeds.size, 2 * n), dtype=complex)
    fwd = np.empty((speeds.size, 2 * n))
    bwd = np.empty((speeds.size, 2 * n))
    chunk = max(1, _CHUNK_ENTRIES // (4 * n * n))
    for lo in range(0, speeds.size, chunk):
        w = speeds[lo:lo + chunk, None, None]
        A = np.zeros((w.shape[0], 2 * n, 2 * n))
        A[:, :n, n:] = np.eye(n)
        A[:, n:, :n] = -(K0 + w * K1 + w**2 * K2)
        A[:, n:, n:] = -(C0 + w * C1)
        vals, vecs = np.linalg.eig(A)
        a, b = eq.lateral[0] @ vecs[:, :n], eq.lateral[1] @ vecs[:, :n]   # y and z of every station
        lam[lo:lo + chunk] = vals
        fwd[lo:lo + chunk] = np.sum(np.abs(a + 1j * b) ** 2, axis=1)
        bwd[lo:lo + chunk] = np.sum(np.abs(a - 1j * b) ** 2, axis=1)
    return lam, fwd, bwd


def _subset(eq, speeds: np.ndarray, count: int):
    """The ``count`` eigenvalues nearest the origin per speed, by ARPACK on the inverse
    state operator ``[x; y] -> [-K^-1 (C x + M y); x]`` (one sparse LU of K per speed,
    or once when K does not depend on the speed); same outputs as :func:`_eigen`, and
    the number of speeds where ARPACK did not converge (repeated eigenvalues, as of an
    undamped isotropic rotor at rest, where every frequency is double) and the dense
    solver gave the ``count`` nearest the origin instead."""
    import scipy.sparse as sp
    from scipy.sparse.linalg import ArpackError, ArpackNoConvergence, LinearOperator, eigs

    n = eq.mass.shape[0]
    M = sp.csr_matrix(eq.mass)
    C0, C1 = (sp.csr_matrix(c) for c in eq.damping)
    K0, K1, K2 = (sp.csc_matrix(k) for k in eq.stiffness)
    constant_k = K1.nnz == 0 and K2.nnz == 0
    lam = np.empty((speeds.size, count), dtype=complex)
    fwd = np.empty((speeds.size, count))
    bwd = np.empty((speeds.size, count))
    lu = _stiffness_lu(K0, 0.0) if constant_k else None
    start = np.ones(2 * n)
    fallbacks = 0
    for i, w in enumerate(speeds):
        if not constant_k:
            lu = _stiffness_lu(sp.csc_matrix(K0 + w * K1 + w**2 * K2), w)
        C = C0 + w * C1

        def apply(v, lu=lu, C=C):
            v = np.ravel(v)
            return np.concatenate([-lu.solve(C @ v[:n] + M @ v[n:]), v[:n]])

        try:
            mu, vecs = eigs(LinearOperator((2 * n, 2 * n), matvec=apply, dtype=float), k=count, v0=start, tol=1e-13)
        except ArpackNoConvergence:
            every, f, b = _eigen(eq, np.array([w]))
            nearest = np.argsort(np.abs(every[0]), kind="stable")[:count]
            lam[i], fwd[i], bwd[i] = every[0, nearest], f[0, nearest], b[0, nearest]
            fallbacks += 1
            continue
        except ArpackError as exc:
            raise ConvergenceError(f"subset eigenvalues failed at speed {w:.6g} rad/s ({exc}); use eigensolver='dense'"
                                   ) from None
        start = np.real(vecs[:, 0]) + np.imag(vecs[:, 0])
        lam[i] = 1.0 / mu
        a, b = eq.lateral[0] @ vecs[:n], eq.lateral[1] @ vecs[:n]
        fwd[i] = np.sum(np.abs(a + 1j * b) ** 2, axis=0)
        bwd[i] = np.sum(np.abs(a - 1j * b) ** 2, axis=0)
    return lam, fwd, bwd, fallbacks


def _stiffness_lu(K, speed: float):
    """Sparse LU of the stiffness at ``speed`` (rad/s); InputError when it is singular."""
    from scipy.sparse.linalg import splu

    try:
        lu = splu(K)
        pivots = np.abs(lu.U.diagonal())
        singular = not pivots.min() > SINGULAR_PIVOT * pivots.max()
    except RuntimeError:   # exactly singular
        singular = True
    if singular:
        raise InputError(f"eigensolver='subset' needs a non-singular stiffness matrix, but it is singular at speed "
                         f"{speed:.6g} rad/s (an unsupported rotor: rigid-body modes at zero frequency); add "
                         "bearings or use eigensolver='dense'")
    return lu


def _one_per_mode(lam):
    """Stationary-frame eigenvalues (S, 2n) with the rigid-body ones (|lambda| <=
    RIGID_TOL |lambda|_max per speed) set to exactly 0, and the mask (S, 2n) of one
    eigenvalue per mode: the member with Im >= 0 of each vibrating pair, both real
    eigenvalues of an overdamped mode, and half of the rigid zeros (a rigid coordinate
    gives a pair of them), whatever the signs rounding gave them."""
    rigid = np.abs(lam) <= RIGID_TOL * np.abs(lam).max(axis=1, keepdims=True)
    lam = np.where(rigid, 0.0, lam)
    rigid_half = np.cumsum(rigid, axis=1) <= (np.sum(rigid, axis=1, keepdims=True) + 1) // 2
    return lam, np.where(rigid, rigid_half, lam.imag >= 0.0)


def _stationary(lam, fwd, bwd, speeds, frame):
    """One stationary-frame eigenvalue (positive frequency) and whirl per mode pair."""
    if frame == "rotating":
        n = lam.shape[1] // 2
        order = np.argsort(-(fwd - bwd) / (fwd + bwd), axis=1, kind="stable")[:, :n]
        chosen = np.take_along_axis(lam, order, axis=1) + 1j * speeds[:, None]
        forward = chosen.imag >= 0.0
    else:
        lam, keep = _one_per_mode(lam)
        n = int(np.min(np.sum(keep, axis=1)))
        order = np.argsort(np.where(keep, -lam.imag, np.inf), axis=1, kind="stable")[:, :n]
        chosen = np.take_along_axis(lam, order, axis=1)
        forward = np.take_along_axis(fwd, order, axis=1) >= np.take_along_axis(bwd, order, axis=1)
    chosen = np.where(chosen.imag < 0.0, chosen.conj(), chosen)
    by_frequency = np.argsort(chosen.imag, axis=1, kind="stable")
    return np.take_along_axis(chosen, by_frequency, axis=1), np.take_along_axis(forward, by_frequency, axis=1)


def campbell(model: RotorModel | ElementRotor, speeds, *, modes: int | None = None, frame: str = "auto",
             eigensolver: str = "auto", method: str | None = None) -> xr.Dataset:
    """Eigenvalues of the rotor at spin speeds ``speeds`` (rad/s), converted to the
    stationary frame, the ``modes`` lowest by frequency (default all).

    frame: ``rotating`` solves the time-invariant co-rotating equations (as the paper),
    ``stationary`` the stationary-frame ones, ``auto`` the first where the rotor allows
    (anisotropic bearings need the stationary frame). eigensolver: ``dense`` (all
    eigenvalues, batched LAPACK), ``subset`` (the 2 modes + 8 eigenvalues nearest the
    origin by sparse ARPACK, in the stationary frame: cost grows about linearly with the
    model; a mode far more damped than it vibrates may be passed over), ``auto``
    (dense up to 120 coordinates or when the rotating frame is asked for). An
    :class:`ElementRotor` (an element model's co-rotating equations) has only the
    rotating frame and the dense eigensolver (``method=``: its deprecated name). Returns a dataset with dims
    (speed, mode): ``eigenvalue`` (complex, 1/s, Im >= 0), ``frequency`` (rad/s),
    ``damping_ratio`` (-Re/|lambda|), ``whirl`` ("forward"/"backward"); coordinate
    ``speed_rpm``; ``max_real_eigenvalue`` (speed,) over all modes found. A rigid-body
    mode (an eigenvalue within :data:`RIGID_TOL` of the largest, in the stationary frame)
    is listed once per pair of zero eigenvalues, with eigenvalue exactly 0 and damping
    ratio NaN. Attrs ``frame``, ``rotor``,
    ``dense_fallback_speeds`` (speeds the subset solver left to the dense one) and ``threshold_speed``
    (rad/s, the lowest speed where a mode becomes unstable, NaN if none in range; see
    :func:`stability_threshold`). Save it with :func:`periodyn.results.save`."""
    if not isinstance(model, (RotorModel, ElementRotor)):
        raise InputError(f"campbell takes a compiled rotor (Rotor(...).compile(), periodyn.examples.rotor() or an "
                         f"ElementRotor), got {type(model).__name__}")
    speeds = _speeds(speeds)
    if method is not None:
        warnings.warn("campbell(method=...) is deprecated and goes in the next release; pass eigensolver="
                      f"{method!r}", DeprecationWarning, stacklevel=2)
        eigensolver = method
    if eigensolver not in ("auto", "dense", "subset"):
        raise InputError(f"eigensolver must be 'auto', 'dense' or 'subset', got {eigensolver!r}")
    n = model.n
    modes = n if modes is None else modes
    if isinstance(modes, bool) or not isinstance(modes, (int, np.integer)) or not 1 <= modes <= n:
        raise InputError(f"modes must be between 1 and {n} (the rotor's coordinates), got {modes}")
    if "stationary" not in model.frames:       # coordinates that turn with the shaft
        frame = "rotating" if frame == "auto" else frame
    if eigensolver == "auto":
        eigensolver = "dense" if n <= 120 or 2 * modes + 8 >= 2 * n - 1 or frame == "rotating" else "subset"
    if frame == "auto":
        frame = "rotating" if model.isotropic and eigensolver == "dense" else "stationary"
    eq = model.equations(frame)
    if eigensolver == "subset":
        if frame != "stationary":
            raise InputError("eigensolver='subset' works in the stationary frame; use frame='stationary' or 'auto'"
                             if "stationary" in model.frames else
                             f"eigensolver='subset' works in the stationary frame, which rotor '{model.name}' has not "
                             "(its coordinates turn with the shaft); use eigensolver='dense'")
        lam, fwd, bwd, fallbacks = _subset(eq, speeds, min(2 * modes + 8, 2 * n - 2))
    else:
        (lam, fwd, bwd), fallbacks = _eigen(eq, speeds), 0
    values, forward = _stationary(lam, fwd, bwd, speeds, frame)
    if values.shape[1] < modes:
        raise ConvergenceError(f"only {values.shape[1]} vibrating modes found among the eigenvalues nearest the "
                               f"origin, {modes} asked; use eigensolver='dense' or fewer modes")
    growth = values.real.max(axis=1)            # over every mode found, kept or not
    values, forward = values[:, :modes], forward[:, :modes]
    damping_ratio = np.divide(-values.real, np.abs(values), out=np.full(values.shape, np.nan), where=values != 0)
    ds = xr.Dataset(
        {"eigenvalue": (("speed", "mode"), values, {"units": "1/s", "long_name": "eigenvalue (stationary frame)"}),
         "frequency": (("speed", "mode"), values.imag, {"units": "rad/s"}),
         "damping_ratio": (("speed", "mode"), damping_ratio, {"units": "1"}),
         "whirl": (("speed", "mode"), np.where(forward, FORWARD, BACKWARD).astype(object)),
         "max_real_eigenvalue": ("speed", growth, {"units": "1/s", "long_name": "largest real part of all modes"})},
        coords={"speed": ("speed", speeds, {"units": "rad/s"}), "mode": np.arange(modes),
                "speed_rpm": ("speed", speeds * 30.0 / np.pi, {"units": "rpm"})},
        attrs={"frame": frame, "method": eigensolver, "rotor": model.name, "dense_fallback_speeds": fallbacks})
    ds.attrs["threshold_speed"] = stability_threshold(ds)
    return ds


def stability_threshold(ds: xr.Dataset) -> float:
    """Lowest speed (rad/s) where the largest real part of the eigenvalues
    (``max_real_eigenvalue``, else of the listed modes) crosses zero towards an
    instability, linearly interpolated between grid speeds; NaN if every speed is
    stable. A speed is unstable when that real part exceeds the one stability verdict's
    tolerance (:data:`periodyn.stability.floquet.STABILITY_TOL`) per cycle of the fastest listed
    mode, ``STABILITY_TOL |lambda|_max / (2 pi)``: the rounding of an undamped rotor's
    neutral modes (Re ~ 1e-10 1/s) is not an instability. The crossing is the last
    sign change of the growth before the first unstable speed."""
    eigenvalues = ds["eigenvalue"].values
    growth = ds["max_real_eigenvalue"].values if "max_real_eigenvalue" in ds else eigenvalues.real.max(axis=1)
    tol = STABILITY_TOL / (2.0 * np.pi) * np.abs(eigenvalues).max(axis=1)
    speed = ds["speed"].values
    above = np.nonzero(growth > tol)[0]
    if above.size == 0:
        return float("nan")
    j = int(above[0])
    while j > 0 and growth[j - 1] > 0.0:   # back to where the growth turned positive
        j -= 1
    if j == 0:
        return float(speed[0])
    g0, g1 = growth[j - 1], growth[j]
    return float(speed[j - 1] + (speed[j] - speed[j - 1]) * (-g0) / (g1 - g0))
