/* Private to capture/. */
#ifndef TRYON_CAP_PRIVATE_H
#define TRYON_CAP_PRIVATE_H

#include "capture.h"

extern const cap_source_api cap_freenect_api;
extern const cap_source_api cap_openni2_api;

#endif
