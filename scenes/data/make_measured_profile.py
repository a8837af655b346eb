"""Write ``measured_style_profile.csv``: a synthetic self-affine trace dressed as an AFM line scan.

It is NOT a measurement. Recipe (also written into the file's header):

1. ``asperity2d.surface.self_affine_profile``: 4096 points over 50 µm
   (12.2 nm spacing), Hurst exponent 0.8, rms height 0.15 µm, power between
   the wavelengths 10 µm (with a roll-off plateau below that wavenumber) and
   0.1 µm, seed 2024;
2. instrument-like errors, from ``numpy.random.default_rng(7)``: white
   Gaussian height noise of 2 nm rms, a sample tilt of 1 mrad (1 nm per µm,
   not levelled), and heights quantised to 0.1 nm;
3. x and z written in micrometres, 6 and 4 decimals.

    python scenes/data/make_measured_profile.py [-o PATH]
"""

from __future__ import annotations

import argparse
import io
import math
from pathlib import Path

import numpy as np

from asperity2d._io import atomic_write_text
from asperity2d.surface import self_affine_profile

HERE = Path(__file__).resolve().parent
FILE = HERE / "measured_style_profile.csv"
RECIPE = dict(n=4096, length=50e-6, rms_height=0.15e-6, hurst=0.8, q_min=2 * math.pi / 10e-6,
              q_max=2 * math.pi / 0.1e-6, rolloff=True, seed=2024)
NOISE_RMS, TILT, QUANTUM, NOISE_SEED = 2e-9, 1e-3, 1e-10, 7


def make() -> tuple[np.ndarray, np.ndarray]:
    """The trace (x, z) in metres, quantised as it is written."""
    clean = self_affine_profile(**RECIPE)
    rng = np.random.default_rng(NOISE_SEED)
    z = clean.z + NOISE_RMS * rng.standard_normal(clean.count) + TILT * clean.x
    return clean.x, np.round(z / QUANTUM) * QUANTUM


HEADER = """\
# SYNTHETIC, measured-style surface profile: NOT a measurement.
# Made by scenes/data/make_measured_profile.py (asperity2d):
# 1. asperity2d.surface.self_affine_profile: 4096 points over 50 um (12.2 nm spacing),
#    Hurst exponent 0.8, rms height 0.15 um, power between the wavelengths 10 um
#    (roll-off plateau below that wavenumber) and 0.1 um, seed 2024;
# 2. instrument-like errors from numpy.random.default_rng(7): white Gaussian height
#    noise of 2 nm rms, a sample tilt of 1 mrad (not levelled), heights quantised to 0.1 nm.
# Read it with asperity2d.surface.read_profile(path, unit="um"); detrend before statistics.
# unit: um
x_um,z_um
"""


def text() -> str:
    x, z = make()
    out = io.StringIO()
    out.write(HEADER)
    np.savetxt(out, np.column_stack([x * 1e6, z * 1e6]), fmt=("%.6f", "%.4f"), delimiter=",")
    return out.getvalue()


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("-o", "--output", default=str(FILE))
    atomic_write_text(p.parse_args(argv).output, text())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
