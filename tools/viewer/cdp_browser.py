"""Headless Chromium driven over its DevTools protocol (a WebSocket of JSON calls; python3-websocket), for
hadal-viewer's browser test (tests/integration/viewer_test.py) and its screenshot in docs/viewer.md (screenshot.py)."""

import base64
import itertools
import json
import os
import shutil
import subprocess
import time
import urllib.request

import websocket

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"


def wait_until(condition, timeout_s=60.0, what="condition"):
    deadline = time.monotonic() + timeout_s
    while True:
        value = condition()
        if value:
            return value
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(0.1)


class Browser:
    """Headless Chromium with one page, driven over the DevTools protocol (a WebSocket of JSON calls)."""

    def __init__(self, profile_dir):
        # The flags this machine's Chromium needs headless (no GPU: WebGL on SwiftShader; no background
        # traffic on a closed network).
        self.process = subprocess.Popen(
            [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
             "--enable-unsafe-swiftshader", "--disable-quic", "--no-first-run", "--disable-background-networking",
             "--disable-component-update", "--disable-sync", f"--user-data-dir={profile_dir}",
             "--window-size=1400,850", "--remote-debugging-port=0", "--remote-allow-origins=*", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        port_file = os.path.join(profile_dir, "DevToolsActivePort")
        wait_until(lambda: os.path.exists(port_file) and open(port_file).read().strip(), 30, "Chromium's DevTools port")
        port = int(open(port_file).read().split()[0])
        targets = json.load(urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list"))
        page = next(t for t in targets if t["type"] == "page")
        self.socket = websocket.create_connection(page["webSocketDebuggerUrl"], timeout=60)
        self.ids = itertools.count(1)
        self.console = []
        self.load_events = 0  # the page's load events so far (Page.loadEventFired)
        self.call("Runtime.enable")
        self.call("Page.enable")

    def call(self, method, **params):
        call_id = next(self.ids)
        self.socket.send(json.dumps({"id": call_id, "method": method, "params": params}))
        while True:
            message = self._next()
            if message.get("id") == call_id:
                assert "error" not in message, message["error"]
                return message["result"]

    def _next(self):
        """The next message from Chromium, its events noted (console lines, exceptions, load events)."""
        message = json.loads(self.socket.recv())
        if message.get("method") == "Runtime.exceptionThrown":
            self.console.append(message["params"]["exceptionDetails"].get("exception", {}).get("description"))
        elif message.get("method") == "Runtime.consoleAPICalled":
            self.console.append(" ".join(str(a.get("value")) for a in message["params"]["args"]))
        elif message.get("method") == "Page.loadEventFired":
            self.load_events += 1
        return message

    def evaluate(self, expression):
        result = self.call("Runtime.evaluate", expression=expression, returnByValue=True)
        assert "exceptionDetails" not in result, result["exceptionDetails"]
        return result["result"].get("value")

    def open(self, url):
        self.call("Page.navigate", url=url)
        wait_until(lambda: self.evaluate("typeof window.hadalViewer === 'object'"), 30, "the page's script")

    def load(self, url, timeout_s=60.0):
        """Navigates to url and returns when the page's load event has fired (what a one-shot screenshot shows)."""
        before = self.load_events
        self.call("Page.navigate", url=url)
        self.socket.settimeout(timeout_s)
        try:
            while self.load_events == before:
                self._next()
        finally:
            self.socket.settimeout(60)

    def screenshot(self, path):
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        data = self.call("Page.captureScreenshot", format="png")["data"]
        with open(path, "wb") as f:
            f.write(base64.b64decode(data))
        return path

    def close(self):
        self.socket.close()
        self.process.terminate()
        self.process.wait(timeout=30)
