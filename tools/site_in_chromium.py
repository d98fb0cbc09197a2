"""The built documentation site as a reader's browser shows it: how wide each code block
is beside the room the theme gives it, and what the theme's own search answers.

    python tools/site_in_chromium.py widths [--site DIR] [--width PX]
    python tools/site_in_chromium.py search QUERY [QUERY ...] [--site DIR] [--width PX]

Build the site first (``.venv/bin/mkdocs build``; ``--site`` default ``build/site``). The
site is served on localhost and loaded in headless Chromium (``$CHROMIUM``, default
``chromium``: Debian's ``apt-get install chromium``), driven over the DevTools protocol on
a pipe, with nothing but the standard library; the viewport is ``--width`` pixels wide
(default 1280) and 800 high.

``widths`` prints, for each page, each code block whose text is wider than the block
(its ``scrollWidth`` beyond its ``clientWidth``), and then the characters of the code
font that fit in a block of the content column (measured on a run of 100 zeros in the
block's own font), the smallest over the pages. The site loads no web fonts here, so the
code font is the theme's fallback, the system's monospace (DejaVu Sans Mono on Debian,
0.602 em a character, wider than the theme's Roboto Mono, 0.600 em): the figure is what
the widest of the fonts the theme names shows.

``search`` types each query into the site's search box (the theme's own search, its
lunr index and worker) and prints the pages it lists, in order, with their URL.
"""

from __future__ import annotations

import argparse
import contextlib
import fcntl
import functools
import http.server
import json
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: what runs in each page for ``widths``: each code block's widths, before and beside
#: the characters of its font that fit
WIDTHS = """(async () => {
  await document.fonts.ready;
  const blocks = [];
  for (const code of document.querySelectorAll(".md-content pre > code")) {
    const style = getComputedStyle(code);
    const room = code.clientWidth - parseFloat(style.paddingLeft)
      - parseFloat(style.paddingRight);
    const probe = document.createElement("span");
    probe.textContent = "0".repeat(100);
    probe.style.whiteSpace = "pre";
    const scroll = code.scrollWidth, client = code.clientWidth;
    code.appendChild(probe);
    const char = probe.getBoundingClientRect().width / 100;
    probe.remove();
    const lines = code.textContent.replace(/\\n$/, "").split("\\n");
    const longest = lines.reduce((a, b) => (b.length > a.length ? b : a), "");
    blocks.push({scroll, client, char, fits: Math.floor(room / char + 1e-6),
                 longest: longest.length, line: longest,
                 font: style.fontFamily, size: style.fontSize});
  }
  return blocks;
})()"""

#: what runs for ``search``: the results the search box lists, once it has answered
RESULTS = """(async () => {
  for (let i = 0; i < 100; i++) {
    const meta = document.querySelector(".md-search-result__meta");
    if (meta && !/Initializing|Type to start/i.test(meta.textContent)) break;
    await new Promise(r => setTimeout(r, 100));
  }
  await new Promise(r => setTimeout(r, 300));
  return {
    meta: document.querySelector(".md-search-result__meta").textContent,
    pages: [...document.querySelectorAll(".md-search-result__item")].map(item => ({
      href: item.querySelector("a").getAttribute("href").split("?")[0],
      title: item.querySelector("h1, h2").textContent.trim(),
      sections: [...item.querySelectorAll("a h2")].map(h => h.textContent.trim())
    }))
  };
})()"""


class Browser:
    """Headless Chromium over the DevTools protocol on a pipe (fds 3 and 4)."""

    def __init__(self, executable: str, width: int):
        self.profile = tempfile.mkdtemp(prefix="chromium-profile-")
        # the pipes' ends above 4, so that the child's dup2 onto 3 and 4 is never a no-op
        # (which would leave an end close-on-exec)
        read_commands, write_commands, read_answers, write_answers = (
            fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 10) for fd in (*os.pipe(), *os.pipe()))
        args = [executable, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                "--no-first-run", "--disable-background-networking",
                "--disable-component-update", "--disable-sync", "--remote-debugging-pipe",
                f"--user-data-dir={self.profile}", f"--window-size={width},800",
                "about:blank"]

        def fds():  # Chromium reads the commands on fd 3 and writes its answers on fd 4
            os.dup2(read_commands, 3)
            os.dup2(write_answers, 4)

        self.process = subprocess.Popen(args, preexec_fn=fds, close_fds=False,
                                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(read_commands)
        os.close(write_answers)
        self._write, self._read = os.fdopen(write_commands, "wb"), os.fdopen(read_answers, "rb")
        self._id, self._buffer = 0, b""
        target = self.call("Target.createTarget", url="about:blank")["targetId"]
        self.session = self.call("Target.attachToTarget", targetId=target,
                                 flatten=True)["sessionId"]
        self.call("Emulation.setDeviceMetricsOverride", self.session, width=width,
                  height=800, deviceScaleFactor=1, mobile=False)
        self.call("Page.enable", self.session)

    def call(self, method: str, session: str | None = None, **params):
        self._id += 1
        message = {"id": self._id, "method": method, "params": params}
        if session:
            message["sessionId"] = session
        self._write.write(json.dumps(message).encode() + b"\0")
        self._write.flush()
        while True:
            while b"\0" not in self._buffer:
                chunk = os.read(self._read.fileno(), 1 << 16)
                if not chunk:
                    raise RuntimeError("chromium closed its pipe")
                self._buffer += chunk
            text, _, self._buffer = self._buffer.partition(b"\0")
            answer = json.loads(text)
            if answer.get("id") == self._id:
                if "error" in answer:
                    raise RuntimeError(f"{method}: {answer['error']}")
                return answer["result"]

    def evaluate(self, expression: str):
        result = self.call("Runtime.evaluate", self.session, expression=expression,
                           awaitPromise=True, returnByValue=True)
        if "exceptionDetails" in result:
            raise RuntimeError(json.dumps(result["exceptionDetails"])[:2000])
        return result["result"].get("value")

    def load(self, url: str) -> None:
        self.call("Page.navigate", self.session, url=url)
        for _ in range(200):
            time.sleep(0.05)
            if self.evaluate(f"location.href === {json.dumps(url)} && "
                             "document.readyState === 'complete'"):
                return
        raise RuntimeError(f"{url} did not load")

    def close(self) -> None:
        with contextlib.suppress(Exception):
            self.call("Browser.close")
        try:
            self.process.wait(10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        shutil.rmtree(self.profile, ignore_errors=True)


@contextlib.contextmanager
def served(site: Path):
    """The folder ``site`` served on a free port of localhost: its base URL."""
    handler = functools.partial(_Quiet, directory=str(site))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}/"
    finally:
        server.shutdown()
        server.server_close()


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


def pages(site: Path) -> list[str]:
    """Each page of the site (its folder's ``index.html``), as a path from the root."""
    folders = [p.parent.relative_to(site) for p in site.rglob("index.html")]
    return sorted("/" if f == Path(".") else f"{f.as_posix()}/" for f in folders
                  if f.parts[:1] not in (("assets",), ("search",)))


def widths(browser: Browser, base: str, site: Path) -> int:
    fits = []
    for page in pages(site):
        browser.load(base + page.lstrip("/"))
        for k, block in enumerate(browser.evaluate(WIDTHS)):
            fits.append(block["fits"])
            if block["scroll"] > block["client"]:
                print(f"{page} block {k + 1}: {block['scroll']} px of text in "
                      f"{block['client']} px; its longest line, {block['longest']} "
                      f"characters (fit: {block['fits']}): {block['line']}")
    print(f"code blocks: {len(fits)}; characters that fit: {min(fits)} to {max(fits)} "
          f"(font {block['font']}, {block['size']}, {block['char']:.3f} px a character)")
    return 1 if any(f < min(fits) for f in fits) else 0


def search(browser: Browser, base: str, queries: list[str]) -> int:
    for query in queries:
        browser.load(base)
        browser.evaluate("document.querySelector('.md-search__input').focus(), true")
        browser.call("Input.insertText", browser.session, text=query)
        found = browser.evaluate(RESULTS)
        print(f"{query!r}: {found['meta']}")
        for rank, page in enumerate(found["pages"], 1):
            sections = "; ".join(page["sections"][:3])
            print(f"  {rank}. {page['title']}  ({page['href'].removeprefix(base)})"
                  + (f": {sections}" if sections else ""))
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("what", choices=("widths", "search"))
    parser.add_argument("queries", nargs="*")
    parser.add_argument("--site", type=Path, default=ROOT / "build" / "site")
    parser.add_argument("--width", type=int, default=1280)
    args = parser.parse_args(argv)
    if not (args.site / "index.html").is_file():
        parser.error(f"{args.site}: no site built there (.venv/bin/mkdocs build)")
    executable = shutil.which(os.environ.get("CHROMIUM", "chromium"))
    if executable is None:
        parser.error("no chromium (apt-get install chromium, or set CHROMIUM)")
    browser = Browser(executable, args.width)
    try:
        with served(args.site) as base:
            if args.what == "widths":
                return widths(browser, base, args.site)
            return search(browser, base, args.queries)
    finally:
        browser.close()


if __name__ == "__main__":
    sys.exit(main())
