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
 *   deserialize ID BYTES -> int S;  free ID [keep] (keep: the slot keeps the freed pointer)
 *   null ID METHOD N                       -> METHOD with NULL pointer arguments (N elements)
 *   debug ID ON N CATEGORY...              -> fmi2SetDebugLogging
 *   pulse ID QVR Q0 T0 H N NVR VR...       -> N steps of Q = Q0 for t < T0, else 0, stepped
 *                                             t = k H; us per step and the NVR outputs per step
 *   setenv NAME VALUE                      (VALUE "-": unset)
 *   guard                                  -> the loader's exit-guard target and its 2 words
 *   quit
 *
 * Strings (NAME, GUID, URI, string values, BYTES, BINARY) are hex-encoded, "~" for NULL. Each
 * log message is printed when it comes, as "@L INSTANCE STATUS CATEGORY MESSAGE" (hex; CATEGORY
 * "NULL" when NULL), after printf formatting as hosts do; the answer is "@@ STATUS KIND VALUES...". The loop and the
 * commands alike in both versions are fmi_host.h's.
 */
#define FMI "fmi2"
#define STATE_WORD "FMUstate"
#define DESERIALIZE "DeSerialize"
#define REAL "Real"
#define COUNTS_VALUES 0
typedef int Boolean;
#include "fmi_host.h"

#include <stdarg.h>

typedef void (*Logger)(void *, String, Status, String, String, ...);
typedef struct {
    Logger logger;
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(void *, Status);
    void *componentEnvironment;
} Callbacks;

static void logger(void *env, String name, Status status, String category, String message,
                   ...) {
    (void)env;
    char text[16384];
    va_list ap;
    va_start(ap, message);
    vsnprintf(text, sizeof text, message ? message : "", ap);
    va_end(ap);
    log_line(name ? name : "", status, category, text);
}

static Callbacks callbacks = {logger, calloc, free, NULL, NULL};

static void instantiate(void) {
    char *name = from_hex(words[1], NULL), *guid = from_hex(words[2], NULL),
         *uri = from_hex(words[3], NULL);
    int type = n_words > 5 ? atoi(words[5]) : 1;
    lib = n_words > 6 ? libs[atoi(words[6]) % 8] : libs[0];
    Instance (*f)(String, int, String, String, const Callbacks *, int, int) =
        (Instance (*)(String, int, String, String, const Callbacks *, int, int))fn(
            "fmi2Instantiate");
    Instance made = f(name, type, guid, uri, &callbacks, 0, atoi(words[4]));
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
}

static int own_call(Instance c, const char *method, char **a) {
    if (strcmp(method, "setupExperiment") == 0) {
        Status (*f)(Instance, int, double, double, int, double) =
            (Status (*)(Instance, int, double, double, int, double))fn("fmi2SetupExperiment");
        int tol = strcmp(a[0], "none") != 0, stop = strcmp(a[2], "none") != 0;
        answer_status(f(c, tol, tol ? real_arg(a[0]) : 0.0, real_arg(a[1]), stop,
                        stop ? real_arg(a[2]) : 0.0));
    } else if (strcmp(method, "doStep") == 0) {
        Status (*f)(Instance, double, double, int) =
            (Status (*)(Instance, double, double, int))fn("fmi2DoStep");
        answer_status(f(c, real_arg(a[0]), real_arg(a[1]), 1));
    } else {
        return 0;
    }
    return 1;
}

static Status null_arrays(Instance c, const char *method, const char *name, size_t n) {
    if (strncmp(method, "get", 3) == 0 && strstr(method, "Status") != NULL)
        return ((Status (*)(Instance, int, void *))fn(name))(c, 2, NULL);  /* LastSuccessfulTime */
    return ((Status (*)(Instance, const void *, size_t, void *))fn(name))(c, NULL, n, NULL);
}

static Status pulse_step(const Pulse *p, double q, double t, double *out) {
    Status status = ((Status (*)(Instance, const VR *, size_t, const double *))p->set)(
        p->c, &p->q_vr, 1, &q);
    if (status == 0) status = ((Status (*)(Instance, double, double, int))p->step)(p->c, t, p->h, 1);
    if (status == 0)
        status = ((Status (*)(Instance, const VR *, size_t, double *))p->get)(p->c, p->vr,
                                                                            p->nvr, out);
    return status;
}
