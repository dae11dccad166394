"""Each filled drawing program passes on only what its shading and view read (shaders/surface.glsl). Mesa drops
a varying the fragment stage never reads, but at least one GPU driver (NVIDIA's) keeps it, and the
attributes it is made from, at a cost in every frame: so the vertex stage of each shading must not
even declare the others' varyings. A transform-feedback program capturing a varying links only where
the vertex stage declares it.
"""

from __future__ import annotations

import moderngl
import pytest

from marraztu.model.lights import shader_defines
from marraztu.model.scene import Shading
from marraztu.render.gpu import SURFACE_WAYS, SurfaceWay, load_program

READS = {
    SurfaceWay(Shading.FLAT): {"v_flat_lit", "v_uv"},  # the polygon's own row, lit once, and the texture
    SurfaceWay(Shading.GOURAUD): {"v_smooth_colour", "v_uv"},
    SurfaceWay(Shading.PHONG): {"v_smooth_colour", "v_uv", "v_world_position", "v_world_normal"},  # lit per pixel
    # The depth view paints the depth: Flat keeps its row for SPEC 4's back-face test, the others
    # ask the rasteriser.
    SurfaceWay(Shading.FLAT, depth_view=True): {"v_flat_lit"},
    SurfaceWay(Shading.GOURAUD, depth_view=True): set(),
    SurfaceWay(Shading.PHONG, depth_view=True): set(),
}
EVERY_VARYING = sorted(set().union(*READS.values()))


def test_every_surface_program_is_listed() -> None:
    assert set(READS) == set(SURFACE_WAYS)


@pytest.mark.parametrize("way", SURFACE_WAYS, ids=lambda way: f"{way.shading.name}{'-depth' * way.depth_view}")
def test_each_drawing_program_declares_only_the_varyings_its_way_reads(gl_ctx, way: SurfaceWay) -> None:
    defines = {**way.defines, **shader_defines()}
    for name in EVERY_VARYING:
        if name in READS[way]:
            load_program(gl_ctx, "surface", defines=defines, varyings=(name,)).release()
        else:
            with pytest.raises(moderngl.Error):
                load_program(gl_ctx, "surface", defines=defines, varyings=(name,))


def test_the_depth_view_program_is_made_when_first_drawn(gl_ctx) -> None:
    """Start-up compiles the lit programs only; a depth view's program is made the first time that
    view is drawn, and kept."""
    from marraztu.loaders.scenefile import load_builtin_scene
    from marraztu.model.lights import TermView
    from marraztu.render.gpu import LIT_SURFACE_WAYS
    from marraztu.render.renderer import Renderer

    renderer = Renderer(gl_ctx)
    scene = load_builtin_scene()
    fbo = gl_ctx.simple_framebuffer((64, 48), components=4)
    try:
        assert set(renderer.programs.surfaces) == set(LIT_SURFACE_WAYS)
        renderer.render(scene, fbo, (64, 48))
        assert set(renderer.programs.surfaces) == set(LIT_SURFACE_WAYS)
        scene.modes.term_view = TermView.DEPTH
        renderer.render(scene, fbo, (64, 48))
        depth = SurfaceWay(Shading.FLAT, depth_view=True)
        made = renderer.programs.surfaces[depth]
        assert set(renderer.programs.surfaces) == {*LIT_SURFACE_WAYS, depth}
        renderer.render(scene, fbo, (64, 48))
        assert renderer.programs.surfaces[depth] is made
    finally:
        fbo.release()
        renderer.release()
