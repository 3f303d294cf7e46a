/* FMI 2.0 side of the loader (loader.c): its types, pythonfmu 0.7's functions, and the names
 * the shared sources (calls.c, states.c, resources.c, text.c) use for this version. */
#ifndef PIPEPLUG_FMI2_H
#define PIPEPLUG_FMI2_H

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

typedef fmi2Status Status;
typedef fmi2FMUstate FmuState;
typedef fmi2Byte Byte;
typedef fmi2Boolean Boolean;
#define ST_OK fmi2OK
#define ST_WARNING fmi2Warning
#define ST_DISCARD fmi2Discard
#define ST_ERROR fmi2Error
#define ST_FATAL fmi2Fatal
/* The host's callbacks, and ours given to pythonfmu (Instance). */
#define HOST_FIELDS fmi2CallbackFunctions host, mine;
#define FMI_PREFIX fmi2                /* of the calls: FMI_FUNCTION(Reset) is fmi2Reset */
#define FMI "fmi2"
#define FMI_TITLE "FMI 2.0"
#define TOKEN_ARGUMENT "fmuGUID"            /* Instantiate's, checked against TOKEN */
#define TOKEN_ATTRIBUTE "guid"          /* modelDescription.xml's */
#define RESOURCE_ARGUMENT "fmuResourceLocation"
#define RESOURCE_EXAMPLE "file:///path/to/resources"
#define RESOURCE_SPELLING "the URI of " MODEL "'s resources folder, " RESOURCE_EXAMPLE
#define ESCAPE_PERCENT 1                   /* FMI 2.0 hosts printf the line */
#define STATE_WORD "FMUstate"
#define STATE_MAGIC "FMI2STAT"
#define STATE_GET fmi2GetFMUstate
#define STATE_SET fmi2SetFMUstate
#define STATE_FREE fmi2FreeFMUstate
#define STATE_SIZE fmi2SerializedFMUstateSize
#define STATE_SERIALIZE fmi2SerializeFMUstate
#define STATE_DESERIALIZE fmi2DeSerializeFMUstate
/* A NULL array (name, n elements, call) and the most elements a call takes (calls.c). */
#define NULL_ARRAY_FORMAT "%s = NULL is not allowed with n = %zu in %s; allowed: an array of " \
                          "n elements"
#define MAX_COUNT INT_MAX                  /* pythonfmu indexes with a C int */
/* FMI 2.0 has no configuration mode: nothing to refuse. */
#define NOT_CONFIGURING(call)

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

#endif
