#version 330 core
// The lighting probe's outline (key `i`): the probed face's edges in one colour whichever way the face
// looks. In lines mode over everything; in filled mode solid where the picture shows them and dashed
// where something hides them, as CAD and x-ray views tell a hidden edge: two passes through the depth
// test, u_hidden the second. The edges program's rows, read without their polygon's texel.

#if defined VERTEX_SHADER

in vec3 in_position;

uniform mat4 u_model;
uniform mat4 u_view_projection;
uniform vec4 u_viewport;  // x, y, width, height in window pixels

out vec3 v_position;  // world, less the frame's origin
flat out vec2 v_start;  // the line's first end in window pixels: its dashes are measured from there

void main() {
    v_position = (u_model * vec4(in_position, 1.0)).xyz;
    gl_Position = u_view_projection * vec4(v_position, 1.0);
    // An end behind the eye is clipped away; its w only must not be 0 here.
    v_start = u_viewport.xy + (gl_Position.xy / max(abs(gl_Position.w), 1e-20) * 0.5 + 0.5) * u_viewport.zw;
}

#elif defined FRAGMENT_SHADER

uniform vec3 u_colour;
uniform bool u_hidden;  // the pass where the picture's depth hides the outline: dashed
uniform float u_pull_px;  // the outline's depth is taken this far toward the eye (Renderer._probe_pull_px)

in vec3 v_position;
flat in vec2 v_start;

#include "ray_depth"

out vec4 out_colour;

const float DASH_PX = 3.0;

void main() {
    gl_FragDepth = clamp(depth_along_ray(v_position, -u_pull_px), 0.0, gl_FragCoord.z);
    if (u_hidden && mod(distance(gl_FragCoord.xy, v_start), 2.0 * DASH_PX) >= DASH_PX) {
        discard;
    }
    out_colour = vec4(u_colour, 1.0);
}

#endif
