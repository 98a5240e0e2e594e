"""Each choice named after what it chooses: ``stability = "<method>"`` in sweep files
(the old ``method`` key still read, with a warning) and ``campbell(eigensolver=)``."""

import pytest

from periodyn.errors import InputError
from periodyn.studies.spec import parse_sweep

FILE = """
[model]
example = "pendulum"
[sweep]
omega = {{ start = 0.1, stop = 1.2, num = 3, unit = "omega0" }}
harmonics = 4
{line}
"""


@pytest.mark.parametrize("line, stability, method", [("", True, "auto"), ("stability = true", True, "auto"),
                                                     ("stability = false", False, "auto"),
                                                     ('stability = "dense"', True, "dense")])
def test_stability_takes_true_false_or_a_method(line, stability, method):
    spec = parse_sweep(FILE.format(line=line))
    assert (spec.stability, spec.method) == (stability, method)


def test_the_old_method_key_is_read_with_a_note():
    with pytest.warns(DeprecationWarning, match=r'old name of stability = "magnus"'):
        spec = parse_sweep(FILE.format(line='method = "magnus"'))
    assert (spec.stability, spec.method) == (True, "magnus")
    with pytest.raises(InputError, match="give the stability method once"):
        parse_sweep(FILE.format(line='stability = "dense"\nmethod = "dense"'))
    with pytest.raises(InputError, match=r"stability: must be true or false or a stability method.*'sparse'"):
        parse_sweep(FILE.format(line='stability = "sprase"'))


def test_campbell_names_its_eigensolver():
    import periodyn

    model = periodyn.examples.rotor()
    new = periodyn.campbell(model, [100.0], modes=4, eigensolver="dense")
    with pytest.warns(DeprecationWarning, match="eigensolver='dense'"):
        old = periodyn.campbell(model, [100.0], modes=4, method="dense")
    assert (new.eigenvalue.values == old.eigenvalue.values).all() and new.attrs["method"] == "dense"
    with pytest.raises(InputError, match="eigensolver must be"):
        periodyn.campbell(model, [100.0], eigensolver="fast")
