"""The built-model cache of sweep files (periodyn.studies.cache.cached_model): a second sweep
of a model reads it instead of building it, with the same result to the bit; the key is what
the build reads and runs; a damaged, disabled, unwritable or full cache never changes a result."""

from __future__ import annotations

import dataclasses
import functools

import numpy as np
import pytest
import xarray as xr

from periodyn.engine.front import sweep_file
from periodyn.studies import cache
from periodyn.studies.spec import parse_sweep

PENDULUM = """
[model]
example = "pendulum"

[model.parameters]
length = 1.0
radius = 0.5
eccentricity = 0.5
zeta = 0.01

[sweep]
omega = { start = 0.2, stop = 1.2, num = 6, unit = "omega0" }
harmonics = 6
samples = 32
"""


@pytest.fixture
def store(tmp_path, monkeypatch):
    folder = tmp_path / "cache"
    monkeypatch.setenv("PERIODYN_CACHE_DIR", str(folder))
    monkeypatch.delenv("PERIODYN_MODEL_CACHE", raising=False)
    return folder / "models"


def _spec(text=PENDULUM):
    return parse_sweep(text, "p.toml", "p")


def _counted(spec):
    """The spec with its builder counting its calls (same signature)."""
    calls = []
    builder = spec.builder

    @functools.wraps(builder)
    def counting(**kwargs):
        calls.append(kwargs)
        return builder(**kwargs)

    return dataclasses.replace(spec, builder=counting), calls


def _without_timings(ds):
    out = ds.drop_vars([v for v in ds.data_vars if "time" in v])
    out.attrs = {k: v for k, v in ds.attrs.items() if "elapsed" not in k and "time" not in k}
    return out


def test_a_second_sweep_reads_the_model_and_gives_the_same_bits(store, monkeypatch):
    spec, calls = _counted(_spec())
    first = sweep_file(spec, progress=False)
    assert len(calls) == 1 and len(list(store.glob("*.npz"))) == 1
    second = sweep_file(spec, progress=False)
    assert len(calls) == 1  # read, not built
    xr.testing.assert_identical(_without_timings(first), _without_timings(second))
    built, read = spec._build(), spec.build()
    for name in ("mass", "damping", "stiffness", "force", "output_maps"):
        assert np.array_equal(getattr(built, name), getattr(read, name))
    assert (read.coordinate_names, read.output_names, read.name, read.metadata) == (
        built.coordinate_names, built.output_names, built.name, built.metadata)
    resampled, fresh = read.with_samples(48), built.with_samples(48)  # resampling is the builder's
    assert np.array_equal(resampled.stiffness, fresh.stiffness)


def test_the_key_is_what_the_build_reads_and_runs(store, monkeypatch):
    key = cache.model_fingerprint(_spec())
    assert cache.model_fingerprint(_spec(PENDULUM.replace("num = 6", "num = 9"))) == key  # the speeds: same model
    assert cache.model_fingerprint(_spec(PENDULUM.replace("harmonics = 6", "harmonics = 4"))) == key
    assert cache.model_fingerprint(_spec(PENDULUM.replace("zeta = 0.01", "zeta = 0.02"))) != key
    assert cache.model_fingerprint(_spec(PENDULUM.replace("samples = 32", "samples = 48"))) != key
    monkeypatch.setattr(cache, "code_version", lambda: "another periodyn")
    assert cache.model_fingerprint(_spec()) != key


def test_a_damaged_entry_is_built_again(store, monkeypatch):
    spec, calls = _counted(_spec())
    spec.build()
    (entry,) = store.glob("*.npz")
    entry.write_bytes(entry.read_bytes()[:200])
    model = spec.build()
    assert len(calls) == 2 and np.array_equal(model.mass, spec._build().mass)
    spec.build()
    assert len(calls) == 3  # the entry written again whole
    spec.build()
    assert len(calls) == 3


def test_off_builds_every_time_and_writes_nothing(store, monkeypatch):
    monkeypatch.setenv("PERIODYN_MODEL_CACHE", "off")
    spec, calls = _counted(_spec())
    spec.build()
    spec.build()
    assert len(calls) == 2 and not store.exists()


def test_an_unwritable_cache_is_passed_by(tmp_path, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("PERIODYN_CACHE_DIR", str(blocker))
    spec = _spec()
    assert np.array_equal(spec.build().mass, spec._build().mass)


def test_the_least_recently_used_go_beyond_the_budget(store, monkeypatch):
    size = None
    for i, zeta in enumerate(("0.01", "0.02", "0.03")):
        _spec(PENDULUM.replace("zeta = 0.01", f"zeta = {zeta}")).build()
        size = size or next(store.glob("*.npz")).stat().st_size
        if i == 1:
            monkeypatch.setattr(cache, "MODEL_CACHE_BYTES", 2 * size)
    kept = {p.name for p in store.glob("*.npz")}
    assert len(kept) == 2
    assert f"{cache.model_fingerprint(_spec())}.npz" not in kept  # the oldest
