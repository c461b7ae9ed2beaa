/* Private to bodyfit/: the parsed BVH file, shared by the reader and the retargeting. */
#ifndef TRYON_MOCAP_H
#define TRYON_MOCAP_H

#include "bodyfit.h"

#define MOCAP_NAME_MAX 64

typedef enum mocap_channel {
    MOCAP_XPOS,
    MOCAP_YPOS,
    MOCAP_ZPOS,
    MOCAP_XROT,
    MOCAP_YROT,
    MOCAP_ZROT
} mocap_channel;

typedef struct mocap_joint {
    char name[MOCAP_NAME_MAX];
    int parent; /* -1 for the root */
    float offset[3];
    int channel_count;     /* 0..6 */
    int channel_first;     /* index of its first value in a frame */
    unsigned char chan[6]; /* mocap_channel, in the file's order */
    int has_end;           /* an End Site follows: end_offset is valid */
    float end_offset[3];
} mocap_joint;

struct fit_bvh {
    mocap_joint joint[FIT_BVH_MAX_JOINTS];
    int joint_count;
    int channels; /* values per frame */
    int frames;
    double frame_time_s;
    float *values; /* [frames][channels] as in the file: degrees and file units */
};

/* Rotation helpers (double, row-major 3x3; quaternions w, x, y, z). */
void mocap_mat_mul(const double a[9], const double b[9], double out[9]);
void mocap_mat_tmul(const double a[9], const double b[9], double out[9]); /* a^T b */
void mocap_mat_apply(const double m[9], const double v[3], double out[3]);
void mocap_mat_to_quat(const double m[9], double q[4]);
void mocap_quat_to_mat(const double q[4], double m[9]);
void mocap_quat_slerp(const double a[4], const double b[4], double t, double out[4]);
void mocap_quat_to_axis_angle(const double q[4], float rot[3]);
/* The smallest rotation taking unit vector from onto unit vector to. */
void mocap_mat_between(const double from[3], const double to[3], double m[9]);

#endif
