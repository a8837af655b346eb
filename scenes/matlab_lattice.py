"""Ooten's MATLAB contact model as rigid bodies
============================================

From E. Ooten, *Precision Motion Control at Low Velocities in the Presence of
Friction* (senior thesis, Texas A&M University, 1997-98).

Ooten's MATLAB contact model (figures 13-17, Appendix B) as rigid bodies.

The lower surface is a lattice: each peak (mass, no rotation) hangs on a
vertical spring to ground and is joined to its neighbours and to the two walls
by horizontal springs, so pushing one peak sideways loads the next (the
seed's equations 9-18). In pymunk each horizontal spring is a
``DampedSpring`` between the two body centres with rest length equal to their
spacing (a wall link is anchored one pitch outside the end peak); for small
displacements they act along x with the stiffness matrix of
``LowerSurface.lateral_stiffness_matrix()`` (tests/test_lattice.py measures it
to 1e-11). The slider is a single peak of mass M on a horizontal track,
pulled by a spring whose far end moves at V0 (figure 13).

Ooten scripted its "contact cases" (Table 2: no contact, contact with peak
1, no contact, peak 2, ...) as if-branches; here they come out of the
rigid-body contacts, and the JSON lists the contact episodes per peak.
Steel values of Table 1 (45 deg flanks, height 0.5 um for a 1 um base), drive
sped up from Ooten's 5e-3 m/s (the factor is reported).

The lesson: a coupled lower surface (``lateral_stiffness``) and reading a
run's contact arrays.

Run::

    python scenes/matlab_lattice.py        # or: asperity2d run scenes/matlab_lattice.py
"""

# %%
# The steps are functions made of the package's public calls; ``main`` at the bottom reads the
# command line, runs them and prints. One deterministic run: ``--quick`` gives the same contact
# cases with fewer animation frames.

from __future__ import annotations

import numpy as np


import asperity2d as a
from asperity2d import scripting
from asperity2d.studies.ooten import plot_position_velocity
from asperity2d.experiments.quasistatic import SEED_DRIVE_VELOCITY

K = 37_200.0  # N/m, Ooten's Table 1 (all springs)
MASS = 2.88e-16  # kg, Ooten's Table 1 (all peaks and the slider)
DRIVE_VELOCITY = 20.0  # m/s = 4000 x Ooten's 5e-3 m/s


# %%
# 1. The lattice as a scene
# -------------------------
#
# :func:`asperity2d.make_scene` with ``lateral_stiffness`` joins the lower peaks to each other
# and to the walls by horizontal springs: Ooten's lattice. Three peaks, one slider tip on a
# fixed track, Table 1's mass and stiffness, the drive sped up.

def build_scene(quick: bool = False, **overrides):
    params = dict(lower_count=3, upper_count=1, track="fixed", interference=0.25e-6,
                  mass=MASS, stiffness=K, lateral_stiffness=K, damping_ratio=0.05,
                  slider_mass=MASS, drive_stiffness=K, drive_velocity=DRIVE_VELOCITY,
                  mu=0.2, name="matlab-lattice")
    params.update(overrides)
    return a.make_scene(**params)


# %%
# 2. Ooten's contact cases, read off the run
# ------------------------------------------
#
# ``result.lower_contact`` says, at every recorded step, which lower peak touches the slider;
# its runs are the contact episodes, and their order is Ooten's Table 2 of contact cases, which
# the MATLAB code had to script as if-branches.

def contact_episodes(result, *, merge_gap: float = 0.0) -> list[list[tuple[float, float]]]:
    """Per lower peak, the (start, end) times (s) of each contact with the slider.

    Contacts separated by less than ``merge_gap`` (s) are one episode: the
    rattle of an impact (the slider bounces on a peak that the lattice springs
    push back) is not a new contact case.
    """
    out = []
    for flags in result.lower_contact:
        edges = np.flatnonzero(np.diff(np.concatenate(([0], flags.astype(np.int8), [0]))))
        episodes = []
        for i, j in zip(edges[::2], edges[1::2]):
            start, end = float(result.t[i]), float(result.t[j - 1])
            if episodes and start - episodes[-1][1] < merge_gap:
                episodes[-1] = (episodes[-1][0], end)
            else:
                episodes.append((start, end))
        out.append(episodes)
    return out


def contact_cases(episodes, t_end: float) -> list[str]:
    """The sequence of contact cases (Ooten's Table 2): "none" or "peak i", in time order."""
    marks = sorted((s, e, i + 1) for i, eps in enumerate(episodes) for s, e in eps)
    cases, t = [], 0.0
    for start, end, peak in marks:
        if start > t and (not cases or cases[-1] != "none"):
            cases.append("none")
        cases.append(f"peak {peak}")
        t = max(t, end)
    if t < t_end:
        cases.append("none")
    return cases


# %%
# 3. Run, save, draw
# ------------------
#
# :func:`asperity2d.simulate` runs the scene (``record_every=2``), ``result.save`` writes it
# (read back with :func:`asperity2d.load`), :func:`asperity2d.render` animates it, and
# ``studies.ooten.plot_position_velocity`` draws Ooten's figure 17: position and velocity against
# time, the velocity spikes the impacts on the lattice's peaks.

def main(argv=None) -> int:
    args = scripting.parser(scripting.title(__doc__)).parse_args(argv)
    out = scripting.out_dir(args, __file__)
    scene = build_scene(args.quick)
    result = a.simulate(scene, record_every=2)
    result.save(out / "run.npz")
    plot_position_velocity(result, out / "figure17.png",
                           title=f"lattice of {scene.lower.count} peaks, drive {DRIVE_VELOCITY:g} m/s")
    if not args.no_gif:
        a.render(result, out / "run.gif", frames=args.frames or (30 if args.quick else 90))
    rattle = 5.0 * scene.slowest_period()  # bounces of an impact come ~4 periods apart
    raw = contact_episodes(result)
    episodes = contact_episodes(result, merge_gap=rattle)
    cases = contact_cases(episodes, float(result.t[-1]))
    summary = {
        **result.summary(),
        "acceleration_factor": DRIVE_VELOCITY / SEED_DRIVE_VELOCITY,
        "contact_episodes_s": episodes,
        "raw_contact_episodes": [len(eps) for eps in raw],
        "rattle_merge_gap_s": rattle,
        "contact_cases": cases,
        "peak_slider_speed_m_per_s": float(np.max(np.abs(result.v))),
        "max_lateral_peak_displacement_m": float(np.max(np.abs(result.lower_dx))),
        "lateral_stiffness_matrix_N_per_m": scene.lower.lateral_stiffness_matrix().tolist(),
    }
    lines = [f"{scene.name}: {result.status} after {scripting.si(result.t[-1], 's', 3)}",
             f"contact cases: {' -> '.join(cases)} (Ooten's Table 2: none, 1, none, 2, none, 3, none)"]
    lines += [f"peak {i + 1}: contact " + ", ".join(f"{s * 1e9:.1f}-{e * 1e9:.1f} ns" for s, e in eps)
              for i, eps in enumerate(episodes)]
    lines.append(f"largest sideways push of a peak: {summary['max_lateral_peak_displacement_m'] * 1e9:.1f} nm")
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
