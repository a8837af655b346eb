"""The source documents' studies: what each claims, measured and judged.

Study code, kept apart from the model a user imports:

* :mod:`.claims` -- the one claim record every study writes to its
  ``summary.json``, and its plain-language verdict line;
* :mod:`.ooten` -- the asperity studies of E. Ooten, *Precision Motion Control at Low
  Velocities in the Presence of Friction* (senior thesis, Texas A&M, 1997-98): the two slider
  set-ups, scene sizes and the sweep run functions of the ``scenes/ooten_*`` scripts;
* :mod:`.mdof_belt` -- the belt-chain studies of the thesis *Vibration Analysis of Multi Degree
  of Freedom Self-excited Systems* (``scenes/belt_*``);
* :mod:`.rough` -- the rough-surface studies (``scenes/rough_*``): measures of
  random-height and profile scenes;
"""
