"""Serving the tablet's app with uvicorn in a thread of its own, beside a run loop or a
waiting main thread; a token is made for any host but loopback."""

from __future__ import annotations

import ipaddress
import secrets
import threading
import time
from typing import Any

import uvicorn

from app.tablet.server import create_app
from core.errors import UserError

START_TIMEOUT_S = 10.0


def is_loopback(host: str) -> bool:
    """Whether ``host`` is a loopback address or ``localhost``."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


class TabletServer:
    """The app over ``backend`` on ``host:port`` (port 0: a free one), in a daemon thread.
    Use as a context manager, or :meth:`start` and :meth:`stop`."""

    def __init__(self, backend: Any, host: str, port: int) -> None:
        self.host = host
        self.token = None if is_loopback(host) else secrets.token_urlsafe(16)
        self.stopping = threading.Event()
        app = create_app(backend, token=self.token, loopback=is_loopback(host),
                         stopping=self.stopping)
        self._server = uvicorn.Server(uvicorn.Config(
            app, host=host, port=port, log_level="warning", access_log=False,
            timeout_graceful_shutdown=2, lifespan="off"))
        self._thread = threading.Thread(target=self._server.run, name="tablet-server",
                                        daemon=True)

    @property
    def port(self) -> int:
        """The port actually bound (after :meth:`start`)."""
        return self._server.servers[0].sockets[0].getsockname()[1]

    @property
    def url(self) -> str:
        """The tablet page's address (with the token, when one is needed)."""
        host = f"[{self.host}]" if ":" in self.host else self.host
        query = f"?token={self.token}" if self.token else ""
        return f"http://{host}:{self.port}/{query}"

    def start(self) -> TabletServer:
        """Start serving; a port that cannot be bound is a :class:`UserError`."""
        self._thread.start()
        deadline = time.monotonic() + START_TIMEOUT_S
        while not self._server.started:
            if not self._thread.is_alive() or time.monotonic() > deadline:
                raise UserError(f"the tablet cannot serve on {self.host} (port in use, or "
                                "an address this machine does not have)")
            time.sleep(0.02)
        return self

    def stop(self) -> None:
        """End the event streams and the server."""
        self.stopping.set()
        self._server.should_exit = True
        self._thread.join(timeout=5)

    def __enter__(self) -> TabletServer:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()
