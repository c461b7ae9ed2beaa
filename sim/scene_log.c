/* A recorded session's bodies as a scene (scene.h, sim_scene_log): what tryon-bench-sim and
 * tryon-probe-motion run the garment on when --motion names an lcm-logger log, so that the sim
 * is measured on the bodies a pipeline really published (the fitter's, with its jitter), not only
 * on the body model's own motions. */
#include <lcm/eventlog.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bus.h"
#include "scene.h"
#ifdef SIM_HAVE_BODYFIT
#include "bodyfit.h"
#define SCENE_LOG_JOINT_FLOATS (FIT_JOINT_COUNT * 3) /* the skeleton the shirt is made on */
#else
#define SCENE_LOG_JOINT_FLOATS 0
#endif

/* A log's bodies held at once: a 15-minute session of 6,000-vertex bodies (1.9 GB) is refused
 * rather than taken into memory; a bench run wants seconds of it. */
#define SCENE_LOG_MAX_FLOATS (256u << 20) /* 1 GiB of vertices and joints */
#define SCENE_LOG_DT_S       (1.0 / 30.0)

typedef struct log_bodies {
    int nv, nt, joint_floats, frames, cap;
    int32_t topology, *tris;
    float *xyz, *joints;
    long skipped_lost, skipped_init, skipped_other, rejected;
    bus_reject first_reject;
} log_bodies;

static int ends_with(const char *s, const char *tail)
{
    size_t n = strlen(s), m = strlen(tail);
    return n >= m && strcmp(s + n - m, tail) == 0;
}

/* Room for one more body. Returns 0, or -1 (too many, or no memory). */
static int grow(log_bodies *b)
{
    if (b->frames < b->cap)
        return 0;
    size_t per = (size_t)b->nv * 3 + (size_t)b->joint_floats;
    int cap = b->cap ? 2 * b->cap : 64;
    if ((size_t)cap * per > SCENE_LOG_MAX_FLOATS)
        cap = (int)(SCENE_LOG_MAX_FLOATS / per);
    if (cap <= b->frames)
        return -1;
    float *x = realloc(b->xyz, (size_t)cap * b->nv * 3 * sizeof *x);
    if (!x)
        return -1;
    b->xyz = x;
    if (b->joint_floats > 0) {
        float *j = realloc(b->joints, (size_t)cap * b->joint_floats * sizeof *j);
        if (!j)
            return -1;
        b->joints = j;
    }
    b->cap = cap;
    return 0;
}

/* One decoded body. Returns 0 (kept or skipped, counted), or -1 with err filled. */
static int take(log_bodies *b, const tryon_body_t *m, const char *path, char *err, size_t err_size)
{
    int nv = m->num_vertex_coords / 3, nt = m->num_triangle_indices / 3;
    if (m->state == TRYON_BODY_T_STATE_LOST || nv == 0) {
        b->skipped_lost++;
        return 0;
    }
    if (!b->frames && nt > 0) { /* until the first body tracked: the newest triangle list */
        int32_t *t = realloc(b->tris, (size_t)nt * 3 * sizeof *t);
        if (!t) {
            snprintf(err, err_size, "%s: out of memory", path);
            return -1;
        }
        b->tris = t;
        memcpy(b->tris, m->triangles, (size_t)nt * 3 * sizeof *b->tris);
        b->nt = nt;
        b->topology = m->topology_id;
    }
    if (!b->frames && m->state != TRYON_BODY_T_STATE_TRACKING) {
        b->skipped_init++; /* a person's first frames: tryon-sim dresses the settled shape */
        return 0;
    }
    if (!b->frames) { /* the first body tracked: its mesh is the scene's */
        if (!b->tris || b->topology != m->topology_id) {
            snprintf(err, err_size,
                     "%s: the first body tracked (seq %d) names topology %d without its "
                     "triangles (the log starts after its sender did)",
                     path, (int)m->seq, (int)m->topology_id);
            return -1;
        }
        for (int i = 0; i < b->nt * 3; i++)
            if (b->tris[i] < 0 || b->tris[i] >= nv) {
                snprintf(err, err_size,
                         "%s: body seq %d: topology %d's triangles[%d][%d] = %d, past its %d "
                         "vertices",
                         path, (int)m->seq, (int)m->topology_id, i / 3, i % 3, (int)b->tris[i], nv);
                return -1;
            }
        b->nv = nv;
        /* joints only of the body model's skeleton (as tryon-sim takes them) */
        b->joint_floats =
            m->num_joint_coords == SCENE_LOG_JOINT_FLOATS ? SCENE_LOG_JOINT_FLOATS : 0;
    }
    if (m->topology_id != b->topology || nv != b->nv ||
        (nt > 0 &&
         (nt != b->nt || memcmp(m->triangles, b->tris, (size_t)nt * 3 * sizeof *b->tris) != 0)) ||
        (b->joint_floats > 0 && m->num_joint_coords != b->joint_floats)) {
        b->skipped_other++; /* another sender's, or a remeshed body: not this scene's */
        return 0;
    }
    if (grow(b) != 0) {
        snprintf(err, err_size, "%s: more bodies than a scene holds (%d kept; %u floats at most)",
                 path, b->frames, SCENE_LOG_MAX_FLOATS);
        return -1;
    }
    memcpy(b->xyz + (size_t)b->frames * nv * 3, m->vertices, (size_t)nv * 3 * sizeof *b->xyz);
    if (b->joint_floats > 0)
        memcpy(b->joints + (size_t)b->frames * b->joint_floats, m->joints,
               (size_t)b->joint_floats * sizeof *b->joints);
    b->frames++;
    return 0;
}

sim_scene *sim_scene_log(const char *path, char *err, size_t err_size)
{
    lcm_eventlog_t *log = lcm_eventlog_create(path, "r");
    if (!log) {
        snprintf(err, err_size, "%s: cannot open it as an LCM log", path);
        return NULL;
    }
    log_bodies b = {0};
    int bad = 0;
    lcm_eventlog_event_t *ev;
    while (!bad && (ev = lcm_eventlog_read_next_event(log)) != NULL) {
        if (ev->channel && ends_with(ev->channel, BUS_CHANNEL_BODY)) {
            tryon_body_t m;
            bus_reject why;
            if (bus_decode_sealed(BUS_BODY, ev->channel, ev->data, (size_t)ev->datalen, &m, &why) ==
                BUS_OK) {
                bad = take(&b, &m, path, err, err_size) != 0;
                bus_msg_free(BUS_BODY, &m);
            } else if (b.rejected++ == 0) {
                b.first_reject = why;
            }
        }
        lcm_eventlog_free_event(ev);
    }
    lcm_eventlog_destroy(log);
    sim_scene *sc = NULL;
    if (!bad && b.frames == 0)
        snprintf(err, err_size, "%s: no body tracked (%ld lost, %ld before, %ld refused%s%s)", path,
                 b.skipped_lost, b.skipped_init, b.rejected, b.rejected ? ": " : "",
                 b.rejected ? b.first_reject.detail : "");
    else if (!bad && !(sc = sim_scene_recorded(b.nv, b.tris, b.nt, b.frames, b.xyz, b.joints,
                                               b.joint_floats, SCENE_LOG_DT_S)))
        snprintf(err, err_size, "%s: out of memory, or a body too small to dress (%d vertices)",
                 path, b.nv);
    if (sc)
        fprintf(stderr,
                "%s: %d bodies from the first tracked; skipped %ld before it, %ld lost, %ld of "
                "another mesh or sender; %ld refused%s%s%s\n",
                path, b.frames, b.skipped_init, b.skipped_lost, b.skipped_other, b.rejected,
                b.rejected ? " (the first: " : "", b.rejected ? b.first_reject.detail : "",
                b.rejected ? ")" : "");
    if (!sc) {
        free(b.xyz);
        free(b.joints);
    }
    free(b.tris);
    return sc;
}
