"""Draws a Scene into any framebuffer: the window's, or an offscreen one for screenshots and tests.

GPU resources of each object are built once, keyed by the object's uid, and dropped when the object
leaves the scene; objects placing one mesh share its buffers (MeshGpus). Per frame only uniforms
change, and only those whose values changed are written.
The lighting itself lives in shaders/surface.glsl; marraztu.model.lighting is the same formula in
numpy, kept apart so that each checks the other. Flat and Gouraud light the vertices in a pass of their own
that is skipped while every uniform it reads keeps its value (ObjectGpu.light).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Callable, Iterable

import moderngl
import numpy as np

from marraztu.errors import ViewerError
from marraztu.loaders.images import fit_texture
from marraztu.model.guides import Guides, scene_guides
from marraztu.model.lights import MAX_LIGHTS, Show, WorldLight, shader_defines
from marraztu.model.mesh import PLAIN_PICTURE, WHOLE, Mesh
from marraztu.model.probe import ProbedFace, facings, probed_face
from marraztu.model.sampling import TextureSampling
from marraztu.model.scene import (
    NORMAL_LENGTH_FRACTION,
    Fill,
    Material,
    Projection,
    Scene,
    SceneObject,
    Shading,
    Target,
)
from marraztu.model.transforms import normal_matrix, translation_by
from marraztu.model.viewports import View, views
from marraztu.render.context import (
    SOFTWARE_SEGMENT_PIECES_IN_FLIGHT,
    check_gl,
    draw_piece_primitives,
    gl_flush,
    lights_by_compute,
    max_texture_side,
)
from marraztu.render.gpu import (
    EDGE_FACE_UNITS,
    LIGHTING_DEFINES,
    LIT_LAYOUT,
    LIT_SURFACE_WAYS,
    ComputeLighting,
    MeshGpu,
    MeshGpus,
    ObjectGpu,
    Programs,
    SurfaceWay,
    VertexRange,
    lighting_window_rows,
    load_compute_program,
    load_program,
)
from marraztu.render.guides import GuidesDrawer
from marraztu.render.layout import pixel_per_w, scaled_px
from marraztu.render.mipmaps import MipmappedTexture, create_mipmapped

CLEAR_COLOUR = (0.0, 0.0, 0.7)  # SPEC 3: the seed's blue
SELECTED_LINE_COLOUR = (0.0, 1.0, 0.0)
LINE_COLOUR = (1.0, 1.0, 1.0)
NORMAL_COLOUR = (1.0, 1.0, 0.0)
MARKER_SIZE_PX = 9.0
PROBE_COLOUR = (0.0, 1.0, 1.0)  # cyan: no other drawing uses it
PROBE_MARKER_PX = 7.0
HOLLOW_BORDER_PX = 2.0  # a hidden probed corner's dot: its border, at 800x800 as the dot's size
# Corners the probe marks at most, a draw each: every corner of any polygon a model has; a polygon of
# thousands (one file's whole outline) shows its outline instead.
MAX_PROBE_MARKERS = 1024
# The probe's outline lies on its face and its neighbours, whose depth at the line's pixels is up to
# half a pixel's slope off: taken a pixel toward the eye, more the more obliquely they are seen, it is
# seen wherever they are, and hidden by what lies a few pixels' depth in front of them.
PROBE_PULL_PX = 1.0
MIN_PROBE_FACING = 0.05  # the shallowest view the pull grows for
# The probe's passes in filled mode: (hidden, depth test) where the picture shows the outline, and
# where it hides it: together every fragment once.
_PROBE_PASSES = ((False, "<="), (True, ">"))
# An eye this many times the smallest model's size from the world's origin leaves a 32-bit position
# near it about a thousandth of that size (24 bits of mantissa, 14 of them spent on the distance).
EYE_ORIGIN_SIZES = 2.0**14
SEPARATOR_COLOUR = (0.0, 0.0, 0.0)
SEPARATOR_PX = 2
# The uniform the lighting's V comes from: the eye's position in perspective, its direction in parallel.
_VIEW_UNIFORM_BY_PROJECTION = {Projection.PERSPECTIVE: "u_eye_position", Projection.PARALLEL: "u_eye_backward"}
_VIEW_UNIFORMS = frozenset(_VIEW_UNIFORM_BY_PROJECTION.values())


def gl_matrix(matrix: np.ndarray) -> bytes:
    """A matrix's bytes as GL reads a uniform's: numpy is row-major and GL column-major, so M.T's bytes
    are M for GL."""
    return np.ascontiguousarray(matrix.T, dtype="f4").tobytes()


class Uniforms:
    """The uniforms of a program, or of programs that always hold the same values, looked up once.
    Uniforms the GLSL compiler removed as unused are skipped silently: e.g. u_colour does not exist
    where the colour is not needed.

    Each uniform is written only when its value differs from the one it holds, compared exactly (as
    bytes: -0.0 is not 0.0), and `values()` tells what they all hold: the lighting pass is skipped
    while that stays the same."""

    def __init__(self, *programs: moderngl.Program | moderngl.ComputeShader) -> None:
        self._handles: dict[str, list[Any]] = {}  # by name, the uniform in each program that has it
        for program in programs:
            for name in program:
                if isinstance(program[name], moderngl.Uniform):
                    self._handles.setdefault(name, []).append(program[name])
        self._held: dict[str, bytes] = {}  # by name, the exact value last written

    def set(self, name: str, value: Any) -> None:
        handles = self._handles.get(name)
        if handles is not None and self._changed(name, np.asarray(value).tobytes()):
            for handle in handles:
                handle.value = value

    def set_matrix(self, name: str, matrix: np.ndarray) -> None:
        self.set_bytes(name, gl_matrix(matrix))

    def set_array(self, name: str, values: np.ndarray) -> None:
        self.set_bytes(name, np.ascontiguousarray(values).tobytes())

    def values(self) -> tuple[tuple[str, bytes], ...]:
        """Every uniform written so far with its value: equal tuples, equal program state."""
        return tuple(self._held.items())

    def set_bytes(self, name: str, data: bytes) -> None:
        """The uniform's value as the bytes GL reads (gl_matrix's, set_array's)."""
        handles = self._handles.get(name)
        if handles is not None and self._changed(name, data):
            for handle in handles:
                handle.write(data)

    def _changed(self, name: str, exact: bytes) -> bool:
        if self._held.get(name) == exact:
            return False
        self._held[name] = exact
        return True


@dataclass(frozen=True)
class DrawItem:
    """One object to draw and which of its faces: [start, stop). With `part` (an index into the mesh's
    parts, one per material) the faces are the part's own."""

    obj: SceneObject
    start: int
    stop: int
    part: int = WHOLE

    @property
    def file_material(self) -> int:
        """Which of the file's materials the faces use (Mesh.materials; -1: the object's own)."""
        return -1 if self.part == WHOLE else self.obj.mesh.parts[self.part].material


def split_by_material(item: DrawItem) -> list[DrawItem]:
    """The item as one item per material part its faces reach: each part keeps the file's order, so a
    range of the whole mesh's faces is a range of each part's."""
    parts = item.obj.mesh.parts
    if not parts:
        return [item]
    split = []
    for index, part in enumerate(parts):
        start, stop = part.face_range(item.start, item.stop)
        if stop > start:
            split.append(DrawItem(item.obj, start, stop, index))
    return split


def part_of_face(obj: SceneObject, face: int) -> tuple[int, int]:
    """(part, the face's index in it) of polygon `face` of the whole mesh; (WHOLE, face) without parts."""
    for index, part in enumerate(obj.mesh.parts):
        local = part.own_face(face)
        if local is not None:
            return index, local
    return WHOLE, face


class Renderer:
    def __init__(self, ctx: moderngl.Context, compute_lighting: bool | None = None) -> None:
        """`compute_lighting`: whether large lighting passes run as compute programs (None: where that
        is quicker, lights_by_compute)."""
        self.ctx = ctx
        self.size = (1, 1)  # the framebuffer being drawn: the dots' size follows it (layout.screen_scale)
        self.draw, self.draw_segments = pieced_draws(ctx)
        # A surface program per shading (the depth view's too, made when first drawn: _use_way), and a
        # lighting pass (and on llvmpipe a compute one too) for the shadings that light vertices; the
        # current view's are `self.surface` and `self.lighting`.
        self._defines = lights = shader_defines()
        self.compute_lighting = lights_by_compute(ctx) if compute_lighting is None else compute_lighting
        passes = {way: {**SurfaceWay(way).defines, "LIGHTING_PASS": "1", **lights}
                  for way in Shading if way.lights_vertices}
        self.programs = Programs(
            surfaces={way: self._surface_program(way) for way in LIT_SURFACE_WAYS},
            lightings={way: load_program(ctx, "surface", varyings=("v_lit",), defines=defines)
                       for way, defines in passes.items()},
            edges=load_program(ctx, "edges"), normals=load_program(ctx, "normals"),
            outline=load_program(ctx, "outline"),
            compute_lighting=ComputeLighting(
                {way: load_compute_program(ctx, "surface", {**defines, **LIGHTING_DEFINES})
                 for way, defines in passes.items()}, lighting_window_rows(ctx)) if self.compute_lighting else None)
        self.surface_uniforms = {way: Uniforms(program) for way, program in self.programs.surfaces.items()}
        # A shading's two lighting passes, where it has both, read the same uniforms: set once for both.
        self.lighting_uniforms = {way: Uniforms(*self.programs.lighting_passes(way)) if way.lights_vertices
                                  else self.surface_uniforms[SurfaceWay(way)] for way in Shading}
        # The current view's way, the uniforms of its surface program and of the program that lights it
        # (its lighting pass in Flat and Gouraud, the surface program itself in Phong), and whether the
        # surface program reads the lighting pass's rows: set by _use_way, with object_uniforms.
        self._use_way(SurfaceWay(Shading.FLAT))
        # The frame's world origin for the GPU (Renderer._frame_origin): subtracted from every world
        # position the uniforms carry, in 64-bit numbers, so that the GPU's 32-bit ones stay small.
        self.origin = np.zeros(3)
        self.lighting_passes = 0  # run so far: a frame where nothing lighting reads changed adds none
        # Set by each frame (_set_frame_uniforms): the uniform V comes from, and whether a specular
        # term shows (a light on, the term view keeping the term).
        self.view_uniform = _VIEW_UNIFORM_BY_PROJECTION[Projection.PERSPECTIVE]
        self.specular_shown = True
        self.marker_program = load_program(ctx, "marker")
        self.edges = Uniforms(self.programs.edges)
        for sampler, unit in EDGE_FACE_UNITS.items():
            self.edges.set(sampler, unit)
        self.normals = Uniforms(self.programs.normals)
        self.outline = Uniforms(self.programs.outline)
        self.marker = Uniforms(self.marker_program)
        self.marker_vao = ctx.vertex_array(self.marker_program, [])  # the position is a uniform
        self.guides = GuidesDrawer(ctx)
        self.guide_uniforms = Uniforms(self.guides.program)
        self.texture: MipmappedTexture | None = None
        self._texture_image: np.ndarray | None = None  # the scene's picture the texture was made from
        self._set_texture(PLAIN_PICTURE)
        self._objects: dict[tuple[int, int], ObjectGpu] = {}  # by (uid, part)
        # The probed face's mesh, the face, and the polygons across its edges (Mesh.edge_neighbours).
        self._probe_neighbours: tuple[Mesh, int, np.ndarray] | None = None
        self._meshes = MeshGpus(ctx)  # the buffers of each mesh, shared by the objects placing it
        # By id of the image and its sampling: materials may sample one picture two ways.
        self._file_textures: dict[tuple[int, TextureSampling], tuple[np.ndarray, MipmappedTexture]] = {}

    # --- resources ---------------------------------------------------------------------------
    def _use_scene_texture(self, scene: Scene) -> None:
        image = PLAIN_PICTURE if scene.texture is None else scene.texture
        if image is not self._texture_image:
            self._set_texture(image)

    @property
    def max_texture_side(self) -> int:
        """The longest texture side this GL takes (the viewer fits larger pictures to it)."""
        return max_texture_side(self.ctx)

    def _set_texture(self, image: np.ndarray) -> None:
        """(H, W, 3) uint8, top row first. GL's first row is v = 0, and SPEC 5 wants v = 0 at the
        image's bottom row, so the rows go up reversed."""
        height, width = image.shape[:2]
        if max(height, width) > self.max_texture_side:
            raise ViewerError(f"a texture of {width}x{height} is larger than this OpenGL takes "
                              f"({self.max_texture_side} pixels a side)")
        pixels = np.ascontiguousarray(np.flipud(np.asarray(image, dtype=np.uint8)[..., :3]))
        if self.texture is not None:
            self.texture.release()
            self.texture = None
        self.ctx.error  # noqa: B018 - reading it clears an older error, so the check is about this upload
        self.texture = create_mipmapped(self.ctx, pixels)
        check_gl(self.ctx, f"a texture of {width}x{height}")
        self._texture_image = image

    def release_object(self, obj: SceneObject) -> None:
        for key in [key for key in self._objects if key[0] == obj.uid]:
            self._meshes.release(self._objects.pop(key))

    def release(self) -> None:
        for gpu in self._objects.values():
            self._meshes.release(gpu)
        self._objects.clear()
        for _, texture in self._file_textures.values():
            texture.release()
        self._file_textures.clear()
        self.guides.release_program()
        lighting_passes = [program for way in self.programs.lightings for program in self.programs.lighting_passes(way)]
        for resource in (self.marker_vao, self.texture, *self.programs.surfaces.values(), *lighting_passes,
                         self.programs.edges, self.programs.normals, self.programs.outline, self.marker_program):
            if resource is not None:
                resource.release()
        self.texture = None

    def _surface_program(self, way: SurfaceWay) -> moderngl.Program:
        return load_program(self.ctx, "surface", defines={**way.defines, **self._defines})

    def _use_way(self, way: SurfaceWay) -> None:
        """Draws surfaces with the program of `way` from now on, made the first time it is used."""
        if way not in self.programs.surfaces:
            self.programs.surfaces[way] = program = self._surface_program(way)
            self.surface_uniforms[way] = Uniforms(program)
        # Looked up once a view, not once an object drawn.
        self.way, self.surface, self.lighting = way, self.surface_uniforms[way], self.lighting_uniforms[way.shading]
        # Those that read each object's model and whether it is vertex coloured (Phong's are one).
        self.object_uniforms = (self.surface,) if self.lighting is self.surface else (self.surface, self.lighting)
        # Gouraud's depth view reads no lit row (Flat's reads its N.V): nothing to light for it.
        self.reads_lit_rows = way.shading.lights_vertices and LIT_LAYOUT[1] in self.programs.surfaces[way]

    def _gpu_for(self, obj: SceneObject, part: int = WHOLE) -> ObjectGpu:
        gpu = self._objects.get((obj.uid, part))
        if gpu is not None and gpu.mesh is obj.mesh:
            return gpu
        if gpu is not None:  # the object got a new mesh: its old buffers are stale
            self._meshes.release(self._objects.pop((obj.uid, part)))
        gpu = self._objects[(obj.uid, part)] = self._meshes.object_gpu(obj.mesh, self.programs, part)
        return gpu

    def _drop_departed(self, scene: Scene) -> None:
        elements = scene.objects + scene.cameras
        live = {(obj.uid, part) for obj in elements for part in range(WHOLE, len(obj.mesh.parts))}
        for key in [key for key in self._objects if key not in live]:
            self._meshes.release(self._objects.pop(key))
        pictures = {(id(obj.picture_of(part)), obj.sampling_of(part)) for obj in elements
                    for part in range(WHOLE, len(obj.mesh.materials))}
        for key in [key for key in self._file_textures if key not in pictures]:
            self._file_textures.pop(key)[1].release()

    def _file_texture(self, image: np.ndarray, sampling: TextureSampling) -> MipmappedTexture:
        """A material's own picture on the GPU, sampled its way, made once; one larger than the GPU takes
        is scaled down (the scene's texture is, by the viewer, with a note; a file's can only be done here)."""
        held = self._file_textures.get((id(image), sampling))
        if held is None:
            fitted, _ = fit_texture(image, self.max_texture_side)
            pixels = np.ascontiguousarray(np.flipud(np.asarray(fitted, dtype=np.uint8)[..., :3]))
            self.ctx.error  # noqa: B018 - reading it clears an older error, so the check is about this upload
            made = create_mipmapped(self.ctx, pixels, sampling)
            try:
                check_gl(self.ctx, f"a texture of {pixels.shape[1]}x{pixels.shape[0]}")
            except ViewerError:
                made.release()  # held by nothing yet: kept, it would never be freed
                raise
            held = self._file_textures[id(image), sampling] = (image, made)
        return held[1]

    # --- a frame -----------------------------------------------------------------------------
    def render(self, scene: Scene, fbo: moderngl.Framebuffer, size: tuple[int, int]) -> None:
        """Clear `fbo` to the seed's blue and draw `scene` into its (0, 0, width, height) viewport,
        once, or three times side by side."""
        self._drop_departed(scene)
        self._use_scene_texture(scene)
        width, height = max(int(size[0]), 1), max(int(size[1]), 1)
        self.size = (width, height)
        fbo.use()
        fbo.viewport = (0, 0, width, height)
        fbo.clear(*CLEAR_COLOUR, 1.0, depth=1.0)
        items = [(part, self._gpu_for(part.obj, part.part))
                 for item in self._draw_list(scene) for part in split_by_material(item)]
        all_views = views(scene, (width, height))
        for view in all_views:
            fbo.viewport = view.viewport
            self._render_view(scene, view, items)
        for view in all_views[1:]:  # a thin line between the thirds, so each reads as its own picture
            fbo.clear(*SEPARATOR_COLOUR, 1.0, viewport=(view.viewport[0] - SEPARATOR_PX // 2, 0,
                                                        SEPARATOR_PX, height))
        fbo.viewport = (0, 0, width, height)  # the overlay draws over the whole framebuffer
        self.ctx.disable(moderngl.DEPTH_TEST)

    def _render_view(self, scene: Scene, view: View,
                     items: list[tuple[DrawItem, ObjectGpu]]) -> None:
        self._use_way(SurfaceWay(view.shading, depth_view=scene.modes.term_view.shows is Show.DEPTH))
        self.origin = self._frame_origin(scene, items)
        placed = scene.view_matrix() @ translation_by(self.origin)
        slices = scene.depth_slices(view.aspect)  # worked out once: the near plane looks at every box
        projections = [lens.matrix() for lens in slices]
        self._set_frame_uniforms(scene, projections[0] @ placed)
        guides = scene_guides(scene) if scene.modes.guides else None
        for index, projection in enumerate(projections):
            if index:  # a nearer slice: its own depth buffer, over the farther one's picture
                self._clear_depth(view)
                self._set_view_projection(projection @ placed)
            self._draw_slice(scene, view, items, projection, placed, guides)
        if scene.modes.target is Target.LIGHTS:
            if len(slices) > 1:  # over everything, undepth-tested: the whole depth's lens keeps it unclipped
                self._set_view_projection(replace(slices[0], near=slices[-1].near).matrix() @ placed)
            self._draw_light_marker(scene)

    def _draw_slice(self, scene: Scene, view: View, items: list[tuple[DrawItem, ObjectGpu]],
                    projection: np.ndarray, placed: np.ndarray, guides: Guides | None) -> None:
        """What a view draws between one depth slice's near and far planes (the whole view's, but for
        extreme depths: Scene.depth_slices)."""
        filled = scene.modes.fill is Fill.FILLED
        self._set_gl_state(depth_test=filled)  # per slice: the farther one's probe outline ends with it off
        if filled:
            for item, gpu in items:
                self._draw_surface(item, gpu)
        else:
            self._draw_all_edges(scene, items)
        if scene.modes.normals:
            for item, gpu in items:
                self._draw_normals(item, gpu, face_normals=view.shading is Shading.FLAT)
        per_w = pixel_per_w(projection, view)  # what ray_depth.glsl moves depths by
        if guides is not None:
            self.guide_uniforms.set("u_pixel_per_w", per_w)
            self.guides.draw(guides, self.ctx.fbo, self.origin)
        if scene.modes.probe or scene.modes.pipeline:  # the face the panel follows
            self._draw_probe_outline(scene, view, filled, per_w, projection @ placed)

    def _clear_depth(self, view: View) -> None:
        """The view's depth cleared, its colours kept: GL clears only what the colour mask lets through."""
        fbo = self.ctx.fbo
        mask = fbo.color_mask
        fbo.color_mask = (False, False, False, False)
        try:
            fbo.clear(depth=1.0, viewport=view.viewport)
        finally:  # the mask is the framebuffer's own: left off, every later picture in it would be blank
            fbo.color_mask = mask
            fbo.use()  # moderngl hands a framebuffer's masks to GL as it binds it (or clears), not as they are set

    @staticmethod
    def _frame_origin(scene: Scene, items: list[tuple[DrawItem, ObjectGpu]]) -> np.ndarray:
        """The world's origin, or the eye where a model far from it is drawn (Mesh.gpu_origin) or the
        eye is far from it for the models' sizes (a scene placing a 1-unit model at 1e8): world
        positions are then measured from the eye, in 64-bit numbers, and stay small near it."""
        eye = np.asarray(scene.eye_position(), dtype=np.float64)
        sizes = [gpu.shared.size for _, gpu in items if gpu.shared.size > 0]
        if any(gpu.shared.offset for _, gpu in items) or (
                sizes and np.abs(eye).max() > EYE_ORIGIN_SIZES * min(sizes)):
            return eye
        return np.zeros(3)

    def _set_gl_state(self, depth_test: bool) -> None:
        # Flat needs the first vertex's values: the fan's first corner is the polygon's first vertex.
        self.ctx.provoking_vertex = moderngl.FIRST_VERTEX_CONVENTION
        # SPEC defines back faces by N.V, not by winding (parallel projection has one V), so GL's
        # own culling stays off and the shaders decide.
        self.ctx.disable(moderngl.CULL_FACE | moderngl.BLEND)
        if depth_test:
            self.ctx.enable(moderngl.DEPTH_TEST)
        else:
            self.ctx.disable(moderngl.DEPTH_TEST)

    def _draw_list(self, scene: Scene) -> list[DrawItem]:
        """What the picture draws (Scene.drawn_faces: SPEC 5's `o` and `d`), as draw items."""
        return [DrawItem(element, start, stop) for element, start, stop in scene.drawn_faces()]

    # --- uniforms ----------------------------------------------------------------------------
    def _set_frame_uniforms(self, scene: Scene, view_projection: np.ndarray) -> None:
        modes = scene.modes
        parallel = modes.projection is Projection.PARALLEL
        eye = tuple(float(c) for c in scene.eye_position() - self.origin)
        backward = tuple(float(c) for c in scene.eye_backward())
        self._set_view_projection(view_projection)
        for uniforms in (self.lighting, self.edges, self.outline, self.guide_uniforms, self.marker):
            uniforms.set("u_parallel", parallel)
            uniforms.set("u_eye_position", eye)
            uniforms.set("u_eye_backward", backward)
        # Only the lights the term view shows: "one light alone" switches the others off here.
        shown = scene.lights_in_view()[:MAX_LIGHTS]
        self.view_uniform = _VIEW_UNIFORM_BY_PROJECTION[modes.projection]
        term_view = modes.term_view
        self.specular_shown = term_view.shows is Show.LIT and term_view.weights.specular != 0 and bool(shown)
        self.surface.set("u_culling", modes.culling)
        self.surface.set("u_textured", modes.texture)
        for uniforms in (self.surface, self.lighting):
            uniforms.set("u_show", modes.term_view.shows.value)
        self.surface.set("u_texture", 0)
        self.lighting.set("u_term_weights", modes.term_view.weights.as_tuple())
        self.lighting.set("u_ambient", tuple(float(c) for c in scene.ambient))
        self._set_light_uniforms(shown)
        self.normals.set("u_colour", NORMAL_COLOUR)

    def _set_view_projection(self, view_projection: np.ndarray) -> None:
        for uniforms in (self.surface, self.edges, self.normals, self.outline, self.marker, self.guide_uniforms):
            uniforms.set_matrix("u_view_projection", view_projection)

    def _set_light_uniforms(self, shown: list[WorldLight]) -> None:
        """The lights `shown` (on, and in the term view), packed first: the shader lights with the
        first u_lights_on of them."""
        kind = np.zeros(MAX_LIGHTS, "i4")
        intensity = np.zeros((MAX_LIGHTS, 3), "f4")
        position = np.zeros((MAX_LIGHTS, 3), "f4")
        direction = np.zeros((MAX_LIGHTS, 3), "f4")
        cos_aperture = np.ones(MAX_LIGHTS, "f4")
        for i, light in enumerate(shown):
            kind[i] = light.kind.shader_code
            intensity[i] = light.intensity
            position[i] = light.position - self.origin
            direction[i] = light.direction
            cos_aperture[i] = np.cos(np.radians(light.aperture_deg))
        self.lighting.set("u_lights_on", len(shown))
        self.lighting.set_array("u_light_kind", kind)
        self.lighting.set_array("u_light_intensity", intensity)
        self.lighting.set_array("u_light_position", position)
        self.lighting.set_array("u_light_direction", direction)
        self.lighting.set_array("u_light_cos_aperture", cos_aperture)

    def _set_model(self, uniforms: Iterable[Uniforms], model: np.ndarray, gpu: ObjectGpu) -> None:
        """The object's model and normal matrices, worked out again only when it or the frame's origin
        has moved since its last draw (a still scene of a thousand objects inverts no matrix)."""
        key = model.tobytes() + self.origin.tobytes()
        if gpu.placement is None or gpu.placement[0] != key:
            gpu.placement = (key, *self._placement(model, gpu.shared))
        _, model_bytes, normal_bytes = gpu.placement
        for u in uniforms:
            u.set_bytes("u_model", model_bytes)
            u.set_bytes("u_normal_matrix", normal_bytes)

    def _placement(self, model: np.ndarray, shared: MeshGpu) -> tuple[bytes, bytes]:
        """`model` for a mesh's GPU rows (from its gpu_origin, into the world less the frame's origin)
        and its normal matrix, as GL reads them."""
        normals = normal_matrix(model)
        if shared.offset or self.origin.any():
            model = translation_by(-self.origin) @ model @ translation_by(shared.mesh.gpu_origin)
        return gl_matrix(model), gl_matrix(normals)

    # --- drawing -----------------------------------------------------------------------------
    def _draw_surface(self, item: DrawItem, gpu: ObjectGpu) -> None:
        material = item.obj.material_of(item.file_material)
        lighting = self.lighting
        self._set_model(self.object_uniforms, item.obj.model, gpu)
        lighting.set("u_ka", tuple(material.ka))
        lighting.set("u_kd", tuple(material.kd))
        lighting.set("u_ks", tuple(material.ks))
        lighting.set("u_ns", float(material.ns))
        for uniforms in self.object_uniforms:  # the lighting pass tints its rows; Phong, its pixels
            uniforms.set("u_vertex_coloured", gpu.shared.vertex_coloured)
        if self.reads_lit_rows:
            self.lighting_passes += gpu.light(self.way.shading, self._lighting_inputs(material), item.start, item.stop)
        assert self.texture is not None
        picture = item.obj.picture_of(item.file_material)
        if picture is None:
            self.texture.use(location=0)
        else:
            self._file_texture(picture, item.obj.sampling_of(item.file_material)).use(location=0)
        self.draw(gpu.surface(self.way), moderngl.TRIANGLES, gpu.shared.surface_range(item.start, item.stop))

    def _lighting_inputs(self, material: Material) -> tuple[tuple[str, bytes], ...]:
        """What the lighting pass reads, for the rows it keeps: its uniforms, less the V it does not
        read, so that a camera that changes only that lights nothing again. Flat's rows carry N.V, for
        its back-face test; Gouraud's colours read V only through a specular term that shows: a weight
        of 0 times surface.glsl's pow, which it keeps at most 1, adds nothing."""
        reads_view = self.way.shading is not Shading.GOURAUD or (self.specular_shown and any(material.ks))
        unread = _VIEW_UNIFORMS - {self.view_uniform} if reads_view else _VIEW_UNIFORMS
        return tuple((name, value) for name, value in self.lighting.values() if name not in unread)

    def _draw_all_edges(self, scene: Scene, items: list[tuple[DrawItem, ObjectGpu]]) -> None:
        """Every object's edges in one pass: front faces' edges over back faces' (red; skipped with
        culling on) through the depth test on the depth edges.glsl writes, so an edge between a front
        and a back face shows the front's colour. The model's own depth is never tested: hidden edges show."""
        self.edges.set("u_culling", scene.modes.culling)
        self.ctx.enable(moderngl.DEPTH_TEST)
        self.ctx.depth_func = "<="
        for item, gpu in items:
            self._draw_edges(item, gpu, selected=item.obj is scene.object)
        self.ctx.depth_func = "<"
        self.ctx.disable(moderngl.DEPTH_TEST)

    def _draw_edges(self, item: DrawItem, gpu: ObjectGpu, selected: bool) -> None:
        self._set_model([self.edges], item.obj.model, gpu)
        self.edges.set("u_colour", SELECTED_LINE_COLOUR if selected else LINE_COLOUR)
        self._draw_edge_lines(gpu.shared, gpu.shared.edge_range(item.start, item.stop))

    def _draw_probe_outline(self, scene: Scene, view: View, filled: bool, per_w: float,
                            view_projection: np.ndarray) -> None:
        """The probed face's edges and a dot on each vertex the probe lights, so that the face can be
        found whatever covers it: in filled mode solid where the picture shows them and dashed (the
        dots hollow) where something hides them, as CAD and x-ray views tell a hidden edge; in lines
        mode, where nothing hides anything, solid over everything."""
        found = probed_face(scene)
        if found is None or found.obj is scene.viewer:
            return
        part, face = part_of_face(found.obj, found.face)
        gpu = self._gpu_for(found.obj, part)
        self._set_model([self.outline], found.obj.model, gpu)
        self.outline.set("u_colour", PROBE_COLOUR)
        pull = self._probe_pull_px(scene, found)
        for uniforms in (self.outline, self.marker):
            uniforms.set("u_viewport", tuple(float(c) for c in view.viewport))
            uniforms.set("u_pull_px", pull)
            uniforms.set("u_pixel_per_w", per_w)
        self.marker.set("u_plane_normal", tuple(float(c) for c in found.face_normal))
        self.marker.set_matrix("u_inverse_view_projection", np.linalg.inv(view_projection))  # a pixel's ray
        points = scene.probed_points(MAX_PROBE_MARKERS)
        fbo = self.ctx.fbo
        fbo.depth_mask = False  # the picture's depth stays for the second pass to test against
        for hidden, depth_func in _PROBE_PASSES if filled else ((False, None),):
            if depth_func is None:
                self.ctx.disable(moderngl.DEPTH_TEST)
            else:
                self.ctx.enable(moderngl.DEPTH_TEST)
                self.ctx.depth_func = depth_func
            for uniforms in (self.outline, self.marker):
                uniforms.set("u_hidden", hidden)
            self.draw(gpu.shared.outline, moderngl.LINES, gpu.shared.edge_range(face, face + 1))
            for point in points:
                self._draw_marker(point, np.array(PROBE_COLOUR), PROBE_MARKER_PX)
        fbo.depth_mask = True
        self.ctx.depth_func = "<"
        self.ctx.disable(moderngl.DEPTH_TEST)

    def _probe_pull_px(self, scene: Scene, found: ProbedFace) -> float:
        """How far toward the eye the probe's outline and dots are tested: the outline's pixels lie on
        the face or on a polygon across one of its edges, up to half a pixel off the edge, so the more
        obliquely the most oblique of them is seen, the further."""
        mesh = found.obj.mesh
        held = self._probe_neighbours
        if held is None or held[0] is not mesh or held[1] != found.face:  # one pass over the mesh a face
            held = self._probe_neighbours = (mesh, found.face, mesh.edge_neighbours(found.face))
        steepest = min(abs(found.facing), float(np.abs(facings(scene, found.obj, held[2])).min(initial=1.0)))
        return PROBE_PULL_PX / max(steepest, MIN_PROBE_FACING)

    def _draw_normals(self, item: DrawItem, gpu: ObjectGpu, face_normals: bool) -> None:
        """Face normals where lighting uses them (Flat), vertex normals otherwise (Gouraud, Phong)."""
        self._set_model([self.normals], item.obj.model, gpu)
        self.normals.set("u_length", NORMAL_LENGTH_FRACTION * item.obj.mesh.size)  # the whole object's scale
        shared = gpu.shared
        if face_normals:  # one point per normal: normals.glsl draws its segment
            self.draw_segments(shared.face_normals, moderngl.POINTS, shared.face_normal_range(item.start, item.stop))
        else:
            vao, span = shared.vertex_normals(item.start, item.stop)
            self.draw_segments(vao, moderngl.POINTS, span)

    def _draw_edge_lines(self, gpu: MeshGpu, span: VertexRange) -> None:
        edges = gpu.edges
        gpu.use_edge_faces()
        self.draw(edges, moderngl.LINES, span)

    def _draw_light_marker(self, scene: Scene) -> None:
        """The selected light as a dot in its own colour (dimmed while it is off), over everything."""
        light = scene.light
        colour = np.asarray(light.intensity, float) / 255.0 * (1.0 if light.on else 0.4)
        self.ctx.disable(moderngl.DEPTH_TEST)
        self.marker.set("u_hidden", False)  # a dot of its own, whole: not a probed corner
        self.marker.set("u_pull_px", 0.0)
        self.marker.set("u_plane_normal", (0.0, 0.0, 0.0))
        self._draw_marker(scene.placed_light(light).position, colour, MARKER_SIZE_PX)

    def _draw_marker(self, position: np.ndarray, colour: np.ndarray, size_px: float) -> None:
        """A square dot, through the depth test as it stands."""
        self.marker.set("u_position", tuple(float(c) for c in position - self.origin))
        self.marker.set("u_colour", tuple(float(c) for c in colour))
        self.marker.set("u_point_size", scaled_px(size_px, self.size))  # as large to the eye as the text
        self.marker.set("u_hollow_border_px", scaled_px(HOLLOW_BORDER_PX, self.size))  # grown with the dot
        self.ctx.enable(moderngl.PROGRAM_POINT_SIZE)
        self.marker_vao.render(moderngl.POINTS, vertices=1)
        self.ctx.disable(moderngl.PROGRAM_POINT_SIZE)


@dataclass(frozen=True)
class Draw:
    """Draw calls, whole, or in pieces of `piece_primitives` with a `flush` after each but the last
    (marraztu.render.context.draw_piece_primitives), and with a wait for the GPU instead every
    `pieces_in_flight` pieces where that is set: the same pixels any way, GL keeping the order."""

    piece_primitives: int | None = None
    flush: Callable[[], None] = lambda: None
    pieces_in_flight: int | None = None

    def __call__(self, vao: moderngl.VertexArray, mode: int, span: VertexRange) -> None:
        stop = span.first + span.vertices
        piece = span.vertices if self.piece_primitives is None else self.piece_primitives * _VERTICES_PER[mode]
        for count, first in enumerate(range(span.first, stop, max(piece, 1))):
            if count and self.pieces_in_flight and count % self.pieces_in_flight == 0:
                vao.ctx.finish()
            elif count:
                self.flush()
            vao.render(mode, vertices=min(piece, stop - first), first=first)


def pieced_draws(ctx: moderngl.Context) -> tuple[Draw, Draw]:
    """The draws for surfaces and edges, and for the normals' segments: in pieces on llvmpipe."""
    piece = draw_piece_primitives(ctx)
    if piece is None:
        return Draw(), Draw()

    def flush() -> None:  # glFlush is looked up at a draw's second piece: a start whose draws fit in one never looks
        gl_flush()()

    return Draw(piece, flush), Draw(piece, flush, SOFTWARE_SEGMENT_PIECES_IN_FLIGHT)


_VERTICES_PER = {moderngl.TRIANGLES: 3, moderngl.LINES: 2, moderngl.POINTS: 1}  # the modes the renderer draws
