"""Rotor files are type-checked and report positions in the file's own units: a string
stiffness (TypeError), a zero length unit (ZeroDivisionError) and a binary file
(UnicodeDecodeError) used to escape as tracebacks; positions were given in metres for a
file in inches."""

from __future__ import annotations

import pytest

from periodyn.errors import InputError
from periodyn.rotor import load_rotor
from periodyn.studies.spec import project_root

TABLE1 = project_root() / "sweeps" / "rotors" / "table1.toml"


def _file(tmp_path, old: str, new: str):
    text = TABLE1.read_text()
    assert old in text
    path = tmp_path / "r.toml"
    path.write_text(text.replace(old, new, 1))
    return path


@pytest.mark.parametrize("old, new, match", [
    ("kyy = 1.0e5", 'kyy = "stiff"', r"\[\[bearing\]\] number 1 kyy must be a finite number .*'stiff'"),
    ("length = 0.0254", "length = 0", r"\[units\] length must be a positive finite number"),
    ("mass = 0.45359237", "mass = -1.0", r"\[units\] mass must be a positive"),
    ("E = 3.0e7", "E = true", r"\[material\] E must be a positive finite number"),
    ("elements = 5", "elements = 2.5", r"\[\[shaft\]\] number 1 elements must be a positive integer"),
    ("elements = 5", "elements = 5\nrotary_inertia = 1", r"\[\[shaft\]\] number 1 rotary_inertia must be true or false"),
    ("name = \"rotor\"", "name = 3", r"\[rotor\] name must be a string"),
    ("end = 50.0", "end = 0.0", r"\[\[shaft\]\] number 1: shaft section .*end must lie beyond start"),
    ("at = 20.0\nK", "at = nan\nK", r"\[\[seal\]\] number 1 at must be a finite number"),
])
def test_bad_values_are_refused_naming_file_entry_and_key(tmp_path, old, new, match):
    path = _file(tmp_path, old, new)
    with pytest.raises(InputError, match=rf"r\.toml: {match}"):
        load_rotor(path)


def test_a_binary_file_is_refused(tmp_path):
    path = tmp_path / "r.toml"
    path.write_bytes(bytes(range(256)))
    with pytest.raises(InputError, match=r"r\.toml is not a text file"):
        load_rotor(path)


def test_a_position_off_the_stations_is_reported_in_the_files_inches(tmp_path):
    path = _file(tmp_path, "at = 40.0", "at = 45.0")
    with pytest.raises(InputError, match=r"r\.toml: rotor 'rotor': disk at 45\.0 \(file length units of 0\.0254 m; "
                                         r"1\.143 m\) is not on a station; stations are at \[0\.0, 10\.0, 20\.0"):
        load_rotor(path)
