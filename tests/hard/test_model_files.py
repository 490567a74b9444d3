"""Model files that fail, exit or define the wrong things: a named ModelFileError (exit
2), and `mechdyn models` lists every other file, one line per broken one."""
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import mechdyn as md
from mechdyn.cli import main
from mechdyn.declare.model_file import ModelFileError

ROOT = Path(__file__).resolve().parents[2]
GOOD = (ROOT / "models" / "shoe_brake.py").read_text()

# file name -> (contents, what the error must say)
BROKEN = {
    "exits.py": ("import sys\nsys.exit(7)\n", "sys.exit(7)"),
    "exits_quietly.py": ("raise SystemExit\n", "sys.exit(None)"),
    "raises.py": ("x = 1\nraise ValueError('bad lever ratio')\n",
                  "line 2: ValueError: bad lever ratio"),
    "interrupts.py": ("raise KeyboardInterrupt\n", "raised KeyboardInterrupt"),
    "base_exception.py": ("class Odd(BaseException):\n    pass\nraise Odd('odd')\n",
                          "line 3: Odd: odd"),
    "scenes_list.py": (GOOD + "scenes = [1, 2]\n", "`scenes` must be a dict"),
    "scene_not_scene.py": (GOOD + "scenes = {'a': 3}\n", "scenes['a'] is not a md.Scene"),
    "params_list.py": (GOOD + "params = [1]\n", "`params` must be a dict"),
    "params_key.py": (GOOD + "params = {3: 1}\n", "the key 3 is not a parameter"),
    "params_value.py": (GOOD + "params = {I: 'heavy', f: 0.2, P: 20, R: 0.1}\n",
                        "parameter I: 'heavy'"),
    "params_negative.py": (GOOD + "params = {I: -0.4, f: 0.2, P: 20, R: 0.1}\n",
                           "parameter I = -0.4 is negative"),
    "no_mechanism.py": ("params = {}\n", "defines no `mechanism`"),
    "binary.py": ("\x00\x01garbage", "SyntaxError"),
    "doc_not_text.py": None,             # loads: a non-text __doc__ is ignored
}


@pytest.fixture
def folder(tmp_path):
    (tmp_path / "good.py").write_text(GOOD)
    for name, case in BROKEN.items():
        text = case[0] if case else GOOD + "__doc__ = 5\n"
        (tmp_path / name).write_text(text)
    return tmp_path


@pytest.mark.parametrize("name", sorted(n for n, case in BROKEN.items() if case))
def test_a_broken_model_file_is_a_named_model_file_error(folder, name):
    with pytest.raises(ModelFileError) as raised:
        md.load_model(folder / name)
    assert str(folder / name) in str(raised.value)
    assert BROKEN[name][1] in str(raised.value)


def test_the_listing_goes_on_past_broken_files_one_line_each(folder, capsys):
    assert main(["models", str(folder)]) == 2
    out = capsys.readouterr().out
    lines = out.splitlines()
    for name, case in BROKEN.items():
        mine = [line for line in lines if line.startswith(str(folder / name))]
        assert len(mine) == 1, (name, out)
        if case:
            assert "cannot be loaded" in mine[0] and case[1] in mine[0]
    assert f"{folder / 'good.py'}  Shoe brake" in out and "scenes: braking" in out


@pytest.mark.parametrize("name", ["exits.py", "interrupts.py", "scenes_list.py"])
def test_commands_on_a_broken_model_file_exit_2_with_one_line(folder, name, capsys):
    assert main(["simulate", str(folder / name), "--scene", "braking"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("mechdyn: error: ") and err.count("\n") == 1
    assert BROKEN[name][1] in err


def test_a_real_ctrl_c_while_a_model_file_runs_still_interrupts(tmp_path):
    """A KeyboardInterrupt the user gives is not mistaken for one the file raised."""
    inside = tmp_path / "inside"
    (tmp_path / "slow.py").write_text(f"import time\nopen({str(inside)!r}, 'w').close()\n"
                                      "time.sleep(60)\n")
    process = subprocess.Popen([sys.executable, "-m", "mechdyn.cli.command", "models", str(tmp_path)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               env=dict(os.environ, PYTHONPATH=str(ROOT)),
                               # SIGINT as in a terminal (a pytest-xdist worker ignores it)
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 60
    while not inside.exists() and time.monotonic() < deadline:
        time.sleep(0.05)
    process.send_signal(signal.SIGINT)
    out, err = process.communicate(timeout=30)
    assert process.returncode == 130 and "interrupted" in err
    assert "cannot be loaded" not in out
