"""Plain-NumPy twins of the jitted kernels, written independently of them: ``planar``
(planar multibody), ``spatial`` (spatial beam), ``spatial_joints`` (rotation helpers,
spatial joints, rigid bodies). Each kernel must match its twin to about 1e-13
(tests/unit/kernels/). The twins need NumPy and periodyn only, never pytest:
benchmarks/bench_linearize.py imports ``planar``."""
