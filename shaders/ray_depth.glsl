// Not a program: moderngl pastes it where a program's stage includes it (gpu.SHADER_INCLUDES).
// A line drawn on a surface gets a depth up to half a pixel off the surface's at the same pixel, so
// the two fight pixel by pixel; moved a pixel or so along its ray, it loses (guides) or wins (the
// probe's outline and dots) such ties and is still drawn where it is.

uniform mat4 u_view_projection;
uniform bool u_parallel;
uniform vec3 u_eye_position;
uniform vec3 u_eye_backward;
uniform float u_pixel_per_w;  // a pixel's width in the world at clip w = 1, in either projection

// From the eye through `position` (world, less the frame's origin).
vec3 ray_through(vec3 position) {
    return u_parallel ? -u_eye_backward : normalize(position - u_eye_position);
}

// The window depth of `position` moved `pixels` pixel widths (taken there) along its ray: away from
// the eye, or toward it where negative, then at most half way to a perspective eye (w stays > 0).
float depth_along_ray(vec3 position, float pixels) {
    float w = (u_view_projection * vec4(position, 1.0)).w;
    float distance = u_pixel_per_w * w * pixels;
    if (!u_parallel) {
        distance = max(distance, -0.5 * w);  // the eye is at least w away
    }
    vec4 moved = u_view_projection * vec4(position + ray_through(position) * distance, 1.0);
    return moved.z / moved.w * 0.5 + 0.5;
}
