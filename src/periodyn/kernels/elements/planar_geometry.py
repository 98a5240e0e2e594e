"""Shared planar geometry for the planar element families: length ``l`` and direction
angle ``alpha`` of the chord ``u = x_q - x_p`` and their derivatives up to third order
with respect to the element's local nodal coordinates.

With ``z = u_x + i u_y``: ``log z = log l + i alpha`` and the n-th derivative of
``log z`` with respect to components (a1..an) is ``(-1)^(n-1) (n-1)! w_a1...w_an / z^n``,
``w = (1, i)``; real parts are derivatives of ``log l``, imaginary parts of ``alpha``.
"""

import numpy as np
from numba import njit


@njit(cache=True)
def chord(xe, ip, iq, n):
    """Chord from local position coordinates ``xe[ip:ip+2]`` to ``xe[iq:iq+2]``.

    Returns (length, angle, L1, L2, L3, A1, A2, A3): length (m) and angle (rad), and
    their first to third derivatives w.r.t. the first n local coordinates (the element's;
    xe may be longer), L1/A1 (n,), L2/A2 (n,n), L3/A3 (n,n,n).
    """
    L1, A1 = np.empty(n), np.empty(n)
    L2, A2 = np.empty((n, n)), np.empty((n, n))
    L3, A3 = np.empty((n, n, n)), np.empty((n, n, n))
    ux = xe[iq] - xe[ip]
    uy = xe[iq + 1] - xe[ip + 1]
    z = complex(ux, uy)
    length = abs(z)
    inv = 1.0 / z
    w = (1.0 + 0.0j, 1.0j)
    # derivatives of log z w.r.t. (ux, uy)
    g1 = np.empty(2, dtype=np.complex128)
    g2 = np.empty((2, 2), dtype=np.complex128)
    g3 = np.empty((2, 2, 2), dtype=np.complex128)
    for a in range(2):
        g1[a] = w[a] * inv
        for b in range(2):
            g2[a, b] = -w[a] * w[b] * inv * inv
            for c in range(2):
                g3[a, b, c] = 2.0 * w[a] * w[b] * w[c] * inv * inv * inv
    # length derivatives from l = exp(Re log z)
    l1 = np.empty(2)
    l2 = np.empty((2, 2))
    l3 = np.empty((2, 2, 2))
    for a in range(2):
        l1[a] = length * g1[a].real
        for b in range(2):
            l2[a, b] = length * (g2[a, b].real + g1[a].real * g1[b].real)
            for c in range(2):
                l3[a, b, c] = length * (g3[a, b, c].real + g2[a, b].real * g1[c].real
                                        + g2[a, c].real * g1[b].real + g2[b, c].real * g1[a].real
                                        + g1[a].real * g1[b].real * g1[c].real)
    # map (ux, uy) to local coordinates: u = xe[iq:iq+2] - xe[ip:ip+2]
    L1[:] = 0.0
    L2[:] = 0.0
    L3[:] = 0.0
    A1[:] = 0.0
    A2[:] = 0.0
    A3[:] = 0.0
    idx = (ip, ip + 1, iq, iq + 1)
    sgn = (-1.0, -1.0, 1.0, 1.0)
    comp = (0, 1, 0, 1)
    for i in range(4):
        a = comp[i]
        si = sgn[i]
        L1[idx[i]] += si * l1[a]
        A1[idx[i]] += si * g1[a].imag
        for j in range(4):
            b = comp[j]
            sij = si * sgn[j]
            L2[idx[i], idx[j]] += sij * l2[a, b]
            A2[idx[i], idx[j]] += sij * g2[a, b].imag
            for k in range(4):
                c = comp[k]
                sijk = sij * sgn[k]
                L3[idx[i], idx[j], idx[k]] += sijk * l3[a, b, c]
                A3[idx[i], idx[j], idx[k]] += sijk * g3[a, b, c].imag
    return length, np.arctan2(uy, ux), L1, L2, L3, A1, A2, A3
