/* The one error convention's plumbing (docs/building.md, "Conventions: errors"), written once for
 * every library: a library lists its errors as an X-macro, X(ID, "text"), whose order is the
 * enum's, and instantiates the words and, where it has a reject record, its setter here. */
#ifndef TRYON_ERRORS_H
#define TRYON_ERRORS_H

#include <stdarg.h>
#include <stdio.h>

#define TRYON_ERROR_NAME_ENTRY(id, text) #id,
#define TRYON_ERROR_TEXT_ENTRY(id, text) text,

/* Entry |e| of a table of n (a code either way round: e or -e, INT_MIN included), or unknown. */
static inline const char *tryon_error_entry(const char *const *table, unsigned n, int e,
                                            const char *unknown)
{
    unsigned u = e < 0 ? 0u - (unsigned)e : (unsigned)e;
    return u < n ? table[u] : unknown;
}

/* Defines the file's tables error_names / error_texts and `const char *NAME_FN(int e)` and
 * `const char *TEXT_FN(int e)` from LIST (COUNT entries). */
#define TRYON_ERROR_WORDS(LIST, COUNT, NAME_FN, TEXT_FN, UNKNOWN_NAME)                             \
    static const char *const error_names[] = {LIST(TRYON_ERROR_NAME_ENTRY)};                       \
    static const char *const error_texts[] = {LIST(TRYON_ERROR_TEXT_ENTRY)};                       \
    const char *NAME_FN(int e)                                                                     \
    {                                                                                              \
        return tryon_error_entry(error_names, (unsigned)(COUNT), e, UNKNOWN_NAME);                 \
    }                                                                                              \
    const char *TEXT_FN(int e)                                                                     \
    {                                                                                              \
        return tryon_error_entry(error_texts, (unsigned)(COUNT), e, "unknown error");              \
    }

/* Defines `int FN(REJECT *why, ERROR code, const char *fmt, ...)`: when why is given, its code
 * and its detail (what and where, printf-style); returns -code, the convention's failure. */
#define TRYON_REJECT_SETTER(FN, REJECT, ERROR)                                                     \
    int FN(REJECT *why, ERROR code, const char *fmt, ...)                                          \
    {                                                                                              \
        if (why) {                                                                                 \
            why->code = code;                                                                      \
            va_list ap;                                                                            \
            va_start(ap, fmt);                                                                     \
            vsnprintf(why->detail, sizeof why->detail, fmt, ap);                                   \
            va_end(ap);                                                                            \
        }                                                                                          \
        return -(int)code;                                                                         \
    }

#endif
