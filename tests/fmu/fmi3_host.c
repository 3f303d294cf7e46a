/* A plain C FMI 3.0 host for the tests: no Python in it, the FMU's binary opened with dlopen
 * (RTLD_NOW | RTLD_LOCAL) as C importers do. It speaks the answers of fmi_host.c (the FMI 2.0
 * host; fmi_c_host.CHost drives both), with FMI 3.0's calls:
 *
 *   open BINARY                            -> int L: another FMU's binary (0: the first one)
 *   instantiate NAME TOKEN PATH LOGGING [EVENTMODE [L]]  -> int ID, or null
 *   call ID METHOD ARGS...                 -> the FMI status; getters: their values
 *       enterInitializationMode START STOP|none     doStep T H
 *       exitInitializationMode terminate reset enterConfigurationMode exitConfigurationMode
 *       enterEventMode enterStepMode
 *       get{Float64,Int32,UInt64,Boolean,String,Float32,Int64} NVALUES NVR VR...
 *       set{...} NVR VR... NVALUES VALUE...
 *   get_state ID -> int S;  set_state ID S (S 0: NULL);  free_state ID S [keep]
 *   serialize ID S [SIZE] -> hex BYTES;  deserialize ID BYTES -> int S;  free ID
 *   null ID METHOD N                       -> METHOD with NULL pointer arguments (N elements)
 *   debug ID ON N CATEGORY...              -> fmi3SetDebugLogging
 *   pulse ID QVR Q0 T0 H N NVALUES NVR VR...  -> N steps of Q = Q0 for t < T0, else 0, stepped
 *                                             t = k H; us per step and NVALUES outputs per step
 *   setenv NAME VALUE (VALUE "-": unset);  guard;  quit
 *
 * Compiled with -DPYTHON_HOST -shared it is a library whose host_main(binary) runs the same
 * loop inside a Python process (``python_host3.py``, through ctypes as FMPy calls FMUs): the FMU
 * then uses that process's interpreter.
 *
 * Strings (NAME, TOKEN, PATH, string values, BYTES, BINARY) are hex-encoded, "~" for NULL. The
 * logger knows the instance only by its instanceEnvironment (FMI 3.0 loggers get no instance
 * name): each instance gets an environment of its own holding its id, and each message is
 * printed when it comes as "@L ENV STATUS CATEGORY MESSAGE" (hex; ENV the id the environment
 * holds, "?" when the environment is not one of this host's).
 */
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
typedef void (*Logger)(void *, Status, String, String);

#define MAX 4096
#define ENV_MAGIC 0x46e1f3u
typedef struct { unsigned magic; char id[16]; } Environment;   /* one per instance id */

static void *libs[8], *lib;
static int n_libs;
static Instance instances[MAX];
static void *instance_libs[MAX];
static Environment envs[MAX];
static State states[MAX];
static int n_instances, n_states;

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

/* The message as it is: FMI 3.0 loggers do not printf. */
static void logger(void *env, Status status, String category, String message) {
    const Environment *e = env;
    const char *id = e != NULL && e->magic == ENV_MAGIC ? e->id : "?";
    printf("@L");
    put_hex(id, strlen(id));
    printf(" %d", status);
    if (category == NULL) printf(" NULL");
    else put_hex(category, strlen(category));
    put_hex(message ? message : "", message ? strlen(message) : 0);
    putchar('\n');
    fflush(stdout);
}

static void answer_status(int status) { printf("@@ %d none\n", status); }

static double real_arg(const char *w) { return strtod(w, NULL); }

/* Value kinds by the type's name: size and how values are read and printed. */
typedef enum { F64, F32, I32, I64, U64, BOOL, STR } Kind;

static Kind kind_of(const char *type) {
    return strcmp(type, "Float64") == 0 ? F64 : strcmp(type, "Float32") == 0 ? F32
         : strcmp(type, "Int32") == 0 ? I32 : strcmp(type, "Int64") == 0 ? I64
         : strcmp(type, "UInt64") == 0 ? U64 : strcmp(type, "Boolean") == 0 ? BOOL : STR;
}

static void get_set(Instance c, const char *method, char **a) {
    char name[64];
    snprintf(name, sizeof name, "fmi3%c%s", method[0] == 'g' ? 'G' : 'S', method + 1);
    Kind kind = kind_of(method + 3);
    int getting = method[0] == 'g';
    size_t n_values = 0, nvr, at = 0;
    if (getting) n_values = strtoul(a[at++], NULL, 10);
    nvr = strtoul(a[at++], NULL, 10);
    VR *vr = calloc(nvr + 1, sizeof *vr);
    for (size_t i = 0; i < nvr; i++) vr[i] = (VR)strtoul(a[at++], NULL, 10);
    if (!getting) n_values = strtoul(a[at++], NULL, 10);
    void *values = calloc(n_values + 1, 8);
    char **strings = calloc(n_values + 1, sizeof *strings);
    for (size_t i = 0; !getting && i < n_values; i++) {
        const char *w = a[at++];
        switch (kind) {
        case F64: ((double *)values)[i] = real_arg(w); break;
        case F32: ((float *)values)[i] = (float)real_arg(w); break;
        case I32: ((int32_t *)values)[i] = (int32_t)strtol(w, NULL, 10); break;
        case I64: ((int64_t *)values)[i] = strtoll(w, NULL, 10); break;
        case U64: ((uint64_t *)values)[i] = strtoull(w, NULL, 10); break;
        case BOOL: ((bool *)values)[i] = strtol(w, NULL, 10) != 0; break;
        case STR: ((String *)values)[i] = strings[i] = from_hex(w, NULL); break;
        }
    }
    Status (*f)(Instance, const VR *, size_t, void *, size_t) =
        (Status (*)(Instance, const VR *, size_t, void *, size_t))fn(name);
    Status status = f(c, vr, nvr, values, n_values);
    if (!getting || status > 1) {
        answer_status(status);
    } else {
        const char *word = kind == F64 || kind == F32 ? "reals" : kind == BOOL ? "bools"
                         : kind == STR ? "strs" : "ints";
        printf("@@ %d %s %zu", status, word, n_values);
        for (size_t i = 0; i < n_values; i++) {
            switch (kind) {
            case F64: printf(" %.17g", ((double *)values)[i]); break;
            case F32: printf(" %.9g", ((float *)values)[i]); break;
            case I32: printf(" %d", ((int32_t *)values)[i]); break;
            case I64: printf(" %lld", (long long)((int64_t *)values)[i]); break;
            case U64: printf(" %llu", (unsigned long long)((uint64_t *)values)[i]); break;
            case BOOL: printf(" %d", ((bool *)values)[i] ? 1 : 0); break;
            case STR: {
                String s = ((String *)values)[i];
                put_hex(s ? s : "~", s ? strlen(s) : 1);
            }
            }
        }
        putchar('\n');
    }
    for (size_t i = 0; i < n_values; i++) free(strings[i]);
    free(strings), free(values), free(vr);
}

static void call(Instance c, const char *method, char **a) {
    if (strcmp(method, "enterInitializationMode") == 0) {
        Status (*f)(Instance, bool, double, double, bool, double) =
            (Status (*)(Instance, bool, double, double, bool, double))fn(
                "fmi3EnterInitializationMode");
        int stop = strcmp(a[1], "none") != 0;
        answer_status(f(c, false, 0.0, real_arg(a[0]), stop, stop ? real_arg(a[1]) : 0.0));
    } else if (strcmp(method, "doStep") == 0) {
        Status (*f)(Instance, double, double, bool, bool *, bool *, bool *, double *) =
            (Status (*)(Instance, double, double, bool, bool *, bool *, bool *, double *))fn(
                "fmi3DoStep");
        bool event = true, terminate = true, early = true;
        double last = -1.0;
        Status status = f(c, real_arg(a[0]), real_arg(a[1]), true, &event, &terminate, &early,
                          &last);
        printf("@@ %d step %d %d %d %.17g\n", status, event, terminate, early, last);
    } else if (strncmp(method, "get", 3) == 0 || strncmp(method, "set", 3) == 0) {
        get_set(c, method, a);
    } else {
        char name[64];
        snprintf(name, sizeof name, "fmi3%c%s", method[0] - 'a' + 'A', method + 1);
        answer_status(((Status (*)(Instance))fn(name))(c));
    }
}

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void pulse(Instance c, char **a) {
    VR q_vr = (VR)strtoul(a[0], NULL, 10);
    double q0 = real_arg(a[1]), t0 = real_arg(a[2]), h = real_arg(a[3]);
    long n = strtol(a[4], NULL, 10);
    size_t n_values = strtoul(a[5], NULL, 10), nvr = strtoul(a[6], NULL, 10);
    VR *vr = calloc(nvr + 1, sizeof *vr);
    for (size_t i = 0; i < nvr; i++) vr[i] = (VR)strtoul(a[7 + i], NULL, 10);
    double *out = calloc((size_t)n * n_values + 1, sizeof *out);
    Status (*set)(Instance, const VR *, size_t, const double *, size_t) =
        (Status (*)(Instance, const VR *, size_t, const double *, size_t))fn("fmi3SetFloat64");
    Status (*get)(Instance, const VR *, size_t, double *, size_t) =
        (Status (*)(Instance, const VR *, size_t, double *, size_t))fn("fmi3GetFloat64");
    Status (*step)(Instance, double, double, bool, bool *, bool *, bool *, double *) =
        (Status (*)(Instance, double, double, bool, bool *, bool *, bool *, double *))fn(
            "fmi3DoStep");
    Status status = 0;
    long k = 0;
    double start = now();
    for (; k < n && status == 0; k++) {
        double t = k * h, q = t < t0 ? q0 : 0.0, last;
        bool event, terminate, early;
        status = set(c, &q_vr, 1, &q, 1);
        if (status == 0) status = step(c, t, h, true, &event, &terminate, &early, &last);
        if (status == 0) status = get(c, vr, nvr, out + (size_t)k * n_values, n_values);
    }
    double elapsed = now() - start;
    printf("@@ %d pulse %.6g %zu", status, 1e6 * elapsed / (double)(k ? k : 1),
           (size_t)k * n_values);
    for (size_t i = 0; i < (size_t)k * n_values; i++) printf(" %.17g", out[i]);
    putchar('\n');
    free(out), free(vr);
}

/* METHOD of instance c with NULL where it takes pointers, n elements where it takes a count. */
static void null_call(Instance c, const char *method, size_t n) {
    char name[64];
    snprintf(name, sizeof name, "fmi3%c%s", method[0] - 'a' + 'A', method + 1);
    if (strcmp(method, "getFMUState") == 0 || strcmp(method, "freeFMUState") == 0)
        answer_status(((Status (*)(Instance, void *))fn(name))(c, NULL));
    else if (strcmp(method, "serializedFMUStateSize") == 0)
        answer_status(((Status (*)(Instance, void *, void *))fn(name))(c, NULL, NULL));
    else if (strcmp(method, "deserializeFMUState") == 0)
        answer_status(((Status (*)(Instance, const void *, size_t, void *))fn(name))(
            c, NULL, n, NULL));
    else if (strcmp(method, "setDebugLogging") == 0)
        answer_status(((Status (*)(Instance, bool, size_t, void *))fn(name))(c, true, n, NULL));
    else if (strcmp(method, "doStep") == 0)
        answer_status(((Status (*)(Instance, double, double, bool, void *, void *, void *,
                                   void *))fn(name))(c, 0.0, 1e-3, true, NULL, NULL, NULL, NULL));
    else   /* getters and setters: NULL value references and values of n elements */
        answer_status(((Status (*)(Instance, const void *, size_t, void *, size_t))fn(name))(
            c, NULL, n, NULL, n));
}

static void debug_logging(Instance c, char **a) {
    size_t n = strtoul(a[1], NULL, 10);
    char **categories = calloc(n + 1, sizeof *categories);
    for (size_t i = 0; i < n; i++) categories[i] = from_hex(a[2 + i], NULL);
    answer_status(((Status (*)(Instance, bool, size_t, char **))fn("fmi3SetDebugLogging"))(
        c, atoi(a[0]) != 0, n, categories));
    for (size_t i = 0; i < n; i++) free(categories[i]);
    free(categories);
}

static char guard_symbol[256];
static char *words[1 << 16];
static int n_words;

static int run(const char *binary);

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

static int run(const char *binary) {
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
        const char *op = words[0];
        Instance c = n_words > 1 ? instances[atoi(words[1]) % MAX] : NULL;
        lib = n_words > 1 && instance_libs[atoi(words[1]) % MAX]
                  ? instance_libs[atoi(words[1]) % MAX] : libs[0];
        if (strcmp(op, "quit") == 0) {
            break;
        } else if (strcmp(op, "open") == 0) {
            char *path = from_hex(words[1], NULL);
            void *opened = n_libs < 8 ? dlopen(path, RTLD_NOW | RTLD_LOCAL) : NULL;
            if (opened == NULL) printf("@@ 4 dlopen %s\n", dlerror());
            else printf("@@ 0 int %d\n", n_libs), libs[n_libs++] = opened;
            free(path);
        } else if (strcmp(op, "instantiate") == 0) {
            char *name = from_hex(words[1], NULL), *token = from_hex(words[2], NULL),
                 *path = from_hex(words[3], NULL);
            int event_mode = n_words > 5 ? atoi(words[5]) : 0;
            lib = n_words > 6 ? libs[atoi(words[6]) % 8] : libs[0];
            int id = n_instances + 1;
            if (instances[id % MAX] != NULL) {
                printf("@@ 4 host: more than %d instances alive\n", MAX - 1);
                fflush(stdout);
                continue;
            }
            Environment *env = &envs[id % MAX];
            env->magic = ENV_MAGIC;
            snprintf(env->id, sizeof env->id, "%d", id);
            Instance (*f)(String, String, String, bool, bool, bool, bool, const VR *, size_t,
                          void *, Logger, void *) =
                (Instance (*)(String, String, String, bool, bool, bool, bool, const VR *, size_t,
                              void *, Logger, void *))fn("fmi3InstantiateCoSimulation");
            Instance made = f(name, token, path, false, atoi(words[4]) != 0, event_mode != 0,
                              false, NULL, 0, env, logger, NULL);
            if (made == NULL) {
                printf("@@ 0 null\n");
            } else {
                n_instances = id;
                instances[id % MAX] = made, instance_libs[id % MAX] = lib;
                printf("@@ 0 int %d\n", id);
            }
            free(name), free(token), free(path);
        } else if (strcmp(op, "call") == 0) {
            call(c, words[2], words + 3);
        } else if (strcmp(op, "pulse") == 0) {
            pulse(c, words + 2);
        } else if (strcmp(op, "get_state") == 0 || strcmp(op, "deserialize") == 0) {
            State state = NULL;
            Status status;
            if (op[0] == 'g') {
                status = ((Status (*)(Instance, State *))fn("fmi3GetFMUState"))(c, &state);
            } else {
                size_t n;
                char *bytes = from_hex(words[2], &n);
                status = ((Status (*)(Instance, const char *, size_t, State *))fn(
                    "fmi3DeserializeFMUState"))(c, bytes, n, &state);
                free(bytes);
            }
            if (states[(n_states + 1) % MAX] != NULL) {
                printf("@@ 4 host: more than %d states alive\n", MAX - 1);
            } else {
                states[++n_states % MAX] = state;
                printf("@@ %d int %d\n", status, n_states);
            }
        } else if (strcmp(op, "set_state") == 0) {
            answer_status(((Status (*)(Instance, State))fn("fmi3SetFMUState"))(
                c, states[atoi(words[2]) % MAX]));
        } else if (strcmp(op, "free_state") == 0) {
            State kept = states[atoi(words[2]) % MAX];
            answer_status(((Status (*)(Instance, State *))fn("fmi3FreeFMUState"))(
                c, &states[atoi(words[2]) % MAX]));
            states[atoi(words[2]) % MAX] = n_words > 3 && strcmp(words[3], "keep") == 0 ? kept
                                                                                       : NULL;
        } else if (strcmp(op, "serialize") == 0) {
            State state = states[atoi(words[2]) % MAX];
            size_t size = 0;
            Status status = ((Status (*)(Instance, State, size_t *))fn(
                "fmi3SerializedFMUStateSize"))(c, state, &size);
            size_t real = size;
            if (n_words > 3) size = strtoul(words[3], NULL, 10);
            char *bytes = calloc((size > real ? size : real) + 1, 1);
            if (status == 0)
                status = ((Status (*)(Instance, State, char *, size_t))fn(
                    "fmi3SerializeFMUState"))(c, state, bytes, size);
            printf("@@ %d hex", status);
            put_hex(bytes, size);
            putchar('\n');
            free(bytes);
        } else if (strcmp(op, "null") == 0) {
            null_call(c, words[2], strtoul(words[3], NULL, 10));
        } else if (strcmp(op, "debug") == 0) {
            debug_logging(c, words + 2);
        } else if (strcmp(op, "free") == 0) {
            ((void (*)(Instance))fn("fmi3FreeInstance"))(c);
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
        fflush(stdout);
    }
    return 0;
}
