"""The entry page (OUT/index.html, `fivebar-drake index`) opened in headless Chromium (Debian's
`chromium`): every picture it shows must have loaded (exit 1 naming those that did not), and
its first screen is written as a PNG for the docs.

    python tools/page_screenshot.py [OUT/index.html] [--out docs/index_page.png]
"""

from __future__ import annotations

import argparse
import io
import sys
from pathlib import Path

from recording_screenshot import capture

BROKEN = ("Array.from(document.images).filter(i => !i.complete || i.naturalWidth === 0)"
          ".map(i => i.getAttribute('src'))")


def main() -> int:
    from PIL import Image

    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("page", nargs="?", type=Path, default=Path("out/index.html"))
    parser.add_argument("--out", type=Path, default=Path("docs/index_page.png"))
    args = parser.parse_args()
    if not args.page.is_file():
        print(f"{args.page}: no such page; run make demo (or fivebar-drake index) first",
              file=sys.stderr)
        return 2
    png, broken = capture(args.page.resolve().as_uri(), (1280, 1600), 3.0, BROKEN)
    if broken:
        print(f"{args.page}: pictures that did not load: {', '.join(broken)}", file=sys.stderr)
        return 1
    image = Image.open(io.BytesIO(png)).convert("RGB").quantize(256)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    image.save(args.out, optimize=True)
    print(f"wrote {args.out} (every picture of {args.page} loaded)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
