"""Each filled drawing program passes on only what its shading reads (shaders/surface.glsl). Mesa drops
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
from marraztu.render.gpu import load_program

READS = {
    Shading.FLAT: {"v_flat_lit", "v_uv"},  # the polygon's own row, lit once, and the texture
    Shading.GOURAUD: {"v_smooth_colour", "v_uv"},
    Shading.PHONG: {"v_smooth_colour", "v_uv", "v_world_position", "v_world_normal"},  # lit per pixel
}
EVERY_VARYING = sorted(set().union(*READS.values()))


@pytest.mark.parametrize("way", list(Shading), ids=lambda way: way.name)
def test_each_drawing_program_declares_only_the_varyings_its_shading_reads(gl_ctx, way: Shading) -> None:
    defines = {"SHADING": way.name, **shader_defines()}
    for name in EVERY_VARYING:
        if name in READS[way]:
            load_program(gl_ctx, "surface", defines=defines, varyings=(name,)).release()
        else:
            with pytest.raises(moderngl.Error):
                load_program(gl_ctx, "surface", defines=defines, varyings=(name,))
