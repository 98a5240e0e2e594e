"""Per-model sweep data kept with the model (OmegaSplitModel.derived): a second sweep of the
same model reuses it, and a speed's result does not depend on what the model solved before."""

import pickle

import numpy as np
import xarray as xr

import periodyn
from periodyn.examples.slider_crank_rod import first_bending_frequency, slider_crank_model
from periodyn.model.linearization import omega_split


def crank(elements: int):
    w1 = first_bending_frequency(slider_crank_model(0.0, rod_elements=elements))
    return omega_split(slider_crank_model(2 * 0.02 / w1, rod_elements=elements), 64)


def kept(model) -> dict:
    return {kind: entry[1] for kind, entry in model.__dict__.get("_derived", {}).items()}


def test_a_second_sweep_reuses_the_model_data_and_gives_the_same_bits():
    """16 rod elements (32 coordinates: "auto" takes the reduced method and the reduced HB):
    the model's data built by a first sweep over other speeds (other chunks, other coupling
    bands) is reused, not rebuilt, and the results equal those of a fresh model to the bit;
    the data is not pickled."""
    w = np.array([150.0, 205.0, 266.5, 300.0])
    model = crank(16)
    periodyn.sweep(model, np.linspace(290.0, 160.0, 7), 12, progress=False)
    first = kept(model)
    assert {"prepared reduced", "reduced_balance", "sweep_truncation"} <= set(first)
    again = periodyn.sweep(model, w, 12, progress=False)
    assert all(kept(model)[kind] is obj for kind, obj in first.items())
    assert set(again["stability_method"].values) == {"reduced"} and (again["balance_modes"].values > 0).all()
    fresh = periodyn.sweep(crank(16), w, 12, progress=False)
    xr.testing.assert_equal(again, fresh)  # exact values, coordinates and names; attributes (timings) aside
    assert "_derived" not in pickle.loads(pickle.dumps(model)).__dict__


def test_another_key_replaces_the_kinds_entry():
    """One entry per kind (memory stays bounded): the same key reuses it, another replaces it."""
    model = crank(4)
    built = []
    for m in (3, 3, 4):
        model.derived("example", m, lambda: built.append(m) or object())
    assert built == [3, 4] and model.__dict__["_derived"]["example"][0] == 4
