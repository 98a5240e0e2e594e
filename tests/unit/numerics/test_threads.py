"""periodyn.numerics.threads: the non-linear solvers run with one Numba (and BLAS) thread
and give the caller's settings back; nested blocks keep the outermost block's limits."""

import numba
import numpy as np

import periodyn
from periodyn.numerics.threads import one_thread


def _duffing_recording(seen: list) -> periodyn.DAE:
    """x'' + 0.1 x' + x + 0.5 x^3 = 0.5 cos(w t), its force recording Numba's thread count."""
    def force(q, qd, t, omega):
        seen.append(numba.get_num_threads())
        return -0.1 * qd - q - 0.5 * q**3 + 0.5 * np.cos(omega * t)[..., None]

    return periodyn.DAE(np.eye(1), force)


def test_solvers_run_with_one_thread_and_restore_the_callers():
    outside = numba.get_num_threads()
    seen = []
    system = _duffing_recording(seen)
    seen.clear()  # the DAE's own checks call the force outside any solver
    orbit = periodyn.ihb(system, 1.2, 3)
    periodyn.shooting(system, 1.2, initial=orbit)
    assert seen and set(seen) == {1}
    assert numba.get_num_threads() == outside


def test_nested_blocks_keep_one_thread_until_the_outermost_ends():
    outside = numba.get_num_threads()
    with one_thread():
        with one_thread():
            assert numba.get_num_threads() == 1
        assert numba.get_num_threads() == 1
    assert numba.get_num_threads() == outside
