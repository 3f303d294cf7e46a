/* The FMI 2.0 binary, on linux64, of the project's pythonfmu FMUs (PipePlug.fmu, Hammer.fmu).
 *
 * Compiled once per FMU with -DMODEL_IDENTIFIER=<its modelIdentifier> (say PipePlug) and shipped
 * as binaries/linux64/PipePlug.so; every name below that belongs to one FMU derives from it.
 *
 * pythonfmu's binary (shipped beside this one as PipePlug_pythonfmu.so) runs the slave in a
 * Python interpreter that must already be in the process: it is not linked to libpython. This
 * loader exports every fmi2 function and, at the first fmi2Instantiate, makes a Python visible:
 *
 *   1. a Python already in the process (a Python host): that interpreter, never a second one;
 *   2. else the python executable named by PIPEPLUG_PYTHON (>= 3.10 with numpy);
 *   3. else python3 on PATH, if it has numpy.
 *
 * For 2 and 3 the python is asked (once, in a child process) where its shared libpython, its
 * standard library and its module path are; the library is loaded with RTLD_GLOBAL and the
 * interpreter initialised with that home and path (PYTHONHOME/PYTHONPATH are set only while it
 * initialises). When no usable Python is found, fmi2Instantiate logs one line saying what to
 * set and returns NULL.
 *
 * Every call is forwarded to pythonfmu's binary with a logger of this loader's: log lines are
 * buffered and given to the host's logger only after pythonfmu's call has returned (never while
 * a Python exception is pending), each with a category of modelDescription.xml's LogCategories
 * (pythonfmu gives none to its own lines). pythonfmu can only report an exception of the slave
 * as fmi2Fatal; a refusal of the slave (an exception whose repr starts with REFUSAL) is given to
 * the host as its own line with fmi2Error, and the call returns fmi2Error. The resource URI is
 * normalised to the one spelling pythonfmu understands (file:// + plain path).
 *
 * Exit guard: pythonfmu's binary releases its interpreter state (a global shared_ptr, pyState)
 * twice at exit: the C++ exit handler destroys it, then an ELF destructor resets it again,
 * writing into freed heap. An exit handler registered after that binary is loaded runs before
 * its C++ exit handler and empties the pointer, so both releases do nothing.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <elf.h>
#include <errno.h>
#include <fcntl.h>
#include <link.h>
#include <pthread.h>
#include <spawn.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

extern char **environ;

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
#define MIN_MINOR 10                       /* Python 3.10 or newer */
#define REFUSAL MODEL "Refusal: "          /* repr of the slave's refusals (pipeplug_fmu.fmi) */
#define PYSTATE_SYMBOL "_ZN12_GLOBAL__N_17pyStateE"   /* (anonymous namespace)::pyState */
#define PYSTATE_SIZE 16                    /* a shared_ptr: object pointer, control block */

/* What the python asked answers (one "key value" a line; "error reason" if unusable). */
static const char PROBE[] =
    "import os, sys, sysconfig\n"
    "def out(key, value): sys.stdout.write(key + ' ' + value.replace('\\n', ' ') + '\\n')\n"
    "if sys.version_info < (3, %d):\n"
    "    out('error', 'is Python %%d.%%d, older than 3.%d' %% sys.version_info[:2]); raise SystemExit\n"
    "try:\n"
    "    import numpy\n"
    "except Exception as exc:\n"
    "    out('error', 'has no numpy (%%s: %%s)' %% (type(exc).__name__, exc)); raise SystemExit\n"
    "v = sysconfig.get_config_var\n"
    "out('version', '%%d.%%d.' %% sys.version_info[:2])\n"
    "out('stdlib', sysconfig.get_path('stdlib'))\n"
    "homes = dict.fromkeys([sys.base_prefix, sys.base_exec_prefix])\n"
    "out('home', os.pathsep.join(homes))\n"
    "out('path', os.pathsep.join(p for p in sys.path if p))\n"
    "for name in (v('INSTSONAME'), v('LDLIBRARY')):\n"
    "    if name and '.so' in name:\n"
    "        for d in (v('LIBDIR'), os.path.join(v('LIBDIR') or '', v('MULTIARCH') or ''),\n"
    "                  os.path.join(sys.base_prefix, 'lib')):\n"
    "            out('lib', os.path.join(d, name))\n"
    "        out('lib', name)\n";

/* pythonfmu's functions --------------------------------------------------------------------- */
#define INNER_FUNCTIONS(X) \
    X(fmi2Component, fmi2Instantiate, (fmi2String, fmi2Type, fmi2String, fmi2String, \
                                       const fmi2CallbackFunctions *, fmi2Boolean, fmi2Boolean)) \
    X(void, fmi2FreeInstance, (fmi2Component)) \
    X(fmi2Status, fmi2SetDebugLogging, (fmi2Component, fmi2Boolean, size_t, const fmi2String[])) \
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
static struct { INNER_FUNCTIONS(DECLARE_POINTER) } inner;

static pthread_mutex_t load_lock = PTHREAD_MUTEX_INITIALIZER;
static int loaded;                          /* inner is complete */
static void *pystate;                       /* pythonfmu's pyState, emptied at exit */

/* Text helpers ---------------------------------------------------------------------------- */
typedef struct { char *data; size_t len, cap; } Text;

static void text_add(Text *t, const char *s, size_t n) {
    if (t->len + n + 1 > t->cap) {
        size_t cap = (t->len + n + 1) * 2;
        char *data = realloc(t->data, cap);
        if (data == NULL) return;
        t->data = data, t->cap = cap;
    }
    memcpy(t->data + t->len, s, n);
    t->len += n;
    t->data[t->len] = '\0';
}

/* Append printf-style text; every '%' of the arguments is doubled (hosts printf the line). */
static void text_printf(Text *t, const char *format, ...) {
    char buffer[4096];
    va_list ap;
    va_start(ap, format);
    int n = vsnprintf(buffer, sizeof buffer, format, ap);
    va_end(ap);
    if (n < 0) return;
    size_t len = (size_t)n < sizeof buffer ? (size_t)n : sizeof buffer - 1;
    for (size_t i = 0; i < len; i++) {
        text_add(t, &buffer[i], 1);
        if (buffer[i] == '%') text_add(t, "%", 1);
    }
}

/* Instances: the host's callbacks and the lines logged during the current call --------------- */
typedef struct { fmi2Status status; char *category, *message; } Line;

typedef struct {
    fmi2Component inner;
    fmi2CallbackFunctions host, mine;
    char *name;
    Line *lines;
    size_t n_lines, cap_lines;
} Instance;

static void buffer_line(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status,
                        fmi2String category, fmi2String message, ...) {
    (void)name;
    Instance *in = env;
    if (in->n_lines == in->cap_lines) {
        size_t cap = in->cap_lines ? 2 * in->cap_lines : 4;
        Line *lines = realloc(in->lines, cap * sizeof *lines);
        if (lines == NULL) return;
        in->lines = lines, in->cap_lines = cap;
    }
    in->lines[in->n_lines++] = (Line){status, category ? strdup(category) : NULL,
                                      strdup(message ? message : "")};
}

static const char *const CATEGORIES[] = {"logAll", "logStatusWarning", "logStatusDiscard",
                                         "logStatusError", "logStatusFatal", "logAll"};

/* The category of a line: its own if modelDescription.xml lists it, else the status's. */
static const char *category_of(const char *given, fmi2Status status) {
    for (size_t i = 0; given != NULL && i < sizeof CATEGORIES / sizeof *CATEGORIES; i++)
        if (strcmp(given, CATEGORIES[i]) == 0) return CATEGORIES[i];
    return CATEGORIES[(unsigned)status <= fmi2Pending ? status : fmi2Fatal];
}

static void host_log(const Instance *in, fmi2Status status, const char *category,
                     const char *message) {
    if (in->host.logger != NULL)
        in->host.logger(in->host.componentEnvironment, in->name, status, category, message);
}

/* Give the buffered lines to the host; the call's status, a refusal's fmi2Fatal made fmi2Error. */
static fmi2Status finish(Instance *in, fmi2Status status) {
    int refused = 0;
    for (size_t i = 0; i < in->n_lines; i++) {
        Line *line = &in->lines[i];
        const char *message = line->message, *refusal = strstr(message, REFUSAL);
        if (line->status == fmi2Fatal && refusal != NULL) {
            line->status = fmi2Error, message = refusal + strlen(REFUSAL), refused = 1;
            free(line->category);
            line->category = NULL;
        }
        host_log(in, line->status, category_of(line->category, line->status), message);
        free(line->category), free(line->message);
    }
    in->n_lines = 0;
    return refused && status == fmi2Fatal ? fmi2Error : status;
}

/* Finding a Python --------------------------------------------------------------------------- */
typedef struct { char version[16], stdlib[4096], home[8192]; Text path, libs; char error[1024]; }
    Probe;

/* Run `python -c PROBE`; fill `probe` or its error. Returns 0 when the python is usable. */
static int ask_python(const char *python, Probe *probe) {
    char script[sizeof PROBE + 64];
    snprintf(script, sizeof script, PROBE, MIN_MINOR, MIN_MINOR);
    int fds[2];
    if (access(python, X_OK) != 0) {
        snprintf(probe->error, sizeof probe->error, "is not an executable file (%s)",
                 strerror(errno));
        return -1;
    }
    if (pipe2(fds, O_CLOEXEC) != 0) {
        snprintf(probe->error, sizeof probe->error, "cannot be run (pipe: %s)", strerror(errno));
        return -1;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    char *argv[] = {(char *)python, "-c", script, NULL};
    pid_t pid;
    int spawned = posix_spawn(&pid, python, &actions, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    close(fds[1]);
    if (spawned != 0) {
        close(fds[0]);
        snprintf(probe->error, sizeof probe->error, "cannot be run (%s)", strerror(spawned));
        return -1;
    }
    Text out = {0};
    char buffer[4096];
    ssize_t n;
    while ((n = read(fds[0], buffer, sizeof buffer)) > 0 || (n < 0 && errno == EINTR))
        if (n > 0) text_add(&out, buffer, (size_t)n);
    close(fds[0]);
    while (waitpid(pid, NULL, 0) < 0 && errno == EINTR) {}
    for (char *line = out.data, *end; line != NULL && *line; line = end + 1) {
        end = strchr(line, '\n');
        if (end == NULL) break;
        *end = '\0';
        char *value = strchr(line, ' ');
        if (value == NULL) continue;
        *value++ = '\0';
        if (strcmp(line, "error") == 0) snprintf(probe->error, sizeof probe->error, "%s", value);
        else if (strcmp(line, "version") == 0)
            snprintf(probe->version, sizeof probe->version, "%s", value);
        else if (strcmp(line, "stdlib") == 0)
            snprintf(probe->stdlib, sizeof probe->stdlib, "%s", value);
        else if (strcmp(line, "home") == 0) snprintf(probe->home, sizeof probe->home, "%s", value);
        else if (strcmp(line, "path") == 0) text_add(&probe->path, value, strlen(value));
        else if (strcmp(line, "lib") == 0) text_add(&probe->libs, value, strlen(value) + 1);
    }
    free(out.data);
    if (probe->error[0] == '\0' && (probe->version[0] == '\0' || probe->libs.len == 0))
        snprintf(probe->error, sizeof probe->error,
                 "did not answer as a Python 3 with a shared libpython does");
    return probe->error[0] == '\0' ? 0 : -1;
}

/* The first executable `name` in PATH, into `found`; 0 if there is one. */
static int find_on_path(const char *name, char *found, size_t size) {
    const char *path = getenv("PATH");
    for (const char *dir = path; dir != NULL && *dir; dir = strchr(dir, ':') ? strchr(dir, ':') + 1
                                                                              : NULL) {
        size_t len = strchr(dir, ':') ? (size_t)(strchr(dir, ':') - dir) : strlen(dir);
        if (len == 0) continue;
        snprintf(found, size, "%.*s/%s", (int)len, dir, name);
        if (access(found, X_OK) == 0) return 0;
    }
    return -1;
}

static void setenv_or_unset(const char *name, const char *value) {
    if (value != NULL) setenv(name, value, 1);
    else unsetenv(name);
}

/* Load the probed python's libpython globally and start its interpreter; 0 on success. */
static int start_python(const Probe *probe, char *error, size_t size) {
    void *lib = NULL;
    const char *candidate = probe->libs.data;
    for (; candidate < probe->libs.data + probe->libs.len; candidate += strlen(candidate) + 1)
        if ((lib = dlopen(candidate, RTLD_NOW | RTLD_GLOBAL)) != NULL) break;
    if (lib == NULL) {
        snprintf(error, size, "has no loadable shared libpython (tried %s ...)", probe->libs.data);
        return -1;
    }
    const char *(*get_version)(void) = (const char *(*)(void))dlsym(lib, "Py_GetVersion");
    void (*initialize)(int) = (void (*)(int))dlsym(lib, "Py_InitializeEx");
    int (*is_initialized)(void) = (int (*)(void))dlsym(lib, "Py_IsInitialized");
    void *(*save_thread)(void) = (void *(*)(void))dlsym(lib, "PyEval_SaveThread");
    if (!get_version || !initialize || !is_initialized || !save_thread
            || strncmp(get_version(), probe->version, strlen(probe->version)) != 0) {
        snprintf(error, size, "has a libpython %s that is not its own Python %s",
                 candidate, probe->version);
        return -1;
    }
    char os_py[4200];
    snprintf(os_py, sizeof os_py, "%s/os.py", probe->stdlib);
    if (access(os_py, R_OK) != 0) {
        snprintf(error, size, "has no standard library where it says (%s)", os_py);
        return -1;
    }
    if (is_initialized()) return 0;
    char *old_home = getenv("PYTHONHOME"), *old_path = getenv("PYTHONPATH");
    old_home = old_home ? strdup(old_home) : NULL, old_path = old_path ? strdup(old_path) : NULL;
    setenv("PYTHONHOME", probe->home, 1);
    setenv("PYTHONPATH", probe->path.data ? probe->path.data : "", 1);
    initialize(0);                    /* 0: the host's signal handlers stay as they are */
    setenv_or_unset("PYTHONHOME", old_home), setenv_or_unset("PYTHONPATH", old_path);
    free(old_home), free(old_path);
    save_thread();                    /* release the GIL: pythonfmu takes it per call */
    return 0;
}

/* Make a Python visible to pythonfmu's binary (the order of the header); 0 on success, else
 * one line for the host in `why`. */
static int ensure_python(Text *why) {
    int (*is_initialized)(void) = (int (*)(void))dlsym(RTLD_DEFAULT, "Py_IsInitialized");
    if (is_initialized != NULL && is_initialized()) return 0;      /* a Python host */
    const char *chosen = getenv(PYTHON_VARIABLE);
    char on_path[4096], error[2048] = "";
    Probe probe;
    memset(&probe, 0, sizeof probe);
    int ok;
    if (chosen != NULL && *chosen) {
        ok = ask_python(chosen, &probe) == 0 && start_python(&probe, error, sizeof error) == 0;
        if (!ok)
            text_printf(why, MODEL " cannot use the Python given by %s=%s: it %s. Set %s to "
                        "the python executable of a Python >= 3.%d with numpy (a virtual "
                        "environment's bin/python works).", PYTHON_VARIABLE, chosen,
                        error[0] ? error : probe.error, PYTHON_VARIABLE, MIN_MINOR);
    } else if (find_on_path("python3", on_path, sizeof on_path) == 0) {
        ok = ask_python(on_path, &probe) == 0 && start_python(&probe, error, sizeof error) == 0;
        if (!ok)
            text_printf(why, MODEL " needs a Python >= 3.%d with numpy: none is loaded in this "
                        "process, %s is not set, and python3 on PATH (%s) %s. Set %s to the "
                        "python executable of such a Python (a virtual environment's bin/python "
                        "works).", MIN_MINOR, PYTHON_VARIABLE, on_path,
                        error[0] ? error : probe.error, PYTHON_VARIABLE);
    } else {
        ok = 0;
        text_printf(why, MODEL " needs a Python >= 3.%d with numpy: none is loaded in this "
                    "process, %s is not set, and there is no python3 on PATH. Set %s to the "
                    "python executable of such a Python (a virtual environment's bin/python "
                    "works).", MIN_MINOR, PYTHON_VARIABLE, PYTHON_VARIABLE);
    }
    free(probe.path.data), free(probe.libs.data);
    return ok ? 0 : -1;
}

/* The exit guard -------------------------------------------------------------------------------- */
/* Virtual address of pythonfmu's pyState in the ELF file at `path`, or 0. */
static size_t pystate_address(const char *path) {
    size_t found = 0;
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0 || (size_t)st.st_size < sizeof(Elf64_Ehdr)) {
        if (fd >= 0) close(fd);
        return 0;
    }
    size_t size = (size_t)st.st_size;
    const unsigned char *elf = mmap(NULL, size, PROT_READ, MAP_PRIVATE, fd, 0);
    close(fd);
    if (elf == MAP_FAILED) return 0;
    const Elf64_Ehdr *eh = (const Elf64_Ehdr *)elf;
    if (memcmp(eh->e_ident, ELFMAG, SELFMAG) != 0 || eh->e_ident[EI_CLASS] != ELFCLASS64
            || eh->e_shentsize != sizeof(Elf64_Shdr)
            || eh->e_shoff + (size_t)eh->e_shnum * sizeof(Elf64_Shdr) > size) {
        munmap((void *)elf, size);
        return 0;
    }
    const Elf64_Shdr *sections = (const Elf64_Shdr *)(elf + eh->e_shoff);
    for (size_t s = 0; s < eh->e_shnum && !found; s++) {
        const Elf64_Shdr *sh = &sections[s];
        if (sh->sh_type != SHT_SYMTAB || sh->sh_link >= eh->e_shnum
                || sh->sh_offset + sh->sh_size > size || sh->sh_entsize != sizeof(Elf64_Sym))
            continue;
        const Elf64_Shdr *names = &sections[sh->sh_link];
        const Elf64_Sym *symbols = (const Elf64_Sym *)(elf + sh->sh_offset);
        for (size_t k = 0; k < sh->sh_size / sizeof(Elf64_Sym); k++) {
            size_t at = names->sh_offset + symbols[k].st_name;
            if (at + sizeof PYSTATE_SYMBOL <= names->sh_offset + names->sh_size && at < size
                    && memcmp(elf + at, PYSTATE_SYMBOL, sizeof PYSTATE_SYMBOL) == 0
                    && symbols[k].st_size == PYSTATE_SIZE) {
                found = symbols[k].st_value;
                break;
            }
        }
    }
    munmap((void *)elf, size);
    return found;
}

static void empty_pystate(void) {
    if (pystate != NULL) memset(pystate, 0, PYSTATE_SIZE);
}



/* Where the exit guard acts (pythonfmu's pyState), NULL when it is not armed. For tests.
 * (PipePlug_exitGuardTarget in PipePlug.so.) */
EXPORT void *JOINED(MODEL_IDENTIFIER, _exitGuardTarget)(void) { return pystate; }

/* Loading pythonfmu's binary ------------------------------------------------------------------ */
static int load_inner(Text *why) {
    Dl_info self;
    char path[4096];
    if (dladdr((void *)load_inner, &self) == 0 || self.dli_fname == NULL) {
        text_printf(why, MODEL " cannot find its own binary");
        return -1;
    }
    const char *slash = strrchr(self.dli_fname, '/');
    snprintf(path, sizeof path, "%.*s%s", slash ? (int)(slash - self.dli_fname + 1) : 0,
             self.dli_fname, INNER_BINARY);
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (lib == NULL) {
        text_printf(why, MODEL " cannot load %s: %s", path, dlerror());
        return -1;
    }
#define LOAD_POINTER(ret, name, args) \
    if ((*(void **)&inner.name = dlsym(lib, #name)) == NULL) { \
        text_printf(why, MODEL ": %s has no %s", path, #name); \
        return -1; \
    }
    INNER_FUNCTIONS(LOAD_POINTER)
    struct link_map *map;
    size_t address = pystate_address(path);
    if (address != 0 && dlinfo(lib, RTLD_DI_LINKMAP, &map) == 0) {
        pystate = (char *)map->l_addr + address;
        /* registered after pythonfmu's own exit handlers, so run before them */
        atexit(empty_pystate);    /* this library is linked nodelete: it is still there */
    }
    return 0;
}

/* The resource URI ------------------------------------------------------------------------ */
static int hex_digit(char c) {
    return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10
         : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
}

/* The directory of a file URI (file:///p, file:/p, file://localhost/p, %XX escapes) or of an
 * absolute path, as a plain path into `out`; -1 if `uri` is neither. */
static int resource_path(const char *uri, char *out, size_t size) {
    const char *p = uri;
    if (p == NULL) return -1;
    if (strncasecmp(p, "file:", 5) == 0) {
        p += 5;
        if (p[0] == '/' && p[1] == '/') {          /* an authority: empty or localhost */
            p += 2;
            if (strncasecmp(p, "localhost", 9) == 0 && (p[9] == '/' || p[9] == '\0')) p += 9;
            if (*p != '/') return -1;
        }
    }
    if (*p != '/') return -1;
    size_t n = 0;
    for (; *p && *p != '?' && *p != '#' && n + 1 < size; p++) {
        if (p[0] == '%' && hex_digit(p[1]) >= 0 && hex_digit(p[2]) >= 0) {
            out[n++] = (char)(hex_digit(p[1]) * 16 + hex_digit(p[2]));
            p += 2;
        } else {
            out[n++] = *p;
        }
    }
    out[n] = '\0';
    while (n > 1 && out[n - 1] == '/') out[--n] = '\0';
    return 0;
}

/* The resources directory next to this binary (binaries/linux64/ -> resources). */
static int own_resources(char *out, size_t size) {
    Dl_info self;
    if (dladdr((void *)own_resources, &self) == 0 || self.dli_fname == NULL) return -1;
    char *copy = realpath(self.dli_fname, NULL);
    if (copy == NULL) return -1;
    for (int up = 0; up < 3; up++) {
        char *slash = strrchr(copy, '/');
        if (slash != NULL) *slash = '\0';
    }
    snprintf(out, size, "%s/resources", copy);
    free(copy);
    return 0;
}

/* The URI given to pythonfmu: "file://" + the directory. pythonfmu strips that prefix, turns
 * every "%20" into a space and decodes nothing else (other spellings crash it). A directory
 * whose path holds "%20" itself is given as /proc/self/fd/N of a descriptor kept open for the
 * process's life (the slave's modules stay importable from it). */
static void pythonfmu_uri(const char *uri, char *out, size_t size) {
    char path[4096];
    if (resource_path(uri, path, sizeof path) != 0 && own_resources(path, sizeof path) != 0)
        snprintf(path, sizeof path, "%s", uri ? uri : "");
    int fd;
    if (strstr(path, "%20") != NULL
            && (fd = open(path, O_PATH | O_DIRECTORY | O_CLOEXEC)) >= 0)
        snprintf(path, sizeof path, "/proc/self/fd/%d", fd);
    snprintf(out, size, "file://%s", path);
}

/* The fmi2 functions ------------------------------------------------------------------------ */
EXPORT const char *fmi2GetTypesPlatform(void) { return "default"; }
EXPORT const char *fmi2GetVersion(void) { return "2.0"; }

EXPORT fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                                     fmi2String resources, const fmi2CallbackFunctions *functions,
                                     fmi2Boolean visible, fmi2Boolean logging_on) {
    if (functions == NULL) return NULL;
    Instance *in = calloc(1, sizeof *in);
    if (in == NULL) return NULL;
    in->host = *functions;
    in->name = strdup(name ? name : "");
    in->mine = (fmi2CallbackFunctions){buffer_line, functions->allocateMemory,
                                        functions->freeMemory, NULL, in};
    Text why = {0};
    pthread_mutex_lock(&load_lock);
    int ready = loaded || (ensure_python(&why) == 0 && load_inner(&why) == 0);
    loaded = ready;
    pthread_mutex_unlock(&load_lock);
    if (ready) {
        char uri[8192];
        pythonfmu_uri(resources, uri, sizeof uri);
        in->inner = inner.fmi2Instantiate(name, type, guid, uri, &in->mine, visible, logging_on);
        finish(in, fmi2OK);
    } else {
        host_log(in, fmi2Error, "logStatusError", why.data ? why.data : MODEL " cannot start");
    }
    free(why.data);
    if (in->inner == NULL) {
        free(in->lines), free(in->name), free(in);
        return NULL;
    }
    return in;
}

EXPORT void fmi2FreeInstance(fmi2Component c) {
    Instance *in = c;
    if (in == NULL) return;
    inner.fmi2FreeInstance(in->inner);
    finish(in, fmi2OK);
    free(in->lines), free(in->name), free(in);
}

/* Forward a call of instance `c` and finish it (a NULL instance is an error). */
#define FORWARD(name, ...) \
    Instance *in = c; \
    if (in == NULL) return fmi2Error; \
    return finish(in, inner.name(in->inner, __VA_ARGS__))
#define FORWARD0(name) \
    Instance *in = c; \
    if (in == NULL) return fmi2Error; \
    return finish(in, inner.name(in->inner))

EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n,
                                      const fmi2String categories[]) {
    FORWARD(fmi2SetDebugLogging, on, n, categories);
}
EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolerance_defined,
                                      fmi2Real tolerance, fmi2Real start,
                                      fmi2Boolean stop_defined, fmi2Real stop) {
    FORWARD(fmi2SetupExperiment, tolerance_defined, tolerance, start, stop_defined, stop);
}
EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    FORWARD0(fmi2EnterInitializationMode);
}
EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    FORWARD0(fmi2ExitInitializationMode);
}
EXPORT fmi2Status fmi2Terminate(fmi2Component c) { FORWARD0(fmi2Terminate); }
EXPORT fmi2Status fmi2Reset(fmi2Component c) { FORWARD0(fmi2Reset); }

#define GETTER_SETTER(name, type) \
    EXPORT fmi2Status name(fmi2Component c, const fmi2ValueReference vr[], size_t n, \
                           type values[]) { FORWARD(name, vr, n, values); }
GETTER_SETTER(fmi2GetReal, fmi2Real)
GETTER_SETTER(fmi2GetInteger, fmi2Integer)
GETTER_SETTER(fmi2GetBoolean, fmi2Boolean)
GETTER_SETTER(fmi2GetString, fmi2String)
GETTER_SETTER(fmi2SetReal, const fmi2Real)
GETTER_SETTER(fmi2SetInteger, const fmi2Integer)
GETTER_SETTER(fmi2SetBoolean, const fmi2Boolean)
GETTER_SETTER(fmi2SetString, const fmi2String)

EXPORT fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state) {
    FORWARD(fmi2GetFMUstate, state);
}
EXPORT fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state) {
    FORWARD(fmi2SetFMUstate, state);
}
EXPORT fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state) {
    FORWARD(fmi2FreeFMUstate, state);
}
EXPORT fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t *size) {
    FORWARD(fmi2SerializedFMUstateSize, state, size);
}
EXPORT fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state, fmi2Byte bytes[],
                                        size_t size) {
    FORWARD(fmi2SerializeFMUstate, state, bytes, size);
}
EXPORT fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size,
                                          fmi2FMUstate *state) {
    FORWARD(fmi2DeSerializeFMUstate, bytes, size, state);
}
EXPORT fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[],
                                               size_t nu, const fmi2ValueReference z[],
                                               size_t nz, const fmi2Real du[], fmi2Real dz[]) {
    FORWARD(fmi2GetDirectionalDerivative, u, nu, z, nz, du, dz);
}
EXPORT fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                              size_t n, const fmi2Integer order[],
                                              const fmi2Real values[]) {
    FORWARD(fmi2SetRealInputDerivatives, vr, n, order, values);
}
EXPORT fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                               size_t n, const fmi2Integer order[],
                                               fmi2Real values[]) {
    FORWARD(fmi2GetRealOutputDerivatives, vr, n, order, values);
}
EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean no_set_prior) {
    FORWARD(fmi2DoStep, t, h, no_set_prior);
}
EXPORT fmi2Status fmi2CancelStep(fmi2Component c) { FORWARD0(fmi2CancelStep); }

#define STATUS_QUERY(name, type) \
    EXPORT fmi2Status name(fmi2Component c, const fmi2StatusKind kind, type *value) { \
        FORWARD(name, kind, value); \
    }
STATUS_QUERY(fmi2GetStatus, fmi2Status)
STATUS_QUERY(fmi2GetRealStatus, fmi2Real)
STATUS_QUERY(fmi2GetIntegerStatus, fmi2Integer)
STATUS_QUERY(fmi2GetBooleanStatus, fmi2Boolean)
STATUS_QUERY(fmi2GetStringStatus, fmi2String)
