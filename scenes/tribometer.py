"""Virtual tribometer on Table 1 steel asperities: the emergent friction law and its fits.

Velocity-controlled sliding (stiff drive) at a ladder of speeds over four
decades, both directions; pre-sliding reversal loops from rest; fits of
Coulomb + viscous, Stribeck, Dahl and LuGre; the fitted Stribeck law run in
the belt solver against the spring-driven asperity scene's stick-slip period.

    python scenes/tribometer.py [--quick] [--json]
"""

from __future__ import annotations

import numpy as np

import asperity2d as a
from asperity2d import fitting as ft
from asperity2d import scripting
from asperity2d import tribometer as tb


def _plots(curve, loops, fits, path):
    from asperity2d.render.plots import _figure, _save

    fig, (ax_v, ax_x) = _figure(2, height=3.0, sharex=False)
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
    return _save(fig, path, 120)


def main(argv=None) -> int:
    args = scripting.parser(__doc__.splitlines()[0]).parse_args(argv)
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
    # the asperity scene the law came from, spring-driven (3720 N/m at 10 m/s)
    driven = tb.make_tribometer_scene(drive_stiffness=3_720.0, drive_velocity=10.0, lower_count=12)
    run = a.simulate(driven)
    t_slip = [e.t_slip for e in a.stick_slip_events(run) if e.complete]
    asperity_period = float(np.mean(np.diff(t_slip))) if len(t_slip) > 2 else float("nan")
    belt = ft.belt_period(fits["stribeck"].law, mass=driven.slider.mass, stiffness=3_720.0,
                          velocity=10.0, normal_load=driven.slider.normal_load)
    _plots(curve, loops, fits, out / "friction_law.png")
    low = int(np.searchsorted(curve.velocity, 0.0))  # first +v point; low - 1 is the first -v
    summary = {"curve": curve.as_dict(), "static_coefficient": mu_s,
               "breakaway_displacement_m": loops.breakaway_displacement(),
               "fits": {k: f.as_dict() for k, f in fits.items()}, "energy": energy,
               "asperity_period_s": asperity_period, "belt": belt,
               "period_ratio": belt["period_s"] / asperity_period,
               "force_limit_at_zero_N": [float(curve.force[low - 1]), float(curve.force[low])]}
    lines = [f"steady friction at +-{abs(curve.velocity[low]):g} m/s: {curve.force[low - 1]:.3g} / "
             f"{curve.force[low]:.3g} N; breakaway {mu_s:.3g} L over {loops.breakaway_displacement():.2g} m",
             *(f"{k}: relative RMS {f.relative_rms:.2%}" for k, f in fits.items()),
             f"energy balance error {energy['balance_error']:.2%}",
             f"stick-slip period: asperities {asperity_period:.3g} s, belt (Stribeck) {belt['period_s']:.3g} s"]
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    raise SystemExit(main())
