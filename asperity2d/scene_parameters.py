"""The scene's parameter records: every keyword of :func:`asperity2d.make_scene` and a TOML
scene with its default, SI unit and meaning (:class:`Parameter`), and Ooten's fixed track, the
defaults of the scene dataclasses (:data:`OOTEN_PARAMETERS`, :data:`OOTEN_DEFAULTS`).
``asperity2d.scene`` re-exports every name here.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Parameter:
    """One keyword of :func:`asperity2d.make_scene`: its default, SI unit and meaning.

    The records are the single source of the defaults: :data:`OOTEN_DEFAULTS`
    and :data:`asperity2d.builders.DEFAULTS` are built from them, and the
    documentation's parameter table is generated from them.

    Parameters
    ----------
    name : str
        The keyword, as ``make_scene`` and a TOML scene spell it.
    default : object
        Its default value (``None``: derived from other parameters, as
        ``meaning`` says).
    unit : str
        The SI unit of the value; ``"1"`` for a pure number, ``"-"`` for a
        choice, a text, a flag or a file.
    meaning : str
        What it is, in a sentence.
    """

    name: str
    default: object
    unit: str
    meaning: str


#: Ooten's fixed track: the Working Model set-up of E. Ooten's thesis (*Precision Motion Control
#: at Low Velocities in the Presence of Friction*, Texas A&M, 1997-98; its figures 5-8 and Table
#: 1): 45° full triangles on a 1 µm base, steel asperity mass and stiffness, lightly damped
#: tracks (figure 8), the slider on a fixed-height horizontal track ("the top surface was
#: constrained to move on a horizontal track") with its tips a quarter of the asperity height
#: into the lower surface, pulled through a spring. The drive speed is the quasi-static limit at
#: this scale (see :mod:`asperity2d.experiments.quasistatic`). These are the defaults of the
#: scene's dataclasses and of :func:`asperity2d.make_scene`.
OOTEN_PARAMETERS = (
    Parameter("base", 1e-6, "m", "base width of every triangular asperity (Ooten's Table 1)"),
    Parameter("flank_angle", 45.0, "°", "flank angle of the triangles above the horizontal "
              "(sets their height on the given base; give `height` instead to set it directly)"),
    Parameter("lower_count", 16, "1", "number of lower asperities, each on its own vertical "
              "spring-damper track"),
    Parameter("upper_count", 4, "1", "number of asperities (tips) the slider carries"),
    Parameter("pitch", 1.25e-6, "m", "centre-to-centre spacing of the asperities on both surfaces "
              "(the mean spacing when random)"),
    Parameter("mass", 2.88e-16, "kg", "mass of each lower asperity (Ooten's Table 1, steel); one "
              "value or one per asperity"),
    Parameter("stiffness", 37_200.0, "N/m", "stiffness of each lower asperity's vertical track "
              "spring (Ooten's Table 1, steel); one value or one per asperity"),
    Parameter("damping_ratio", 0.1, "1", "damping of each lower track as a fraction of its "
              "critical damping 2√(k m) (Ooten's figure 8 dampers)"),
    Parameter("slider_mass", 2.88e-15, "kg", "mass of the slider with all its tips"),
    Parameter("track", "fixed", "-", '"fixed": the slider runs at a fixed height (Ooten\'s fixed '
              'track); "free": it rides the surface pressed down by `normal_load` (the free slider '
              'under a load)'),
    Parameter("normal_load", 0.01, "N", "downward load on the slider (used with `track=\"free\"`)"),
    Parameter("mu_static", 0.3, "1", "static friction coefficient of every asperity contact"),
    Parameter("drive_stiffness", 3_720.0, "N/m", "stiffness of the drive spring (spring drive)"),
    Parameter("drive_velocity", 20.0, "m/s", "speed of the drive spring's far end (spring drive): "
              "1.8e-3 of ω × base, the quasi-static limit at this scale"),
    Parameter("drive_force", 0.02, "N", "the constant horizontal force on the slider "
              '(`drive="force"`)'),
)
#: Ooten's fixed track as a dict: parameter name -> default (from :data:`OOTEN_PARAMETERS`).
OOTEN_DEFAULTS = {p.name: p.default for p in OOTEN_PARAMETERS}


def kinetic_default(mu_static: float) -> float:
    """The default kinetic coefficient: two thirds of the static one (0.2 for 0.3)."""
    return float(f"{2.0 * mu_static / 3.0:.12g}")
