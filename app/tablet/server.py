"""The tablet's web app (starlette): the tablet page, the live view, their scripts and the
JSON, file and Server-Sent-Events endpoints, over a backend (a run, the dialogue alone, or a
finished run's replay).

Safety: every page, script and style sheet comes from this package (a fixed list read at
start, so no path from the client reaches the file system) and the Content-Security-Policy
lets the pages load nothing from elsewhere; images are served by id only
(:class:`~app.tablet.cards.FileRegistry`); request bodies are size-limited; with a token
(any host but loopback) every request must carry it, once as ``?token=`` (which sets a
cookie) and then as that cookie or an ``X-Tablet-Token`` header.
"""

from __future__ import annotations

import asyncio
import hmac
import json
from pathlib import Path
from typing import Any

from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.exceptions import HTTPException
from starlette.requests import Request
from starlette.responses import FileResponse, JSONResponse, Response, StreamingResponse
from starlette.routing import Route

from app.tablet.config import KINDS
from app.tablet.run_link import BusyError

STATIC = Path(__file__).resolve().parent / "static"
MEDIA = {".html": "text/html; charset=utf-8", ".js": "text/javascript; charset=utf-8",
         ".css": "text/css; charset=utf-8"}
CSP = ("default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self' data:; "
       "connect-src 'self'; base-uri 'none'; form-action 'none'; frame-ancestors 'none'")
COOKIE = "tablet_token"
SSE_POLL_S = 0.05      # how often a stream looks for a new snapshot
SSE_PING_S = 15.0      # a comment line keeps an idle stream open through proxies
MODES = ("auto", *KINDS)


def _assets() -> dict[str, tuple[bytes, str]]:
    """Every page, script and style sheet, read once: name -> (bytes, media type)."""
    return {p.name: (p.read_bytes(), MEDIA[p.suffix]) for p in sorted(STATIC.iterdir())
            if p.suffix in MEDIA}


class Guard:
    """ASGI middleware: the token (when set), the Host (loopback binding: loopback names
    only, against DNS rebinding), the body limit and the security headers."""

    def __init__(self, app: Any, token: str | None, max_body: int, loopback: bool) -> None:
        self.app, self.token, self.max_body, self.loopback = app, token, max_body, loopback

    async def __call__(self, scope: dict[str, Any], receive: Any, send: Any) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        request = Request(scope)
        problem = self._refuse(request)
        if problem is not None:
            await JSONResponse({"error": problem[1]}, problem[0])(scope, receive, send)
            return
        set_cookie = self.token is not None and request.query_params.get("token") == self.token

        async def headed(message: dict[str, Any]) -> None:
            if message["type"] == "http.response.start":
                headers = list(message.get("headers", []))
                headers += [(b"content-security-policy", CSP.encode()),
                            (b"x-content-type-options", b"nosniff"),
                            (b"referrer-policy", b"no-referrer"),
                            (b"cache-control", b"no-store")]
                if set_cookie:
                    headers.append((b"set-cookie", f"{COOKIE}={self.token}; Path=/; HttpOnly; "
                                                   "SameSite=Strict".encode()))
                message = {**message, "headers": headers}
            await send(message)

        await self.app(scope, self._limited(receive), headed)

    def _refuse(self, request: Request) -> tuple[int, str] | None:
        host = (request.headers.get("host") or "").rsplit(":", 1)[0].strip("[]")
        if self.loopback and host not in ("127.0.0.1", "localhost", "::1"):
            return 421, "unexpected Host"
        length = request.headers.get("content-length")
        if length is not None and (not length.isdigit() or int(length) > self.max_body):
            return 413, f"request body over {self.max_body} bytes"
        if self.token is not None:
            given = (request.query_params.get("token") or request.headers.get("x-tablet-token")
                     or request.cookies.get(COOKIE) or "")
            if not hmac.compare_digest(given.encode(), self.token.encode()):
                return 401, "a valid token is needed (printed when the server started)"
        return None

    def _limited(self, receive: Any) -> Any:
        seen = 0

        async def limited() -> dict[str, Any]:
            nonlocal seen
            message = await receive()
            seen += len(message.get("body", b""))
            if seen > self.max_body:
                raise HTTPException(413, f"request body over {self.max_body} bytes")
            return message

        return limited


async def _json_body(request: Request) -> dict[str, Any]:
    try:
        data = json.loads(await request.body())
    except (ValueError, UnicodeDecodeError):
        raise HTTPException(400, "the body must be a JSON object") from None
    if not isinstance(data, dict):
        raise HTTPException(400, "the body must be a JSON object")
    return data


def create_app(backend: Any, *, token: str | None = None, loopback: bool = True,
               stopping: Any = None) -> Any:
    """The web app over ``backend`` (:class:`~app.tablet.run_link.RunTablet`,
    :class:`~app.tablet.chat_link.ChatTablet` or :class:`~app.tablet.replay.ReplayView`).
    ``stopping``: a ``threading.Event`` that ends the event streams (server shutdown)."""
    assets = _assets()
    cfg = backend.config

    def asset(name: str) -> Response:
        body, media = assets[name]
        return Response(body, media_type=media)

    async def page(request: Request) -> Response:
        return asset("tablet.html" if request.url.path == "/" else "mind.html")

    async def static(request: Request) -> Response:
        name = request.path_params["name"]
        if name not in assets:
            raise HTTPException(404, "no such file")
        return asset(name)

    async def config(request: Request) -> Response:
        return JSONResponse({
            "kind": backend.kind, "person": cfg.person,
            "buttons": [{"kind": k, "label": cfg.buttons[k].label, "line": cfg.buttons[k].line}
                        for k in KINDS]})

    async def say(request: Request) -> Response:
        data = await _json_body(request)
        text, mode = data.get("text"), data.get("mode", "auto")
        if not isinstance(text, str) or not text.strip() or mode not in MODES:
            raise HTTPException(400, f"give a non-empty 'text' and a 'mode' of {', '.join(MODES)}")
        if not hasattr(backend, "say"):
            raise HTTPException(405, "a replay cannot be spoken to")
        try:
            return JSONResponse(await run_in_threadpool(backend.say, text, mode))
        except BusyError:
            raise HTTPException(503, "the robot is busy; try again") from None

    async def feedback(request: Request) -> Response:
        value = (await _json_body(request)).get("value")
        if value not in (1, -1) or isinstance(value, bool):
            raise HTTPException(400, "'value' must be 1 (praise) or -1 (scolding)")
        if not hasattr(backend, "feedback"):
            raise HTTPException(405, "a replay takes no feedback")
        try:
            return JSONResponse(backend.feedback(value))
        except BusyError:
            raise HTTPException(503, "the robot is busy; try again") from None

    async def replies(request: Request) -> Response:
        after = request.query_params.get("after", "0")
        if not after.isdigit():
            raise HTTPException(400, "'after' must be a reply number")
        return JSONResponse(backend.replies.after(int(after)))

    async def file(request: Request) -> Response:
        found = backend.files.get(request.path_params["file_id"]) if backend.files else None
        if found is None:
            raise HTTPException(404, "no such file")
        return FileResponse(found[0], media_type=found[1])

    async def snapshot(request: Request) -> Response:
        return Response(backend.snapshot()[1], media_type="application/json")

    async def stream(request: Request) -> Response:
        async def events() -> Any:
            last, quiet = 0, 0.0   # snapshot 0 is the empty one before the first
            while stopping is None or not stopping.is_set():
                seq, data = backend.snapshot()
                if seq != last:
                    last, quiet = seq, 0.0
                    yield b"id: %d\ndata: %s\n\n" % (seq, data)
                elif quiet >= SSE_PING_S:
                    quiet = 0.0
                    yield b": ping\n\n"
                await asyncio.sleep(SSE_POLL_S)
                quiet += SSE_POLL_S

        return StreamingResponse(events(), media_type="text/event-stream")

    async def replay_index(request: Request) -> Response:
        if not hasattr(backend, "snapshot_at"):
            raise HTTPException(404, "not a replay")
        return JSONResponse(backend.index())

    async def replay_at(request: Request) -> Response:
        if not hasattr(backend, "snapshot_at"):
            raise HTTPException(404, "not a replay")
        try:
            t = float(request.query_params.get("t", "0"))
        except ValueError:
            raise HTTPException(400, "'t' must be a number of seconds") from None
        return JSONResponse(backend.snapshot_at(t))

    routes = [Route("/", page), Route("/mind", page), Route("/static/{name}", static),
              Route("/api/config", config), Route("/api/say", say, methods=["POST"]),
              Route("/api/feedback", feedback, methods=["POST"]),
              Route("/api/replies", replies), Route("/api/file/{file_id}", file),
              Route("/api/snapshot", snapshot), Route("/api/stream", stream),
              Route("/api/replay", replay_index), Route("/api/replay/at", replay_at)]
    app = Starlette(routes=routes)
    return Guard(app, token, cfg.server.max_body_bytes, loopback)
