/* A plain C FMI 2.0 host for the tests: no Python in it, the FMU's binary opened with dlopen
 * (RTLD_NOW | RTLD_LOCAL) as C importers do. Driven by commands on stdin, one a line:
 *
 *   open BINARY                            -> int L: another FMU's binary (0: the first one)
 *   instantiate NAME GUID URI LOGGING [TYPE [L]]  -> int ID, or null (of binary L)
 *   call ID METHOD ARGS...                 -> the FMI status; getters: their values
 *       setupExperiment TOL|none START STOP|none     doStep T H
 *       enterInitializationMode exitInitializationMode terminate reset
 *       get{Real,Integer,Boolean,String} N VR...      set{...} N VR... VALUE...
 *   get_state ID -> int S;  set_state ID S (S 0: NULL);  free_state ID S [keep]
 *       (keep: the slot keeps the freed pointer);  serialize ID S [SIZE] -> hex BYTES
 *       (SIZE: the buffer's size given instead of fmi2SerializedFMUstateSize's)
 *   deserialize ID BYTES -> int S;  free ID
 *   null ID METHOD N                       -> METHOD with NULL pointer arguments (N elements)
 *   debug ID ON N CATEGORY...              -> fmi2SetDebugLogging
 *   pulse ID QVR Q0 T0 H N NVR VR...       -> N steps of Q = Q0 for t < T0, else 0, stepped
 *                                             t = k H; us per step and the NVR outputs per step
 *   setenv NAME VALUE                      (VALUE "-": unset)
 *   guard                                  -> the loader's exit-guard target and its 2 words
 *   quit
 *
 * Strings (NAME, GUID, URI, string values, BYTES, BINARY) are hex-encoded, "~" for NULL. Each
 * log message is printed
 * when it comes, as "@L INSTANCE STATUS CATEGORY MESSAGE" (hex; CATEGORY "-" when NULL), after
 * printf formatting as hosts do; the answer is "@@ STATUS KIND VALUES...".
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef void *fmi2Component;
typedef void *fmi2FMUstate;
typedef unsigned int fmi2ValueReference;
typedef int fmi2Status;
typedef const char *fmi2String;
typedef void (*Logger)(void *, fmi2String, fmi2Status, fmi2String, fmi2String, ...);
typedef struct {
    Logger logger;
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(void *, fmi2Status);
    void *componentEnvironment;
} Callbacks;

#define MAX 4096
static void *libs[8], *lib;                 /* lib: the binary of the current command */
static int n_libs;
static fmi2Component instances[MAX];
static void *instance_libs[MAX];
static fmi2FMUstate states[MAX];
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

static void logger(void *env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...) {
    (void)env;
    char text[16384];
    va_list ap;
    va_start(ap, message);
    vsnprintf(text, sizeof text, message ? message : "", ap);
    va_end(ap);
    printf("@L");
    put_hex(name ? name : "", name ? strlen(name) : 0);
    printf(" %d", status);
    if (category == NULL) printf(" NULL");
    else put_hex(category, strlen(category));
    put_hex(text, strlen(text));
    putchar('\n');
    fflush(stdout);
}

static Callbacks callbacks = {logger, calloc, free, NULL, NULL};
static char *words[1 << 16];
static int n_words;

static double real_arg(const char *w) { return strtod(w, NULL); }

static void answer_status(int status) { printf("@@ %d none\n", status); }

static void call(fmi2Component c, const char *method, char **a) {
    int status;
    if (strcmp(method, "setupExperiment") == 0) {
        fmi2Status (*f)(fmi2Component, int, double, double, int, double) =
            (fmi2Status (*)(fmi2Component, int, double, double, int, double))fn(
                "fmi2SetupExperiment");
        int tol = strcmp(a[0], "none") != 0, stop = strcmp(a[2], "none") != 0;
        answer_status(f(c, tol, tol ? real_arg(a[0]) : 0.0, real_arg(a[1]), stop,
                        stop ? real_arg(a[2]) : 0.0));
    } else if (strcmp(method, "doStep") == 0) {
        fmi2Status (*f)(fmi2Component, double, double, int) =
            (fmi2Status (*)(fmi2Component, double, double, int))fn("fmi2DoStep");
        answer_status(f(c, real_arg(a[0]), real_arg(a[1]), 1));
    } else if (strncmp(method, "get", 3) == 0 || strncmp(method, "set", 3) == 0) {
        char name[64];
        snprintf(name, sizeof name, "fmi2%c%s", method[0] == 'g' ? 'G' : 'S', method + 1);
        size_t n = strtoul(a[0], NULL, 10);
        fmi2ValueReference *vr = calloc(n + 1, sizeof *vr);
        for (size_t i = 0; i < n; i++) vr[i] = (fmi2ValueReference)strtoul(a[1 + i], NULL, 10);
        char kind = method[3];                 /* R, I, B, S */
        void *values = calloc(n + 1, 8);
        char **strings = calloc(n + 1, sizeof *strings);
        if (method[0] == 's') {
            for (size_t i = 0; i < n; i++) {
                const char *w = a[1 + n + i];
                if (kind == 'R') ((double *)values)[i] = real_arg(w);
                else if (kind == 'S') ((fmi2String *)values)[i] = strings[i] = from_hex(w, NULL);
                else ((int *)values)[i] = (int)strtol(w, NULL, 10);
            }
        }
        fmi2Status (*f)(fmi2Component, const fmi2ValueReference *, size_t, void *) =
            (fmi2Status (*)(fmi2Component, const fmi2ValueReference *, size_t, void *))fn(name);
        status = f(c, vr, n, values);
        if (method[0] == 's' || status > 1) {
            answer_status(status);
        } else {
            printf("@@ %d %s %zu", status, kind == 'R' ? "reals" : kind == 'I' ? "ints"
                                           : kind == 'B' ? "bools" : "strs", n);
            for (size_t i = 0; i < n; i++) {
                if (kind == 'R') printf(" %.17g", ((double *)values)[i]);
                else if (kind == 'S') {
                    fmi2String s = ((fmi2String *)values)[i];
                    put_hex(s ? s : "~", s ? strlen(s) : 1);
                } else printf(" %d", ((int *)values)[i]);
            }
            putchar('\n');
        }
        for (size_t i = 0; i < n; i++) free(strings[i]);
        free(strings), free(values), free(vr);
    } else {
        char name[64];
        snprintf(name, sizeof name, "fmi2%c%s", method[0] - 'a' + 'A', method + 1);
        fmi2Status (*f)(fmi2Component) = (fmi2Status (*)(fmi2Component))fn(name);
        answer_status(f(c));
    }
}

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void pulse(fmi2Component c, char **a) {
    fmi2ValueReference q_vr = (fmi2ValueReference)strtoul(a[0], NULL, 10);
    double q0 = real_arg(a[1]), t0 = real_arg(a[2]), h = real_arg(a[3]);
    long n = strtol(a[4], NULL, 10);
    size_t nvr = strtoul(a[5], NULL, 10);
    fmi2ValueReference *vr = calloc(nvr + 1, sizeof *vr);
    for (size_t i = 0; i < nvr; i++) vr[i] = (fmi2ValueReference)strtoul(a[6 + i], NULL, 10);
    double *out = calloc((size_t)n * nvr + 1, sizeof *out);
    fmi2Status (*set)(fmi2Component, const fmi2ValueReference *, size_t, const double *) =
        (fmi2Status (*)(fmi2Component, const fmi2ValueReference *, size_t, const double *))fn(
            "fmi2SetReal");
    fmi2Status (*get)(fmi2Component, const fmi2ValueReference *, size_t, double *) =
        (fmi2Status (*)(fmi2Component, const fmi2ValueReference *, size_t, double *))fn(
            "fmi2GetReal");
    fmi2Status (*step)(fmi2Component, double, double, int) =
        (fmi2Status (*)(fmi2Component, double, double, int))fn("fmi2DoStep");
    int status = 0;
    long k = 0;
    double start = now();
    for (; k < n && status == 0; k++) {
        double t = k * h, q = t < t0 ? q0 : 0.0;
        status = set(c, &q_vr, 1, &q);
        if (status == 0) status = step(c, t, h, 1);
        if (status == 0) status = get(c, vr, nvr, out + (size_t)k * nvr);
    }
    double elapsed = now() - start;
    printf("@@ %d pulse %.6g %zu", status, 1e6 * elapsed / (double)(k ? k : 1), (size_t)k * nvr);
    for (size_t i = 0; i < (size_t)k * nvr; i++) printf(" %.17g", out[i]);
    putchar('\n');
    free(out), free(vr);
}

/* METHOD of instance c with NULL where it takes pointers, n elements where it takes a count. */
static void null_call(fmi2Component c, const char *method, size_t n) {
    typedef fmi2Status (*Arrays)(fmi2Component, const void *, size_t, void *);
    typedef fmi2Status (*Pointer)(fmi2Component, void *);
    typedef fmi2Status (*Query)(fmi2Component, int, void *);
    char name[64];
    snprintf(name, sizeof name, "fmi2%c%s", method[0] - 'a' + 'A', method + 1);
    if (strncmp(method, "get", 3) == 0 && strstr(method, "Status") != NULL)
        answer_status(((Query)fn(name))(c, 2, NULL));             /* fmi2LastSuccessfulTime */
    else if (strcmp(method, "getFMUstate") == 0 || strcmp(method, "freeFMUstate") == 0)
        answer_status(((Pointer)fn(name))(c, NULL));
    else if (strcmp(method, "serializedFMUstateSize") == 0)
        answer_status(((fmi2Status (*)(fmi2Component, void *, void *))fn(name))(c, NULL, NULL));
    else if (strcmp(method, "deSerializeFMUstate") == 0)
        answer_status(((fmi2Status (*)(fmi2Component, const void *, size_t, void *))fn(name))(
            c, NULL, n, NULL));
    else if (strcmp(method, "setDebugLogging") == 0)
        answer_status(((fmi2Status (*)(fmi2Component, int, size_t, void *))fn(name))(
            c, 1, n, NULL));
    else
        answer_status(((Arrays)fn(name))(c, NULL, n, NULL));
}

static void debug_logging(fmi2Component c, char **a) {
    size_t n = strtoul(a[1], NULL, 10);
    char **categories = calloc(n + 1, sizeof *categories);
    for (size_t i = 0; i < n; i++) categories[i] = from_hex(a[2 + i], NULL);
    answer_status(((fmi2Status (*)(fmi2Component, int, size_t, char **))fn(
        "fmi2SetDebugLogging"))(c, atoi(a[0]), n, categories));
    for (size_t i = 0; i < n; i++) free(categories[i]);
    free(categories);
}

static char guard_symbol[256];

int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: %s BINARY < commands\n", argv[0]);
        return 2;
    }
    /* the loader's test export: <modelIdentifier>_exitGuardTarget, from the binary's name */
    const char *base = strrchr(argv[1], '/') ? strrchr(argv[1], '/') + 1 : argv[1];
    snprintf(guard_symbol, sizeof guard_symbol, "%.*s_exitGuardTarget",
             (int)(strstr(base, ".so") ? strstr(base, ".so") - base : (long)strlen(base)), base);
    lib = libs[n_libs++] = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
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
        fmi2Component c = n_words > 1 ? instances[atoi(words[1]) % MAX] : NULL;
        lib = n_words > 1 && instance_libs[atoi(words[1]) % MAX] ? instance_libs[atoi(words[1]) % MAX]
                                                                 : libs[0];
        if (strcmp(op, "quit") == 0) {
            break;
        } else if (strcmp(op, "open") == 0) {
            char *path = from_hex(words[1], NULL);
            void *opened = n_libs < 8 ? dlopen(path, RTLD_NOW | RTLD_LOCAL) : NULL;
            if (opened == NULL) printf("@@ 4 dlopen %s\n", dlerror());
            else printf("@@ 0 int %d\n", n_libs), libs[n_libs++] = opened;
            free(path);
        } else if (strcmp(op, "instantiate") == 0) {
            char *name = from_hex(words[1], NULL), *guid = from_hex(words[2], NULL),
                 *uri = from_hex(words[3], NULL);
            int type = n_words > 5 ? atoi(words[5]) : 1;
            lib = n_words > 6 ? libs[atoi(words[6]) % 8] : libs[0];
            fmi2Component (*f)(fmi2String, int, fmi2String, fmi2String, const Callbacks *, int,
                               int) =
                (fmi2Component (*)(fmi2String, int, fmi2String, fmi2String, const Callbacks *,
                                   int, int))fn("fmi2Instantiate");
            fmi2Component made = f(name, type, guid, uri, &callbacks, 0, atoi(words[4]));
            if (made == NULL) {
                printf("@@ 0 null\n");
            } else if (instances[(n_instances + 1) % MAX] != NULL) {
                printf("@@ 4 host: more than %d instances alive\n", MAX - 1);  /* never wrap */
            } else {
                instances[++n_instances % MAX] = made;    /* ids look up modulo MAX too */
                instance_libs[n_instances % MAX] = lib;
                printf("@@ 0 int %d\n", n_instances);
            }
            free(name), free(guid), free(uri);
        } else if (strcmp(op, "call") == 0) {
            call(c, words[2], words + 3);
        } else if (strcmp(op, "pulse") == 0) {
            pulse(c, words + 2);
        } else if (strcmp(op, "get_state") == 0 || strcmp(op, "deserialize") == 0) {
            fmi2FMUstate state = NULL;
            int status;
            if (op[0] == 'g') {
                status = ((fmi2Status (*)(fmi2Component, fmi2FMUstate *))fn("fmi2GetFMUstate"))(
                    c, &state);
            } else {
                size_t n;
                char *bytes = from_hex(words[2], &n);
                status = ((fmi2Status (*)(fmi2Component, const char *, size_t, fmi2FMUstate *))fn(
                    "fmi2DeSerializeFMUstate"))(c, bytes, n, &state);
                free(bytes);
            }
            if (states[(n_states + 1) % MAX] != NULL) {
                printf("@@ 4 host: more than %d states alive\n", MAX - 1);     /* never wrap */
            } else {
                states[++n_states % MAX] = state;           /* ids look up modulo MAX too */
                printf("@@ %d int %d\n", status, n_states);
            }
        } else if (strcmp(op, "set_state") == 0) {
            answer_status(((fmi2Status (*)(fmi2Component, fmi2FMUstate))fn("fmi2SetFMUstate"))(
                c, states[atoi(words[2]) % MAX]));
        } else if (strcmp(op, "free_state") == 0) {
            fmi2FMUstate kept = states[atoi(words[2]) % MAX];
            answer_status(((fmi2Status (*)(fmi2Component, fmi2FMUstate *))fn("fmi2FreeFMUstate"))(
                c, &states[atoi(words[2]) % MAX]));
            /* the slot is free again, or keeps the freed pointer ("keep") */
            states[atoi(words[2]) % MAX] = n_words > 3 && strcmp(words[3], "keep") == 0 ? kept
                                                                                       : NULL;
        } else if (strcmp(op, "serialize") == 0) {
            fmi2FMUstate state = states[atoi(words[2]) % MAX];
            size_t size = 0;
            int status = ((fmi2Status (*)(fmi2Component, fmi2FMUstate, size_t *))fn(
                "fmi2SerializedFMUstateSize"))(c, state, &size);
            size_t real = size;
            if (n_words > 3) size = strtoul(words[3], NULL, 10);       /* a buffer of SIZE */
            char *bytes = calloc((size > real ? size : real) + 1, 1);
            if (status == 0)
                status = ((fmi2Status (*)(fmi2Component, fmi2FMUstate, char *, size_t))fn(
                    "fmi2SerializeFMUstate"))(c, state, bytes, size);
            printf("@@ %d hex", status);
            put_hex(bytes, size);
            putchar('\n');
            free(bytes);
        } else if (strcmp(op, "null") == 0) {
            null_call(c, words[2], strtoul(words[3], NULL, 10));
        } else if (strcmp(op, "debug") == 0) {
            debug_logging(c, words + 2);
        } else if (strcmp(op, "free") == 0) {
            ((void (*)(fmi2Component))fn("fmi2FreeInstance"))(c);
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
