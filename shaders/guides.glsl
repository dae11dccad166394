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

uniform mat4 u_view_projection;
uniform bool u_parallel;
uniform vec3 u_eye_position;
uniform vec3 u_eye_backward;
uniform float u_pixel_per_w;  // a pixel's width in the world at clip w = 1, in either projection

out vec4 out_colour;

void main() {
    // A line's depth is its nearest point's, up to half a pixel off the depth a surface in its plane
    // gets at the same pixel, so a model lying on the ground fought the grid pixel by pixel. Taken a
    // pixel further along its ray, a guide loses such ties and is still drawn where it is; a level
    // one, whose likeliest companion is a level surface, further where the ray grazes that surface's
    // plane and its depth changes fastest across a pixel.
    vec3 ray = u_parallel ? -u_eye_backward : normalize(v_position - u_eye_position);
    float pixel = u_pixel_per_w * (u_view_projection * vec4(v_position, 1.0)).w;
    float pixels = mix(1.0, 1.0 / max(abs(ray.y), MIN_GRAZE), v_level);
    vec4 pushed = u_view_projection * vec4(v_position + ray * pixel * pixels, 1.0);
    // Never past the far plane, which the clear's depth of 1 would hide.
    gl_FragDepth = max(gl_FragCoord.z, min(pushed.z / pushed.w * 0.5 + 0.5, 0.9999999));
    out_colour = vec4(v_colour, 1.0);
}

#endif
