/* Finding a Python for pythonfmu's binary (see loader.c, steps 1-3 of the header).
 *
 * The python named by PIPEPLUG_PYTHON, or python3 on PATH, is asked once, in a child process
 * of its own process group, where its shared libpython, standard library and module path are.
 * The child gets PIPEPLUG_PYTHON_TIMEOUT seconds (default 60) and may print at most
 * PROBE_LIMIT bytes; past either it is killed with its group and the python is not used.
 */
#include "loader.h"

#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

extern char **environ;

#define MIN_MINOR 10                       /* Python 3.10 or newer */
#define PROBE_LIMIT (1 << 20)              /* bytes a python may print when asked */
#define DEFAULT_TIMEOUT 60.0               /* seconds it may take to answer */

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

/* Finding a Python --------------------------------------------------------------------------- */
typedef struct { char version[16], stdlib[4096], home[8192]; Text path, libs; char error[1024]; }
    Probe;

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Seconds a python may take to answer: PIPEPLUG_PYTHON_TIMEOUT, else DEFAULT_TIMEOUT. */
static double probe_timeout(void) {
    const char *given = getenv(TIMEOUT_VARIABLE);
    char *end;
    double seconds = given ? strtod(given, &end) : 0.0;
    return given && end != given && seconds > 0.0 && seconds < 1e6 ? seconds : DEFAULT_TIMEOUT;
}

/* Start `python -c script` in a process group of its own, its stdout into a pipe whose read
 * end goes to *fd; its pid, or -1 with the reason in `error`. */
static pid_t spawn_probe(const char *python, char *script, int *fd, char *error, size_t size) {
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) {
        snprintf(error, size, "cannot be run (pipe: %s)", strerror(errno));
        return -1;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawnattr_t attributes;               /* its own group: killed with its children */
    posix_spawnattr_init(&attributes);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attributes, 0);
    char *argv[] = {(char *)python, "-c", script, NULL};
    pid_t pid;
    int spawned = posix_spawn(&pid, python, &actions, &attributes, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    close(fds[1]);
    if (spawned != 0) {
        close(fds[0]);
        snprintf(error, size, "cannot be run (%s)", strerror(spawned));
        return -1;
    }
    *fd = fds[0];
    return pid;
}

/* Read the child's output into `out` until it closes it, the deadline passes or it has printed
 * more than PROBE_LIMIT bytes; 0, or -1 with the reason in `error`. */
static int read_probe(int fd, double deadline, Text *out, char *error, size_t size) {
    char buffer[4096];
    for (;;) {
        double left = deadline - now();
        if (left <= 0.0) {
            snprintf(error, size, "did not answer within %g s (it was stopped; %s sets the "
                     "time allowed)", probe_timeout(), TIMEOUT_VARIABLE);
            return -1;
        }
        struct pollfd wait = {fd, POLLIN, 0};
        int ready = poll(&wait, 1, (int)(left * 1000.0) + 1);
        if (ready < 0 && errno != EINTR) {
            snprintf(error, size, "cannot be read (%s)", strerror(errno));
            return -1;
        }
        if (ready <= 0) continue;
        ssize_t n = read(fd, buffer, sizeof buffer);
        if (n == 0) return 0;
        if (n < 0) {
            if (errno == EINTR || errno == EAGAIN) continue;
            snprintf(error, size, "cannot be read (%s)", strerror(errno));
            return -1;
        }
        if (out->len + (size_t)n > PROBE_LIMIT) {
            snprintf(error, size, "printed more than %d bytes when asked where its libpython "
                     "is (it was stopped)", PROBE_LIMIT);
            return -1;
        }
        text_add(out, buffer, (size_t)n);
    }
}

/* Wait for the child until the deadline, then kill its group; never blocks past it. */
static void reap_probe(pid_t pid, double deadline, int kill_now) {
    for (;;) {
        pid_t done = waitpid(pid, NULL, WNOHANG);
        if (done == pid || (done < 0 && errno != EINTR)) return;   /* ended (or reaped) */
        if (kill_now || now() >= deadline) {
            kill(-pid, SIGKILL);
            while (waitpid(pid, NULL, 0) < 0 && errno == EINTR) {}
            return;
        }
        struct timespec pause = {0, 10 * 1000 * 1000};
        nanosleep(&pause, NULL);
    }
}

/* Run `python -c PROBE`; fill `probe` or its error. Returns 0 when the python is usable. */
static int ask_python(const char *python, Probe *probe) {
    char script[sizeof PROBE + 64];
    snprintf(script, sizeof script, PROBE, MIN_MINOR, MIN_MINOR);
    if (access(python, X_OK) != 0) {
        snprintf(probe->error, sizeof probe->error, "is not an executable file (%s)",
                 strerror(errno));
        return -1;
    }
    int fd;
    double deadline = now() + probe_timeout();
    pid_t pid = spawn_probe(python, script, &fd, probe->error, sizeof probe->error);
    if (pid < 0) return -1;
    Text out = {0};
    int read_all = read_probe(fd, deadline, &out, probe->error, sizeof probe->error) == 0;
    close(fd);
    reap_probe(pid, deadline, !read_all);
    if (!read_all) {
        free(out.data);
        return -1;
    }
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
int ensure_python(Text *why) {
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
