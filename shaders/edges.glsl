#version 330 core
// Lines mode (SPEC 5): every polygon's boundary edges in one colour (the selected object green,
// the others white), no lighting, no texture; edges of back faces red, or not drawn with culling on.
// A silhouette edge belongs to a front and a back face and must show the front's colour. One pass
// does it with the depth test (GL_LEQUAL) on a depth that says only which kind an edge is: front
// edges nearer than back ones, so a front edge covers a back one whichever is drawn first, and among
// edges of one kind the last drawn wins: the picture of back edges drawn before front ones, in one pass.
// The lighting probe's outline draws the same rows with a program of its own (outline.glsl).

#if defined VERTEX_SHADER

in vec3 in_position;
in uvec2 in_face_texel;  // its polygon's texel in the two tables below

uniform sampler2D u_face_points;  // each polygon's first vertex: where SPEC 4 makes the back-face test
uniform sampler2D u_face_normals;
uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_view_projection;
uniform bool u_parallel;
uniform vec3 u_eye_position;
uniform vec3 u_eye_backward;

flat out float v_facing;

void main() {
    ivec2 texel = ivec2(in_face_texel);
    vec3 face_point = (u_model * vec4(texelFetch(u_face_points, texel, 0).xyz, 1.0)).xyz;
    vec3 face_normal = normalize(u_normal_matrix * texelFetch(u_face_normals, texel, 0).xyz);
    vec3 view = u_parallel ? u_eye_backward : normalize(u_eye_position - face_point);
    v_facing = dot(face_normal, view);  // the same at both ends: both look up the same polygon
    gl_Position = u_view_projection * u_model * vec4(in_position, 1.0);
}

#elif defined FRAGMENT_SHADER

uniform vec3 u_colour;
uniform bool u_culling;  // back faces' edges: not drawn with culling on, red otherwise

flat in float v_facing;

out vec4 out_colour;

const float FRONT_EDGE_DEPTH = 0.25;
const float BACK_EDGE_DEPTH = 0.75;

void main() {
    bool front = v_facing > 0.0;
    if (!front && u_culling) {
        discard;
    }
    gl_FragDepth = front ? FRONT_EDGE_DEPTH : BACK_EDGE_DEPTH;
    out_colour = front ? vec4(u_colour, 1.0) : vec4(1.0, 0.0, 0.0, 1.0);
}

#endif
