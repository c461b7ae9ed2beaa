/* The solver kernels, twins of sim/springs.c: same names, same order of
 * operations, one work-item per vertex or spring. sim_iterations_tryon runs a whole frame of the
 * tryon solver in ONE work-group, with barriers between the passes instead of kernel launches:
 * on PoCL a launch costs 10-50 us and a frame has about 30 passes x 25 iterations. */

/* x' = x + (x - x_prev) keep + a dt^2; pinned (w = 0) stays. */
void sim_verlet_one(__global float4 *x, __global float4 *x_prev, int i, float keep, float4 a)
{
    float4 xi = x[i], xp = x_prev[i];
    if (xi.w == 0.0f)
        return;
    float vx = (xi.x - xp.x) * keep, vy = (xi.y - xp.y) * keep, vz = (xi.z - xp.z) * keep;
    x_prev[i] = (float4)(xi.x, xi.y, xi.z, xp.w);
    x[i] = (float4)(xi.x + vx + a.x, xi.y + vy + a.y, xi.z + vz + a.z, xi.w);
}

/* Move the ends of spring (i, j) by d c wi and -d c wj. */
void sim_move_ends(__global float4 *x, int i, int j, float4 d, float c, float wi, float wj)
{
    float4 a = x[i], b = x[j];
    x[i] = (float4)(a.x + d.x * c * wi, a.y + d.y * c * wi, a.z + d.z * c * wi, a.w);
    x[j] = (float4)(b.x - d.x * c * wj, b.y - d.y * c * wj, b.z - d.z * c * wj, b.w);
}

/* XPBD distance constraint, one Gauss-Seidel step (sim_project_springs). */
void sim_project_spring(__global float4 *x, __global const int2 *ends, __global const float *rest,
                        __global const uchar *kind, float4 alpha, int s)
{
    int i = ends[s].x, j = ends[s].y;
    float wi = x[i].w, wj = x[j].w;
    int k = kind[s];
    float al = k == 0 ? alpha.x : (k == 1 ? alpha.y : alpha.z);
    float wsum = wi + wj + al;
    if (wi + wj == 0.0f)
        return;
    float4 d = (float4)(x[j].x - x[i].x, x[j].y - x[i].y, x[j].z - x[i].z, 0.0f);
    float len = sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    if (len < 1e-9f)
        return;
    float c = (len - rest[s]) / (len * wsum);
    sim_move_ends(x, i, j, d, c, wi, wj);
}

/* Stretch springs clamped to rest (1 + limit) (sim_strain_limit). */
void sim_strain_limit_one(__global float4 *x, __global const int2 *ends, __global const float *rest,
                          __global const uchar *kind, int s, float limit)
{
    if (kind[s] != 0)
        return;
    int i = ends[s].x, j = ends[s].y;
    float wi = x[i].w, wj = x[j].w;
    float wsum = wi + wj;
    if (wsum == 0.0f)
        return;
    float4 d = (float4)(x[j].x - x[i].x, x[j].y - x[i].y, x[j].z - x[i].z, 0.0f);
    float len = sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    float lmax = rest[s] * (1.0f + limit);
    if (len <= lmax)
        return;
    float c = (len - lmax) / (len * wsum);
    sim_move_ends(x, i, j, d, c, wi, wj);
}

/* Twin of pull_within (sim/springs.c): x[i] moved alone to within lmax of x[q]. */
void sim_pull_within(__global float4 *x, int i, int q, float lmax)
{
    float4 p = x[i], o = x[q];
    float dx = p.x - o.x, dy = p.y - o.y, dz = p.z - o.z;
    float l = sqrt(dx * dx + dy * dy + dz * dz);
    if (l <= lmax)
        return;
    float c = (l - lmax) / l;
    x[i] = (float4)(p.x - dx * c, p.y - dy * c, p.z - dz * c, p.w);
}

/* Long-range attachment of vertex i to its anchor (sim_tethers). */
void sim_tether_one(__global float4 *x, __global const int *anchor, __global const float *len,
                    int i, float limit)
{
    int a = anchor[i];
    if (a < 0 || x[i].w == 0.0f)
        return;
    sim_pull_within(x, i, a, len[i] * (1.0f + limit));
}

/* Twin of pull_within_still (sim/springs.c): x[i] moved alone to within lmax of x[q], and where
   it was farther its velocity away from x[q] removed (x_prev holds -(x - x_prev) in the
   post-stabilisation's bracket): seed 003's velocity modification, one-sided. */
void sim_pull_within_still(__global float4 *x, __global float4 *x_prev, int i, int q, float lmax)
{
    float4 p = x[i], o = x[q], v = x_prev[i];
    float dx = p.x - o.x, dy = p.y - o.y, dz = p.z - o.z;
    float len = sqrt(dx * dx + dy * dy + dz * dz);
    if (len <= lmax)
        return;
    float away = -(v.x * dx + v.y * dy + v.z * dz) / len;
    float c = (len - lmax) / len;
    x[i] = (float4)(p.x - dx * c, p.y - dy * c, p.z - dz * c, p.w);
    if (away > 0.0f)
        x_prev[i] = (float4)(v.x + away * (dx / len), v.y + away * (dy / len),
                             v.z + away * (dz / len), v.w);
}

/* The strain-limit hierarchy, entry e (sim_strain_hierarchy): its vertex moved alone to within
   rest (1 + limit) of each parent in turn, its velocity away from them removed. */
void sim_strain_hierarchy_one(__global float4 *x, __global float4 *x_prev,
                              __global const int *vertex, __global const int *parent_start,
                              __global const int *parent, __global const float *rest, int e,
                              float limit)
{
    int i = vertex[e];
    if (x[i].w == 0.0f)
        return;
    for (int k = parent_start[e]; k < parent_start[e + 1]; k++)
        sim_pull_within_still(x, x_prev, i, parent[k], rest[k] * (1.0f + limit));
}

/* The support hierarchy (sim/solver_c.c support_hierarchy, sim/springs.c sim_support_levels and
   sim_support_pull), for a garment without attachments. How squarely the body holds vertex i up
   (sim_collider_resting): its contact face's +y when it lies within h + tol of that face, else
   -2 (SIM_NOT_RESTING). */
float sim_resting_one(__global const float4 *x, int i, __global const int *contact,
                      __global const float4 *v, __global const int4 *tris,
                      __global const float4 *nrm, float h, float tol)
{
    int t = contact[i], region;
    if (t < 0)
        return -2.0f;
    float r = h + tol;
    return sim_tri_dist2(v, tris, t, x[i], &region) <= r * r ? nrm[t].y : -2.0f;
}

/* Floats as ints in the same order (-0 taken as +0, as C's comparison takes it). */
int sim_float_order(float f)
{
    int k = as_int(f == 0.0f ? 0.0f : f);
    return k < 0 ? k ^ 0x7fffffff : k;
}

/* sim_support_pull: vertex i to within the limit of its stretch neighbours one level nearer the
   root, as the hierarchy does. */
void sim_support_pull_one(__global float4 *x, __global float4 *x_prev, __global const int2 *ends,
                          __global const float *rest, __global const int *adj_start,
                          __global const int *adj_spring, __global const int *level, int i,
                          float limit)
{
    if (x[i].w == 0.0f)
        return;
    for (int k = adj_start[i]; k < adj_start[i + 1]; k++) {
        int s = adj_spring[k];
        int u = ends[s].x == i ? ends[s].y : ends[s].x;
        if (level[u] == level[i] - 1)
            sim_pull_within_still(x, x_prev, i, u, rest[s] * (1.0f + limit));
    }
}

/* Post-stabilisation brackets (sim_post_begin / sim_post_end): x_prev -= x, then += x. */
void sim_post_begin_one(__global const float4 *x, __global float4 *x_prev, int i)
{
    float4 p = x[i], q = x_prev[i];
    if (p.w != 0.0f)
        x_prev[i] = (float4)(q.x - p.x, q.y - p.y, q.z - p.z, q.w);
}

void sim_post_end_one(__global const float4 *x, __global float4 *x_prev, int i)
{
    float4 p = x[i], q = x_prev[i];
    if (p.w != 0.0f)
        x_prev[i] = (float4)(q.x + p.x, q.y + p.y, q.z + p.z, q.w);
}

/* The moving frame (sim/follow.c sim_follow): x and x_prev of every vertex moved by the rigid
   motion whose rows are r0, r1, r2 (x' = r.xyz . x + r.w), in the C loop's order. */
__kernel void sim_follow(__global float4 *x, __global float4 *x_prev, int n, float4 r0, float4 r1,
                         float4 r2)
{
    int i = get_global_id(0);
    if (i >= n)
        return;
    float4 p = x[i], q = x_prev[i];
    x[i] = (float4)(r0.x * p.x + r0.y * p.y + r0.z * p.z + r0.w,
                    r1.x * p.x + r1.y * p.y + r1.z * p.z + r1.w,
                    r2.x * p.x + r2.y * p.y + r2.z * p.z + r2.w, p.w);
    x_prev[i] = (float4)(r0.x * q.x + r0.y * q.y + r0.z * q.z + r0.w,
                         r1.x * q.x + r1.y * q.y + r1.z * q.z + r1.w,
                         r2.x * q.x + r2.y * q.y + r2.z * q.z + r2.w, q.w);
}

/* The layout of sim_attachment (sim/sim.h). */
typedef struct sim_attachment {
    int vertex;
    int body_triangle;
    float bary[3];
    float offset_m;
} sim_attachment;

/* Attached vertices follow their body triangle: from where they are (att_from) to where frame k
   puts them (att_to), spread over the steps of the frame (sim/solver_c.c attachment_targets,
   the face normal computed as sim.c body_store does). */
__kernel void sim_attachment_targets(__global const float4 *x, __global const sim_attachment *at,
                                     int n, __global const float4 *v, __global const int4 *tris,
                                     __global float4 *att_from, __global float4 *att_to)
{
    int a = get_global_id(0);
    if (a >= n)
        return;
    sim_attachment t = at[a];
    int4 f = tris[t.body_triangle];
    float4 p0 = v[f.x], p1 = v[f.y], p2 = v[f.z];
    float e1x = p1.x - p0.x, e1y = p1.y - p0.y, e1z = p1.z - p0.z;
    float e2x = p2.x - p0.x, e2y = p2.y - p0.y, e2z = p2.z - p0.z;
    float nx = e1y * e2z - e1z * e2y, ny = e1z * e2x - e1x * e2z, nz = e1x * e2y - e1y * e2x;
    float len = sqrt(nx * nx + ny * ny + nz * nz);
    float inv = len > 0.0f ? 1.0f / len : 0.0f;
    nx *= inv;
    ny *= inv;
    nz *= inv;
    float4 xv = x[t.vertex];
    att_from[a] = (float4)(xv.x, xv.y, xv.z, 0.0f);
    att_to[a] =
        (float4)(t.bary[0] * p0.x + t.bary[1] * p1.x + t.bary[2] * p2.x + t.offset_m * nx,
                 t.bary[0] * p0.y + t.bary[1] * p1.y + t.bary[2] * p2.y + t.offset_m * ny,
                 t.bary[0] * p0.z + t.bary[1] * p1.z + t.bary[2] * p2.z + t.offset_m * nz, 0.0f);
}

/* Step it of iters: attached vertex a at the fraction (it + 1) / iters of its way. */
void sim_place_attachment(__global float4 *x, __global float4 *x_prev,
                          __global const sim_attachment *at, __global const float4 *att_from,
                          __global const float4 *att_to, int a, int it, int iters)
{
    float u = (float)(it + 1) / (float)iters;
    int vi = at[a].vertex;
    float4 p = x[vi], f = att_from[a], t = att_to[a];
    x_prev[vi] = (float4)(p.x, p.y, p.z, x_prev[vi].w);
    x[vi] = (float4)(f.x + u * (t.x - f.x), f.y + u * (t.y - f.y), f.z + u * (t.z - f.z), p.w);
}

/* One Gauss-Seidel sweep of the strain limit over the stretch colours, a barrier after each
   (strain_limit_sweep in sim/solver_c.c); every work-item of the group calls it. */
void sim_strain_sweep(__global float4 *x, __global const int2 *ends, __global const float *rest,
                      __global const uchar *kind, __global const int *color_start,
                      int num_stretch_colors, float limit)
{
    int lid = get_local_id(0), L = get_local_size(0);
    for (int col = 0; col < num_stretch_colors; col++) {
        for (int s = color_start[col] + lid; s < color_start[col + 1]; s += L)
            sim_strain_limit_one(x, ends, rest, kind, s, limit);
        barrier(CLK_GLOBAL_MEM_FENCE);
    }
}

/* Spring s's stretch strain for the settle test: stretch springs only (0 for the others), NaN
   as infinity. */
float sim_settle_strain_one(__global const float4 *x, __global const int2 *ends,
                            __global const float *rest, __global const uchar *kind, int s)
{
    if (kind[s] != 0 || !(rest[s] > 0.0f))
        return 0.0f;
    float4 a = x[ends[s].x], c = x[ends[s].y];
    float dx = c.x - a.x, dy = c.y - a.y, dz = c.z - a.z;
    float e = (sqrt(dx * dx + dy * dy + dz * dz) - rest[s]) / rest[s];
    return e == e ? e : INFINITY;
}

/* The support hierarchy (SIM_STAGE_SUPPORT) in one work-group: the highest resting vertex is the
   root, then breadth first, level by level, each level pulled towards the level before. key,
   root and count are the group's __local ints. */
void sim_support_group(__global float4 *x, __global float4 *x_prev, int nv,
                       __global const int2 *ends, __global const float *rest,
                       __global const int *contact, __global const float4 *v,
                       __global const int4 *tris, __global const float4 *nrm, float h,
                       float rest_tol, float limit, __global const int *adj_start,
                       __global const int *adj_spring, __global int *level, __global int *front,
                       __local int *support_key, __local int *support_root,
                       __local int *support_count)
{
    int lid = get_local_id(0), L = get_local_size(0);
    if (lid == 0) {
        *support_key = INT_MIN;
        *support_root = INT_MAX;
    }
    barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
    for (int i = lid; i < nv; i += L) {
        level[i] = -1;
        if (sim_resting_one(x, i, contact, v, tris, nrm, h, rest_tol) > 0.0f)
            atomic_max(support_key, sim_float_order(x[i].y));
    }
    barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
    for (int i = lid; i < nv; i += L) {
        if (sim_resting_one(x, i, contact, v, tris, nrm, h, rest_tol) > 0.0f &&
            sim_float_order(x[i].y) == *support_key)
            atomic_min(support_root, i);
    }
    barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
    int root = *support_root, n = root == INT_MAX ? 0 : 1;
    if (lid == 0 && n) {
        level[root] = 0;
        front[0] = root;
    }
    for (int l = 0; n > 0; l++) {
        __global int *cur = front + (l & 1) * nv, *next = front + (~l & 1) * nv;
        if (lid == 0)
            *support_count = 0;
        barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
        for (int f = lid; f < n; f += L) {
            int i = cur[f];
            for (int k = adj_start[i]; k < adj_start[i + 1]; k++) {
                int sp = adj_spring[k];
                int u = ends[sp].x == i ? ends[sp].y : ends[sp].x;
                if (atomic_cmpxchg((volatile __global int *)&level[u], -1, l + 1) == -1)
                    next[atomic_inc(support_count)] = u;
            }
        }
        barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
        n = *support_count;
        for (int f = lid; f < n; f += L)
            sim_support_pull_one(x, x_prev, ends, rest, adj_start, adj_spring, level, next[f],
                                 limit);
        barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
    }
}

/* The tryon solver's iterations of one frame in one work-group: the stages of the frame's list
   (kernels/solver_params.h) after the first two, which the host runs as commands of their own,
   as sim/solver_c.c runs them, a barrier after each pass. The settings in p
   (kernels/solver_params.h, filled by sim/frame_settings.c for both backends), then the buffers
   in the order sim/cl_backend.c iterations sets them. */
__kernel void sim_iterations_tryon(
    const sim_solver_params p, __global float4 *x, __global float4 *x_prev,
    __global const int2 *ends, __global const float *rest, __global const uchar *kind,
    __global const int *color_start, __global const int *tether_anchor,
    __global const float *tether_len, __global const int2 *child, __global const int *order,
    __global const float4 *lo, __global const float4 *hi, __global const float4 *v,
    __global const int4 *tris, __global const float4 *nrm, __global const int4 *nbr,
    __global const int *vt_start, __global const int *vt_list, __global int *contact,
    __global const sim_attachment *att, __global const float4 *att_from,
    __global const float4 *att_to, __global const int *hier_level_start,
    __global const int *hier_vertex, __global const int *hier_parent_start,
    __global const int *hier_parent, __global const float *hier_rest, __global int *settle_rounds,
    __global const int *adj_start, __global const int *adj_spring, __global int *level,
    __global int *front, __global float4 *x_seen)
{
    int lid = get_local_id(0), L = get_local_size(0);
    __local int settle_max, support_key, support_root, support_count;
    const int nv = p.nv, num_colors = p.num_colors, num_stretch_colors = p.num_stretch_colors,
              iters = p.iters, fast = p.fast, nleaves = p.nleaves, natt = p.natt,
              hier_levels = p.hier_levels, settle_batch = p.settle_batch;
    const float limit = p.limit, keep = p.keep, radius = p.radius, h = p.h, mu = p.mu,
                rest_tol = p.rest_tol;
    const float4 alpha = (float4)(p.alpha[0], p.alpha[1], p.alpha[2], 0.0f);
    const float4 g = (float4)(p.g[0], p.g[1], p.g[2], 0.0f);
    if (lid == 0)
        *settle_rounds = 0;
    int nstretch = color_start[num_stretch_colors], stop = 0;
    float prev = 0.0f;
    /* every work-item walks the same stages and takes the same branches (stop: the same maximum) */
    for (int b = 0; b < SIM_BLOCKS && !stop; b++)
        for (int rep = 0; rep < sim_block_repeats(b, &p) && !stop; rep++)
            for (int k = sim_block_start[b]; k < sim_block_start[b + 1] && !stop; k++) {
                int stage = sim_frame_stages[k];
                if (!sim_stage_runs(stage, b, rep, &p))
                    continue;
                switch (stage) {
                case SIM_STAGE_START:
                case SIM_STAGE_CONTACTS:
                    break; /* the commands before this kernel (sim/cl_backend.c cl_frame) */
                case SIM_STAGE_STEP: {
                    for (int i = lid; i < nv; i += L) {
                        if (rep == 0)
                            x_seen[i] = x[i];
                        sim_verlet_one(x, x_prev, i, keep, g);
                    }
                    /* Attached vertices have w = 0, so Verlet left them alone: no race. */
                    for (int a = lid; a < natt; a += L)
                        sim_place_attachment(x, x_prev, att, att_from, att_to, a, rep, iters);
                    barrier(CLK_GLOBAL_MEM_FENCE);
                    break;
                }
                case SIM_STAGE_SPRINGS:
                    for (int col = 0; col < num_colors; col++) {
                        for (int s = color_start[col] + lid; s < color_start[col + 1]; s += L)
                            sim_project_spring(x, ends, rest, kind, alpha, s);
                        barrier(CLK_GLOBAL_MEM_FENCE);
                    }
                    break;
                case SIM_STAGE_SWEEP:
                    sim_strain_sweep(x, ends, rest, kind, color_start, num_stretch_colors, limit);
                    break;
                case SIM_STAGE_VERTICES: {
                    int close = sim_vertices_close(b), open = sim_vertices_open(b, rep, &p);
                    for (int i = lid; i < nv; i += L) {
                        sim_tether_one(x, tether_anchor, tether_len, i, limit);
                        if (close)
                            sim_post_end_one(x, x_prev, i);
                        sim_research_one(x, i, contact, x_seen, v, tris, nrm, nbr, vt_start,
                                         vt_list, nleaves, child, order, lo, hi, h, radius);
                        sim_resolve_one(x, x_prev, i, contact, v, tris, nrm, nbr, vt_start, vt_list,
                                        h, mu);
                        if (open)
                            sim_post_begin_one(x, x_prev, i);
                    }
                    barrier(CLK_GLOBAL_MEM_FENCE);
                    if (lid == 0 && b == SIM_BLOCK_SETTLE)
                        *settle_rounds = rep + 1;
                    break;
                }
                case SIM_STAGE_HIERARCHY:
                    for (int l = 0; l < hier_levels; l++) {
                        for (int e = hier_level_start[l] + lid; e < hier_level_start[l + 1]; e += L)
                            sim_strain_hierarchy_one(x, x_prev, hier_vertex, hier_parent_start,
                                                     hier_parent, hier_rest, e, limit);
                        barrier(CLK_GLOBAL_MEM_FENCE);
                    }
                    break;
                case SIM_STAGE_SUPPORT:
                    sim_support_group(x, x_prev, nv, ends, rest, contact, v, tris, nrm, h, rest_tol,
                                      limit, adj_start, adj_spring, level, front, &support_key,
                                      &support_root, &support_count);
                    break;
                case SIM_STAGE_SETTLE_TEST: {
                    /* the largest stretch strain: the same float as C's (non-negative floats
                       order as their bits), so is the branch */
                    if (lid == 0)
                        settle_max = 0;
                    barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
                    float m = 0.0f;
                    for (int s = lid; s < nstretch; s += L) {
                        float e = sim_settle_strain_one(x, ends, rest, kind, s);
                        if (e > m)
                            m = e;
                    }
                    atomic_max(&settle_max, as_int(m));
                    barrier(CLK_LOCAL_MEM_FENCE);
                    float mx = as_float(settle_max);
                    if (sim_settle_stop(mx, prev, rep == 0, fast, &p))
                        stop = 1;
                    prev = mx;
                    break;
                }
                case SIM_STAGE_REOPEN:
                    for (int i = lid; i < nv; i += L)
                        sim_post_begin_one(x, x_prev, i);
                    barrier(CLK_GLOBAL_MEM_FENCE);
                    break;
                default:
                    break;
                }
            }
}

/* The layout of sim_solver_params as this device compiles it: its size and the offset of its
   last field, in bytes (test_cl_backend compares them with the host's). */
__kernel void sim_solver_params_layout(__global int *out)
{
    sim_solver_params p;
    out[0] = (int)sizeof(sim_solver_params);
    out[1] = (int)((__private char *)&p.rest_tol - (__private char *)&p);
}

/* ---- The frame pass by pass, for a GPU (sim/cl_backend.c, cl_passes) ----------------------------
 * The host walks sim_frame_stages as sim_iterations_tryon does and launches each pass over as many
 * work-groups as it has items: one work-group is one of a GPU's multiprocessors (on the lent H100
 * 1 of 132: the 7,000-vertex shirt 8-11 ms a frame), where a launch costs a few microseconds. Each
 * pass is the same _one function as in sim_iterations_tryon; a colour's springs share no vertex,
 * so the order within a pass does not change the result. */

/* SIM_STAGE_STEP of step rep: Verlet, the attachments placed (item i: vertex i and attachment i);
   in the first, where each point's contact was searched. */
__kernel void sim_pass_step(const sim_solver_params p, int rep, __global float4 *x,
                            __global float4 *x_prev, __global const sim_attachment *att,
                            __global const float4 *att_from, __global const float4 *att_to,
                            __global float4 *x_seen)
{
    int i = get_global_id(0);
    if (i < p.nv) {
        if (rep == 0)
            x_seen[i] = x[i];
        sim_verlet_one(x, x_prev, i, p.keep, (float4)(p.g[0], p.g[1], p.g[2], 0.0f));
    }
    if (i < p.natt)
        sim_place_attachment(x, x_prev, att, att_from, att_to, i, rep, p.iters);
}

/* SIM_STAGE_SPRINGS, one colour: springs [begin, end). */
__kernel void sim_pass_springs(const sim_solver_params p, int begin, int end, __global float4 *x,
                               __global const int2 *ends, __global const float *rest,
                               __global const uchar *kind)
{
    int s = begin + (int)get_global_id(0);
    if (s < end)
        sim_project_spring(x, ends, rest, kind, (float4)(p.alpha[0], p.alpha[1], p.alpha[2], 0.0f),
                           s);
}

/* SIM_STAGE_SWEEP, one stretch colour: springs [begin, end). */
__kernel void sim_pass_strain(const sim_solver_params p, int begin, int end, __global float4 *x,
                              __global const int2 *ends, __global const float *rest,
                              __global const uchar *kind)
{
    int s = begin + (int)get_global_id(0);
    if (s < end)
        sim_strain_limit_one(x, ends, rest, kind, s, p.limit);
}

/* SIM_STAGE_VERTICES: tethers, the bracket closed (close), the contact response, opened (open). */
__kernel void sim_pass_vertices(const sim_solver_params p, int close, int open, __global float4 *x,
                                __global float4 *x_prev, __global const int *tether_anchor,
                                __global const float *tether_len, __global int *contact,
                                __global const float4 *v, __global const int4 *tris,
                                __global const float4 *nrm, __global const int4 *nbr,
                                __global const int *vt_start, __global const int *vt_list,
                                __global const int2 *child, __global const int *order,
                                __global const float4 *lo, __global const float4 *hi,
                                __global float4 *x_seen)
{
    int i = get_global_id(0);
    if (i >= p.nv)
        return;
    sim_tether_one(x, tether_anchor, tether_len, i, p.limit);
    if (close)
        sim_post_end_one(x, x_prev, i);
    sim_research_one(x, i, contact, x_seen, v, tris, nrm, nbr, vt_start, vt_list, p.nleaves, child,
                     order, lo, hi, p.h, p.radius);
    sim_resolve_one(x, x_prev, i, contact, v, tris, nrm, nbr, vt_start, vt_list, p.h, p.mu);
    if (open)
        sim_post_begin_one(x, x_prev, i);
}

/* SIM_STAGE_HIERARCHY, one level: entries [begin, end). */
__kernel void sim_pass_hierarchy(const sim_solver_params p, int begin, int end, __global float4 *x,
                                 __global float4 *x_prev, __global const int *hier_vertex,
                                 __global const int *hier_parent_start,
                                 __global const int *hier_parent, __global const float *hier_rest)
{
    int e = begin + (int)get_global_id(0);
    if (e < end)
        sim_strain_hierarchy_one(x, x_prev, hier_vertex, hier_parent_start, hier_parent, hier_rest,
                                 e, p.limit);
}

/* SIM_STAGE_SUPPORT: breadth first, so in one work-group (sim_support_group). */
__kernel void sim_pass_support(const sim_solver_params p, __global float4 *x,
                               __global float4 *x_prev, __global const int2 *ends,
                               __global const float *rest, __global const int *contact,
                               __global const float4 *v, __global const int4 *tris,
                               __global const float4 *nrm, __global const int *adj_start,
                               __global const int *adj_spring, __global int *level,
                               __global int *front)
{
    __local int support_key, support_root, support_count;
    sim_support_group(x, x_prev, p.nv, ends, rest, contact, v, tris, nrm, p.h, p.rest_tol, p.limit,
                      adj_start, adj_spring, level, front, &support_key, &support_root,
                      &support_count);
}

/* SIM_STAGE_SETTLE_TEST: the largest stretch strain of springs [0, n) into *max_bits (zeroed
   by the host first; non-negative floats order as their bits), read back by the host. */
__kernel void sim_pass_settle_test(int n, __global const float4 *x, __global const int2 *ends,
                                   __global const float *rest, __global const uchar *kind,
                                   __global int *max_bits)
{
    int s = get_global_id(0);
    if (s < n) {
        float e = sim_settle_strain_one(x, ends, rest, kind, s);
        if (e > 0.0f)
            atomic_max(max_bits, as_int(e));
    }
}

/* SIM_STAGE_REOPEN before a settle round. */
__kernel void sim_pass_reopen(const sim_solver_params p, __global float4 *x,
                              __global float4 *x_prev)
{
    int i = get_global_id(0);
    if (i >= p.nv)
        return;
    sim_post_begin_one(x, x_prev, i);
}
