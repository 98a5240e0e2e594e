"""Kernels of the certified Magnus flow of an orbit's samples
(:func:`periodyn.stability.orbit_flow.flow_exponents`).

The generator ``A_j`` (d, d) of ``y' = A(t) y`` at p equidistant times over one period is
kept as a constant matrix (the first sample) and the flat entries that vary along the orbit
(``varying`` (v,), their samples ``values`` (p, v)).

* ``generator_stiffness``: max_j ||A_j||_1 (largest absolute column sum over the samples).
* ``gauss_values``: the trigonometric interpolant of the samples (harmonics 0..(p-1)//2, the
  ones they resolve) at the three Gauss angles of each of ``steps`` equal steps over 2 pi, from
  the samples' discrete Fourier coefficients (cos/sin of k theta by the angle-addition
  recurrence).
* ``sampled_monodromy``: the 6th-order Magnus transition matrix (the steps of
  ``floquet._magnus_steps``) of that interpolant over a span.
* ``certified_flow``: the whole step-doubling climb in one call: the half-period test, the
  monodromy at START / 2, START, 2 START, ... steps, its multipliers (2 x 2 in closed form,
  else LAPACK's double-shift QR) and the error test of the rule written in
  :mod:`periodyn.stability.orbit_flow`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .floquet import _expm, _generator6, _matmul
from .magnus_ladder import GAUSS_NODES_3
from .real_eigvals import eigvals_small


@njit(cache=True)
def generator_stiffness(constant, varying, values):
    """max_j ||A_j||_1 of the samples A_j: ``constant`` (d, d) with flat entries ``varying``
    (v,) replaced by ``values[j]`` (p, v)."""
    d = constant.shape[0]
    base = np.zeros(d)
    for i in range(d):
        for j in range(d):
            base[j] += abs(constant[i, j])
    col = np.empty(d)
    largest = 0.0
    for s in range(values.shape[0]):
        col[:] = base
        for e in range(varying.shape[0]):
            i, j = varying[e] // d, varying[e] % d
            col[j] += abs(values[s, e]) - abs(constant[i, j])
        for j in range(d):
            largest = max(largest, col[j])
    return largest


@njit(cache=True)
def _coefficients(values):
    """Cosine and sine coefficients a, b (K + 1, v), K = (p - 1) // 2, of the samples values
    (p, v) at 2 pi i / p: values_i = a_0 + sum_k a_k cos(k theta_i) + b_k sin(k theta_i)
    (cos and sin of 2 pi k i / p from one table of p angles)."""
    p, v = values.shape
    K = (p - 1) // 2
    cos_t, sin_t = np.cos(2.0 * np.pi * np.arange(p) / p), np.sin(2.0 * np.pi * np.arange(p) / p)
    a = np.zeros((K + 1, v))
    b = np.zeros((K + 1, v))
    for i in range(p):
        for k in range(K + 1):
            c, s = cos_t[(k * i) % p], sin_t[(k * i) % p]
            for e in range(v):
                a[k, e] += c * values[i, e]
                b[k, e] += s * values[i, e]
    a[0] /= p
    a[1:] *= 2.0 / p
    b[1:] *= 2.0 / p
    return a, b


@njit(cache=True)
def _at_gauss(a, b, steps):
    """(3 steps, v): the series of coefficients a, b (:func:`_coefficients`) at the Gauss
    angles 2 pi (k + c) / steps (c: the three Gauss nodes on [0, 1]); cos and sin of
    k theta by the angle-addition recurrence."""
    K, v = a.shape[0] - 1, a.shape[1]
    out = np.empty((3 * steps, v))
    for g in range(3 * steps):
        theta = 2.0 * np.pi * (g // 3 + GAUSS_NODES_3[g % 3]) / steps
        c1, s1 = np.cos(theta), np.sin(theta)
        for e in range(v):
            out[g, e] = a[0, e]
        ck, sk = 1.0, 0.0
        for k in range(1, K + 1):
            ck, sk = ck * c1 - sk * s1, sk * c1 + ck * s1
            for e in range(v):
                out[g, e] += a[k, e] * ck + b[k, e] * sk
    return out


@njit(cache=True)
def gauss_values(values, steps):
    """(3 steps, v): the trigonometric interpolant (harmonics 0..(p-1)//2) of samples values
    (p, v) at 2 pi i / p, taken at the Gauss angles 2 pi (k + c) / steps (c: the three Gauss
    nodes on [0, 1])."""
    a, b = _coefficients(values)
    return _at_gauss(a, b, steps)


@njit(cache=True)
def _moving(values):
    """(v,) whether each column of values (p, v) takes more than one value."""
    v = values.shape[1]
    out = np.zeros(v, np.bool_)
    for e in range(v):
        for i in range(1, values.shape[0]):
            if values[i, e] != values[0, e]:
                out[e] = True
                break
    return out


@njit(cache=True)
def _rung(constant, varying, a, b, moving, first, steps, span, phi):
    """phi: the Magnus transition matrix over span (s) with ``steps`` steps of the series a, b
    of the varying entries; entries not ``moving`` keep their value ``first``. The three
    Gauss-point matrices of a step are kept in one buffer whose varying entries are rewritten
    per step (``floquet._magnus_steps`` on one step at a time)."""
    d, v = constant.shape[0], varying.shape[0]
    G = _at_gauss(a, b, steps)
    A = np.empty((3, d, d))
    for g in range(3):
        A[g] = constant
        for e in range(v):
            if not moving[e]:
                A[g, varying[e] // d, varying[e] % d] = first[e]
    w = np.empty((6, d, d))
    step_generator, E, other = np.empty((d, d)), np.empty((d, d)), np.empty((d, d))
    for step in range(steps):
        for g in range(3):
            for e in range(v):
                if moving[e]:
                    A[g, varying[e] // d, varying[e] % d] = G[3 * step + g, e]
        _generator6(A, 0, span / steps, step_generator, w)
        if step == 0:
            _expm(step_generator, phi, w)
        else:
            _expm(step_generator, E, w)
            _matmul(E, phi, other)
            phi[:, :] = other


@njit(cache=True)
def sampled_monodromy(constant, varying, values, steps, span, phi):
    """Transition matrix phi (d, d) over ``span`` (s), the period of the samples, by
    ``steps`` 6th-order Magnus steps of their interpolant (:func:`gauss_values`); entries
    whose samples are all equal keep their value exactly."""
    a, b = _coefficients(values)
    _rung(constant, varying, a, b, _moving(values), values[0].copy(), steps, span, phi)


@njit(cache=True)
def _multipliers(phi):
    """Eigenvalues (d,) of the real phi; 2 x 2 in closed form (the larger root first, the
    other from the determinant: no cancellation), else by :func:`eigvals_small`."""
    if phi.shape[0] != 2:
        return eigvals_small(phi)
    a, b, c, e = phi[0, 0], phi[0, 1], phi[1, 0], phi[1, 1]
    half, det = 0.5 * (a + e), a * e - b * c
    root = np.sqrt(complex(half * half - det))
    big = half + root if half >= 0 else half - root
    mu = np.empty(2, np.complex128)
    mu[0] = big
    mu[1] = det / big if big != 0 else 0.0
    return mu


@njit(cache=True, error_model="numpy")
def certified_flow(constant, varying, values, period, start, largest, tol, floor, exps):
    """Exponents exps (d,) complex (rad/s: the principal log(mu) / period, sorted by real,
    then imaginary part) of the multipliers mu of the period-``period`` (s) monodromy of
    the sampled generator, certified by step doubling from start / 2 steps up to ``largest``: the
    change of log max|mu| and of the sorted moduli (relative to max|mu|) between N / 2 and
    N steps, at least ``floor``, must be at most tol max(1, |log max|mu||) with the verdict
    log max|mu| <= tol outside it. Samples that repeat after half the period (p even, to
    1e-12 of their largest entry) are integrated over that half (mu = eig(Phi(T/2))^2).
    Returns (steps, error estimate, half): steps 0 when nothing certified (or the monodromy
    is not finite, or max|mu| is 0)."""
    d, p = constant.shape[0], values.shape[0]
    largest_entry = 0.0
    for i in range(d):
        for j in range(d):
            largest_entry = max(largest_entry, abs(constant[i, j]))
    for i in range(p):
        for e in range(values.shape[1]):
            largest_entry = max(largest_entry, abs(values[i, e]))
    half = p % 2 == 0
    if half:
        for i in range(p // 2):
            for e in range(values.shape[1]):
                if abs(values[p // 2 + i, e] - values[i, e]) > 1e-12 * largest_entry:
                    half = False
    span_values = values[: p // 2] if half else values
    span = 0.5 * period if half else period
    a, b = _coefficients(span_values)
    moving, first = _moving(span_values), span_values[0].copy()
    phi = np.empty((d, d))
    mod0 = np.empty(d)
    G0 = np.nan
    steps = start // 2
    while steps <= largest:
        _rung(constant, varying, a, b, moving, first, steps, span, phi)
        if not np.all(np.isfinite(phi)):
            return 0, np.inf, half
        m = _multipliers(phi)
        if half:
            m = m * m
        mod = np.sort(np.abs(m))
        if not mod[d - 1] > 0:
            return 0, np.inf, half
        G = np.log(mod[d - 1])
        if G0 == G0:
            err = max(abs(G - G0), np.abs(mod - mod0).max() / mod[d - 1], floor)
            if err <= tol * max(1.0, abs(G)) and abs(G - tol) > err:
                lam = np.log(m) / period
                order = np.argsort(lam.imag)  # then a stable sort by the real part
                order = order[np.argsort(lam.real[order], kind="mergesort")]
                exps[:] = lam[order]
                return steps, err, half
        G0 = G
        mod0[:] = mod
        steps *= 2
    return 0, np.inf, half
