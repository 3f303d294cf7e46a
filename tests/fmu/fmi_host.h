/* What the tests' plain C hosts share (fmi_host.c: FMI 2.0, fmi3_host.c: FMI 3.0): the command
 * loop, the commands that differ only in the version's names (open, get/set, pulse, FMU states,
 * null, debug, free, setenv, guard, quit), hex words and the log line. No Python in them: the
 * FMU's binary is opened with dlopen (RTLD_NOW | RTLD_LOCAL) as C importers do.
 *
 * A host defines before including this header:
 *   FMI "fmi2"; STATE_WORD "FMUstate"; DESERIALIZE "DeSerialize"; REAL "Real" (the type pulse
 *   steps with); COUNTS_VALUES 0 or 1 (1: gets and sets take nValues beside the value
 *   references, FMI 3.0); typedef Boolean (the version's fmiXBoolean);
 * and after it the hooks declared below (instantiate, own_call, null_arrays, pulse_step).
 *
 * Compiled with -DPYTHON_HOST -shared a host is a library whose host_main(binary) runs the same
 * loop inside a Python process (``python_host3.py``, through ctypes as FMPy calls FMUs): the FMU
 * then uses that process's interpreter.
 *
 * Strings (names, tokens, resource locations, string values, BYTES, BINARY) are hex-encoded,
 * "-" for empty, "~" for NULL. A log line is printed when it comes, as "@L WHO STATUS CATEGORY
 * MESSAGE" (hex; CATEGORY "NULL" when NULL); the answer to a command is "@@ STATUS KIND
 * VALUES...".
 */
#ifndef PIPEPLUG_TEST_FMI_HOST_H
#define PIPEPLUG_TEST_FMI_HOST_H

#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef void *Instance;
typedef void *State;
typedef uint32_t VR;
typedef int Status;
typedef const char *String;

#define MAX 4096
static void *libs[8], *lib;                 /* lib: the binary of the current command */
static int n_libs;
static Instance instances[MAX];
static void *instance_libs[MAX];
static State states[MAX];
static int n_instances, n_states;
static char *words[1 << 16];
static int n_words;
static char guard_symbol[256];

/* The hooks of each host ------------------------------------------------------------------- */
/* The instantiate command (words[1...]): answers "int ID" or "null". */
static void instantiate(void);
/* A call of `method` with words `a` the host makes its own way (not a get or set, nor one
 * without arguments); 1 when it was one. */
static int own_call(Instance c, const char *method, char **a);
/* `name` (the call of `method`) with NULL arrays of n elements or NULL result pointers, for
 * the calls null_call does not know. */
static Status null_arrays(Instance c, const char *method, const char *name, size_t n);
/* What pulse calls, resolved once. */
typedef struct {
    Instance c;
    VR q_vr;
    double h;
    const VR *vr;
    size_t nvr, n_values;
    void *set, *get, *step;                /* fmiXSet<REAL>, fmiXGet<REAL>, fmiXDoStep */
} Pulse;
/* One step of pulse: Q = q set, a step from t, the outputs into `out`. */
static Status pulse_step(const Pulse *p, double q, double t, double *out);

/* Helpers ------------------------------------------------------------------------------------ */
static void *fn(const char *name) {
    void *f = dlsym(lib, name);
    if (f == NULL) {
        printf("@@ 4 missing %s\n", name);
        fflush(stdout);
        exit(3);
    }
    return f;
}

static void put_hex(const char *s, size_t n) {
    putchar(' ');
    if (n == 0) putchar('-');
    for (size_t i = 0; i < n; i++) printf("%02x", (unsigned char)s[i]);
}

/* Decode hex into a new string ("-" is empty, "~" NULL); *len gets its length. */
static char *from_hex(const char *hex, size_t *len) {
    if (strcmp(hex, "~") == 0) {
        if (len) *len = 0;
        return NULL;
    }
    size_t n = strcmp(hex, "-") == 0 ? 0 : strlen(hex) / 2;
    char *s = malloc(n + 1);
    for (size_t i = 0; i < n; i++) {
        unsigned v;
        sscanf(hex + 2 * i, "%2x", &v);
        s[i] = (char)v;
    }
    s[n] = '\0';
    if (len) *len = n;
    return s;
}

/* A log line of `who` (an instance name, or the id its environment holds). */
static void log_line(const char *who, Status status, String category, String message) {
    printf("@L");
    put_hex(who, strlen(who));
    printf(" %d", status);
    if (category == NULL) printf(" NULL");
    else put_hex(category, strlen(category));
    put_hex(message ? message : "", message ? strlen(message) : 0);
    putchar('\n');
    fflush(stdout);
}

static void answer_status(int status) { printf("@@ %d none\n", status); }

static double real_arg(const char *w) { return strtod(w, NULL); }

/* The version's call of a host method: "doStep" -> fmi2DoStep. */
static void call_name(char *name, size_t size, const char *method) {
    snprintf(name, size, FMI "%c%s", method[0] - 'a' + 'A', method + 1);
}

/* Getting and setting ---------------------------------------------------------------------- */
/* Value kinds by the type's name: size and how values are read and printed. */
typedef enum { F64, F32, I32, I64, U64, BOOL, STR } Kind;

static Kind kind_of(const char *type) {
    return strcmp(type, "Float64") == 0 || strcmp(type, "Real") == 0 ? F64
         : strcmp(type, "Float32") == 0 ? F32
         : strcmp(type, "Int32") == 0 || strcmp(type, "Integer") == 0 ? I32
         : strcmp(type, "Int64") == 0 ? I64 : strcmp(type, "UInt64") == 0 ? U64
         : strcmp(type, "Boolean") == 0 ? BOOL : STR;
}

static void read_value(Kind kind, void *values, size_t i, const char *w, char **strings) {
    switch (kind) {
    case F64: ((double *)values)[i] = real_arg(w); break;
    case F32: ((float *)values)[i] = (float)real_arg(w); break;
    case I32: ((int32_t *)values)[i] = (int32_t)strtol(w, NULL, 10); break;
    case I64: ((int64_t *)values)[i] = strtoll(w, NULL, 10); break;
    case U64: ((uint64_t *)values)[i] = strtoull(w, NULL, 10); break;
    case BOOL: ((Boolean *)values)[i] = (Boolean)strtol(w, NULL, 10); break;
    case STR: ((String *)values)[i] = strings[i] = from_hex(w, NULL); break;
    }
}

static void print_value(Kind kind, const void *values, size_t i) {
    switch (kind) {
    case F64: printf(" %.17g", ((const double *)values)[i]); break;
    case F32: printf(" %.9g", ((const float *)values)[i]); break;
    case I32: printf(" %d", ((const int32_t *)values)[i]); break;
    case I64: printf(" %lld", (long long)((const int64_t *)values)[i]); break;
    case U64: printf(" %llu", (unsigned long long)((const uint64_t *)values)[i]); break;
    case BOOL: printf(" %d", (int)((const Boolean *)values)[i]); break;
    case STR: {
        String s = ((const String *)values)[i];
        put_hex(s ? s : "~", s ? strlen(s) : 1);
    }
    }
}

/* get<Type> [NVALUES] NVR VR... or set<Type> NVR VR... [NVALUES] VALUE... (NVALUES with
 * COUNTS_VALUES, else as many values as value references). */
static void get_set(Instance c, const char *method, char **a) {
    char name[64];
    call_name(name, sizeof name, method);
    Kind kind = kind_of(method + 3);
    int getting = method[0] == 'g';
    size_t n_values = 0, nvr, at = 0;
    if (COUNTS_VALUES && getting) n_values = strtoul(a[at++], NULL, 10);
    nvr = strtoul(a[at++], NULL, 10);
    VR *vr = calloc(nvr + 1, sizeof *vr);
    for (size_t i = 0; i < nvr; i++) vr[i] = (VR)strtoul(a[at++], NULL, 10);
    if (!COUNTS_VALUES) n_values = nvr;
    else if (!getting) n_values = strtoul(a[at++], NULL, 10);
    void *values = calloc(n_values + 1, 8);
    char **strings = calloc(n_values + 1, sizeof *strings);
    for (size_t i = 0; !getting && i < n_values; i++) read_value(kind, values, i, a[at++], strings);
    Status status = COUNTS_VALUES
        ? ((Status (*)(Instance, const VR *, size_t, void *, size_t))fn(name))(c, vr, nvr, values,
                                                                               n_values)
        : ((Status (*)(Instance, const VR *, size_t, void *))fn(name))(c, vr, nvr, values);
    if (!getting || status > 1) {
        answer_status(status);
    } else {
        const char *word = kind == F64 || kind == F32 ? "reals" : kind == BOOL ? "bools"
                         : kind == STR ? "strs" : "ints";
        printf("@@ %d %s %zu", status, word, n_values);
        for (size_t i = 0; i < n_values; i++) print_value(kind, values, i);
        putchar('\n');
    }
    for (size_t i = 0; i < n_values; i++) free(strings[i]);
    free(strings), free(values), free(vr);
}

/* Commands ----------------------------------------------------------------------------------- */
static void call(Instance c, const char *method, char **a) {
    if (own_call(c, method, a)) return;
    if (strncmp(method, "get", 3) == 0 || strncmp(method, "set", 3) == 0) {
        get_set(c, method, a);
    } else {
        char name[64];
        call_name(name, sizeof name, method);
        answer_status(((Status (*)(Instance))fn(name))(c));
    }
}

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* pulse QVR Q0 T0 H N [NVALUES] NVR VR...: N steps of Q = Q0 for t < T0, else 0, stepped
 * t = k H; us per step and the outputs per step (NVALUES with COUNTS_VALUES, else NVR). */
static void pulse(Instance c, char **a) {
    Pulse p = {c, (VR)strtoul(a[0], NULL, 10), real_arg(a[3]), NULL, 0, 0,
               fn(FMI "Set" REAL), fn(FMI "Get" REAL), fn(FMI "DoStep")};
    double q0 = real_arg(a[1]), t0 = real_arg(a[2]);
    long n = strtol(a[4], NULL, 10);
    size_t at = 5;
    if (COUNTS_VALUES) p.n_values = strtoul(a[at++], NULL, 10);
    p.nvr = strtoul(a[at++], NULL, 10);
    if (!COUNTS_VALUES) p.n_values = p.nvr;
    VR *vr = calloc(p.nvr + 1, sizeof *vr);
    for (size_t i = 0; i < p.nvr; i++) vr[i] = (VR)strtoul(a[at + i], NULL, 10);
    p.vr = vr;
    double *out = calloc((size_t)n * p.n_values + 1, sizeof *out);
    Status status = 0;
    long k = 0;
    double start = now();
    for (; k < n && status == 0; k++) {
        double t = k * p.h;
        status = pulse_step(&p, t < t0 ? q0 : 0.0, t, out + (size_t)k * p.n_values);
    }
    double elapsed = now() - start;
    printf("@@ %d pulse %.6g %zu", status, 1e6 * elapsed / (double)(k ? k : 1),
           (size_t)k * p.n_values);
    for (size_t i = 0; i < (size_t)k * p.n_values; i++) printf(" %.17g", out[i]);
    putchar('\n');
    free(out), free(vr);
}

#define GET_STATE FMI "Get" STATE_WORD
#define SET_STATE FMI "Set" STATE_WORD
#define FREE_STATE FMI "Free" STATE_WORD
#define STATE_SIZE FMI "Serialized" STATE_WORD "Size"
#define SERIALIZE FMI "Serialize" STATE_WORD
#define DESERIALIZE_STATE FMI DESERIALIZE STATE_WORD

/* METHOD of instance c with NULL where it takes pointers, n elements where it takes a count. */
static void null_call(Instance c, const char *method, size_t n) {
    char name[64];
    call_name(name, sizeof name, method);
    if (strcmp(name, GET_STATE) == 0 || strcmp(name, FREE_STATE) == 0)
        answer_status(((Status (*)(Instance, void *))fn(name))(c, NULL));
    else if (strcmp(name, STATE_SIZE) == 0)
        answer_status(((Status (*)(Instance, void *, void *))fn(name))(c, NULL, NULL));
    else if (strcmp(name, DESERIALIZE_STATE) == 0)
        answer_status(((Status (*)(Instance, const void *, size_t, void *))fn(name))(
            c, NULL, n, NULL));
    else if (strcmp(method, "setDebugLogging") == 0)
        answer_status(((Status (*)(Instance, Boolean, size_t, void *))fn(name))(c, 1, n, NULL));
    else
        answer_status(null_arrays(c, method, name, n));
}

static void debug_logging(Instance c, char **a) {
    size_t n = strtoul(a[1], NULL, 10);
    char **categories = calloc(n + 1, sizeof *categories);
    for (size_t i = 0; i < n; i++) categories[i] = from_hex(a[2 + i], NULL);
    answer_status(((Status (*)(Instance, Boolean, size_t, char **))fn(FMI "SetDebugLogging"))(
        c, (Boolean)atoi(a[0]), n, categories));
    for (size_t i = 0; i < n; i++) free(categories[i]);
    free(categories);
}

/* get_state ID or deserialize ID BYTES: the new state's slot S. */
static void new_state(Instance c, const char *op) {
    State state = NULL;
    Status status;
    if (op[0] == 'g') {
        status = ((Status (*)(Instance, State *))fn(GET_STATE))(c, &state);
    } else {
        size_t n;
        char *bytes = from_hex(words[2], &n);
        status = ((Status (*)(Instance, const char *, size_t, State *))fn(DESERIALIZE_STATE))(
            c, bytes, n, &state);
        free(bytes);
    }
    if (states[(n_states + 1) % MAX] != NULL) {
        printf("@@ 4 host: more than %d states alive\n", MAX - 1);     /* never wrap */
    } else {
        states[++n_states % MAX] = state;           /* ids look up modulo MAX too */
        printf("@@ %d int %d\n", status, n_states);
    }
}

/* serialize ID S [SIZE]: hex BYTES (SIZE: the buffer's size given instead of the state's). */
static void serialize(Instance c) {
    State state = states[atoi(words[2]) % MAX];
    size_t size = 0;
    Status status = ((Status (*)(Instance, State, size_t *))fn(STATE_SIZE))(c, state, &size);
    size_t real = size;
    if (n_words > 3) size = strtoul(words[3], NULL, 10);
    char *bytes = calloc((size > real ? size : real) + 1, 1);
    if (status == 0)
        status = ((Status (*)(Instance, State, char *, size_t))fn(SERIALIZE))(c, state, bytes,
                                                                              size);
    printf("@@ %d hex", status);
    put_hex(bytes, size);
    putchar('\n');
    free(bytes);
}

/* One command of words[]; 0 for quit. */
static int command(void) {
    const char *op = words[0];
    Instance c = n_words > 1 ? instances[atoi(words[1]) % MAX] : NULL;
    lib = n_words > 1 && instance_libs[atoi(words[1]) % MAX]
              ? instance_libs[atoi(words[1]) % MAX] : libs[0];
    if (strcmp(op, "quit") == 0) {
        return 0;
    } else if (strcmp(op, "open") == 0) {
        char *path = from_hex(words[1], NULL);
        void *opened = n_libs < 8 ? dlopen(path, RTLD_NOW | RTLD_LOCAL) : NULL;
        if (opened == NULL) printf("@@ 4 dlopen %s\n", dlerror());
        else printf("@@ 0 int %d\n", n_libs), libs[n_libs++] = opened;
        free(path);
    } else if (strcmp(op, "instantiate") == 0) {
        instantiate();
    } else if (strcmp(op, "call") == 0) {
        call(c, words[2], words + 3);
    } else if (strcmp(op, "pulse") == 0) {
        pulse(c, words + 2);
    } else if (strcmp(op, "get_state") == 0 || strcmp(op, "deserialize") == 0) {
        new_state(c, op);
    } else if (strcmp(op, "set_state") == 0) {
        answer_status(((Status (*)(Instance, State))fn(SET_STATE))(
            c, states[atoi(words[2]) % MAX]));
    } else if (strcmp(op, "free_state") == 0) {
        State kept = states[atoi(words[2]) % MAX];
        answer_status(((Status (*)(Instance, State *))fn(FREE_STATE))(
            c, &states[atoi(words[2]) % MAX]));
        /* the slot is free again, or keeps the freed pointer ("keep") */
        states[atoi(words[2]) % MAX] = n_words > 3 && strcmp(words[3], "keep") == 0 ? kept : NULL;
    } else if (strcmp(op, "serialize") == 0) {
        serialize(c);
    } else if (strcmp(op, "null") == 0) {
        null_call(c, words[2], strtoul(words[3], NULL, 10));
    } else if (strcmp(op, "debug") == 0) {
        debug_logging(c, words + 2);
    } else if (strcmp(op, "free") == 0) {
        ((void (*)(Instance))fn(FMI "FreeInstance"))(c);
        /* the slot is free again, or keeps the freed pointer ("keep": a host's late calls) */
        if (!(n_words > 2 && strcmp(words[2], "keep") == 0))
            instances[atoi(words[1]) % MAX] = NULL, instance_libs[atoi(words[1]) % MAX] = NULL;
        answer_status(0);
    } else if (strcmp(op, "setenv") == 0) {
        char *name = from_hex(words[1], NULL), *value = from_hex(words[2], NULL);
        if (strcmp(words[2], "-") == 0) unsetenv(name);
        else setenv(name, value, 1);
        free(name), free(value);
        answer_status(0);
    } else if (strcmp(op, "guard") == 0) {
        void *(*target)(void) = (void *(*)(void))dlsym(lib, guard_symbol);
        uint64_t *at = target ? target() : NULL;
        printf("@@ 0 guard %llu %llu %llu\n", (unsigned long long)(uintptr_t)at,
               at ? (unsigned long long)at[0] : 0ULL, at ? (unsigned long long)at[1] : 0ULL);
    } else {
        printf("@@ 4 unknown\n");
    }
    return 1;
}

/* The loop over the commands on stdin, with `binary` opened as binary 0. */
static int run(const char *binary) {
    /* the loader's test export: <modelIdentifier>_exitGuardTarget, from the binary's name */
    const char *base = strrchr(binary, '/') ? strrchr(binary, '/') + 1 : binary;
    snprintf(guard_symbol, sizeof guard_symbol, "%.*s_exitGuardTarget",
             (int)(strstr(base, ".so") ? strstr(base, ".so") - base : (long)strlen(base)), base);
    lib = libs[n_libs++] = dlopen(binary, RTLD_NOW | RTLD_LOCAL);
    if (lib == NULL) {
        printf("@@ 4 dlopen %s\n", dlerror());
        return 3;
    }
    static char line[1 << 22];
    while (fgets(line, sizeof line, stdin) != NULL) {
        n_words = 0;
        for (char *w = strtok(line, " \n"); w && n_words < (1 << 16); w = strtok(NULL, " \n"))
            words[n_words++] = w;
        if (n_words == 0) continue;
        if (!command()) break;
        fflush(stdout);
    }
    return 0;
}

#ifdef PYTHON_HOST
__attribute__((visibility("default"))) int host_main(const char *binary) { return run(binary); }
#else
int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: %s BINARY < commands\n", argv[0]);
        return 2;
    }
    return run(argv[1]);
}
#endif

#endif
