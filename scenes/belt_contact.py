"""Contacts that open: separation, mode-coupling flutter and squeal
================================================================

From the thesis *Vibration Analysis of Multi Degree of Freedom Self-excited
Systems* (no author named in the copy used here), called the multi-DOF belt
thesis below.

Contacts that open: separation, mode-coupling flutter and squeal on the moving belt.

Run::

    python scenes/belt_contact.py [--quick] [-o DIR] [--json] [--workers auto|N]

The multi-DOF belt thesis lets its Coulomb contact be "separated, sliding or
sticking" and reviews the mechanisms beyond stick-slip; this script gives the
chains a normal degree of freedom (``simulate_chain(..., normal=NormalContact(...))``)
and measures:

1. Hoffmann's minimal model (one mass, two inclined springs, contact stiffness,
   preload; :class:`asperity2d.belt.MinimalModel`): its flutter onset mu_crit from the
   characteristic polynomial, and a regime map over (mu, belt speed) of exact runs
   from kicked steady sliding -- steady sliding, flutter, stick-slip, separation --
   against the closed-form onset and the speed V* that decides whether a growing
   flutter meets stick or separation first (``contact_map.png``);
2. its squeal: the separation limit cycle, its Floquet multipliers (with the
   Liouville check det M = exp(-2 eta T)), a WAV in real time of the pad's normal
   acceleration (what radiates) beside the same pad's stick-slip at a slow belt,
   with spectrograms;
3. the thesis' 3-DOF chain (Table 2) with normal compliance k_c and one inclined
   spring per mass: over (k_c, mu, belt speed), does the contact open, and is its
   steady sliding unstable there (``thesis_opening.png``); without the inclined
   spring the normal force stays m·g on every preset;
4. one table of the three states (separated / sliding / sticking) for a
   free-slider asperity run (:func:`asperity2d.studies.contact.asperity_states`) and the belt runs.

Writes ``summary.json`` with claim records (:func:`asperity2d.experiments.verdicts.claim`).
"""

# %%
# The lesson is made of the package's public calls: the chains and the minimal model of
# ``asperity2d.belt``, limit cycles, Floquet multipliers and spectra of ``asperity2d.dynamics``,
# the maps, tables, pictures and sounds of ``asperity2d.studies.contact``, and claim records of
# ``asperity2d.experiments.verdicts``.

import math

import numpy as np

import asperity2d as a
from asperity2d import scripting
from asperity2d.belt import MinimalModel, NormalContact, classify_contact, presets, simulate_chain, steady_sliding
from asperity2d.dynamics import chain_cycle, floquet, spectrum
from asperity2d.experiments.verdicts import claim
from asperity2d.studies import contact as C

#: the pad: 1.5 % damping ratio at the coalesced frequency (eta / 2 omega_c)
MODEL = MinimalModel(eta=300.0)
SQUEAL = dict(mu=0.5, v_belt=5.0)  # above the onset, separating
SLOW = dict(mu=0.5, v_belt=0.01)  # the same pad on a slow belt: stick-slip
#: one spring per mass of the thesis chain, as stiff as the chain's, inclined at 135 degrees
INCLINED = ((10.0, 135.0),)


# %%
# 1. The minimal model's regime map
# ---------------------------------
#
# :class:`asperity2d.belt.MinimalModel` gives the flutter onset mu_crit in closed form (the
# characteristic polynomial); :func:`asperity2d.studies.contact.minimal_map` runs the model from
# kicked steady sliding at every (mu, belt speed) and classes each run
# (:func:`asperity2d.belt.classify_contact`). Two claims: steady sliding is stable exactly below
# the closed-form onset, and a growing flutter meets stick first below the speed V*(mu) and
# separation first above it.

def regime_map_step(mm, quick, workers, progress, out, claims, plots):
    """The regime map, its plot and its two claims; the map's record and a line."""
    mus = np.round(np.arange(0.30, 0.701, 0.1 if quick else 0.02), 4)
    speeds = np.logspace(-2, 1, 4) if quick else np.logspace(-2, 1.5, 15)
    cmap = C.minimal_map(mm, mus, speeds, t_end=0.03 if quick else 0.06, workers=workers, progress=progress)
    record = cmap.to_dict()
    plots.append(C.plot_map(cmap, out / "contact_map.png").name)
    lo, hi = cmap.onset()
    claims.append(claim("steady sliding of the minimal model is stable below the closed-form flutter onset "
                        "mu_crit(eta) and not above it", lo < mm.mu_crit_damped() < hi,
                        {"grid_bracket": [lo, hi], "mu_crit_damped": mm.mu_crit_damped()},
                        "every run of the largest all-steady mu row and none of the smallest all-unsteady row "
                        "is steady sliding; holds if mu_crit(eta) lies between them"))
    agree, tested = _first_limit(cmap)
    claims.append(claim("a growing flutter meets stick first below V*(mu) and separation first above it",
                        tested > 0 and agree == tested, {"agree": agree, "tested": tested},
                        "first stick or contact opening of every unstable grid point with V outside "
                        "[V*/2, 2 V*]; holds if all agree"))
    fr = record["fractions"]
    line = ("regime map: " + ", ".join(f"{k} {100 * v:.0f} %" for k, v in fr.items() if v)
            + f"; onset between mu = {lo:g} and {hi:g} (closed form {mm.mu_crit_damped():.4f})")
    return record, line


def _first_limit(cmap):
    """(agreeing, tested): unstable grid points, away from V*(mu) by more than 2x, whose first event (stick or
    opening) is the one V* predicts."""
    agree = tested = 0
    for i, mu in enumerate(cmap.mu):
        vstar = cmap.model.first_limit_speed(mu)
        if not np.isfinite(vstar):
            continue
        for j, v in enumerate(cmap.v_belt):
            first = cmap.values["first"][i, j]
            if not np.isfinite(first) or C.FIRST[int(first)] == "none" or 0.5 * vstar <= v <= 2 * vstar:
                continue
            tested += 1
            agree += C.FIRST[int(first)] == ("stick" if v < vstar else "open")
    return agree, tested


# %%
# 2. The squeal
# -------------
#
# Above the onset on a fast belt the flutter grows until the contact opens once a period: a
# separation limit cycle (:func:`asperity2d.dynamics.chain_cycle`). Its Floquet multipliers
# (:func:`asperity2d.dynamics.floquet`) must multiply to exp(-2 eta T) (Liouville's formula: a
# compliant contact adds no saltation). Its sound is the pad's normal acceleration in real time
# (:func:`asperity2d.studies.contact.normal_sound`), beside the same pad's stick-slip on a slow
# belt; the pitch should be the coalesced modes' frequency.

def squeal_step(mm, quick, out, claims, plots):
    """The separation cycle, its Floquet claim, both sounds, their spectra and the pitch claim."""
    kw = mm.chain(**SQUEAL, t_end=0.12 if quick else 0.3, kick=1e-2, n_samples=1001 if quick else 3001)
    r = simulate_chain(**kw)
    cyc = chain_cycle(r)
    cycle = {"periodic": cyc.periodic, "period_s": cyc.period, "frequency_hz": 1 / cyc.period if cyc.periodic else None,
             "section": cyc.section, "energy_balance_error": r.energy_balance_error(),
             "states_last_half": C.chain_states(r, window=0.5)}
    if cyc.periodic:
        f = floquet(kw)
        liouville = math.exp(-2 * mm.eta * f.period)
        cycle["floquet"] = {**f.to_dict(), "product": float(np.prod(f.multipliers).real), "liouville": liouville}
        claims.append(claim("the squeal is a stable limit cycle that opens the contact once a period; its Floquet "
                            "multipliers multiply to exp(-2 eta T) (Liouville: no saltation at a compliant contact)",
                            f.stable and abs(np.prod(f.multipliers).real / liouville - 1) < 1e-6,
                            {"moduli": [abs(m) for m in f.multipliers], "product": float(np.prod(f.multipliers).real),
                             "liouville": liouville, "openings_per_period": cycle["states_last_half"]["hops"]
                             * cyc.period / (0.5 * r.t[-1])},
                            "every non-trivial |multiplier| < 1 and the product within 1e-6 of exp(-2 eta T)"))
    dense = simulate_chain(**{**kw, "n_samples": None, "t_eval": np.linspace(kw["t_end"] - 4e-3, kw["t_end"], 2001)})
    plots.append(C.plot_cycle(dense, out / "separation_cycle.png",
                              title=f"minimal model, mu = {SQUEAL['mu']}, V = {SQUEAL['v_belt']} m/s: "
                                    "the squeal cycle (last 4 ms)").name)
    sounds, spectra = {}, {}
    for name, case in (("squeal", SQUEAL), ("stick_slip", SLOW)):
        t_end = 0.1 if quick else 1.0
        run = simulate_chain(**mm.chain(**case, t_end=t_end, kick=1e-2, n_samples=int(88_200 * t_end) + 1,
                                        include_events=False))
        t, acc = run.t, C.normal_acceleration(run)
        steady = t >= 0.5 * t_end
        sp = spectrum(t[steady], acc[steady])
        spectra[name] = {"dominant_hz": sp.dominant, "thd": sp.thd,
                         "harmonics_hz": [h.frequency for h in sp.harmonics[:5]],
                         "states": C.chain_states(run, window=0.5), "regime": classify_contact(run)}
        sounds[name] = C.normal_sound(run, out / f"minimal_{name}.wav", time_scale=1.0)
        plots.append(sounds[name]["spectrogram"].split("/")[-1])
    f_c = mm.coalescence_frequency / (2 * math.pi)
    pitch = cycle["frequency_hz"] or float("nan")
    claims.append(claim("the squeal's pitch is the coalesced modes' frequency", abs(pitch / f_c - 1) < 0.10,
                        {"fundamental_hz": pitch, "coalescence_hz": f_c,
                         "dominant_hz_normal_acceleration": spectra["squeal"]["dominant_hz"]},
                        "fundamental 1/T of the separation limit cycle within 10 % of omega_c / 2 pi (the pitch is "
                        "the period: in the tangential acceleration the second harmonic is as strong as the "
                        "fundamental, so its largest peak is no measure of it)"))
    line = (f"squeal: {spectra['squeal']['dominant_hz']:.0f} Hz (THD {spectra['squeal']['thd']:.2f}), "
            f"stick-slip at {SLOW['v_belt']} m/s: {spectra['stick_slip']['dominant_hz']:.0f} Hz "
            f"(THD {spectra['stick_slip']['thd']:.2f}); modes coalesce at {f_c:.0f} Hz")
    return cycle, sounds, spectra, line


# %%
# 3. The thesis' chain with a normal compliance
# ---------------------------------------------
#
# The Table 2 chain given a contact stiffness k_c and one inclined spring per mass
# (:class:`asperity2d.belt.NormalContact`): over (k_c, mu, belt speed), does the contact open
# (:func:`asperity2d.studies.contact.thesis_opening`), and is steady sliding unstable there
# (:func:`asperity2d.belt.steady_sliding`'s growth rate)? Without the inclined spring the normal
# force must stay m g on every preset.

def thesis_step(quick, progress, out, claims, plots):
    """The opening rows, their plot and claim, the uncoupled check and its claim; and a line."""
    stiff = (10.0, 30.0, 100.0) if quick else tuple(np.round(np.logspace(0.5, 3, 11), 3))
    rows = C.thesis_opening(stiff, (0.4,) if quick else (0.2, 0.4), (0.1,) if quick else (0.1, 0.7),
                            inclined=INCLINED, t_end=60.0, progress=progress)
    curves = {}
    for mu in sorted({r["mu"] for r in rows}):  # the linearisation is cheap: draw it on a fine grid
        ks = np.logspace(0.3, 3.2, 120)
        base = presets.preset("table2-3dof", mu_s=mu, mu_k=mu)
        curves[mu] = (ks, [steady_sliding(**base, normal=NormalContact(contact_stiffness=k, inclined=INCLINED))
                           .growth_rate for k in ks])
    plots.append(C.plot_opening(rows, out / "thesis_opening.png", curves=curves).name)
    opened = [r for r in rows if r["openings"]]
    claims.append(claim("the multi-DOF belt thesis' 3-DOF chain with normal compliance loses contact only where its steady sliding is "
                        "unstable", all(r["growth_rate"] > 0 for r in opened),
                        {"opened": len(opened), "runs": len(rows),
                         "growth_rates_where_opened": [r["growth_rate"] for r in opened],
                         "contact_stiffness_where_opened": sorted({r["contact_stiffness"] for r in opened})},
                        "every run whose contact opens has a growing mode (max Re lambda > 0) in steady sliding"))
    flat = C.normal_force_without_coupling(stiff=not quick)  # quick: the rigid contact (tests cover the stiff one)
    claims.append(claim("without an inclined spring a normal contact never opens on the multi-DOF belt thesis' presets (N = m g)",
                        flat["openings"] == 0 and flat["max_relative_departure"] <= 1e-12, flat,
                        "no opening and |N - m g| <= 1e-12 m g on every preset (rigid and stiff compliant contacts)"))
    stiffnesses = ", ".join(f"{k:g}" for k in sorted({r["contact_stiffness"] for r in opened}))
    line = (f"the multi-DOF belt thesis' chain + normal compliance: contact opened in {len(opened)} of "
            f"{len(rows)} runs" + (f", at k_c = {stiffnesses} N/m" if opened else "")
            + f"; without coupling N stays m g to {flat['max_relative_departure']:.1e} of it")
    return rows, flat, line


# %%
# 4. The three states, both models
# --------------------------------
#
# One table of the time spent separated, sliding and sticking: an asperity run of a free slider
# (:func:`asperity2d.studies.contact.asperity_states`) beside the belt runs
# (:func:`asperity2d.studies.contact.chain_states`).

def states_step(quick, rows, spectra):
    """The table's rows, and the asperity run's states."""
    scene = a.make_scene(track="free", **({"lower_count": 8, "upper_count": 2} if quick else {}))
    asperity = C.asperity_states(a.simulate(scene))
    thesis = next((r for r in rows if r["openings"]), rows[0])
    chain = simulate_chain(**presets.preset("table2-3dof", mu_s=thesis["mu"], mu_k=thesis["mu"],
                                            v_belt=thesis["v_belt"], t_end=60.0, n_samples=3001,
                                            normal=NormalContact(contact_stiffness=thesis["contact_stiffness"],
                                                                 inclined=INCLINED)))
    table = [{"model": f"asperity, free slider ({scene.lower.count}/{scene.slider.count} asperities)",
              **asperity.fractions, "hops": asperity.hops, "hops_per_pass": asperity.hops_per_pass,
              "contacts_mean": asperity.touching_mean, "contacts_unit": "lower tips touching"},
             _belt_row(f"minimal model, V = {SQUEAL['v_belt']} m/s (squeal)", spectra["squeal"]["states"]),
             _belt_row(f"minimal model, V = {SLOW['v_belt']} m/s (stick-slip)", spectra["stick_slip"]["states"]),
             _belt_row(f"thesis 3-DOF, k_c = {thesis['contact_stiffness']:g} N/m, mu = {thesis['mu']:g}",
                       C.chain_states(chain))]
    return table, asperity


def _belt_row(name, states):
    return {"model": name, "separated": states["separated"], "sliding": states["sliding"],
            "sticking": states["sticking"], "hops": states["hops"], "hops_per_second": states["hops_per_second"],
            "contacts_mean": states["contacts_mean"], "contacts_unit": "masses in contact"}


# %%
# The command line
# ----------------
#
# ``main`` reads the options (``--quick``: coarse grids, short runs), runs the four steps, writes
# ``summary.json`` and prints what it found and each claim's verdict.

def main(argv=None) -> int:
    p = scripting.parser(scripting.title(__doc__))
    scripting.add_workers(p)
    args = p.parse_args(argv)
    out = scripting.out_dir(args, __file__)
    quick, progress = args.quick, not args.json
    mm = MODEL
    summary = {"model": {"mu_crit": mm.mu_crit, "mu_crit_damped": mm.mu_crit_damped(),
                         "coalescence_hz": mm.coalescence_frequency / (2 * math.pi),
                         "structure_N_per_m": list(mm.structure), "contact_stiffness": mm.contact_stiffness,
                         "preload_N": mm.preload, "eta_per_s": mm.eta, "mass_kg": mm.mass}}
    claims, plots = [], []
    lines = [f"minimal model: mu_crit = {mm.mu_crit:.6f} (undamped), {mm.mu_crit_damped():.6f} "
             f"(eta = {mm.eta:g} 1/s); modes coalesce at {mm.coalescence_frequency / 2 / math.pi:.1f} Hz"]
    summary["regime_map"], line = regime_map_step(mm, quick, args.workers, progress, out, claims, plots)
    lines.append(line)
    summary["separation_cycle"], sounds, spectra, line = squeal_step(mm, quick, out, claims, plots)
    summary["sounds"], summary["spectra"] = sounds, spectra
    lines.append(line)
    rows, flat, line = thesis_step(quick, progress, out, claims, plots)
    summary["thesis_opening"], summary["without_coupling"] = rows, flat
    lines.append(line)
    table, asperity = states_step(quick, rows, spectra)
    summary["states_table"] = table
    summary["asperity_contact_states"] = asperity.to_dict()
    lines.append("three states (fractions of time; belt: last half, all masses):")
    for row in table:
        lines.append(f"  {row['model']:52s} separated {row['separated']:.3f}  sliding {row['sliding']:.3f}  "
                     f"sticking {row['sticking']:.3f}  hops {row['hops']}")
    summary["claims"] = claims
    summary["plots"] = plots
    summary["outputs"] = plots + [f"minimal_{n}.wav" for n in sounds]
    lines += [f"claim: {c['claim']}: {c['verdict']}" for c in claims]
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
