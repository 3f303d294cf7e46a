/* Shared declarations of the FMUs' linux64 loaders (see loader.c for what the FMI 2.0 one
 * does, loader3.c for the FMI 3.0 one).
 *
 * Every source is compiled with -DMODEL_IDENTIFIER=<the FMU's modelIdentifier>,
 * -DFMI_VERSION=2 or 3 and -fvisibility=hidden: only the FMI functions (EXPORT) leave the
 * binary. The version's header (fmi2.h, fmi3.h) gives the shared sources its types (Status,
 * FmuState, Byte), pythonfmu's functions (INNER_FUNCTIONS) and the names its lines use.
 */
#ifndef PIPEPLUG_LOADER_H
#define PIPEPLUG_LOADER_H

#define _GNU_SOURCE
#include <stddef.h>
#include <stdint.h>

#ifndef FMI_VERSION
#error "compile with -DFMI_VERSION=2 or 3"
#endif
#if FMI_VERSION == 3
#include "fmi3.h"
#else
#include "fmi2.h"
#endif

#define EXPORT __attribute__((visibility("default")))
#ifndef MODEL_IDENTIFIER
#error "compile with -DMODEL_IDENTIFIER=<the FMU's modelIdentifier>"
#endif
#ifndef TOKEN
#error "compile with -DTOKEN='\"<modelDescription.xml's guid or instantiationToken>\"'"
#endif
#define STRING_OF_(x) #x
#define STRING_OF(x) STRING_OF_(x)
#define JOINED_(a, b) a##b
#define JOINED(a, b) JOINED_(a, b)
#define MODEL STRING_OF(MODEL_IDENTIFIER)  /* "PipePlug": the FMU's name in log lines */
#define FMI_FUNCTION(name) JOINED(FMI_PREFIX, name)   /* the version's call: fmi2Reset, ... */
#define INNER_BINARY MODEL "_pythonfmu.so"
#define PYTHON_VARIABLE "PIPEPLUG_PYTHON"   /* one variable for all of the project's FMUs */
#define TIMEOUT_VARIABLE "PIPEPLUG_PYTHON_TIMEOUT"
#define REFUSAL MODEL "Refusal: "          /* repr of the slave's refusals (pythonfmu07 P1) */
#define NOT_UTF8 "\x1bnot UTF-8: "         /* a String that is not UTF-8 (pythonfmu07 P7) */
#define MAX_PATH_LENGTH 4096               /* of a resource folder, decoded */

#define DECLARE_POINTER(ret, name, args) ret (*name) args;
typedef struct { INNER_FUNCTIONS(DECLARE_POINTER) } InnerFunctions;
extern InnerFunctions inner;               /* pythonfmu's binary, once loaded */

/* Text (text.c) ----------------------------------------------------------------------------- */
typedef struct { char *data; size_t len, cap; } Text;

void text_add(Text *t, const char *s, size_t n);
/* Append printf-style text; with ESCAPE_PERCENT (FMI 2.0: hosts printf the line) every '%'
 * of the result is doubled. */
void text_printf(Text *t, const char *format, ...) __attribute__((format(printf, 2, 3)));
/* Append `s` (n bytes) quoted, printable ASCII as is, other bytes as \xNN, at most `max`
 * bytes of it shown ("... (N bytes)" after them); "NULL" for a NULL `s`. */
void text_shown(Text *t, const char *s, size_t n, size_t max);
/* 1 when the NUL-terminated `s` is valid UTF-8 (no overlong forms, surrogates or > U+10FFFF). */
int utf8_valid(const char *s);
/* FNV-1a, 64 bits, of `n` bytes, continuing from `hash` (start: FNV_START). */
#define FNV_START 0xcbf29ce484222325ULL
uint64_t fnv1a(uint64_t hash, const void *data, size_t n);
/* Strings the slave can read (P7): `slots` of them, NULL but for `values` (n of them) from
 * `offset` on, each as it is when it is UTF-8 (or NULL, which the slave sees as None), else a
 * copy: NOT_UTF8 and its bytes in hex. NULL when out of memory. */
const char **readable_strings(const char *const values[], size_t n, size_t offset, size_t slots);
/* Free `given` of readable_strings (NULL: nothing) and the copies it made. */
void readable_strings_free(const char **given, const char *const values[], size_t n,
                           size_t offset);

/* Instances (log.c; their FMI functions in loader.c, loader3.c, calls.c, states.c) ---------- */
typedef struct { Status status; char *category, *message; } Line;

typedef struct Instance {
    void *inner;                       /* pythonfmu's instance */
    HOST_FIELDS                        /* the host's logger and environment (fmi2.h, fmi3.h) */
    char *name;
    int logging_on;                    /* the host's debug logging (SetDebugLogging) */
    unsigned categories;               /* its categories, a bit per CATEGORIES entry; 0: all */
    int failed;                        /* an Error or Fatal was returned */
    int configuring;                   /* FMI 3.0: in configuration mode */
    int initialized;                   /* FMI 3.0: EnterInitializationMode done (until Reset) */
    int freed;                         /* FreeInstance done: kept as a marker (below) */
    Line *lines;                       /* logged during the current call */
    size_t n_lines, cap_lines;
} Instance;

/* Give one line to the host's logger, as its version does (loader.c, loader3.c). */
void to_host(const Instance *in, Status status, const char *category, const char *message);
/* Keep a line pythonfmu logged during a call, for finish() (log.c). */
void keep_line(Instance *in, Status status, const char *category, const char *message);
/* The index in CATEGORIES of `name`, or -1; the category of a line of `status` with its own
 * `given` one (its own if modelDescription.xml lists it, else its status's). */
int category_index(const char *name);
const char *category_of(const char *given, Status status);
#define CATEGORY_NAMES "logAll, logStatusWarning, logStatusDiscard, logStatusError, " \
                       "logStatusFatal"
/* Log one line of the loader's own to the host: status, category of that status, text. */
void host_log(const Instance *in, Status status, const char *message);
/* Log `why` with an Error, mark the instance failed; the Error status. */
Status refuse(Instance *in, Text *why);
/* Give the buffered lines of `in` to the host; the status the host sees. */
Status finish(Instance *in, Status status);

/* Checks of every call and the calls both versions have alike (calls.c) --------------------- */
/* No instance to call: NULL, or freed. FreeInstance frees all an instance holds but its own
 * few bytes, which stay marked freed and are never reused: a host that calls an instance it
 * freed (a second FreeInstance, a getter in its clean-up) is refused with the Error status, or
 * ignored for FreeInstance, instead of reading freed memory. No line: the logger and its
 * environment belonged to the freed instance. */
#define GONE(in) ((in) == NULL || (in)->freed)
/* The checks before most calls: an instance, not after an error (the calls allowed then, such
 * as fmi2SetFMUstate, check less). */
#define CHECKED(call) \
    Instance *in = c; \
    if (GONE(in)) return ST_ERROR; \
    if (in->failed) return refuse_after_error(in, call)
Status refuse_after_error(Instance *in, const char *call);
/* Refuse a NULL pointer argument `name` of `call` (an array of n elements when n > 0). */
Status refuse_null(Instance *in, const char *call, const char *name, size_t n);
/* Refuse `n` elements of `name`, more than MAX_COUNT. */
Status refuse_count(Instance *in, const char *call, const char *name, size_t n);
/* What makes the instance name `name` unusable, as one line in `why`; 0 when it is usable. */
int name_refusal(const char *name, Text *why);
/* What makes the host's `token` (fmuGUID, instantiationToken) not this build's, as one line in
 * `why`; 0 when it is TOKEN, the one in this build's modelDescription.xml. */
int token_refusal(const char *token, Text *why);
/* `in` once pythonfmu's instance is made; else NULL, `in` freed. */
Instance *instance_made(Instance *in);
/* Free `in` itself, its name and lines (not pythonfmu's instance). */
void instance_free_memory(Instance *in);
/* Free what `in` holds (its name and lines), mark it freed and keep its own memory (GONE). */
void instance_bury(Instance *in);

/* Finding a Python (python.c) -------------------------------------------------------------- */
/* Make a Python visible to pythonfmu's binary; 0 on success, else one line in `why`. */
int ensure_python(Text *why);

/* pythonfmu's binary and the exit guard (inner.c) -------------------------------------------- */
/* Make a Python visible and load pythonfmu's binary beside this one into `inner`, once per
 * process; 1 when it is loaded, else 0 after one line to the host of `in`. */
int inner_ready(const Instance *in);

/* The resource folder (resources.c) ------------------------------------------------------- */
/* The URI to give pythonfmu for the host's `location` ("file://" + a checked folder); 0 on
 * success, else one line in `why`. Also sets the build's identity (below). */
int resource_uri(const char *location, char *uri, size_t size, Text *why);
/* A hash of the FMU and build whose resources are used: modelIdentifier and slave module. */
extern uint64_t build_identity;

/* FMU states (states.c: the version's FMU-state calls) --------------------------------------- */
/* Free every state obtained through `in` (before the instance itself is freed). */
void states_of_instance_free(Instance *in);

#endif
