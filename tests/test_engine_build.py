"""Building and freeing a scene's space in linear time (issue 27 item 7).

Chipmunk's bounding-box tree chained a surface added in x order (O(n^2) to build: 100,000
asperities took ~20 min) and pymunk freed a space in O(n^2) (over 5 min for 100,000). The
timings are in ``benchmarks/bench_build.py``; here, what makes them linear: the order the
shapes are added in (and that it leaves every scene of up to 256 asperities as it was), and the
clean-up that empties a space before pymunk frees it.
"""

import gc

import numpy as np
import pytest

import asperity2d as a
from asperity2d.engine import native
from asperity2d.engine.space import INSERTION_RUN, insertion_order
from asperity2d.run import Run


@pytest.mark.parametrize("n", [1, 16, 255, 256])
def test_small_surfaces_are_added_in_x_order_as_before(n):
    # the pinned golden scenes (and every scene up to 256 asperities) keep their tree, hence their bits
    assert insertion_order(n) == list(range(n))


def test_large_surfaces_are_added_in_runs_middle_first():
    n = 5 * INSERTION_RUN + 7  # six runs, the last of 7
    order = insertion_order(n)
    assert sorted(order) == list(range(n))  # every shape once
    breaks = [k for k in range(1, n) if order[k] != order[k - 1] + 1]
    runs = [order[a:b] for a, b in zip([0] + breaks, breaks + [n])]
    # within a run, x order (a chain no deeper than the run); the runs middle first: 3, then the
    # middles of the halves (1, 5), then the rest (0, 2, 4)
    assert [r[0] // INSERTION_RUN for r in runs] == [3, 1, 5, 0, 2, 4]
    assert [len(r) for r in runs] == [256, 256, 7, 256, 256, 256]


@pytest.mark.skipif(not native.NATIVE, reason="the clean-up needs the fast path's internals")
def test_a_freed_space_is_emptied_first_and_frees_cleanly():
    run = Run(a.make_scene(lower_count=600, upper_count=4))
    space = run.engine.layout.space
    cp_space, shape = space._space, run.engine.layout.lower_shapes[10]
    finalizer = native.free_fast(space)  # a second one, to call by hand
    assert native.lib.cpSpaceContainsShape(cp_space, shape._shape)
    finalizer()
    assert not native.lib.cpSpaceContainsShape(cp_space, shape._shape)
    assert not native.lib.cpSpaceContainsBody(cp_space, run.engine.layout.slider._body)
    del run, space, shape, cp_space
    gc.collect()  # pymunk's own clean-up (and the build's finalizer) on an empty space: no crash


def test_a_large_surface_runs_deterministically():
    # 600 asperities: three insertion runs; two builds step to the same bits
    scene = a.make_scene(lower_count=600, upper_count=4)
    results = [a.simulate(scene, duration=200 * scene.shortest_period() / 50) for _ in range(2)]
    for name in ("x", "drive_force", "lower_dy"):
        assert np.array_equal(getattr(results[0], name), getattr(results[1], name))
