#version 330 core
// Normals (SPEC 5, key n): one short segment per normal, from its foot (a face's centroid in Flat,
// a vertex in Gouraud) along the world-space normal, a fixed length in world units. Each normal is
// one point (vertex normals: the surface's own rows); the geometry stage draws its segment.

#if defined VERTEX_SHADER

in vec3 in_position;   // the foot, model space
in vec3 in_direction;  // the normal, model space

uniform mat4 u_model;
uniform mat3 u_normal_matrix;

out vec3 v_foot;       // world space
out vec3 v_direction;  // world space, unit: the segment keeps its length whatever the model matrix does

void main() {
    v_foot = (u_model * vec4(in_position, 1.0)).xyz;
    v_direction = normalize(u_normal_matrix * in_direction);
}

#elif defined GEOMETRY_SHADER

layout(points) in;
layout(line_strip, max_vertices = 2) out;

in vec3 v_foot[];
in vec3 v_direction[];

uniform mat4 u_view_projection;
uniform float u_length;

void main() {
    gl_Position = u_view_projection * vec4(v_foot[0], 1.0);
    EmitVertex();
    gl_Position = u_view_projection * vec4(v_foot[0] + v_direction[0] * u_length, 1.0);
    EmitVertex();
    EndPrimitive();
}

#elif defined FRAGMENT_SHADER

uniform vec3 u_colour;

out vec4 out_colour;

void main() {
    out_colour = vec4(u_colour, 1.0);
}

#endif
