"""The command line: `marraztu [MODEL ...]` opens the window; `screenshot`, `record` and `bench` are
subcommands.

Every error a person can cause (bad files, bad keys, no OpenGL, an output that cannot be written)
ends as one line on stderr naming the file (and line), and a non-zero exit: never a traceback.
Notices go to stderr once what they announce has happened.
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
import threading
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, NoReturn

import marraztu
from marraztu.errors import ViewerError, escaped, say, shortened

WINDOW_SIZE = (800, 800)
NO_DISPLAY_SHOT = Path("out") / "marraztu.png"
DESCRIPTION = ("A 3D viewer for learning computer graphics: textured models lit by ambient, diffuse "
               "and specular light from four lights, moved from the keyboard.")


class OneLineParser(argparse.ArgumentParser):
    """argparse's errors in one line, as the program's own: the usage is a --help away."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {escaped(message)} (see {self.prog} --help)\n")


def parse_size(text: str) -> tuple[int, int]:
    from marraztu.render.layout import parse_size as framebuffer_size

    try:
        return framebuffer_size(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def parse_fps(text: str) -> float:
    """--fps out of its range is a usage error, as --size out of its range is."""
    from marraztu.frontends.record import check_fps

    try:
        return check_fps(float(text), text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"frames a second must be a number, not {shortened(text)!r}") from None
    except ViewerError as error:
        raise argparse.ArgumentTypeError(str(error).removeprefix("--fps ")) from None


def user_path(text: str) -> Path:
    """A path as a person types it: `~` is their home, as in `f=~/model.obj` (a shell expands it only
    at a word's start, not in --output=~/shot.png)."""
    return Path(text).expanduser()


def add_scene_arguments(parser: argparse.ArgumentParser) -> None:
    group = parser.add_argument_group("the scene")
    group.add_argument("models", nargs="*", type=user_path, metavar="MODEL",
                       help="model files added to the scene as the `f` key adds them")
    source = group.add_mutually_exclusive_group()
    source.add_argument("--scene", type=user_path, metavar="FILE",
                        help="a TOML scene file instead of the built-in scene")
    source.add_argument("--empty", action="store_true", help="start with the camera alone")
    group.add_argument("--texture", type=user_path, metavar="PATH",
                       help="the texture image (PPM P6/P3, PNG, JPEG); default: the scene's own")


def add_size_argument(parser: argparse.ArgumentParser, what: str) -> None:
    parser.add_argument("--size", type=parse_size, default=WINDOW_SIZE, metavar="WxH",
                        help=f"{what} in pixels (default {WINDOW_SIZE[0]}x{WINDOW_SIZE[1]})")


def start_options(args: argparse.Namespace):
    from marraztu.control.viewer import StartOptions

    return StartOptions(scene_file=args.scene, empty=args.empty, texture=args.texture,
                        models=tuple(args.models), watch=getattr(args, "watch", False))


# --- the commands ----------------------------------------------------------------------------------
class VersionAction(argparse.Action):
    """--version, reading the installed version only when asked: importlib.metadata is slow to import."""

    def __init__(self, option_strings: Sequence[str], dest: str, **kwargs: Any) -> None:
        super().__init__(option_strings, dest, nargs=0, default=argparse.SUPPRESS,
                         help="show the program's version and exit")

    def __call__(self, parser: argparse.ArgumentParser, *_: Any) -> None:
        say(f"marraztu {marraztu.__version__}")
        parser.exit()


def window_parser() -> argparse.ArgumentParser:
    parser = OneLineParser(
        prog="marraztu", description=DESCRIPTION,
        usage="marraztu [--size WxH] [--watch] [--scene FILE | --empty] [--texture PATH] [MODEL ...]\n"
              "       marraztu COMMAND [options]   (marraztu COMMAND --help for its options)",
        epilog="commands:\n" + "\n".join(f"  {name:<12}{command.summary}" for name, command in COMMANDS.items())
               + "\n\nWith no display, the window's command writes a screenshot to "
               f"{NO_DISPLAY_SHOT} instead.",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action=VersionAction)
    add_size_argument(parser, "window size")
    parser.add_argument("--watch", action="store_true",
                        help="read a model, or the --scene file, again when its file changes on disk")
    add_scene_arguments(parser)
    return parser


def parse_command_line(parser: argparse.ArgumentParser, argv: Sequence[str]) -> argparse.Namespace:
    """Options and models in any order; every word after `--` is a model, even one named like an option
    (Python 3.11's parse_intermixed_args refuses it as an unrecognized argument)."""
    words = list(argv)
    after = words.index("--") if "--" in words else len(words)
    args = parser.parse_intermixed_args(words[:after])
    # Python 3.11 and 3.12 take the `--` out of `--output=--`, leaving an empty list as the value (3.13 keeps it).
    emptied = next((name for name, value in vars(args).items() if value == [] and name != "models"), None)
    if emptied is not None:
        parser.error(f"argument --{emptied}: expected one argument")
    args.models = [*args.models, *(user_path(word) for word in words[after + 1:])]
    return args


def run_window(argv: Sequence[str]) -> int:
    args = parse_command_line(window_parser(), argv)
    if not has_display():
        out = take_screenshot(start_options(args), NO_DISPLAY_SHOT, args.size)
        print(escaped(f"no display: wrote a screenshot of the scene to {out} instead"), file=sys.stderr)
        return 0
    from marraztu.frontends.window import run_window as open_window

    return open_window(start_options(args), args.size)


def has_display() -> bool:
    if sys.platform != "linux":
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def screenshot_parser() -> argparse.ArgumentParser:
    parser = OneLineParser(prog="marraztu screenshot", description=COMMANDS["screenshot"].summary)
    parser.add_argument("-o", "--output", type=user_path, required=True, metavar="PICTURE",
                        help="the picture to write: .png, .jpg or .jpeg")
    add_size_argument(parser, "picture size")
    parser.add_argument("--keys", default="", metavar="KEYS",
                        help='keys as typed, space separated: "0 1 F x*5 TAB ENTER f=model.obj"')
    parser.add_argument("--overlay", action="store_true",
                        help="draw the status line, the panels and the last message as the window does")
    add_scene_arguments(parser)
    return parser


def run_screenshot(argv: Sequence[str]) -> int:
    args = parse_command_line(screenshot_parser(), _keys_joined(argv))
    out = take_screenshot(start_options(args), args.output, args.size, args.keys, args.overlay)
    say(escaped(str(out)))
    return 0


def take_screenshot(options, out: Path, size: tuple[int, int], keys: str = "", overlay: bool = False) -> Path:
    from marraztu.frontends.screenshot import take_screenshot as shoot

    return shoot(options, out, size, keys, overlay)


def record_parser() -> argparse.ArgumentParser:
    parser = OneLineParser(prog="marraztu record", description=COMMANDS["record"].summary)
    parser.add_argument("-o", "--output", type=user_path, required=True, metavar="ANIMATION",
                        help="the animation to write: .gif (256 colours a frame), .png (animated PNG, "
                             "lossless) or .mp4 (with imageio-ffmpeg installed)")
    add_size_argument(parser, "frame size")
    parser.add_argument("--keys", required=True, metavar="KEYS",
                        help='keys as for screenshot; one frame is drawn after each press: "y*63"')
    parser.add_argument("--before", default="", metavar="KEYS",
                        help='keys as for --keys, pressed first and not recorded: "T 0 1 s TAB TAB"')
    parser.add_argument("--fps", type=parse_fps, default=20.0, metavar="N", help="frames a second (default 20)")
    parser.add_argument("--overlay", action="store_true",
                        help="draw the status line, the panels and the last message in every frame")
    add_scene_arguments(parser)
    return parser


def run_record(argv: Sequence[str]) -> int:
    from marraztu.frontends.record import record

    args = parse_command_line(record_parser(), _keys_joined(argv, ("--keys", "--before")))
    written = record(start_options(args), args.output, args.size, args.keys, args.fps, args.overlay, args.before)
    say(escaped(f"{args.output}: {written.said()}"))
    return 0


def _keys_joined(argv: Sequence[str], options: tuple[str, ...] = ("--keys",)) -> list[str]:
    """Each of these key `options` and its value as one word: argparse takes a value that starts with
    '-' ("-*5", the key `-` five times) for an option of its own."""
    words, at = [], 0
    while at < len(argv):
        if argv[at] == "--":
            return words + list(argv[at:])
        # --k too, as argparse: --keys and --before share no prefix
        named = [option for option in options if len(argv[at]) > 2 and option.startswith(argv[at])]
        if named and at + 1 < len(argv):
            words.append(f"{named[0]}={argv[at + 1]}")
            at += 2
            continue
        words.append(argv[at])
        at += 1
    return words


def run_bench(argv: Sequence[str]) -> int:
    from marraztu.devtools.bench import main as bench_main

    return bench_main(argv)


class Command:
    def __init__(self, summary: str, run: Callable[[Sequence[str]], int]) -> None:
        self.summary = summary
        self.run = run


COMMANDS = {
    "screenshot": Command("render the scene offscreen after replaying keys; no display needed",
                          run_screenshot),
    "record": Command("replay keys offscreen, one frame per press, into a GIF, PNG or MP4 animation",
                      run_record),
    "bench": Command("measure loading, frames, start-up and memory beside their peers", run_bench),
}


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    command = COMMANDS.get(argv[0]) if argv else None
    for stream in (sys.stdout, sys.stderr):  # a name the terminal's encoding lacks is escaped, not a traceback
        if hasattr(stream, "reconfigure"):
            stream.reconfigure(errors="backslashreplace")
    # `kill` or a closed terminal ends the run as Ctrl-C does: a file being written is taken away whole.
    before = signal.signal(signal.SIGTERM, _interrupted) if threading.current_thread() is threading.main_thread() \
        else None
    try:
        if command is None:
            _check_command_first(argv)
            return run_window(argv)
        return command.run(argv[1:])
    except ViewerError as error:
        print(f"error: {escaped(str(error))}", file=sys.stderr)
        return 1
    except KeyboardInterrupt as stop:
        return 128 + getattr(stop, "signal_number", signal.SIGINT)  # the shell's status for a run a signal ended
    finally:
        if before is not None:
            signal.signal(signal.SIGTERM, before)


class _Terminated(KeyboardInterrupt):
    """SIGTERM, unwound as Ctrl-C is, but told apart in the exit status (143, not 130)."""

    signal_number = signal.SIGTERM


def _interrupted(number: int, frame: object) -> NoReturn:
    raise _Terminated


def _check_command_first(argv: Sequence[str]) -> None:
    """`marraztu --empty screenshot -o a.png`: the command is a word the window's options do not take."""
    named = next((word for word in argv if word in COMMANDS and not Path(word).exists()), None)
    if named is not None:
        raise ViewerError(f"'{named}' is a command, and a command comes first: marraztu {named} [options]")
