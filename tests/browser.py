"""A headless Chromium driven over the DevTools protocol through a pipe
(``--remote-debugging-pipe``: commands on fd 3, replies on fd 4, each message JSON
ended by a NUL byte): no port, no websocket, no package beyond the standard library.

    with Browser() as browser:
        page = browser.open("file:///tmp/report.html")
        page.evaluate("document.title")
        page.screenshot("test-artifacts/report.png")
        page.console_errors, page.requests   # what the page logged and asked for

Debian's ``chromium`` package (``make test`` installs it when missing).
"""

from __future__ import annotations

import base64
import json
import os
import queue
import shutil
import subprocess
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

__all__ = ["Browser", "BrowserError", "Page", "find_chromium", "pages_draw_without_errors"]

_CANDIDATES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")


class BrowserError(RuntimeError):
    """The browser could not be started, or a command failed or timed out."""


def find_chromium() -> str | None:
    """The Chromium executable: $CHROMIUM, else the first of chromium, chromium-browser,
    google-chrome on PATH; None when there is none."""
    given = os.environ.get("CHROMIUM")
    if given:
        return given
    for name in _CANDIDATES:
        path = shutil.which(name)
        if path:
            return path
    return None


PATIENCE = 300.0
"""Seconds before a wait gives up: only a hung browser takes this long, never a slow or
loaded machine (every wait here is for an event or a condition, none for a time)."""


class Browser:
    """One headless Chromium process; pages are tabs of it."""

    def __init__(self, executable: str | None = None, timeout: float = PATIENCE) -> None:
        exe = executable or find_chromium()
        if exe is None:
            raise BrowserError("no Chromium found (apt-get install chromium, or set $CHROMIUM)")
        self.timeout = timeout
        self._profile = tempfile.mkdtemp(prefix="jointgap-chromium-")
        to_browser_r, self._to_browser = os.pipe()
        self._from_browser, from_browser_w = os.pipe()

        def child_fds() -> None:  # runs in the child: the pipe ends become fds 3 and 4
            read_end, write_end = os.dup(to_browser_r), os.dup(from_browser_w)
            os.dup2(read_end, 3)  # dup2 leaves the copies inheritable: they survive exec
            os.dup2(write_end, 4)

        args = [
            exe,
            "--headless",
            "--remote-debugging-pipe",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-dev-shm-usage",
            "--disable-extensions",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            "--no-default-browser-check",
            "--mute-audio",
            f"--user-data-dir={self._profile}",
            "about:blank",
        ]
        self._process = subprocess.Popen(
            args,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            close_fds=False,  # Python's own descriptors are close-on-exec anyway
            preexec_fn=child_fds,  # the reader thread starts after this
        )
        os.close(to_browser_r)
        os.close(from_browser_w)
        self._next_id = 0
        self._replies: dict[int, queue.Queue[dict[str, Any]]] = {}
        self._events: dict[str | None, list[dict[str, Any]]] = {}
        self._lock = threading.Lock()
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()
        self.send("Target.setDiscoverTargets", {"discover": False})

    # ------------------------------------------------------------------ protocol

    def _read(self) -> None:
        buffer = b""
        while True:
            try:
                chunk = os.read(self._from_browser, 1 << 16)
            except OSError:
                return
            if not chunk:
                return
            buffer += chunk
            while b"\0" in buffer:
                raw, buffer = buffer.split(b"\0", 1)
                message = json.loads(raw)
                if "id" in message:
                    with self._lock:
                        box = self._replies.get(message["id"])
                    if box is not None:
                        box.put(message)
                else:
                    with self._lock:
                        self._events.setdefault(message.get("sessionId"), []).append(message)

    def send(
        self, method: str, params: dict[str, Any] | None = None, session: str | None = None
    ) -> Any:
        """Sends one command and waits for its result; BrowserError on an error reply."""
        with self._lock:
            self._next_id += 1
            ident = self._next_id
            box: queue.Queue[dict[str, Any]] = queue.Queue()
            self._replies[ident] = box
        message: dict[str, Any] = {"id": ident, "method": method, "params": params or {}}
        if session is not None:
            message["sessionId"] = session
        os.write(self._to_browser, json.dumps(message).encode() + b"\0")
        try:
            reply = box.get(timeout=self.timeout)
        except queue.Empty:
            raise BrowserError(f"{method}: no reply in {self.timeout:g} s") from None
        finally:
            with self._lock:
                self._replies.pop(ident, None)
        if "error" in reply:
            raise BrowserError(f"{method}: {reply['error'].get('message', reply['error'])}")
        return reply.get("result", {})

    def events(self, session: str | None) -> list[dict[str, Any]]:
        """The events received so far for a session (a copy)."""
        with self._lock:
            return list(self._events.get(session, []))

    # ------------------------------------------------------------------ pages

    def open(self, url: str, width: int = 1400, height: int = 1000) -> Page:
        """A new tab showing ``url``, with console, log and network events recorded from
        before the navigation; returns when the load event has fired."""
        target = self.send("Target.createTarget", {"url": "about:blank"})["targetId"]
        session = self.send("Target.attachToTarget", {"targetId": target, "flatten": True})[
            "sessionId"
        ]
        page = Page(self, session, target)
        for domain in ("Page", "Runtime", "Log", "Network"):
            page.send(f"{domain}.enable")
        page.send(
            "Emulation.setDeviceMetricsOverride",
            {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False},
        )
        page.send("Page.navigate", {"url": url})
        page.wait_for_event("Page.loadEventFired")
        return page

    def close(self) -> None:
        try:
            self.send("Browser.close")
        except (BrowserError, OSError):
            pass
        try:
            self._process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self._process.kill()
            self._process.wait()
        for fd in (self._to_browser, self._from_browser):
            try:
                os.close(fd)
            except OSError:
                pass
        shutil.rmtree(self._profile, ignore_errors=True)

    def __enter__(self) -> Browser:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class Page:
    """One tab: evaluate JavaScript, take screenshots, read what it logged."""

    def __init__(self, browser: Browser, session: str, target: str) -> None:
        self.browser = browser
        self.session = session
        self.target = target

    def send(self, method: str, params: dict[str, Any] | None = None) -> Any:
        return self.browser.send(method, params, self.session)

    def wait_for_event(self, method: str, timeout: float | None = None) -> dict[str, Any]:
        deadline = time.monotonic() + (timeout or self.browser.timeout)
        while time.monotonic() < deadline:
            for event in self.browser.events(self.session):
                if event["method"] == method:
                    return event
            time.sleep(0.02)
        raise BrowserError(f"no {method} within {timeout or self.browser.timeout:g} s")

    def evaluate(self, expression: str) -> Any:
        """The value of a JavaScript expression (awaited when it is a promise);
        BrowserError when it throws."""
        reply = self.send(
            "Runtime.evaluate",
            {"expression": expression, "returnByValue": True, "awaitPromise": True},
        )
        if "exceptionDetails" in reply:
            details = reply["exceptionDetails"]
            text = details.get("exception", {}).get("description") or details.get("text")
            raise BrowserError(f"{expression[:80]}: {text}")
        return reply["result"].get("value")

    def wait_for(self, expression: str, timeout: float = PATIENCE) -> Any:
        """Polls an expression until it is truthy; returns its value."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            value = self.evaluate(expression)
            if value:
                return value
            time.sleep(0.05)
        raise BrowserError(f"'{expression}' still false after {timeout:g} s")

    def wait_for_console_error(self, timeout: float = PATIENCE) -> list[str]:
        """Waits until the page has logged an error; returns the errors."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if errors := self.console_errors:
                return errors
            time.sleep(0.02)
        raise BrowserError(f"no console error within {timeout:g} s")

    def animation_frames(self, count: int) -> None:
        """Returns after ``count`` animation frames of the page have run."""
        self.evaluate(
            "new Promise(done => { let n = "
            f"{count}; const next = () => (--n > 0 ? requestAnimationFrame(next) : done(0));"
            " requestAnimationFrame(next); })"
        )

    def screenshot(self, path: str | Path, full_page: bool = True) -> Path:
        """Saves a PNG of the page (the whole page by default)."""
        params: dict[str, Any] = {"format": "png", "captureBeyondViewport": full_page}
        if full_page:
            metrics = self.send("Page.getLayoutMetrics")
            size = metrics.get("cssContentSize") or metrics["contentSize"]
            params["clip"] = {
                "x": 0,
                "y": 0,
                "width": size["width"],
                "height": size["height"],
                "scale": 1,
            }
        data = self.send("Page.captureScreenshot", params)["data"]
        out = Path(path)
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_bytes(base64.b64decode(data))
        return out

    @property
    def console_errors(self) -> list[str]:
        """Console errors, uncaught exceptions and error log entries, as text."""
        out = []
        for e in self.browser.events(self.session):
            p = e.get("params", {})
            if e["method"] == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
                out.append(
                    " ".join(
                        str(a.get("value", a.get("description", ""))) for a in p.get("args", [])
                    )
                )
            elif e["method"] == "Runtime.exceptionThrown":
                d = p.get("exceptionDetails", {})
                out.append(d.get("exception", {}).get("description") or d.get("text", "exception"))
            elif e["method"] == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
                out.append(p["entry"].get("text", "log error"))
        return out

    @property
    def requests(self) -> list[str]:
        """The URL of every request the page made, in order."""
        return [
            e["params"]["request"]["url"]
            for e in self.browser.events(self.session)
            if e["method"] == "Network.requestWillBeSent"
        ]

    def close(self) -> None:
        self.browser.send("Target.closeTarget", {"targetId": self.target})


def pages_draw_without_errors(pages: dict[str, Path]) -> None:
    """Opens each report page (label -> file), waits until it has drawn itself, moves its
    animation to frame 50 and asserts that no script logged an error. Skips the test
    without Chromium, unless ``JOINTGAP_REQUIRE_BROWSER=1`` makes that a failure."""
    import pytest

    if find_chromium() is None:
        message = "no Chromium: apt-get install chromium (make test does)"
        if os.environ.get("JOINTGAP_REQUIRE_BROWSER") == "1":
            pytest.fail(message)
        pytest.skip(message)
    slide = (
        "(() => { const s = document.getElementById('time-slider'); s.value = '50';"
        " s.dispatchEvent(new Event('input')); return s.value; })()"
    )
    with Browser() as browser:
        for label, path in pages.items():
            page = browser.open(path.as_uri())
            page.wait_for("document.body.dataset.ready === 'true'")
            assert page.evaluate(slide) == "50", label
            assert page.console_errors == [], label
            page.close()
