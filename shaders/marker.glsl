#version 330 core
// A dot on a point: the selected light's position (SPEC 5), over everything, and the probed face's
// corners, solid where the picture shows them and hollow where something hides them (two passes
// through the depth test, u_hidden the second). No vertex buffer: the position is a uniform, so
// moving the light uploads nothing but the uniform.

#if defined VERTEX_SHADER

uniform mat4 u_view_projection;
uniform vec3 u_position;  // world
uniform float u_point_size;

void main() {
    gl_Position = u_view_projection * vec4(u_position, 1.0);
    gl_PointSize = u_point_size;
}

#elif defined FRAGMENT_SHADER

uniform vec3 u_colour;
uniform vec3 u_position;
uniform float u_point_size;
uniform vec4 u_viewport;  // x, y, width, height in window pixels
uniform mat4 u_inverse_view_projection;  // window to world, for a pixel's ray: inverted once a view, on the CPU
uniform vec3 u_plane_normal;  // the probed face's (world); 0 for a dot of its own
uniform float u_pull_px;  // toward the eye, as the outline's
uniform bool u_hidden;  // the pass where the picture's depth hides the dot: its border alone
uniform float u_hollow_border_px;  // that border's width, grown with the dot

#include "ray_depth"

out vec4 out_colour;

// The point of the face's plane this pixel shows, or the dot's own where the plane is seen edge on
// or lies behind the eye: a corner's dot is tested as the face around it would be, so that the
// surfaces about the corner, which a square of pixels reaches over, hide it only if they hide the face.
vec3 on_plane() {
    vec2 ndc = (gl_FragCoord.xy - u_viewport.xy) / u_viewport.zw * 2.0 - 1.0;
    vec4 near = u_inverse_view_projection * vec4(ndc, -1.0, 1.0);
    vec4 far = u_inverse_view_projection * vec4(ndc, 1.0, 1.0);
    vec3 start = near.xyz / near.w;
    vec3 along = far.xyz / far.w - start;
    float across = dot(along, u_plane_normal);
    float t = dot(u_position - start, u_plane_normal) / across;
    return abs(across) > 1e-6 * length(along) && t > 0.0 ? start + t * along : u_position;
}

void main() {
    float depth = min(depth_along_ray(on_plane(), -u_pull_px), depth_along_ray(u_position, -u_pull_px));
    gl_FragDepth = clamp(depth, 0.0, gl_FragCoord.z);
    vec2 from_centre = abs(gl_PointCoord - 0.5) * u_point_size;
    if (u_hidden && max(from_centre.x, from_centre.y) < 0.5 * u_point_size - u_hollow_border_px) {
        discard;
    }
    out_colour = vec4(u_colour, 1.0);
}

#endif
