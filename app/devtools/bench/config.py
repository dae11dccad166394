"""What a bench run measures: sizes, resolutions, repeats and sections, from the command line."""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

from marraztu.errors import shortened

SECTIONS = ("load", "frames", "cpu", "start", "memory", "shapes", "window")
LOADERS = ("ours", "trimesh", "tinyobjloader", "rapidobj")


@dataclass(frozen=True)
class BenchConfig:
    load_sizes: tuple[int, int]  # triangles of the small v/vt/vn file, and of every large file
    frame_sizes: tuple[int, ...]  # triangles of the generated meshes drawn (besides the built-in scene)
    resolutions: tuple[tuple[int, int], ...]
    frames: int  # measured frames per case, at most
    warmup: int
    frame_budget_s: float  # a case stops early (after MIN_FRAMES) once it has taken this long
    repeats: int  # loads per (loader, file) process
    rounds: int  # processes per (loader, file), the loaders taking turns; the median of all loads is reported
    start_runs: int
    cpu_frames: int
    objects: int  # placements of one model in the CPU section's scene of many objects
    shape_megabytes: int  # the size of each input shaped to break linear cost
    idle_seconds: float  # how long the window is left alone while its CPU is measured
    load_pause_s: float  # how long a process waits before its load after a pause
    sections: tuple[str, ...]
    loaders: tuple[str, ...]
    workdir: Path | None = None


DEFAULT_CONFIG = BenchConfig(
    load_sizes=(100_000, 1_000_000), frame_sizes=(100_000, 1_000_000, 5_000_000),
    resolutions=((1280, 720), (1920, 1080)), frames=10, warmup=1, frame_budget_s=5.0, repeats=3, rounds=3,
    start_runs=3, cpu_frames=100, objects=1000, shape_megabytes=50, idle_seconds=10.0, load_pause_s=4.0,
    sections=SECTIONS, loaders=LOADERS)
QUICK_CONFIG = replace(
    DEFAULT_CONFIG, load_sizes=(10_000, 50_000), frame_sizes=(20_000,), resolutions=((1280, 720),),
    frames=5, warmup=1, frame_budget_s=1.0, repeats=1, rounds=1, start_runs=1, cpu_frames=30, objects=200,
    shape_megabytes=5, idle_seconds=2.0, load_pause_s=1.0)


# The largest generated mesh: 100M triangles take tens of GB in the bench's own tables already.
MAX_TRIANGLES = 100_000_000


def parse_count(text: str) -> int:
    """'100k', '1M', '5m', '2500' -> triangles."""
    multipliers = {"k": 1_000, "m": 1_000_000}
    text = text.strip().lower()
    scale = multipliers.get(text[-1:], 1)
    try:
        value = float(text[:-1] if scale != 1 else text) * scale
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a size: {shortened(text)!r} (e.g. 100k, 1m, 2500)") from None
    if not 2 <= value <= MAX_TRIANGLES:  # NaN fails too
        raise argparse.ArgumentTypeError(f"size {shortened(text)!r}: from 2 triangles to {MAX_TRIANGLES:,}")
    return int(value)


def parse_counts(text: str) -> tuple[int, ...]:
    return tuple(parse_count(part) for part in text.split(",") if part.strip())


def parse_resolutions(text: str) -> tuple[tuple[int, int], ...]:
    from marraztu.render.layout import parse_size

    try:
        return tuple(parse_size(part) for part in text.split(",") if part.strip())
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def parse_choices(allowed: Sequence[str]) -> Callable[[str], tuple[str, ...]]:
    def parse(text: str) -> tuple[str, ...]:
        chosen = tuple(part.strip() for part in text.split(",") if part.strip())
        unknown = [name for name in chosen if name not in allowed]
        if unknown:
            raise argparse.ArgumentTypeError(f"unknown {', '.join(unknown)}; choose from {', '.join(allowed)}")
        return chosen
    return parse


def bench_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="marraztu bench",
        description="Measure loading, frames, start-up and memory on generated inputs; print Markdown.")
    parser.add_argument("--quick", action="store_true", help="small sizes, one resolution: a few minutes on two cores")
    parser.add_argument("--sizes", type=parse_counts, metavar="LIST",
                        help="triangles of the drawn meshes, e.g. 100k,1m,5m (the default)")
    parser.add_argument("--skip-5m", action="store_true", help="leave out drawn meshes of 5M triangles and more")
    parser.add_argument("--load-sizes", type=parse_counts, metavar="SMALL,LARGE",
                        help="triangles of the small and the large OBJ files (default 100k,1m)")
    parser.add_argument("--resolutions", type=parse_resolutions, metavar="LIST",
                        help="framebuffer sizes, e.g. 1280x720,1920x1080 (the default)")
    parser.add_argument("--frames", type=int, metavar="N", help="measured frames per case (default 10)")
    parser.add_argument("--warmup", type=int, metavar="N", help="frames drawn before measuring (default 1)")
    parser.add_argument("--frame-budget", type=float, metavar="S", dest="frame_budget_s",
                        help="seconds after which a case stops at 3 frames (default 5)")
    parser.add_argument("--repeats", type=int, metavar="N", help="loads per process (default 3)")
    parser.add_argument("--rounds", type=int, metavar="N",
                        help="processes per loader and file, the loaders taking turns (default 3)")
    parser.add_argument("--start-runs", type=int, metavar="N", help="runs of each start command (default 3)")
    parser.add_argument("--cpu-frames", type=int, metavar="N", help="frames timed for CPU per frame (default 100)")
    parser.add_argument("--objects", type=int, metavar="N",
                        help="placements of one model in the CPU per frame of many objects (default 1000)")
    parser.add_argument("--shape-megabytes", type=int, metavar="N",
                        help="size of each input shaped to break linear cost (default 50)")
    parser.add_argument("--idle-seconds", type=float, metavar="S",
                        help="how long the window is left alone while its CPU is measured (default 10)")
    parser.add_argument("--load-pause", type=float, metavar="S", dest="load_pause_s",
                        help="how long a process waits before its load after a pause (default 4)")
    parser.add_argument("--sections", type=parse_choices(SECTIONS), metavar="LIST",
                        help=f"which sections to run (default all: {','.join(SECTIONS)})")
    parser.add_argument("--loaders", type=parse_choices(LOADERS), metavar="LIST",
                        help=f"loaders compared (default all: {','.join(LOADERS)})")
    parser.add_argument("--workdir", type=Path, metavar="DIR",
                        help="write the generated files here and keep them (default: a temporary folder)")
    return parser


def config_from_args(argv: Sequence[str]) -> BenchConfig:
    parser = bench_parser()
    args = parser.parse_args(list(argv))
    config = QUICK_CONFIG if args.quick else DEFAULT_CONFIG
    overrides = {name: value for name, value in vars(args).items()
                 if name not in ("quick", "skip_5m") and value is not None}
    if "load_sizes" in overrides and len(overrides["load_sizes"]) != 2:
        parser.error("--load-sizes takes two sizes: SMALL,LARGE")
    config = replace(config, **{("frame_sizes" if name == "sizes" else name): value
                                for name, value in overrides.items()})
    if args.skip_5m:
        config = replace(config, frame_sizes=tuple(n for n in config.frame_sizes if n < 5_000_000))
    if min(config.frames, config.repeats, config.rounds, config.start_runs, config.cpu_frames, config.objects,
           config.shape_megabytes) < 1 or config.warmup < 1 or not 0 < config.idle_seconds < math.inf \
            or not 0 <= config.load_pause_s < math.inf or not 0 < config.frame_budget_s < math.inf:
        parser.error("--frames, --warmup, --repeats, --rounds, --start-runs, --cpu-frames, --objects and "
                     "--shape-megabytes must be at least 1, --idle-seconds and --frame-budget more than 0 and "
                     "--load-pause at least 0, all finite")
    return config
