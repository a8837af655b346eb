"""``asperity2d explore [SCENE.toml]``: the workbench in the browser (:mod:`asperity2d.app`).

Checks the scene file and the app extra before anything starts; serves until Ctrl-C, which
stops it with one line and no traceback.
"""

from __future__ import annotations

import sys

from .. import _io
from ..errors import SceneError
from .args import PROG


def run(args) -> int:
    values = {}
    if args.scene is not None:
        path = _io.input_path("scene", args.scene)
        if path.suffix != ".toml":
            raise SceneError(f"`scene` must be a .toml scene file, got {str(path)!r}")
        from .asperity import scene_from_toml

        scene_from_toml(path)  # every problem of the file, named as `run` names it
        data = _io.read_toml("scene", path)
        settings = data.pop("run", {})
        params = data.pop("scene", data)
        from ..app.controls import texts

        values = texts(params, settings)
    try:
        import starlette  # noqa: F401
        import uvicorn  # noqa: F401
    except ImportError:
        raise SceneError('`explore` needs the app extra: pip install "asperity2d[app]"') from None
    from ..app.server import serve

    try:
        serve(port=args.port, open_browser=not args.no_browser, values=values, workers=args.workers)
    except KeyboardInterrupt:
        pass
    print(f"{PROG}: stopped", file=sys.stderr)
    return 0
