/* The viewer's camera (fly_camera.c): a position, a view direction and the
 * scene's up, moved like a first-person camera.  Yaw turns about the up
 * vector; pitch tilts towards it and stops 1 degree short of it, so the
 * camera never flips.  Pure maths, independent of SDL. */
#ifndef RTT_VIEWER_FLY_CAMERA_H
#define RTT_VIEWER_FLY_CAMERA_H

#include "rtt/scene.h"

typedef struct fly_camera {
    rtt_vec3 eye;
    rtt_vec3 forward;    /* unit */
    rtt_vec3 up;         /* unit: the scene camera's up, fixed */
    float fov_deg;
    float focus;         /* distance of look_at from eye in rtt_camera form */
    float speed;         /* units per second */
    rtt_camera start;    /* the camera it was made from, returned exactly until it moves */
    bool moved;
} fly_camera;

/* From a scene camera; the speed starts at a quarter of `scene_size` (the
 * scene's bounding-box diagonal) per second. */
fly_camera fly_camera_from(const rtt_camera *camera, float scene_size);
/* The camera as the scene has it: exactly the start camera until a move or
 * a turn, so an unmoved viewer renders the scene's own picture. */
rtt_camera fly_camera_to(const fly_camera *camera);

/* Moves by forward, right and upward units of speed * seconds each
 * (-1..1 from the keys held). */
void fly_camera_move(fly_camera *camera, float forward, float right, float upward, float seconds);
/* Turns by `yaw_deg` to the right and `pitch_deg` upwards. */
void fly_camera_turn(fly_camera *camera, float yaw_deg, float pitch_deg);
/* Multiplies the speed by `factor`, kept within 1e-6..1e6 of scene_size. */
void fly_camera_scale_speed(fly_camera *camera, float factor, float scene_size);

#endif
