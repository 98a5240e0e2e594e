"""One line with the installed version of every dependency periodyn's tests use."""

from importlib.metadata import PackageNotFoundError, version

names = ("numpy", "scipy", "numba", "llvmlite", "pyfftw", "matplotlib", "xarray", "pandas", "h5netcdf", "h5py",
         "dask", "distributed", "pytest", "hypothesis")
found = []
for name in names:
    try:
        found.append(f"{name} {version(name)}")
    except PackageNotFoundError:
        found.append(f"{name} missing")
print(", ".join(found))
