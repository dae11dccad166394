"""`marraztu record` and the window's F9: one picture per key press, written as an animation.

GIF and animated PNG come from Pillow (the PNG is lossless, the GIF has 256 colours a frame); MP4
needs imageio-ffmpeg, imported only for such a file.
"""

from __future__ import annotations

import struct
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from marraztu.control.keymap import KeyPress, parse_key_sequence, prompt_open_after
from marraztu.control.viewer import StartOptions, Viewer, starting_scene
from marraztu.errors import KeyMapError, ViewerError, error_words, shortened
from marraztu.frontends.screenshot import (
    InputsGuard,
    OffscreenFrontend,
    check_output,
    picture_of,
    render_pixels,
    write_atomically,
)
from marraztu.model.mesh import counted
from marraztu.render.context import create_offscreen_context
from marraztu.render.renderer import Renderer

RECORDING_FORMATS = {".gif": "GIF", ".png": "PNG", ".apng": "PNG", ".mp4": "MP4"}
DEFAULT_FPS = 20
MAX_FPS = 100
MIN_FPS = 0.02  # an animated PNG's frame lasts at most 65.535 s (a 16-bit count of milliseconds)
# GIF counts frame times in hundredths of a second, and browsers show one of less than two as ten.
MAX_GIF_FPS = 50
MIN_MP4_SIDE = 2  # H.264's colour planes are half the picture's size
# Pillow reads an animation's frames twice (APNG) or gathers them (GIF), so they are all held at once.
MAX_RECORDING_BYTES = 2 << 30


def check_fps(fps: float, typed: str | None = None) -> float:
    """`typed`: the number as the person wrote it, which a float past its range would show as inf."""
    if not (MIN_FPS <= fps <= MAX_FPS):
        said = f"{fps:g}" if typed is None else shortened(typed.strip())
        raise ViewerError(f"--fps must be {MIN_FPS:g} to {MAX_FPS}, not {said}")
    return fps


def check_format(out: Path, size: tuple[int, int], fps: float) -> None:
    """What one animation format cannot hold, refused before anything is drawn."""
    kind = RECORDING_FORMATS.get(out.suffix.lower())
    if kind == "GIF" and fps > MAX_GIF_FPS:
        raise ViewerError(f"a GIF plays at most {MAX_GIF_FPS} frames a second (its frame times are whole "
                          f"hundredths of a second), not {fps:g}: use .png or .mp4")
    if kind == "MP4" and min(size) < MIN_MP4_SIDE:
        raise ViewerError(f"an MP4's sides are at least {MIN_MP4_SIDE} pixels, not {size[0]}x{size[1]}")
    if kind == "MP4":
        _ffmpeg_writer()


def check_recording_size(frames: int, size: tuple[int, int]) -> None:
    needed = frames * size[0] * size[1] * 3
    if needed > MAX_RECORDING_BYTES:
        raise ViewerError(f"{frames} frames of {size[0]}x{size[1]} would hold {needed / 2**30:.1f} GiB at once "
                          f"(at most {MAX_RECORDING_BYTES / 2**30:.0f}); record fewer presses or a smaller size")


@dataclass(frozen=True)
class Written:
    """An animation written: its frames, and how many of them repeat the picture of the one before."""

    frames: int
    repeats: int
    kind: str  # a value of RECORDING_FORMATS

    def said(self, by_keys: bool = True) -> str:
        """'63 frames', and what else the person would not guess from it; `by_keys`: the frames are drawn
        after key presses alone (`marraztu record`'s), not also after the window's redraws and the mouse."""
        words = counted(self.frames, "frame")
        if self.frames > 1 and self.repeats == self.frames - 1:
            why = "the keys changed nothing in view" if by_keys else "nothing in view changed"
            return f"{words}, all the same picture: {why}"
        if self.kind == "GIF" and self.repeats:  # Pillow joins them, so a GIF reader counts fewer
            return (f"{words}, held as {self.frames - self.repeats} pictures: a GIF shows a frame "
                    "the same as the one before by showing that one longer")
        return words


def record(options: StartOptions, out: Path, size: tuple[int, int], keys: str, fps: float = DEFAULT_FPS,
           overlay: bool = False, before: str = "") -> Written:
    """Replays `before` on the starting scene, drawing nothing, then `keys`, drawing a frame after each
    press into the animation `out`; returns what was written. ViewerError on bad input, as the
    screenshot command."""
    check_fps(fps)
    check_format(out, size, fps)
    try:
        set_up = parse_key_sequence(before)
    except KeyMapError as error:
        raise KeyMapError(f"--before: {error}") from None
    presses = parse_key_sequence(keys, in_prompt=prompt_open_after(set_up), opened_by="--before")
    if not presses:
        raise ViewerError("record needs --keys: one frame is drawn after each press")
    check_recording_size(len(presses), size)
    inputs = [*options.models, options.texture, options.scene_file, *(press.path for press in presses)]
    check_output(out, inputs, RECORDING_FORMATS, "an animation")
    _check_loads_before(out, set_up)
    frontend = OffscreenFrontend()
    scene = starting_scene(options, frontend.notice)
    check_output(out, [scene.texture_path], RECORDING_FORMATS, "an animation")
    ctx = create_offscreen_context()
    try:
        renderer = Renderer(ctx)
        viewer = Viewer(scene, frontend, strict=True, frame_size=lambda: size)
        viewer.start(options, renderer.max_texture_side)
        inputs = InputsGuard(out, RECORDING_FORMATS, "an animation")
        inputs.check(viewer)
        _set_up(viewer, frontend, set_up, inputs)

        def frames() -> Iterator[np.ndarray]:
            for _ in frontend.replay(viewer, presses):
                # A model loaded by a key brings its MTL and textures: refused before `out` is replaced.
                inputs.check(viewer)
                yield render_pixels(ctx, renderer, viewer, size, overlay)

        return write_animation(frames(), out, fps)
    finally:
        ctx.release()


def _check_loads_before(out: Path, set_up: list[KeyPress]) -> None:
    """Refuses an f=FILE of --before that is `out`, saying it is of --before, as its other refusals do."""
    try:
        check_output(out, [press.path for press in set_up], RECORDING_FORMATS, "an animation")
    except ViewerError as error:
        raise ViewerError(f"--before: {error}") from None


def _set_up(viewer: Viewer, frontend: OffscreenFrontend, set_up: list[KeyPress], inputs: InputsGuard) -> None:
    """--before's presses, drawing nothing; what refuses one says it came from --before, as its parse errors do."""
    try:
        for _ in frontend.replay(viewer, set_up):
            inputs.check(viewer)  # a model loaded by a key brings its MTL and textures
    except ViewerError as error:
        raise ViewerError(f"--before: {error}") from None
    if frontend.quitting:
        raise ViewerError("--before: ESC quits before the first frame is drawn (ESC in --keys ends the recording)")


def write_animation(frames: Iterable[np.ndarray], out: Path, fps: float) -> Written:
    """The frames, (H, W, 3) uint8 each, as the animation of `out`'s suffix; returns what was written."""
    kind = RECORDING_FORMATS[out.suffix.lower()]
    passing = _Counted(frames)
    if kind == "MP4":
        write_atomically(out, lambda temporary: _write_mp4(passing, temporary, fps))
    else:
        write_atomically(out, lambda temporary: _write_with_pillow(passing, temporary, kind, fps))
    return Written(passing.count, passing.repeats, kind)


class BackgroundSaves:
    """The window's recordings, written one after another on a thread of their own: the window draws on
    while Pillow encodes a GIF (its quantizing and compressing let go of the GIL)."""

    def __init__(self, wake: Callable[[], None]) -> None:
        self._pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="marraztu-recording")
        self._pending: list[tuple[Future[str], int]] = []  # each save and the bytes of its frames
        self._wake = wake  # called on the writer's thread once a save is done: the window says it at once

    def save(self, frames: list[np.ndarray], out: Path, fps: float) -> None:
        future = self._pool.submit(_saved, frames, out, fps)
        future.add_done_callback(lambda _: self._wake())  # after the future is done: the wake finds it so
        self._pending.append((future, sum(frame.nbytes for frame in frames)))

    def finished(self) -> list[str]:
        """What each save done since the last call says, in the order they were asked for."""
        done = []
        while self._pending and self._pending[0][0].done():
            future = self._pending.pop(0)[0]
            error = future.exception()  # what _saved did not foresee (no memory left): one line, as guarded says it
            done.append(future.result() if error is None else f"recording not saved: {error_words(error)}")
        return done

    def held_bytes(self) -> int:
        """The frames of the saves not yet written, held until they are: a new recording has what they leave."""
        return sum(nbytes for future, nbytes in self._pending if not future.done())

    def close(self) -> list[str]:
        """Waits for every save asked for; what those not yet said say."""
        self._pool.shutdown(wait=True)
        return self.finished()


def _saved(frames: list[np.ndarray], out: Path, fps: float) -> str:
    """What F9 says of its save: where it went, and of its frames what `marraztu record` says, the
    window's frames not only a key's."""
    try:
        written = write_animation(frames, out, fps)
    except ViewerError as error:
        return f"recording not saved: {error}"
    return f"recording saved to {out}: {written.said(by_keys=False)}"


class _Counted:
    """The frames as they pass: counted, and each compared with the one before, the one more it holds."""

    def __init__(self, frames: Iterable[np.ndarray]) -> None:
        self.frames = iter(frames)
        self.count = 0
        self.repeats = 0

    def __iter__(self) -> Iterator[np.ndarray]:
        previous = None
        for frame in self.frames:
            self.count += 1
            if previous is not None and np.array_equal(frame, previous):
                self.repeats += 1
            previous = frame
            yield frame


def _write_with_pillow(frames: _Counted, temporary: Path, kind: str, fps: float) -> None:
    pictures = [picture_of(frame) for frame in frames]
    if not pictures:
        raise ViewerError("no frame to write: the keys quit before the first one was drawn")
    # GIF's times are hundredths of a second, which Pillow would truncate: rounded to the nearest.
    duration = round(100.0 / fps) * 10 if kind == "GIF" else round(1000.0 / fps)
    try:
        # disposal 1 and no optimisation: every frame is whole and shown as drawn (GIF and APNG alike).
        pictures[0].save(temporary, format=kind, save_all=True, append_images=pictures[1:], duration=duration,
                         loop=0, disposal=1, optimize=False)
    # Pillow joins a GIF's frames that repeat the one before, adding their times: past 16 bits, Pillow 13
    # raises OverflowError, Pillow 10.2 to 12 struct.error.
    except (OverflowError, struct.error):
        raise ViewerError("a GIF shows one picture for at most 655 s, and these presses leave the same one longer: "
                          "use a higher --fps or .png") from None


def _ffmpeg_writer() -> Any:
    try:
        import imageio_ffmpeg
    except ImportError:
        raise ViewerError("writing MP4 needs imageio-ffmpeg (pip install imageio-ffmpeg); "
                          ".gif and .png need nothing more") from None
    return imageio_ffmpeg


def _write_mp4(frames: _Counted, temporary: Path, fps: float) -> None:
    imageio_ffmpeg = _ffmpeg_writer()
    writer = None
    for frame in frames:
        if writer is None:
            height, width = frame.shape[:2]
            # Even sides: the usual H.264 pixel format halves the colour planes.
            # Block size 1: the sides as drawn (imageio's 16 stretched 800x600 to 800x608, with a warning).
            writer = imageio_ffmpeg.write_frames(str(temporary), (width - width % 2, height - height % 2),
                                                 fps=fps, output_params=["-f", "mp4"], macro_block_size=1)
            writer.send(None)
        writer.send(np.ascontiguousarray(frame[: frame.shape[0] - frame.shape[0] % 2,
                                               : frame.shape[1] - frame.shape[1] % 2]))
    if writer is None:
        raise ViewerError("no frame to write: the keys quit before the first one was drawn")
    writer.close()
    if temporary.stat().st_size == 0:  # ffmpeg said why on stderr, and exited as if it had written
        raise ViewerError("ffmpeg wrote nothing (its words are above)")
