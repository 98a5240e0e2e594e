"""Special points of the shipped 41-body slider-chain study (Ju, Fan & Zhu 2021, App. B eqs.
(70)-(82); sweeps/dae_slider_chain_pendulum.toml, IHB with H = 10) and their verdicts.

The study runs ``confirm = "truncation"``: every special point carries its orbit defect (DAE
residual between the IHB samples relative to the force scale); where it exceeds 1e-3 the
branch is continued afresh at H = 14 around the point. Of the 28 points, 19 are rejected:
18 in 6.339-6.475 rad/s, next to the fold at 6.339 (defects 3.5e-3 to 5.3e-3), among them
that fold, 6 branch points and 11 Neimark-Sacker points: Newton at H = 14 converges from
none of their orbits, or the H = 14 branch has its Neimark-Sacker point at 6.32569 on an
orbit unresolved too (defect 1.9e-3); and the Neimark-Sacker point at 6.54329 (defect 1.3e-3;
the H = 14 branch has none within 1 %). 9 are left open: 8 resolved (defect <= 1e-3) and the
Neimark-Sacker point at 6.65460, found at 6.59669 on a resolved H = 14 orbit (defect 9e-4).
By one period of the DAE with its variational equations (benchmarks/confirm_chain.py
--integrate) the open Neimark-Sacker point at 7.30385 is confirmed (2 complex multipliers
outside the unit circle at 7.18546, 0 at 7.33522), pinned below.
"""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from periodyn.studies.spec import load_sweep_file, project_root
from periodyn.arclength import confirm_special_points
from periodyn.studies.continuation import load_study, run_study

pytestmark = pytest.mark.slow  # CPU: the branch ~90 s, its truncation check ~120 s, one integration ~40 s

STUDY = project_root() / "sweeps" / "dae_slider_chain_pendulum.toml"
NS, BP, FOLD = "neimark-sacker", "branch-point", "fold"
OPEN = {  # omega (rad/s, 5 decimals) -> type: left open by the truncation check
    7.23968: FOLD, 6.83196: NS, 6.60155: BP, 6.65460: NS, 6.90036: NS, 7.30385: NS, 9.60640: FOLD, 9.50780: BP,
    9.50597: FOLD}
SPURIOUS = {  # rejected by it
    6.54329: NS, 6.35407: NS, 6.34818: NS, 6.34559: NS, 6.34101: NS, 6.33989: NS, 6.33896: NS, 6.33877: FOLD,
    6.33887: NS, 6.33960: NS, 6.34053: BP, 6.35007: BP, 6.34100: BP, 6.35908: BP, 6.35027: BP, 6.36891: BP,
    6.41654: NS, 6.45647: NS, 6.47475: NS}


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    spec = load_sweep_file(STUDY)
    out = Path(tmp_path_factory.mktemp("chain")) / "chain.nc"
    return spec, run_study(spec, out)["frequency"], out


def test_every_point_is_checked_and_the_verdicts_are_pinned(study):
    _, br, _ = study
    assert [len(br.points(t)) for t in ("fold", "branch-point", "neimark-sacker")] == [4, 8, 16]
    verdicts = {round(p.omega, 5): p for p in br.special_points}
    assert {w for w, p in verdicts.items() if p.confirmed is None} == set(OPEN)
    assert {w for w, p in verdicts.items() if p.confirmed is False} == set(SPURIOUS)
    for w, p in verdicts.items():
        assert p.type == (OPEN | SPURIOUS)[w]
        assert np.isfinite(p.defect)
        if p.confirmed is False:
            assert p.defect > 1e-3 and p.check.startswith("spurious: orbit defect") and "H' = 14" in p.check
        elif p.defect <= 1e-3:
            assert p.check.startswith("resolved")
        else:
            assert p.check.startswith("persists") and "H' = 14" in p.check


def test_verdicts_survive_the_study_file(study):
    _, br, out = study
    back = load_study(out)["frequency"]
    for a, b in zip(br.special_points, back.special_points):
        assert (a.confirmed, a.check, a.defect) == (b.confirmed, b.check, b.defect)


def test_the_resolved_neimark_sacker_point_at_7_30_is_confirmed_by_integration(study):
    spec, br, _ = study
    (ns,) = [p for p in br.points("neimark-sacker") if abs(p.omega - 7.30385) < 1e-4]
    (checked,) = confirm_special_points(replace(br, special_points=(ns,)), spec.build(), rtol=1e-8).special_points
    assert checked.confirmed is True and "2 at omega=7.18546" in checked.check and ", 0 at 7.33522" in checked.check
