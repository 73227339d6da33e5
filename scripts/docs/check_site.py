#!/usr/bin/env python3
"""Open every page of the built site in a real browser and check that nothing is broken.

    python scripts/docs/check_site.py target/site [--chromium chromium]

Serves the site on 127.0.0.1 (a free port, `http.server` in a thread), starts headless Chromium
with the DevTools protocol on loopback, and for every HTML page of the site:
* navigates to it and waits for its `load` event; the page must answer HTTP 200, no script may
  throw and no request (of any host: the site is read offline) may fail;
* every <img> must have loaded (`complete` and `naturalWidth > 0`);
* every internal link (same host: `href`, and `src` of scripts and images) must answer HTTP 200,
  and a link's `#fragment` must name an element of its target page.
Prints one line per page and exits 1 listing every problem. Needs `websocket-client`
(python/requirements-docs.txt) and Chromium (Debian's package `chromium`).
"""

from __future__ import annotations

import argparse
import functools
import html.parser
import http.server
import json
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import urllib.error
import urllib.parse
import urllib.request
from pathlib import Path
from typing import Any

import websocket  # websocket-client

PAGE_TIMEOUT = 120.0  # a hang guard: CI loads the pages beside the other test jobs on two cores

COLLECT = """(() => {
  const imgs = Array.from(document.images).map(i => ({src: i.currentSrc || i.src, ok: i.complete && i.naturalWidth > 0}));
  const links = Array.from(document.querySelectorAll('a[href]')).map(a => a.href);
  const srcs = Array.from(document.querySelectorAll('script[src], link[rel=stylesheet][href]'))
    .map(e => e.src || e.href);
  return JSON.stringify({title: document.title, imgs, links, srcs,
                         body: document.body ? document.body.innerText.length : 0});
})()"""


class Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args: Any) -> None:  # noqa: D102 - no access log on stderr
        pass


class Ids(html.parser.HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.ids: set[str] = set()

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        for k, v in attrs:
            if k in ("id", "name") and v:
                self.ids.add(v)


class DevTools:
    """A minimal DevTools-protocol session on one page target."""

    def __init__(self, ws_url: str) -> None:
        self.ws = websocket.create_connection(ws_url, timeout=PAGE_TIMEOUT, suppress_origin=True)
        self.next_id = 0
        self.events: list[dict[str, Any]] = []

    def call(self, method: str, **params: Any) -> dict[str, Any]:
        self.next_id += 1
        my_id = self.next_id
        self.ws.send(json.dumps({"id": my_id, "method": method, "params": params}))
        while True:
            msg = json.loads(self.ws.recv())
            if msg.get("id") == my_id:
                if "error" in msg:
                    raise RuntimeError(f"{method}: {msg['error']}")
                return msg.get("result", {})
            self.events.append(msg)

    def wait_event(self, method: str, timeout: float = PAGE_TIMEOUT) -> dict[str, Any]:
        deadline = time.monotonic() + timeout
        while True:
            for i, e in enumerate(self.events):
                if e.get("method") == method:
                    return self.events.pop(i)
            if time.monotonic() > deadline:
                raise TimeoutError(f"no {method} within {timeout} s")
            self.ws.settimeout(max(0.1, deadline - time.monotonic()))
            self.events.append(json.loads(self.ws.recv()))

    def close(self) -> None:
        self.ws.close()


def start_chromium(chromium: str, profile: str) -> tuple[subprocess.Popen[bytes], int]:
    args = [chromium, "--headless=new", "--no-sandbox", "--disable-gpu", "--no-first-run",
            "--no-default-browser-check", "--disable-extensions", "--disable-background-networking",
            "--disable-component-update", "--disable-sync", "--mute-audio", "--remote-debugging-address=127.0.0.1",
            "--remote-debugging-port=0", f"--user-data-dir={profile}", "about:blank"]
    proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    port_file = Path(profile) / "DevToolsActivePort"
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:
        if port_file.exists() and port_file.read_text().strip():
            return proc, int(port_file.read_text().split()[0])
        if proc.poll() is not None:
            raise SystemExit(f"{chromium} exited with status {proc.returncode} before opening DevTools")
        time.sleep(0.1)
    proc.kill()
    raise SystemExit(f"{chromium} did not open its DevTools port within 30 s")


def status(url: str, cache: dict[str, tuple[int, bytes]]) -> tuple[int, bytes]:
    if url not in cache:
        try:
            with urllib.request.urlopen(url, timeout=60) as r:
                cache[url] = (r.status, r.read())
        except urllib.error.HTTPError as e:
            cache[url] = (e.code, b"")
    return cache[url]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("site", type=Path)
    ap.add_argument("--chromium", default=os.environ.get("CHROMIUM", "chromium"))
    args = ap.parse_args()
    site = args.site.resolve()
    if not (site / "index.html").exists():
        raise SystemExit(f"{site}/index.html not found: build the site first (scripts/docs/build.sh)")
    chromium = shutil.which(args.chromium)
    if not chromium:
        raise SystemExit(f"{args.chromium} not found: install Debian's package `chromium` (scripts/test-all does, as root)")

    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(Quiet, directory=str(site)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    base = f"http://127.0.0.1:{server.server_address[1]}/"

    pages = sorted(p.relative_to(site).as_posix() for p in site.rglob("*.html"))
    problems: list[str] = []
    cache: dict[str, tuple[int, bytes]] = {}
    with tempfile.TemporaryDirectory(prefix="carl-spec-chromium-") as profile:
        proc, port = start_chromium(chromium, profile)
        try:
            target = json.loads(urllib.request.urlopen(
                urllib.request.Request(f"http://127.0.0.1:{port}/json/new?about:blank", method="PUT"), timeout=10).read())
            dt = DevTools(target["webSocketDebuggerUrl"])
            dt.call("Page.enable")
            dt.call("Network.enable")
            dt.call("Runtime.enable")
            images = links = 0
            for page in pages:
                url = urllib.parse.urljoin(base, page)
                before = len(problems)
                dt.events.clear()
                dt.call("Page.navigate", url=url)
                dt.wait_event("Page.loadEventFired")
                code = next((e["params"]["response"]["status"] for e in dt.events
                             if e.get("method") == "Network.responseReceived"
                             and e["params"]["response"]["url"] == url), None)
                if code is None:
                    code = status(url, cache)[0]
                if code != 200:
                    problems.append(f"{page}: HTTP {code}")
                    continue
                # Let scripts run, then look at what went wrong while loading: exceptions thrown by
                # the page's scripts, and requests that failed (any host: the site is read offline).
                time.sleep(0.05)
                dt.call("Runtime.evaluate", expression="1")
                failed_ids = set()
                for e in dt.events:
                    if e.get("method") == "Runtime.exceptionThrown":
                        d = e["params"]["exceptionDetails"]
                        text = d.get("exception", {}).get("description") or d.get("text", "")
                        problems.append(f"{page}: script error: {text.splitlines()[0] if text else d}")
                    elif e.get("method") == "Network.loadingFailed" and not e["params"].get("canceled"):
                        failed_ids.add(e["params"]["requestId"])
                for e in dt.events:
                    if e.get("method") == "Network.requestWillBeSent" and e["params"]["requestId"] in failed_ids:
                        problems.append(f"{page}: request failed: {e['params']['request']['url']}")
                    elif (e.get("method") == "Network.responseReceived" and e["params"]["response"]["status"] >= 400):
                        problems.append(f"{page}: HTTP {e['params']['response']['status']} for {e['params']['response']['url']}")
                res = dt.call("Runtime.evaluate", expression=COLLECT, returnByValue=True)
                data = json.loads(res["result"]["value"])
                if not data["title"] or data["body"] == 0:
                    problems.append(f"{page}: empty page")
                for img in data["imgs"]:
                    images += 1
                    if not img["ok"]:
                        problems.append(f"{page}: image did not load: {img['src']}")
                for link in data["links"] + data["srcs"]:
                    if not link.startswith(base):
                        continue
                    links += 1
                    target_url, _, frag = link.partition("#")
                    code, body = status(target_url, cache)
                    if code != 200:
                        problems.append(f"{page}: broken link {link} (HTTP {code})")
                    elif frag and target_url.endswith(("/", ".html")):
                        ids = Ids()
                        ids.feed(body.decode("utf-8", "replace"))
                        if urllib.parse.unquote(frag) not in ids.ids:
                            problems.append(f"{page}: link {link}: no element #{frag}")
                print(f"{'ok ' if len(problems) == before else 'BAD'} {page}  ({len(data['imgs'])} images)")
            dt.close()
        finally:
            proc.terminate()
            try:
                proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                proc.kill()
            server.shutdown()
    print(f"{len(pages)} pages, {images} images, {links} internal links checked in Chromium")
    bad_pages = {p.split(":", 1)[0] for p in problems}
    print(f"pages: {len(pages) - len(bad_pages)} passed, {len(bad_pages)} failed")
    if problems:
        print("\n".join(["problems:"] + problems), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
