"""Rough surfaces in 1-D: profiles, their statistics, and the asperities they hold.

Data flow (all SI)::

    self_affine_profile / gaussian_profile / read_profile  ->  SurfaceProfile (x, z)
        rms_height, rms_slope, power_spectrum -> PowerSpectrum, fit_hurst -> HurstFit
        find_asperities -> Asperities (one frozen record per surface: centres, heights,
                                       flank runs, base levels, stiffness, mass)
        (pictures of them: asperity2d.renderers.surface.plot_asperities, plot_spectrum)
    random_heights, fraction_above          (random summit heights for a scene)
    make_scene(lower_surface=..., upper_surface=..., height_std=...)
        -> source.surface_asperities -> source.surface_spec: the scene's per-asperity
           Shapes, tip positions and rigid valley floor (asperity2d.shapes)

Modules: :mod:`.profile` (record and generators), :mod:`.read` (text traces;
instrument files through the optional SurfaceTopography), :mod:`.stats`,
:mod:`.asperities` (the summit-to-triangle rule), :mod:`.heights`,
:mod:`.source` (a profile, arrays or file as a scene surface). The plots are
:mod:`asperity2d.renderers.surface`'s (renderers sit above the model).
"""

from .asperities import Asperities, find_asperities, pyramid_mass, table1_stiffness
from .heights import fraction_above, random_heights
from .profile import SurfaceProfile, gaussian_profile, self_affine_profile
from .read import read_profile
from .stats import HurstFit, PowerSpectrum, fit_hurst, power_spectrum, rms_height, rms_slope


__all__ = [
    "SurfaceProfile", "self_affine_profile", "gaussian_profile", "read_profile", "rms_height",
    "rms_slope", "PowerSpectrum", "power_spectrum", "HurstFit", "fit_hurst", "Asperities",
    "find_asperities", "table1_stiffness", "pyramid_mass", "random_heights", "fraction_above",
]
