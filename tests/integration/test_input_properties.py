"""Property-based tests (hypothesis) over sweep files and sweep() arguments: every input
either runs or is refused cleanly (InputError / exit code 2 with a message naming the
problem), never a traceback, and a run never holds a silent NaN: each point is either
solved with every number finite, or failed with its reason."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from periodyn.cli import main
from periodyn.errors import InputError
from periodyn.examples import pendulum
from periodyn.results import STATUS_FAILED, STATUS_SOLVED, load
from periodyn.engine.front import sweep

W0 = math.sqrt(9.81)
SETTINGS = settings(max_examples=50, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])

FINITE_CHECKED = ("amplitude", "mean", "harmonics", "residual")
STABILITY_CHECKED = ("exponents", "multipliers", "max_real_exponent")


def assert_honest(ds) -> None:
    """Each point solved with finite numbers, or failed (NaN, not stable) with a reason."""
    status = ds["status"].values.reshape(-1)
    assert set(np.unique(status)) <= {STATUS_SOLVED, STATUS_FAILED}
    stability = bool(int(ds.attrs.get("stability", 1)))
    names = FINITE_CHECKED + (STABILITY_CHECKED if stability else ())
    point_dims = ds["status"].dims
    for name in names:
        values = ds[name].values.reshape(status.size, -1)
        finite = np.isfinite(values).all(axis=1)
        assert finite[status == STATUS_SOLVED].all(), f"{name} holds a non-finite number at a solved point"
    messages = ds["message"].values.reshape(-1)
    assert all(messages[status == STATUS_FAILED]), "a failed point without its reason"
    assert not ds["stable"].values.reshape(-1)[status == STATUS_FAILED].any()
    assert ds.attrs["failed_points"] == int((status == STATUS_FAILED).sum())
    assert point_dims[-1] == "omega"


# ----------------------------------------------------------------------------- sweep files
ANY_SCALAR = st.one_of(st.booleans(), st.text(max_size=4), st.floats(allow_nan=True, allow_infinity=True))
#: per field: (values that run, values to try as the one broken field of a file)
FIELDS = {
    "harmonics": (st.integers(1, 6), st.one_of(st.integers(-2, 0), st.sampled_from([40, 1000, 1001, 100000]),
                                               ANY_SCALAR)),
    "samples": (st.one_of(st.none(), st.integers(13, 32)), st.one_of(st.integers(-1, 12), st.just(200001),
                                                                     ANY_SCALAR)),
    "start": (st.floats(0.05, 1.5), st.one_of(st.sampled_from([0.0, -1.0, 1e300, 1e-300]), ANY_SCALAR)),
    "stop": (st.floats(0.05, 1.5), st.one_of(st.sampled_from([0.0, -1.0, 1e300, 1e-300]), ANY_SCALAR)),
    "num": (st.integers(1, 4), st.one_of(st.integers(-1, 0), st.just(10**8), ANY_SCALAR)),
    "unit": (st.sampled_from(["omega0", "Hz"]), st.one_of(st.sampled_from(["omega1", "furlongs"]), ANY_SCALAR)),
    "stability": (st.one_of(st.booleans(), st.sampled_from(["auto", "dense", "sparse", "monodromy", "magnus"])),
                  st.one_of(st.sampled_from(["fast", "Dense"]), ANY_SCALAR.filter(lambda v: not isinstance(v, bool)))),
    "eccentricity": (st.one_of(st.floats(0.0, 0.9), st.sampled_from([1e300, 1e150, 1e-300])),
                     st.one_of(st.floats(max_value=-1e-9), ANY_SCALAR)),
    "zeta": (st.one_of(st.floats(0.0, 0.5), st.just(1e300)), st.one_of(st.floats(max_value=-1e-9), ANY_SCALAR)),
    "length": (st.floats(0.1, 5.0), st.one_of(st.sampled_from([0.0, -1.0]), ANY_SCALAR)),
}


def toml_value(value) -> str:
    """A Python value as TOML text (numbers including nan and inf, strings, booleans)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    return repr(value)


@st.composite
def sweep_files(draw) -> str:
    """A pendulum sweep file of at most 4 speeds with at most one broken field (edge
    values such as eccentricity = 1e300 count as valid: they must run)."""
    broken = draw(st.sampled_from([None] * 5 + list(FIELDS)))
    v = {name: draw(bad if name == broken else good) for name, (good, bad) in FIELDS.items()}
    if broken not in ("samples", "harmonics") and v["samples"] is not None and v["samples"] < 2 * v["harmonics"] + 1:
        v["samples"] = None
    lines = ["[model]", 'example = "pendulum"', "[model.parameters]"]
    lines += [f"{name} = {toml_value(v[name])}" for name in ("eccentricity", "zeta", "length")]
    lines += ["[sweep]", f"omega = {{ start = {toml_value(v['start'])}, stop = {toml_value(v['stop'])}, "
                         f"num = {toml_value(v['num'])}, unit = {toml_value(v['unit'])} }}",
              f"harmonics = {toml_value(v['harmonics'])}", f"stability = {toml_value(v['stability'])}"]
    if v["samples"] is not None:
        lines.append(f"samples = {toml_value(v['samples'])}")
    return "\n".join(lines) + "\n"


@SETTINGS
@given(text=sweep_files())
def test_every_sweep_file_runs_or_is_refused_cleanly(tmp_path, capsys, text):
    path = tmp_path / "prop.toml"
    out = tmp_path / "prop.nc"
    path.write_text(text)
    out.unlink(missing_ok=True)
    code = main(["sweep", str(path), "--out", str(out), "--workers", "1", "-q"])
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err
    if code == 2:
        assert f"error: {path}: " in captured.err  # the message starts with the file (then the table)
        assert not out.exists()
        return
    assert code == 0, captured.err
    assert_honest(load(out))


# ----------------------------------------------------------------------------- API arguments
SPEED = st.one_of(st.floats(0.05, 1.5).map(lambda r: r * W0), st.sampled_from([0.0, -1.0, 1e300, 1e-300]),
                  ANY_SCALAR)
OMEGA = st.one_of(st.lists(st.floats(0.05, 1.5).map(lambda r: r * W0), min_size=1, max_size=3),
                  st.lists(SPEED, min_size=0, max_size=3), ANY_SCALAR)


@SETTINGS
@given(data=st.data(), omega=OMEGA)
def test_every_sweep_call_runs_or_is_refused_cleanly(data, omega):
    broken = data.draw(st.sampled_from([None, None, "harmonics", "samples", "stability", "eccentricity", "zeta"]))
    v = {name: data.draw(bad if name == broken else good)
         for name, (good, bad) in FIELDS.items() if name in ("harmonics", "samples", "stability", "eccentricity", "zeta")}
    try:
        model = pendulum(samples=24, eccentricity=v["eccentricity"], zeta=v["zeta"])
    except (InputError, TypeError):  # the builder refuses a bad parameter by name
        return
    try:
        ds = sweep(model, omega, v["harmonics"], v["samples"], v["stability"], progress=False)
    except InputError as exc:
        assert str(exc)
        return
    assert_honest(ds)


def test_property_helper_catches_a_silent_nan():
    ds = sweep(pendulum(samples=24), W0 * np.array([0.5, 0.7]), 3, progress=False)
    ds["residual"].values[0] = np.nan
    with pytest.raises(AssertionError, match="residual holds a non-finite number"):
        assert_honest(ds)
