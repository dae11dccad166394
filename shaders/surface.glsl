#version 330 core
// Filled polygons (SPEC 4 and 5): the seed's ambient + diffuse + specular lighting in world space,
// in the seed's 0..255 units; back faces red or discarded; the lit colour multiplied by the texture
// and by the model's own vertex colours when it has them.
// Three ways to spread it over a polygon, one program each (SHADING, defined by the renderer: a
// program built for one way drops the others' code and varyings):
//   Flat: evaluated once, at the polygon's first vertex with the face normal;
//   Gouraud: evaluated at every vertex with its vertex normal, the colours interpolated;
//   Phong: the position and vertex normal interpolated, evaluated at every pixel (side by side only).
// The depth view (DEPTH_VIEW defined) has a program of its own for each way, which paints the depth
// and hands on no colour: on an NVIDIA GPU, gl_FragCoord.z read in Gouraud's lit program, even in a
// branch never taken, made its frames of small triangles much slower.
// Flat and Gouraud light their vertices in a pass of their own (LIGHTING_PASS: transform feedback,
// nothing rasterised, or a compute program) that writes a colour per vertex row into the object's
// lit buffer, and the drawing pass reads it back as an attribute. The renderer runs that pass only
// when a uniform it reads has changed (marraztu.render.gpu's ObjectGpu.light), so a still frame
// lights nothing, and Flat lights only the polygons' own rows (one per polygon), not every corner a
// triangle touches.
// The lighting function is written once, above the stage blocks, so every pass compiles the same one.

// Macros, not constants, so that each program declares only the varyings its way reads: a GPU
// driver may keep a varying one stage writes and the other never reads.
#define FLAT 0
#define GOURAUD 1
#define PHONG 2
#ifndef SHADING
#error "SHADING must be defined as FLAT, GOURAUD or PHONG (the renderer does it)"
#endif
// The kinds of light and how many lights there are come from marraztu.model.lights.
#if !defined LIGHT_DIRECTIONAL || !defined LIGHT_POINT || !defined LIGHT_SPOT || !defined MAX_LIGHTS
#error "the light kinds' codes and MAX_LIGHTS must be defined (the renderer does it)"
#endif
// What the term view paints (marraztu.model.lights.Show): the lit colour, the depth or the normal.
#if !defined SHOW_LIT || !defined SHOW_DEPTH || !defined SHOW_NORMALS
#error "the term views' codes must be defined (the renderer does it)"
#endif

// V: perspective looks from a point, so V changes over the surface; parallel projection has one V.
uniform bool u_parallel;
uniform vec3 u_eye_position;
uniform vec3 u_eye_backward;

// The material, and the lights already placed in the world by the renderer.
uniform vec3 u_ka;
uniform vec3 u_kd;
uniform vec3 u_ks;
uniform float u_ns;
uniform vec3 u_ambient;  // Ia
// The term view (key `v`): 1 keeps the ambient, diffuse, specular term, 0 drops it. Lights that
// the view leaves out are switched off by the renderer.
uniform vec3 u_term_weights;

uniform int u_lights_on;  // how many: the renderer packs the lights that are on first
uniform int u_light_kind[MAX_LIGHTS];
uniform vec3 u_light_intensity[MAX_LIGHTS];
uniform vec3 u_light_position[MAX_LIGHTS];
uniform vec3 u_light_direction[MAX_LIGHTS];  // directional: toward the light; spot: the cone's axis
uniform float u_light_cos_aperture[MAX_LIGHTS];

vec3 toward_eye(vec3 point) {
    return u_parallel ? u_eye_backward : normalize(u_eye_position - point);
}

// Unit vector from the surface point toward the light.
vec3 toward_light(int i, vec3 point) {
    if (u_light_kind[i] == LIGHT_DIRECTIONAL) {
        return u_light_direction[i];
    }
    return normalize(u_light_position[i] - point);
}

// A spotlight lights the point only inside its cone: the angle between the axis and the ray from
// the light to the point (-L, exactly: normalize(-v) is -normalize(v)) is below the aperture, i.e.
// the cosine is above cos(aperture). Written so that NaN is outside.
bool outside_cone(int i, vec3 light) {
    return u_light_kind[i] == LIGHT_SPOT && !(dot(-light, u_light_direction[i]) > u_light_cos_aperture[i]);
}

// I = Ka*Ia + sum I_l * (Kd*max(N.L, 0) + Ks*max(N.H, 0)^ns), clamped to 255, returned as I/255.
// The loop stops at the lights that are on instead of testing a flag per light, and the cone test
// reuses L: both spare llvmpipe work in the lighting pass and give the same pixels.
vec3 lit_colour(vec3 point, vec3 normal, vec3 view) {
    vec3 intensity = u_term_weights.x * u_ka * u_ambient;
    vec3 specular_weight = u_term_weights.z * u_ks;
    for (int i = 0; i < MAX_LIGHTS; ++i) {
        if (i >= u_lights_on) {
            break;
        }
        vec3 light = toward_light(i, point);
        if (outside_cone(i, light)) {
            continue;
        }
        vec3 halfway = normalize(light + view);  // Blinn's H: the normal that would mirror L into V
        float diffuse = max(dot(normal, light), 0.0);
        // At most 1, as for unit vectors: where rounding took N.H past 1, a huge ns made pow infinite
        // and a Ks or weight of 0 times it NaN. So a term that weighs 0 adds 0 whatever V
        // (Renderer._lighting_inputs keeps such rows when only V changes).
        float n_dot_h = clamp(dot(normal, halfway), 0.0, 1.0);
        // pow(0, ns) is undefined in GLSL; the formula's value there is 0 for any ns > 0.
        float specular = n_dot_h > 0.0 ? pow(n_dot_h, u_ns) : 0.0;
        intensity += u_light_intensity[i] * (u_term_weights.y * u_kd * diffuse + specular_weight * specular);
    }
    return min(intensity, vec3(255.0)) / 255.0;
}

#if defined LIGHTING_PASS

uniform mat4 u_model;
uniform mat3 u_normal_matrix;  // inverse transpose of the model's 3x3: keeps normals perpendicular
uniform bool u_vertex_coloured;
uniform int u_show;

// What a row shows is made here, once per row and only when it changes, so the drawing pass of
// Flat and Gouraud is the same whatever the view: the lit colour times the vertex colour, or the
// normal the lighting would use as a colour (the normals view). rgb: what the row shows (0..1);
// a: N.V (Flat's back-face test at the first vertex).
vec4 lit_row(vec3 position, vec3 model_normal, vec4 colour) {
    vec3 world_position = (u_model * vec4(position, 1.0)).xyz;
    vec3 normal = normalize(u_normal_matrix * model_normal);
    vec3 view = toward_eye(world_position);
    vec3 shown;
    if (u_show == SHOW_NORMALS) {
        shown = normal * 0.5 + 0.5;
    } else {
        shown = lit_colour(world_position, normal, view);
        if (u_vertex_coloured) {
            shown *= colour.rgb;
        }
    }
    return vec4(shown, dot(normal, view));
}

#endif

#if defined VERTEX_SHADER && defined LIGHTING_PASS

in vec3 in_position;     // model space
in vec3 in_normal;       // a shared row's vertex normal (Gouraud); a polygon's own row's face normal (Flat)
in vec4 in_colour;       // the model's vertex colour (no buffer, and unread, for a model without)

out vec4 v_lit;  // captured by transform feedback into the lit buffer, at this row

void main() {
    v_lit = lit_row(in_position, in_normal, in_colour);
}

#elif defined COMPUTE_SHADER && defined LIGHTING_PASS

// The same pass as a compute program, where the renderer prefers one (llvmpipe runs a vertex stage
// on one thread and a compute program on all of them). The renderer binds a window of rows of each
// buffer, from a row that keeps every window's offset aligned, and names the rows to light in it.
layout(local_size_x = LIGHTING_GROUP_ROWS) in;

layout(std430, binding = SURFACE_BINDING) readonly buffer SurfaceBuffer { float surface_rows[]; };
layout(std430, binding = COLOURS_BINDING) readonly buffer ColourBuffer { uint colour_rows[]; };  // 4 bytes each
layout(std430, binding = LIT_BINDING) writeonly buffer LitBuffer { vec4 lit_rows[]; };

uniform uint u_first_row;  // in the window
uniform uint u_stop_row;

vec3 surface_vec3(uint at) {
    return vec3(surface_rows[at], surface_rows[at + 1u], surface_rows[at + 2u]);
}

void main() {
    uint row = gl_GlobalInvocationID.x;
    if (row < u_first_row || row >= u_stop_row) {
        return;
    }
    uint at = row * uint(SURFACE_ROW_FLOATS);  // where SURFACE_LAYOUT's row starts, in floats
    vec3 position = surface_vec3(at + uint(POSITION_AT));
    vec3 normal = surface_vec3(at + uint(NORMAL_AT));
    vec4 colour = vec4(1.0);
    if (u_vertex_coloured) {
        // Bytes times 1/255, as llvmpipe's vertex fetch reads them (unpackUnorm4x8 divides: a bit apart).
        colour = vec4((uvec4(colour_rows[row]) >> uvec4(0u, 8u, 16u, 24u)) & 255u) * (1.0 / 255.0);
    }
    lit_rows[row] = lit_row(position, normal, colour);
}

#elif defined VERTEX_SHADER

in vec3 in_position;  // model space
in vec3 in_normal;    // this corner's vertex normal (Phong: shared rows only)
in vec4 in_lit;       // Flat, Gouraud: the lighting pass's colour and N.V for this row
in vec2 in_uv;
in vec4 in_colour;    // Phong: the model's vertex colour (no buffer, and unread, for a model without)

uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_view_projection;
uniform bool u_vertex_coloured;

#if SHADING == FLAT
// With the provoking vertex set to the first one, `flat` varyings take the value of the first
// corner of each fan triangle, which Flat's indices make its polygon's own row (SPEC 4's Flat).
flat out vec4 v_flat_lit;  // the depth view reads its N.V alone
#elif !defined DEPTH_VIEW
smooth out vec3 v_smooth_colour;  // Gouraud: the lit colour; Phong: the vertex colour, or white
#endif
#if SHADING == PHONG && !defined DEPTH_VIEW
out vec3 v_world_position;  // interpolated, lit per pixel
out vec3 v_world_normal;
#endif
#if !defined DEPTH_VIEW
out vec2 v_uv;
#endif

void main() {
    vec3 world_position = (u_model * vec4(in_position, 1.0)).xyz;
#if SHADING == FLAT
    v_flat_lit = in_lit;
#elif SHADING == GOURAUD && !defined DEPTH_VIEW
    v_smooth_colour = in_lit.rgb;
#elif SHADING == PHONG && !defined DEPTH_VIEW
    v_smooth_colour = u_vertex_coloured ? in_colour.rgb : vec3(1.0);
    v_world_position = world_position;
    v_world_normal = normalize(u_normal_matrix * in_normal);
#endif
#if !defined DEPTH_VIEW
    v_uv = in_uv;
#endif
    gl_Position = u_view_projection * vec4(world_position, 1.0);
}

#elif defined FRAGMENT_SHADER

uniform bool u_culling;
uniform bool u_textured;
uniform sampler2D u_texture;
uniform int u_show;

#if SHADING == FLAT
flat in vec4 v_flat_lit;
#elif !defined DEPTH_VIEW
smooth in vec3 v_smooth_colour;
#endif
#if SHADING == PHONG && !defined DEPTH_VIEW
in vec3 v_world_position;
in vec3 v_world_normal;
#endif
#if !defined DEPTH_VIEW
in vec2 v_uv;
#endif

out vec4 out_colour;

#if !defined DEPTH_VIEW
vec3 surface_colour() {
#if SHADING == FLAT
    return v_flat_lit.rgb;
#elif SHADING == GOURAUD
    return v_smooth_colour;
#else
    // Interpolated unit normals are shorter than 1 between the corners: normalize again.
    vec3 normal = normalize(v_world_normal);
    if (u_show == SHOW_NORMALS) {
        return normal * 0.5 + 0.5;
    }
    return lit_colour(v_world_position, normal, toward_eye(v_world_position)) * v_smooth_colour;
#endif
}
#endif

// SPEC 4's back face: N.V <= 0 with the face normal at the polygon's first vertex. Flat draws from
// the polygon's own row, which carries that value. Gouraud and Phong draw from the shared rows only
// (SurfaceArrays.shared_indices: each corner lit once), where no row is the polygon's, so they ask
// the rasteriser, whose winding test gives the same verdict: the face normal is Newell's, from the
// same corner order as the winding, and N.(E - P) keeps one sign over the polygon's plane. (A
// polygon that is not flat may differ along a fold; the model matrices are rotations and
// translations, never mirrors, so counter-clockwise stays front.)
bool is_front_face() {
#if SHADING == FLAT
    return v_flat_lit.a > 0.0;
#else
    return gl_FrontFacing;
#endif
}

void main() {
    if (!is_front_face()) {  // a back face: hidden with culling on, shown red otherwise (SPEC 5)
        if (u_culling) {
            discard;
        }
        out_colour = vec4(1.0, 0.0, 0.0, 1.0);
        return;
    }
#if defined DEPTH_VIEW
    out_colour = vec4(vec3(gl_FragCoord.z), 1.0);
#else
    vec3 colour = surface_colour();
    if (u_textured && u_show == SHOW_LIT) {
        colour *= texture(u_texture, v_uv).rgb;
    }
    out_colour = vec4(colour, 1.0);
#endif
}

#endif
