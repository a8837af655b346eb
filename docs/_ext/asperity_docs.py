"""Tables generated from the code at build time, so the documentation never pastes a number.

Directives (reStructuredText; in a MyST page wrap them in an ``{eval-rst}`` block):

``.. parameter-table::``
    every keyword of :func:`asperity2d.make_scene` with its default, unit and meaning, from
    :data:`asperity2d.builders.KEYWORDS` and :data:`asperity2d.builders.PARAMETERS` (the single
    source of the defaults).

``.. validation-table::``
    runs every closed-form check of :mod:`asperity2d.closed_forms` (the ones the test suite runs)
    and tabulates expected, measured, relative error and tolerance. A failing check is a build
    warning, so a ``-W`` build fails on it.

``.. claims-table:: NAME``
    the claim records of a study's full-size run, from ``docs/data/claims/NAME.json``
    (``docs/data/README.md`` says how those files are made). Options: ``:setup: fixed|free``
    keeps one set-up's claims.

``.. cli-help::``
    ``asperity2d --help`` and every subcommand's help, from the command line's own parser.

``{claim-seeds}`NAME; key=value; ...```` (a role)
    how the seeds of one claim of ``docs/data/claims/NAME.json`` fell ("12/24 above, 4 below
    and 8 equal"), the claim picked by its fields (``measure=critical; setup=fixed``): a count
    quoted in prose comes from the data, not typed.

``.. stick-precision-table::`` (option ``:seeds: FIRST-LAST``)
    the stick forces' step bias (dt -> dt/2 -> dt/4) and per-seed precision, computed from the
    measured passes in ``docs/data/measures/stick_bias.json`` by ``docs/data/stick_precision.py``;
    ``{stick-figure}`MEASURE; FIELD; FIRST-LAST``` quotes one of its numbers in prose (FIELD:
    ``1.0->0.5``, ``0.5->0.25``, ``per_seed_sd``, ``per_pass_sd``, ``seeds_for_5_percent``,
    ``seeds``, ``regular 1.0->0.5``: the regular surface's shift).

``.. measure-steps::``
    every named measure with the step it runs at (a fraction of the default step, from
    :func:`asperity2d.experiments.measures.measure_step`) and the tolerance halving it again is
    held to (``STEP_TOLERANCE``).

``.. constant-value:: module.NAME``
    a constant's value as a reader wants it: a table of records (one row per record, one column
    per field), a table of a mapping's keys and values, or the literal (the API reference's
    constant pages use it through ``docs/_templates/autosummary/data.rst``).
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

from docutils import nodes
from docutils.parsers.rst import Directive, directives
from docutils.statemachine import StringList
from sphinx.util import logging

DOCS = Path(__file__).resolve().parent.parent
CLAIMS = DOCS / "data" / "claims"
logger = logging.getLogger(__name__)


def cell(text) -> str:
    """Plain text for a list-table cell: backticked names as literals, no stray markup."""
    text = str(text).replace("\\", "\\\\").replace("*", "\\*").replace("|", "\\|")
    text = re.sub(r"(?<!`)`([^`]+)`(?!`)", r"``\1``", text)
    text = re.sub(r'(?<![`\w])"([\w. -]+)"(?![`\w])', r'``"\1"``', text)  # quoted choices as code
    return " ".join(text.split()) or "\\ "


def list_table(header: list[str], rows: list[list[str]], *, widths: str | None = None,
               cls: str = "") -> list[str]:
    lines = [".. list-table::", "   :header-rows: 1"]
    if widths:
        lines.append(f"   :widths: {widths}")
    if cls:
        lines.append(f"   :class: {cls}")
    lines.append("")
    for row in [header] + rows:
        lines.append(f"   * - {row[0]}")
        lines += [f"     - {c}" for c in row[1:]]
    return lines + [""]


class _Generated(Directive):
    """A directive whose content is reST made by :meth:`lines`."""

    has_content = False

    def lines(self) -> list[str]:  # pragma: no cover - abstract
        raise NotImplementedError

    def run(self):
        container = nodes.container()
        self.state.nested_parse(StringList(self.lines(), source=f"<{self.name}>"), self.content_offset,
                                container)
        return container.children


# -- make_scene's parameters ------------------------------------------------------------------
def default_text(record) -> str:
    """A parameter's default as a reader writes it: SI prefixes, quotes on text, None as derived."""
    from asperity2d._format import si

    value = record.default
    if value is None:
        return "derived"
    if isinstance(value, bool):
        return f"``{value}``"
    if isinstance(value, str):
        return f'``"{value}"``' if value else '``""``'
    if record.unit in ("1", "-"):
        return f"{value:g}"
    if record.unit == "°":
        return f"{value:g}°"
    return si(value, record.unit, 3, trim=True)


class ParameterTable(_Generated):
    def lines(self):
        from asperity2d import builders

        groups = (("make_scene's named keywords", builders.KEYWORDS),
                  ("Ooten's fixed track (asperity2d.scene.OOTEN_PARAMETERS)",
                   builders.PARAMETERS[:len(_ooten())]),
                  ("everything else (asperity2d.builders.PARAMETERS)", builders.PARAMETERS[len(_ooten()):]))
        out = []
        for title, records in groups:  # one table per group, its title above it (not a row that widens column 1)
            rows = [[f"``{r.name}``", default_text(r), cell("—" if r.unit == "-" else r.unit), math_cell(r.meaning)]
                    for r in records]
            out += [f".. rubric:: {title}", ""]
            out += list_table(["keyword", "default", "unit", "meaning"], rows, widths="18 12 8 62",
                              cls="parameter-table")
        return out


def _ooten():
    from asperity2d.scene import OOTEN_PARAMETERS

    return OOTEN_PARAMETERS


# -- formulas in one notation ------------------------------------------------------------------
#: the closed forms and parameter meanings that the code states in plain text, as LaTeX (the pages
#: typeset them with MathJax; a form not listed here stays text)
LATEX = {
    "(belt work - Δ energy - dissipation) / belt work = 0":
        r"(W_\text{belt} - \Delta E - D) / W_\text{belt} = 0",
    "F / W = tan(θ + atan μ)": r"F / W = \tan(\theta + \arctan\mu)",
    "F = μk N": r"F = \mu_k N",
    "F = μs N": r"F = \mu_s N",
    "F_crit / N = μs (tan θ_crit = μ)": r"F_\text{crit} / N = \mu_s \; (\tan\theta_\text{crit} = \mu)",
    "T = (2π - 2 atan(ω d / V)) / ω + 2 d / V, d = (Fs - Fk) / k":
        r"T = \frac{2\pi - 2\arctan(\omega d / V)}{\omega} + \frac{2 d}{V},\; d = \frac{F_s - F_k}{k}",
    "T = 2π / ω": r"T = 2\pi / \omega",
    "drive work = Δ stored + dissipated + numerical": r"W_\text{drive} = \Delta E_\text{stored} + D + \varepsilon",
    "f_j = sqrt(k (2 - 2 cos(jπ/4)) / m) / 2π": r"f_j = \sqrt{k (2 - 2\cos(j\pi/4)) / m} \,/\, 2\pi",
    "k x = Fs = μs m g": r"k x = F_s = \mu_s m g",
    "n k δ tan(45° + atan μs)": r"n k \delta \tan(45^\circ + \arctan\mu_s)",
    "ΔF = 2 (Fs - Fk)": r"\Delta F = 2 (F_s - F_k)",
    "Δx = 4 Fk / k": r"\Delta x = 4 F_k / k",
    "Σ F_n = L": r"\textstyle\sum F_n = L",
    "Σ F_t = F_drive": r"\textstyle\sum F_t = F_\text{drive}",
    "μ_crit = [(K11 - K22')² + 4κ²] / (4 s κ k_c)":
        r"\mu_\text{crit} = \frac{(K_{11} - K'_{22})^2 + 4\kappa^2}{4 s \kappa k_c}",
    "σ = Re λ of the characteristic polynomial": r"\sigma = \operatorname{Re}\lambda \text{ of the characteristic polynomial}",
    "2√(k m)": r"2\sqrt{k m}",
    "K = 2 E b": r"K = 2 E b",
    "ρ b² h / 3": r"\rho b^2 h / 3",
}


def math_cell(text: str) -> str:
    """A table cell with the formulas of :data:`LATEX` typeset (``:math:``), the rest as :func:`cell`."""
    text = str(text)
    if text in LATEX:
        return f":math:`{LATEX[text]}`"
    out = cell(text)
    for plain, latex in LATEX.items():
        if plain in text and len(plain) < len(text):
            out = out.replace(cell(plain), f":math:`{latex}`")
    return out


# -- closed-form checks --------------------------------------------------------------------
class ValidationTable(_Generated):
    def lines(self):
        import platform

        import pymunk

        import asperity2d
        from asperity2d import closed_forms

        checks = closed_forms.run_all()
        rows, notes = [], []
        for check_id, check in zip(closed_forms.CHECKS, checks):
            if not check.passed:
                logger.warning(f"closed-form check {check_id!r} fails: {check.line()}", location=self.get_location())
            rows.append([cell(check.name), math_cell(check.closed_form), cell(check.show(check.expected)),
                         cell(check.show(check.measured)), f"{check.error:.1e}", f"{check.tolerance:.0e}",
                         "✓" if check.passed else "**fails**"])
            notes.append([cell(check.name), cell(check.why), cell(check.source)])
        passed = sum(c.passed for c in checks)
        head = [f"Measured when this page was built: {passed} of {len(checks)} checks within tolerance "
                f"(asperity2d {asperity2d.__version__}, pymunk {pymunk.version}, Python "
                f"{platform.python_version()}).", ""]
        return (head + list_table(["check", "closed form", "expected", "measured", "relative error",
                                   "tolerance", ""], rows, widths="30 22 11 11 9 8 4", cls="validation-table")
                + [".. rubric:: Why each tolerance, and where each closed form comes from", ""]
                + list_table(["check", "the tolerance, because", "source"], notes, widths="30 45 25"))


# -- claim records -------------------------------------------------------------------------
SETUPS = {"fixed": "Ooten's fixed track", "free": "free slider"}


def claim_rows(claims: list[dict], *, setup: str | None = None, setups: bool = True) -> list[list[str]]:
    from asperity2d.studies.claims import numbers_text, rejudge, seeds_needed

    rows = []
    for record in claims:
        if setup and record.get("setup") not in (setup, None):
            continue
        verdict = rejudge(record)  # today's rule: "no effect" or "undecided" where it is not shown the other way
        shown = f"**{verdict}**" if verdict == "holds" else verdict
        numbers = record.get("numbers") or {}
        if verdict == "undecided" and isinstance(numbers, dict):
            more = numbers.get("seeds_needed") or seeds_needed(
                numbers, numbers.get("tost_alpha", 0.01), direction=numbers.get("alternative") or
                ("greater" if "(higher)" in record.get("test", "") else "less"), min_effect=numbers.get("margin", 0.01))
            shown += f" (about {more} seeds would decide it)" if more else " (at the margin)"
        row = [cell(record["claim"])]
        if setups:
            row.append(cell(SETUPS.get(record.get("setup"), record.get("setup") or "—")))
        rows.append(row + [shown, cell(numbers_text(record.get("numbers", {}))), cell(short_test(record.get("test", "")))])
    return rows


#: the words every test of a claim repeats, said once above the tables instead of on every row
_BOILERPLATE = (("; holds if p < 0.01 and the change is at least 1 %; no effect if the 98 % interval of the "
                 "ratio lies within +-1 %; does not hold if shown the other way", ""),
                ("; holds if p < 0.01 and the change is at least 1 %", ""),
                ("one-sample Wilcoxon signed-rank against the reference value", "Wilcoxon against the regular value"),
                ("Wilcoxon signed-rank", "Wilcoxon"), (" (same seeds)", ""))


def short_test(text: str) -> str:
    """A claim's test without the criterion every claim shares (the page states it once)."""
    for long, short in _BOILERPLATE:
        text = text.replace(long, short)
    return text


class ClaimsSummary(Directive):
    """A summary of a study page's claims: one row per section, the verdicts counted per set-up.

    Content: one line per claims file, ``NAME | section title | #anchor``.
    """

    has_content = True

    def run(self):
        from asperity2d.studies.claims import rejudge

        rows = []
        setups_seen = []
        parsed = []
        for line in self.content:
            if not line.strip():
                continue
            name, title, anchor = [part.strip() for part in line.split("|")]
            path = CLAIMS / f"{name}.json"
            self.state.document.settings.record_dependencies.add(str(path))
            claims = json.loads(path.read_text(encoding="utf-8"))["claims"]
            counts = {}
            for record in claims:
                setup = record.get("setup") or "—"
                if setup not in setups_seen:
                    setups_seen.append(setup)
                held, total = counts.get(setup, (0, 0))
                counts[setup] = (held + (rejudge(record) == "holds"), total + 1)
            parsed.append((title, anchor, counts))
        for title, anchor, counts in parsed:
            row = [f"`{title} <{anchor}>`__"]
            for setup in setups_seen:
                held, total = counts.get(setup, (0, 0))
                row.append(f"**{held}** of {total}" if total else "—")
            rows.append(row)
        header = ["claim (section)"] + [f"holds on {SETUPS.get(s, s)}" for s in setups_seen]
        lines = list_table(header, rows, cls="claims-summary")
        container = nodes.container()
        self.state.nested_parse(StringList(lines, source="<claims-summary>"), self.content_offset, container)
        return container.children


def claims_table_lines(claims: list[dict], *, setup: str | None = None) -> list[str]:
    """A claims table; the set-up column only when some claim has one (the asperity studies)."""
    setups = any(record.get("setup") for record in claims)
    header = ["claim"] + (["set-up"] if setups else []) + ["verdict", "what was measured", "test"]
    return list_table(header, claim_rows(claims, setup=setup, setups=setups),
                      widths="28 10 9 33 20" if setups else "30 10 38 22", cls="claims-table")


class ClaimsTable(_Generated):
    required_arguments = 1
    option_spec = {"setup": lambda s: directives.choice(s, tuple(SETUPS))}

    def lines(self):
        name = self.arguments[0]
        path = CLAIMS / f"{name}.json"
        if not path.exists():
            return [".. admonition:: Full-size claim records not committed yet", "   :class: warning", "",
                    f"   ``docs/data/claims/{name}.json`` does not exist: run ``python docs/data/collect_claims.py "
                    f"{name}`` (see ``docs/data/README.md``). The quick run of the script in the gallery "
                    "shows the same claims on a few seeds.", ""]
        data = json.loads(path.read_text(encoding="utf-8"))
        self.state.document.settings.record_dependencies.add(str(path))
        lines = [f"*Full-size run:* ``{data['command']}`` ({data['date']}; {_duration(data.get('cpu_s'))}).", ""]
        return lines + claims_table_lines(data["claims"], setup=self.options.get("setup"))


def claim_seeds_role(name, rawtext, text, lineno, inliner, options=None, content=None):
    """``{claim-seeds}`ooten_profiles; measure=critical; setup=fixed; friction=mu_s > mu_k```."""
    file, *selectors = [part.strip() for part in text.split(";")]
    wanted = dict(part.split("=", 1) for part in selectors)
    wanted = {k.strip(): v.strip() for k, v in wanted.items()}
    path = CLAIMS / f"{file}.json"
    try:
        claims = json.loads(path.read_text(encoding="utf-8"))["claims"]
    except (OSError, ValueError, KeyError) as exc:
        msg = inliner.reporter.error(f"claim-seeds: cannot read {path}: {exc}", line=lineno)
        return [inliner.problematic(rawtext, rawtext, msg)], [msg]
    found = [c for c in claims if all(str(c.get(k)) == v for k, v in wanted.items())]
    if len(found) != 1:
        msg = inliner.reporter.error(f"claim-seeds: {len(found)} claims of {file} match {wanted} (want one)",
                                     line=lineno)
        return [inliner.problematic(rawtext, rawtext, msg)], [msg]
    inliner.document.settings.record_dependencies.add(str(path))
    n = found[0]["numbers"]
    equal = n["n"] - n["above"] - n["below"]
    return [nodes.Text(f"{n['above']}/{n['n']} above, {n['below']} below and {equal} equal")], []


# -- the stick forces' step bias and precision, from docs/data/measures/stick_bias.json ---------
_STICK_SUMMARIES: dict = {}


def stick_summary(seeds: str | None) -> dict:
    """docs/data/stick_precision.py's summary of the seeds ``"FIRST-LAST"`` (all if None), cached."""
    if seeds not in _STICK_SUMMARIES:
        import importlib.util

        spec = importlib.util.spec_from_file_location("_stick_precision", DOCS / "data" / "stick_precision.py")
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        _STICK_SUMMARIES[seeds] = (module, module.summary(seeds=module.seed_range(seeds)))
    return _STICK_SUMMARIES[seeds]


def _pm(mean: float, se: float) -> str:
    """``"+1.4 ± 2.5 %"``; three decimals for a shift under 0.1 % (the first breakaway's)."""
    digits = 1 if max(abs(mean), se) >= 1e-3 else 3
    return f"{100 * mean:+.{digits}f} ± {100 * se:.{digits}f} %".replace("-", "−")


def _percent(x: float) -> str:
    if x < 5e-6:
        return "under 0.001 %"
    return f"{100 * x:.0f} %" if x >= 0.1 else f"{100 * x:.1f} %" if x >= 1e-3 else f"{100 * x:.3f} %"


def _shift(s: dict) -> str:
    return _pm(s["mean"], s["se"]) + f" ({s['up']} up, {s['down']} down; p {s['p_wilcoxon']:.2g})"


def _seeds_for(n) -> str:
    return "more than 3,200" if n is None else f"{n:,}"


class StickPrecisionTable(_Generated):
    option_spec = {"seeds": directives.unchanged}

    def lines(self):
        try:
            module, result = stick_summary(self.options.get("seeds"))
        except (OSError, ValueError, KeyError) as exc:
            raise self.error(f"stick-precision-table: {exc}")
        self.state.document.settings.record_dependencies.add(str(module.DATA))
        rows = [[e["label"], _shift(e["1.0->0.5"]), _shift(e["0.5->0.25"]), e["step"], _percent(e["per_seed_sd"]),
                 _percent(e["per_pass_sd"]), _seeds_for(e["seeds_for_5_percent"])]
                for e in result["measures"].values()]
        lines = list_table(["stick force (mean of the passes)", "dt → dt/2", "dt/2 → dt/4", "its step",
                            "per-seed sd at its step", "one pass's sd", "seeds for a 5 % difference"],
                           rows, widths="16 17 17 8 12 11 19", cls="stick-precision-table")
        return lines + [f"Seeds {module.seeds_text(result['seeds'])}, {result['setup']} track 10/3, random spacing, "
                        f"{result['passes']} passes each at dt, dt/2 and dt/4 ({result['cpu_minutes']:.0f} CPU-minutes); "
                        "shifts are the mean over seeds ± one standard error, with the seeds up and down and a "
                        "two-sided Wilcoxon p. Seeds for a 5 % difference: the fewest at which 80 % of "
                        "comparisons against a reference 5 % away hold by the verdict rule (one-sided Wilcoxon "
                        "p < 0.01, a change of at least 1 %; never fewer than 7), the seeds drawn from the "
                        "measured per-seed values.", ""]


def stick_figure_role(name, rawtext, text, lineno, inliner, options=None, content=None):
    """``{stick-figure}`peak; 0.5->0.25; 9401-9424``` -> "−1.4 ± 3.0 %"."""
    parts = [part.strip() for part in text.split(";")]
    try:
        measure, field = parts[0], parts[1]
        module, result = stick_summary(parts[2] if len(parts) > 2 else None)
        if field == "seeds":
            out = module.seeds_text(result["seeds"])
        elif field.startswith("regular "):
            value = result["measures"][measure]["regular"][field.split()[1]]
            if not math.isfinite(value):
                raise ValueError("the regular surface was not measured at these steps")
            out = f"{100 * value:+.{1 if abs(value) >= 1e-3 else 2}f} %".replace("-", "−")
        else:
            value = result["measures"][measure][field]
            out = (_pm(value["mean"], value["se"]) if isinstance(value, dict)
                   else _seeds_for(value) if field == "seeds_for_5_percent" else _percent(value))
    except (OSError, ValueError, KeyError, IndexError) as exc:
        msg = inliner.reporter.error(f"stick-figure: cannot quote {text!r}: {exc}", line=lineno)
        return [inliner.problematic(rawtext, rawtext, msg)], [msg]
    inliner.document.settings.record_dependencies.add(str(module.DATA))
    return [nodes.Text(out)], []


class MeasureSteps(_Generated):
    """The step policy as the code has it: each named measure's step and tolerance."""

    def lines(self):
        import asperity2d as a
        from asperity2d.experiments import measures
        from asperity2d.run import default_dt

        scene = a.make_scene()
        words = {1.0: "dt", 0.5: "dt/2", 0.25: "dt/4", 0.125: "dt/8"}
        rows = []
        for name, m in measures.MEASURES.items():
            if name not in measures.STEP_TOLERANCE:
                continue
            fraction = measures.measure_step(name, scene) / default_dt(scene)
            rows.append([f"``{name}``", cell(m.label), words.get(round(fraction, 6), f"{fraction:g} dt"),
                         f"{100 * measures.STEP_TOLERANCE[name]:g} %" + (" of the mean over seeds" if m.distribution
                                                                         else " of the larger of itself and a pitch"
                                                                         if name == "travel" else "")])
        return list_table(["measure", "what it is", "its step", "halving it again moves it by less than"], rows,
                          widths="18 42 12 28", cls="measure-steps-table")


# -- benchmarks: the cost model, from benchmarks/results.json ------------------------------------
RESULTS = DOCS.parent / "benchmarks" / "results.json"


def _us(x: float) -> str:
    return f"{x:,.0f} µs" if x >= 100 else f"{x:.1f} µs"


def _secs(x: float) -> str:
    if x < 1:
        return f"{x * 1e3:.0f} ms"
    if x < 120:
        return f"{x:.1f} s"
    if x < 7200:
        return f"{x / 60:.0f} min"
    return f"{x / 3600:.1f} h"


def cost_fit(rows: list[dict]) -> tuple[float, float]:
    """The line ``a + b N`` (µs a step) through the measured per-step costs, least squares in the
    relative error (each point weighted by 1/cost, so the small scenes count as much as the large)."""
    import numpy as np

    n = np.array([r["N"] for r in rows], float)
    c = np.array([r["run_us_per_step"] for r in rows], float)
    b, a = np.polyfit(n, c, 1, w=1.0 / c)
    return float(a), float(b)


def batched_cost_lines(res: dict | None, pymunk: tuple[float, float]) -> list[str]:
    """The batched engine's measured cost per scene-step by batch size B and lower count N
    (``benchmarks/bench_batched.py``'s ``cost``), its fitted lines, and pymunk's beside them."""
    if not res or "cost" not in res:
        why = (res or {}).get("skipped", "not measured in benchmarks/results.json")
        return [f"The batched engine's cost model is not measured here: {why}.", ""]
    cost = res["cost"]
    sizes = sorted({r["B"] for r in cost["rows"]})
    counts = sorted({r["N"] for r in cost["rows"]})
    cell_of = {(r["B"], r["N"]): r for r in cost["rows"]}
    rows = []
    for n in counts:
        row = [str(n)]
        for b in sizes:
            r = cell_of.get((b, n))
            row.append("" if r is None else f"{_us(r['cpu_us_per_scene_step'])} ({_us(r['wall_us_per_scene_step'])})")
        row.append(_us(pymunk[0] + pymunk[1] * n))
        rows.append(row)
    import numpy as np

    # the line through the batches that fill the threads (B >= 16), weighted by 1 / cost as pymunk's
    full = [r for r in cost["rows"] if r["B"] >= 16] or cost["rows"]
    n = np.array([r["N"] for r in full], float)
    c = np.array([r["cpu_us_per_scene_step"] for r in full], float)
    fb, fa = np.polyfit(n, c, 1, w=1.0 / c)
    worst = float(np.max(np.abs((fa + fb * n) / c - 1.0)))
    pa, pb = pymunk
    load = res["measured"].get("load_average_before")
    out = [f"CPU (wall) per scene-step of the batched engine, a regular fixed-track scene of N lower asperities "
           f"and 4 tips with its slider on the surface, {cost['threads']} threads, measured "
           f"{res['measured']['date'].split()[0]}" + (f" (load {load[0]:.1f})" if load else "") + "; the "
           "last column is pymunk's line above:", ""]
    out += list_table(["N"] + [f"B = {b}" for b in sizes] + ["pymunk c(N)"], rows, cls="benchmark-table")
    out += [f"The fitted line through the batches of 16 scenes or more: **c(N) = {fa:.2f} µs + {fb:.3f} µs × N** "
            f"of CPU a scene-step (within {100 * worst:.0f} % of each of those cells), against pymunk's "
            f"{pa:.1f} µs + {pb:.2f} µs × N. Each scene runs its steps in one thread: from B = 16 on the CPU of a "
            "scene-step no longer depends on B, and the wall time falls with B until every thread has scenes; "
            "a batch of one or four leaves threads idle, which the CPU time of its cells also counts. "
            "Per B: " + ", ".join(f"B = {b}: {f['a']:.2f} + {f['b_per_N']:.3f} N"
                                  for b, f in cost["fit_cpu_us_by_B"].items()) + " µs.", ""]
    return out


class BenchmarkTables(_Generated):
    """The benchmarks page's figures, read from ``benchmarks/results.json`` when the page is built.

    Argument: ``cost`` (the per-step cost by asperity count and the cost model), ``batched`` (the
    batched engine's cost per scene-step by batch size and asperity count), ``measures``
    (a critical force's steps and time), ``workers`` (what parallel workers give), ``others``
    (the belt solver, pictures, start-up) or ``machine`` (where and when it was measured).
    """

    required_arguments = 1

    def lines(self):
        import asperity2d as a

        self.state.document.settings.record_dependencies.add(str(RESULTS))
        data = json.loads(RESULTS.read_text(encoding="utf-8"))
        res = data["results"]
        what = self.arguments[0]
        if what == "machine":
            m = data["machine"]
            return [f"Measured on a {m['cpus']}-core x86-64 Linux machine shared with other work (Python "
                    f"{m['python']}; load {m['load_average'][0]:.1f} at the start of the full run), CPU time, "
                    f"each figure the median of interleaved repeats; the per-step costs on "
                    f"{res['core']['measured']['date'].split()[0]}. Re-measure with "
                    "``python benchmarks/run_all.py`` (it rewrites ``benchmarks/results.json``, and this page "
                    "follows at its next build).", ""]
        if what == "cost":
            rows = res["core"]["rows"]
            fa, fb = cost_fit(rows)
            table = [[str(r["N"]), str(r["upper"]), f"**{_us(r['run_us_per_step'])}**", _us(fa + fb * r["N"]),
                      _us(r["bare_us_per_step"]), f"{r['ratio']:.2f}×"] for r in rows]
            for name, r in res["core"]["steel"].items():
                table.append([cell(r["N"]).replace("x2000", "×2000"), "", f"**{_us(r['run_us_per_step'])}**", "",
                              _us(r["bare_us_per_step"]), f"{r['ratio']:.2f}×"])
            scene = a.make_scene()
            dt = scene.shortest_period() / 50
            per_um = 1e-6 / dt
            n16 = scene.lower.count if hasattr(scene.lower, "count") else 16
            c16 = fa + fb * n16
            worst = max(abs(fa + fb * r["N"] - r["run_us_per_step"]) / r["run_us_per_step"] for r in rows)
            out = [f"The fitted line: **c(N) = {fa:.1f} µs + {fb:.2f} µs × N** a step (N lower asperities, the "
                   f"slider carrying max(3, N/25) tips), within {100 * worst:.0f} % of each measured point. The "
                   "cost follows the contacts more than the count: the steel scenes below, with their slider "
                   "pressed into more asperities, cost more than the line says for their N.", ""]
            out += list_table(["lower asperities N", "slider tips", "a step of a run (measured)", "the line",
                               "a bare pymunk loop", "run / bare"], table, cls="benchmark-table")
            out += [f"Worked example, the default scene (``make_scene()``: {n16} lower asperities, 4 tips): its "
                    f"shortest natural period is {scene.shortest_period() * 1e12:.0f} ps, so the default step "
                    f"is {dt * 1e12:.1f} ps and 1 µs of simulated time is {per_um:,.0f} steps: about "
                    f"**{_secs(per_um * c16 * 1e-6)}** of CPU at {_us(c16)} a step.", ""]
            return out
        if what == "batched":
            return batched_cost_lines(res.get("batched"), cost_fit(res["core"]["rows"]))
        if what == "measures":
            rows = []
            for key, r in res["critical"]["rows"].items():
                setup, start = key.split("/")
                rows.append([f"``critical_force(scene, start=\"{start}\")``",
                             "fixed track" if setup == "fixed" else "free slider",
                             f"{r['steps']:,}", f"**{_secs(r['new_cpu_s'])}**",
                             f"{1e6 * r['new_cpu_s'] / r['steps']:.0f} µs"])
            return list_table(["measure (default scene, constant force)", "set-up", "steps", "CPU time",
                               "a step, all included"], rows, cls="benchmark-table")
        if what == "workers":
            sw = res["sweep"]
            thr = sw["throughput"]["cpu"]
            over = sw["overhead"]["cpu"]
            rows = [["runs a second, 1 worker", f"{thr['runs_per_s_1']:.2f}"],
                    ["runs a second, 2 workers", f"{thr['runs_per_s_2']:.2f} (×{thr['runs_per_s_2'] / thr['runs_per_s_1']:.2f})"],
                    ["starting a pool of 2 workers", _secs(sw["pool_start_2_workers_s"])],
                    ["overhead a run, in this process", f"{over['in-process']['per_run_ms']:.1f} ms"],
                    ["overhead a run, a warm worker", f"{over['pool1-warm']['per_run_ms']:.1f} ms"],
                    ["overhead a run, a cold worker (first run: start-up and imports)",
                     f"{over['pool1-cold']['per_run_ms']:.0f} ms"]]
            return ([f"Runs of about {sw['run_seconds']:g} s of CPU each, the sweep engine's own measurement "
                     f"(``benchmarks/bench_sweep.py``):", ""]
                    + list_table(["", "measured"], rows, widths="60 40", cls="benchmark-table"))
        if what == "others":
            belt = res["belt"]["speed"]
            gif = res["gif"]
            start = res["startup"]["rows"]
            basin = res["basins"]["per_run"]["base"]
            rows = [["a belt chain (2 masses, 10 s), exact solver", _secs(belt["10s"]["cpu_s"]["exact"]),
                     f"{belt['10s']['cpu_s']['solve_ivp+events'] / belt['10s']['cpu_s']['exact']:.1f}× faster than "
                     "the best ``solve_ivp`` with events"],
                    ["… 1000 s", _secs(belt["1000s"]["cpu_s"]["exact"]),
                     f"{belt['1000s']['cpu_s']['solve_ivp+events'] / belt['1000s']['cpu_s']['exact']:.0f}× faster"],
                    ["a basin-map point (3-DOF chain, 100 s)", f"{basin['ms_per_run_median']:.1f} ms", ""],
                    [f"a GIF frame with meters ({gif['width']} × {gif['height']})", _secs(gif["ours_s_per_frame"]),
                     f"{gif['speedup']:.0f}× faster than matplotlib blitting"],
                    ["``import asperity2d``", f"{start['import asperity2d']['wall_ms']:.0f} ms",
                     f"``import pymunk`` alone: {start['import pymunk']['wall_ms']:.0f} ms"],
                    ["``asperity2d --help``", f"{start['asperity2d --help']['wall_ms']:.0f} ms", ""]]
            return list_table(["what", "time", "compared"], rows, widths="45 20 35", cls="benchmark-table")
        raise self.error(f"benchmark-tables: unknown table {what!r}")


# -- mutation scores ---------------------------------------------------------------------------
MUTATION = DOCS / "data" / "mutation"
#: tools/mutation.py's modules, in the order the page lists them
MUTATION_MODULES = ("critical", "events", "forces", "slip-thresholds", "contact-states", "stats", "geometry",
                    "belt-events")


class MutationTable(_Generated):
    """The recorded mutation score of each measure module (``docs/data/mutation/<module>.json``,
    written by ``python tools/mutation.py``)."""

    def lines(self):
        rows, missing, dates, sampled = [], [], set(), False
        for name in MUTATION_MODULES:
            path = MUTATION / f"{name}.json"
            if not path.exists():
                missing.append(name)
                continue
            self.state.document.settings.record_dependencies.add(str(path))
            data = json.loads(path.read_text(encoding="utf-8"))
            judged = data["killed"] + len(data["survived"])
            tests = [t.split("/")[-1].replace("::", " (") + (")" if "::" in t else "") for t in data["tests"]]
            survived = str(len(data["survived"])) + (f" (+{len(data['unknown'])} without an outcome)"
                                                      if data["unknown"] else "")
            rows.append([f"``{data['module'].removeprefix('asperity2d/')}``", cell(", ".join(tests)),
                         str(data["mutants"]), f"{data['killed']} ({data.get('timeouts', '?')})", survived,
                         f"**{100 * data['killed'] / judged:.1f} %**" if judged else "—"])
            dates.add(data.get("date", "an unrecorded date"))
            sampled = sampled or data["run"] < data["mutants"]
        lines = []
        if rows:
            lines = list_table(["module", "its tests", "mutants", "killed (time-outs)", "survived", "score"],
                               rows, widths="16 38 10 14 10 12", cls="mutation-table")
            extent = "a seeded sample of the mutants of some modules" if sampled else "every mutant of each module"
            lines += [f"Measured on {', '.join(sorted(dates))}, {extent}.", ""]
        if missing:
            lines += [".. admonition:: Not measured yet", "   :class: warning", "",
                      f"   No record for {', '.join(missing)}: run ``python tools/mutation.py "
                      f"{' '.join(missing)}`` and commit ``docs/data/mutation/``.", ""]
        return lines


def _duration(cpu_s) -> str:
    if cpu_s is None or not math.isfinite(cpu_s):
        return "run time not recorded"
    from asperity2d._format import si

    return f"{si(cpu_s, 's', 2)} of CPU" if cpu_s < 120 else f"{cpu_s / 60:.0f} min of CPU"


# -- the command line ------------------------------------------------------------------------
class CliHelp(_Generated):
    def lines(self):
        import argparse

        from asperity2d.cli.main import build_parser

        parser = build_parser()
        out = []

        def walk(p: argparse.ArgumentParser, words: list[str]):
            out.extend([f".. rubric:: {' '.join(words)}", "", ".. code-block:: text", ""])
            out.extend("   " + line for line in p.format_help().splitlines())
            out.append("")
            for action in p._actions:
                if isinstance(action, argparse._SubParsersAction):
                    for name, sub in action.choices.items():
                        walk(sub, words + [name])

        walk(parser, ["asperity2d"])
        return out


# -- constants as tables ------------------------------------------------------------------------
def _short(value) -> str:
    """A value as a reader writes it: a function by name, a record by its fields, no addresses."""
    import functools
    import inspect

    if isinstance(value, functools.partial):
        args = ", ".join([repr(a) for a in value.args] + [f"{k}={v!r}" for k, v in value.keywords.items()])
        return f"{_short(value.func)}({args})"
    if inspect.isfunction(value) or inspect.isclass(value) or inspect.isbuiltin(value):
        name = value.__name__
        return "a function" if name == "<lambda>" else f"{name}"
    if isinstance(value, tuple) and not hasattr(value, "_fields"):
        return ", ".join(_short(v) for v in value)
    if hasattr(value, "_fields"):
        return "; ".join(f"{f} {_short(getattr(value, f))}" for f in value._fields)
    if isinstance(value, (set, frozenset)):
        return ", ".join(sorted(map(str, value)))
    if value in ("-", "1") and isinstance(value, str):  # a record's unit: "-" none (a choice, a text), "1" a number
        return "—" if value == "-" else "1"
    if isinstance(value, str):  # a word (a choice, a unit) as code, prose as prose
        return value if " " in value or len(value) > 30 else f"``{value!r}``" if value else "``''``"
    return repr(value)


class ConstantValue(_Generated):
    required_arguments = 1

    def lines(self):
        import dataclasses
        import importlib

        module_name, name = self.arguments[0].rsplit(".", 1)
        value = getattr(importlib.import_module(module_name), name)
        records = isinstance(value, (tuple, list)) and value and all(
            hasattr(v, "_fields") or dataclasses.is_dataclass(v) for v in value)
        if records:
            fields = (value[0]._fields if hasattr(value[0], "_fields")
                      else [f.name for f in dataclasses.fields(value[0])])
            rows = [[cell(_short(getattr(v, f))) if f != "name" else f"``{getattr(v, f)}``" for f in fields]
                    for v in value]
            return [f"{len(value)} records:", ""] + list_table(list(fields), rows, cls="constant-table")
        if isinstance(value, dict):
            rows = [[f"``{k!r}``", cell(_short(v))] for k, v in value.items()]
            return [f"{len(value)} entries:", ""] + list_table(["key", "value"], rows, widths="25 75",
                                                                 cls="constant-table")
        if isinstance(value, (tuple, list, set, frozenset)):
            items = sorted(value, key=str) if isinstance(value, (set, frozenset)) else value
            return ["Value: " + ", ".join(f"``{v!r}``" for v in items), ""]
        return [f"Value: ``{value!r}``", ""]


def _drop_type_docstring(app, what, name, obj, options, lines) -> None:
    """A constant without its own ``#:`` comment would show its type's docstring (tuple's, str's):
    nothing instead. A named tuple's field shows no "Alias for field number N"."""
    text = "\n".join(lines).strip()
    if what in ("data", "attribute") and text and text == (type(obj).__doc__ or "").strip():
        lines.clear()
    elif text.startswith("Alias for field number"):
        lines.clear()


def type_aliases() -> dict[str, str]:
    """numpydoc's type links: common short forms and every public class of the package by its
    bare name (the first module listing it wins: the top level before the subpackages)."""
    import importlib
    import inspect

    aliases = {"Path": "pathlib.Path", "pathlib.Path": "pathlib.Path", "os.PathLike": "os.PathLike",
               "path-like": ":term:`python:path-like object`", "Generator": "numpy.random.Generator",
               "numpy.random.Generator": "numpy.random.Generator", "Figure": "matplotlib.figure.Figure",
               "matplotlib.figure.Figure": "matplotlib.figure.Figure", "Axes": "matplotlib.axes.Axes",
               "matplotlib.axes.Axes": "matplotlib.axes.Axes", "numpy.ndarray": "numpy.ndarray",
               "complex": ":class:`python:complex`", "object": ":class:`python:object`",
               "Mapping": "collections.abc.Mapping", "Sequence": "collections.abc.Sequence",
               "Iterable": "collections.abc.Iterable", "Callable": "collections.abc.Callable",
               "pymunk.Space": "pymunk.Space", "pymunk.Body": "pymunk.Body"}
    for module_name, _title, _what in API:
        module = importlib.import_module(module_name)
        for name in public_names(module):
            obj = getattr(module, name, None)
            if inspect.isclass(obj):
                aliases.setdefault(name, f"{module_name}.{name}")
                aliases.setdefault(f"{module_name}.{name}", f"{module_name}.{name}")
    return aliases


# -- the API reference, generated from the packages' public names ------------------------------
#: (module, title, what it holds): one page each. A module's public names are its ``__all__``, or
#: else the classes, functions and upper-case data it defines; ``asperity2d.experiments`` lists
#: every submodule it has (so a new one appears without editing this file).
API = (
    ("asperity2d", "asperity2d", "the model a user imports: scenes, runs, results, measures, pictures"),
    ("asperity2d.scene", "asperity2d.scene", "the scene's parameter records and Ooten's fixed track"),
    ("asperity2d.builders", "asperity2d.builders", "make_scene's parameter table"),
    ("asperity2d.belt", "asperity2d.belt", "masses on a moving belt: the exact event-driven solver"),
    ("asperity2d.belt.presets", "asperity2d.belt.presets", "the multi-DOF belt thesis' chains by name"),
    ("asperity2d.friction", "asperity2d.friction", "friction laws for the belt chains"),
    ("asperity2d.contact_laws", "asperity2d.contact_laws",
     "the asperity contacts' friction laws (static/kinetic, velocity weakening, viscous, rate-and-state)"),
    ("asperity2d.surface", "asperity2d.surface", "rough surfaces: profiles, statistics, asperities"),
    ("asperity2d.dynamics", "asperity2d.dynamics", "spectra, sections, cycles, Floquet, Lyapunov, basins"),
    ("asperity2d.experiments", "asperity2d.experiments", "measures and comparisons, tribometer, quasi-static runs"),
    ("asperity2d.sweep", "asperity2d.sweep", "ensembles on local processes or Dask, the resumable store"),
    ("asperity2d.renderers", "asperity2d.renderers", "pictures and sounds by file extension"),
    ("asperity2d.stats", "asperity2d.stats", "statistics on plain numbers"),
    ("asperity2d.closed_forms", "asperity2d.closed_forms", "closed-form checks of both models"),
    ("asperity2d.studies", "asperity2d.studies", "the two theses' studies as functions: what the gallery and the findings run"),
    ("asperity2d.scripting", "asperity2d.scripting", "the harness of a study script: options, output folder, summary"),
)


#: Names left out of the reference: the renderers' dispatch tables (implementation, not use).
HIDDEN = {"asperity2d.renderers": {"RENDERERS", "DRAWERS"}}
#: Submodules left out: the studies' claim records re-export asperity2d.experiments.verdicts.
HIDDEN_MODULES = {"asperity2d.studies.claims"}


def public_names(module) -> list[str]:
    import inspect

    names = getattr(module, "__all__", None)
    if names is None:
        names = [n for n, o in vars(module).items() if not n.startswith("_") and (
            ((inspect.isclass(o) or inspect.isfunction(o)) and getattr(o, "__module__", "") == module.__name__)
            or (n.isupper() and not inspect.ismodule(o)))]
    return [n for n in names if n != "__version__" and n not in HIDDEN.get(module.__name__, ())]


def write_api(app, config=None) -> None:
    """Write ``docs/api/*.rst`` (autosummary pages) from the modules' public names.

    Runs on ``config-inited``: Sphinx lists the source files before ``builder-inited``, so pages
    written later are not read on a clean checkout, and autosummary finds no stubs to generate.
    """
    import importlib
    import pkgutil

    out = DOCS / "api"
    out.mkdir(exist_ok=True)
    index = ["API reference", "=============", "",
             "Generated from the docstrings (numpydoc style) of every public name. Quantities are SI "
             "unless a docstring says otherwise.", "", ".. toctree::", "   :maxdepth: 1", ""]
    expected = set()
    for name, title, what in API:
        module = importlib.import_module(name)
        index.append(f"   {name}")
        lines = [title, "=" * len(title), "", f".. module:: {name}", "", what[0].upper() + what[1:] + ".",
                 ""]
        groups = [(name, module)]
        if name in ("asperity2d.experiments", "asperity2d.studies"):
            groups = [(f"{name}.{m.name}", importlib.import_module(f"{name}.{m.name}"))
                      for m in pkgutil.iter_modules(module.__path__) if f"{name}.{m.name}" not in HIDDEN_MODULES]
        for group_name, group in groups:
            members = [n for n in public_names(group) if not _is_submodule(group, n)]
            if group_name != name:
                # a submodule is a link target: its ``module`` directive before its heading, so the
                # anchor (module-NAME) lands on the section; after it, docutils moved it onto the
                # table that follows, whose id the theme's table wrapper drops
                lines += [f".. module:: {group_name}", "", f"``{group_name}``", "-" * (len(group_name) + 4), ""]
            first = (group.__doc__ or "").strip().split("\n\n")[0]
            if first:
                lines += [" ".join(first.split()), ""]
            if group_name == name:
                lines += [f".. currentmodule:: {group_name}", ""]
            lines += [".. autosummary::", "   :toctree: generated", "   :nosignatures:", ""]
            lines += [f"   {n}" for n in members] + [""]
            expected.update(f"{group_name}.{n}.rst" for n in members)
        _write_if_changed(out / f"{name}.rst", "\n".join(lines) + "\n")
    _write_if_changed(out / "index.rst", "\n".join(index) + "\n")
    for stale in (out / "generated").glob("*.rst"):  # a name no longer public loses its page
        if stale.name not in expected:
            stale.unlink()


def _is_submodule(module, name: str) -> bool:
    import inspect

    return inspect.ismodule(getattr(module, name, None))


def _write_if_changed(path: Path, text: str) -> None:
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


def setup(app):
    app.connect("config-inited", write_api)
    app.add_directive("parameter-table", ParameterTable)
    app.add_directive("validation-table", ValidationTable)
    app.add_directive("claims-table", ClaimsTable)
    app.add_directive("claims-summary", ClaimsSummary)
    app.add_directive("mutation-table", MutationTable)
    app.add_directive("cli-help", CliHelp)
    app.add_directive("constant-value", ConstantValue)
    app.add_role("claim-seeds", claim_seeds_role)
    app.add_directive("stick-precision-table", StickPrecisionTable)
    app.add_role("stick-figure", stick_figure_role)
    app.add_directive("measure-steps", MeasureSteps)
    app.add_directive("benchmark-tables", BenchmarkTables)
    app.connect("autodoc-process-docstring", _drop_type_docstring)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
