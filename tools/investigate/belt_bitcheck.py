"""Investigation (issue 28 item 4): are a change's belt-chain outputs byte-identical to another tree's?

    git archive main asperity2d | tar -x -C /tmp/main-tree          # the code to compare against
    python tools/investigate/belt_bitcheck.py dump /tmp/main-tree main.pkl
    python tools/investigate/belt_bitcheck.py dump . branch.pkl
    python tools/investigate/belt_bitcheck.py compare main.pkl branch.pkl

``dump ROOT OUT`` imports asperity2d from ROOT and pickles, per run, every array of the result as
bytes, its events, stick intervals and meta (less the wall time; a callable belt's repr less its
address): every preset at 10 s and 60 s, the benchmark's 10 s Table 2 run (t_eval, no events),
Table 2 over 1000 s, ``NRAND`` (default 120) random chains of 3-100 masses (undamped, damped,
links removed, static/kinetic and Coulomb), callable-belt (integrated phases), Stribeck and
normal-contact chains. ``compare`` lists the runs that differ by a single byte.
"""
import os
import pickle
import re
import sys


def dump(root, out):
    sys.path.insert(0, os.path.abspath(root))
    import numpy as np

    import asperity2d
    assert asperity2d.__file__.startswith(os.path.abspath(root)), asperity2d.__file__
    from asperity2d.belt import presets, simulate_chain
    from asperity2d.belt.normal import NormalContact
    from asperity2d.friction.laws import Stribeck

    def pack(r):
        d = {}
        for k in dir(r):
            if k.startswith("_"):
                continue
            try:
                a = getattr(r, k)
            except Exception:  # noqa: BLE001 -- a property a result kind does not support
                continue
            if isinstance(a, np.ndarray):
                d[k] = (a.dtype.str, a.shape, a.tobytes())
            elif isinstance(a, (float, int, str)):
                d[k] = a
        d["events"] = [repr(e) for e in r.events]
        d["stick"] = repr(getattr(r, "stick_intervals", None))
        d["meta"] = re.sub(r"0x[0-9a-f]+", "0x?", repr({k: v for k, v in r.meta.items() if k != "wall_time"}))
        return d

    def run(key, **kw):
        try:
            runs[key] = pack(simulate_chain(**kw))
        except Exception as exc:  # noqa: BLE001 -- a refused run must be refused the same way
            runs[key] = ("raised", type(exc).__name__, str(exc))

    runs = {}
    for name in presets.names():
        for t_end in (10.0, 60.0):
            run((name, t_end), **presets.preset(name, t_end=t_end))
    run("bench10", **presets.preset("table2-3dof", t_end=10.0), t_eval=np.linspace(0, 10, 2001),
        include_events=False, max_steps=10**8)
    run("table2-1000s", **presets.preset("table2-3dof", t_end=1000.0), max_steps=10**8)
    rng = np.random.default_rng(20261125)
    for i in range(int(os.environ.get("NRAND", 120))):
        n = int(rng.choice([3, 4, 5, 7, 10, 20, 40, 100])) if i < 50 else int(rng.integers(3, 12))
        k = rng.uniform(5, 30, n + 1)
        c = np.zeros(n + 1) if i % 3 == 0 else rng.uniform(0, 1.0, n + 1)
        if i % 5 == 1:  # unlinked: some links removed
            cut = rng.random(n + 1) < 0.3
            k[cut], c[cut] = 0.0, 0.0
        mu_s = float(rng.uniform(0.1, 0.5))
        run(("random", i), masses=rng.uniform(0.5, 2.0, n).tolist(), springs=k.tolist(), dampers=c.tolist(),
            mu_s=mu_s, mu_k=mu_s if i % 2 else mu_s * float(rng.uniform(0.6, 1.0)),
            v_belt=float(rng.uniform(0.05, 0.5)), x0=rng.uniform(-0.05, 0.1, n).tolist(),
            v0=rng.uniform(-0.1, 0.3, n).tolist(), t_end=10.0 if n > 20 else 30.0, max_steps=10**8)
    for name in ("table2-3dof", "table4-c0.5", "table1-2dof-belt"):
        kw = presets.preset(name, t_end=5.0)
        V = kw.pop("v_belt")
        run(("ramp", name), **kw, v_belt=lambda t, V=V: V * min(1.0, 0.5 + t / 4))
        kw = presets.preset(name, t_end=5.0)
        kw.pop("mu_s"), kw.pop("mu_k")
        run(("stribeck", name), **kw, friction=Stribeck(0.3, 0.2, 0.05))
    contacts = [NormalContact(), NormalContact(contact_stiffness=1e6),
                NormalContact(stiffness=400.0, damping=3.0, preload=20.0),
                NormalContact(stiffness=100.0, preload=-5.0, contact_stiffness=1e4)]
    for i, normal in enumerate(contacts):
        for name in ("table2-3dof", "table4-c0.5"):
            run(("contact", i, name), **presets.preset(name, t_end=3.0), normal=normal, y0=[0.001, 0.0, 0.002],
                vy0=[0.1, 0.0, -0.05])
    with open(out, "wb") as fh:
        pickle.dump(runs, fh)
    events = sum(len(v["events"]) for v in runs.values() if isinstance(v, dict))
    print(f"{len(runs)} runs, {events} events, {sum(not isinstance(v, dict) for v in runs.values())} raised")


def compare(first, second):
    a, b = (pickle.load(open(p, "rb")) for p in (first, second))
    if a.keys() != b.keys():
        sys.exit("the dumps hold different runs")
    differ = [k for k in a if pickle.dumps(a[k]) != pickle.dumps(b[k])]
    events = sum(len(v["events"]) for v in a.values() if isinstance(v, dict))
    print(f"{len(a)} runs, {events} events compared; {len(differ)} differ{': ' if differ else ''}"
          f"{', '.join(map(str, differ[:20]))}")
    sys.exit(1 if differ else 0)


if __name__ == "__main__":
    {"dump": dump, "compare": compare}[sys.argv[1]](*sys.argv[2:])
