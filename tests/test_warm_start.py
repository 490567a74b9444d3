"""The command line's warm start: a repeated `mechdyn simulate` runs from the cache without
executing the model file or importing sympy, and gives the same result; a changed model
file or parameter is a new command."""
import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PROBE = ("import sys\nfrom mechdyn.cli import main\nstatus = main(sys.argv[1:])\n"
         "print('SYMPY', 'sympy' in sys.modules, 'STATUS', status)\n")


def run(cache, *args):
    env = {**os.environ, "MECHDYN_CACHE": str(cache)}
    done = subprocess.run([sys.executable, "-c", PROBE, *args], capture_output=True,
                          text=True, env=env, cwd=ROOT, timeout=120)
    assert done.returncode == 0, done.stderr
    summary, probe = done.stdout.rsplit("SYMPY", 1)
    return summary, probe.split()


def test_a_repeated_run_skips_the_model_file_and_sympy_and_agrees(tmp_path, share_kernels):
    share_kernels(tmp_path / "cache")
    model = tmp_path / "brake.py"
    shutil.copy(ROOT / "models" / "shoe_brake.py", model)
    first, probe = run(tmp_path / "cache", "simulate", str(model), "--scene", "braking")
    assert probe == ["True", "STATUS", "0"]             # the cold run declares with sympy
    second, probe = run(tmp_path / "cache", "simulate", str(model), "--scene", "braking")
    assert probe == ["False", "STATUS", "0"]            # the warm one never imports it
    strip = [line for line in first.splitlines() if " ms" not in line]
    assert strip == [line for line in second.splitlines() if " ms" not in line]
    assert "t = 50 s" in second and "final 2500 rad" in second     # worked example 1


def test_another_parameter_or_a_changed_model_file_is_a_cold_run(tmp_path, share_kernels):
    model = tmp_path / "brake.py"
    shutil.copy(ROOT / "models" / "shoe_brake.py", model)
    cache = share_kernels(tmp_path / "cache")
    run(cache, "simulate", str(model), "--scene", "braking")
    text, probe = run(cache, "simulate", str(model), "--scene", "braking", "--param", "P=40")
    assert probe[0] == "True" and "t = 25 s" in text    # I omega0 / (2 f P R) = 1000 / P
    model.write_text(model.read_text().replace("P: 20", "P: 50"))
    text, probe = run(cache, "simulate", str(model), "--scene", "braking")
    assert probe[0] == "True" and "t = 20 s" in text
