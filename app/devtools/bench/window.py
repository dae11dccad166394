"""6. The real window under Xvfb: the CPU it takes while nothing happens, how long a key takes to reach
the screen beside the frame it brings, and how long a load takes while a model is shown beside the
same load into an empty window. Each case runs the window in a fresh process on a private Xvfb."""

from __future__ import annotations

import json
import os
import shutil
import statistics
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from marraztu.devtools.bench.config import BenchConfig
from marraztu.devtools.bench.inputs import LoadInput
from marraztu.devtools.bench.report import markdown_table, number, progress, ratio

WINDOW_HEADERS = ("case", "measured", "beside", "ratio")
KEY_PRESSES = 8
LOAD_RUNS = 3  # loads with and without a model shown, taking turns: one of each varied from 0.55x to 1.1x here
WINDOW_SIZE = (800, 800)

# Runs in the window's own process; its events come from a thread, queued the way pyglet queues the
# window system's, so the loop answers them as it answers a person.
_WORKER = r'''
import json, statistics, sys, threading, time
from pathlib import Path
import pyglet.app
from marraztu.control.viewer import StartOptions
from marraztu.frontends.window import open_window

case, shown, other, idle_seconds, presses = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4]), int(sys.argv[5])
window = open_window(StartOptions(empty=True, models=(Path(shown),) if shown else ()), (800, 800))
frames = []  # (started, shown on screen, objects in the scene)
draw, swap = window.wnd.render_func, window.wnd.swap_buffers

def drawn(*args):
    frames.append([time.perf_counter(), None, None])
    draw(*args)

def swapped():
    swap()
    frames[-1][1:] = [time.perf_counter(), len(window.scene.objects)]  # what that frame showed

window.wnd.render_func, window.wnd.swap_buffers = drawn, swapped
pyglet_window = window.wnd._window

def send(*event):  # queued, then the loop woken from its wait, as the window system's events wake it
    pyglet_window.dispatch_event(*event)
    pyglet.app.platform_event_loop.notify()

def settled():  # loads done and on screen, then a moment of rest
    while window.viewer.loading_lines() or not frames or frames[-1][1] is None or (shown and not window.scene.objects):
        time.sleep(0.05)
    time.sleep(1.0)

def frame_after(count, started):
    while len(frames) <= count or frames[count][1] is None:
        time.sleep(0.001)
    return frames[count]

def script():
    settled()
    result = {}
    if case == "idle":
        cpu, wall = time.process_time(), time.perf_counter()
        time.sleep(idle_seconds)
        result["cpu_share"] = (time.process_time() - cpu) / (time.perf_counter() - wall)
    elif case in ("key", "camera key"):
        if case == "camera key":  # the camera targeted: y turns it in place, and no light is on to follow it
            send("on_text", "c")
            settled()
        latencies, draws = [], []
        for _ in range(presses):
            count, started = len(frames), time.perf_counter()
            send("on_text", "y")  # turns the model (every vertex is lit again) or the camera (none is)
            frame = frame_after(count, started)
            latencies.append(frame[1] - started)
            draws.append(frame[1] - frame[0])
            time.sleep(0.2)
        result["latency"], result["frame"] = statistics.median(latencies), statistics.median(draws)
    else:
        from marraztu.loaders.obj.fast import load_machine_code
        load_machine_code()  # as the shown model's load did: both drops then read alike
        objects, started = len(window.scene.objects), time.perf_counter()
        send("on_file_drop", 0, 0, [other])
        while len(window.scene.objects) <= objects:
            time.sleep(0.005)
        result["in_scene"] = time.perf_counter() - started
        while not frames or frames[-1][1] is None or frames[-1][2] <= objects:
            time.sleep(0.005)
        result["load"] = frames[-1][1] - started
    print(json.dumps(result), flush=True)
    window.wnd.is_closing = True

threading.Thread(target=script, daemon=True).start()
window.run()
'''


@contextmanager
def _xvfb() -> Iterator[str | None]:
    """A private X server's display name; None where there is no Xvfb."""
    if shutil.which("Xvfb") is None:
        yield None
        return
    read_end, write_end = os.pipe()
    server = subprocess.Popen(["Xvfb", "-displayfd", str(write_end), "-screen", "0", "1024x1024x24", "-nolisten",
                               "tcp"], pass_fds=[write_end], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(write_end)
    with os.fdopen(read_end) as pipe:
        display = pipe.readline().strip()
    try:
        yield f":{display}"
    finally:
        server.terminate()
        server.wait(timeout=10)


def _run(display: str, case: str, shown: Path | None, other: Path | None, idle_seconds: float = 0.0) -> dict:
    done = subprocess.run([sys.executable, "-c", _WORKER, case, str(shown or ""), str(other or ""),
                           str(idle_seconds), str(KEY_PRESSES)], env={**os.environ, "DISPLAY": display},
                          capture_output=True, text=True, timeout=900, check=False)
    if done.returncode != 0:
        raise RuntimeError(f"window worker ({case}) failed: {done.stderr.strip()[-300:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def window_section(config: BenchConfig, inputs: list[LoadInput]) -> list[str]:
    large, second = inputs[1], inputs[-1]  # the large v/vt/vn file, shown; the large v/f file, dropped
    head = ["## 6. The window under Xvfb", ""]
    with _xvfb() as display:
        if display is None:
            return [*head, "Skipped: no Xvfb on this machine (apt-get install xvfb).", ""]
        rows = []
        for label, shown in (("built-in scene", None), (large.label, large.path)):
            progress(f"window: idle CPU, {label}")
            share = _run(display, "idle", shown, None, config.idle_seconds)["cpu_share"]
            rows.append([f"idle CPU over {config.idle_seconds:g} s, {label}", f"{100 * share:.1f}% of a core",
                         "goal: under 1%", ""])
        progress("window: key to picture")
        key = _run(display, "key", large.path, None)
        rows.append([f"key to picture, {large.label} shown", f"{1000 * key['latency']:.0f} ms",
                     f"that frame alone {1000 * key['frame']:.0f} ms", ratio(key["latency"], key["frame"])])
        turn = _run(display, "camera key", large.path, None)
        rows.append([f"the camera's turn to picture, {large.label} shown", f"{1000 * turn['latency']:.0f} ms",
                     f"the model's turn {1000 * key['latency']:.0f} ms", ratio(turn["latency"], key["latency"])])
        progress("window: loading with and without a model shown")
        runs = [(_run(display, "load", None, second.path), _run(display, "load", large.path, second.path))
                for _ in range(LOAD_RUNS)]
        what = f"dropping {second.label} onto the window, {large.label} shown"
        for key, where in (("in_scene", "in the scene"), ("load", "on screen")):
            empty, busy = (statistics.median(pair[shown][key] for pair in runs) for shown in (0, 1))
            rows.append([f"{what}: {where}", f"{number(busy)} s", f"into an empty window {number(empty)} s",
                         ratio(busy, empty)])
    return [*head,
            f"Window {WINDOW_SIZE[0]}x{WINDOW_SIZE[1]}, one fresh process per case. *Key to picture*: from the "
            f"key event to the end of the buffer swap that shows it, median of {KEY_PRESSES} presses of `y` "
            "(the model turns: every vertex lit again), beside the time that frame took to draw and swap; "
            "then with the camera targeted (`c`), which `y` turns in place, and with no light on, no vertex is "
            "lit again. *Loading*: from the "
            "drop to the model joining the scene, and to the swap of the first frame that shows it (with a "
            f"model shown, that frame draws both), median of {LOAD_RUNS} processes each, taking turns; the "
            "compiled OBJ reader is loaded before the drop in both, as the shown model's load loads it.",
            "", *markdown_table(WINDOW_HEADERS, rows), ""]
