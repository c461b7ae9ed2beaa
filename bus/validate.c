/* Checking the contents of decoded messages: dimensions, counts, index ranges, finite floats. */
#include "bus_private.h"

#include <math.h>
#include <string.h>

/* Every float must be finite; coordinates also within BUS_MAX_COORD_M of the origin. */
static int check_floats(const float *v, int64_t n, float limit, const char *name, int stride,
                        bus_reject *why)
{
    for (int64_t i = 0; i < n; i++) {
        if (!isfinite(v[i]))
            return bus_reject_set(why, BUS_ERR_NOT_FINITE, "%s[%lld][%d] = %g", name,
                                  (long long)(i / stride), (int)(i % stride), (double)v[i]);
        if (limit > 0 && fabsf(v[i]) > limit)
            return bus_reject_set(why, BUS_ERR_RANGE, "%s[%lld][%d] = %g m (|x| <= %g)", name,
                                  (long long)(i / stride), (int)(i % stride), (double)v[i],
                                  (double)limit);
    }
    return BUS_OK;
}

static int check_count(int32_t n, int64_t max, const char *name, bus_reject *why)
{
    if (n < 0 || n > max)
        return bus_reject_set(why, BUS_ERR_COUNT, "%s = %d (0..%lld)", name, (int)n,
                              (long long)max);
    return BUS_OK;
}

/* A count of flat xyz coordinates or triangle corners: a multiple of 3 within its limit. */
static int check_triples(int32_t n, int64_t max_triples, const char *name, bus_reject *why)
{
    if (n < 0 || n > 3 * max_triples || n % 3 != 0)
        return bus_reject_set(why, BUS_ERR_COUNT, "%s = %d (a multiple of 3, 0..%lld)", name,
                              (int)n, (long long)(3 * max_triples));
    return BUS_OK;
}

static int check_mesh(int32_t ncoords, const float *v, int32_t nindices, const int32_t *t,
                      bus_reject *why)
{
    int e = check_triples(ncoords, BUS_MAX_VERTICES, "num_vertex_coords", why);
    if (e == BUS_OK)
        e = check_triples(nindices, BUS_MAX_TRIANGLES, "num_triangle_indices", why);
    if (e == BUS_OK)
        e = check_floats(v, ncoords, BUS_MAX_COORD_M, "vertices", 3, why);
    if (e != BUS_OK)
        return e;
    int32_t nv = ncoords / 3;
    for (int32_t i = 0; i < nindices; i++)
        if (t[i] < 0 || t[i] >= nv)
            return bus_reject_set(why, BUS_ERR_INDEX, "triangles[%d][%d] = %d, %d vertices",
                                  (int)(i / 3), (int)(i % 3), (int)t[i], (int)nv);
    return BUS_OK;
}

static int check_string(const char *s, const char *name, bus_reject *why)
{
    if (!s || strnlen(s, BUS_MAX_STRING) >= BUS_MAX_STRING)
        return bus_reject_set(why, BUS_ERR_STRING, "%s missing or longer than %d", name,
                              BUS_MAX_STRING - 1);
    return BUS_OK;
}

static int validate_depth_frame(const tryon_depth_frame_t *m, bus_reject *why)
{
    int se = check_string(m->source, "source", why);
    if (se != BUS_OK)
        return se;
    if (m->width < 1 || m->width > BUS_MAX_IMAGE_SIDE || m->height < 1 ||
        m->height > BUS_MAX_IMAGE_SIDE)
        return bus_reject_set(why, BUS_ERR_DIMENSIONS, "%d x %d (1..%d each)", (int)m->width,
                              (int)m->height, BUS_MAX_IMAGE_SIDE);
    if (m->encoding != TRYON_DEPTH_FRAME_T_ENCODING_U16)
        return bus_reject_set(why, BUS_ERR_ENCODING, "encoding %d", (int)m->encoding);
    int64_t expect = (int64_t)m->width * m->height * 2;
    if (m->num_bytes != expect || (expect > 0 && !m->data))
        return bus_reject_set(why, BUS_ERR_DATA_SIZE, "num_bytes %d, %d x %d x 2 = %lld",
                              (int)m->num_bytes, (int)m->width, (int)m->height, (long long)expect);
    const float intr[5] = {m->fx, m->fy, m->cx, m->cy, m->metres_per_unit};
    int e = check_floats(intr, 5, 0, "fx,fy,cx,cy,metres_per_unit", 5, why);
    if (e == BUS_OK)
        e = check_floats(m->camera_to_world, 16, BUS_MAX_COORD_M, "camera_to_world", 16, why);
    if (e != BUS_OK)
        return e;
    if (!(m->fx > 0 && m->fy > 0 && m->metres_per_unit > 0))
        return bus_reject_set(why, BUS_ERR_RANGE, "fx %g, fy %g, metres_per_unit %g must be > 0",
                              (double)m->fx, (double)m->fy, (double)m->metres_per_unit);
    return BUS_OK;
}

static int validate_body(const tryon_body_t *m, bus_reject *why)
{
    if (m->state < TRYON_BODY_T_STATE_INIT || m->state > TRYON_BODY_T_STATE_LOST)
        return bus_reject_set(why, BUS_ERR_RANGE, "state %d", (int)m->state);
    int e = check_count(m->num_shape, BUS_MAX_PARAMS, "num_shape", why);
    if (e == BUS_OK)
        e = check_count(m->num_pose, BUS_MAX_PARAMS, "num_pose", why);
    if (e == BUS_OK)
        e = check_triples(m->num_joint_coords, BUS_MAX_PARAMS, "num_joint_coords", why);
    if (e == BUS_OK)
        e = check_floats(&m->fit_residual_mm, 1, 0, "fit_residual_mm", 1, why);
    if (e == BUS_OK)
        e = check_floats(m->shape, m->num_shape, BUS_MAX_COORD_M, "shape", 1, why);
    if (e == BUS_OK)
        e = check_floats(m->pose, m->num_pose, BUS_MAX_COORD_M, "pose", 1, why);
    if (e == BUS_OK)
        e = check_floats(m->joints, m->num_joint_coords, BUS_MAX_COORD_M, "joints", 3, why);
    if (e != BUS_OK)
        return e;
    return check_mesh(m->num_vertex_coords, m->vertices, m->num_triangle_indices, m->triangles,
                      why);
}

static int validate_cloth(const tryon_cloth_t *m, bus_reject *why)
{
    int se = check_string(m->garment_id, "garment_id", why);
    if (se != BUS_OK)
        return se;
    /* every state cloth_t.lcm names, CARRIED the last (the sim's sim_state values) */
    if (m->state < TRYON_CLOTH_T_STATE_OK || m->state > TRYON_CLOTH_T_STATE_CARRIED)
        return bus_reject_set(why, BUS_ERR_RANGE, "state %d", (int)m->state);
    const float f[3] = {m->max_strain, m->p99_strain, m->max_pen_mm};
    int e = check_floats(f, 3, 0, "max_strain,p99_strain,max_pen_mm", 3, why);
    if (e != BUS_OK)
        return e;
    if (m->penetrating < 0 || m->penetrating > m->num_vertex_coords / 3)
        return bus_reject_set(why, BUS_ERR_RANGE, "penetrating %d of %d vertices",
                              (int)m->penetrating, (int)(m->num_vertex_coords / 3));
    return check_mesh(m->num_vertex_coords, m->vertices, m->num_triangle_indices, m->triangles,
                      why);
}

static int validate_timing(const tryon_timing_t *m, bus_reject *why)
{
    int se = check_string(m->stage, "stage", why);
    if (se != BUS_OK)
        return se;
    if (m->stage[0] == 0)
        return bus_reject_set(why, BUS_ERR_STRING, "stage is empty");
    int e = check_count(m->num_substages, BUS_MAX_SUBSTAGES, "num_substages", why);
    if (e != BUS_OK)
        return e;
    for (int i = 0; i < m->num_substages; i++) {
        se = check_string(m->substage[i], "substage", why);
        if (se != BUS_OK)
            return se;
    }
    e = check_floats(m->substage_ms, m->num_substages, 0, "substage_ms", 1, why);
    if (e != BUS_OK)
        return e;
    const int64_t stamps[4] = {m->utime_capture, m->utime_received, m->utime_started,
                               m->utime_finished};
    for (int i = 0; i < 4; i++)
        if (stamps[i] < 0 || stamps[i] > BUS_MAX_UTIME_US)
            return bus_reject_set(why, BUS_ERR_RANGE, "timestamp %d = %lld us (0..%lld)", i,
                                  (long long)stamps[i], (long long)BUS_MAX_UTIME_US);
    if (m->utime_finished < m->utime_started)
        return bus_reject_set(why, BUS_ERR_RANGE, "finished %lld before started %lld",
                              (long long)m->utime_finished, (long long)m->utime_started);
    return BUS_OK;
}

static int validate_control(const tryon_control_t *m, bus_reject *why)
{
    int e = check_string(m->garment, "garment", why);
    if (e == BUS_OK)
        e = check_string(m->fabric, "fabric", why);
    if (e != BUS_OK)
        return e;
    if (m->garment[0] == 0)
        return bus_reject_set(why, BUS_ERR_STRING, "garment is empty");
    if (m->size < TRYON_CONTROL_T_SIZE_S || m->size > TRYON_CONTROL_T_SIZE_L)
        return bus_reject_set(why, BUS_ERR_RANGE, "size %d (S %d, M %d, L %d)", (int)m->size,
                              TRYON_CONTROL_T_SIZE_S, TRYON_CONTROL_T_SIZE_M,
                              TRYON_CONTROL_T_SIZE_L);
    if (m->utime < 0 || m->seq < 0)
        return bus_reject_set(why, BUS_ERR_RANGE, "utime %lld, seq %d (both >= 0)",
                              (long long)m->utime, (int)m->seq);
    return BUS_OK;
}

int bus_validate(bus_type t, const void *msg, bus_reject *why)
{
    if (why)
        *why = (bus_reject){.code = BUS_OK};
    switch (t) {
    case BUS_DEPTH_FRAME:
        return validate_depth_frame(msg, why);
    case BUS_BODY:
        return validate_body(msg, why);
    case BUS_CLOTH:
        return validate_cloth(msg, why);
    case BUS_TIMING:
        return validate_timing(msg, why);
    case BUS_CONTROL:
        return validate_control(msg, why);
    default:
        return bus_reject_set(why, BUS_ERR_TYPE, "type %d", (int)t);
    }
}
