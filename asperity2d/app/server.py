"""``asperity2d explore``: the workbench as a local web app (Starlette under uvicorn).

Bound to 127.0.0.1 only. Every request must carry the session's random token (``?token=...``
in the URL, as Jupyter does; the page passes it on to its scripts and its WebSocket) and come
from the app's own origin: a request without the token, with a ``Host`` that is not the
loopback address the app listens on (DNS rebinding), or with an ``Origin`` of another site is
refused with 403 before any handler sees it -- HTTP and WebSocket alike. The page, its scripts
and styles are package data (``assets/``, and the player's); nothing is fetched from the
network. Each WebSocket is one :class:`~asperity2d.app.session.Session`; closing the tab closes
it and stops its jobs.
"""

from __future__ import annotations

import asyncio
import html
import secrets
import socket
import sys
import threading
from http.cookies import SimpleCookie
from importlib import resources
from urllib.parse import parse_qs

from ..errors import SceneError

LOOPBACK = "127.0.0.1"
#: Scripts and styles the page loads, by the name it asks for: (package, file, media type).
ASSETS = {
    "app.js": ("asperity2d.app", "app.js", "text/javascript"),
    "app.css": ("asperity2d.app", "app.css", "text/css"),
    "player.js": ("asperity2d.renderers", "player.js", "text/javascript"),
    "player.css": ("asperity2d.renderers", "player.css", "text/css"),
}
COOKIE = "asperity2d_token"


def asset(name: str) -> str:
    package, file, _ = ASSETS[name]
    return resources.files(package).joinpath("assets", file).read_text(encoding="utf-8")


class Guard:
    """ASGI middleware: the token, the Host and the Origin of every HTTP request and WebSocket,
    checked before the app sees it; anything else is a bare 403."""

    def __init__(self, app, *, token: str, hosts: set[str]):
        self.app, self.token, self.hosts = app, token, hosts

    def allowed(self, scope) -> bool:
        headers = {k.decode("latin-1").lower(): v.decode("latin-1") for k, v in scope.get("headers", [])}
        if headers.get("host", "") not in self.hosts:
            return False
        origin = headers.get("origin")
        if origin is not None and origin not in {f"http://{h}" for h in self.hosts}:
            return False
        given = parse_qs(scope.get("query_string", b"").decode("latin-1")).get("token", [""])[0]
        if not given and "cookie" in headers:
            try:
                jar = SimpleCookie(headers["cookie"])
                given = jar[COOKIE].value if COOKIE in jar else ""
            except Exception:  # noqa: BLE001 -- a malformed cookie is no token
                given = ""
        return bool(given) and secrets.compare_digest(given.encode(), self.token.encode())

    async def __call__(self, scope, receive, send):
        if scope["type"] not in ("http", "websocket") or self.allowed(scope):
            return await self.app(scope, receive, send)
        if scope["type"] == "websocket":
            await send({"type": "websocket.close", "code": 1008})  # before accept: uvicorn answers 403
            return
        await send({"type": "http.response.start", "status": 403,
                    "headers": [(b"content-type", b"text/plain; charset=utf-8")]})
        await send({"type": "http.response.body", "body": b"403 forbidden: the token or the origin is wrong\n"})


def page(token: str, title: str = "asperity2d workbench") -> str:
    """The app's HTML page: the player's and the workbench's scripts from this server."""
    q = f"?token={token}"
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><meta name="viewport" content="width=device-width, initial-scale=1">
<link rel="icon" href="data:,"><title>{html.escape(title)}</title>
<link rel="stylesheet" href="assets/player.css{q}"><link rel="stylesheet" href="assets/app.css{q}">
</head><body class="aw-page"><div id="workbench"></div>
<script src="assets/player.js{q}"></script>
<script type="module">
import app, {{ socketModel }} from "./assets/app.js{q}";
const url = new URL("ws{q}", location.href); url.protocol = location.protocol === "https:" ? "wss:" : "ws:";
app.render({{ model: socketModel(url.href), el: document.getElementById("workbench") }});
</script></body></html>"""


def create_app(*, token: str, hosts: set[str], values: dict | None = None, workers: int | None = None,
               sessions: list | None = None):
    """The Starlette app behind :class:`Guard`. ``values``: the starting scene's texts;
    ``sessions`` (a list), if given, collects every page's Session (tests watch them)."""
    from starlette.applications import Starlette
    from starlette.responses import HTMLResponse, PlainTextResponse, Response
    from starlette.routing import Route, WebSocketRoute
    from starlette.websockets import WebSocketDisconnect

    from .session import Session

    async def index(request):
        response = HTMLResponse(page(token))
        response.set_cookie(COOKIE, token, httponly=True, samesite="strict")
        response.headers["Cache-Control"] = "no-store"
        response.headers["X-Frame-Options"] = "DENY"
        return response

    async def assets(request):
        name = request.path_params["name"]
        if name not in ASSETS:
            return PlainTextResponse("404 not found\n", status_code=404)
        return Response(asset(name), media_type=ASSETS[name][2] + "; charset=utf-8",
                        headers={"Cache-Control": "no-store"})

    async def socket_endpoint(websocket):
        await websocket.accept()
        loop = asyncio.get_running_loop()
        queue: asyncio.Queue = asyncio.Queue()

        def send(text: str) -> None:  # from any thread
            loop.call_soon_threadsafe(queue.put_nowait, text)

        session = Session(send, values=values, workers=workers)
        if sessions is not None:
            sessions.append(session)

        async def pump():
            while True:
                text = await queue.get()
                await websocket.send_text(text)

        sender = asyncio.create_task(pump())
        try:
            while True:
                message = await websocket.receive()
                if message["type"] == "websocket.disconnect":
                    break
                text = message.get("text")
                if text is None:
                    continue
                await asyncio.to_thread(session.handle, text)
        except (WebSocketDisconnect, RuntimeError, ConnectionError):
            pass
        finally:
            session.close()
            sender.cancel()

    routes = [Route("/", index), Route("/assets/{name}", assets), WebSocketRoute("/ws", socket_endpoint)]
    return Guard(Starlette(routes=routes), token=token, hosts=hosts)


def bind(port: int = 0) -> socket.socket:
    """A listening TCP socket on 127.0.0.1:``port`` (0: a free one)."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind((LOOPBACK, port))
    except OSError as exc:
        sock.close()
        raise SceneError(f"`--port` {port} cannot be used on {LOOPBACK}: {exc.strerror or exc}") from None
    sock.listen(128)
    sock.set_inheritable(True)
    return sock


def serve(*, port: int = 0, open_browser: bool = True, values: dict | None = None,
          workers: int | None = None, out=None, ready=None) -> None:
    """Serve the workbench on 127.0.0.1:``port`` until Ctrl-C (or SIGTERM); print its URL (with
    the token) on one line; open the browser on it unless ``open_browser`` is False.
    ``values``: the starting scene's control texts (:func:`asperity2d.app.controls.texts`).
    ``ready(url, server)``, if given, is called once the socket listens (tests)."""
    import uvicorn

    token = secrets.token_urlsafe(24)
    sock = bind(port)
    port = sock.getsockname()[1]
    hosts = {f"{LOOPBACK}:{port}", f"localhost:{port}"}
    app = create_app(token=token, hosts=hosts, values=values, workers=workers)
    # no keepalive pings: on the loopback a closed tab closes the socket, and uvicorn's ping
    # timeout (20 s) dropped live pages whose pong waited behind a busy machine (close code 1005)
    config = uvicorn.Config(app, log_level="warning", access_log=False, ws="wsproto", lifespan="off",
                            timeout_graceful_shutdown=2, ws_ping_interval=None, ws_ping_timeout=None)
    server = uvicorn.Server(config)
    url = f"http://{LOOPBACK}:{port}/?token={token}"
    print(url, file=out or sys.stdout, flush=True)
    if open_browser:
        import webbrowser

        threading.Timer(0.5, webbrowser.open, args=(url,)).start()
    if ready is not None:
        ready(url, server)
    try:
        server.run(sockets=[sock])
    finally:
        sock.close()
