"""Headless Chromium driven over the DevTools protocol, for tests of pages served here.

Chromium from the system (Debian's package ``chromium``: ``.ci/run`` installs it), started with the
flags a closed machine needs (no background networking, no sandbox as root) and SwiftShader for
WebGL, so that a WebGL page (the Rerun web viewer) renders without a GPU. The protocol is spoken
over a WebSocket with tornado's client (a dependency of Dask's distributed, no new package).
"""

from __future__ import annotations

import asyncio
import base64
import contextlib
import io
import json
import os
import shutil
import signal
import socket
import subprocess
import tempfile
import time
import urllib.request
from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np

#: The browser programs tried, in order.
BROWSERS = ("chromium", "chromium-browser", "google-chrome")


def browser() -> str | None:
    """The Chromium program on PATH, or None."""
    return next((path for name in BROWSERS if (path := shutil.which(name))), None)


def free_port() -> int:
    """A TCP port nothing listens on now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


class Page:
    """One tab over one DevTools connection: navigate to a URL, take screenshots as arrays."""

    def __init__(self, debugger_url: str):
        from tornado.websocket import websocket_connect

        self._loop = asyncio.new_event_loop()
        self._id = 0

        async def connect():  # in this loop: tornado binds the connection to the running one
            return await websocket_connect(debugger_url, max_message_size=256 * 2**20)

        self._ws = self._loop.run_until_complete(connect())
        self._call("Page.enable")

    def _call(self, method: str, **params) -> dict:
        """The result of one DevTools command (its error raised as RuntimeError)."""
        self._id += 1
        ident = self._id

        async def exchange() -> dict:
            await self._ws.write_message(json.dumps({"id": ident, "method": method,
                                                     "params": params}))  # fmt: skip
            while True:
                message = await self._ws.read_message()
                if message is None:
                    raise RuntimeError(f"{method}: the browser closed the connection")
                answer = json.loads(message)
                if answer.get("id") == ident:
                    return answer

        answer = self._loop.run_until_complete(exchange())
        if "error" in answer:
            raise RuntimeError(f"{method}: {answer['error']}")
        return answer["result"]

    def navigate(self, url: str) -> None:
        """Open ``url`` in the tab."""
        self._call("Page.navigate", url=url)

    def screenshot(self) -> np.ndarray:
        """The tab as it is drawn now: (height, width, 3) floats in [0, 1]."""
        import matplotlib.image

        for attempt in range(100):  # a page that swaps its renderer while it loads: try again
            try:
                shot = self._call("Page.captureScreenshot", format="png")
                break
            except RuntimeError as err:
                if "Not attached" not in str(err) or attempt == 99:
                    raise
                time.sleep(0.2)
        return matplotlib.image.imread(io.BytesIO(base64.b64decode(shot["data"])))[..., :3]

    def close(self) -> None:
        """Close the connection and its event loop."""
        self._ws.close()
        self._loop.run_until_complete(asyncio.sleep(0.1))  # the close handshake
        self._loop.close()


@contextmanager
def chromium(width: int = 1400, height: int = 900) -> Iterator[Page]:
    """A headless Chromium with one tab, closed on exit."""
    program = browser()
    if program is None:
        raise FileNotFoundError("no Chromium on PATH (apt-get install chromium)")
    port = free_port()
    # Chromium's helpers (renderer, GPU, crash handler) outlive its main process for a moment
    # and still write to the profile: the whole process group is stopped, and a file they add
    # while the profile is removed does not fail the test.
    with tempfile.TemporaryDirectory(ignore_cleanup_errors=True) as profile:
        process = subprocess.Popen(
            [program, "--headless", "--no-sandbox", "--use-angle=swiftshader",
             "--enable-unsafe-swiftshader", "--disable-quic", "--no-first-run",
             "--disable-background-networking", "--disable-component-update", "--disable-sync",
             f"--user-data-dir={profile}", f"--window-size={width},{height}",
             f"--remote-debugging-port={port}", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True,
        )  # fmt: skip
        try:
            deadline = time.monotonic() + 30.0
            while True:
                try:
                    with urllib.request.urlopen(f"http://127.0.0.1:{port}/json") as answer:
                        targets = json.load(answer)
                    break
                except OSError:
                    if time.monotonic() > deadline or process.poll() is not None:
                        raise
                    time.sleep(0.2)
            tab = Page(next(t for t in targets if t["type"] == "page")["webSocketDebuggerUrl"])
            try:
                yield tab
            finally:
                tab.close()
        finally:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(process.pid, signal.SIGTERM)
            process.wait(timeout=30)
