"""The gallery's sources (examples/, run by sphinx-gallery in the docs build): a page
per bundled model and per worked example, each a script in sphinx-gallery's format that
goes through the public API. The slow test runs every script as a user would."""
import ast
import os
import subprocess
import sys
from pathlib import Path

import pytest

import mechdyn as md

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
# The worked examples 0-8 of the project's reference, one script each.
WORKED = ["plot_0_equation_of_motion", "plot_1_shoe_brake", "plot_2_gear_pair",
          "plot_3_cam_follower", "plot_4_scotch_yoke", "plot_5_planetary_gear",
          "plot_6_rope_hoist", "plot_7_reduction", "plot_8_loom_sley"]
SCRIPTS = sorted(EXAMPLES.glob("*/plot_*.py"))


def docstring(path):
    return ast.get_docstring(ast.parse(path.read_text(encoding="utf-8")), clean=False)


def test_every_bundled_model_has_a_page_and_no_page_lacks_its_model():
    models = {p.stem for p in (ROOT / "models").glob("*.py") if not p.name.startswith("_")}
    pages = {p.stem.removeprefix("plot_") for p in (EXAMPLES / "models").glob("plot_*.py")}
    assert models and models == pages, (models - pages, pages - models)
    for name in models:      # each page shows its own model, loaded by name
        source = (EXAMPLES / "models" / f"plot_{name}.py").read_text(encoding="utf-8")
        assert f'md.load_model("{name}")' in source, name


def test_every_worked_example_has_a_page_titled_with_its_number():
    pages = sorted(p.stem for p in (EXAMPLES / "worked").glob("plot_*.py"))
    assert pages == WORKED
    for number, name in enumerate(WORKED):
        title = docstring(EXAMPLES / "worked" / f"{name}.py").strip().splitlines()[0]
        assert title.startswith(f"{number}. "), (name, title)


def test_each_gallery_folder_has_its_header():
    for folder in (EXAMPLES, EXAMPLES / "models", EXAMPLES / "worked"):
        lines = (folder / "GALLERY_HEADER.rst").read_text(encoding="utf-8").splitlines()
        assert lines[0].strip() and set(lines[1]) <= set("=-") and len(lines[1]) >= len(lines[0])


@pytest.mark.parametrize("path", SCRIPTS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_script_opens_with_an_rst_title_and_a_paragraph(path):
    text = docstring(path)
    assert text is not None and text.startswith("\n"), "the docstring opens the file"
    title, underline, blank, paragraph, *_ = text.strip("\n").splitlines()
    assert title.strip() and underline == "=" * len(underline) and len(underline) >= len(title)
    assert blank == "" and paragraph.strip(), "a paragraph follows the title"
    assert "# %%" in path.read_text(encoding="utf-8"), "cells, as sphinx-gallery reads them"


@pytest.mark.parametrize("path", SCRIPTS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_script_uses_only_the_public_api(path):
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            assert not any(a.name.startswith("mechdyn.") for a in node.names), ast.unparse(node)
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("mechdyn"):
            assert node.module == "mechdyn", ast.unparse(node)
            assert {a.name for a in node.names} <= set(md.__all__), ast.unparse(node)


# Runs the scripts one after another in one process, each in a namespace of its own and
# from its own folder, as sphinx-gallery does (one process: the imports are paid once).
RUNNER = """
import os, runpy, sys, traceback
import matplotlib.pyplot as plt
for path in sys.argv[1:]:
    os.chdir(os.path.dirname(path))
    try:
        runpy.run_path(path, run_name="__main__")
    except BaseException:
        traceback.print_exc()
        print("FAILED", path, file=sys.stderr)
    plt.close("all")
print("RAN", len(sys.argv) - 1, file=sys.stderr)
"""


@pytest.mark.slow
def test_every_gallery_script_runs():
    env = {**os.environ, "MPLBACKEND": "Agg",
           "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))}
    run = subprocess.run([sys.executable, "-c", RUNNER, *map(str, SCRIPTS)], env=env,
                         capture_output=True, text=True, timeout=1800)
    assert len(SCRIPTS) == len(WORKED) + len(list((ROOT / "models").glob("[!_]*.py")))
    failed = [line for line in run.stderr.splitlines() if line.startswith("FAILED")]
    assert run.returncode == 0 and not failed, run.stderr[-4000:]
    assert f"RAN {len(SCRIPTS)}" in run.stderr
