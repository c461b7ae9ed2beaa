/* The source registry: names to provider tables, as LCM picks a provider by URL. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "capture.h"
#include "cap_private.h"

#define CAP_ERROR_NAME(id, text) #id,
static const char *const error_names[] = {CAP_ERROR_LIST(CAP_ERROR_NAME)};
#undef CAP_ERROR_NAME
#define CAP_ERROR_TEXT(id, text) text,
static const char *const error_texts[] = {CAP_ERROR_LIST(CAP_ERROR_TEXT)};
#undef CAP_ERROR_TEXT

const char *cap_error_name(int e)
{
    e = e < 0 ? -e : e;
    return (unsigned)e < CAP_ERROR_COUNT ? error_names[e] : "CAP_ERR_UNKNOWN";
}

const char *cap_error_text(int e)
{
    e = e < 0 ? -e : e;
    return (unsigned)e < CAP_ERROR_COUNT ? error_texts[e] : "unknown error";
}

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
