/* The source registry: names to provider tables, as LCM picks a provider by URL. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "capture.h"
#include "cap_private.h"
#include "tryon_errors.h"

TRYON_ERROR_WORDS(CAP_ERROR_LIST, CAP_ERROR_COUNT, cap_error_name, cap_error_text,
                  "CAP_ERR_UNKNOWN")

static const cap_source_api *const sources[] = {&cap_freenect_api, &cap_openni2_api};
#define SOURCE_COUNT (int)(sizeof sources / sizeof sources[0])

const cap_source_api *cap_source_find(const char *name)
{
    for (int i = 0; name && i < SOURCE_COUNT; i++)
        if (!strcmp(sources[i]->name, name))
            return sources[i];
    return NULL;
}

const char *cap_source_name(int i)
{
    return i >= 0 && i < SOURCE_COUNT ? sources[i]->name : NULL;
}

cap_source *cap_source_create(const char *name, const cap_source_desc *d, int *code, char *err,
                              size_t errlen)
{
    const cap_source_api *api = cap_source_find(name);
    if (!api) {
        snprintf(err, errlen, "unknown source '%s' (freenect or openni2)", name ? name : "");
        *code = -CAP_ERR_SOURCE;
        return NULL;
    }
    cap_source *s = calloc(1, sizeof *s);
    if (!s) {
        snprintf(err, errlen, "out of memory");
        *code = -CAP_ERR_NO_MEMORY;
        return NULL;
    }
    s->api = api;
    *code = api->open(s, d, err, errlen);
    if (*code != CAP_OK) {
        api->close(s);
        free(s);
        return NULL;
    }
    return s;
}

int cap_source_next(cap_source *s, cap_frame *out, char *err, size_t errlen)
{
    return s->api->next(s, out, err, errlen);
}

void cap_source_destroy(cap_source *s)
{
    if (!s)
        return;
    s->api->close(s);
    free(s);
}
