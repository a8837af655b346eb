"""The belt guide's squeal example shows the squeal: steady sliding above the flutter onset is an
unstable equilibrium, so a run started exactly on it stays there (0 separations); the guide kicks
it, as scenes/belt_contact.py does, and the contact opens."""

import re
from pathlib import Path

from asperity2d.belt import simulate_chain
from asperity2d.belt.contact.minimal import MinimalModel

GUIDE = Path(__file__).resolve().parents[1] / "docs" / "guide" / "belt.md"


def test_the_guides_squeal_example_separates():
    line = next(ln for ln in GUIDE.read_text().splitlines() if ln.startswith("squeal = simulate_chain("))
    namespace = {"simulate_chain": simulate_chain, "mm": MinimalModel(eta=300.0)}
    exec(line, namespace)  # the guide's own line, as printed on the page
    squeal = namespace["squeal"]
    assert len(squeal.separation_intervals[0]) >= 10  # a limit cycle of openings, not one bounce
    # without the kick the same call stays on the unstable steady sliding: the kick is what matters
    call = re.search(r"mm\.chain\((.*?)\)\)", line).group(1)
    assert "kick=" in call
    unkicked = simulate_chain(**namespace["mm"].chain(mu=0.5, v_belt=5.0, t_end=0.05))
    assert len(unkicked.separation_intervals[0]) == 0
