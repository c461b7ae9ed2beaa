/* Lookup in the table kernels/embed.cmake generates. */
#include <string.h>

#include "kernels.h"

const char *kernels_source(const char *name)
{
    for (int i = 0; name && kernels_files[i].name; i++)
        if (strcmp(kernels_files[i].name, name) == 0)
            return kernels_files[i].text;
    return NULL;
}
