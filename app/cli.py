"""Command line: `python -m app [OBJ ...]` opens the window; `screenshot` renders offscreen.

Every error a person can cause (bad files, bad keys, no EGL) ends as one line on stderr naming the
file (and line), and a non-zero exit: never a traceback.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from app.errors import ViewerError

DEFAULT_SIZE = (800, 800)
NO_DISPLAY_SHOT = Path("out") / "marraztu.png"


def parse_size(text: str) -> tuple[int, int]:
    try:
        width, height = (int(part) for part in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"size must look like 800x600, not {text!r}") from None
    if not (1 <= width <= 16384 and 1 <= height <= 16384):
        raise argparse.ArgumentTypeError(f"size {width}x{height} is out of range 1..16384")
    return width, height


def add_scene_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("models", nargs="*", type=Path, metavar="OBJ",
                        help="OBJ files added to the scene as the `f` key would add them")
    source = parser.add_mutually_exclusive_group()
    source.add_argument("--scene", type=Path, metavar="FILE",
                        help="a TOML scene file instead of the built-in scene")
    source.add_argument("--empty", action="store_true", help="start with the camera alone")
    parser.add_argument("--texture", type=Path, metavar="PATH",
                        help="the texture image (PPM P6/P3, PNG, JPEG); default: the scene's selfi.ppm")


def start_options(args: argparse.Namespace):
    from app.viewer import StartOptions

    return StartOptions(scene_file=args.scene, empty=args.empty, texture=args.texture,
                        models=tuple(args.models))


def screenshot_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="marraztu screenshot",
        description="Render the scene offscreen (EGL, no display needed) after replaying keys.")
    parser.add_argument("-o", "--output", type=Path, required=True, help="the PNG to write")
    parser.add_argument("--size", type=parse_size, default=DEFAULT_SIZE, metavar="WxH",
                        help="image size (default 800x800)")
    parser.add_argument("--keys", default="", metavar="KEYS",
                        help='keys as typed, space separated: "0 1 F x*5 TAB ENTER f=model.obj"')
    parser.add_argument("--overlay", action="store_true",
                        help="draw the status line and the last message as the window does")
    add_scene_arguments(parser)
    return parser


def run_screenshot(argv: list[str]) -> int:
    args = screenshot_parser().parse_args(argv)
    from app.screenshot import take_screenshot

    out = take_screenshot(start_options(args), args.output, args.size, args.keys, args.overlay)
    print(out)
    return 0


def has_display() -> bool:
    if sys.platform != "linux":
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def run_window(argv: list[str]) -> int:
    if not has_display():
        print(f"no display: wrote a screenshot of the scene instead: {NO_DISPLAY_SHOT}")
        return run_screenshot(["-o", str(NO_DISPLAY_SHOT), *argv])
    from app.window import run

    return run(argv)


def run_bench(argv: list[str]) -> int:
    from app.bench import main as bench_main

    return bench_main(argv)


SUBCOMMANDS = {"screenshot": run_screenshot, "bench": run_bench}


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    command = SUBCOMMANDS.get(argv[0]) if argv else None
    try:
        if command is not None:
            return command(argv[1:])
        return run_window(argv)
    except ViewerError as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130
