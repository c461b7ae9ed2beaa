/* The last few depth frames, so that each CLOTH is drawn over the very frame its body was fitted
 * to (its utime_capture), not over whatever depth arrived last: the sim is a frame or two behind
 * the camera, and a person moves in that time. */
#include <stdlib.h>
#include <string.h>

#include "mirror.h"
#include "render_private.h"

typedef struct slot {
    mirror_depth d;
    uint16_t *pixels;
    size_t cap;    /* pixels */
    float *person; /* the person's image, made on arrival (mirror_person_image) */
    int person_cap;
    int used;
} slot;

struct mirror_ring {
    slot s[MIRROR_RING];
    int next;
};

mirror_ring *mirror_ring_create(void)
{
    return calloc(1, sizeof(mirror_ring));
}

void mirror_ring_destroy(mirror_ring *r)
{
    if (!r)
        return;
    for (int i = 0; i < MIRROR_RING; i++) {
        free(r->s[i].pixels);
        free(r->s[i].person);
    }
    free(r);
}

int mirror_ring_push(mirror_ring *r, const mirror_depth *d)
{
    slot *s = &r->s[r->next];
    size_t n = (size_t)d->width * d->height;
    if (n > s->cap) {
        uint16_t *p = realloc(s->pixels, n * sizeof *p);
        if (!p)
            return -MIRROR_ERR_NO_MEMORY;
        s->pixels = p;
        s->cap = n;
    }
    memcpy(s->pixels, d->data, n * sizeof *s->pixels);
    s->d = *d;
    s->d.data = s->pixels;
    s->used = 1;
    /* the person's image now, while the sim works on this frame, not once its CLOTH is here;
     * without memory for it the renderer makes it then */
    s->d.person = mirror_person_image(&s->d, &s->person, &s->person_cap) == 0 ? s->person : NULL;
    r->next = (r->next + 1) % MIRROR_RING;
    return 0;
}

const mirror_depth *mirror_ring_find(const mirror_ring *r, int64_t utime, int *exact)
{
    const mirror_depth *best = NULL;
    *exact = 0;
    for (int i = 0; i < MIRROR_RING; i++) {
        const slot *s = &r->s[i];
        if (!s->used)
            continue;
        if (s->d.utime_capture == utime) {
            *exact = 1;
            return &s->d;
        }
        if (s->d.utime_capture < utime && (!best || s->d.utime_capture > best->utime_capture))
            best = &s->d;
    }
    return best;
}

const mirror_depth *mirror_ring_newest(const mirror_ring *r)
{
    int i = (r->next + MIRROR_RING - 1) % MIRROR_RING;
    return r->s[i].used ? &r->s[i].d : NULL;
}

void mirror_ring_forget(mirror_ring *r)
{
    for (int i = 0; i < MIRROR_RING; i++)
        r->s[i].used = 0;
    r->next = 0;
}
