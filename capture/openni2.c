/* The OpenNI2 source, through OpenNI2's C API (OniCAPI.h): a live device (URI, or empty for any
 * device) or an .oni recording opened as a device URI by OpenNI2's file driver. Recordings are
 * read in OpenNI's "manual" playback speed (-1: a frame only when asked), so that cap_pacer paces
 * them from their own timestamps exactly as it paces fakenect dumps. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* OniCTypes.h does not compile as C as shipped: it uses the struct tags below as type names.
 * These are OpenNI's names, declared the way its C++ users get them implicitly. */
typedef struct _OniDevice _OniDevice;
typedef struct _OniStream _OniStream;
typedef struct _OniRecorder _OniRecorder;
#include <OniCAPI.h>

#include "bus.h"
#include "cap_private.h"

typedef struct oni_state {
    OniDeviceHandle dev;
    OniStreamHandle stream;
    int started;
    int file;
    int timeout_ms;
    int32_t seq;
    uint64_t first_ts;
    float hfov, vfov;
    int width, height;
    uint16_t *mm;
} oni_state;

static int is_oni_file(const char *uri)
{
    struct stat st;
    size_t n = uri ? strlen(uri) : 0;
    return n > 4 && !strcmp(uri + n - 4, ".oni") && stat(uri, &st) == 0 && S_ISREG(st.st_mode);
}

static int oni_fail(char *err, size_t errlen, cap_error code, const char *what, const char *uri)
{
    /* OpenNI's extended error comes with tabs and newlines: keep it on one line. */
    char detail[256];
    snprintf(detail, sizeof detail, "%s", oniGetExtendedError());
    for (char *c = detail; *c; c++)
        if (*c == '\t' || *c == '\n' || *c == '\r')
            *c = ' ';
    const char *d = detail;
    while (*d == ' ')
        d++;
    size_t n = strlen(d);
    while (n > 0 && d[n - 1] == ' ')
        n--;
    snprintf(err, errlen, "%s%s%s: %.*s", what, uri ? " " : "", uri ? uri : "", (int)n, d);
    return -(int)code;
}

static int oni_open(cap_source *src, const cap_source_desc *d, char *err, size_t errlen)
{
    oni_state *s = calloc(1, sizeof *s);
    if (!s)
        return -CAP_ERR_NO_MEMORY;
    src->impl = s;
    s->timeout_ms = d->timeout_ms > 0 ? d->timeout_ms : 2000;
    const char *uri = d->uri && *d->uri ? d->uri : NULL;
    size_t n = uri ? strlen(uri) : 0;
    if (n > 4 && !strcmp(uri + n - 4, ".oni") && !is_oni_file(uri)) {
        snprintf(err, errlen, "%s: no such recording (not a readable .oni file)", uri);
        return -CAP_ERR_RECORDING;
    }
    s->file = is_oni_file(uri);
    if (oniInitialize(ONI_API_VERSION) != ONI_STATUS_OK)
        return oni_fail(err, errlen, CAP_ERR_DEVICE, "oniInitialize failed", NULL);
    if (oniDeviceOpen(uri ? uri : "", &s->dev) != ONI_STATUS_OK) {
        s->dev = NULL;
        return oni_fail(err, errlen, s->file ? CAP_ERR_RECORDING : CAP_ERR_NO_DEVICE, "cannot open",
                        uri ? uri : "any OpenNI2 device");
    }
    if (s->file) {
        OniBool no = 0;
        float manual = -1.0f;
        oniDeviceSetProperty(s->dev, ONI_DEVICE_PROPERTY_PLAYBACK_REPEAT_ENABLED, &no, sizeof no);
        oniDeviceSetProperty(s->dev, ONI_DEVICE_PROPERTY_PLAYBACK_SPEED, &manual, sizeof manual);
    }
    if (oniDeviceCreateStream(s->dev, ONI_SENSOR_DEPTH, &s->stream) != ONI_STATUS_OK) {
        s->stream = NULL;
        return oni_fail(err, errlen, CAP_ERR_DEVICE, "no depth stream on", uri);
    }
    if (!s->file) {
        /* Ask for the Kinect-like mode; devices that refuse keep their own, read back below. */
        OniVideoMode want = {ONI_PIXEL_FORMAT_DEPTH_1_MM, 640, 480, 30};
        oniStreamSetProperty(s->stream, ONI_STREAM_PROPERTY_VIDEO_MODE, &want, sizeof want);
    }
    int size = sizeof s->hfov;
    if (oniStreamGetProperty(s->stream, ONI_STREAM_PROPERTY_HORIZONTAL_FOV, &s->hfov, &size) !=
        ONI_STATUS_OK)
        s->hfov = 0.0f;
    size = sizeof s->vfov;
    if (oniStreamGetProperty(s->stream, ONI_STREAM_PROPERTY_VERTICAL_FOV, &s->vfov, &size) !=
        ONI_STATUS_OK)
        s->vfov = 0.0f;
    if (oniStreamStart(s->stream) != ONI_STATUS_OK)
        return oni_fail(err, errlen, CAP_ERR_DEVICE, "cannot start the depth stream of", uri);
    s->started = 1;
    return CAP_OK;
}

/* The frame buffer follows the stream's resolution; it changes only when the mode does. */
static int oni_buffer(oni_state *s, int w, int h, char *err, size_t errlen)
{
    if (w == s->width && h == s->height && s->mm)
        return CAP_OK;
    if (w <= 0 || h <= 0 || w > 4096 || h > 4096) {
        snprintf(err, errlen, "OpenNI2 frame of %dx%d pixels", w, h);
        return -CAP_ERR_DEVICE;
    }
    free(s->mm);
    s->mm = malloc(sizeof(uint16_t) * (size_t)w * (size_t)h);
    s->width = w;
    s->height = h;
    return s->mm ? CAP_OK : -CAP_ERR_NO_MEMORY;
}

static void oni_convert(oni_state *s, const OniFrame *f)
{
    int scale_down = f->videoMode.pixelFormat == ONI_PIXEL_FORMAT_DEPTH_100_UM;
    for (int y = 0; y < f->height; y++) {
        const uint16_t *row = (const uint16_t *)((const uint8_t *)f->data + (size_t)y * f->stride);
        for (int x = 0; x < f->width; x++)
            s->mm[y * f->width + x] = scale_down ? (uint16_t)(row[x] / 10) : row[x];
    }
}

static int oni_next(cap_source *src, cap_frame *out, char *err, size_t errlen)
{
    oni_state *s = src->impl;
    int which = 0;
    /* A recording that stays silent has ended (repeat is off); a live camera that does is lost. */
    OniStatus st = oniWaitForAnyStream(&s->stream, 1, &which, s->file ? 1000 : s->timeout_ms);
    if (st == ONI_STATUS_TIME_OUT) {
        if (s->file)
            return CAP_END;
        snprintf(err, errlen, "no depth frame from the OpenNI2 device in %d ms", s->timeout_ms);
        return -CAP_ERR_TIMEOUT;
    }
    OniFrame *f = NULL;
    if (st != ONI_STATUS_OK || oniStreamReadFrame(s->stream, &f) != ONI_STATUS_OK || !f)
        return oni_fail(err, errlen, CAP_ERR_DEVICE, "reading a depth frame failed", NULL);
    int64_t utime = bus_now_wall_us();
    int e = CAP_OK;
    if (f->videoMode.pixelFormat != ONI_PIXEL_FORMAT_DEPTH_1_MM &&
        f->videoMode.pixelFormat != ONI_PIXEL_FORMAT_DEPTH_100_UM) {
        snprintf(err, errlen, "OpenNI2 depth pixel format %d is not millimetres",
                 (int)f->videoMode.pixelFormat);
        e = -CAP_ERR_DEVICE;
    } else if (f->stride < f->width * 2) {
        snprintf(err, errlen, "OpenNI2 frame stride %d < width %d x 2", f->stride, f->width);
        e = -CAP_ERR_DEVICE;
    } else {
        e = oni_buffer(s, f->width, f->height, err, errlen);
    }
    if (e == CAP_OK) {
        oni_convert(s, f);
        if (s->seq == 0)
            s->first_ts = f->timestamp;
        /* Pinhole focal length from the field of view the device reports. */
        float fx = s->hfov > 0.0f ? (float)(f->width / (2.0 * tan(s->hfov / 2.0))) : 575.8f;
        float fy = s->vfov > 0.0f ? (float)(f->height / (2.0 * tan(s->vfov / 2.0))) : fx;
        *out = (cap_frame){.width = f->width,
                           .height = f->height,
                           .depth_mm = s->mm,
                           .raw = NULL,
                           .fx = fx,
                           .fy = fy,
                           .cx = f->width / 2.0f,
                           .cy = f->height / 2.0f,
                           .device_timestamp = (int64_t)f->timestamp,
                           .seq = s->seq++,
                           .utime_capture = utime,
                           .replay_time_s =
                               s->file ? (double)(f->timestamp - s->first_ts) * 1e-6 : -1.0};
    }
    oniFrameRelease(f);
    return e;
}

static void oni_close(cap_source *src)
{
    oni_state *s = src->impl;
    if (!s)
        return;
    if (s->stream) {
        if (s->started)
            oniStreamStop(s->stream);
        oniStreamDestroy(s->stream);
    }
    if (s->dev)
        oniDeviceClose(s->dev);
    /* No oniShutdown: in Debian's OpenNI2 2.2.0.33 it segfaults (in the driver unload) once a
     * stream has existed, with the Dummy and the File driver alike. Capture closes a source only
     * on its way out, so the process exit releases what OpenNI2 holds. */
    free(s->mm);
    free(s);
    src->impl = NULL;
}

const cap_source_api cap_openni2_api = {"openni2", oni_open, oni_next, oni_close};
