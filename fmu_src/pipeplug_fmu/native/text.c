/* Text helpers of the loader: growing strings, values shown in log lines, UTF-8, a hash, strings
 * the slave can read. */
#include "loader.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void text_add(Text *t, const char *s, size_t n) {
    if (t->len + n + 1 > t->cap) {
        size_t cap = (t->len + n + 1) * 2;
        char *data = realloc(t->data, cap);
        if (data == NULL) return;
        t->data = data, t->cap = cap;
    }
    memcpy(t->data + t->len, s, n);
    t->len += n;
    t->data[t->len] = '\0';
}

void text_printf(Text *t, const char *format, ...) {
    char buffer[4096];
    va_list ap;
    va_start(ap, format);
    int n = vsnprintf(buffer, sizeof buffer, format, ap);
    va_end(ap);
    if (n < 0) return;
    size_t len = (size_t)n < sizeof buffer ? (size_t)n : sizeof buffer - 1;
    for (size_t i = 0; i < len; i++) {
        text_add(t, &buffer[i], 1);
        if (ESCAPE_PERCENT && buffer[i] == '%') text_add(t, "%", 1);
    }
}

void text_shown(Text *t, const char *s, size_t n, size_t max) {
    if (s == NULL) {
        text_add(t, "NULL", 4);
        return;
    }
    text_add(t, "'", 1);
    for (size_t i = 0; i < n && i < max; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c == '%') text_add(t, "%%", ESCAPE_PERCENT ? 2 : 1);   /* FMI 2.0 hosts printf */
        else if (c == '\'' || c == '\\') text_printf(t, "\\%c", c);
        else if (c >= 0x20 && c < 0x7f) text_add(t, (const char *)&c, 1);
        else text_printf(t, "\\x%02x", c);
    }
    text_add(t, "'", 1);
    if (n > max) text_printf(t, "... (%zu bytes)", n);
}

/* The length of the UTF-8 sequence starting at `s`, 0 if it is not a valid one. */
static size_t utf8_sequence(const unsigned char *s) {
    if (s[0] < 0x80) return 1;
    size_t n = s[0] >= 0xf0 ? 4 : s[0] >= 0xe0 ? 3 : s[0] >= 0xc2 ? 2 : 0;
    if (n == 0 || s[0] > 0xf4) return 0;
    for (size_t i = 1; i < n; i++)
        if ((s[i] & 0xc0) != 0x80) return 0;
    if (n == 3 && ((s[0] == 0xe0 && s[1] < 0xa0) || (s[0] == 0xed && s[1] >= 0xa0)))
        return 0;                                      /* overlong, or a surrogate */
    if (n == 4 && ((s[0] == 0xf0 && s[1] < 0x90) || (s[0] == 0xf4 && s[1] >= 0x90)))
        return 0;                                      /* overlong, or above U+10FFFF */
    return n;
}

int utf8_valid(const char *s) {
    const unsigned char *p = (const unsigned char *)s;
    while (*p) {
        size_t n = utf8_sequence(p);
        if (n == 0) return 0;
        p += n;
    }
    return 1;
}

uint64_t fnv1a(uint64_t hash, const void *data, size_t n) {
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) hash = (hash ^ p[i]) * 0x100000001b3ULL;
    return hash;
}

/* A copy of `s` that the slave can read (see readable_strings); NULL only when out of memory. */
static const char *readable(const char *s) {
    if (s == NULL || utf8_valid(s)) return s;
    size_t n = strlen(s), shown = n < 1024 ? n : 1024;
    char *copy = malloc(sizeof NOT_UTF8 + 2 * shown + 1);
    if (copy == NULL) return NULL;
    size_t at = (size_t)sprintf(copy, "%s", NOT_UTF8);
    for (size_t i = 0; i < shown; i++) at += (size_t)sprintf(copy + at, "%02x", (unsigned char)s[i]);
    return copy;
}

const char **readable_strings(const char *const values[], size_t n, size_t offset,
                              size_t slots) {
    const char **given = calloc(slots, sizeof *given);
    for (size_t i = 0; given != NULL && i < n; i++) {
        given[offset + i] = readable(values[i]);
        if (values[i] != NULL && given[offset + i] == NULL) {
            readable_strings_free(given, values, i, offset);
            return NULL;
        }
    }
    return given;
}

void readable_strings_free(const char **given, const char *const values[], size_t n,
                           size_t offset) {
    for (size_t i = 0; given != NULL && i < n; i++)
        if (given[offset + i] != values[i]) free((char *)given[offset + i]);
    free(given);
}
