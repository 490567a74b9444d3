"""The HTML report and the Jupyter views: structure, content, embedded figures, and a
render in headless chromium, with the network off, when chromium is installed."""
import base64
import json
import re
import shutil
import subprocess
from html import unescape as html_unescape
from html.parser import HTMLParser
from pathlib import Path

import pytest

import mechdyn as md
from mechdyn import cli
from mechdyn.report.document import report

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
    assert structure.scripts == []                      # nothing to load: no MathJax
    assert not re.search(r"(src|href)=['\"]?https?:", page.html)
    # The derivation as MathML (T = I phidot^2 / 2), its LaTeX source for copying.
    assert "<mi>T</mi><mo>&#x0003D;</mo><mfrac><mrow><mi>I</mi>" in page.html
    assert "<mo>sign</mo>" in page.html and "\\" not in page.html.split("<details>")[0]
    assert r"T &amp;= \frac{I \dot{\phi}^{2}}{2}" in page.html
    assert r"I \ddot{\phi} &amp;= - 2 P R f \operatorname{sign}" in page.html
    # The scene and its result: stop condition, initial speed, events, final angle.
    assert "stopped(phi)" in page.html and "<mn>100</mn>" in page.html
    assert "<td class='num'>20</td><td>N</td>" in page.html         # parameter P, its unit
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
    assert "<mtext>moment</mtext><mo>&#x0003D;</mo><mn>2</mn><mi>P</mi><mi>R</mi><mi>f" \
        in mechanism_view
    # Jupyter right-aligns cells; the views align their text columns left.
    for view_html in (view, mechanism_view):
        assert view_html.startswith("<div class='mechdyn'><style>.mechdyn table td")


def test_the_unit_column_is_filled_for_moments_and_powers():
    model = md.load_model(ROOT / "models" / "motor_startup.py")
    page = report(model.mechanism, model.scenes["startup"], model.params)
    assert re.search(r"<tr><td>motor</td>(<td class='num'>[^<]+</td>){3}<td>N\*m</td></tr>",
                     page.html)
    assert re.search(r"<tr><td>power:motor</td>(<td class='num'>[^<]+</td>){3}<td>W</td>",
                     page.html)


# Run in the page after load: the layout of the MathML and of the images, as JSON in
# the DOM. A fraction is laid out when its numerator sits above its denominator, a
# superscript when it sits above its base; raw LaTeX or unsupported MathML fails both.
_LAYOUT_PROBE = """<script>
const box = e => e.getBoundingClientRect();
const fractions = [...document.querySelectorAll('mfrac')].map(f => {
  const [top, bottom] = [box(f.children[0]), box(f.children[1])];
  return top.bottom <= bottom.top + 1 && top.height > 0 && bottom.height > 0; });
const powers = [...document.querySelectorAll('msup')].map(p => {
  const [base, power] = [box(p.children[0]), box(p.children[1])];
  return power.top < base.top && power.height > 0; });
const maths = [...document.querySelectorAll('math')].map(m => box(m).width > 0);
const images = [...document.images].map(i => i.complete && i.naturalWidth > 0);
document.body.setAttribute('data-layout', JSON.stringify({fractions, powers, maths,
  images, text: document.body.innerText.includes('\\\\frac')}));
</script>"""


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("chromium") is None, reason="chromium is not installed")
def test_the_report_renders_its_math_in_headless_chromium_without_network(tmp_path, capsys):
    page, probed = tmp_path / "brake.html", tmp_path / "probed.html"
    status = cli.main(["report", str(ROOT / "models" / "scotch_yoke.py"), "--scene",
                       "startup", "-o", str(page)])
    assert status == 0 and f"wrote {page}" in capsys.readouterr().out
    probed.write_text(page.read_text().replace("</body>", _LAYOUT_PROBE + "</body>"))
    offline = ["--host-resolver-rules=MAP * ~NOTFOUND", "--proxy-server=http://127.0.0.1:9",
               "--disable-background-networking"]
    dom = subprocess.run(["chromium", "--headless", "--no-sandbox", "--disable-gpu",
                          *offline, "--dump-dom", probed.as_uri()],
                         check=True, capture_output=True, text=True, timeout=120).stdout
    layout = json.loads(html_unescape(re.search(r'data-layout="([^"]*)"', dom).group(1)))
    assert len(layout["fractions"]) >= 3 and all(layout["fractions"]), layout["fractions"]
    assert len(layout["powers"]) >= 3 and all(layout["powers"]), layout["powers"]
    assert len(layout["maths"]) >= 20 and all(layout["maths"])
    assert layout["images"] == [True] and not layout["text"]
    shot = tmp_path / "page.png"
    subprocess.run(["chromium", "--headless", "--no-sandbox", "--disable-gpu", *offline,
                    f"--screenshot={shot}", "--window-size=1200,2400", page.as_uri()],
                   check=True, capture_output=True, timeout=120)
    assert shot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_layout_probe_fails_on_raw_latex(tmp_path):
    """The probe above can fail: LaTeX text has no fractions to lay out, and a fraction
    written as inline text is not stacked."""
    if shutil.which("chromium") is None:
        pytest.skip("chromium is not installed")
    page = tmp_path / "raw.html"
    page.write_text("<!DOCTYPE html><html><body><p>\\(\\frac{a}{b}\\)</p>"
                    "<p><span class='mfrac'>a b</span></p>"
                    "<mfrac><span>a</span><span>b</span></mfrac>"
                    + _LAYOUT_PROBE + "</body></html>")
    dom = subprocess.run(["chromium", "--headless", "--no-sandbox", "--disable-gpu",
                          "--dump-dom", page.as_uri()], check=True, capture_output=True,
                         text=True, timeout=120).stdout
    layout = json.loads(html_unescape(re.search(r'data-layout="([^"]*)"', dom).group(1)))
    assert layout["fractions"] == [False] and layout["text"] and layout["maths"] == []
