"""The command line and the README's Python example, end to end at tiny sizes."""

import re
from pathlib import Path

import numpy as np
import pytest
from restircl import read_exr
from restircl.cli.arguments import settings_from_args
from restircl.cli.main import build_parser, main

ROOT = Path(__file__).resolve().parents[2]


def test_demo_writes_finite_exr_and_png(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["demo", "--width", "48", "--height", "27", "--frames", "3", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "device:" in text and "48x27" in text and "ms per frame" in text
    exrs = sorted(out.glob("*.exr"))
    assert len(exrs) == 3 and len(sorted(out.glob("*.png"))) == 3
    ch = read_exr(exrs[-1])
    for name in ("R", "G", "B", "A", "Depth.Z", "Normal.X", "Vector.X", "Noisy.R", "Albedo.G"):
        assert name in ch, name
        assert np.all(np.isfinite(ch[name])), name
    assert ch["R"].shape == (27, 48) and ch["R"].max() > 0


def test_render_still_scene_file_and_methods(tmp_path, capsys):
    scene = tmp_path / "box.npz"
    assert main(["save-scene", "cornell_box", str(scene), "--width", "24", "--height", "24"]) == 0
    for method in ("uniform", "light_array", "ris", "reference", "restir"):
        assert main(["render", str(scene), "--method", method, "--frames", "4", "--out", str(tmp_path)]) == 0
        assert (tmp_path / f"cornell_box_{method}.exr").exists()
    assert "4 samples" in capsys.readouterr().out


def test_bad_input_gives_a_clear_error_not_a_traceback(tmp_path, capsys):
    bad = tmp_path / "bad.npz"
    bad.write_bytes(b"nope")
    assert main(["render", str(bad)]) == 2
    assert "not a restircl scene file" in capsys.readouterr().err
    assert main(["render", "no_such_scene"]) == 2
    assert main(["render", "cornell_box", "--width", "8", "--height", "8", "--device", "no-such-device-xyz"]) == 2
    assert "no OpenCL device matches" in capsys.readouterr().err


BAD_NUMBERS = """
render cornell_box --width 0
render cornell_box --height -2
render cornell_box --frames -3
render cornell_box --frames 0
render cornell_box --target-error nan
render cornell_box --target-error 0
render cornell_box --candidates 0
render cornell_box --gamma inf
render cornell_box --neighbours 17
demo --frames 0
demo --width 1.5
save-scene cornell_box x.npz --width 0
bench frame --width 0
bench traversal --triangles -1
report cornell_box --budgets 1,nan
report cornell_box --budgets 0.5,-1
report cornell_box --every 0
report cornell_box --reference-seconds inf
report cornell_box --ms-per-frame 0
compare --budgets 1,0
compare --reps 0
compare --agreement-seconds nan
compare --max-bounces -1
compare --glossy-bounces 1025
stress --bench-frames 0
stress --seed -1
""".strip().splitlines()


@pytest.mark.parametrize("command", BAD_NUMBERS)
def test_numbers_out_of_range_are_argparse_errors_naming_the_option(command, capsys):
    """No number falls back to a default or renders something else silently: exit status 2 and the option named."""
    argv = command.split()
    with pytest.raises(SystemExit) as e:
        main(argv)
    assert e.value.code == 2
    flag = next(a for a in reversed(argv) if a.startswith("--"))
    err = capsys.readouterr().err
    assert f"argument {flag}: " in err and ("out of range" in err or "is not" in err), err


def test_every_setting_is_an_option():
    """The README's promise: every Settings field has a command-line flag, in render and demo."""
    from restircl import Settings
    from restircl.settings.spec import declared

    for cmd in (["render", "cornell_box"], ["demo"]):
        args = vars(build_parser().parse_args(cmd))
        assert set(Settings.names()) <= set(args), cmd
    s = settings_from_args(build_parser().parse_args(
        ["render", "x", "--depth-tolerance", "0.2", "--normal-angle", "30", "--max-history", "64",
         "--slots-per-light", "2", "--light-tile-count", "16", "--light-tile-size", "256",
         "--light-change-ratio", "0", "--no-jitter"]))
    assert (s.depth_tolerance, s.normal_angle, s.max_history, s.slots_per_light, s.light_tile_count,
            s.light_tile_size, s.light_change_ratio, s.jitter) == (0.2, 30.0, 64, 2.0, 16, 256, 0.0, False)
    assert all(d.spec.flag for d in declared(Settings))


def test_help_texts():
    for cmd in ("demo", "render", "devices", "bench", "save-scene", "compare"):
        with pytest.raises(SystemExit) as e:
            main([cmd, "--help"])
        assert e.value.code == 0


def test_devices_lists_the_choice(capsys):
    assert main(["devices"]) == 0
    assert "chosen:" in capsys.readouterr().out


def test_readme_python_example_runs(tmp_path, monkeypatch):
    text = (ROOT / "README.md").read_text()
    code = re.search(r"## Python\n\n```python\n(.*?)```", text, re.S).group(1)
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "README.md", "exec"), {})
    assert (tmp_path / "out" / "cornell.exr").exists()
