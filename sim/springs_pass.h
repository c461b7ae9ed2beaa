/* Private to sim/springs.c: the vectorised passes, written once on the wide-float layer (wide.h)
 * and included once per width with WF(op) naming that width's operation (wf1_op, wf4_op, wf8_op),
 * WF_LANES its lanes and WF_TARGET its function attribute. Each pass takes the items [i, end) (its
 * last two arguments) a run of WF_LANES at a time and returns where it stopped; the next narrower
 * width takes the rest. Lane by lane each is the scalar formula, so every width gives the same
 * bits. No include guard: included once per width. */

/* Springs [s, end) of one colour (they share no vertex, so the lanes do not alias). alpha set:
 * XPBD, dlambda = -C / (wi + wj + alpha[kind]) on every spring not pinned at both ends and not of
 * zero length. alpha NULL: the clamp, the springs of the kinds in `kinds` (bit per kind) longer
 * than rest (1 + ratio) shortened back to it, each end moved in proportion to its inverse mass. */
static inline WF_TARGET int WF(springs)(float (*x)[4], const int32_t (*ends)[2], const float *rest,
                                        const uint8_t *kind, const float *alpha, unsigned kinds,
                                        float ratio, int s, int end)
{
    const WF(t) zero = WF(set1)(0.0f), tiny = WF(set1)(1e-9f), scale = WF(set1)(1.0f + ratio);
    const float none[3] = {0.0f, 0.0f, 0.0f};
    const WF(table) table = WF(table_of)(alpha ? alpha : none);
    for (; s + WF_LANES <= end; s += WF_LANES) {
        WF(t) a[4], b[4];
        WF(rows)((const float(*)[4])x, &ends[s][0], 2, a);
        WF(rows)((const float(*)[4])x, &ends[s][1], 2, b);
        WF(t) d[3] = {WF(sub)(b[0], a[0]), WF(sub)(b[1], a[1]), WF(sub)(b[2], a[2])};
        WF(t) w2 = WF(add)(a[3], b[3]);
        WF(t)
        len = WF(sqrt)(
            WF(add)(WF(add)(WF(mul)(d[0], d[0]), WF(mul)(d[1], d[1])), WF(mul)(d[2], d[2])));
        WF(t) target, wsum;
        int mask;
        if (alpha) {
            target = WF(load)(rest + s);
            wsum = WF(add)(w2, WF(lookup)(&table, kind + s));
            mask = WF(neq)(w2, zero) & WF(nlt)(len, tiny);
        } else {
            target = WF(mul)(WF(load)(rest + s), scale);
            wsum = w2;
            mask = WF(neq)(w2, zero) & WF(nle)(len, target);
            if (!(kinds & 1u) || !wf_bytes_zero(kind + s, WF_LANES))
                for (int k = 0; k < WF_LANES; k++)
                    if (!(kinds >> kind[s + k] & 1u))
                        mask &= ~(1 << k);
        }
        if (!mask)
            continue;
        WF(t) c = WF(div)(WF(sub)(len, target), WF(mul)(len, wsum));
        WF(t) ni[4], nj[4];
        for (int k = 0; k < 3; k++) {
            WF(t) t = WF(mul)(d[k], c);
            ni[k] = WF(add)(a[k], WF(mul)(t, a[3]));
            nj[k] = WF(sub)(b[k], WF(mul)(t, b[3]));
        }
        ni[3] = a[3], nj[3] = b[3];
        WF(store)(x, &ends[s][0], 2, ni, mask);
        WF(store)(x, &ends[s][1], 2, nj, mask);
    }
    return s;
}

/* Verlet on vertices [i, end): x' = x + (x - x_prev) keep + a dt^2, x_prev' = x; pinned or
 * attached vertices (w = 0) stay, the driver places them. */
static inline WF_TARGET int WF(verlet)(float (*x)[4], float (*x_prev)[4], float keep,
                                       const float accel_dt2[3], int i, int end)
{
    const WF(t) zero = WF(set1)(0.0f), k = WF(set1)(keep);
    const WF(t) g[3] = {WF(set1)(accel_dt2[0]), WF(set1)(accel_dt2[1]), WF(set1)(accel_dt2[2])};
    for (; i + WF_LANES <= end; i += WF_LANES) {
        int32_t self[WF_LANES];
        for (int l = 0; l < WF_LANES; l++)
            self[l] = i + l;
        WF(t) p[4], q[4], n[4];
        WF(rows)((const float(*)[4])x, self, 1, p);
        WF(rows)((const float(*)[4])x_prev, self, 1, q);
        int mask = WF(neq)(p[3], zero);
        if (!mask)
            continue;
        for (int d = 0; d < 3; d++)
            n[d] = WF(add)(WF(add)(p[d], WF(mul)(WF(sub)(p[d], q[d]), k)), g[d]);
        n[3] = p[3];
        q[0] = p[0], q[1] = p[1], q[2] = p[2]; /* x_prev = x, its own w kept */
        WF(store)(x_prev, self, 1, q, mask);
        WF(store)(x, self, 1, n, mask);
    }
    return i;
}

/* Tethers on vertices [i, end): each free vertex with an anchor moved alone to within
 * len (1 + limit) of it (the anchors are attached and do not move). Mid-step which of the lanes
 * are out of reach is a coin toss for the branch predictor: every tethered free vertex is stored,
 * one in reach as it was. */
static inline WF_TARGET int WF(tethers)(float (*x)[4], const int32_t *anchor, const float *len,
                                        float limit, int i, int end)
{
    const WF(t) zero = WF(set1)(0.0f), scale = WF(set1)(1.0f + limit);
    for (; i + WF_LANES <= end; i += WF_LANES) {
        int32_t self[WF_LANES], to[WF_LANES];
        int mask = 0;
        for (int l = 0; l < WF_LANES; l++) {
            self[l] = i + l;
            to[l] = anchor[i + l] >= 0 ? anchor[i + l] : i + l;
            mask |= (anchor[i + l] >= 0) << l;
        }
        if (!mask)
            continue;
        WF(t) p[4], q[4], n[4];
        WF(rows)((const float(*)[4])x, self, 1, p);
        mask &= WF(neq)(p[3], zero);
        if (!mask)
            continue;
        WF(rows)((const float(*)[4])x, to, 1, q);
        WF(t) d[3] = {WF(sub)(p[0], q[0]), WF(sub)(p[1], q[1]), WF(sub)(p[2], q[2])};
        WF(t)
        l = WF(sqrt)(
            WF(add)(WF(add)(WF(mul)(d[0], d[0]), WF(mul)(d[1], d[1])), WF(mul)(d[2], d[2])));
        WF(t) lmax = WF(mul)(WF(load)(len + i), scale);
        int move = mask & WF(nle)(l, lmax);
        WF(t) c = WF(div)(WF(sub)(l, lmax), l);
        for (int k = 0; k < 3; k++)
            n[k] = WF(select)(move, WF(sub)(p[k], WF(mul)(d[k], c)), p[k]);
        n[3] = p[3];
        WF(store)(x, self, 1, n, mask);
    }
    return i;
}
