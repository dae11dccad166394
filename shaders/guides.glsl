#version 330 core
// The grid and axes (key `a`): coloured segments already in world space, unlit, through the depth
// test in filled mode so that the models hide what lies behind them.

#if defined VERTEX_SHADER

in vec3 in_position;  // world
in vec3 in_colour;

uniform mat4 u_view_projection;

out vec3 v_colour;

void main() {
    v_colour = in_colour;
    gl_Position = u_view_projection * vec4(in_position, 1.0);
}

#elif defined FRAGMENT_SHADER

in vec3 v_colour;

out vec4 out_colour;

void main() {
    out_colour = vec4(v_colour, 1.0);
}

#endif
