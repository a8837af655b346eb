"""A virtual tribometer: the friction law that emerges from asperities
===================================================================

From E. Ooten, *Precision Motion Control at Low Velocities in the Presence of
Friction* (senior thesis, Texas A&M University, 1997-98).

Virtual tribometer on Table 1 steel asperities: the emergent friction law and its fits.

Velocity-controlled sliding (stiff drive) at a ladder of speeds over four
decades, both directions; pre-sliding reversal loops from rest; fits of
Coulomb + viscous, Stribeck, Dahl and LuGre. Then the same asperities on a
soft drive spring (stick-slip): a static/kinetic law fitted to the cycles at
1000 N/m is run in the belt solver and predicts the stick-slip period at
held-out drive stiffnesses and speeds; the steady-sliding Stribeck law is
run too, to show why it cannot.

The lesson: measuring a friction law on simulated asperities, fitting the
classic laws to it, and checking the fitted law where it was not fitted.

Run::

    python scenes/tribometer.py [--quick] [--json]
"""

# %%
# The steps are functions made of the package's public calls; ``main`` at the bottom reads the
# command line, runs them and prints. ``--quick`` runs three speeds (one decade each) and two
# stick-slip runs: the calibration one and one held-out stiffness.

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

import asperity2d as a
from asperity2d import friction as ft
from asperity2d import scripting
from asperity2d.belt import belt_period
from asperity2d.experiments import tribometer as tb


# %%
# 1. The measured law and its fit
# -------------------------------
#
# ``tb.steady_curve`` slides the tribometer's asperities at a ladder of speeds (a stiff drive:
# velocity control) and returns the mean friction force at each; ``tb.reversal_loops`` the
# pre-sliding loops from rest. :func:`asperity2d.friction.steady_mask` marks the points that
# stayed in contact; the Stribeck fit (:func:`asperity2d.friction.fit_stribeck`) is drawn over
# them with matplotlib.

def _plots(curve, loops, fits, path):
    fig = Figure(figsize=(7.0, 6.0), layout="constrained")
    ax_v, ax_x = fig.subplots(2, 1)
    ok = ft.steady_mask(curve)
    ax_v.errorbar(curve.velocity[ok], curve.force[ok] * 1e3, yerr=curve.spread[ok] * 1e3, fmt="o", ms=3)
    ax_v.plot(curve.velocity[~ok], curve.force[~ok] * 1e3, "x", color="gray", label="lift-off")
    v = np.concatenate([-np.logspace(-2, 3, 200)[::-1], np.logspace(-2, 3, 200)])
    ax_v.plot(v, fits["stribeck"].law.curve(v) * curve.normal_load * 1e3, lw=0.8, label="Stribeck fit")
    ax_v.set_xscale("symlog", linthresh=float(np.min(np.abs(curve.velocity))))
    ax_v.set_xlabel("sliding velocity (m/s)")
    ax_v.set_ylabel("friction (mN)")
    ax_v.legend(fontsize=8)
    ax_x.plot(loops.displacement * 1e9, loops.force * 1e3, lw=0.8)
    ax_x.set_xlabel("slider displacement from rest (nm)")
    ax_x.set_ylabel("friction (mN)")
    fig.savefig(path, dpi=120)


#: (drive stiffness N/m, drive speed m/s, lower asperities): the calibration
#: run first, then held-out ones (enough asperities for >= 2 whole cycles).
STICK_SLIP_RUNS = ((1000.0, 10.0, 16), (500.0, 10.0, 24), (2000.0, 10.0, 12), (3720.0, 10.0, 12),
                   (1000.0, 3.0, 16), (1000.0, 30.0, 16))
QUICK_STICK_SLIP_RUNS = ((1000.0, 10.0, 16), (2000.0, 10.0, 12))


# %%
# 2. From asperities to a friction law, and back
# ----------------------------------------------
#
# On a soft drive spring the same asperities stick and slip.
# :func:`asperity2d.friction.fit_stick_slip` fits a static/kinetic law to the cycles of the first
# run (``STICK_SLIP_RUNS``); :func:`asperity2d.belt.belt_period` runs that law in the belt
# solver on the same mass and spring, and predicts the stick-slip period of the held-out drive
# stiffnesses and speeds. The steady-sliding Stribeck law, run the same way, shows why a law
# measured in steady sliding cannot.

def _stick_slip_periods(stribeck, *, quick: bool) -> tuple:
    """(calibrated law, report): stick-slip periods of the asperity scene vs the belt solver."""
    runs = []
    law = calibration = base = None
    for stiffness, velocity, count in (QUICK_STICK_SLIP_RUNS if quick else STICK_SLIP_RUNS):
        scene = tb.make_tribometer_scene(drive_stiffness=stiffness, drive_velocity=velocity, lower_count=count)
        result = a.simulate(scene)
        if law is None:
            fit = ft.fit_stick_slip(result)
            law, base = fit.law, scene
            calibration = {**fit.to_dict(), "stiffness_N_per_m": stiffness, "velocity_m_per_s": velocity}
        cycles = ft.stick_slip_cycles(result)
        common = dict(mass=scene.slider.mass, stiffness=stiffness, velocity=velocity,
                      normal_load=scene.slider.normal_load)
        belt = belt_period(law, **common)["period_s"]
        try:  # the contrast only: a steady-sliding law the belt solver cannot run is reported, not fatal
            steady = belt_period(stribeck, **common)["period_s"]
        except a.SimulationError:
            steady = float("nan")
        pitch = scene.lower.spacing.mean_pitch
        runs.append({"stiffness_N_per_m": stiffness, "velocity_m_per_s": velocity,
                     "held_out": bool(runs), "cycles": len(cycles["periods_s"]),
                     "asperity_period_s": cycles["period_s"], "belt_period_s": belt,
                     "asperity_pitches": cycles["period_s"] * velocity / pitch,
                     "belt_pitches": belt * velocity / pitch, "ratio": belt / cycles["period_s"],
                     "stribeck_ratio": steady / cycles["period_s"],
                     "net_drop_over_load": float(np.mean(cycles["breakaway_N"] - cycles["restick_N"])
                                                 / cycles["normal_load_N"])})
    velocity = STICK_SLIP_RUNS[0][1]
    grid = np.geomspace(400.0, 5000.0, 24)
    pitch = base.lower.spacing.mean_pitch
    line = [belt_period(law, mass=base.slider.mass, stiffness=float(k), velocity=velocity,
                           normal_load=base.slider.normal_load)["period_s"] * velocity / pitch for k in grid]
    return law, {"calibration": calibration, "runs": runs,
                 "belt_curve": {"velocity_m_per_s": velocity, "stiffness_N_per_m": grid.tolist(), "pitches": line}}


# %%
# 3. Periods: asperities against the belt solver
# ----------------------------------------------
#
# The stick-slip period in pitches against the drive stiffness, drawn with matplotlib: the
# asperity runs as points, the calibrated law in the belt solver as a line.

def _period_plot(periods, path):
    """Stick-slip period in pitches against drive stiffness: asperities vs belt solver."""
    fig = Figure(figsize=(7.0, 3.0), layout="constrained")
    ax = fig.subplots()
    line = periods["belt_curve"]
    ax.plot(line["stiffness_N_per_m"], line["pitches"], "-", lw=0.8, color="gray",
            label=f"belt solver, calibrated law, {line['velocity_m_per_s']:g} m/s")
    markers = iter([dict(marker="o", ms=9, mfc="none"), dict(marker="o", ms=5), dict(marker="s", ms=5)] * 3)
    for velocity in sorted({r["velocity_m_per_s"] for r in periods["runs"]}):
        rows = [r for r in periods["runs"] if r["velocity_m_per_s"] == velocity]
        ax.plot([r["stiffness_N_per_m"] for r in rows], [r["asperity_pitches"] for r in rows], ls="none",
                label=f"asperities, {velocity:g} m/s", **next(markers))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("drive spring stiffness (N/m)")
    ax.set_ylabel("stick-slip period x V / pitch")
    ax.legend(fontsize=7)
    fig.savefig(path, dpi=120)


# %%
# 4. The law in a multi-DOF belt chain
# ------------------------------------
#
# The multi-DOF belt thesis' 3-DOF chain (``asperity2d.belt.presets``) with the asperity-measured
# law: written as a chain file (``asperity2d belt <file>`` runs it again), read back, its
# ``[friction]`` table made a law again by :func:`asperity2d.friction.law_from_dict`, solved by
# :func:`asperity2d.belt.simulate_chain` and drawn by :func:`asperity2d.render`.

def _macroscopic_chain(law, out) -> dict:
    """The multi-DOF belt thesis' 3-DOF chain (Table 2, from rest) with the asperity-measured law.

    Written as a chain file (``asperity2d belt <file>`` runs it again), read
    back through the same loader, solved exactly and plotted.
    """
    import json
    import tomllib

    from asperity2d.belt import presets, simulate_chain
    from asperity2d.friction import law_from_dict

    chain = {k: v for k, v in presets.preset("table2-3dof-rest", t_end=120.0).items() if k not in ("mu_s", "mu_k")}
    lines = ["# the multi-DOF belt thesis Table 2 chain (from rest) with friction measured on the asperities"]
    lines += [f"{key} = {json.dumps(value)}" for key, value in chain.items()]
    lines += ["", "[friction]", *(f"{key} = {json.dumps(value)}" for key, value in law.to_dict().items())]
    path = out / "asperity_law_chain.toml"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    chain_file = tomllib.loads(path.read_text(encoding="utf-8"))  # what ``asperity2d belt`` reads
    result = simulate_chain(**{**chain_file, "friction": law_from_dict(chain_file["friction"])})
    a.render(result, out / "asperity_law_chain.png", title="3-DOF belt chain, friction from the asperities")
    ends = [b for _, b in result.stick_intervals[0] if b < chain["t_end"]]
    return {"chain_file": str(path), "stick_intervals_mass1": len(result.stick_intervals[0]),
            "period_mass1_s": float(np.mean(np.diff(ends[1:]))) if len(ends) > 2 else float("nan")}


def _ratio(value: float) -> str:
    return "gives no stick-slip" if not np.isfinite(value) else f"{value:.2f}"


# %%
# 5. The whole tribometer
# -----------------------
#
# The scene (``tb.make_tribometer_scene``: Table 1 steel asperities, two tips at 1 mN), the
# steady curve and the loops, the four fits (Coulomb + viscous, Stribeck, Dahl, LuGre), the
# energy balance of one window (``tb.energy_window``), then steps 2-4. ``main`` reads the
# options with :mod:`asperity2d.scripting`.

def main(argv=None) -> int:
    args = scripting.parser(scripting.title(__doc__)).parse_args(argv)
    out = scripting.out_dir(args, __file__)
    scene = tb.make_tribometer_scene()
    velocities = (3.0, 30.0, 300.0) if args.quick else (0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1000.0)
    protocol = tb.Protocol(velocities=velocities, pitches=1 if not args.quick else 2,
                           transient_pitches=0.5)
    curve = tb.steady_curve(scene, protocol)
    loops = tb.reversal_loops(scene, protocol)
    mu_s = float(np.abs(loops.force).max() / loops.normal_load)
    fits = {"coulomb_viscous": ft.fit_coulomb_viscous(curve), "stribeck": ft.fit_stribeck(curve, mu_s=mu_s),
            "dahl": ft.fit_dahl(loops)}
    fits["lugre"] = ft.fit_lugre(loops, fits["stribeck"].law)
    energy = tb.energy_window(scene, velocity=30.0)
    law, periods = _stick_slip_periods(fits["stribeck"].law, quick=args.quick)
    cal = periods["calibration"]
    chain = _macroscopic_chain(law, out)
    _plots(curve, loops, fits, out / "friction_law.png")
    _period_plot(periods, out / "stick_slip_period.png")
    low = int(np.searchsorted(curve.velocity, 0.0))  # first +v point; low - 1 is the first -v
    summary = {"curve": curve.to_dict(), "static_coefficient": mu_s,
               "breakaway_displacement_m": loops.breakaway_displacement(),
               "fits": {k: f.to_dict() for k, f in fits.items()}, "energy": energy,
               "stick_slip": periods, "macroscopic_chain": chain,
               "force_limit_at_zero_N": [float(curve.force[low - 1]), float(curve.force[low])]}
    lines = [f"steady friction at +-{abs(curve.velocity[low]):g} m/s: {scripting.si(curve.force[low - 1], 'N', 3)} / "
             f"{scripting.si(curve.force[low], 'N', 3)}; breakaway {mu_s:.3g} L over {scripting.si(loops.breakaway_displacement(), 'm', 2)}",
             *(f"{k}: relative RMS {f.relative_rms:.2%} on {f.points} points" for k, f in fits.items()),
             f"energy balance error {energy['balance_error']:.2%}",
             f"stick-slip law from the cycles at {cal['stiffness_N_per_m']:g} N/m: mu_s {cal['mu_s']:.3f}, "
             f"mu_k {cal['mu_k']:.3f} (steady sliding: {fits['stribeck'].law.mu_k:.3f})",
             *(f"  k {r['stiffness_N_per_m']:g} N/m, V {r['velocity_m_per_s']:g} m/s: asperities "
               f"{r['asperity_pitches']:.3f} pitches, belt {r['belt_pitches']:.3f} "
               f"(ratio {r['ratio']:.3f}; steady Stribeck law {_ratio(r['stribeck_ratio'])})"
               for r in periods["runs"]),
             f"3-DOF belt chain with that law: mass 1 stick-slip period {chain['period_mass1_s']:.3g} s "
             f"(the chain file {Path(chain['chain_file']).name} runs again with "
             f"`asperity2d belt`)"]
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
