#version 330
// A translucent dark rectangle behind overlay text, so it stays legible over any scene.

#if defined VERTEX_SHADER

in vec2 in_position;  // pixels, origin bottom-left
uniform vec2 u_viewport;  // pixels

void main() {
    gl_Position = vec4(in_position / u_viewport * 2.0 - 1.0, 0.0, 1.0);
}

#elif defined FRAGMENT_SHADER

uniform vec4 u_colour;
out vec4 f_colour;

void main() {
    f_colour = u_colour;
}

#endif
