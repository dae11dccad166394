"""2. Frames: the renderer beside a pass-through program on the same vertex data; Python CPU per frame."""

from __future__ import annotations

import math
import statistics
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from marraztu.devtools.bench.config import BenchConfig
from marraztu.devtools.bench.inputs import generated_mesh
from marraztu.devtools.bench.report import count_label, markdown_table, number, progress, ratio

if TYPE_CHECKING:
    import moderngl

    from marraztu.model.mesh import Mesh
    from marraztu.model.scene import Scene, SceneObject
    from marraztu.render.gpu import VertexRange
    from marraztu.render.mipmaps import MipmappedTexture
    from marraztu.render.renderer import Renderer

FRAME_HEADERS = ("scene", "triangles", "size", "mode", "still ms", "moving ms", "bare ms", "bare moving ms",
                 "inputs ms", "still ÷ bare", "moving ÷ bare", "moving ÷ bare moving", "still ÷ inputs", "frames")
CPU_HEADERS = ("scene", "mode", "program process ms", "program thread ms", "program without draw calls ms",
               "bare process ms", "bare thread ms")


BARE_VERTEX_SHADER = """#version 330
uniform mat4 u_mvp;
in vec3 in_position;
void main() { gl_Position = u_mvp * vec4(in_position, 1.0); }
"""
BARE_FRAGMENT_SHADER = """#version 330
out vec4 f_colour;
void main() { f_colour = vec4(1.0); }
"""
# The floor under a still filled frame's inputs: each row's position, texture coordinate and lit row read, the
# lit colour handed on as the renderer's program hands it (flat in Flat, interpolated in Gouraud) and
# multiplied by the texture; no back-face test, no view switch, no uniforms but these.
# Compiled through shaded_source, which defines FLAT for Flat's.
BARE_INPUTS_VERTEX_SHADER = """
uniform mat4 u_mvp;
in vec3 in_position;
in vec2 in_uv;
in vec4 in_lit;
#if defined FLAT
flat out vec4 v_lit;
#else
smooth out vec3 v_lit;
#endif
out vec2 v_uv;
void main() {
#if defined FLAT
    v_lit = in_lit;
#else
    v_lit = in_lit.rgb;
#endif
    v_uv = in_uv;
    gl_Position = u_mvp * vec4(in_position, 1.0);
}
"""
BARE_INPUTS_FRAGMENT_SHADER = """
uniform sampler2D u_texture;
#if defined FLAT
flat in vec4 v_lit;
#else
smooth in vec3 v_lit;
#endif
in vec2 v_uv;
out vec4 f_colour;
void main() { f_colour = vec4(v_lit.rgb * texture(u_texture, v_uv).rgb, 1.0); }
"""
# The lighting pass's floor: the same rows read and the same 16-byte rows captured, no lighting.
BARE_LIGHTING_SHADER = """#version 330
in vec3 in_position;
out vec4 v_lit;
void main() { v_lit = vec4(in_position, 1.0); }
"""
# The same as a compute program, where the renderer's pass is one (surface.glsl's storage buffers;
# compiled after LIGHTING_DEFINES).
BARE_COMPUTE_LIGHTING_SHADER = """
layout(local_size_x = LIGHTING_GROUP_ROWS) in;
layout(std430, binding = SURFACE_BINDING) readonly buffer SurfaceBuffer { float surface_rows[]; };
layout(std430, binding = LIT_BINDING) writeonly buffer LitBuffer { vec4 lit_rows[]; };
uniform uint u_first_row;
uniform uint u_stop_row;
void main() {
    uint row = gl_GlobalInvocationID.x;
    if (row < u_first_row || row >= u_stop_row) {
        return;
    }
    uint at = row * uint(SURFACE_ROW_FLOATS) + uint(POSITION_AT);
    lit_rows[row] = vec4(surface_rows[at], surface_rows[at + 1u], surface_rows[at + 2u], 1.0);
}
"""


def shaded_source(body: str, mode: str) -> str:
    """A bare program's GLSL for a filled mode: FLAT defined for Flat's."""
    return f"#version 330\n{'#define FLAT' if mode == 'flat' else ''}\n{body}"


MODES = ("flat", "gouraud", "lines")
MIN_FRAMES = 3  # a median of fewer says little


def set_mode(scene: Scene, mode: str) -> None:
    from marraztu.model.scene import Fill, Shading

    scene.modes.fill = Fill.LINES if mode == "lines" else Fill.FILLED
    scene.modes.shading = Shading.GOURAUD if mode == "gouraud" else Shading.FLAT


def drawn_objects(scene: Scene) -> list[SceneObject]:
    """What the renderer draws with the start modes: every object and camera but the viewer."""
    return [obj for obj in scene.objects + scene.cameras if obj is not scene.viewer and obj.mesh.face_count]


def scene_triangles(scene: Scene) -> int:
    return sum(int(obj.mesh.triangles_before_face()[-1]) for obj in drawn_objects(scene))


@dataclass(frozen=True)
class BareLighting:
    """One object's pass-through lighting pass: the rows it reads, the buffer it captures into, and
    the rows each filled mode lights."""

    vertex_array: moderngl.VertexArray
    surface: moderngl.Buffer
    lit: moderngl.Buffer
    rows: dict[str, tuple[int, int]]


class BareDraw:
    """A pass-through program drawing the renderer's vertex arrays: the floor under a frame's cost.

    Same framebuffer, clear, depth test, primitives, index buffers (Flat's, or the shared one of
    Gouraud) and vertex count as the renderer; no lighting, no texture, one pass of edges. A moving
    frame first runs a pass-through lighting pass over the rows the renderer's lighting pass lights
    (gpu.lit_row_range), writing as many bytes, by transform feedback or by a compute program as the
    renderer would. Given the renderer's texture, a filled frame instead draws the still frame's
    inputs (BARE_INPUTS_VERTEX_SHADER). Each object's mesh is taken whole, as one part: the renderer
    draws and lights a mesh of several materials part by part, and the bench's meshes have one.
    """

    def __init__(self, ctx: moderngl.Context, scene: Scene, compute_lighting: bool) -> None:
        import moderngl

        from marraztu.model.scene import Shading
        from marraztu.render.gpu import (
            LIGHTING_DEFINES,
            LIT_ROW_BYTES,
            ComputeLighting,
            compute_program,
            lighting_window_rows,
        )
        from marraztu.render.renderer import CLEAR_COLOUR, pieced_draws

        self.gl = moderngl  # imported here, not per frame, so the bare CPU figures stay bare
        self.draw = pieced_draws(ctx)[0]  # in the renderer's pieces
        self.shadings = {way.value: way for way in (Shading.FLAT, Shading.GOURAUD)}  # the modes that light
        self.clear_colour = CLEAR_COLOUR
        self.ctx = ctx
        self.scene = scene
        self.lit_row_bytes = LIT_ROW_BYTES
        self.buffers: list[moderngl.Buffer] = []
        # Per object: each mode's vertex array and the vertices it draws, and each filled mode's inputs' array.
        self.objects: list[tuple[SceneObject, dict[str, tuple[moderngl.VertexArray, VertexRange]],
                                 dict[str, moderngl.VertexArray]]] = []
        self.lighting: list[BareLighting] = []
        self.programs: list[moderngl.Program | moderngl.ComputeShader] = []
        self.compute_lighting: ComputeLighting | None = None  # the same pass-through for both shadings
        try:
            self.program = self._program(vertex_shader=BARE_VERTEX_SHADER, fragment_shader=BARE_FRAGMENT_SHADER)
            self.mvp = self.program["u_mvp"]
            self.inputs_programs = {mode: self._program(
                vertex_shader=shaded_source(BARE_INPUTS_VERTEX_SHADER, mode),
                fragment_shader=shaded_source(BARE_INPUTS_FRAGMENT_SHADER, mode)) for mode in self.shadings}
            self.inputs_mvps = {mode: program["u_mvp"] for mode, program in self.inputs_programs.items()}
            self.lighting_program = self._program(vertex_shader=BARE_LIGHTING_SHADER, varyings=["v_lit"])
            if compute_lighting:
                program = compute_program(ctx, BARE_COMPUTE_LIGHTING_SHADER, LIGHTING_DEFINES)
                self.programs.append(program)
                self.compute_lighting = ComputeLighting(dict.fromkeys(self.shadings.values(), program),
                                                        lighting_window_rows(ctx))
            for obj in drawn_objects(scene):
                self._add(obj)
        except Exception:
            self.release()
            raise

    def _program(self, **shaders: object) -> moderngl.Program:
        program = self.ctx.program(**shaders)
        self.programs.append(program)
        return program

    def _buffer(self, data: np.ndarray | None = None, reserve: int = 0) -> moderngl.Buffer:
        buffer = self.ctx.buffer(data, reserve=reserve)
        self.buffers.append(buffer)
        return buffer

    def _add(self, obj: SceneObject) -> None:
        """The object's surface, edges and lit rows, and the vertex arrays that read them."""
        from marraztu.model.scene import Shading
        from marraztu.render.context import max_texture_side
        from marraztu.render.gpu import (
            EDGE_LAYOUT,
            LIT_LAYOUT,
            SURFACE_LAYOUT,
            VertexRange,
            edge_face_shape,
            edge_pairs,
            edge_rows,
            layout_for,
            lit_row_range,
            surface_arrays,
        )

        ctx, mesh = self.ctx, obj.mesh
        arrays = surface_arrays(mesh)
        rows = arrays.vertices.shape[0]
        surface, indices, shared = (self._buffer(data) for data in
                                    (arrays.vertices, arrays.indices, arrays.shared_indices))
        width, _ = edge_face_shape(mesh.face_count, max_texture_side(ctx))
        pair_indices = edge_pairs(mesh)
        edges, pairs = self._buffer(edge_rows(mesh, width)), self._buffer(pair_indices)
        lit = self._buffer(reserve=rows * self.lit_row_bytes)
        position = [(surface, *layout_for(self.program, SURFACE_LAYOUT))]  # the bare program reads in_position only
        lit_rows = {shading.value: lit_row_range(shading, arrays.shared_rows, 0, mesh.face_count)
                    for shading in (Shading.FLAT, Shading.GOURAUD)}
        self.lighting.append(BareLighting(ctx.vertex_array(self.lighting_program, position), surface, lit, lit_rows))
        filled = {"flat": (indices, arrays.indices.size), "gouraud": (shared, arrays.shared_indices.size)}
        self.objects.append((obj, {
            **{mode: (ctx.vertex_array(self.program, position, index_buffer=buffer, index_element_size=4),
                      VertexRange(0, count)) for mode, (buffer, count) in filled.items()},
            "lines": (ctx.vertex_array(self.program, [(edges, *layout_for(self.program, EDGE_LAYOUT))],
                                       index_buffer=pairs, index_element_size=4), VertexRange(0, pair_indices.size))},
            {mode: ctx.vertex_array(program, [(surface, *layout_for(program, SURFACE_LAYOUT)), (lit, *LIT_LAYOUT)],
                                    index_buffer=filled[mode][0], index_element_size=4)
             for mode, program in self.inputs_programs.items()}))

    def render(self, fbo: moderngl.Framebuffer, size: tuple[int, int], mode: str, moving: bool = False,
               texture: MipmappedTexture | None = None) -> None:
        """The bare frame; with `texture` (filled modes), the still frame's inputs shown instead."""
        gl = self.gl
        width, height = size
        fbo.use()  # before the lighting pass too: with no framebuffer bound, a draw captures nothing
        if moving:
            self._light(mode)
        fbo.viewport = (0, 0, width, height)
        fbo.clear(*self.clear_colour, 1.0, depth=1.0)
        filled = mode != "lines"
        if filled:
            self.ctx.enable(gl.DEPTH_TEST)
        else:
            self.ctx.disable(gl.DEPTH_TEST)
        shown = texture is not None and filled
        if shown:
            texture.use(location=0)
        mvp_uniform = self.inputs_mvps[mode] if shown else self.mvp
        view_projection = self.scene.projection_matrix(width / height) @ self.scene.view_matrix()
        for obj, arrays, inputs in self.objects:
            mvp = view_projection @ obj.model
            mvp_uniform.write(np.ascontiguousarray(mvp.T, dtype="f4").tobytes())
            vertex_array, span = arrays[mode]
            self.draw(inputs[mode] if shown else vertex_array, gl.TRIANGLES if filled else gl.LINES, span)
        self.ctx.disable(gl.DEPTH_TEST)

    def _light(self, mode: str) -> None:
        for lighting in self.lighting:
            if mode not in lighting.rows:  # lines light nothing
                continue
            first, stop = lighting.rows[mode]
            compute = self.compute_lighting
            if compute is not None and compute.takes(first, stop):
                compute.run(self.ctx, self.shadings[mode], lighting.surface, None, lighting.lit, first, stop)
            else:
                lighting.vertex_array.transform(lighting.lit, self.gl.POINTS, vertices=stop - first, first=first,
                                                buffer_offset=first * self.lit_row_bytes)

    def release(self) -> None:
        for _, arrays, inputs in self.objects:
            for vao in [vao for vao, _ in arrays.values()] + list(inputs.values()):
                vao.release()
        for lighting in self.lighting:
            lighting.vertex_array.release()
        for resource in (*self.buffers, *self.programs):
            resource.release()


@dataclass
class FrameTimes:
    moving: list[float] = field(default_factory=list)
    still: list[float] = field(default_factory=list)
    bare: list[float] = field(default_factory=list)
    bare_moving: list[float] = field(default_factory=list)
    inputs: list[float] = field(default_factory=list)


# The camera turns this far, to and fro, before each moving frame: every lit colour changes (V and
# the camera's spotlight move), the picture hardly.
NUDGE_RADIANS = 1e-3


def nudge_camera(scene: Scene, step: int) -> None:
    """Turns the viewing camera about its own y axis, one way on even steps and back on odd ones."""
    from marraztu.model.transforms import apply_local, rotation_about_axis

    turn = rotation_about_axis(1, NUDGE_RADIANS if step % 2 == 0 else -NUDGE_RADIANS)
    scene.camera.history[-1] = apply_local(scene.camera.model, turn)  # in place: no undo step per frame


def paired_frame_times(ctx: moderngl.Context, scene: Scene, program_frame: Callable[[], None],
                       bare_frame: Callable[[], None], bare_moving_frame: Callable[[], None],
                       inputs_frame: Callable[[], None] | None, config: BenchConfig) -> FrameTimes:
    """A moving frame (the camera nudged first), a still one (nothing changed since), a bare one, a
    bare moving one and (where there is one) the still frame's inputs, in turn, so all see the same
    load from other processes.

    The first warm-up frame also builds the renderer's buffers for the object and compiles shader
    variants, which is why it is never measured.
    """
    times = FrameTimes()
    frames = [(program_frame, times.moving), (program_frame, times.still), (bare_frame, times.bare),
              (bare_moving_frame, times.bare_moving)] + ([(inputs_frame, times.inputs)] if inputs_frame else [])
    for _ in range(config.warmup):  # the inputs' programs and arrays are first used here too, not measured
        for frame in (program_frame, bare_moving_frame, *([inputs_frame] if inputs_frame else [])):
            frame()
            ctx.finish()
    started = time.perf_counter()
    while len(times.still) < config.frames:
        if len(times.still) >= MIN_FRAMES and time.perf_counter() - started > config.frame_budget_s:
            break
        nudge_camera(scene, len(times.moving))
        for frame, record in frames:
            start = time.perf_counter()
            frame()
            ctx.finish()
            record.append(time.perf_counter() - start)
    return times


@dataclass
class FrameBench:
    """The GL pieces shared by sections 2 and 4: one context, one renderer, the scene's texture."""

    ctx: moderngl.Context
    renderer: Renderer

    @classmethod
    def open(cls) -> FrameBench:
        from marraztu.render.context import create_offscreen_context
        from marraztu.render.renderer import Renderer

        ctx = create_offscreen_context()
        return cls(ctx, Renderer(ctx))

    def use_scene_texture(self, scene: Scene) -> None:
        from marraztu.loaders.images import load_texture_or_fallback

        scene.texture, _ = load_texture_or_fallback(scene.texture_path)

    def release(self) -> None:
        self.renderer.release()
        self.ctx.release()


def bench_scene(mesh: Mesh | None) -> Scene:
    """The built-in scene (its camera, lights, texture), its objects replaced by `mesh` if given;
    all four lights on."""
    from marraztu.loaders.scenefile import DEFAULT_MATERIAL, load_builtin_scene
    from marraztu.model.scene import SceneObject

    scene = load_builtin_scene()
    if mesh is not None:
        scene.objects = [SceneObject.placed(mesh.name, mesh, DEFAULT_MATERIAL, (0.0, 0.0, 0.0))]
        scene.selected_object = 0
    for light in scene.lights:
        light.on = True
    return scene


def many_objects_scene(count: int) -> Scene:
    """The built-in scene (bench_scene) with its Rammer_255 alone, placed `count` times in a square
    that fills the camera's view, each turned a little more: one Mesh for all."""
    from marraztu.model.scene import SceneObject
    from marraztu.model.transforms import placement

    scene = bench_scene(None)
    rammer = next(obj for obj in scene.objects if obj.name == "Rammer_255")
    side = math.ceil(math.sqrt(count))
    step = 260.0 / side  # the square is 260 units wide at the origin, 150 in front of the camera
    scene.objects = []
    for k in range(count):
        model = rammer.model @ placement((0.0, 0.0, 0.0), (0.0, 0.0, 7.0 * k))
        model[:3, :3] *= 3.0 / side  # each about four fifths of its step across
        model[:3, 3] = ((k % side - (side - 1) / 2) * step, (k // side - (side - 1) / 2) * step, 0.0)
        scene.objects.append(SceneObject(f"Rammer_255 {k}", rammer.mesh, rammer.material, [model]))
    scene.selected_object = 0
    return scene


@contextmanager
def scene_and_bare(bench: FrameBench, scene: Scene) -> Iterator[BareDraw]:
    """`scene` ready to draw with its texture, and the bare program on the same vertex data; both
    programs' buffers released afterwards."""
    bench.use_scene_texture(scene)
    bare = BareDraw(bench.ctx, scene, bench.renderer.compute_lighting)
    try:
        yield bare
    finally:
        bare.release()
        for obj in drawn_objects(scene):
            bench.renderer.release_object(obj)


@contextmanager
def framebuffer(bench: FrameBench, size: tuple[int, int]) -> Iterator[moderngl.Framebuffer]:
    fbo = bench.ctx.simple_framebuffer(size, components=4)
    try:
        yield fbo
    finally:
        fbo.release()


def frame_cases(bench: FrameBench, scene: Scene, label: str, config: BenchConfig) -> list[list[str]]:
    rows = []
    with scene_and_bare(bench, scene) as bare:
        for size in config.resolutions:
            with framebuffer(bench, size) as fbo:
                for mode in MODES:
                    progress(f"frames: {label} {size[0]}x{size[1]} {mode}")
                    set_mode(scene, mode)
                    times = paired_frame_times(bench.ctx, scene, lambda: bench.renderer.render(scene, fbo, size),
                                               lambda: bare.render(fbo, size, mode),
                                               lambda: bare.render(fbo, size, mode, moving=True),
                                               None if mode == "lines" else
                                               lambda: bare.render(fbo, size, mode, texture=bench.renderer.texture),
                                               config)
                    rows.append(_frame_row(label, scene_triangles(scene), size, mode, times))
    return rows


def _frame_row(label: str, triangles: int, size: tuple[int, int], mode: str, times: FrameTimes) -> list[str]:
    still, moving, bare, bare_moving, inputs = (statistics.median(frames) * 1000 if frames else None for frames in
                                                (times.still, times.moving, times.bare, times.bare_moving,
                                                 times.inputs))
    return [label, str(triangles), f"{size[0]}x{size[1]}", mode, number(still), number(moving), number(bare),
            number(bare_moving), number(inputs), ratio(still, bare), ratio(moving, bare), ratio(moving, bare_moving),
            ratio(still, inputs), str(len(times.still))]


def frames_section(bench: FrameBench, config: BenchConfig) -> list[str]:
    rows = frame_cases(bench, bench_scene(None), "built-in", config)
    for triangles in config.frame_sizes:
        progress(f"building the {count_label(triangles)}-triangle mesh")
        rows += frame_cases(bench, bench_scene(generated_mesh(triangles)), f"grid {count_label(triangles)}",
                            config)
    sizes = ", ".join(count_label(n) for n in config.frame_sizes) or "none"
    resolutions = ", ".join(f"{w}x{h}" for w, h in config.resolutions)
    return [
        "## 2. Frames: GPU-complete frame time",
        "",
        f"Meshes: the built-in scene and generated grids of {sizes} triangles; sizes {resolutions}; "
        "all four lights on, texture on. Each frame is `render` + `ctx.finish()`; median of up to "
        f"{config.frames} frames after {config.warmup} warm-up frame(s) (a case stops at {MIN_FRAMES} frames after "
        f"{config.frame_budget_s:g} s). *moving*: the camera turns {NUDGE_RADIANS:g} rad before the frame, so "
        "every vertex is lit again; *still*: the next frame, nothing changed, so the lighting pass is "
        "skipped. *bare* = a pass-through program drawing the same vertex buffers (same layout, depth "
        "test, primitive count and draw calls, in the renderer's pieces on llvmpipe; lines drawn once) in "
        "the same process, frames alternating with the "
        "program's; the ratios are what the program adds. *bare moving* = the bare draw after a "
        "pass-through transform feedback over the rows the lighting pass reads, capturing as many bytes "
        "per row (Flat: one row per polygon; Gouraud: the shared rows; lines: none): the floor under a "
        "moving frame, which must light every row again. *inputs* (filled modes) = the bare draw reading "
        "and showing what a still frame reads: each row's position, texture coordinate and lit row, the lit "
        "colour handed on as the program hands it (flat in Flat, interpolated in Gouraud) and multiplied by "
        "the scene's texture, sampled as the program samples it; no back-face test or view switch: the floor "
        "under a still frame that shows the lit, textured picture.",
        "",
        *markdown_table(FRAME_HEADERS, rows),
    ]


def cpu_section(bench: FrameBench, config: BenchConfig) -> list[str]:
    """Python CPU per frame on the built-in scene and on one of many objects: render() without finish,
    GPU work waited out between frames so none of it lands in the next measurement."""
    size = config.resolutions[0]
    many = f"{config.objects:,} × Rammer_255"
    rows = []
    for label, scene in (("built-in", bench_scene(None)), (many, many_objects_scene(config.objects))):
        with scene_and_bare(bench, scene) as bare, framebuffer(bench, size) as fbo:
            for mode in MODES:
                progress(f"CPU per frame: {label} {mode}")
                set_mode(scene, mode)
                program = _cpu_per_frame(bench.ctx, lambda: bench.renderer.render(scene, fbo, size), config)
                with _draw_calls_skipped():
                    python_only = _cpu_per_frame(bench.ctx, lambda: bench.renderer.render(scene, fbo, size), config)
                bare_cpu = _cpu_per_frame(bench.ctx, lambda: bare.render(fbo, size, mode), config)
                rows.append([label, mode, *(number(ms) for ms in (*program, python_only[1], *bare_cpu))])
    return [
        "### Python CPU per frame",
        "",
        f"Median over {config.cpu_frames} frames at {size[0]}x{size[1]} of `time.process_time()` (all "
        "threads) and `time.thread_time()` (the calling thread) around `render` alone, without "
        "`finish`. llvmpipe runs vertex shading in the calling thread, so both include some driver "
        "work; the bare columns are that floor. *without draw calls*: thread time with "
        "`VertexArray.render` made a no-op, i.e. the renderer's own Python work. Scenes: the built-in "
        f"one, and {many}: the built-in scene with its Rammer_255 placed {config.objects:,} times in a "
        "square, one mesh for all, as a scene file placing one model again and again (what the renderer "
        "spends per object; the bare draw builds buffers of its own for each).",
        "",
        *markdown_table(CPU_HEADERS, rows),
    ]


@contextmanager
def _draw_calls_skipped() -> Iterator[None]:
    """Every VertexArray.render does nothing: what is left of a frame is Python and uniform uploads."""
    import moderngl

    original = moderngl.VertexArray.render
    moderngl.VertexArray.render = lambda self, *args, **kwargs: None  # type: ignore[method-assign]
    try:
        yield
    finally:
        moderngl.VertexArray.render = original  # type: ignore[method-assign]


def _cpu_per_frame(ctx: moderngl.Context, frame: Callable[[], None], config: BenchConfig) -> tuple[float, float]:
    for _ in range(config.warmup):
        frame()
        ctx.finish()
    process, thread = [], []
    for _ in range(config.cpu_frames):
        process_start, thread_start = time.process_time(), time.thread_time()
        frame()
        thread.append(time.thread_time() - thread_start)
        process.append(time.process_time() - process_start)
        ctx.finish()
    return statistics.median(process) * 1000, statistics.median(thread) * 1000
