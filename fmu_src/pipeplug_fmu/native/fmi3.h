/* FMI 3.0 side of the loader (loader3.c): its types, pythonfmu3's functions, and the names the
 * shared sources (calls.c, states.c, resources.c, text.c, log.c) use for this version. */
#ifndef PIPEPLUG_FMI3_H
#define PIPEPLUG_FMI3_H

#include <stdbool.h>

/* FMI 3.0 types (fmi3PlatformTypes.h, fmi3FunctionTypes.h) ---------------------------------- */
typedef void *fmi3Instance;
typedef void *fmi3InstanceEnvironment;
typedef void *fmi3FMUState;
typedef uint32_t fmi3ValueReference;
typedef float fmi3Float32;
typedef double fmi3Float64;
typedef int8_t fmi3Int8;
typedef uint8_t fmi3UInt8;
typedef int16_t fmi3Int16;
typedef uint16_t fmi3UInt16;
typedef int32_t fmi3Int32;
typedef uint32_t fmi3UInt32;
typedef int64_t fmi3Int64;
typedef uint64_t fmi3UInt64;
typedef bool fmi3Boolean;
typedef char fmi3Char;
typedef const fmi3Char *fmi3String;
typedef uint8_t fmi3Byte;
typedef const fmi3Byte *fmi3Binary;
typedef bool fmi3Clock;
typedef enum { fmi3OK, fmi3Warning, fmi3Discard, fmi3Error, fmi3Fatal } fmi3Status;
typedef enum { fmi3Independent, fmi3Constant, fmi3Fixed, fmi3Tunable, fmi3Discrete,
               fmi3Dependent } fmi3DependencyKind;
typedef enum { fmi3IntervalNotYetKnown, fmi3IntervalUnchanged,
               fmi3IntervalChanged } fmi3IntervalQualifier;
typedef void (*fmi3LogMessageCallback)(fmi3InstanceEnvironment, fmi3Status, fmi3String,
                                       fmi3String);
typedef void (*fmi3IntermediateUpdateCallback)(fmi3InstanceEnvironment, fmi3Float64,
                                               fmi3Boolean, fmi3Boolean, fmi3Boolean,
                                               fmi3Boolean, fmi3Boolean *, fmi3Float64 *);
typedef void (*fmi3ClockUpdateCallback)(fmi3InstanceEnvironment);
typedef void (*fmi3LockPreemptionCallback)(void);
typedef void (*fmi3UnlockPreemptionCallback)(void);

typedef fmi3Status Status;
typedef fmi3FMUState FmuState;
typedef fmi3Byte Byte;
typedef fmi3Boolean Boolean;
#define ST_OK fmi3OK
#define ST_WARNING fmi3Warning
#define ST_DISCARD fmi3Discard
#define ST_ERROR fmi3Error
#define ST_FATAL fmi3Fatal
/* The host's logger and its instanceEnvironment (Instance). */
#define HOST_FIELDS fmi3InstanceEnvironment environment; fmi3LogMessageCallback logger;
#define FMI_PREFIX fmi3                /* of the calls: FMI_FUNCTION(Reset) is fmi3Reset */
#define FMI "fmi3"
#define FMI_TITLE "FMI 3.0"
#define TOKEN_ARGUMENT "instantiationToken"            /* Instantiate's, checked against TOKEN */
#define TOKEN_ATTRIBUTE "instantiationToken"          /* modelDescription.xml's */
#define RESOURCE_ARGUMENT "resourcePath"
#define RESOURCE_EXAMPLE "/path/to/resources/"
#define RESOURCE_SPELLING "the absolute path of " MODEL "'s resources folder, " RESOURCE_EXAMPLE
#define ESCAPE_PERCENT 0                   /* FMI 3.0 loggers take the message as it is */
#define STATE_WORD "FMUState"
#define STATE_MAGIC "FMI3STAT"
#define STATE_GET fmi3GetFMUState
#define STATE_SET fmi3SetFMUState
#define STATE_FREE fmi3FreeFMUState
#define STATE_SIZE fmi3SerializedFMUStateSize
#define STATE_SERIALIZE fmi3SerializeFMUState
#define STATE_DESERIALIZE fmi3DeserializeFMUState
/* A NULL array (name, n elements, call) and the most elements a call takes (calls.c): the
 * header's value references come first (HEADER_VRS below). */
#define NULL_ARRAY_FORMAT "%s = NULL is not allowed with %zu elements in %s; allowed: an " \
                          "array of that many elements"
#define MAX_COUNT (INT_MAX - HEADER_VRS)
/* The FMI 3.0 state machine's configuration mode (loader3.c): `call` of the instance `in` is
 * refused in it. */
struct Instance;
fmi3Status refuse_configuring(struct Instance *in, const char *call);
#define NOT_CONFIGURING(call) if (in->configuring) return refuse_configuring(in, call)

/* Value references the loader puts first in pythonfmu3's calls (never the host's: a host's
 * value reference comes after them); the slave's binding (pipeplug_fmu/fmi3.py) reads them.
 * COUNT_MARK, nValues, nValueReferences, then the host's value references: every get and set.
 * EXPERIMENT_MARK alone, with the values startTime, stopTimeDefined, stopTime: fmi3SetFloat64
 * before fmi3EnterInitializationMode, whose times pythonfmu3 drops. */
#define COUNT_MARK 0xffffffffu
#define EXPERIMENT_MARK 0xfffffffeu
#define HEADER_VRS 3

/* pythonfmu3's functions -------------------------------------------------------------------- */
#define ARRAY_ARGS(type) (fmi3Instance, const fmi3ValueReference[], size_t, type, size_t)
#define INNER_FUNCTIONS(X) \
    X(fmi3Instance, fmi3InstantiateCoSimulation, (fmi3String, fmi3String, fmi3String, \
        fmi3Boolean, fmi3Boolean, fmi3Boolean, fmi3Boolean, const fmi3ValueReference[], size_t, \
        fmi3InstanceEnvironment, fmi3LogMessageCallback, fmi3IntermediateUpdateCallback)) \
    X(void, fmi3FreeInstance, (fmi3Instance)) \
    X(fmi3Status, fmi3EnterInitializationMode, (fmi3Instance, fmi3Boolean, fmi3Float64, \
                                                fmi3Float64, fmi3Boolean, fmi3Float64)) \
    X(fmi3Status, fmi3ExitInitializationMode, (fmi3Instance)) \
    X(fmi3Status, fmi3Terminate, (fmi3Instance)) \
    X(fmi3Status, fmi3Reset, (fmi3Instance)) \
    X(fmi3Status, fmi3GetFloat64, ARRAY_ARGS(fmi3Float64[])) \
    X(fmi3Status, fmi3GetInt32, ARRAY_ARGS(fmi3Int32[])) \
    X(fmi3Status, fmi3GetUInt64, ARRAY_ARGS(fmi3UInt64[])) \
    X(fmi3Status, fmi3GetBoolean, ARRAY_ARGS(fmi3Boolean[])) \
    X(fmi3Status, fmi3GetString, ARRAY_ARGS(fmi3String[])) \
    X(fmi3Status, fmi3SetFloat64, ARRAY_ARGS(const fmi3Float64[])) \
    X(fmi3Status, fmi3SetInt32, ARRAY_ARGS(const fmi3Int32[])) \
    X(fmi3Status, fmi3SetUInt64, ARRAY_ARGS(const fmi3UInt64[])) \
    X(fmi3Status, fmi3SetBoolean, ARRAY_ARGS(const fmi3Boolean[])) \
    X(fmi3Status, fmi3SetString, ARRAY_ARGS(const fmi3String[])) \
    X(fmi3Status, fmi3GetFMUState, (fmi3Instance, fmi3FMUState *)) \
    X(fmi3Status, fmi3SetFMUState, (fmi3Instance, fmi3FMUState)) \
    X(fmi3Status, fmi3FreeFMUState, (fmi3Instance, fmi3FMUState *)) \
    X(fmi3Status, fmi3SerializedFMUStateSize, (fmi3Instance, fmi3FMUState, size_t *)) \
    X(fmi3Status, fmi3SerializeFMUState, (fmi3Instance, fmi3FMUState, fmi3Byte[], size_t)) \
    X(fmi3Status, fmi3DeserializeFMUState, (fmi3Instance, const fmi3Byte[], size_t, \
                                            fmi3FMUState *)) \
    X(fmi3Status, fmi3DoStep, (fmi3Instance, fmi3Float64, fmi3Float64, fmi3Boolean, \
                               fmi3Boolean *, fmi3Boolean *, fmi3Boolean *, fmi3Float64 *))

#endif
