/* recordings: fakenect dumps (read, write, validate), the Kinect v1 disparity <-> depth
 * conversion libfreenect uses, a Kinect v1 noise model, and tryon-synth's renderer that films the
 * bodyfit model through a simulated Kinect with ground truth beside every frame.
 *
 * Frames: world is metres, y up, floor at y = 0. Camera coordinates are x right, y down, z along
 * the optical axis (the pinhole convention of depth_frame_t); camera_to_world is row-major 4x4. */
#ifndef TRYON_RECORDINGS_H
#define TRYON_RECORDINGS_H

#include <stddef.h>
#include <stdint.h>

/* The simulated Kinect v1 depth camera. */
#define REC_WIDTH      640
#define REC_HEIGHT     480
#define REC_FPS        30.0
#define REC_RAW_NONE   2047 /* 11-bit disparity meaning "no reading" */
#define REC_RAW_LEVELS 2048
/* libfreenect's default zero-plane info (src/registration.c, "default values ripped from my
 * Kinect"): IR camera to projector 7.5 cm, reference distance 120 mm, reference pixel size
 * 0.1042 mm at the 1280-wide sensor. freenect_camera_to_world derives its focal length from the
 * same numbers: fx = fy = 120 / (2 * 0.1042) = 575.8 px at 640x480, principal point at the image
 * centre. Published calibrations of individual Kinects give 575-595 px. */
#define REC_ZP_EMITTER_CM  7.5
#define REC_ZP_REF_DIST_MM 120.0
#define REC_ZP_PIXEL_MM    0.1042
#define REC_CONST_SHIFT    200.0
#define REC_FX             (REC_ZP_REF_DIST_MM / (2.0 * REC_ZP_PIXEL_MM))
#define REC_FY             REC_FX
#define REC_CX             320.0
#define REC_CY             240.0
#define REC_BASELINE_M     0.075 /* IR projector beside the IR camera, +x in camera coordinates */
#define REC_RANGE_MIN_M    0.5
#define REC_RANGE_MAX_M    4.5

/* libfreenect's raw 11-bit disparity to millimetres (registration.c, freenect_raw_to_mm), with
 * its table's rule that 2047 reads 0. Raw values whose formula leaves 0..10 m (libfreenect's
 * DEPTH_MAX_METRIC_VALUE) also read 0 here; libfreenect leaves those undefined. */
uint16_t rec_raw_to_mm(uint16_t raw);
/* Fills table[REC_RAW_LEVELS] with rec_raw_to_mm. */
void rec_raw_to_mm_table(uint16_t table[REC_RAW_LEVELS]);
/* The raw disparity whose rec_raw_to_mm is nearest to depth_m, or REC_RAW_NONE where depth_m is
 * outside [REC_RANGE_MIN_M, REC_RANGE_MAX_M] or not finite. */
uint16_t rec_mm_to_raw(double depth_m);

/* Errors of a recording. One list makes the enum and the words (STYLE.md 11). */
#define REC_ERROR_LIST(X)                                                                          \
    X(REC_OK, "ok")                                                                                \
    X(REC_ERR_NO_DIR, "recording directory cannot be opened")                                      \
    X(REC_ERR_NO_INDEX, "INDEX.txt is missing or unreadable")                                      \
    X(REC_ERR_EMPTY, "INDEX.txt lists no depth frame")                                             \
    X(REC_ERR_BAD_LINE, "INDEX.txt line is not <type>-<time>-<timestamp>... ")                     \
    X(REC_ERR_NO_FRAME, "frame file listed in INDEX.txt is missing")                               \
    X(REC_ERR_HEADER, "frame header is not 'P5 640 480 65535\\n'")                                 \
    X(REC_ERR_TRUNCATED, "frame file is shorter than header + 640x480x2 bytes")                    \
    X(REC_ERR_TOO_LONG, "frame file is longer than header + 640x480x2 bytes")                      \
    X(REC_ERR_VALUE, "frame holds a disparity above 2047")                                         \
    X(REC_ERR_TIME_ORDER, "record times do not increase")                                          \
    X(REC_ERR_TIMESTAMP_ORDER, "device timestamps go backwards")                                   \
    X(REC_ERR_IO, "file cannot be written")                                                        \
    X(REC_ERR_NO_MEMORY, "out of memory")                                                          \
    X(REC_ERR_ARG, "invalid argument")

#define REC_ERROR_ENUM(id, text) id,
typedef enum rec_error { REC_ERROR_LIST(REC_ERROR_ENUM) REC_ERROR_COUNT } rec_error;
#undef REC_ERROR_ENUM
/* Functions return 0 or -REC_ERR_x (docs/building.md, "Conventions: errors"). */
const char *rec_error_name(int e); /* "REC_ERR_TRUNCATED"; accepts e or -e */
const char *rec_error_text(int e);

/* Where a check failed: the file, the frame (index among depth frames, -1 = not a frame) and
 * the INDEX.txt line (1-based, 0 = none), and a sentence for the user. */
typedef struct rec_report {
    rec_error code;
    int frame;
    int line;
    char file[256];
    char message[1024];
} rec_report;

/* One depth frame listed in INDEX.txt. */
typedef struct rec_entry {
    double record_time_s;
    uint32_t device_timestamp;
    char name[96]; /* file name inside the directory */
} rec_entry;

/* The depth frames of a dump, in INDEX.txt order (other kinds of line are skipped). */
typedef struct rec_index {
    int count;
    rec_entry *frames;
} rec_index;

/* Reads INDEX.txt. Returns 0 or -REC_ERR_x with the report filled; free with
 * rec_index_free (also after a failure). */
int rec_index_read(const char *dir, rec_index *out, rec_report *why);
void rec_index_free(rec_index *idx);

/* Full check of a dump before anything replays it: INDEX.txt present and parsable, at least one
 * depth frame, every frame present with the exact header and size, values <= 2047, record times
 * increasing, device timestamps not going backwards (modulo 2^32 wrap). Stops at the first
 * problem. frames_out (may be NULL) gets the number of depth frames. */
int rec_validate(const char *dir, int *frames_out, rec_report *why);

/* Reads one frame file (header checked) into raw[640*480] (host order). */
int rec_frame_read(const char *dir, const rec_entry *e, int frame, uint16_t *raw, rec_report *why);

/* Writes a dump frame by frame. INDEX.txt is flushed after every frame, so a dump cut short by a
 * signal is still a valid dump of the frames written. */
typedef struct rec_writer rec_writer;
rec_writer *rec_writer_create(const char *dir, rec_report *why); /* makes dir if needed */
/* raw: 640*480 values, written little-endian. Returns 0 or -REC_ERR_IO. */
int rec_writer_frame(rec_writer *w, const uint16_t *raw, double record_time_s,
                     uint32_t device_timestamp, rec_report *why);
/* Adds a ground-truth line "frame time depth_file gt_file" to groundtruth.txt and returns the
 * path for the gt file of the last frame written in path (size path_size). */
int rec_writer_gt_path(rec_writer *w, char *path, size_t path_size, char *name, size_t name_size);
int rec_writer_frames(const rec_writer *w);
void rec_writer_destroy(rec_writer *w);

/* Deterministic random numbers (splitmix64 seeding a xoshiro128-style generator). */
typedef struct rec_rng {
    uint64_t s[2];
} rec_rng;
void rec_rng_seed(rec_rng *r, uint64_t seed, uint64_t stream);
uint64_t rec_rng_u64(rec_rng *r);
double rec_rng_uniform(rec_rng *r); /* [0, 1) */
double rec_rng_normal(rec_rng *r);  /* mean 0, sigma 1 */

/* The Kinect v1 noise model (docs/recordings.md). Axial sigma from Nguyen, Izadi & Lovell 2012
 * (Eq. for sigma_z), lateral sigma 0.8 px (same paper), quantisation through the 11-bit
 * disparity (Khoshelham & Elberink 2012), range 0.5-4.5 m, projector shadows and edge dropouts. */
typedef struct rec_noise_desc {
    int enabled;       /* 0: only quantisation and range */
    uint64_t seed;     /* with the frame number, picks the random stream */
    float lateral_px;  /* 0 = 0.8 */
    float edge_drop;   /* probability a silhouette-edge pixel is lost; 0 = 0.5 */
    float edge_jump_m; /* a depth step above this between neighbours is an edge; 0 = 0.05 */
    int shadows;       /* 1 = projector shadows (default when enabled) */
} rec_noise_desc;
rec_noise_desc rec_noise_default(int enabled, uint64_t seed);
/* Axial standard deviation (m) at depth z (m) for a surface facing the camera, Nguyen et al.
 * 2012; with the surface seen at angle theta (rad, normal to ray), their extra term; and their
 * lateral standard deviation (px). */
double rec_sigma_z(double z_m);
double rec_sigma_z_angle(double z_m, double theta);
double rec_sigma_lateral_px(double theta);
/* depth_m: 640*480 metres along the optical axis (0 or non-finite = nothing seen).
 * scratch: 640*480 floats. raw_out: 640*480 disparities. */
void rec_noise_apply(const rec_noise_desc *d, int frame, const float *depth_m, float *scratch,
                     uint16_t *raw_out);

/* The camera of tryon-synth: 2.5 m in front of the person (world z = +2.5), lens 1.0 m above
 * the floor, looking along world -z at the body. */
#define REC_CAMERA_HEIGHT_M   1.0
#define REC_CAMERA_DISTANCE_M 2.5
void rec_camera_to_world(float m[16]);

/* The static scene around the person: floor, back wall, optional box. */
typedef struct rec_scene {
    float wall_z;     /* world z of the back wall (camera at +2.5, so -1.5 is 4 m away) */
    int has_box;      /* occluding box between camera and person */
    float box_min[3]; /* world AABB */
    float box_max[3];
} rec_scene;
rec_scene rec_scene_default(int with_box);

/* Depth (m along the optical axis) of the scene without the person, for every pixel. */
void rec_render_background(const rec_scene *s, const float cam_to_world[16], float *depth_m);
/* Z-buffers world-space triangles into depth_m (keeps the nearer). vertices: [n][3] world. */
void rec_render_triangles(const float cam_to_world[16], const float *vertices,
                          const int32_t *triangles, int triangle_count, float *depth_m);

/* Ground truth beside each synthetic frame (gt-<frame>.txt, listed in groundtruth.txt): enough
 * to rebuild the true mesh with bodyfit (fit_model_create with the shape and target_vertices,
 * then fit_model_pose with the pose). Arrays use bodyfit's layouts: shape as
 * fit_shape_to_array, pose as root translation (3) then axis-angle per joint (3 each). */
#define REC_GT_MAX_SHAPE  16
#define REC_GT_MAX_POSE   128
#define REC_GT_MAX_JOINTS 40
typedef struct rec_gt {
    int frame;
    double time_s; /* motion time, seconds since the first frame */
    char depth_file[96];
    char motion[32];
    int shape_preset;
    int target_vertices;
    int num_shape;
    float shape[REC_GT_MAX_SHAPE];
    int num_pose;
    float pose[REC_GT_MAX_POSE];
    int num_joints;
    char joint_name[REC_GT_MAX_JOINTS][24];
    float joints[REC_GT_MAX_JOINTS][3]; /* world, metres */
    int width, height;
    float fx, fy, cx, cy;
    float camera_to_world[16];
    int noise;
    uint64_t seed;
    rec_scene scene;
} rec_gt;
int rec_gt_write(const char *path, const rec_gt *g, rec_report *why);
int rec_gt_read(const char *path, rec_gt *g, rec_report *why);

/* tryon-synth. Motions: bodyfit's (still, arm_raise, turn, walk, fast_swing, enter_leave, ...),
 * "occlusion" (arm_raise behind a box), or a motion-capture file FILE.bvh retargeted onto the
 * body (0 frames: the whole clip). */
typedef struct rec_synth_desc {
    const char *out_dir;
    const char *motion;
    int shape;  /* bodyfit preset 0..2 */
    int frames; /* 0 = one motion period */
    int noise;  /* 0 = exact depth, only quantised */
    uint64_t seed;
    int target_vertices; /* 0 = bodyfit's default */
    int occluder;        /* 1 = add the box for any motion */
    int keep_heading;    /* a FILE.bvh clip: 0 = turned to face the camera at its start (a
                            person in front of a mirror: fit_clip_face_camera); 1 = as captured */
} rec_synth_desc;
/* Names tryon-synth accepts, NULL past the end. */
const char *rec_synth_motion_name(int i);
int rec_synth(const rec_synth_desc *d, rec_report *why);

#endif
