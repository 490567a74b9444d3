"""The `mechdyn` command: help, model listing, exit codes, one-line errors, --debug."""
import csv
import textwrap
from pathlib import Path

import pytest

from mechdyn import cli
from mechdyn.cli import model_commands

ROOT = Path(__file__).resolve().parents[1]
BRAKE = str(ROOT / "models" / "shoe_brake.py")

# A disc driven by a moment growing with the square of its speed: omega' = omega^2
# runs away to infinity at t = 1 / omega_0 = 1 s, so the integration must fail.
RUNAWAY = textwrap.dedent('''
    """Runaway disc: the drive grows with the square of the speed."""
    import mechdyn as md
    phi = md.coordinate("phi")
    mechanism = md.Mechanism("Runaway", [phi])
    mechanism.link("disc", J=1, angle=phi)
    mechanism.load("drive", md.speed(phi) ** 2, along=phi)
    params = {}
    scenes = {"run": md.Scene("run", initial={phi: 0, md.speed(phi): 1}, t_end=2)}
''')


def run(capsys, *argv):
    """Exit status, stdout and stderr of `mechdyn argv`."""
    try:
        status = cli.main(list(argv))
    except SystemExit as exit_:          # argparse: --help and usage errors
        status = exit_.code
    out, err = capsys.readouterr()
    return status, out, err


def test_help_lists_every_command_with_examples_and_exit_codes(capsys):
    status, out, _ = run(capsys, "--help")
    assert status == 0
    for command in ("models", "equations", "simulate", "report", "sweep"):
        assert command in out
    assert "exit status" in out and "examples" in out
    for command in ("models", "equations", "simulate", "report", "sweep"):
        status, out, _ = run(capsys, command, "--help")
        assert status == 0 and "examples:" in out and f"mechdyn {command}" in out


@pytest.mark.slow        # reads all 21 model files (5 s); the quick loop finds them by name
def test_models_lists_the_bundled_models_with_scenes_and_descriptions(capsys, monkeypatch):
    monkeypatch.chdir(ROOT)
    status, out, _ = run(capsys, "models")                  # bundled: by name
    assert status == 0
    assert "\nshoe_brake  Shoe brake (worked example 1): a disc braked by a " \
           "lever-pressed shoe." in out
    assert "scenes: braking" in out and "scenes: startup, braking" in out
    status, out, _ = run(capsys, "models", "models")        # a folder: by path
    assert status == 0 and "models/shoe_brake.py  Shoe brake" in out


def test_models_of_a_missing_folder_says_so_in_one_line(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    status, out, err = run(capsys, "models", "models")
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and "no folder models in" in err and "mechdyn models DIR" in err


def test_usage_and_input_errors_exit_2_with_one_line(capsys):
    cases = [("simulate", BRAKE, "--scene", "nope"),                     # unknown scene
             ("simulate", str(ROOT / "models" / "missing.py"), "--scene", "x"),
             ("simulate", BRAKE, "--scene", "braking", "--param", "P=__import__('os')"),
             ("simulate", BRAKE, "--scene", "braking", "--param", "Q=1"),
             ("sweep", BRAKE, "--scene", "braking", "--grid", "P=1:2:2.5")]
    for argv in cases:
        status, _, err = run(capsys, *argv)
        assert status == 2, argv
        assert err.startswith("mechdyn: error: ") and err.count("\n") == 1, err
        assert "Traceback" not in err
    status, _, err = run(capsys, "simulate", BRAKE)          # argparse: --scene missing
    assert status == 2 and "--scene" in err


@pytest.mark.parametrize("where", ["before", "after"])
def test_debug_shows_the_traceback_before_or_after_the_command(capsys, where):
    argv = ["simulate", BRAKE, "--scene", "nope"]
    argv = ["--debug", *argv] if where == "before" else [*argv, "--debug"]
    status, _, err = run(capsys, *argv)
    assert status == 2
    assert "Traceback (most recent call last)" in err and "no scene 'nope'" in err


def test_a_failed_simulation_exits_1_and_keeps_the_partial_result(capsys, tmp_path):
    model = tmp_path / "runaway.py"
    model.write_text(RUNAWAY)
    partial = tmp_path / "partial.csv"
    status, _, err = run(capsys, "simulate", str(model), "--scene", "run", "--csv", str(partial))
    assert status == 1
    assert "mechdyn: simulation failed: integration failed" in err
    with open(partial, newline="") as handle:
        times = [float(row["t"]) for row in csv.DictReader(handle)]
    assert 0.5 < times[-1] < 1.0 + 1e-6            # it got close to the blow-up at 1 s


def test_an_internal_error_exits_3_with_a_hint(capsys, monkeypatch):
    def broken(args):
        raise RuntimeError("something mechdyn did not expect")
    monkeypatch.setattr(model_commands, "_models", broken)
    status, _, err = run(capsys, "models")
    assert status == 3
    assert err.strip() == ("mechdyn: internal error: RuntimeError: something mechdyn did "
                           "not expect (rerun with --debug for the traceback)")


def test_simulate_writes_the_summary_plot_and_csv(capsys, tmp_path):
    pytest.importorskip("matplotlib")
    plot, table = tmp_path / "brake.png", tmp_path / "brake.csv"
    status, out, _ = run(capsys, "simulate", BRAKE, "--scene", "braking", "--param", "P=40",
                         "--plot", str(plot), "--csv", str(table))
    assert status == 0
    assert "ended at t = 25 s" in out                   # 1000 / P
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and table.stat().st_size > 100


def test_sweep_command_streams_rows_and_plots(capsys, tmp_path):
    pytest.importorskip("matplotlib")
    out_file, plot = tmp_path / "brake.csv", tmp_path / "stop.png"
    status, out, _ = run(capsys, "sweep", BRAKE, "--scene", "braking", "--grid", "P=10:40:4",
                         "--workers", "2", "--out", str(out_file), "--plot", str(plot))
    assert status == 0
    with open(out_file, newline="") as handle:
        rows = {float(r["P"]): float(r["t_end"]) for r in csv.DictReader(handle)}
    assert rows == pytest.approx({10.0: 100.0, 20.0: 50.0, 30.0: 1000 / 30, 40.0: 25.0},
                                 rel=1e-9)
    assert "33.3333" in out and plot.read_bytes()[:4] == b"\x89PNG"


def test_a_sweep_with_a_failed_point_exits_1(capsys, tmp_path):
    status, out, err = run(capsys, "sweep", BRAKE, "--scene", "braking", "--grid",
                           "I=0.4,-0.4", "--workers", "1")
    assert status == 1
    assert "1 of 2 points failed" in err and "ParameterError" in out
