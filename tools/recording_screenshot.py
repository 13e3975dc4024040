"""Screenshot of a run's recording in the Rerun web viewer, served locally (offline: the viewer
comes with rerun-sdk) and opened in headless Chromium (Debian's `chromium`), driven over the
DevTools protocol (tornado's websocket client, from the test extras).

    python tools/recording_screenshot.py [RUN.rrd --out FILE.png]

Without RUN.rrd it simulates the default trot (6 s) and a jump (3 s) into a temporary folder and
writes docs/recording_trot.png and docs/recording_jump.png (--gait to choose, --duration to
change a run's length): the viewer at the recording's default layout, as a reader first sees it.
The viewer gets --wait seconds to load the wasm and the file, then the page is captured
until two screenshots are the same; the PNG is reduced to a 256-colour palette (< 300 kB)."""

from __future__ import annotations

import argparse
import asyncio
import base64
import io
import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.parse
import urllib.request
from pathlib import Path

STABLE_S = 4.0      # the viewer is drawn once two screenshots this far apart are the same
MAX_WAIT_S = 120.0
CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                  "--disable-background-networking", "--disable-component-update",
                  "--disable-sync", "--enable-unsafe-swiftshader", "--hide-scrollbars"]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for(url: str, seconds: float) -> bytes:
    """The body at url once it answers (within seconds)."""
    end = time.monotonic() + seconds
    while True:
        try:
            with urllib.request.urlopen(url, timeout=2) as answer:
                return answer.read()
        except OSError:
            if time.monotonic() > end:
                raise
            time.sleep(0.2)


def capture(page_url: str, size: tuple[int, int], wait_s: float,
            expression: str | None = None) -> tuple[bytes, object]:
    """PNG of page_url in headless Chromium after wait_s seconds, and the value of the
    JavaScript expression evaluated in the page then (None without one)."""
    from tornado.ioloop import IOLoop
    from tornado.websocket import websocket_connect

    port = free_port()
    chrome = subprocess.Popen(
        ["chromium", *CHROMIUM_FLAGS, f"--remote-debugging-port={port}",
         f"--user-data-dir={tempfile.mkdtemp(prefix='chromium-')}",
         f"--window-size={size[0]},{size[1]}", "about:blank"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        targets = json.loads(wait_for(f"http://127.0.0.1:{port}/json/list", 30))
        ws_url = next(t["webSocketDebuggerUrl"] for t in targets if t["type"] == "page")

        async def drive() -> bytes:
            ws = await websocket_connect(ws_url, max_message_size=1 << 28)
            ids = iter(range(1, 1 << 30))

            async def call(method, **params):
                k = next(ids)
                ws.write_message(json.dumps({"id": k, "method": method, "params": params}))
                while True:
                    message = json.loads(await ws.read_message())
                    if message.get("id") == k:
                        return message.get("result", {})

            await call("Emulation.setDeviceMetricsOverride", width=size[0], height=size[1],
                       deviceScaleFactor=1, mobile=False)
            await call("Page.navigate", url=page_url)
            await asyncio.sleep(wait_s)
            value = None
            if expression is not None:
                value = (await call("Runtime.evaluate", expression=expression,
                                    returnByValue=True))["result"].get("value")
            # until two screenshots STABLE_S apart are the same: the file is loaded and drawn
            shots = [None]
            while len(shots) * STABLE_S < MAX_WAIT_S:
                shots.append((await call("Page.captureScreenshot", format="png"))["data"])
                if shots[-1] == shots[-2]:
                    break
                await asyncio.sleep(STABLE_S)
            ws.close()
            return base64.b64decode(shots[-1]), value

        return IOLoop.current().run_sync(drive)
    finally:
        os.killpg(chrome.pid, signal.SIGTERM)           # the browser and its helpers
        chrome.wait(10)


def screenshot(rrd: Path, out: Path, size=(1600, 1000), wait_s: float = 10.0) -> Path:
    """Serve rrd with `rerun --web-viewer` on local ports and write the viewer's screenshot."""
    from PIL import Image

    web, grpc = free_port(), free_port()
    rerun = Path(sys.executable).with_name("rerun")
    # its own process group: the `rerun` script starts the viewer binary as a child
    viewer = subprocess.Popen(
        [str(rerun), "--web-viewer", "--bind", "127.0.0.1", "--web-viewer-port", str(web),
         "--port", str(grpc), str(rrd)],
        env={**os.environ, "BROWSER": "true"}, stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        wait_for(f"http://127.0.0.1:{web}", 30)
        source = urllib.parse.quote(f"rerun+http://127.0.0.1:{grpc}/proxy", safe="")
        png, _ = capture(f"http://127.0.0.1:{web}/?url={source}", size, wait_s)
    finally:
        os.killpg(viewer.pid, signal.SIGTERM)
        viewer.wait(10)
    image = Image.open(io.BytesIO(png)).convert("RGB").quantize(256)
    out.parent.mkdir(parents=True, exist_ok=True)
    image.save(out, optimize=True)
    return out


GAITS = {"trot": 6.0, "jump": 3.0}    # the README's screenshots: gait -> simulated seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("rrd", nargs="?", type=Path, help="recording (default: simulate them)")
    parser.add_argument("--out", type=Path, default=None,
                        help="the PNG of RUN.rrd (default recording.png), or the folder of "
                             "the simulated ones' (default docs)")
    parser.add_argument("--gait", action="append", choices=sorted(GAITS),
                        help="the gaits to simulate and capture (default: all)")
    parser.add_argument("--duration", type=float, default=None,
                        help="simulated time of every run (default: the gait's own)")
    parser.add_argument("--wait", type=float, default=10.0,
                        help="seconds the viewer gets to load before the first screenshot "
                             f"(then one every {STABLE_S:g} s until two are the same)")
    args = parser.parse_args()
    if args.rrd is not None:
        path = screenshot(args.rrd, args.out or Path("recording.png"), wait_s=args.wait)
        print(f"wrote {path} ({path.stat().st_size / 1e3:.0f} kB)")
        return
    for gait in args.gait or list(GAITS):
        with tempfile.TemporaryDirectory() as tmp:
            code = subprocess.run([sys.executable, "-m", "fivebar_drake", "simulate", "--gait",
                                   gait, "--duration", str(args.duration or GAITS[gait]),
                                   "--out", tmp]).returncode
            if code not in (0, 1):          # 1: a run without a verdict still writes its file
                raise SystemExit(f"simulate --gait {gait} exited {code}")
            path = screenshot(Path(tmp) / "run.rrd",
                              (args.out or Path("docs")) / f"recording_{gait}.png",
                              wait_s=args.wait)
        print(f"wrote {path} ({path.stat().st_size / 1e3:.0f} kB)")


if __name__ == "__main__":
    main()
