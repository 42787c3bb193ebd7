/* The viewer's first-person camera (fly_camera.h). */
#include <math.h>

#include "fly_camera.h"

#define DEG (3.14159265358979f / 180.0f)
#define MIN_POLE_ANGLE_DEG 1.0f

fly_camera fly_camera_from(const rtt_camera *camera, float scene_size)
{
    rtt_vec3 view = rtt_v3_sub(camera->look_at, camera->eye);
    float focus = rtt_v3_length(view);
    if (!(scene_size > 0.0f) || !isfinite(scene_size)) scene_size = 1.0f;
    return (fly_camera){
        .eye = camera->eye,
        .forward = rtt_v3_normalize(view),
        .up = rtt_v3_normalize(camera->up),
        .fov_deg = camera->fov_deg,
        .focus = focus > 0.0f ? focus : 1.0f,
        .speed = 0.25f * scene_size,
        .start = *camera,
    };
}

rtt_camera fly_camera_to(const fly_camera *camera)
{
    if (!camera->moved) return camera->start;
    return (rtt_camera){
        .eye = camera->eye,
        .look_at = rtt_v3_madd(camera->eye, camera->forward, camera->focus),
        .up = camera->up,
        .fov_deg = camera->fov_deg,
    };
}

/* right = forward x up, unit; the forward vector never reaches the up
 * vector (fly_camera_turn), so it exists. */
static rtt_vec3 right_of(const fly_camera *camera)
{
    return rtt_v3_normalize(rtt_v3_cross(camera->forward, camera->up));
}

void fly_camera_move(fly_camera *camera, float forward, float right, float upward, float seconds)
{
    const float step = camera->speed * seconds;
    rtt_vec3 eye = camera->eye;
    eye = rtt_v3_madd(eye, camera->forward, forward * step);
    eye = rtt_v3_madd(eye, right_of(camera), right * step);
    eye = rtt_v3_madd(eye, camera->up, upward * step);
    if (!rtt_v3_is_finite(eye) || (eye.x == camera->eye.x && eye.y == camera->eye.y && eye.z == camera->eye.z)) return;
    camera->eye = eye;
    camera->moved = true;
}

/* v rotated by `angle` radians about the unit axis k (Rodrigues). */
static rtt_vec3 rotate(rtt_vec3 v, rtt_vec3 k, float angle)
{
    const float c = cosf(angle), s = sinf(angle);
    rtt_vec3 out = rtt_v3_scale(v, c);
    out = rtt_v3_madd(out, rtt_v3_cross(k, v), s);
    return rtt_v3_madd(out, k, rtt_v3_dot(k, v) * (1.0f - c));
}

void fly_camera_turn(fly_camera *camera, float yaw_deg, float pitch_deg)
{
    if (yaw_deg == 0.0f && pitch_deg == 0.0f) return;
    rtt_vec3 forward = rotate(camera->forward, camera->up, -yaw_deg * DEG);
    /* pitch: the angle from the up vector stays within [1, 179] degrees */
    const float from_up = acosf(fmaxf(-1.0f, fminf(1.0f, rtt_v3_dot(forward, camera->up)))) / DEG;
    const float target = fmaxf(MIN_POLE_ANGLE_DEG, fminf(180.0f - MIN_POLE_ANGLE_DEG, from_up - pitch_deg));
    const rtt_vec3 right = rtt_v3_normalize(rtt_v3_cross(forward, camera->up));
    forward = rotate(forward, right, (from_up - target) * DEG);
    forward = rtt_v3_normalize(forward);
    if (forward.x == camera->forward.x && forward.y == camera->forward.y && forward.z == camera->forward.z) return;
    camera->forward = forward;
    camera->moved = true;
}

void fly_camera_scale_speed(fly_camera *camera, float factor, float scene_size)
{
    if (!(scene_size > 0.0f) || !isfinite(scene_size)) scene_size = 1.0f;
    float speed = camera->speed * factor;
    camera->speed = fmaxf(1e-6f * scene_size, fminf(1e6f * scene_size, speed));
}
