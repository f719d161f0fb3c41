"""A headless Chromium driven over the DevTools protocol, for the tests of `a2b view`.

The protocol runs over a pipe (``--remote-debugging-pipe``: commands into file descriptor 3,
answers and events out of 4, each a JSON text ended by a NUL byte), so nothing but the
standard library is needed. Not a test module.
"""

from __future__ import annotations

import base64
import json
import os
import shutil
import subprocess
import tempfile
import time

#: The names Debian and others give the browser.
NAMES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")


def find() -> str | None:
    return next((path for path in map(shutil.which, NAMES) if path), None)


def _wire(to_browser: int, from_browser: int):
    """In the child before exec: the pipe ends onto descriptors 3 and 4, through copies above
    both, so that neither is closed by the other's move."""
    import fcntl

    def wire():
        ends = [fcntl.fcntl(fd, fcntl.F_DUPFD, 100) for fd in (to_browser, from_browser)]
        for target, fd in zip((3, 4), ends):
            os.dup2(fd, target)

    return wire


class Chromium:
    """One headless browser with one page: :meth:`open`, :meth:`evaluate`, :meth:`click`,
    :meth:`screenshot`. ``events`` keeps every protocol event of the page."""

    def __init__(self, exe: str, width: int = 1600, height: int = 900):
        self.profile = tempfile.mkdtemp(prefix="a2b-chromium-")
        to_browser, self._commands = os.pipe()
        self._answers, from_browser = os.pipe()
        args = [
            exe, "--headless=new", "--remote-debugging-pipe", "--no-sandbox", "--no-first-run",
            "--no-default-browser-check", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
            f"--user-data-dir={self.profile}", f"--window-size={width},{height}",
            "--proxy-server=127.0.0.1:9",  # the network is off: any request would fail
        ]  # fmt: skip
        self._log = open(os.environ.get("A2B_CHROMIUM_LOG", os.devnull), "wb")  # noqa: SIM115
        self.process = subprocess.Popen(
            args, pass_fds=(3, 4), preexec_fn=_wire(to_browser, from_browser),
            stdout=subprocess.DEVNULL, stderr=self._log,
        )  # fmt: skip
        os.close(to_browser)
        os.close(from_browser)
        self._buffer = b""
        self._id = 0
        self.events: list[dict] = []
        target = self.send("Target.createTarget", url="about:blank")["targetId"]
        self.session = self.send("Target.attachToTarget", targetId=target, flatten=True)[
            "sessionId"
        ]
        for domain in ("Page", "Runtime", "Log", "Network"):
            self.send(f"{domain}.enable", session=True)
        self.send("Emulation.setDeviceMetricsOverride", session=True, width=width,
                  height=height, deviceScaleFactor=1, mobile=False)  # fmt: skip

    def _read(self, timeout: float) -> dict:
        deadline = time.monotonic() + timeout
        while b"\0" not in self._buffer:
            if time.monotonic() > deadline:
                raise TimeoutError("the browser did not answer")
            chunk = os.read(self._answers, 1 << 20)
            if not chunk:
                raise RuntimeError("the browser closed its pipe")
            self._buffer += chunk
        message, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(message)

    def send(self, method: str, session: bool = False, timeout: float = 60, **params):
        """Send a command and return its result; events that come first are kept."""
        self._id += 1
        message = {"id": self._id, "method": method, "params": params}
        if session:
            message["sessionId"] = self.session
        os.write(self._commands, json.dumps(message).encode() + b"\0")
        while True:
            answer = self._read(timeout)
            if answer.get("id") == self._id:
                if "error" in answer:
                    raise RuntimeError(f"{method}: {answer['error']}")
                return answer.get("result", {})
            self.events.append(answer)

    def evaluate(self, expression: str):
        """The value of a JavaScript expression in the page (promises are awaited)."""
        result = self.send("Runtime.evaluate", session=True, expression=expression,
                           awaitPromise=True, returnByValue=True)  # fmt: skip
        if "exceptionDetails" in result:
            raise RuntimeError(f"{expression}: {result['exceptionDetails']}")
        return result["result"].get("value")

    def open(self, url: str, ready: str, timeout: float = 60) -> None:
        """Load ``url`` and wait until the expression ``ready`` is true."""
        self.send("Page.navigate", session=True, url=url)
        deadline = time.monotonic() + timeout
        while not self.evaluate(ready):
            if time.monotonic() > deadline:
                raise TimeoutError(f"{url} was not ready after {timeout} s")
            time.sleep(0.1)

    def click(self, x: float, y: float) -> None:
        for kind in ("mousePressed", "mouseReleased"):
            self.send("Input.dispatchMouseEvent", session=True, type=kind, x=x, y=y,
                      button="left", clickCount=1)  # fmt: skip

    def screenshot(self) -> bytes:
        return base64.b64decode(self.send("Page.captureScreenshot", session=True)["data"])

    def problems(self) -> list[str]:
        """The page's console errors and uncaught exceptions."""
        found = []
        for event in self.events:
            method, params = event.get("method"), event.get("params", {})
            if method == "Runtime.exceptionThrown":
                found.append(str(params.get("exceptionDetails", {}).get("text")))
            elif method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
                found.append(" ".join(str(a.get("value")) for a in params.get("args", [])))
            elif method == "Log.entryAdded" and params.get("entry", {}).get("level") == "error":
                found.append(str(params["entry"].get("text")))
        return found

    def requests(self) -> list[str]:
        """The URLs the page asked for."""
        return [event["params"]["request"]["url"] for event in self.events
                if event.get("method") == "Network.requestWillBeSent"]  # fmt: skip

    def close(self) -> None:
        try:
            self.send("Browser.close", timeout=10)
        except (RuntimeError, TimeoutError, OSError):
            pass
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
        os.close(self._commands)
        os.close(self._answers)
        self._log.close()
        shutil.rmtree(self.profile, ignore_errors=True)
