/* The words of mirror_error (mirror.h): one list makes the enum and these. */
#include "mirror.h"
#include "tryon_errors.h"

TRYON_ERROR_WORDS(MIRROR_ERROR_LIST, MIRROR_ERROR_COUNT, mirror_error_name, mirror_error_text,
                  "MIRROR_ERR_UNKNOWN")
