"""Numerics shared by the linear and the non-linear floor: Fourier spectra and their
conventions (``spectra``: FFT plans, the band threshold, sampled series), the one Newton
(``newton_iteration``), Krylov solves (``krylov``), the one integrator wrapper and
stabilized index-1 integration (``integration``), stiff integration of ODE models
(``stiff``), the phase-time flow with variational equations (``flow``: monodromy
columns and parameter sensitivities) and one BLAS/Numba thread for the computing paths
(``threads``)."""
