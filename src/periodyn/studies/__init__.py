"""Study files (TOML): ONE dialect, parsed by ``spec`` (the one entry, the dispatch on a
file's kind, ``run`` and ``ensure``), with ONE "is this result current" rule (``cache``);
the shared checker (``checks``), element models in a file (``elements``) and one module
per kind: ``sweep``, ``continuation`` (orbits at given speeds in ``points``; in ``orbits``
what it stores for the figures: a time history, element outputs), ``transient`` and
``campbell``."""
