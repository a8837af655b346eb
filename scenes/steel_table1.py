"""Steel micro-asperities (Ooten's Table 1) and the quasi-static speed-up
======================================================================

From E. Ooten, *Precision Motion Control at Low Velocities in the Presence of
Friction* (senior thesis, Texas A&M University, 1997-98).

Ooten's Table 1 steel micro-asperities, spring-driven, with the quasi-static speed-up shown to converge.

Table 1: base 1 µm, asperity mass 2.88e-16 kg, spring stiffness 37,200 N/m
(omega = 1.14e10 rad/s), drive 5e-3 m/s. Geometry fix: Ooten's MATLAB
code puts a 1.5 µm tip on a 1 µm base with 45° flanks, which is
inconsistent (45° flanks on a 1 µm base rise 0.5 µm); we keep the 45° flank
angle and use the consistent 0.5 µm height.

Both set-ups, regular spacing, 4 upper tips, the default 3,720 N/m drive
spring: Ooten's fixed-height track first (tips 0.125 µm into the lower
surface; 24 lower asperities, as each slip runs ~9 pitches), then the free
slider under 1 mN per tip (8 lower asperities). The package default load,
2.5 mN per 1-µm tip, is 625 MPa mean pressure over Table 1's 4e-12 m²
asperity section, beyond the yield strength of ordinary steel, so elastic
asperities are not an honest model there -- and its slips land hard enough
to overlap 4 % of a base. At 1 mN per tip overlap stays ~1 %.

Real time costs ~1.8e7 steps per µm, so the drive is sped up. Whether that
changes the result is measured on a ladder of speed-ups (x4000, x2000, x1000,
x500: :func:`asperity2d.experiments.quasistatic.convergence_ladder`) for the stick force,
first breakaway, force drop, slip distance and -- set by the slip's dynamics
-- slip duration and energy dissipated per cycle; ``converged`` in the JSON
means every quantity is within ``--tolerance`` of the slowest rung at the
production speed-up ``--factor`` (default x2000, the one the micro-scale
studies use) and its changes shrink down the ladder. ``--quick``: the free
slider only, on 6 lower asperities, with the ladder x8000, x4000, x2000.

The lesson: a scene from a paper's table of material values, and how to show
that a numerical short cut (a faster drive) does not change the answer.

Run::

    python scenes/steel_table1.py [--json] [--factor A] [--real-time]
"""

# %%
# The steps are functions made of the package's public calls; ``main`` at the bottom reads the
# command line, runs them and prints. Nothing here is random (regular spacing): the verdict,
# ``converged``, is a direct check, and ``--quick`` (the free slider on 6 lower asperities, a
# three-rung ladder) gives it too.

from __future__ import annotations

import math


import asperity2d as a
from asperity2d.experiments import quasistatic as qs
from asperity2d import scripting
from asperity2d.studies.ooten import plot_position_velocity

TABLE1 = dict(base=1e-6, mass=2.88e-16, stiffness=37_200.0, flank_angle=45.0)
FACTOR = 2000.0
QUICK_LADDER = (8000.0, 4000.0, 2000.0)
SETUPS = {"fixed": {"track": "fixed", "interference": 0.125e-6, "lower_count": 24},
          "free": {"track": "free", "normal_load": 4e-3, "lower_count": 8}}


# %%
# 1. The steel scene
# ------------------
#
# :func:`asperity2d.make_scene` with Table 1's values (``TABLE1``), regular spacing and a spring
# drive sped up ``FACTOR`` times above Ooten's 5e-3 m/s (``SEED_DRIVE_VELOCITY`` of
# :mod:`asperity2d.experiments.quasistatic`).

def build_scene(quick: bool = False, *, setup: str = "free", **overrides):
    """The steel scene of ``setup`` (regular spacing, spring drive at x``FACTOR``)."""
    params = dict(TABLE1, upper_count=4, drive_velocity=qs.SEED_DRIVE_VELOCITY * FACTOR,
                  name=f"steel-table1-{setup}", **SETUPS[setup])
    if quick:
        params["lower_count"] = 6
    params.update(overrides)
    return a.make_scene(spacing="regular", drive="spring", **params)


def _line(name: str, q: dict, factors) -> str:
    unit = name.rsplit("_", 1)[1]
    scale = {"N": (1e3, "mN"), "m": (1e6, "µm"), "s": (1e9, "ns"), "J": (1e9, "nJ")}[unit]
    values = ", ".join(f"x{f:g} {v * scale[0]:.4g}" for f, v in zip(factors, q["values"]))
    errors = ", ".join(f"{100 * e:.2g}" if math.isfinite(e) else "-" for e in q["error_vs_slowest"][:-1])
    since = q["converged_from_factor"]
    since = f"converged from x{since:g}" if math.isfinite(since) else "not converged above the slowest rung"
    return f"  {name.rsplit('_', 1)[0].replace('_', ' ')} ({scale[1]}): {values}; error vs slowest {errors} %; {since}"


# %%
# 2. Is the speed-up harmless? The convergence ladder
# ---------------------------------------------------
#
# :func:`asperity2d.experiments.quasistatic.convergence_ladder` runs the scene at each speed-up
# of the ladder and compares the stick force, first breakaway, force drop, slip distance, slip
# duration and energy per cycle with the slowest rung: converged when every quantity is within
# the tolerance at the production speed-up and its changes shrink down the ladder. The
# production run is saved (``result.save``), drawn and animated (:func:`asperity2d.render`), and
# its position and velocity drawn as Ooten's figure 17 (``studies.ooten.plot_position_velocity``:
# the velocity spikes are the collisions with the lower flanks).

def main(argv=None) -> int:
    p = scripting.parser(scripting.title(__doc__))
    p.add_argument("--factor", type=float, default=FACTOR, help="production speed-up (drive / 5e-3 m/s)")
    p.add_argument("--tolerance", type=float, default=qs.TOLERANCE)
    p.add_argument("--real-time", action="store_true", help="also time the unaccelerated drive")
    args = p.parse_args(argv)
    if not (math.isfinite(args.tolerance) and 0 < args.tolerance < 1):
        p.error(f"`tolerance` must be in (0, 1), got {args.tolerance}")
    out = scripting.out_dir(args, __file__)
    factors = QUICK_LADDER if args.quick else tuple(args.factor * 2.0 ** k for k in (1, 0, -1, -2))
    production = factors[1]
    summary = {"table1": TABLE1, "setups": {}, "ladder": list(factors), "production_factor": production,
               "tolerance": args.tolerance, "outputs": []}
    lines = []
    setups = ("free",) if args.quick else ("fixed", "free")
    for setup in setups:
        scene = build_scene(args.quick, setup=setup)
        shown = {}

        def keep(factor, result, shown=shown):
            if factor == production:
                shown["result"] = result

        ladder = qs.convergence_ladder(scene, factors=factors, production=production,
                                       tolerance=args.tolerance, on_rung=keep)
        result = shown["result"]
        result.save(out / f"run_{setup}.npz")
        plot_position_velocity(result, out / f"figure17_{setup}.png",
                                  title=f"Table 1 steel, {setup} set-up, drive {result.scene.drive.velocity:g} "
                                        f"m/s (x{production:g})")
        summary["outputs"] += [f"run_{setup}.npz", f"figure17_{setup}.png"]
        if setup == setups[0] and not args.no_gif:
            a.render(result, out / f"run_{setup}.gif", frames=args.frames or (30 if args.quick else 100))
            summary["outputs"].append(f"run_{setup}.gif")
        report = ladder.to_dict()
        report.update(
            max_overlap_fraction=max(r["max_overlap_fraction"] for r in ladder.rungs),
            max_track_drift_fraction=max(r["max_track_drift_fraction"] for r in ladder.rungs),
            height_m=scene.lower.profile.height, omega_rad_per_s=max(scene.natural_frequencies().values()),
            scene={k: v for k, v in SETUPS[setup].items()} | ({"lower_count": 6} if args.quick else {}))
        summary["setups"][setup] = report
        lines.append(f"[{setup}] steel Table 1, ladder {', '.join(f'x{f:g}' for f in factors)}: converged at "
                     f"x{production:g} = {report['converged']} (tolerance {args.tolerance:.0%}); max overlap "
                     f"{report['max_overlap_fraction']:.2%} of the base")
        lines += [_line(name, q, factors) for name, q in report["quantities"].items()]
    summary["converged"] = all(s["converged"] for s in summary["setups"].values())
    if args.real_time:
        summary["real_time"] = qs.real_time_rate(build_scene(args.quick))
        rt = summary["real_time"]
        lines.append(f"real time (5e-3 m/s): {rt['steps_per_s']:.0f} steps/s, "
                     f"{rt['wall_time_per_um_s'] / 60:.1f} min per µm")
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
