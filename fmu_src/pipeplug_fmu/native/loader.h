/* Shared declarations of the FMUs' linux64 loader (see loader.c for what it does).
 *
 * Every source is compiled with -DMODEL_IDENTIFIER=<the FMU's modelIdentifier> and
 * -fvisibility=hidden: only the fmi2 functions (EXPORT) leave the binary.
 */
#ifndef PIPEPLUG_LOADER_H
#define PIPEPLUG_LOADER_H

#define _GNU_SOURCE
#include <stddef.h>
#include <stdint.h>

/* FMI 2.0 types (fmi2TypesPlatform.h, fmi2FunctionTypes.h) ---------------------------------- */
typedef void *fmi2Component;
typedef void *fmi2ComponentEnvironment;
typedef void *fmi2FMUstate;
typedef unsigned int fmi2ValueReference;
typedef double fmi2Real;
typedef int fmi2Integer;
typedef int fmi2Boolean;
typedef char fmi2Char;
typedef const fmi2Char *fmi2String;
typedef char fmi2Byte;
typedef enum { fmi2OK, fmi2Warning, fmi2Discard, fmi2Error, fmi2Fatal, fmi2Pending } fmi2Status;
typedef enum { fmi2ModelExchange, fmi2CoSimulation } fmi2Type;
typedef enum { fmi2DoStepStatus, fmi2PendingStatus, fmi2LastSuccessfulTime,
               fmi2Terminated } fmi2StatusKind;
typedef void (*fmi2CallbackLogger)(fmi2ComponentEnvironment, fmi2String, fmi2Status, fmi2String,
                                   fmi2String, ...);
typedef struct {
    fmi2CallbackLogger logger;
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(fmi2ComponentEnvironment, fmi2Status);
    fmi2ComponentEnvironment componentEnvironment;
} fmi2CallbackFunctions;

#define EXPORT __attribute__((visibility("default")))
#ifndef MODEL_IDENTIFIER
#error "compile with -DMODEL_IDENTIFIER=<the FMU's modelIdentifier>"
#endif
#define STRING_OF_(x) #x
#define STRING_OF(x) STRING_OF_(x)
#define JOINED_(a, b) a##b
#define JOINED(a, b) JOINED_(a, b)
#define MODEL STRING_OF(MODEL_IDENTIFIER)  /* "PipePlug": the FMU's name in log lines */
#define INNER_BINARY MODEL "_pythonfmu.so"
#define PYTHON_VARIABLE "PIPEPLUG_PYTHON"   /* one variable for all of the project's FMUs */
#define TIMEOUT_VARIABLE "PIPEPLUG_PYTHON_TIMEOUT"
#define REFUSAL MODEL "Refusal: "          /* repr of the slave's refusals (pythonfmu07 P1) */
#define NOT_UTF8 "\x1bnot UTF-8: "         /* a String that is not UTF-8 (pythonfmu07 P7) */
#define MAX_PATH_LENGTH 4096               /* of a resource folder, decoded */

/* pythonfmu's functions --------------------------------------------------------------------- */
#define INNER_FUNCTIONS(X) \
    X(fmi2Component, fmi2Instantiate, (fmi2String, fmi2Type, fmi2String, fmi2String, \
                                       const fmi2CallbackFunctions *, fmi2Boolean, fmi2Boolean)) \
    X(void, fmi2FreeInstance, (fmi2Component)) \
    X(fmi2Status, fmi2SetupExperiment, (fmi2Component, fmi2Boolean, fmi2Real, fmi2Real, \
                                        fmi2Boolean, fmi2Real)) \
    X(fmi2Status, fmi2EnterInitializationMode, (fmi2Component)) \
    X(fmi2Status, fmi2ExitInitializationMode, (fmi2Component)) \
    X(fmi2Status, fmi2Terminate, (fmi2Component)) \
    X(fmi2Status, fmi2Reset, (fmi2Component)) \
    X(fmi2Status, fmi2GetReal, (fmi2Component, const fmi2ValueReference[], size_t, fmi2Real[])) \
    X(fmi2Status, fmi2GetInteger, (fmi2Component, const fmi2ValueReference[], size_t, \
                                   fmi2Integer[])) \
    X(fmi2Status, fmi2GetBoolean, (fmi2Component, const fmi2ValueReference[], size_t, \
                                   fmi2Boolean[])) \
    X(fmi2Status, fmi2GetString, (fmi2Component, const fmi2ValueReference[], size_t, \
                                  fmi2String[])) \
    X(fmi2Status, fmi2SetReal, (fmi2Component, const fmi2ValueReference[], size_t, \
                                const fmi2Real[])) \
    X(fmi2Status, fmi2SetInteger, (fmi2Component, const fmi2ValueReference[], size_t, \
                                   const fmi2Integer[])) \
    X(fmi2Status, fmi2SetBoolean, (fmi2Component, const fmi2ValueReference[], size_t, \
                                   const fmi2Boolean[])) \
    X(fmi2Status, fmi2SetString, (fmi2Component, const fmi2ValueReference[], size_t, \
                                  const fmi2String[])) \
    X(fmi2Status, fmi2GetFMUstate, (fmi2Component, fmi2FMUstate *)) \
    X(fmi2Status, fmi2SetFMUstate, (fmi2Component, fmi2FMUstate)) \
    X(fmi2Status, fmi2FreeFMUstate, (fmi2Component, fmi2FMUstate *)) \
    X(fmi2Status, fmi2SerializedFMUstateSize, (fmi2Component, fmi2FMUstate, size_t *)) \
    X(fmi2Status, fmi2SerializeFMUstate, (fmi2Component, fmi2FMUstate, fmi2Byte[], size_t)) \
    X(fmi2Status, fmi2DeSerializeFMUstate, (fmi2Component, const fmi2Byte[], size_t, \
                                            fmi2FMUstate *)) \
    X(fmi2Status, fmi2GetDirectionalDerivative, (fmi2Component, const fmi2ValueReference[], \
        size_t, const fmi2ValueReference[], size_t, const fmi2Real[], fmi2Real[])) \
    X(fmi2Status, fmi2SetRealInputDerivatives, (fmi2Component, const fmi2ValueReference[], \
        size_t, const fmi2Integer[], const fmi2Real[])) \
    X(fmi2Status, fmi2GetRealOutputDerivatives, (fmi2Component, const fmi2ValueReference[], \
        size_t, const fmi2Integer[], fmi2Real[])) \
    X(fmi2Status, fmi2DoStep, (fmi2Component, fmi2Real, fmi2Real, fmi2Boolean)) \
    X(fmi2Status, fmi2CancelStep, (fmi2Component)) \
    X(fmi2Status, fmi2GetStatus, (fmi2Component, const fmi2StatusKind, fmi2Status *)) \
    X(fmi2Status, fmi2GetRealStatus, (fmi2Component, const fmi2StatusKind, fmi2Real *)) \
    X(fmi2Status, fmi2GetIntegerStatus, (fmi2Component, const fmi2StatusKind, fmi2Integer *)) \
    X(fmi2Status, fmi2GetBooleanStatus, (fmi2Component, const fmi2StatusKind, fmi2Boolean *)) \
    X(fmi2Status, fmi2GetStringStatus, (fmi2Component, const fmi2StatusKind, fmi2String *))

#define DECLARE_POINTER(ret, name, args) ret (*name) args;
typedef struct { INNER_FUNCTIONS(DECLARE_POINTER) } InnerFunctions;
extern InnerFunctions inner;               /* pythonfmu's binary, once loaded */

/* Text (text.c) ----------------------------------------------------------------------------- */
typedef struct { char *data; size_t len, cap; } Text;

void text_add(Text *t, const char *s, size_t n);
/* Append printf-style text; every '%' of the result is doubled (hosts printf the line). */
void text_printf(Text *t, const char *format, ...) __attribute__((format(printf, 2, 3)));
/* Append `s` (n bytes) quoted, printable ASCII as is, other bytes as \xNN, at most `max`
 * bytes of it shown ("... (N bytes)" after them); "NULL" for a NULL `s`. */
void text_shown(Text *t, const char *s, size_t n, size_t max);
/* 1 when the NUL-terminated `s` is valid UTF-8 (no overlong forms, surrogates or > U+10FFFF). */
int utf8_valid(const char *s);
/* FNV-1a, 64 bits, of `n` bytes, continuing from `hash` (start: FNV_START). */
#define FNV_START 0xcbf29ce484222325ULL
uint64_t fnv1a(uint64_t hash, const void *data, size_t n);

/* Instances (loader.c) --------------------------------------------------------------------- */
typedef struct { fmi2Status status; char *category, *message; } Line;

typedef struct Instance {
    fmi2Component inner;               /* pythonfmu's instance */
    fmi2CallbackFunctions host, mine;  /* the host's callbacks; ours given to pythonfmu */
    char *name;
    int logging_on;                    /* the host's debug logging (fmi2SetDebugLogging) */
    unsigned categories;               /* its categories, a bit per CATEGORIES entry; 0: all */
    int failed;                        /* an fmi2Error or fmi2Fatal was returned */
    Line *lines;                       /* logged during the current call */
    size_t n_lines, cap_lines;
} Instance;

/* Log one line of the loader's own to the host: status, category of that status, text. */
void host_log(const Instance *in, fmi2Status status, const char *message);
/* Log `why` with fmi2Error, mark the instance failed; fmi2Error. */
fmi2Status refuse(Instance *in, Text *why);

/* Finding a Python (python.c) -------------------------------------------------------------- */
/* Make a Python visible to pythonfmu's binary; 0 on success, else one line in `why`. */
int ensure_python(Text *why);

/* pythonfmu's binary and the exit guard (inner.c) -------------------------------------------- */
/* Load pythonfmu's binary beside this one into `inner`; 0 on success, else a line in `why`. */
int load_inner(Text *why);

/* The resource folder (resources.c) ------------------------------------------------------- */
/* The URI to give pythonfmu for the host's `location` ("file://" + a checked folder); 0 on
 * success, else one line in `why`. Also sets the build's identity (below). */
int resource_uri(const char *location, char *uri, size_t size, Text *why);
/* A hash of the FMU and build whose resources are used: modelIdentifier and slave module. */
extern uint64_t build_identity;

/* FMU states (states.c) -------------------------------------------------------------------- */
fmi2Status state_get(Instance *in, fmi2FMUstate *state);
fmi2Status state_set(Instance *in, fmi2FMUstate state);
fmi2Status state_free(Instance *in, fmi2FMUstate *state);
fmi2Status state_size(Instance *in, fmi2FMUstate state, size_t *size);
fmi2Status state_serialize(Instance *in, fmi2FMUstate state, fmi2Byte bytes[], size_t size);
fmi2Status state_deserialize(Instance *in, const fmi2Byte bytes[], size_t size,
                             fmi2FMUstate *state);
/* Free every state obtained through `in` (before the instance itself is freed). */
void states_of_instance_free(Instance *in);
/* Give the buffered lines of `in` to the host; the status the host sees (loader.c). */
fmi2Status finish(Instance *in, fmi2Status status);

#endif
