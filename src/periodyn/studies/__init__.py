"""Study files (TOML): the checker every file kind shares (``checks``), the speed-sweep
file and the dispatch on a file's kind (``spec``), element models written in a file
(``elements``), continuation studies (``continuation``, with orbits at listed speeds in
``points``) and transients (``transient``)."""
