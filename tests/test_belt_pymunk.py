"""The exact belt solver against the same chains built as rigid bodies in pymunk.

Tolerance: pymunk's iterative contact solver holds static friction ~0.4 %
past mu_s*N (its normal impulse carries the overlap correction), so a 1-DOF
stick ends ~0.015 s late in a 5 s cycle: phase durations agree to ~1 %, and
switch times to 2 % of a cycle over the first cycles.
"""

import numpy as np
import pytest

from asperity2d.belt import simulate_chain
from belt_pymunk import simulate_chain_rigid


def _long(intervals, t_max, min_length):
    return [iv for iv in intervals if iv[1] - iv[0] >= min_length and iv[0] < t_max]


def test_one_mass_stick_intervals_match_the_exact_solver():
    kw = dict(masses=[1.0], springs=[10.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.2,
              v_belt=0.1, x0=[0.0], v0=[0.1], t_end=12.0)
    exact = simulate_chain(**kw).stick_intervals[0]
    rigid = simulate_chain_rigid(**kw).stick_intervals()[0]
    assert len(exact) == len(rigid) == 3
    e, r = np.array(exact), np.array(rigid)
    # each full stick phase and each slip phase lasts as long, to 1.5 %
    # (measured: stick +0.9 %, slip +0.45 %) ...
    np.testing.assert_allclose(r[1, 1] - r[1, 0], e[1, 1] - e[1, 0], rtol=0.015)
    np.testing.assert_allclose(r[1:, 0] - r[:-1, 1], e[1:, 0] - e[:-1, 1], rtol=0.015)
    # ... so over two cycles the switch times stay within 2 % of a cycle
    np.testing.assert_allclose(r, e, atol=0.02 * (e[1, 0] - e[0, 0]))


def test_three_mass_table2_stick_intervals_match_the_exact_solver():
    kw = dict(masses=[1.0] * 3, springs=[10.0] * 4, dampers=[0.0] * 4, mu_s=0.2, v_belt=0.1,
              x0=[0.05, 0.06, 0.07], v0=[0.04, 0.03, 0.05], t_end=10.0)
    exact = simulate_chain(**kw).stick_intervals
    rigid = simulate_chain_rigid(**kw).stick_intervals()
    for i in range(3):
        e, r = _long(exact[i], 10.0, 0.1), _long(rigid[i], 10.0, 0.1)
        assert len(e) == len(r) >= 1, i
        np.testing.assert_allclose(np.array(r), np.array(e), atol=0.03)


def test_rigid_chain_rejects_bad_input():
    from asperity2d import SceneError

    with pytest.raises(SceneError, match="`mu_s`"):
        simulate_chain_rigid([1.0], [1.0, 1.0], [0.0, 0.0], mu_s=0.1, mu_k=0.2, v_belt=0.1,
                             x0=[0.0], v0=[0.0], t_end=1.0)
    with pytest.raises(SceneError, match="`springs`"):
        simulate_chain_rigid([1.0], [1.0], [0.0, 0.0], mu_s=0.1, v_belt=0.1,
                             x0=[0.0], v0=[0.0], t_end=1.0)
