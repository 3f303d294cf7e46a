/* What both versions' loaders (loader.c, loader3.c) do alike: the checks of a call and their
 * one-line refusals, the instance's name and memory, and the calls that differ only in the
 * version's names and types (fmi2FreeInstance and fmi3FreeInstance, ...; the FMU-state calls
 * are in states.c).
 */
#include "loader.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* Refusals ------------------------------------------------------------------------------------ */
Status refuse_after_error(Instance *in, const char *call) {
    Text why = {0};
    text_printf(&why, "%s is not allowed after an error; allowed: " STRING_OF(STATE_SET) ", "
                FMI "Reset, " FMI "Terminate, " FMI "FreeInstance", call);
    return refuse(in, &why);
}

Status refuse_null(Instance *in, const char *call, const char *name, size_t n) {
    Text why = {0};
    if (n) text_printf(&why, NULL_ARRAY_FORMAT, name, n, call);
    else text_printf(&why, "%s = NULL is not allowed in %s; allowed: a pointer to a result",
                     name, call);
    return refuse(in, &why);
}

Status refuse_count(Instance *in, const char *call, const char *name, size_t n) {
    Text why = {0};
    text_printf(&why, "%s = %zu is not allowed in %s; allowed: <= %d", name, n, call, MAX_COUNT);
    return refuse(in, &why);
}

/* Instances ---------------------------------------------------------------------------------- */
int name_refusal(const char *name, Text *why) {
    if (name == NULL) {
        text_printf(why, "instanceName = NULL is not allowed; allowed: a string (" FMI_TITLE
                    ": the instance's name)");
    } else if (!utf8_valid(name)) {
        text_printf(why, "instanceName = ");
        text_shown(why, name, strlen(name), 200);
        text_printf(why, " is not allowed; allowed: UTF-8 text");
    } else {
        return 0;
    }
    return -1;
}

int token_refusal(const char *token, Text *why) {
    if (token != NULL && strcmp(token, TOKEN) == 0) return 0;
    text_printf(why, TOKEN_ARGUMENT " = ");
    text_shown(why, token, token ? strlen(token) : 0, 100);
    text_printf(why, " is not allowed; allowed: \"%s\" (the " TOKEN_ATTRIBUTE " of this "
                MODEL "'s modelDescription.xml: the host read another FMU's)", TOKEN);
    return -1;
}

void instance_free_memory(Instance *in) {
    free(in->lines), free(in->name), free(in);
}

void instance_bury(Instance *in) {
    free(in->lines), free(in->name);
    *in = (Instance){0};
    in->freed = 1;
}

Instance *instance_made(Instance *in) {
    if (in->inner != NULL) return in;
    instance_free_memory(in);
    return NULL;
}

/* The calls alike ---------------------------------------------------------------------------- */
EXPORT void FMI_FUNCTION(FreeInstance)(void *c) {
    Instance *in = c;
    if (GONE(in)) return;
    states_of_instance_free(in);
    inner.FMI_FUNCTION(FreeInstance)(in->inner);
    finish(in, ST_OK);
    instance_bury(in);
}

EXPORT Status FMI_FUNCTION(SetDebugLogging)(void *c, Boolean on, size_t n,
                                            const char *const categories[]) {
    Instance *in = c;
    if (GONE(in)) return ST_ERROR;
    if (n > 0 && categories == NULL)
        return refuse_null(in, FMI "SetDebugLogging", "categories", n);
    unsigned mask = 0;
    for (size_t i = 0; i < n; i++) {
        int bit = category_index(categories[i]);
        if (bit < 0) {
            Text why = {0};
            text_printf(&why, "categories[%zu] = ", i);
            text_shown(&why, categories[i], categories[i] ? strlen(categories[i]) : 0, 100);
            text_printf(&why, " is not allowed; allowed: " CATEGORY_NAMES);
            return refuse(in, &why);
        }
        mask |= 1u << bit;
    }
    in->logging_on = on == 1, in->categories = mask;
    return ST_OK;
}

EXPORT Status FMI_FUNCTION(Terminate)(void *c) {
    Instance *in = c;
    if (GONE(in)) return ST_ERROR;
    if (in->failed) return ST_OK;            /* allowed after an error: nothing more to do */
    NOT_CONFIGURING(FMI "Terminate");
    return finish(in, inner.FMI_FUNCTION(Terminate)(in->inner));
}
