/* The words of mirror_error (mirror.h): one list makes the enum and these. */
#include "mirror.h"

#define MIRROR_ERROR_NAME(id, text) #id,
#define MIRROR_ERROR_TEXT(id, text) text,
static const char *const error_names[] = {MIRROR_ERROR_LIST(MIRROR_ERROR_NAME)};
static const char *const error_texts[] = {MIRROR_ERROR_LIST(MIRROR_ERROR_TEXT)};
#undef MIRROR_ERROR_NAME
#undef MIRROR_ERROR_TEXT

const char *mirror_error_name(int e)
{
    e = e < 0 ? -e : e;
    return e < MIRROR_ERROR_COUNT ? error_names[e] : "MIRROR_ERR_UNKNOWN";
}

const char *mirror_error_text(int e)
{
    e = e < 0 ? -e : e;
    return e < MIRROR_ERROR_COUNT ? error_texts[e] : "unknown error";
}
