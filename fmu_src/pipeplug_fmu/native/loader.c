/* The FMI 2.0 binary, on linux64, of the project's pythonfmu FMUs (PipePlug.fmu, Hammer.fmu).
 *
 * Compiled once per FMU with -DMODEL_IDENTIFIER=<its modelIdentifier> (say PipePlug) and
 * -DFMI_VERSION=2, and shipped as binaries/linux64/PipePlug.so; every name below that belongs to
 * one FMU derives from it. The parts it shares with the FMI 3.0 loader (loader3.c) are the other
 * sources: log.c (P1, P3 below), calls.c (the checks of every call, fmi2FreeInstance,
 * fmi2SetDebugLogging, fmi2Terminate), python.c, inner.c, resources.c, states.c (the
 * FMU-state calls) and text.c.
 *
 * pythonfmu's binary (shipped beside this one as PipePlug_pythonfmu.so) runs the slave in a
 * Python interpreter that must already be in the process: it is not linked to libpython. This
 * loader exports every fmi2 function and, at the first fmi2Instantiate, makes a Python visible
 * (python.c):
 *
 *   1. a Python already in the process (a Python host): that interpreter, never a second one;
 *   2. else the python executable named by PIPEPLUG_PYTHON (>= 3.10 with numpy);
 *   3. else python3 on PATH, if it has numpy.
 *
 * When no usable Python is found, fmi2Instantiate logs one line saying what to set and returns
 * NULL. Every call is then forwarded to pythonfmu's binary, which does the pythonfmu 0.7
 * workarounds of pipeplug_fmu/pythonfmu07.py marked "loader":
 *
 * - P1, P3: pythonfmu's logging stays on, into a logger of this loader's; the lines are given to
 *   the host after pythonfmu's call has returned (never while a Python exception is pending),
 *   each with a category of modelDescription.xml's LogCategories. Errors, discards and warnings
 *   always reach the host; other lines only with debug logging on (and in the categories of
 *   fmi2SetDebugLogging, which the loader handles itself). A refusal of the slave (pythonfmu's
 *   fmi2Fatal line holding REFUSAL) is given to the host as its own line with fmi2Error.
 * - After a call returned fmi2Error (or fmi2Fatal), the instance accepts fmi2SetFMUstate,
 *   fmi2Reset, fmi2Terminate (fmi2OK, nothing else done) and fmi2FreeInstance, and the
 *   bookkeeping calls fmi2FreeFMUstate and fmi2SetDebugLogging; any other call returns fmi2Error
 *   with one short line. A successful fmi2SetFMUstate or fmi2Reset ends this.
 * - P7, P8, P9: arguments pythonfmu would crash on are refused with one line (fmi2Error, or NULL
 *   from fmi2Instantiate): a NULL instance name or one that is not UTF-8, a model-exchange
 *   instance, a resource location that does not hold this build's resources (resources.c),
 *   NULL arrays of n > 0 elements, NULL pointers for results, unknown FMU states and malformed
 *   serialized ones (states.c). A String value that is not UTF-8 reaches the slave as NOT_UTF8
 *   and its bytes in hex, so that the slave refuses it naming the variable.
 * - An fmuGUID that is not this build's (the host read another modelDescription.xml) is
 *   refused like them; a call through an instance already freed returns fmi2Error (GONE).
 *
 * The exit guard against pythonfmu's double release of its interpreter at exit is in inner.c.
 */
#include "loader.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* Logging (the rest is log.c) ------------------------------------------------------------- */
static void buffer_line(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status,
                        fmi2String category, fmi2String message, ...) {
    (void)name;
    keep_line(env, status, category, message);
}

void to_host(const Instance *in, fmi2Status status, const char *category, const char *message) {
    if (in->host.logger != NULL)
        in->host.logger(in->host.componentEnvironment, in->name, status, category, message);
}

/* Instantiation ------------------------------------------------------------------------------- */
/* A line for a host that has no instance yet. */
static void early_log(const fmi2CallbackFunctions *f, const char *name, Text *why) {
    if (f->logger != NULL)
        f->logger(f->componentEnvironment, name, fmi2Error, "logStatusError",
                  why->data ? why->data : MODEL ": fmi2Instantiate refused");
    free(why->data);
}

/* What makes the arguments unusable, as one line in `why`; 0 when they are usable. */
static int instantiate_refusal(fmi2String name, fmi2Type type, Text *why) {
    if (name_refusal(name, why) != 0) return -1;
    if (type == fmi2CoSimulation) return 0;
    text_printf(why, "fmuType = %d is not allowed; allowed: %d (fmi2CoSimulation; " MODEL
                " has no model exchange)", (int)type, (int)fmi2CoSimulation);
    return -1;
}

EXPORT const char *fmi2GetTypesPlatform(void) { return "default"; }
EXPORT const char *fmi2GetVersion(void) { return "2.0"; }

EXPORT fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                                     fmi2String resources, const fmi2CallbackFunctions *functions,
                                     fmi2Boolean visible, fmi2Boolean logging_on) {
    if (functions == NULL) return NULL;
    Text why = {0};
    char uri[MAX_PATH_LENGTH + 64];
    if (instantiate_refusal(name, type, &why) != 0 || token_refusal(guid, &why) != 0
            || resource_uri(resources, uri, sizeof uri, &why) != 0) {
        early_log(functions, name && utf8_valid(name) ? name : "", &why);
        return NULL;
    }
    Instance *in = calloc(1, sizeof *in);
    if (in == NULL) return NULL;
    in->host = *functions;
    in->name = strdup(name);
    in->logging_on = logging_on == 1;
    in->mine = (fmi2CallbackFunctions){buffer_line, functions->allocateMemory,
                                        functions->freeMemory, NULL, in};
    if (inner_ready(in)) {   /* P3: pythonfmu logs everything; finish() filters for the host */
        in->inner = inner.fmi2Instantiate(name, type, guid, uri, &in->mine, visible, 1);
        finish(in, fmi2OK);
    }
    return instance_made(in);
}

/* Arrays of `n` elements given (`a` and `b`; the checks of every call are in calls.c). */
#define ARRAYS(call, a, b, n) \
    if ((n) > 0 && (a) == NULL) return refuse_null(in, call, #a, n); \
    if ((n) > 0 && (b) == NULL) return refuse_null(in, call, #b, n); \
    if ((n) > (size_t)MAX_COUNT) return refuse_count(in, call, "n", n)

/* The fmi2 functions (fmi2FreeInstance, fmi2SetDebugLogging, fmi2Terminate: calls.c) -------- */

EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolerance_defined,
                                      fmi2Real tolerance, fmi2Real start,
                                      fmi2Boolean stop_defined, fmi2Real stop) {
    CHECKED("fmi2SetupExperiment");
    return finish(in, inner.fmi2SetupExperiment(in->inner, tolerance_defined, tolerance, start,
                                                stop_defined, stop));
}

EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    CHECKED("fmi2EnterInitializationMode");
    return finish(in, inner.fmi2EnterInitializationMode(in->inner));
}

EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    CHECKED("fmi2ExitInitializationMode");
    return finish(in, inner.fmi2ExitInitializationMode(in->inner));
}

EXPORT fmi2Status fmi2Reset(fmi2Component c) {
    Instance *in = c;
    if (GONE(in)) return fmi2Error;
    in->failed = 0;                          /* finish() sets it again if the reset fails */
    return finish(in, inner.fmi2Reset(in->inner));
}

#define GETTER_SETTER(name, type) \
    EXPORT fmi2Status name(fmi2Component c, const fmi2ValueReference vr[], size_t n, \
                           type value[]) { \
        CHECKED(#name); \
        ARRAYS(#name, vr, value, n); \
        return finish(in, inner.name(in->inner, vr, n, value)); \
    }
GETTER_SETTER(fmi2GetReal, fmi2Real)
GETTER_SETTER(fmi2GetInteger, fmi2Integer)
GETTER_SETTER(fmi2GetBoolean, fmi2Boolean)
GETTER_SETTER(fmi2GetString, fmi2String)
GETTER_SETTER(fmi2SetReal, const fmi2Real)
GETTER_SETTER(fmi2SetInteger, const fmi2Integer)
GETTER_SETTER(fmi2SetBoolean, const fmi2Boolean)

/* A String that is not UTF-8 reaches the slave as NOT_UTF8 and its bytes in hex (P7). */
EXPORT fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                const fmi2String value[]) {
    CHECKED("fmi2SetString");
    ARRAYS("fmi2SetString", vr, value, n);
    const char **given = readable_strings(value, n, 0, n + 1);
    if (given == NULL)
        return refuse_null(in, "fmi2SetString", "a copy of value (out of memory)", n);
    fmi2Status status = finish(in, inner.fmi2SetString(in->inner, vr, n, given));
    readable_strings_free(given, value, n, 0);
    return status;
}

/* The FMU-state calls are in states.c. */
/* Calls pythonfmu answers with fmi2Error itself (no Python involved). */
EXPORT fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[],
                                               size_t nu, const fmi2ValueReference z[],
                                               size_t nz, const fmi2Real du[], fmi2Real dz[]) {
    CHECKED("fmi2GetDirectionalDerivative");
    return finish(in, inner.fmi2GetDirectionalDerivative(in->inner, u, nu, z, nz, du, dz));
}

EXPORT fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                              size_t n, const fmi2Integer order[],
                                              const fmi2Real values[]) {
    CHECKED("fmi2SetRealInputDerivatives");
    return finish(in, inner.fmi2SetRealInputDerivatives(in->inner, vr, n, order, values));
}

EXPORT fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                               size_t n, const fmi2Integer order[],
                                               fmi2Real values[]) {
    CHECKED("fmi2GetRealOutputDerivatives");
    return finish(in, inner.fmi2GetRealOutputDerivatives(in->inner, vr, n, order, values));
}

EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean no_set_prior) {
    CHECKED("fmi2DoStep");
    return finish(in, inner.fmi2DoStep(in->inner, t, h, no_set_prior));
}

EXPORT fmi2Status fmi2CancelStep(fmi2Component c) {
    CHECKED("fmi2CancelStep");
    return finish(in, inner.fmi2CancelStep(in->inner));
}

#define STATUS_QUERY(name, type) \
    EXPORT fmi2Status name(fmi2Component c, const fmi2StatusKind kind, type *value) { \
        CHECKED(#name); \
        if (value == NULL) return refuse_null(in, #name, "value", 0); \
        return finish(in, inner.name(in->inner, kind, value)); \
    }
STATUS_QUERY(fmi2GetStatus, fmi2Status)
STATUS_QUERY(fmi2GetRealStatus, fmi2Real)
STATUS_QUERY(fmi2GetIntegerStatus, fmi2Integer)
STATUS_QUERY(fmi2GetBooleanStatus, fmi2Boolean)
STATUS_QUERY(fmi2GetStringStatus, fmi2String)
