"""The bench's output: the machine it ran on, and figures as Markdown tables on stdout, progress on stderr."""

from __future__ import annotations

import os
import platform
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from marraztu.errors import say

if TYPE_CHECKING:
    import moderngl

    from marraztu.devtools.bench.config import BenchConfig

MEGABYTE = 1 << 20
MISSING = "—"
MACHINE_HEADING = "## Machine"


def machine_lines(ctx: moderngl.Context | None, config: BenchConfig) -> list[str]:
    import moderngl

    cores = os.cpu_count()
    usable = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else cores
    memory_gb = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 1e9 if hasattr(os, "sysconf") else 0
    info = ctx.info if ctx is not None else {}
    lines = [
        MACHINE_HEADING,
        "",
        f"- CPU: {_cpu_model()}, {cores} cores ({usable} usable), {memory_gb:.0f} GB memory",
        f"- GL_RENDERER: {info.get('GL_RENDERER', 'no context')}; GL_VERSION: {info.get('GL_VERSION', '-')}",
        f"- Python {platform.python_version()}, numpy {np.__version__}, moderngl {moderngl.__version__}",
        f"- load average at start: {load_average()} (other processes share the cores: expect noise)",
        f"- sections: {', '.join(config.sections)}; OBJ files of {count_label(config.load_sizes[0])} and "
        f"{count_label(config.load_sizes[1])} triangles (the latter as binary STL, PLY and GLB too, the former "
        f"as ASCII STL, ASCII PLY and OFF); drawn grids: "
        f"{', '.join(count_label(n) for n in config.frame_sizes) or 'none'}; sizes: "
        f"{', '.join(f'{w}x{h}' for w, h in config.resolutions)}",
    ]
    return lines


def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def load_average() -> str:
    try:
        return " ".join(f"{value:.2f}" for value in os.getloadavg())
    except OSError:
        return "unknown"


def markdown_table(headers: Sequence[str], rows: Sequence[Sequence[str]]) -> list[str]:
    lines = ["| " + " | ".join(headers) + " |", "|" + "|".join("---" for _ in headers) + "|"]
    return lines + ["| " + " | ".join(row) + " |" for row in rows]


def number(value: float | None) -> str:
    """Three significant figures, never in exponent form (the README reads better)."""
    if value is None:
        return MISSING
    magnitude = abs(value)
    if magnitude >= 100:
        return f"{value:.0f}"
    if magnitude >= 10:
        return f"{value:.1f}"
    if magnitude >= 1:
        return f"{value:.2f}"
    return f"{value:.3g}"


def ratio(value: float | None, reference: float | None) -> str:
    """Two decimals; below 0.01 (a C parser beside ours on a tiny file), three significant figures, not 0.00."""
    if value is None or not reference:
        return MISSING
    quotient = value / reference
    return f"{quotient:.2f}" if abs(quotient) >= 0.01 else number(quotient)


def count_label(count: int) -> str:
    if count >= 1_000_000 and count % 100_000 == 0:
        return f"{count / 1_000_000:g}M"
    if count >= 1_000 and count % 100 == 0:
        return f"{count / 1_000:g}k"
    return str(count)


def progress(message: str) -> None:
    print(f"[bench] {message}", file=sys.stderr, flush=True)


def emit(lines: Sequence[str]) -> None:
    if not say("\n".join(lines) + "\n"):
        raise SystemExit(0)  # the reader has gone (`marraztu bench | head`): measuring on would be for no one
