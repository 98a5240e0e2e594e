"""Integration tests: the command line, the engine (worker processes, Dask, checkpoints),
kernel warm-up, every shipped study file and runs in fresh interpreters. Every test here
carries the ``jit`` marker (conftest.py): ``python -m pytest -m "not jit"`` leaves them out
for a fast loop; CI runs them."""
