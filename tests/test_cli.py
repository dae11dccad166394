"""The command line as a person uses it: exit codes, one-line errors, no tracebacks, real PNGs."""

from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from marraztu.cli import parse_fps
from marraztu.control.keymap import parse_key_sequence
from marraztu.devtools.bench.config import parse_count
from marraztu.errors import shortened
from marraztu.model.scene import triple_refusal
from marraztu.render.layout import parse_size
from support.processes import buffered_environment
from support.scenes import BACKGROUND

ROOT = Path(__file__).resolve().parents[1]


def run_app(*args: str, cwd: Path = ROOT, env: dict | None = None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "marraztu", *args], cwd=cwd, capture_output=True,
                          text=True, timeout=120, env=env)


def assert_one_line_error(result: subprocess.CompletedProcess, *fragments: str) -> None:
    assert result.returncode != 0
    assert "Traceback" not in result.stderr
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1, result.stderr
    for fragment in fragments:
        assert fragment in lines[0]


def test_screenshot_writes_the_built_in_scene(tmp_path: Path) -> None:
    out = tmp_path / "shot.png"
    result = run_app("screenshot", "-o", str(out), "--size", "320x240")
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip().endswith("shot.png")
    pixels = np.asarray(Image.open(out).convert("RGB"))
    assert pixels.shape == (240, 320, 3)
    assert tuple(pixels[0, 0]) == BACKGROUND
    assert (np.abs(pixels.astype(int) - BACKGROUND).sum(axis=2) > 30).mean() > 0.01, "nothing drawn"


def test_screenshot_replays_keys_and_loads_models_from_the_command_line(tmp_path: Path) -> None:
    model = tmp_path / "tri.obj"
    model.write_text("v -50 -50 0\nv 50 -50 0\nv 0 50 0\nf 1 2 3\n")
    out = tmp_path / "shot.png"
    result = run_app("screenshot", "-o", str(out), "--size", "64x64", "--empty", "--keys", "T l",
                     str(model))
    assert result.returncode == 0, result.stderr
    pixels = np.asarray(Image.open(out).convert("RGB"))
    # Lines mode: the new object is selected, so its edges are green and nothing is filled.
    green = (pixels[..., 1] > 200) & (pixels[..., 0] < 50)
    assert green.any()
    assert tuple(pixels[32, 32]) == BACKGROUND


@pytest.mark.parametrize("content, fragment", [
    ("v 0 0 0\nv 1 0 0\nf 1 2 7\n", ":3:"),
    ("v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", ":1:"),
])
def test_screenshot_bad_model_is_one_line_naming_file_and_line(tmp_path: Path, content: str,
                                                               fragment: str) -> None:
    model = tmp_path / "bad.obj"
    model.write_text(content)
    result = run_app("screenshot", "-o", str(tmp_path / "x.png"), "--size", "32x32", str(model))
    assert_one_line_error(result, "bad.obj", fragment)
    assert not (tmp_path / "x.png").exists()


def test_no_dependency_speaks_where_no_bytecode_is_cached(tmp_path: Path) -> None:
    """Where Python finds no cached bytecode and may write none (a read-only install, pip --no-compile)
    it compiles every module it imports at every start, and a module's SyntaxWarning (an invalid
    escape, from Python 3.12) would land on stderr before our one line."""
    shot = tmp_path / "x.png"
    model = tmp_path / "bad.obj"
    model.write_text("v 0 0 0\nv 1 0 0\nf 1 2 7\n")
    for case, args in (("good", ("--keys", "T l g")), ("bad", (str(model),))):
        env = {**os.environ, "PYTHONPYCACHEPREFIX": str(tmp_path / case), "PYTHONDONTWRITEBYTECODE": "1",
               "PYTHONWARNINGS": ""}  # an empty cache, left empty; Python's default warning filters
        result = run_app("screenshot", "-o", str(shot), "--size", "32x32", *args, env=env)
        if case == "good":
            assert result.returncode == 0 and result.stderr == "", f"printed at start: {result.stderr}"
        else:
            assert_one_line_error(result, "bad.obj", ":3:")


def test_screenshot_missing_model(tmp_path: Path) -> None:
    result = run_app("screenshot", "-o", str(tmp_path / "x.png"), str(tmp_path / "nope.obj"))
    assert_one_line_error(result, "nope.obj")


def test_screenshot_bad_key(tmp_path: Path) -> None:
    result = run_app("screenshot", "-o", str(tmp_path / "x.png"), "--keys", "0 NOSUCHKEY")
    assert_one_line_error(result, "NOSUCHKEY")


def test_screenshot_bad_scene_file(tmp_path: Path) -> None:
    scene = tmp_path / "scene.toml"
    scene.write_text("[[objects]]\nmodel = 3\n")
    result = run_app("screenshot", "-o", str(tmp_path / "x.png"), "--scene", str(scene))
    assert_one_line_error(result, "scene.toml")


def test_screenshot_bad_named_texture(tmp_path: Path) -> None:
    texture = tmp_path / "broken.ppm"
    texture.write_bytes(b"P6\n4 4\n255\n\x00\x01")
    result = run_app("screenshot", "-o", str(tmp_path / "x.png"), "--texture", str(texture))
    assert_one_line_error(result, "broken.ppm")


def test_run_without_display_writes_a_screenshot(tmp_path: Path) -> None:
    env = {k: v for k, v in __import__("os").environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    result = run_app("--size", "64x64", cwd=tmp_path, env=env)
    assert result.returncode == 0, result.stderr
    assert result.stdout == "" and result.stderr.startswith("no display: wrote a screenshot")
    assert (tmp_path / "out" / "marraztu.png").exists()


def test_help_lists_the_commands_and_the_scene_options_but_no_window_toolkit_internals(tmp_path: Path) -> None:
    env = {k: v for k, v in __import__("os").environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    result = run_app("--help", cwd=tmp_path, env=env)
    assert result.returncode == 0 and result.stderr == ""
    assert result.stdout.startswith("usage: marraztu ")
    for word in ("screenshot", "bench", "--scene", "--empty", "--texture", "--size", "--version", "MODEL"):
        assert word in result.stdout, word
    for internal in ("-wnd", "-vs", "-hd", "__main__"):
        assert internal not in result.stdout, internal
    assert not (tmp_path / "out").exists(), "--help must not render anything"


def test_version(tmp_path: Path) -> None:
    result = run_app("--version", cwd=tmp_path)
    assert result.returncode == 0 and result.stdout.startswith("marraztu ") and result.stdout.count("\n") == 1


@pytest.mark.parametrize("output, fragment", [
    ("{tmp}", "picture"), ("{tmp}/x.bmp", ".png, .jpg"), ("{tmp}/no/such/../../x", ".png, .jpg"),
    ("/proc/marraztu-test.png", "cannot write"), ("", "picture"),
])
def test_screenshot_output_that_cannot_be_written_is_one_line(tmp_path: Path, output: str, fragment: str) -> None:
    result = run_app("screenshot", "-o", output.format(tmp=tmp_path), "--size", "16x16")
    assert_one_line_error(result, fragment)


def test_screenshot_writes_jpeg_for_a_jpeg_suffix(tmp_path: Path) -> None:
    out = tmp_path / "shot.jpg"
    result = run_app("screenshot", "-o", str(out), "--size", "32x24")
    assert result.returncode == 0, result.stderr
    with Image.open(out) as picture:
        assert picture.format == "JPEG" and picture.size == (32, 24)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="EGL through libglvnd: Linux")
def test_no_opengl_at_all_is_one_line_saying_what_to_install(tmp_path: Path) -> None:
    """libglvnd's EGL with no vendor library to load, and no display: as on a machine without libegl1."""
    env = {**os.environ, "__EGL_VENDOR_LIBRARY_FILENAMES": str(tmp_path / "none.json")}
    env.pop("DISPLAY", None)
    env.pop("WAYLAND_DISPLAY", None)
    result = run_app("screenshot", "-o", str(tmp_path / "shot.png"), "--size", "8x8", cwd=tmp_path, env=env)
    if result.returncode == 0:
        pytest.skip("this machine's EGL is not libglvnd's: it drew without a vendor library")
    assert_one_line_error(result, "cannot create an offscreen OpenGL 3.3 context",
                          "apt-get install libegl1 libgl1-mesa-dri")


def test_an_unreachable_display_is_one_line_saying_what_is_wrong_and_what_to_do(tmp_path: Path) -> None:
    """It said 'cannot open a window on :97531 (Cannot connect to "None")': pyglet's words, naming no display."""
    env = {**__import__("os").environ, "DISPLAY": ":97531"}
    env.pop("WAYLAND_DISPLAY", None)
    result = run_app("--size", "64x64", cwd=tmp_path, env=env)
    assert_one_line_error(result, "error: cannot open a window on :97531: no X server there accepts a connection; "
                                  "without a display, `marraztu screenshot -o shot.png` draws offscreen")
    assert "None" not in result.stderr


def test_a_wayland_display_alone_says_the_window_needs_an_x_server(tmp_path: Path) -> None:
    """pyglet 2.1 opens X windows only: it said 'cannot open a window on wayland-0 (Cannot connect to "None")'."""
    env = {**__import__("os").environ, "WAYLAND_DISPLAY": "wayland-97531"}
    env.pop("DISPLAY", None)
    result = run_app("--size", "64x64", cwd=tmp_path, env=env)
    assert_one_line_error(result, "cannot open a window: it needs an X server, and DISPLAY is not set")


def test_keys_that_start_with_a_minus_models_after_options_and_a_home_path(tmp_path: Path,
                                                                           monkeypatch: pytest.MonkeyPatch) -> None:
    """`--keys "-*5"` is the key `-` five times, not an option (argparse refused it); a model may follow
    an option; `~` in --output=~/x.png (which no shell expands) is the home folder, as in f=~/model.obj."""
    from marraztu.cli import main

    model = tmp_path / "tri.obj"
    model.write_text("v -50 -50 0\nv 50 -50 0\nv 0 50 0\nf 1 2 3\n")
    monkeypatch.setenv("HOME", str(tmp_path))
    assert main(["screenshot", "--keys", "c c -*5", "-o=~/split.png", "--size", "32x32", str(model)]) == 0
    joined = ["screenshot", str(model), "--keys=c c -*5", "-o", str(tmp_path / "joined.png"), "--size", "32x32"]
    assert main(joined) == 0
    assert main(["screenshot", "--ke", "c c -*5", "-o", str(tmp_path / "short.png"), "--size=32x32", str(model)]) == 0
    names = ("split.png", "joined.png", "short.png")
    split, joined, short = (np.asarray(Image.open(tmp_path / name)) for name in names)
    assert np.array_equal(split, joined) and np.array_equal(split, short) and (split != split[0, 0]).any()
    # `--k`, the shortest prefix argparse takes for --keys, with keys that start with a minus
    assert main(["screenshot", "--k", "-*5", "-o", str(tmp_path / "k.png"), "--size=32x32", str(model)]) == 0
    assert main(["screenshot", "--keys=-*5", "-o", str(tmp_path / "keys.png"), "--size=32x32", str(model)]) == 0
    assert np.array_equal(*(np.asarray(Image.open(tmp_path / name)) for name in ("k.png", "keys.png")))


def test_words_after_a_double_dash_are_models_even_named_like_options(tmp_path: Path,
                                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    """`marraztu screenshot -o a.png -- -x.obj` loads the model `-x.obj` (Python 3.11's intermixed parsing
    refused it as an unrecognized argument)."""
    from marraztu.cli import main

    (tmp_path / "-x.obj").write_text("v -50 -50 0\nv 50 -50 0\nv 0 50 0\nf 1 2 3\n")
    monkeypatch.chdir(tmp_path)
    assert main(["screenshot", "-o", "dashed.png", "--size", "32x32", "--empty", "--", "-x.obj"]) == 0
    assert main(["screenshot", "-o", "dotted.png", "--size", "32x32", "--empty", "./-x.obj"]) == 0
    assert main(["record", "--keys", "y", "-o", "dashed.gif", "--size", "8x8", "--", "-x.obj"]) == 0
    dashed, dotted = (np.asarray(Image.open(tmp_path / name)) for name in ("dashed.png", "dotted.png"))
    assert np.array_equal(dashed, dotted) and (dashed != dashed[0, 0]).any()
    from marraztu.cli import parse_command_line, window_parser

    args = parse_command_line(window_parser(), ["a.obj", "--size", "8x8", "--", "-x.obj", "--empty"])
    assert args.models == [Path("a.obj"), Path("-x.obj"), Path("--empty")] and not args.empty


@pytest.mark.parametrize("arguments", [
    ["screenshot", "-o", "a.png", "--output=--"], ["screenshot", "-o--"], ["screenshot", "-o", "a.png", "--keys", "--"],
    ["screenshot", "-o", "a.png", "--size=--"], ["record", "-o", "a.gif", "--keys", "y", "--fps=--"],
    ["--texture=--"], ["--scene=--"],
])
def test_an_option_given_only_a_double_dash_is_a_usage_error(tmp_path: Path, capsys, monkeypatch: pytest.MonkeyPatch,
                                                             arguments: list[str]) -> None:
    """Python 3.11 and 3.12 strip the `--` of `--output=--` and leave an empty list as the value: a traceback.
    Python 3.13 keeps `--` as the value, refused as the file, keys, size or rate it names."""
    from marraztu.cli import main

    monkeypatch.chdir(tmp_path)
    try:
        code = main(arguments)
    except SystemExit as stop:
        code = stop.code
    error = capsys.readouterr().err
    assert code != 0 and error.count("\n") == 1 and "Traceback" not in error, error
    if sys.version_info < (3, 13):
        assert code == 2 and "expected one argument" in error, error
    else:
        assert "'--'" in error or "error: --:" in error, error
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("arguments, words", [
    (["--empty", "screenshot", "-o", "{tmp}/a.png"], "'screenshot' is a command, and a command comes first"),
    (["screenshot", "-o", "{tmp}/file.txt/a.png"], "file.txt is not a folder"),
])
def test_misplaced_commands_and_outputs_under_a_file_are_one_line(tmp_path: Path, capsys, arguments: list[str],
                                                                  words: str) -> None:
    from marraztu.cli import main

    (tmp_path / "file.txt").write_text("")
    assert main([word.format(tmp=tmp_path) for word in arguments]) == 1
    error = capsys.readouterr().err.strip()
    assert error.startswith("error:") and "\n" not in error and words in error, error


def test_standard_output_full_or_closed_is_no_traceback(tmp_path: Path) -> None:
    with open("/dev/full", "w") as full:
        result = subprocess.run([sys.executable, "-m", "marraztu", "screenshot", "-o", str(tmp_path / "a.png"),
                                 "--size", "16x16", "--empty"], stdout=full, stderr=subprocess.PIPE, text=True,
                                timeout=120, env=buffered_environment())
    assert result.returncode == 1 and result.stderr.strip() == (
        "error: cannot write to standard output (No space left on device)")
    assert (tmp_path / "a.png").exists()


def test_the_version_to_a_full_or_closed_output_is_no_traceback() -> None:
    version = [sys.executable, "-m", "marraztu", "--version"]
    with open("/dev/full", "w") as full:
        result = subprocess.run(version, stdout=full, stderr=subprocess.PIPE, text=True, timeout=120,
                                env=buffered_environment())
    assert result.returncode == 1 and result.stderr.strip() == (
        "error: cannot write to standard output (No space left on device)")
    reader, writer = os.pipe()
    os.close(reader)  # `marraztu --version | true`: the reader is gone before the line is written
    try:
        result = subprocess.run(version, stdout=writer, stderr=subprocess.PIPE, text=True, timeout=120,
                                env=buffered_environment())
    finally:
        os.close(writer)
    assert result.returncode == 0 and result.stderr == ""


def test_a_usage_error_is_one_line_too(tmp_path: Path) -> None:
    result = run_app("screenshot", "-o", str(tmp_path / "a.png"), "--size", "0x0")
    assert result.returncode == 2 and result.stderr.count("\n") == 1
    assert result.stderr.startswith("marraztu screenshot: error: argument --size:")
    assert result.stderr.rstrip().endswith("(see marraztu screenshot --help)")


def test_a_failed_write_takes_away_the_folders_it_made(tmp_path: Path) -> None:
    from marraztu.errors import ViewerError
    from marraztu.frontends.screenshot import write_atomically

    def full(temporary: Path) -> None:
        raise OSError(28, "No space left on device")

    with pytest.raises(ViewerError, match="No space left on device"):
        write_atomically(tmp_path / "new" / "deeper" / "shot.png", full)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(("number", "status"), [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_signal_ends_a_run_with_the_shells_status(monkeypatch: pytest.MonkeyPatch, number: int, status: int) -> None:
    """Ctrl-C and `kill` both unwind the run (a file being written is taken away), each with its own status."""
    from marraztu import cli

    def signalled(argv: object) -> int:
        os.kill(os.getpid(), number)
        time.sleep(30)  # the handler interrupts this
        return 0

    monkeypatch.setitem(cli.COMMANDS, "screenshot", cli.Command("test", signalled))
    assert cli.main(["screenshot"]) == status



LONG = "9" * 30 + "x" * 70  # a hundred characters: a paste gone wrong


@pytest.mark.parametrize(("refusal", "text"), [
    (parse_fps, LONG), (parse_size, LONG), (parse_key_sequence, f"y*{LONG}"),
    (parse_key_sequence, f"y*{'9' * 100}"), (parse_key_sequence, f"'{LONG}"), (parse_count, LONG),
], ids=["--fps", "--size", "an unknown key", "a repeat count", "an unclosed quote", "the bench's --sizes"])
def test_a_long_word_is_quoted_shortened_with_its_length(refusal: Callable[[str], object], text: str) -> None:
    """These cut the word at 40 characters without a sign (or not at all), where the loaders say
    '...' and how long it is."""
    with pytest.raises(Exception) as caught:
        refusal(text)
    message = str(caught.value)
    assert f"... ({len(text)} characters)" in message and "9" * 20 in message, message
    assert "x" * 20 not in message and "9" * 50 not in message


@pytest.mark.parametrize("text", ["9" * 5000, "1e999", "-1e999"])
def test_an_fps_too_large_for_a_float_is_said_as_typed(text: str) -> None:
    """float() reads it as infinity, which the message showed: '--fps: must be 0.02 to 100, not inf'."""
    with pytest.raises(argparse.ArgumentTypeError) as caught:
        parse_fps(text)
    assert str(caught.value) == f"must be 0.02 to 100, not {shortened(text)}", caught.value


def test_a_long_value_given_for_a_point_is_shortened_with_its_length() -> None:
    said = triple_refusal(list(range(60)), "x, y, z")
    assert said is not None and said.startswith("must be 3 numbers (x, y, z), not [0, 1, 2,") and "characters)" in said
