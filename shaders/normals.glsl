#version 330 core
// Normals (SPEC 5, key n): one short segment per normal, from its foot (a face's centroid in Flat,
// a vertex in Gouraud) along the world-space normal, a fixed length in world units.

#if defined VERTEX_SHADER

in vec3 in_position;   // the foot, model space
in vec3 in_direction;  // the normal, model space
in float in_along;     // 0 at the foot, 1 at the tip

uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_view_projection;
uniform float u_length;

void main() {
    vec3 foot = (u_model * vec4(in_position, 1.0)).xyz;
    vec3 direction = normalize(u_normal_matrix * in_direction);
    gl_Position = u_view_projection * vec4(foot + direction * (u_length * in_along), 1.0);
}

#elif defined FRAGMENT_SHADER

uniform vec3 u_colour;

out vec4 out_colour;

void main() {
    out_colour = vec4(u_colour, 1.0);
}

#endif
