"""Numba-jitted kernels: the only compiled code in periodyn.

Convention: ``@njit(cache=True)``; float64/complex128 arrays and int loop bounds only, no
Python objects; outputs are caller-allocated ``out`` arrays where a kernel fills a block.
One module per family: ``harmonic`` (Fourier-series evaluation), element families in
their own modules. Every kernel has a plain-NumPy twin in the tests.
"""
