"""The one home of "is it stable": the verdict and its result type (``floquet``:
:class:`FloquetExponents`, ``is_stable``), Hill's method (``hill``, eq. 25-27), the Magnus
monodromy and its certified ladder (``magnus``), the monodromy by direct integration
(``monodromy``) and stability boundaries over speed (``boundaries``)."""
