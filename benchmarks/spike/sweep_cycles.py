"""Does the batched engine's island ever come back exactly to a state it had a few sweeps before?

If a sweep's whole state (per contact point its three accumulated impulses; per island body its
velocities, bias velocities, spring target and groove impulses; the slider's) equalled the state
p sweeps earlier, the remaining sweeps of the step would be known without running them, bit for
bit. This script measures how often that happens: it copies the package to a temporary folder,
adds to the copy of ``engine/batched_kernel.py`` a record of every sweep's state and a comparison
with the four before it (one thread, so the counters need no locks), runs ``passes`` default
peak-stick passes of ``seeds`` random surfaces and prints, per cycle length 1-4, at which sweep
the steps entered one. Needs the ``[batch]`` extra; the copy compiles afresh (about a minute)::

    python benchmarks/spike/sweep_cycles.py [seeds] [passes]

The answer is on the benchmarks page ("Where its time goes").
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

#: (text in the kernel, what the copy has instead): the counters' argument, the state's record
#: and its comparison, at the end of each lane's sweep
PATCHES = [
    ("slow_since, v_unit, dt_s, off_x):\n", "slow_since, v_unit, dt_s, off_x, stats):\n"),
    ("slow_since, v_unit, dt_s, off_x, n_groups):",
     "slow_since, v_unit, dt_s, off_x, n_groups, stats):"),
    ("                    slow_since, v_unit, dt_s, off_x)\n", "                    slow_since, v_unit, dt_s, off_x, stats)\n"),
    ("    changed = np.zeros(L, np.bool_)\n",
     "    changed = np.zeros(L, np.bool_)\n"
     "    hist = np.zeros((L, iterations.max() + 1, 3 * pt.shape[1] + 7 * bd.shape[1] + 8))\n"
     "    found = np.zeros(L, np.int64)\n"),
    ("                if not changed[l] or it + 1 >= iterations[b]:\n                    sweep[l] = False\n", """\
                w = 0
                for m in range(n_c_[l]):
                    for f in (JB, JN, JT):
                        hist[l, it, w] = pt[l, m, f]
                        w += 1
                for q in range(n_isl_[l]):
                    for f in (V0, V1, B0, B1, TG, G0, G1):
                        hist[l, it, w] = bd[l, q, f]
                        w += 1
                for f in range(8):
                    hist[l, it, w] = r_s[l, f]
                    w += 1
                if it == 0:
                    found[l] = 0
                for p in range(1, 5):
                    if found[l] == 0 and it >= p:
                        same = True
                        for x in range(w):
                            if hist[l, it, x] != hist[l, it - p, x]:
                                same = False
                                break
                        if same:
                            found[l] = p
                            stats[p, it] += 1
                if not changed[l] or it + 1 >= iterations[b]:
                    stats[5, it] += 1
                    sweep[l] = False
"""),
    ("LANES = 4\n", "LANES = 4\nSTATS = np.zeros((6, 1024), np.int64)\n"),
]

RUN = """
import sys
import numpy as np
import asperity2d as a
from asperity2d.engine import batched_kernel as K
from asperity2d.experiments.measures import stick_forces_of
seeds, passes = int(sys.argv[1]), int(sys.argv[2])
stick_forces_of([a.make_scene(spacing="random", seed=9401 + s) for s in range(seeds)], passes=passes,
                engine="batched")
S = K.STATS
steps, full = S[5].sum(), S[5, 19]
print(f"{steps} steps; {full} used all 20 sweeps")
for p in range(1, 5):
    print(f"entered a cycle of {p} (at sweep 1..20):", S[p, :20].tolist(), "total", S[p].sum())
"""


def main(seeds: int = 4, passes: int = 1) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        pkg = Path(tmp) / "asperity2d"
        shutil.copytree(ROOT / "asperity2d", pkg, ignore=shutil.ignore_patterns("__pycache__"))
        kernel = pkg / "engine" / "batched_kernel.py"
        text = kernel.read_text()
        for old, new in PATCHES:
            if old not in text:
                raise SystemExit(f"the kernel no longer has the text this script patches: {old.strip()[:60]!r}")
            text = text.replace(old, new)
        kernel.write_text(text.replace("cache=True", "cache=False"))
        batched = pkg / "engine" / "batched.py"
        call = "self.off_x, k.groups(len(self.dt)))"
        if call not in batched.read_text():
            raise SystemExit("engine/batched.py no longer calls the kernel as this script patches it")
        batched.write_text(batched.read_text().replace(call, "self.off_x, k.groups(len(self.dt)), k.STATS)"))
        env = {**os.environ, "PYTHONPATH": tmp, "NUMBA_NUM_THREADS": "1", "TQDM_DISABLE": "1"}
        subprocess.run([sys.executable, "-c", RUN, str(seeds), str(passes)], env=env, cwd=tmp, check=True)


if __name__ == "__main__":
    main(*(int(x) for x in sys.argv[1:3]))
