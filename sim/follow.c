/* The tryon solver's moving frame ("follow", sim_desc.follow): before the feature points of a
 * body frame, the whole garment is moved by the rigid motion that its attachments made since the
 * last frame (x and x_prev alike, so its velocity relative to that frame is kept), then simulated
 * as before. The static iterations see the body at rest; without this, a turning or walking
 * body moves the garment only through its attachments and the contacts, and 25 Gauss-Seidel steps
 * propagate that motion about 25 springs down the garment: the tube twists and its hoops stretch
 * (docs/sim.md). A garment simulated in the frame of the body part it hangs from is how game
 * cloth handles characters that turn (NvCloth's linear and angular inertia, Unreal Chaos's
 * velocity scales of the reference bone: follow = 1 - that scale); fraction 1 drops the frame's
 * fictitious forces (centrifugal, Euler) from the garment, fraction 0 is the world frame.
 *
 * Which body part: not the attachments (the shirt's chest) but the body under the garment's
 * waist band (SIM_FOLLOW_DEPTH, half way down). A trunk that bends moves the chest and not the
 * hips: the chest's rigid motion swung the whole tube about the chest, its hem into the hips in
 * front and off them behind, and the contacts then pushed the hem's hoop out against its strain
 * limit (bend_forward: 31 % max strain, the hem's hoops; 2.9 % in the world frame). The waist turns
 * with a body that turns or walks, and hardly moves when the trunk bends above it (docs/sim.md,
 * "Real motion").
 *
 * The rigid motion that best maps points p_i (frame k-1) onto q_i (frame k) in the least-squares
 * sense: Horn (1987), "Closed-form solution of absolute orientation using unit quaternions": the
 * rotation is the unit quaternion of the largest eigenvalue of a symmetric 4x4 matrix built from
 * the cross-covariance of the centred sets (found here by Jacobi rotations, in double). Unlike the
 * SVD of the cross-covariance it needs no special case for planar sets, such as a ring of
 * attachment points round the chest. */
#include <math.h>
#include <string.h>

#include "cloth.h"
#include "collide.h"

/* Eigenvector of the largest eigenvalue of the symmetric 4x4 a (destroyed), cyclic Jacobi. */
static void largest_eigenvector(double a[4][4], double out[4])
{
    double v[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
    for (int sweep = 0; sweep < 50; sweep++) {
        double off = 0.0, diag = 0.0;
        for (int i = 0; i < 4; i++) {
            diag += a[i][i] * a[i][i];
            for (int j = i + 1; j < 4; j++)
                off += a[i][j] * a[i][j];
        }
        if (off <= 1e-30 * (diag + 1e-300))
            break;
        for (int p = 0; p < 3; p++)
            for (int q = p + 1; q < 4; q++) {
                if (a[p][q] == 0.0)
                    continue;
                double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                double t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 4; k++) { /* a = J^T a J */
                    double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 4; k++) {
                    double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 4; k++) {
                    double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
    }
    int best = 0;
    for (int i = 1; i < 4; i++)
        if (a[i][i] > a[best][best])
            best = i;
    for (int k = 0; k < 4; k++)
        out[k] = v[k][best];
}

int sim_fit_rigid(const double (*p)[3], const double (*q)[3], int n, double fraction, float m[12])
{
    if (n < 3 || !(fraction >= 0.0 && fraction <= 1.0))
        return -1;
    double pc[3] = {0}, qc[3] = {0};
    for (int i = 0; i < n; i++)
        for (int d = 0; d < 3; d++) {
            pc[d] += p[i][d] / n;
            qc[d] += q[i][d] / n;
        }
    double s[3][3] = {{0}}; /* s[a][b] = sum (p - pc)_a (q - qc)_b */
    for (int i = 0; i < n; i++)
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++)
                s[a][b] += (p[i][a] - pc[a]) * (q[i][b] - qc[b]);
    double sxx = s[0][0], sxy = s[0][1], sxz = s[0][2], syx = s[1][0], syy = s[1][1], syz = s[1][2],
           szx = s[2][0], szy = s[2][1], szz = s[2][2];
    double nm[4][4] = {
        {sxx + syy + szz, syz - szy, szx - sxz, sxy - syx},
        {syz - szy, sxx - syy - szz, sxy + syx, szx + sxz},
        {szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy},
        {sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz},
    };
    double e[4];
    largest_eigenvector(nm, e);
    double len = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
    if (!(len > 0.0) || !isfinite(len))
        return -1;
    if (e[0] < 0.0) /* the shorter way round */
        len = -len;
    /* a fraction of the rotation: the same axis, that fraction of the angle */
    double w = e[0] / len, sn = sqrt(fmax(0.0, 1.0 - w * w));
    double half = fraction * acos(fmin(1.0, w)), ax[3] = {0.0, 0.0, 0.0};
    if (sn > 1e-12)
        for (int k = 0; k < 3; k++)
            ax[k] = e[k + 1] / len / sn * sin(half);
    w = cos(half);
    double x = ax[0], y = ax[1], z = ax[2];
    double r[3][3] = {
        {w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)},
        {2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)},
        {2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z},
    };
    /* and the centroid that fraction of its way */
    for (int a = 0; a < 3; a++) {
        double t = pc[a] + fraction * (qc[a] - pc[a]);
        for (int b = 0; b < 3; b++) {
            m[4 * a + b] = (float)r[a][b];
            t -= r[a][b] * pc[b];
        }
        m[4 * a + 3] = (float)t;
        if (!isfinite(m[4 * a + 3]))
            return -1;
    }
    return 0;
}

void sim_follow(float (*x)[4], float (*x_prev)[4], int begin, int end, const float m[12])
{
    for (int i = begin; i < end; i++) {
        float a[3], b[3];
        for (int d = 0; d < 3; d++) {
            a[d] =
                m[4 * d] * x[i][0] + m[4 * d + 1] * x[i][1] + m[4 * d + 2] * x[i][2] + m[4 * d + 3];
            b[d] = m[4 * d] * x_prev[i][0] + m[4 * d + 1] * x_prev[i][1] +
                   m[4 * d + 2] * x_prev[i][2] + m[4 * d + 3];
        }
        memcpy(x[i], a, sizeof a);
        memcpy(x_prev[i], b, sizeof b);
    }
}

/* Whether the anchors' band goes round two body parts, not one: its centre (on the body frame
   k) lies outside the body. Half way down trousers or a skirt held at the waist are the thighs,
   which swing opposite ways in a stride and read as the pelvis turning: fitted to them, the
   moving frame turned the jeans 7.8 degrees and moved them 53 mm on the walk's first frame, the
   frame diverged (docs/garments.md, "The jeans on the walk"). Such a garment follows its
   attachments, the waist band itself. */
static int band_between_parts(const struct sim *s)
{
    float c[3] = {0.0f, 0.0f, 0.0f};
    for (int a = 0; a < s->num_follow_anchors; a++)
        for (int d = 0; d < 3; d++)
            c[d] += s->body.v[s->follow_anchor[a]][d] / (float)s->num_follow_anchors;
    return sim_collider_clearly_outside(s->collider, c);
}

/* The anchors: of the garment's vertices whose tether length is within SIM_FOLLOW_BAND_M under
   SIM_FOLLOW_DEPTH of the longest, at most SIM_FOLLOW_ANCHORS evenly, each to the body vertex
   nearest it on the last body frame (where the cloth is). Chosen on the first body frame with a
   previous one, and again after the body's vertex count changes. */
static void choose_anchors(struct sim *s)
{
    const sim_cloth *c = &s->cloth;
    const sim_body *b = &s->body;
    s->num_follow_anchors = 0;
    s->follow_anchor_nv = b->nv;
    float depth = 0.0f;
    for (int i = 0; i < c->nv; i++)
        depth = c->tether_anchor[i] >= 0 && c->tether_len[i] > depth ? c->tether_len[i] : depth;
    depth *= SIM_FOLLOW_DEPTH;
    int n = 0, k = 0;
    for (int i = 0; i < c->nv; i++)
        n += c->tether_anchor[i] >= 0 && c->tether_len[i] <= depth &&
             c->tether_len[i] >= depth - SIM_FOLLOW_BAND_M;
    int every = (n + SIM_FOLLOW_ANCHORS - 1) / SIM_FOLLOW_ANCHORS;
    for (int i = 0; i < c->nv && s->num_follow_anchors < SIM_FOLLOW_ANCHORS; i++) {
        if (!(c->tether_anchor[i] >= 0 && c->tether_len[i] <= depth &&
              c->tether_len[i] >= depth - SIM_FOLLOW_BAND_M) ||
            k++ % every)
            continue;
        float best = INFINITY;
        int bv = -1;
        for (int v = 0; v < b->nv; v++) {
            float d2 = 0.0f;
            for (int d = 0; d < 3; d++)
                d2 += (b->v_prev[v][d] - c->x[i][d]) * (b->v_prev[v][d] - c->x[i][d]);
            if (d2 < best) {
                best = d2;
                bv = v;
            }
        }
        if (bv >= 0)
            s->follow_anchor[s->num_follow_anchors++] = bv;
    }
    if (s->num_follow_anchors >= 3 && band_between_parts(s))
        s->num_follow_anchors = 0; /* follow_points falls back to the attachments */
}

/* The points the moving frame is fitted to, in frames k-1 (p) and k (q): the anchors, or where
   there are fewer than 3 the attachments. Returns their count. */
static int follow_points(struct sim *s, double (*p)[3], double (*q)[3])
{
    const sim_body *b = &s->body;
    if (s->follow_anchor_nv != b->nv)
        choose_anchors(s);
    int n = s->num_follow_anchors;
    if (n >= 3) {
        for (int a = 0; a < n; a++)
            for (int d = 0; d < 3; d++) {
                p[a][d] = b->v_prev[s->follow_anchor[a]][d];
                q[a][d] = b->v[s->follow_anchor[a]][d];
            }
        return n;
    }
    n = s->cloth.num_attachments;
    for (int a = 0; a < n; a++) {
        const sim_attachment *at = &s->cloth.attachments[a];
        const int32_t *t = b->tris[at->body_triangle];
        for (int d = 0; d < 3; d++) {
            p[a][d] = q[a][d] = 0.0;
            for (int k = 0; k < 3; k++) {
                p[a][d] += (double)at->bary[k] * b->v_prev[t[k]][d];
                q[a][d] += (double)at->bary[k] * b->v[t[k]][d];
            }
        }
    }
    return n;
}

void sim_follow_motion(struct sim *s)
{
    const sim_body *b = &s->body;
    int na = s->cloth.num_attachments;
    s->follow_on = 0;
    if (s->desc.solver != SIM_SOLVER_TRYON || !(s->desc.follow > 0.0f) || !b->have_prev || na < 3 ||
        !s->follow_pq || !s->follow_anchor)
        return;
    double(*p)[3] = s->follow_pq, (*q)[3] = s->follow_pq + na + SIM_FOLLOW_ANCHORS;
    int n = follow_points(s, p, q);
    if (sim_fit_rigid((const double(*)[3])p, (const double(*)[3])q, n, (double)s->desc.follow,
                      s->follow_m) != 0)
        return;
    /* a body standing still: nothing to move (the identity would leave the same bits) */
    for (int k = 0; k < 12; k++)
        if (s->follow_m[k] != (k % 5 == 0 ? 1.0f : 0.0f))
            s->follow_on = 1;
}
