"""Screenshots of the built site in headless Chromium: its front page and one gallery page.

Serves ``docs/_build/html`` on localhost (a free port, this process only) and has
Chromium draw each page into a PNG, so a person can look at what a reader sees::

    python -m sphinx -W --keep-going -b html docs docs/_build/html
    python docs/screenshot.py                      # writes docs/_build/screenshots/*.png
    python docs/screenshot.py --page gallery/worked/plot_shoe_brake.html --out /tmp/shots

The gallery page defaults to the first example page the build wrote. Chromium runs with
a fresh profile folder and no background network, sync or updates.
"""
import argparse
import functools
import http.server
import shutil
import subprocess
import sys
import tempfile
import threading
from pathlib import Path

HTML = Path(__file__).resolve().parent / "_build" / "html"
BROWSERS = ("chromium", "chromium-browser", "google-chrome")


def first_gallery_page(root: Path) -> str:
    """The first example page under ``gallery/`` (not an index or a timing page)."""
    pages = sorted(path for path in (root / "gallery").rglob("plot_*.html"))
    if not pages:
        raise SystemExit(f"no gallery page under {root / 'gallery'}: build the docs first")
    return pages[0].relative_to(root).as_posix()


def browser() -> str:
    found = next((shutil.which(name) for name in BROWSERS if shutil.which(name)), None)
    if found is None:
        raise SystemExit("needs Chromium (apt-get install chromium)")
    return found


def shoot(url: str, png: Path, size: str) -> None:
    with tempfile.TemporaryDirectory() as profile:
        subprocess.run([browser(), "--headless", "--no-sandbox", "--disable-gpu",
                        "--disable-background-networking", "--disable-component-update",
                        "--disable-sync", "--no-first-run", "--hide-scrollbars",
                        f"--user-data-dir={profile}", f"--screenshot={png}",
                        f"--window-size={size}", url],
                       check=True, capture_output=True, timeout=120)
    if not png.is_file():
        raise SystemExit(f"Chromium wrote no {png}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--html", type=Path, default=HTML, help="the built site")
    parser.add_argument("--out", type=Path, default=HTML.parent / "screenshots")
    parser.add_argument("--page", help="the gallery page (default: the first)")
    parser.add_argument("--size", default="1280,1600", help="window width,height")
    args = parser.parse_args(argv)
    if not (args.html / "index.html").is_file():
        raise SystemExit(f"no {args.html / 'index.html'}: build the docs first")
    pages = {"front": "index.html", "gallery": args.page or first_gallery_page(args.html)}
    handler = functools.partial(QuietHandler, directory=str(args.html))
    with http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler) as server:
        threading.Thread(target=server.serve_forever, daemon=True).start()
        args.out.mkdir(parents=True, exist_ok=True)
        for name, page in pages.items():
            png = args.out / f"{name}.png"
            shoot(f"http://127.0.0.1:{server.server_port}/{page}", png, args.size)
            print(f"{png}: {page}")
        server.shutdown()
    return 0


class QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):          # one line per page shot is enough
        pass


if __name__ == "__main__":
    sys.exit(main())
