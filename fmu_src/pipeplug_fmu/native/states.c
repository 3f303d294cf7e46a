/* FMU states: handles the loader checks, and serialized states it frames (pythonfmu07 P9).
 *
 * pythonfmu's FMU state is the Python object the slave returned, and it uses whatever pointer
 * the host hands back as one. The host gets a handle instead: a number of this loader's own
 * (a random start, counted up; never reused), looked up in the list of live states. A NULL
 * handle, a freed one, or one of another FMU (whose loader is another copy with its own list)
 * is refused with one line before pythonfmu sees it. The states obtained through an instance
 * are freed with it.
 *
 * A serialized state is a 32-byte header and pythonfmu's bytes (the payload): the magic
 * STATE_MAGIC ("FMI2STAT", "FMI3STAT"), the identity of the FMU and build (build_identity), the
 * payload's length and its FNV-1a hash, each 8 bytes, little-endian. Deserializing refuses
 * bytes of another FMU, build or FMI version, of the wrong length or whose hash differs;
 * serializing refuses a buffer smaller than the state. What the bytes hold is checked by the
 * slave when it is set. The calls and words in lines are the version's (fmi2.h, fmi3.h).
 *
 * The calls (fmi2GetFMUstate, fmi3GetFMUState, ...) are the version's by name: a state may be
 * set, and freed, after an error; FMI 3.0 refuses states in configuration mode.
 */
#include "loader.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define MAGIC STATE_MAGIC
#define HEADER 32

typedef struct Record {
    uint64_t handle;
    FmuState inner;        /* pythonfmu's state */
    Instance *owner;           /* the instance it was obtained through */
    struct Record *next;
} Record;

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static Record *records;
static uint64_t next_handle;

/* A handle never given out before by this loader, and unlikely to be another loader's. */
static uint64_t new_handle(void) {
    if (next_handle == 0) {
        uint64_t seed[3] = {(uint64_t)(uintptr_t)&records, (uint64_t)time(NULL),
                            (uint64_t)getpid()};
        next_handle = fnv1a(FNV_START, seed, sizeof seed) & ~(uint64_t)0xf;
    }
    next_handle += 16;
    return next_handle ? next_handle : (next_handle = 16);
}

/* The live record of `handle`, or NULL. */
static Record *find(FmuState handle) {
    pthread_mutex_lock(&lock);
    Record *r = records;
    while (r != NULL && r->handle != (uint64_t)(uintptr_t)handle) r = r->next;
    pthread_mutex_unlock(&lock);
    return r;
}

static FmuState add(Instance *in, FmuState inner_state) {
    Record *r = calloc(1, sizeof *r);
    if (r == NULL) return NULL;
    pthread_mutex_lock(&lock);
    *r = (Record){new_handle(), inner_state, in, records};
    records = r;
    pthread_mutex_unlock(&lock);
    return (FmuState)(uintptr_t)r->handle;
}

static void drop(Record *gone) {
    pthread_mutex_lock(&lock);
    for (Record **r = &records; *r != NULL; r = &(*r)->next)
        if (*r == gone) {
            *r = gone->next;
            break;
        }
    pthread_mutex_unlock(&lock);
    free(gone);
}

/* Refuse a state argument `name` with value `handle` (or a NULL pointer to one). */
static Status refuse_state(Instance *in, const char *call, const char *name,
                               const void *handle, const char *allowed) {
    Text why = {0};
    if (handle == NULL) text_printf(&why, "%s = NULL", name);
    else text_printf(&why, "%s = %p", name, handle);
    text_printf(&why, " is not allowed in %s; allowed: %s", call, allowed);
    return refuse(in, &why);
}

#define GET_NAME STRING_OF(STATE_GET)
#define SET_NAME STRING_OF(STATE_SET)
#define FREE_NAME STRING_OF(STATE_FREE)
#define SIZE_NAME STRING_OF(STATE_SIZE)
#define SERIALIZE_NAME STRING_OF(STATE_SERIALIZE)
#define DESERIALIZE_NAME STRING_OF(STATE_DESERIALIZE)
#define LIVE "a live state of this " MODEL " (from " GET_NAME " or " DESERIALIZE_NAME ", " \
             "not freed, not of another FMU)"

/* Store a new pythonfmu state in *state: into its record if *state is a live handle (FMI:
 * the state is overwritten), else under a new handle. */
static Status keep(Instance *in, FmuState *state, FmuState fresh) {
    Record *r = *state != NULL ? find(*state) : NULL;
    if (r != NULL) {
        FmuState old = r->inner;
        r->inner = fresh;
        inner.STATE_FREE(in->inner, &old);
        return ST_OK;
    }
    *state = add(in, fresh);
    if (*state != NULL) return ST_OK;
    inner.STATE_FREE(in->inner, &fresh);
    Text why = {0};
    text_printf(&why, STATE_WORD " cannot be kept: out of memory");
    return refuse(in, &why);
}

static Status state_get(Instance *in, FmuState *state) {
    if (state == NULL)
        return refuse_state(in, GET_NAME, STATE_WORD, NULL, "a pointer to a variable");
    FmuState fresh = NULL;
    Status status = finish(in, inner.STATE_GET(in->inner, &fresh));
    if (status > ST_WARNING) return status;
    return keep(in, state, fresh);
}

static Status state_set(Instance *in, FmuState state) {
    Record *r = state != NULL ? find(state) : NULL;
    if (r == NULL) return refuse_state(in, SET_NAME, STATE_WORD, state, LIVE);
    return finish(in, inner.STATE_SET(in->inner, r->inner));
}

static Status state_free(Instance *in, FmuState *state) {
    if (state == NULL)
        return refuse_state(in, FREE_NAME, STATE_WORD, NULL, "a pointer to a state");
    if (*state == NULL) return ST_OK;                      /* FMI: ignored */
    Record *r = find(*state);
    if (r == NULL) return refuse_state(in, FREE_NAME, "*" STATE_WORD, *state, LIVE);
    inner.STATE_FREE(in->inner, &r->inner);
    drop(r);
    *state = NULL;
    return ST_OK;
}

void states_of_instance_free(Instance *in) {
    pthread_mutex_lock(&lock);
    Record **r = &records;
    while (*r != NULL) {
        Record *gone = *r;
        if (gone->owner != in) {
            r = &gone->next;
            continue;
        }
        *r = gone->next;
        inner.STATE_FREE(in->inner, &gone->inner);
        free(gone);
    }
    pthread_mutex_unlock(&lock);
}

/* The length of pythonfmu's bytes of the state of record `r` into *n; its status. */
static Status payload_size(Instance *in, Record *r, size_t *n) {
    *n = 0;
    return finish(in, inner.STATE_SIZE(in->inner, r->inner, n));
}

static Status state_size(Instance *in, FmuState state, size_t *size) {
    Record *r = state != NULL ? find(state) : NULL;
    if (r == NULL) return refuse_state(in, SIZE_NAME, STATE_WORD, state, LIVE);
    if (size == NULL)
        return refuse_state(in, SIZE_NAME, "size", NULL,
                            "a pointer to a size_t");
    size_t n;
    Status status = payload_size(in, r, &n);
    if (status <= ST_WARNING) *size = HEADER + n;
    return status;
}

static void put64(Byte *at, uint64_t value) {
    for (int i = 0; i < 8; i++) at[i] = (Byte)(value >> (8 * i));
}

static uint64_t get64(const Byte *at) {
    uint64_t value = 0;
    for (int i = 0; i < 8; i++) value |= (uint64_t)(unsigned char)at[i] << (8 * i);
    return value;
}

static Status state_serialize(Instance *in, FmuState state, Byte bytes[], size_t size) {
    Record *r = state != NULL ? find(state) : NULL;
    if (r == NULL) return refuse_state(in, SERIALIZE_NAME, STATE_WORD, state, LIVE);
    if (bytes == NULL)
        return refuse_state(in, SERIALIZE_NAME, "serializedState", NULL,
                            "an array of " SIZE_NAME " bytes");
    size_t n;
    Status status = payload_size(in, r, &n);
    if (status > ST_WARNING) return status;
    if (size < HEADER + n) {
        Text why = {0};
        text_printf(&why, "size = %zu is not allowed in " SERIALIZE_NAME "; allowed: >= %zu "
                    "(" SIZE_NAME " of this state)", size, HEADER + n);
        return refuse(in, &why);
    }
    Byte *payload = malloc(n + 1);
    if (payload == NULL) return refuse_state(in, SERIALIZE_NAME, STATE_WORD, state,
                                             "a state that fits in memory");
    status = finish(in, inner.STATE_SERIALIZE(in->inner, r->inner, payload, n));
    if (status <= ST_WARNING) {
        memcpy(bytes, MAGIC, 8);
        put64(bytes + 8, build_identity);
        put64(bytes + 16, n);
        put64(bytes + 24, fnv1a(FNV_START, payload, n));
        memcpy(bytes + HEADER, payload, n);
    }
    free(payload);
    return status;
}

/* What is wrong with `bytes` as a serialized state of this FMU and build, NULL if nothing. */
static const char *framing_error(const Byte bytes[], size_t size) {
    if (size < HEADER) return "a serialized state of this " MODEL " build (it is shorter than "
                              "the 32-byte header)";
    if (memcmp(bytes, MAGIC, 8) != 0 || get64(bytes + 8) != build_identity)
        return "a state serialized by this " MODEL " build (these bytes are not)";
    if (get64(bytes + 16) != size - HEADER)
        return "the length of the serialized state (32 + the payload length in its header)";
    if (get64(bytes + 24) != fnv1a(FNV_START, bytes + HEADER, size - HEADER))
        return "a serialized state as written (its checksum does not match: the bytes were "
               "changed)";
    return NULL;
}

static Status state_deserialize(Instance *in, const Byte bytes[], size_t size,
                                FmuState *state) {
    if (state == NULL)
        return refuse_state(in, DESERIALIZE_NAME, STATE_WORD, NULL,
                            "a pointer to a variable");
    if (bytes == NULL)
        return refuse_state(in, DESERIALIZE_NAME, "serializedState", NULL,
                            "the bytes of " SERIALIZE_NAME);
    const char *wrong = framing_error(bytes, size);
    if (wrong != NULL) {
        Text why = {0};
        text_printf(&why, "serializedState of size = %zu is not allowed in "
                    DESERIALIZE_NAME "; allowed: %s", size, wrong);
        return refuse(in, &why);
    }
    FmuState fresh = NULL;
    Status status = finish(in, inner.STATE_DESERIALIZE(in->inner, bytes + HEADER,
                                                                 size - HEADER, &fresh));
    if (status > ST_WARNING) return status;
    return keep(in, state, fresh);
}

/* The calls ------------------------------------------------------------------------------------ */
EXPORT Status STATE_GET(void *c, FmuState *state) {
    CHECKED(GET_NAME);
    NOT_CONFIGURING(GET_NAME);
    return state_get(in, state);
}

EXPORT Status STATE_SET(void *c, FmuState state) {
    Instance *in = c;
    if (GONE(in)) return ST_ERROR;
    NOT_CONFIGURING(SET_NAME);
    Status status = state_set(in, state);      /* allowed after an error; ends it if it works */
    in->failed = status > ST_WARNING;
    return status;
}

EXPORT Status STATE_FREE(void *c, FmuState *state) {
    Instance *in = c;
    if (GONE(in)) return ST_ERROR;
    int failed = in->failed;
    Status status = state_free(in, state);
    in->failed |= failed;                      /* bookkeeping: allowed after an error */
    return status;
}

EXPORT Status STATE_SIZE(void *c, FmuState state, size_t *size) {
    CHECKED(SIZE_NAME);
    return state_size(in, state, size);
}

EXPORT Status STATE_SERIALIZE(void *c, FmuState state, Byte bytes[], size_t size) {
    CHECKED(SERIALIZE_NAME);
    return state_serialize(in, state, bytes, size);
}

EXPORT Status STATE_DESERIALIZE(void *c, const Byte bytes[], size_t size, FmuState *state) {
    CHECKED(DESERIALIZE_NAME);
    return state_deserialize(in, bytes, size, state);
}
