"""Solver kernels: block-banded LU of the harmonic-balance operator, Floquet multipliers
and the certified Magnus ladder, Fourier-series evaluation, implicit and explicit flows of
element and rigid planar models, saddle-point solves, products by the entries of sparse
factors and the eigenvalues of small real matrices by the double-shift QR."""
