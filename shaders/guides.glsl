#version 330 core
// The grid and axes (key `a`): coloured segments already in world space, unlit, through the depth
// test in filled mode so that the models hide what lies behind them.

#if defined VERTEX_SHADER

in vec3 in_position;  // world, less the frame's origin
in vec3 in_colour;
in float in_level;  // 1 for a horizontal segment, 0 for any other

uniform mat4 u_view_projection;

out vec3 v_position;
out vec3 v_colour;
flat out float v_level;

void main() {
    v_position = in_position;
    v_colour = in_colour;
    v_level = in_level;
    gl_Position = u_view_projection * vec4(in_position, 1.0);
}

#elif defined FRAGMENT_SHADER

const float MIN_GRAZE = 0.02;  // the sine of the shallowest ray-to-ground angle pushed for

in vec3 v_position;
in vec3 v_colour;
flat in float v_level;

#include "ray_depth"

out vec4 out_colour;

void main() {
    // A model lying on the ground fought the grid pixel by pixel (ray_depth.glsl): a guide is taken
    // a pixel further along its ray; a level one, whose likeliest companion is a level surface,
    // further where the ray grazes that surface's plane and its depth changes fastest across a pixel.
    float pixels = mix(1.0, 1.0 / max(abs(ray_through(v_position).y), MIN_GRAZE), v_level);
    // Never past the far plane, which the clear's depth of 1 would hide.
    gl_FragDepth = max(gl_FragCoord.z, min(depth_along_ray(v_position, pixels), 0.9999999));
    out_colour = vec4(v_colour, 1.0);
}

#endif
