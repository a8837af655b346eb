"""The source documents' studies: what each seed claims, measured and judged.

Study code, kept apart from the model a user imports:

* :mod:`.claims` -- the one claim record every study writes to its
  ``summary.json``, and its plain-language verdict line;
* :mod:`.seed000` -- seed 000's asperity studies: the two slider set-ups,
  scene sizes and the sweep run functions of the ``scenes/seed000_*`` scripts;
* :mod:`.seed001` -- seed 001's belt-chain studies (``scenes/belt_*``);
* :mod:`.rough` -- issue 14's rough-surface studies (``scenes/rough_*``): measures of
  random-height and profile scenes;
* :mod:`.scripting` -- the plumbing every ``scenes/*.py`` script shares
  (arguments, output folder, ``summary.json``).
"""
