"""The one home of "is it stable": the verdict and its result type (``floquet``:
:class:`FloquetExponents`, ``is_stable``), the one registry of stability methods with the
"auto" rule, its costs and the scalar entry points (``methods``), a method over chunks of
speeds (``batch``), Hill's method (``hill``, eq. 25-27), the Magnus monodromy and its
certified ladder (``magnus``), the monodromy by direct integration (``monodromy``), the one
classifier of a stability loss (``crossings``), stability boundaries over speed
(``boundaries``) and followed over a model parameter as a stability chart (``charts``, its
data and file layout in ``chart_data``)."""
