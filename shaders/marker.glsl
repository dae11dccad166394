#version 330 core
// The selected light's position (SPEC 5): one square point, drawn over everything. No vertex
// buffer: the position is a uniform, so moving the light uploads nothing but the uniform.

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

out vec4 out_colour;

void main() {
    out_colour = vec4(u_colour, 1.0);
}

#endif
