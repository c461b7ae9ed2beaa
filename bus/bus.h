/* bus: the LCM messages every tryon stage exchanges, the one way to open LCM, channel names,
 * clocks, timing reports, and validation of everything that arrives. */
#ifndef TRYON_BUS_H
#define TRYON_BUS_H

#include <stddef.h>
#include <stdint.h>

#include <lcm/lcm.h>

#include "tryon_body_t.h"
#include "tryon_cloth_t.h"
#include "tryon_control_t.h"
#include "tryon_depth_frame_t.h"
#include "tryon_timing_t.h"

/* Channel names. TRYON_CHANNEL_PREFIX, when set, is put in front of every one so that several
 * pipelines (or tests run with ctest -j) can share one LCM network without cross-talk. */
#define BUS_CHANNEL_DEPTH   "DEPTH"
#define BUS_CHANNEL_BODY    "BODY"
#define BUS_CHANNEL_CLOTH   "CLOTH"
#define BUS_CHANNEL_TIMING  "TIMING"
#define BUS_CHANNEL_CONTROL "CONTROL"
#define BUS_CHANNEL_MAX     96
/* Writes prefix + base into out. Returns 0, or -BUS_ERR_STRING if it does not fit. */
int bus_channel(const char *base, char *out, size_t out_size);

/* The default URL: multicast that never leaves the host (ttl=0), with a kernel receive buffer
 * that holds several 640x480 16-bit frames (600 KiB each); with the kernel's default buffer LCM
 * silently drops such large messages when the reader falls behind. */
#define BUS_DEFAULT_URL "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608"
/* url: NULL = $TRYON_LCM_URL, else BUS_DEFAULT_URL. On failure returns NULL and writes a reason
 * (with the fix, for multicast routing) into err. */
lcm_t *bus_open(const char *url, char *err, size_t err_size);
const char *bus_default_url(void); /* $TRYON_LCM_URL or BUS_DEFAULT_URL */

/* Clocks in microseconds. Monotonic for durations, wall (CLOCK_REALTIME) for stamps that cross
 * processes. */
int64_t bus_now_mono_us(void);
int64_t bus_now_wall_us(void);
/* CPU time of the whole process, every thread: what a stage's frame costs whatever the load. */
int64_t bus_now_cpu_us(void);

/* Why a message was refused. One list makes the enum and the words, so a test can name which
 * rejection happened. */
#define BUS_ERROR_LIST(X)                                                                          \
    X(BUS_OK, "ok")                                                                                \
    X(BUS_ERR_TRUNCATED, "buffer ends inside the message")                                         \
    X(BUS_ERR_TRAILING, "bytes left over after the message")                                       \
    X(BUS_ERR_FINGERPRINT, "not this message type (fingerprint differs)")                          \
    X(BUS_ERR_COUNT, "negative or absurd element count")                                           \
    X(BUS_ERR_STRING, "string too long or not terminated")                                         \
    X(BUS_ERR_DIMENSIONS, "image dimensions out of range")                                         \
    X(BUS_ERR_DATA_SIZE, "data size does not match the dimensions")                                \
    X(BUS_ERR_ENCODING, "unknown encoding")                                                        \
    X(BUS_ERR_NOT_FINITE, "number is NaN or infinite")                                             \
    X(BUS_ERR_RANGE, "value out of its range")                                                     \
    X(BUS_ERR_INDEX, "triangle index out of range")                                                \
    X(BUS_ERR_NO_MEMORY, "out of memory")                                                          \
    X(BUS_ERR_PUBLISH, "LCM could not send the message")                                           \
    X(BUS_ERR_TYPE, "unknown message type")                                                        \
    X(BUS_ERR_AUTH, "not signed with this host's bus key")

#define BUS_ERROR_ENUM(id, text) id,
typedef enum bus_error { BUS_ERROR_LIST(BUS_ERROR_ENUM) BUS_ERROR_COUNT } bus_error;
#undef BUS_ERROR_ENUM
/* Functions return 0 (BUS_OK) or -BUS_ERR_x (docs/building.md, "Conventions: errors"). */
const char *bus_error_name(int e); /* "BUS_ERR_INDEX"; accepts e or -e */
const char *bus_error_text(int e); /* "triangle index out of range" */

typedef struct bus_reject {
    bus_error code;
    char detail[160]; /* where: "vertices[12][1] = nan", "triangles[5][2] = 99 >= 42 vertices" */
} bus_reject;

/* Limits a sane message stays inside. */
#define BUS_MAX_IMAGE_SIDE 4096
#define BUS_MAX_VERTICES   1000000
#define BUS_MAX_TRIANGLES  2000000
#define BUS_MAX_PARAMS     1024
#define BUS_MAX_SUBSTAGES  64
#define BUS_MAX_STRING     256
#define BUS_MAX_COORD_M    1000.0f /* no tryon geometry is a kilometre from the origin */
/* Timestamps (us since the epoch or since boot) stay below 2^52 us (year 2112), so any
 * difference of two of them is far from overflowing int64 and exact as a double. */
#define BUS_MAX_UTIME_US (INT64_C(1) << 52)

typedef enum bus_type {
    BUS_DEPTH_FRAME,
    BUS_BODY,
    BUS_CLOTH,
    BUS_TIMING,
    BUS_CONTROL,
    BUS_TYPE_COUNT
} bus_type;
const char *bus_type_name(bus_type t);
size_t bus_type_size(bus_type t); /* sizeof the decoded struct */

/* Check a decoded message's contents. Returns BUS_OK or minus the first error found. */
int bus_validate(bus_type t, const void *msg, bus_reject *why);
/* Check the wire layout, then decode, then validate. msg must point at a struct of type t; on
 * success it owns memory to be released with bus_msg_free. On failure nothing needs freeing. */
int bus_decode(bus_type t, const void *buf, size_t len, void *msg, bus_reject *why);
void bus_msg_free(bus_type t, void *msg);
/* Every message on the bus ends with a BUS_TAG_BYTES tag: keyed BLAKE2b of the channel name and
 * the payload, with the key in $TRYON_BUS_KEY_FILE, else $XDG_RUNTIME_DIR/tryon-bus.key, else
 * ~/.cache/tryon/bus.key (made 0600 on first use; refused if others can read it). Messages
 * without a valid tag (another machine's, or anyone's without the key) are refused as
 * BUS_ERR_AUTH. bus_open loads the key; lcm-logger logs keep the tags, replays verify them. */
#define BUS_TAG_BYTES 32
int bus_key_load(char *err, size_t err_size); /* 0, or -BUS_ERR_AUTH with the reason in err */
const char *bus_key_path(void);
/* Writes the tag of buf[0..len) on channel at buf[len] (room for BUS_TAG_BYTES needed). */
int bus_seal(const char *channel, uint8_t *buf, size_t len, bus_reject *why);
/* Checks the tag at the end of buf; *payload_len = len - BUS_TAG_BYTES on success. */
int bus_unseal(const char *channel, const uint8_t *buf, size_t len, size_t *payload_len,
               bus_reject *why);
/* Unseal, then bus_decode: what a subscriber or a log reader does with one event. */
int bus_decode_sealed(bus_type t, const char *channel, const void *buf, size_t len, void *msg,
                      bus_reject *why);
/* Seals and sends payload bytes as they are (tests, tools that forward encoded messages). */
int bus_publish_raw(lcm_t *lcm, const char *channel, const void *payload, size_t len,
                    bus_reject *why);
/* Validate, then publish. A message that fails validation is not sent. */
int bus_publish(lcm_t *lcm, const char *channel, bus_type t, const void *msg, bus_reject *why);

/* Subscriptions that decode and validate before the handler sees anything. Rejected messages are
 * counted, reported on stderr (the first few, then every hundredth) and dropped. */
typedef void (*bus_handler)(const char *channel, const void *msg, void *user);
typedef struct bus_stats {
    uint64_t accepted;
    uint64_t rejected;
    uint64_t rejected_by[BUS_ERROR_COUNT];
    bus_reject last; /* the most recent rejection */
} bus_stats;
typedef struct bus_sub bus_sub;
bus_sub *bus_subscribe(lcm_t *lcm, const char *channel, bus_type t, bus_handler fn, void *user);
const bus_stats *bus_sub_stats(const bus_sub *s);
void bus_sub_quiet(bus_sub *s, int quiet); /* 1 = count rejections without printing them */
void bus_unsubscribe(lcm_t *lcm, bus_sub *s);

/* Timing reports: fill as the work goes, publish when it is done. */
typedef struct bus_timing {
    char stage[32];
    int32_t seq;
    int64_t utime_capture;
    int64_t utime_received;
    int64_t utime_started;
    int num_substages;
    char substage[BUS_MAX_SUBSTAGES][32];
    float substage_ms[BUS_MAX_SUBSTAGES];
} bus_timing;
void bus_timing_begin(bus_timing *t, const char *stage, int32_t seq, int64_t utime_capture,
                      int64_t utime_received);
void bus_timing_add(bus_timing *t, const char *substage, float ms); /* ignored past the max */
/* Stamps utime_finished now and publishes on the TIMING channel (prefixed). */
int bus_timing_publish(lcm_t *lcm, const bus_timing *t);

#endif
