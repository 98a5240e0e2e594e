"""Kernels on truncated Fourier series ``x(theta) = sum_{k=-M..M} c_k exp(i k theta)``."""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def _value_d1_d2(c, col, theta):
    """x, x' and x'' at theta of the real series with the conjugate-symmetric spectrum
    c[:, col]: x = c_0 + 2 Re sum_{k>0} c_k z^k, z = exp(i theta), the powers of z by
    recurrence (one exp per evaluation; rounding grows like k eps)."""
    M = (c.shape[0] - 1) // 2
    z = np.exp(1j * theta)
    e = z
    v = 0.0
    d1 = 0.0
    d2 = 0.0
    for k in range(1, M + 1):
        t = c[M + k, col] * e
        v += t.real
        d1 -= k * t.imag
        d2 -= k * k * t.real
        e *= z
    return c[M, col].real + 2.0 * v, 2.0 * d1, 2.0 * d2


@njit(cache=True)
def half_range(c, grid, out_half, out_mean):
    """Half peak-to-peak and mean of real series with spectra c (2M+1, r) complex
    (conjugate-symmetric, c_{-k} = conj(c_k)).

    grid: (g, r) samples of the series at g equidistant angles (locates the extrema,
    which 4 Newton steps on the derivative then refine). Fills out_half, out_mean (r,)."""
    M = (c.shape[0] - 1) // 2
    g = grid.shape[0]
    step = 2.0 * np.pi / g
    for col in range(c.shape[1]):
        out_mean[col] = c[M, col].real
        imax = 0
        imin = 0
        for i in range(g):
            if grid[i, col] > grid[imax, col]:
                imax = i
            if grid[i, col] < grid[imin, col]:
                imin = i
        top = grid[imax, col]
        bottom = grid[imin, col]
        for start, sign in ((imax, 1.0), (imin, -1.0)):
            theta = start * step
            for _ in range(4):
                v, d1, d2 = _value_d1_d2(c, col, theta)
                if d2 == 0.0:
                    break
                theta -= d1 / d2
            v, d1, d2 = _value_d1_d2(c, col, theta)
            if sign > 0 and v > top:
                top = v
            if sign < 0 and v < bottom:
                bottom = v
        out_half[col] = 0.5 * (top - bottom)
