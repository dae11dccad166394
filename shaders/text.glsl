#version 330
// Overlay text: one instance per character, a cell of the glyph atlas copied pixel for pixel onto
// whole pixels, so thin strokes stay as the atlas has them instead of being lost to filtering.

#if defined VERTEX_SHADER

in vec2 in_origin;  // per character: its cell's bottom-left corner, in whole pixels, origin bottom-left
in float in_glyph;  // per character: its cell in the atlas, row by row from the atlas's top-left

uniform vec2 u_viewport;     // pixels
uniform vec2 u_cell;         // a character's size in pixels
uniform vec2 u_atlas_cells;  // columns and rows of the atlas

out vec2 v_uv;

void main() {
    vec2 corner = vec2(gl_VertexID & 1, gl_VertexID >> 1);  // a triangle strip: (0,0) (1,0) (0,1) (1,1)
    gl_Position = vec4((in_origin + corner * u_cell) / u_viewport * 2.0 - 1.0, 0.0, 1.0);
    vec2 cell = vec2(mod(in_glyph, u_atlas_cells.x), floor(in_glyph / u_atlas_cells.x));
    // The atlas went up with its rows reversed: its top row of cells is at the top of the texture.
    v_uv = vec2(cell.x + corner.x, u_atlas_cells.y - cell.y - 1.0 + corner.y) / u_atlas_cells;
}

#elif defined FRAGMENT_SHADER

uniform sampler2D u_atlas;  // coverage in red
uniform vec4 u_colour;

in vec2 v_uv;
out vec4 f_colour;

void main() {
    f_colour = vec4(u_colour.rgb, u_colour.a * texture(u_atlas, v_uv).r);
}

#endif
