"""Kernels on truncated Fourier series ``x(theta) = sum_{k=-M..M} c_k exp(i k theta)``."""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def _value_d1_d2(c, col, theta):
    M = (c.shape[0] - 1) // 2
    v = 0.0
    d1 = 0.0
    d2 = 0.0
    for j in range(c.shape[0]):
        k = j - M
        e = np.exp(1j * k * theta)
        t = c[j, col] * e
        v += t.real
        d1 += (1j * k * t).real
        d2 -= k * k * t.real
    return v, d1, d2


@njit(cache=True)
def half_range(c, grid, out_half, out_mean):
    """Half peak-to-peak and mean of real series with spectra c (2M+1, r) complex.

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
