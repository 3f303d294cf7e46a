/* The FMI 3.0 binary, on linux64, of the project's pythonfmu3 FMUs (fmi3/PipePlug.fmu,
 * fmi3/Hammer.fmu): the FMI 2.0 loader's approach (loader.c) in front of pythonfmu3's binary.
 *
 * Compiled with -DFMI_VERSION=3 and shipped as binaries/x86_64-linux/PipePlug.so, pythonfmu3's
 * binary beside it as PipePlug_pythonfmu.so. It shares with the FMI 2.0 loader finding a Python
 * (python.c: the host's, else PIPEPLUG_PYTHON, else python3 on PATH), the exit guard
 * (inner.c: pythonfmu3 releases its interpreter twice at exit, as pythonfmu 0.7 does), the
 * resource check (resources.c), the FMU-state handles and framing (states.c) and the lines
 * (log.c: pythonfmu3's logging stays on into the loader; Errors, Discards and Warnings always
 * reach the host, other lines with debug logging on; a refusal of the slave, which pythonfmu3
 * reports as fmi3Fatal with an empty category, reaches the host as fmi3Error with its own line
 * and category), and calls.c (the checks of every call, fmi3FreeInstance, fmi3SetDebugLogging,
 * fmi3Terminate; states.c: the FMU-state calls). What it adds for FMI 3.0:
 *
 * - fmi3InstantiateCoSimulation returns NULL after one line when it cannot instantiate
 *   (arguments, resources, no Python), and refuses eventModeUsed and intermediate variables
 *   (the FMUs have neither); the host's logger gets the host's instanceEnvironment.
 * - The FMI 3.0 state machine: calls the slave sees are checked by its call sequence
 *   (pipeplug_fmu/base.py); the loader checks the rest: configuration mode (entered only from
 *   instantiated, left only from it; nothing else but getting, setting, fmi3Reset and
 *   fmi3FreeInstance in it), and refuses with one line every call the FMUs do not support
 *   (event mode, model exchange, clocks, derivatives, dependencies, types without variables),
 *   where pythonfmu3 would end the host (a C++ exception out of an extern "C" function).
 * - After a call returned fmi3Error (or fmi3Fatal), the instance accepts fmi3SetFMUState,
 *   fmi3Reset, fmi3Terminate (fmi3OK, nothing else done), fmi3FreeInstance, fmi3FreeFMUState
 *   and fmi3SetDebugLogging; any other call returns fmi3Error with one short line.
 * - Every get and set reaches the slave with COUNT_MARK, nValues and nValueReferences before
 *   the value references (fmi3.h), so that the slave refuses an nValues that is not the number
 *   of values of those variables (pythonfmu3 reads past its list and leaves a Python exception
 *   set in the host); NULL arrays and counts past a C int are refused here.
 * - startTime and stopTime of fmi3EnterInitializationMode reach the slave (EXPERIMENT_MARK),
 *   which pythonfmu3 drops.
 * - fmi3DoStep's flags (eventHandlingNeeded, terminateSimulation, earlyReturn) are set false
 *   and lastSuccessfulTime to the step's start before pythonfmu3 runs (it leaves some unset).
 */
#include "loader.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* Logging (the rest is log.c) ------------------------------------------------------------- */
static void buffer_line(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category,
                        fmi3String message) {
    keep_line(env, status, category, message);
}

void to_host(const Instance *in, fmi3Status status, const char *category, const char *message) {
    if (in->logger != NULL) in->logger(in->environment, status, category, message);
}

/* Instantiation ------------------------------------------------------------------------------ */
/* What makes the arguments unusable, as one line in `why`; 0 when they are usable. */
static int instantiate_refusal(fmi3String name, fmi3Boolean event_mode, size_t n_required,
                               Text *why) {
    if (name_refusal(name, why) != 0) {
        return -1;
    } else if (event_mode) {
        text_printf(why, "eventModeUsed = true is not allowed; allowed: false (" MODEL " has no "
                    "event mode)");
    } else if (n_required > 0) {
        text_printf(why, "nRequiredIntermediateVariables = %zu is not allowed; allowed: 0 ("
                    MODEL " provides no intermediate update)", n_required);
    } else {
        return 0;
    }
    return -1;
}

EXPORT const char *fmi3GetVersion(void) { return "3.0"; }

EXPORT fmi3Instance fmi3InstantiateCoSimulation(
        fmi3String name, fmi3String token, fmi3String resources, fmi3Boolean visible,
        fmi3Boolean logging_on, fmi3Boolean event_mode, fmi3Boolean early_return,
        const fmi3ValueReference required[], size_t n_required, fmi3InstanceEnvironment env,
        fmi3LogMessageCallback logger, fmi3IntermediateUpdateCallback intermediate) {
    (void)early_return, (void)required, (void)intermediate;  /* never returns early */
    Text why = {0};
    char uri[MAX_PATH_LENGTH + 64];
    Instance *in = calloc(1, sizeof *in);
    if (in == NULL) return NULL;
    in->environment = env, in->logger = logger;
    if (instantiate_refusal(name, event_mode, n_required, &why) != 0
            || token_refusal(token, &why) != 0
            || resource_uri(resources, uri, sizeof uri, &why) != 0) {
        refuse(in, &why);
        instance_free_memory(in);
        return NULL;
    }
    in->name = strdup(name);
    in->logging_on = logging_on;
    if (inner_ready(in)) {   /* pythonfmu3 logs everything; finish() filters for the host */
        in->inner = inner.fmi3InstantiateCoSimulation(name, token, uri, visible, true, false,
                                                      false, NULL, 0, in, buffer_line, NULL);
        finish(in, fmi3OK);
    }
    return instance_made(in);
}

/* Another kind of instance: NULL after one line. */
static fmi3Instance no_instance(fmi3InstanceEnvironment env, fmi3LogMessageCallback logger,
                                const char *kind) {
    if (logger != NULL) {
        Text why = {0};
        text_printf(&why, "%s is not allowed; allowed: fmi3InstantiateCoSimulation (" MODEL
                    " is a co-simulation FMU only)", kind);
        logger(env, fmi3Error, category_of(NULL, fmi3Error), why.data ? why.data : kind);
        free(why.data);
    }
    return NULL;
}

EXPORT fmi3Instance fmi3InstantiateModelExchange(
        fmi3String name, fmi3String token, fmi3String resources, fmi3Boolean visible,
        fmi3Boolean logging_on, fmi3InstanceEnvironment env, fmi3LogMessageCallback logger) {
    (void)name, (void)token, (void)resources, (void)visible, (void)logging_on;
    return no_instance(env, logger, "fmi3InstantiateModelExchange");
}

EXPORT fmi3Instance fmi3InstantiateScheduledExecution(
        fmi3String name, fmi3String token, fmi3String resources, fmi3Boolean visible,
        fmi3Boolean logging_on, fmi3InstanceEnvironment env, fmi3LogMessageCallback logger,
        fmi3ClockUpdateCallback clock, fmi3LockPreemptionCallback lock,
        fmi3UnlockPreemptionCallback unlock) {
    (void)name, (void)token, (void)resources, (void)visible, (void)logging_on;
    (void)clock, (void)lock, (void)unlock;
    return no_instance(env, logger, "fmi3InstantiateScheduledExecution");
}

/* Checks before forwarding (the checks of every call are in calls.c) ---------------------- */
/* A call the FMI 3.0 state machine does not allow in configuration mode (fmi3.h). */
fmi3Status refuse_configuring(Instance *in, const char *call) {
    Text why = {0};
    text_printf(&why, "%s is not allowed in configuration mode; allowed: getting and setting "
                "values, fmi3ExitConfigurationMode, fmi3Reset, fmi3FreeInstance (the FMI 3.0 "
                "state machine)", call);
    return refuse(in, &why);
}

/* A call the FMUs do not support: `allowed` says what is. */
static fmi3Status refuse_call(Instance *in, const char *call, const char *allowed) {
    Text why = {0};
    text_printf(&why, "%s is not allowed; allowed: %s", call, allowed);
    return refuse(in, &why);
}

/* Arrays of value references and values given, counts a C int (with the header) holds. */
#define ARRAYS(call, vr, nvr, values, n) \
    if ((nvr) > 0 && (vr) == NULL) return refuse_null(in, call, "valueReferences", nvr); \
    if ((n) > 0 && (values) == NULL) return refuse_null(in, call, "values", n); \
    if ((nvr) > (size_t)MAX_COUNT) return refuse_count(in, call, "nValueReferences", nvr); \
    if ((n) > (size_t)MAX_COUNT) return refuse_count(in, call, "nValues", n)

/* The value references pythonfmu3 gets: the header (fmi3.h), the host's, then `pad` more
 * COUNT_MARKs; NULL when out of memory. */
static fmi3ValueReference *with_header(const fmi3ValueReference vr[], size_t nvr, size_t n,
                                       size_t pad) {
    fmi3ValueReference *all = malloc((HEADER_VRS + nvr + pad) * sizeof *all);
    if (all == NULL) return NULL;
    all[0] = COUNT_MARK, all[1] = (fmi3ValueReference)n, all[2] = (fmi3ValueReference)nvr;
    if (nvr) memcpy(all + HEADER_VRS, vr, nvr * sizeof *vr);
    for (size_t i = 0; i < pad; i++) all[HEADER_VRS + nvr + i] = COUNT_MARK;
    return all;
}

static fmi3Status out_of_memory(Instance *in, const char *call) {
    Text why = {0};
    text_printf(&why, "%s cannot be done: out of memory", call);
    return refuse(in, &why);
}

/* The fmi3 functions (fmi3FreeInstance, fmi3SetDebugLogging, fmi3Terminate: calls.c) ------- */
EXPORT fmi3Status fmi3EnterConfigurationMode(fmi3Instance c) {
    CHECKED("fmi3EnterConfigurationMode");
    if (in->configuring || in->initialized)
        return refuse_call(in, "fmi3EnterConfigurationMode", in->configuring
            ? "once (the instance is in configuration mode)"
            : "in instantiated only (" MODEL "'s structural parameters are fixed; the FMI 3.0 "
              "state machine)");
    in->configuring = 1;
    return fmi3OK;
}

EXPORT fmi3Status fmi3ExitConfigurationMode(fmi3Instance c) {
    CHECKED("fmi3ExitConfigurationMode");
    if (!in->configuring)
        return refuse_call(in, "fmi3ExitConfigurationMode", "in configuration mode only (after "
                           "fmi3EnterConfigurationMode; the FMI 3.0 state machine)");
    in->configuring = 0;
    return fmi3OK;
}

EXPORT fmi3Status fmi3EnterInitializationMode(fmi3Instance c, fmi3Boolean tolerance_defined,
                                              fmi3Float64 tolerance, fmi3Float64 start,
                                              fmi3Boolean stop_defined, fmi3Float64 stop) {
    CHECKED("fmi3EnterInitializationMode");
    NOT_CONFIGURING("fmi3EnterInitializationMode");
    const fmi3ValueReference experiment = EXPERIMENT_MARK;
    const fmi3Float64 times[3] = {start, stop_defined ? 1.0 : 0.0, stop_defined ? stop : 0.0};
    fmi3Status status = finish(in, inner.fmi3SetFloat64(in->inner, &experiment, 1, times, 3));
    if (status > fmi3Warning) return status;
    status = finish(in, inner.fmi3EnterInitializationMode(in->inner, tolerance_defined,
                                                          tolerance, start, stop_defined, stop));
    if (status <= fmi3Warning) in->initialized = 1;
    return status;
}

EXPORT fmi3Status fmi3ExitInitializationMode(fmi3Instance c) {
    CHECKED("fmi3ExitInitializationMode");
    NOT_CONFIGURING("fmi3ExitInitializationMode");
    return finish(in, inner.fmi3ExitInitializationMode(in->inner));
}

EXPORT fmi3Status fmi3Reset(fmi3Instance c) {
    Instance *in = c;
    if (GONE(in)) return fmi3Error;
    in->failed = 0, in->configuring = 0;     /* finish() sets failed again if the reset fails */
    fmi3Status status = finish(in, inner.fmi3Reset(in->inner));
    if (status <= fmi3Warning) in->initialized = 0;
    return status;
}

/* Getters and setters of the types the slaves have: the header before the value references. */
#define FORWARDED(name, type) \
    EXPORT fmi3Status name(fmi3Instance c, const fmi3ValueReference vr[], size_t nvr, \
                           type values[], size_t n) { \
        CHECKED(#name); \
        ARRAYS(#name, vr, nvr, values, n); \
        fmi3ValueReference *all = with_header(vr, nvr, n, 0); \
        if (all == NULL) return out_of_memory(in, #name); \
        fmi3Status status = finish(in, inner.name(in->inner, all, HEADER_VRS + nvr, values, n)); \
        free(all); \
        return status; \
    }
FORWARDED(fmi3GetFloat64, fmi3Float64)
FORWARDED(fmi3GetInt32, fmi3Int32)
FORWARDED(fmi3GetUInt64, fmi3UInt64)
FORWARDED(fmi3GetBoolean, fmi3Boolean)
FORWARDED(fmi3GetString, fmi3String)
FORWARDED(fmi3SetFloat64, const fmi3Float64)
FORWARDED(fmi3SetInt32, const fmi3Int32)
FORWARDED(fmi3SetUInt64, const fmi3UInt64)
FORWARDED(fmi3SetBoolean, const fmi3Boolean)

/* pythonfmu3 makes one String per value reference it is given and fills nValues of them: the
 * loader gives it as many value references (padded with COUNT_MARKs) as Strings, the header's
 * three Strings NULL. A String that is not UTF-8 reaches the slave as NOT_UTF8 and its bytes in
 * hex (P7). */
EXPORT fmi3Status fmi3SetString(fmi3Instance c, const fmi3ValueReference vr[], size_t nvr,
                                const fmi3String values[], size_t n) {
    CHECKED("fmi3SetString");
    ARRAYS("fmi3SetString", vr, nvr, values, n);
    size_t slots = HEADER_VRS + (nvr > n ? nvr : n);
    fmi3ValueReference *all = with_header(vr, nvr, n, slots - HEADER_VRS - nvr);
    const char **given = readable_strings(values, n, HEADER_VRS, slots);
    fmi3Status status = all != NULL && given != NULL
        ? finish(in, inner.fmi3SetString(in->inner, all, slots, given, slots))
        : out_of_memory(in, "fmi3SetString");
    readable_strings_free(given, values, n, HEADER_VRS);
    free(all);
    return status;
}

/* Getters and setters of types the slaves have no variable of (pythonfmu3 would end the host):
 * nothing to do for no value references, else the first one refused. */
static fmi3Status no_variables(Instance *in, const char *call, const char *type,
                               const fmi3ValueReference vr[], size_t nvr) {
    if (nvr == 0) return fmi3OK;
    if (vr == NULL) return refuse_null(in, call, "valueReferences", nvr);
    Text why = {0};
    text_printf(&why, "valueReference = %u is not allowed in %s; allowed: a %s variable of "
                MODEL " (it has none)", (unsigned)vr[0], call, type);
    return refuse(in, &why);
}

#define NO_VARIABLES(name, type, values_type) \
    EXPORT fmi3Status name(fmi3Instance c, const fmi3ValueReference vr[], size_t nvr, \
                           values_type values[], size_t n) { \
        (void)values, (void)n; \
        CHECKED(#name); \
        return no_variables(in, #name, type, vr, nvr); \
    }
#define NO_VARIABLES_PAIR(get, set, type, values_type) \
    NO_VARIABLES(get, type, values_type) \
    NO_VARIABLES(set, type, const values_type)
NO_VARIABLES_PAIR(fmi3GetFloat32, fmi3SetFloat32, "Float32", fmi3Float32)
NO_VARIABLES_PAIR(fmi3GetInt8, fmi3SetInt8, "Int8", fmi3Int8)
NO_VARIABLES_PAIR(fmi3GetUInt8, fmi3SetUInt8, "UInt8", fmi3UInt8)
NO_VARIABLES_PAIR(fmi3GetInt16, fmi3SetInt16, "Int16", fmi3Int16)
NO_VARIABLES_PAIR(fmi3GetUInt16, fmi3SetUInt16, "UInt16", fmi3UInt16)
NO_VARIABLES_PAIR(fmi3GetUInt32, fmi3SetUInt32, "UInt32", fmi3UInt32)
NO_VARIABLES_PAIR(fmi3GetInt64, fmi3SetInt64, "Int64", fmi3Int64)

EXPORT fmi3Status fmi3GetBinary(fmi3Instance c, const fmi3ValueReference vr[], size_t nvr,
                                size_t sizes[], fmi3Binary values[], size_t n) {
    (void)sizes, (void)values, (void)n;
    CHECKED("fmi3GetBinary");
    return no_variables(in, "fmi3GetBinary", "Binary", vr, nvr);
}

EXPORT fmi3Status fmi3SetBinary(fmi3Instance c, const fmi3ValueReference vr[], size_t nvr,
                                const size_t sizes[], const fmi3Binary values[], size_t n) {
    (void)sizes, (void)values, (void)n;
    CHECKED("fmi3SetBinary");
    return no_variables(in, "fmi3SetBinary", "Binary", vr, nvr);
}

EXPORT fmi3Status fmi3GetClock(fmi3Instance c, const fmi3ValueReference vr[], size_t nvr,
                               fmi3Clock values[]) {
    (void)values;
    CHECKED("fmi3GetClock");
    return no_variables(in, "fmi3GetClock", "Clock", vr, nvr);
}

EXPORT fmi3Status fmi3SetClock(fmi3Instance c, const fmi3ValueReference vr[], size_t nvr,
                               const fmi3Clock values[]) {
    (void)values;
    CHECKED("fmi3SetClock");
    return no_variables(in, "fmi3SetClock", "Clock", vr, nvr);
}

/* The FMU-state calls are in states.c (none in configuration mode). */

/* Stepping --------------------------------------------------------------------------------- */
EXPORT fmi3Status fmi3DoStep(fmi3Instance c, fmi3Float64 t, fmi3Float64 h,
                             fmi3Boolean no_set_prior, fmi3Boolean *event_handling_needed,
                             fmi3Boolean *terminate, fmi3Boolean *early_return,
                             fmi3Float64 *last_successful_time) {
    CHECKED("fmi3DoStep");
    NOT_CONFIGURING("fmi3DoStep");
    if (event_handling_needed == NULL)
        return refuse_null(in, "fmi3DoStep", "eventHandlingNeeded", 0);
    if (terminate == NULL) return refuse_null(in, "fmi3DoStep", "terminateSimulation", 0);
    if (early_return == NULL) return refuse_null(in, "fmi3DoStep", "earlyReturn", 0);
    if (last_successful_time == NULL)
        return refuse_null(in, "fmi3DoStep", "lastSuccessfulTime", 0);
    *event_handling_needed = false, *terminate = false, *early_return = false;
    *last_successful_time = t;
    return finish(in, inner.fmi3DoStep(in->inner, t, h, no_set_prior, event_handling_needed,
                                       terminate, early_return, last_successful_time));
}

/* Calls of what the FMUs do not have: fmi3Error with one line ------------------------------ */
#define NO_EVENT_MODE "none (" MODEL " is co-simulation without event mode)"
#define NO_MODEL_EXCHANGE "none (" MODEL " is co-simulation only)"
#define NO_CLOCKS "none (" MODEL " has no clocks)"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#define REFUSED(name, params, allowed) \
    EXPORT fmi3Status name params { \
        CHECKED(#name); \
        return refuse_call(in, #name, allowed); \
    }
REFUSED(fmi3EnterEventMode, (fmi3Instance c), NO_EVENT_MODE)
REFUSED(fmi3EnterStepMode, (fmi3Instance c), NO_EVENT_MODE)
REFUSED(fmi3UpdateDiscreteStates, (fmi3Instance c, fmi3Boolean *need_update,
        fmi3Boolean *terminate, fmi3Boolean *nominals_changed, fmi3Boolean *values_changed,
        fmi3Boolean *next_defined, fmi3Float64 *next_time), NO_EVENT_MODE)
REFUSED(fmi3EvaluateDiscreteStates, (fmi3Instance c), NO_CLOCKS)
REFUSED(fmi3EnterContinuousTimeMode, (fmi3Instance c), NO_MODEL_EXCHANGE)
REFUSED(fmi3CompletedIntegratorStep, (fmi3Instance c, fmi3Boolean no_set_prior,
        fmi3Boolean *enter_event_mode, fmi3Boolean *terminate), NO_MODEL_EXCHANGE)
REFUSED(fmi3SetTime, (fmi3Instance c, fmi3Float64 time), NO_MODEL_EXCHANGE)
REFUSED(fmi3SetContinuousStates, (fmi3Instance c, const fmi3Float64 x[], size_t n),
        NO_MODEL_EXCHANGE)
REFUSED(fmi3GetContinuousStateDerivatives, (fmi3Instance c, fmi3Float64 dx[], size_t n),
        NO_MODEL_EXCHANGE)
REFUSED(fmi3GetEventIndicators, (fmi3Instance c, fmi3Float64 z[], size_t n), NO_MODEL_EXCHANGE)
REFUSED(fmi3GetContinuousStates, (fmi3Instance c, fmi3Float64 x[], size_t n), NO_MODEL_EXCHANGE)
REFUSED(fmi3GetNominalsOfContinuousStates, (fmi3Instance c, fmi3Float64 x[], size_t n),
        NO_MODEL_EXCHANGE)
REFUSED(fmi3GetNumberOfEventIndicators, (fmi3Instance c, size_t *n), NO_MODEL_EXCHANGE)
REFUSED(fmi3GetNumberOfContinuousStates, (fmi3Instance c, size_t *n), NO_MODEL_EXCHANGE)
REFUSED(fmi3GetNumberOfVariableDependencies, (fmi3Instance c, fmi3ValueReference vr,
        size_t *n), "none (" MODEL " provides no per-element dependencies)")
REFUSED(fmi3GetVariableDependencies, (fmi3Instance c, fmi3ValueReference dependent,
        size_t dependent_elements[], fmi3ValueReference independents[],
        size_t independent_elements[], fmi3DependencyKind kinds[], size_t n),
        "none (" MODEL " provides no per-element dependencies)")
REFUSED(fmi3GetDirectionalDerivative, (fmi3Instance c, const fmi3ValueReference unknowns[],
        size_t n_unknowns, const fmi3ValueReference knowns[], size_t n_knowns,
        const fmi3Float64 seed[], size_t n_seed, fmi3Float64 sensitivity[],
        size_t n_sensitivity), "none (" MODEL " provides no directional derivatives)")
REFUSED(fmi3GetAdjointDerivative, (fmi3Instance c, const fmi3ValueReference unknowns[],
        size_t n_unknowns, const fmi3ValueReference knowns[], size_t n_knowns,
        const fmi3Float64 seed[], size_t n_seed, fmi3Float64 sensitivity[],
        size_t n_sensitivity), "none (" MODEL " provides no adjoint derivatives)")
REFUSED(fmi3GetOutputDerivatives, (fmi3Instance c, const fmi3ValueReference vr[], size_t nvr,
        const fmi3Int32 orders[], fmi3Float64 values[], size_t n),
        "none (" MODEL " provides no output derivatives)")
REFUSED(fmi3GetIntervalDecimal, (fmi3Instance c, const fmi3ValueReference vr[], size_t nvr,
        fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[]), NO_CLOCKS)
REFUSED(fmi3GetIntervalFraction, (fmi3Instance c, const fmi3ValueReference vr[], size_t nvr,
        fmi3UInt64 counters[], fmi3UInt64 resolutions[], fmi3IntervalQualifier qualifiers[]),
        NO_CLOCKS)
REFUSED(fmi3GetShiftDecimal, (fmi3Instance c, const fmi3ValueReference vr[], size_t nvr,
        fmi3Float64 shifts[]), NO_CLOCKS)
REFUSED(fmi3GetShiftFraction, (fmi3Instance c, const fmi3ValueReference vr[], size_t nvr,
        fmi3UInt64 counters[], fmi3UInt64 resolutions[]), NO_CLOCKS)
REFUSED(fmi3SetIntervalDecimal, (fmi3Instance c, const fmi3ValueReference vr[], size_t nvr,
        const fmi3Float64 intervals[]), NO_CLOCKS)
REFUSED(fmi3SetIntervalFraction, (fmi3Instance c, const fmi3ValueReference vr[], size_t nvr,
        const fmi3UInt64 counters[], const fmi3UInt64 resolutions[]), NO_CLOCKS)
REFUSED(fmi3SetShiftDecimal, (fmi3Instance c, const fmi3ValueReference vr[], size_t nvr,
        const fmi3Float64 shifts[]), NO_CLOCKS)
REFUSED(fmi3SetShiftFraction, (fmi3Instance c, const fmi3ValueReference vr[], size_t nvr,
        const fmi3UInt64 counters[], const fmi3UInt64 resolutions[]), NO_CLOCKS)
REFUSED(fmi3ActivateModelPartition, (fmi3Instance c, fmi3ValueReference clock,
        fmi3Float64 time), NO_CLOCKS)
#pragma GCC diagnostic pop
