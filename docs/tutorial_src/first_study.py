"""
Your first study
================

A study with asperity2d, start to end: build a surface, run it, choose the force that answers
your question (and see why the others do not), compare two kinds of surface over seeds and
read the verdict honestly, plot, save, load the run again, and hand it to MATLAB.

The question is E. Ooten's (*Precision Motion Control at Low Velocities in the Presence of
Friction*, senior thesis, Texas A&M University, 1997-98): **does random asperity spacing lower
the force that breaks a slider loose?** The scenes here are small (8 lower and 3 upper
asperities instead of Ooten's 16 and 4) so that the whole page runs in under a minute; every
block runs in order, here or in the notebook you can download at the bottom of the page.
"""

# %%
# 1. A surface
# ------------
#
# :func:`asperity2d.make_scene` builds a scene from named physical parameters, all SI. The
# defaults are Ooten's Working Model set-up: 45-degree steel asperities (1 um base) on
# spring-damper tracks, and a slider carrying its own asperities on a track at a fixed height,
# pulled by a spring whose far end moves at 20 m/s. ``spacing="random"`` draws random gaps
# between the asperities, a new surface for each ``seed``.

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import asperity2d as a

out = Path("first_study")  # every file this tutorial writes goes here
out.mkdir(exist_ok=True)

size = {"lower_count": 8, "upper_count": 3}
regular = a.make_scene(**size)
rough = a.make_scene(**size, spacing="random", seed=2)
print(regular.name)
print("  tips (um):", np.round(regular.lower.tips() * 1e6, 2))
print(rough.name)
print("  tips (um):", np.round(rough.lower.tips() * 1e6, 2))

# %%
# A measured or synthetic profile works too: its summits become the asperities (here a
# self-affine profile standing in for ``asperity2d.surface.read_profile("my_trace.txt")``).

from asperity2d.surface import self_affine_profile

profile = self_affine_profile(n=512, length=20e-6, rms_height=0.2e-6,
                              hurst=0.8, seed=1)
scene = a.make_scene(lower_surface=profile, upper_count=3)
print(scene.lower.count, "asperities from the profile")

# %%
# 2. A run
# --------
#
# :func:`asperity2d.simulate` runs the scene until the slider has passed the surface and
# returns a :class:`~asperity2d.Result`: time series in SI and why the run ended.
# :func:`~asperity2d.stick_slip_events` cuts the motion into stick-slip cycles.

result = a.simulate(rough)
events = a.stick_slip_events(result)
print(result)
for e in events:
    print(f"  stuck {e.stick_duration * 1e9:5.1f} ns,"
          f" broke loose at {e.force_peak * 1e3:5.2f} mN,"
          f" slipped {e.slip_distance * 1e6:4.2f} um")

# %%
# 3. Which force? Choose the measure before you compare
# -----------------------------------------------------
#
# "The force that breaks the slider loose" is four different numbers:
#
# * the **first breakaway** (:func:`~asperity2d.breakaway_force`), the drive force at the first
#   slip. On the fixed track only the slider's front tip has met the surface then, so it is
#   the same for every spacing: it cannot answer the question.
# * the **peak stick force** (:func:`~asperity2d.peak_stick_force`), the largest force at a
#   slip over the pass: the slider at its worst position. Which positions a pass sticks at is
#   chaotic, so it scatters from seed to seed.
# * the **mean stick force** (:func:`~asperity2d.mean_stick_force`): the typical force at a
#   slip, steadier than the peak.
# * the **critical force** (:func:`~asperity2d.critical_force`): the smallest constant force
#   that carries the slider, at rest on the surface, all the way across. No spring, no
#   chaos: one number per surface, found by bisection over constant-force runs.

mN = 1e3  # newtons to millinewtons
first_regular = a.breakaway_force(a.simulate(regular))
print(f"first breakaway  {a.breakaway_force(result) * mN:6.2f} mN"
      f"  (regular: {first_regular * mN:.2f} mN)")
print(f"peak stick force {a.peak_stick_force(result) * mN:6.2f} mN")
print(f"mean stick force {a.mean_stick_force(result) * mN:6.2f} mN")
print(f"critical force   {a.critical_force(rough) * mN:6.2f} mN")

# %%
# For a question about the surface, the critical force is the measure to choose: it is a
# property of the surface alone and the cheapest to measure well. The spring-driven measures
# answer a different question (what a drive *feels*) and need more seeds for the same verdict.

# %%
# 4. Compare over seeds, and read the verdict honestly
# ----------------------------------------------------
#
# :func:`asperity2d.compare` measures every variant on every seed. The regular surface is the
# same for every seed; the random one changes.

seeds = range(7)
variants = {"regular": {"spacing": "regular"},
            "random": {"spacing": "random"}}
comparison = a.compare("critical", variants, seeds, base=size,
                       progress=False, workers=1)
reference = comparison.values["regular"][0]
forces = comparison.values["random"]  # one per seed
print(f"regular: {reference * mN:.2f} mN")
print("random: ", ", ".join(f"{f * mN:.2f}" for f in forces), "mN")

# %%
# The test is one-sided Wilcoxon signed-rank of the random values against the regular one
# (:meth:`~asperity2d.Comparison.versus`), and the size of the change is the Hodges-Lehmann
# ratio random / regular with its 95 % interval (:func:`asperity2d.stats.relative_effect`).
# The rule the package's own studies use (:mod:`asperity2d.experiments.verdicts`): the claim
# **holds** if p < 0.01 and the change is at least 1 % (twice the model's force resolution);
# there is **no effect** if the ratio's 98 % interval lies within 1 % of 1; it **does not hold**
# only if the change is shown to go the other way; it is **undecided** otherwise, with about
# how many seeds would decide it; and it is **not testable** when there are too few seeds for
# p to go below 0.01 at all. With n seeds the smallest p a signed-rank test can give is 1/2**n:
# 6 seeds give at best 0.016, so 7 is the fewest that can pass.
# :meth:`~asperity2d.Comparison.verdict` applies it.

test = comparison.versus("random", "regular", alternative="less")
effect = a.stats.relative_effect(forces, reference)
n, p = test["n"], test["p_wilcoxon"]
record = comparison.verdict("random", "regular")
verdict = record["verdict"]
if verdict == "not testable with so few seeds":
    verdict += f" ({n} seeds: the smallest p is {0.5 ** n:.3g}; 7 seeds are the fewest)"
elif verdict == "undecided":
    verdict += f" (about {record['numbers']['seeds_needed']} seeds would decide it)"
ratio = effect["ratio"]
low, high = 1 + effect["ci_low"], 1 + effect["ci_high"]
print(f"random / regular = x{ratio:.2f} [{low:.2f}, {high:.2f}]")
print(f"p = {p:.3g} over {n} seeds")
print("Random spacing lowers the critical force:", verdict)

# %%
# The interval is wide: 7 small surfaces say *that* random spacing lowers the force on this
# set-up, not by how much. The full-size study (Ooten's 16 and 4 asperities, 24 seeds) is on
# :doc:`the page of Ooten's thesis </studies/ooten>`.

# %%
# 5. A plot
# ---------
#
# The results are NumPy arrays, so any matplotlib plot is a few lines; ``a.render(result,
# "run.png")`` draws the package's own (and ``.gif``, ``.html``, ``.wav`` an animation, an
# interactive player, a sound).

ns = 1e9  # seconds to nanoseconds
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9, 3.6),
                               layout="constrained")
ax1.plot(result.t * ns, result.drive_force * mN, lw=1)
ax1.plot([e.t_slip * ns for e in events],
         [e.force_peak * mN for e in events], "v", label="slip")
ax1.set(xlabel="time (ns)", ylabel="drive force (mN)",
        title="one run, random spacing")
ax1.legend(loc="upper left")
ax2.axhline(reference * mN, color="k", lw=1, label="regular")
ax2.plot(list(seeds), np.array(forces) * mN, "o", label="random")
ax2.set(xlabel="seed", ylabel="critical force (mN)",
        ylim=(0, 1.4 * reference * mN), title="over seeds")
ax2.legend(loc="upper right", ncols=2)
fig.savefig(out / "first_study.png", dpi=120)

# %%
# 6. Save, load, and export for MATLAB
# ------------------------------------
#
# ``save`` writes everything (the series, the scene, the run's settings and versions) to one
# ``.npz`` file; :func:`asperity2d.load` reads it back bit for bit, so a run is analysed or
# rendered again without re-running it. A comparison saves as JSON.

path = result.save(out / "run.npz")
again = a.load(path)
print(again)
print("identical:", np.array_equal(again.drive_force, result.drive_force))
print(f"peak stick force: {a.peak_stick_force(again) * mN:.2f} mN")
comparison.save(out / "critical.json")
print(a.Comparison.load(out / "critical.json") == comparison)

# %%
# ``export`` writes a MATLAB ``.mat`` file (or ``.csv``): every series as a row vector, SI
# units, and the run's metadata as a JSON string. In MATLAB::
#
#     load('run.mat');  plot(t * 1e9, drive_force * 1e3);  xlabel('time (ns)')
#
# The same file read back with SciPy:

from scipy.io import loadmat

mat = loadmat(result.export(out / "run.mat"))
for name in sorted(k for k in mat if not k.startswith("__")):
    print(f"{name:17s}", mat[name].shape)
print(f"largest drive force: {mat['drive_force'].max() * mN:.2f} mN")

# %%
# Where next
# ----------
#
# * :doc:`The gallery </auto_scenes/index>`: each scene script as a lesson, from the quickstart
#   to rough surfaces, belt chains and dynamics.
# * :doc:`The parameter table </parameters>`: every keyword of ``make_scene`` with its unit
#   and default.
# * :doc:`The API reference </reference>`: every function used here, with its parameters and
#   examples.
