"""The HTML report and the Jupyter views: structure, content, embedded figures, and a
render in headless chromium when it is installed."""
import base64
import re
import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path

import pytest

import mechdyn as md
from mechdyn import cli
from mechdyn.report import MATHJAX, report

ROOT = Path(__file__).resolve().parents[1]
VOID = {"meta", "img", "br", "hr", "link", "input"}

pytest.importorskip("matplotlib")


class _Structure(HTMLParser):
    """Checks that every element is closed in order; collects headings and images."""

    def __init__(self):
        super().__init__()
        self.stack, self.headings, self.images, self.scripts = [], [], [], []
        self.errors, self._heading = [], None

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "img":
            self.images.append(attrs["src"])
        if tag == "script":
            self.scripts.append(attrs.get("src"))
        if tag not in VOID:
            self.stack.append(tag)
        if tag in ("h1", "h2"):
            self._heading = ""

    def handle_endtag(self, tag):
        if not self.stack or self.stack.pop() != tag:
            self.errors.append(f"unexpected </{tag}>")
        if tag in ("h1", "h2"):
            self.headings.append(self._heading)
            self._heading = None

    def handle_data(self, data):
        if self._heading is not None:
            self._heading += data


def _parse(html):
    parser = _Structure()
    parser.feed(html)
    parser.close()
    assert not parser.errors and not parser.stack, (parser.errors, parser.stack)
    return parser


@pytest.fixture(scope="module")
def brake():
    return md.load_model(ROOT / "models" / "shoe_brake.py")


def test_the_page_holds_derivation_scene_results_and_figure(brake):
    page = report(brake.mechanism, brake.scenes["braking"], brake.params)
    assert page.failure == "" and page.result.t_end == pytest.approx(50.0, rel=1e-9)
    structure = _parse(page.html)
    assert structure.headings == ["Shoe brake — scene braking", "Derivation", "Mechanism",
                                  "Scene", "Results"]
    assert structure.scripts == [MATHJAX]
    # The derivation as LaTeX: T = I phidot^2 / 2 and the textbook equation of motion.
    assert r"\[T = \frac{I \dot{\phi}^{2}}{2}\]" in page.html
    assert r"I \ddot{\phi} = - 2 P R f \operatorname{sign}" in page.html
    # The scene and its result: stop condition, initial speed, events, final angle.
    assert "stopped(phi)" in page.html and r"\(100\)" in page.html
    assert "sliding stopped, held by friction" in page.html
    assert re.search(r"<td>phi</td><td class='num'>0</td><td class='num'>2500</td>",
                     page.html)
    (image,) = structure.images
    png = base64.b64decode(image.removeprefix("data:image/png;base64,"))
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10_000


def test_a_failed_simulation_still_gives_a_page(tmp_path):
    phi = md.coordinate("phi")
    runaway = md.Mechanism("Runaway", [phi])
    runaway.link("disc", J=1, angle=phi)
    runaway.load("drive", md.speed(phi) ** 2, along=phi)      # omega' = omega^2: t* = 1 s
    scene = md.Scene("run", initial={phi: 0, md.speed(phi): 1}, t_end=2)
    page = report(runaway, scene, {})
    assert page.failure.startswith("integration failed")
    assert page.result.t_end < 1.0 + 1e-6
    assert "<p class='failed'>integration failed" in page.html
    _parse(page.html)


def test_the_accuracy_table_on_request(brake):
    page = report(brake.mechanism, brake.scenes["braking"], brake.params, precision=True)
    structure = _parse(page.html)
    assert structure.headings[-1] == "Accuracy" and len(structure.images) == 2
    assert "closed form" in page.html
    for method in ("RK45", "DOP853", "LSODA", "Radau", "BDF"):
        assert f"<td>{method}</td>" in page.html


def test_the_jupyter_views(brake):
    result = brake.mechanism.simulate(brake.scenes["braking"], brake.params)
    view = result._repr_html_()
    _parse(view)
    assert "<h3>Shoe brake — scene braking</h3>" in view and "data:image/png;base64," in view
    mechanism_view = brake.mechanism._repr_html_()
    _parse(mechanism_view)
    assert "<td>shoe</td><td>friction</td><td>brake</td>" in mechanism_view
    assert r"\mathrm{moment} = 2 P R f" in mechanism_view


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("chromium") is None, reason="chromium is not installed")
def test_the_report_command_page_renders_in_headless_chromium(tmp_path, capsys):
    page, shot = tmp_path / "brake.html", tmp_path / "brake.png"
    status = cli.main(["report", str(ROOT / "models" / "shoe_brake.py"), "--scene",
                       "braking", "-o", str(page)])
    assert status == 0 and f"wrote {page}" in capsys.readouterr().out
    subprocess.run(["chromium", "--headless", "--no-sandbox", "--disable-gpu",
                    "--disable-background-networking", f"--screenshot={shot}",
                    "--window-size=1200,2400", page.as_uri()],
                   check=True, capture_output=True, timeout=120)
    picture = shot.read_bytes()
    assert picture[:8] == b"\x89PNG\r\n\x1a\n" and len(picture) > 50_000
    dom = subprocess.run(["chromium", "--headless", "--no-sandbox", "--disable-gpu",
                          "--disable-background-networking", "--dump-dom", page.as_uri()],
                         check=True, capture_output=True, text=True, timeout=120).stdout
    assert "Shoe brake — scene braking" in dom and "data:image/png;base64," in dom
