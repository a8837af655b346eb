"""The optional C step loop (asperity2d/engine/_kernel.c); everything else is in pyproject.toml.

The extension is optional: where it cannot be compiled (no C compiler or no Python headers) the
install goes on without it and the engine steps in Python, bit-identically and ~25 % slower
(``asperity2d.engine.kernel.KERNEL_REASON`` says which is used and why).
"""

import sys

from setuptools import Extension, setup

# -ffp-contract=off: no fused multiply-adds, so the C arithmetic rounds exactly as Python's
# (GCC contracts a * b + c by default where the target has FMA, e.g. on aarch64)
flags = [] if sys.platform == "win32" else ["-O2", "-ffp-contract=off"]
setup(ext_modules=[Extension("asperity2d.engine._kernel", ["asperity2d/engine/_kernel.c"],
                             extra_compile_args=flags, optional=True)])
