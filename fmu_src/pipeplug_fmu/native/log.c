/* Lines to the host, shared by both FMI versions' loaders (loader.c, loader3.c).
 *
 * pythonfmu's logging stays on, into a logger of the loader's that keeps each line
 * (keep_line); finish() gives them to the host after pythonfmu's call has returned (never while
 * a Python exception is pending), each with a category of modelDescription.xml's
 * LogCategories. Errors, discards and warnings always reach the host; other lines only with
 * debug logging on (and in the categories of SetDebugLogging, which the loader handles itself).
 * A refusal of the slave (pythonfmu's Fatal line holding REFUSAL) is given to the host as its
 * own line with Error.
 */
#include "loader.h"

#include <stdlib.h>
#include <string.h>

static const char *const CATEGORIES[] = {"logAll", "logStatusWarning", "logStatusDiscard",
                                         "logStatusError", "logStatusFatal"};
#define N_CATEGORIES (sizeof CATEGORIES / sizeof *CATEGORIES)

int category_index(const char *name) {
    for (size_t i = 0; name != NULL && i < N_CATEGORIES; i++)
        if (strcmp(name, CATEGORIES[i]) == 0) return (int)i;
    return -1;
}

const char *category_of(const char *given, Status status) {
    int own = category_index(given);
    if (own >= 0) return CATEGORIES[own];
    return CATEGORIES[status >= ST_WARNING && status <= ST_FATAL ? status : 0];
}

void keep_line(Instance *in, Status status, const char *category, const char *message) {
    if (in->n_lines == in->cap_lines) {
        size_t cap = in->cap_lines ? 2 * in->cap_lines : 4;
        Line *lines = realloc(in->lines, cap * sizeof *lines);
        if (lines == NULL) return;
        in->lines = lines, in->cap_lines = cap;
    }
    in->lines[in->n_lines++] = (Line){status, category ? strdup(category) : NULL,
                                      strdup(message ? message : "")};
}

/* Whether a line of this status and category reaches the host (see the header). */
static int shown(const Instance *in, Status status, const char *category) {
    if (status >= ST_WARNING && status <= ST_FATAL) return 1;
    int bit = category_index(category);
    return in->logging_on && (in->categories == 0 || (in->categories & 1u)
                              || (bit >= 0 && (in->categories >> bit) & 1u));
}

void host_log(const Instance *in, Status status, const char *message) {
    to_host(in, status, category_of(NULL, status), message);
}

Status refuse(Instance *in, Text *why) {
    host_log(in, ST_ERROR, why->data ? why->data : MODEL ": refused");
    free(why->data);
    in->failed = 1;
    return ST_ERROR;
}

Status finish(Instance *in, Status status) {
    int refused = 0;
    for (size_t i = 0; i < in->n_lines; i++) {
        Line *line = &in->lines[i];
        const char *message = line->message, *refusal = strstr(message, REFUSAL);
        if (line->status == ST_FATAL && refusal != NULL) {
            line->status = ST_ERROR, message = refusal + strlen(REFUSAL), refused = 1;
            free(line->category);
            line->category = NULL;
        }
        const char *category = category_of(line->category, line->status);
        if (shown(in, line->status, category)) to_host(in, line->status, category, message);
        free(line->category), free(line->message);
    }
    in->n_lines = 0;
    if (refused && status == ST_FATAL) status = ST_ERROR;
    if (status == ST_ERROR || status == ST_FATAL) in->failed = 1;
    return status;
}
