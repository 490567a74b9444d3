"""The README is the front door: short, its links into the documentation resolve, and its
install and test commands are the ones CI runs. Its python block runs as written with the
guide's (tests/test_docs_examples.py)."""
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()


def test_the_readme_is_a_front_door_of_at_most_about_250_lines():
    assert len(README.splitlines()) <= 250


def test_every_local_link_and_figure_of_the_readme_exists():
    targets = re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", README)
    local = [target for target in targets if "://" not in target]
    assert len(local) >= 20                     # the table of what it does, the figure
    missing = [target for target in local if not (ROOT / target).exists()]
    assert not missing


def test_ci_runs_the_readmes_install_and_test_command():
    # .ci/run must install the project the README's way and run the README's test
    # command: both are read off the README's first screen, so they cannot drift apart.
    first_block = re.search(r"```bash\n(.*?)```", README, re.S)[1]
    test_line = next(line for line in first_block.splitlines() if "pytest" in line)
    install, command = (part.split("#")[0].strip() for part in test_line.split("&&"))
    ci = (ROOT / ".ci" / "run").read_text().splitlines()
    assert install in ci and command in ci
    assert ci.index(install) < ci.index(command)


def test_ci_builds_the_documentation_as_the_readme_says():
    build = re.search(r"^pip install \"\.\[docs\]\" && (python -m sphinx .*)$", README, re.M)
    assert build
    ci = (ROOT / ".ci" / "run").read_text().splitlines()
    assert 'pip install ".[docs]"' in ci and build[1] in ci
    assert ci.index('pip install ".[docs]"') < ci.index(build[1])
