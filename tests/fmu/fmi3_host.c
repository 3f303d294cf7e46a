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
 *   serialize ID S [SIZE] -> hex BYTES;  deserialize ID BYTES -> int S;  free ID [keep]
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
 * holds, "?" when the environment is not one of this host's). The loop and the commands alike
 * in both versions are fmi_host.h's.
 */
#define FMI "fmi3"
#define STATE_WORD "FMUState"
#define DESERIALIZE "Deserialize"
#define REAL "Float64"
#define COUNTS_VALUES 1
typedef _Bool Boolean;
#include "fmi_host.h"

typedef void (*Logger)(void *, Status, String, String);

#define ENV_MAGIC 0x46e1f3u
typedef struct { unsigned magic; char id[16]; } Environment;   /* one per instance id */
static Environment envs[MAX];

/* The message as it is: FMI 3.0 loggers do not printf. */
static void logger(void *env, Status status, String category, String message) {
    const Environment *e = env;
    log_line(e != NULL && e->magic == ENV_MAGIC ? e->id : "?", status, category, message);
}

static void instantiate(void) {
    char *name = from_hex(words[1], NULL), *token = from_hex(words[2], NULL),
         *path = from_hex(words[3], NULL);
    int event_mode = n_words > 5 ? atoi(words[5]) : 0;
    lib = n_words > 6 ? libs[atoi(words[6]) % 8] : libs[0];
    int id = n_instances + 1;
    if (instances[id % MAX] != NULL) {
        printf("@@ 4 host: more than %d instances alive\n", MAX - 1);
        free(name), free(token), free(path);
        return;
    }
    Environment *env = &envs[id % MAX];
    env->magic = ENV_MAGIC;
    snprintf(env->id, sizeof env->id, "%d", id);
    Instance (*f)(String, String, String, bool, bool, bool, bool, const VR *, size_t, void *,
                  Logger, void *) =
        (Instance (*)(String, String, String, bool, bool, bool, bool, const VR *, size_t, void *,
                      Logger, void *))fn("fmi3InstantiateCoSimulation");
    Instance made = f(name, token, path, false, atoi(words[4]) != 0, event_mode != 0, false, NULL,
                      0, env, logger, NULL);
    if (made == NULL) {
        printf("@@ 0 null\n");
    } else {
        n_instances = id;
        instances[id % MAX] = made, instance_libs[id % MAX] = lib;
        printf("@@ 0 int %d\n", id);
    }
    free(name), free(token), free(path);
}

static int own_call(Instance c, const char *method, char **a) {
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
    } else {
        return 0;
    }
    return 1;
}

static Status null_arrays(Instance c, const char *method, const char *name, size_t n) {
    if (strcmp(method, "doStep") == 0)
        return ((Status (*)(Instance, double, double, bool, void *, void *, void *, void *))fn(
            name))(c, 0.0, 1e-3, true, NULL, NULL, NULL, NULL);
    /* getters and setters: NULL value references and values of n elements */
    return ((Status (*)(Instance, const void *, size_t, void *, size_t))fn(name))(c, NULL, n,
                                                                                  NULL, n);
}

static Status pulse_step(const Pulse *p, double q, double t, double *out) {
    double last;
    bool event, terminate, early;
    Status status = ((Status (*)(Instance, const VR *, size_t, const double *, size_t))p->set)(
        p->c, &p->q_vr, 1, &q, 1);
    if (status == 0)
        status = ((Status (*)(Instance, double, double, bool, bool *, bool *, bool *, double *))
                  p->step)(p->c, t, p->h, true, &event, &terminate, &early, &last);
    if (status == 0)
        status = ((Status (*)(Instance, const VR *, size_t, double *, size_t))p->get)(
            p->c, p->vr, p->nvr, out, p->n_values);
    return status;
}
