/* The resource folder given to pythonfmu (pythonfmu07 P8).
 *
 * pythonfmu deletes "file://" from the URI, turns every "%20" into a space and decodes nothing
 * else; a folder without the slave's files makes it call a NULL class. So the loader decodes the
 * host's URI itself (file:///p, file:/p, file://localhost/p, %XX escapes, or an absolute path),
 * checks that the folder holds this build's resources (the slavemodule.txt of the resources
 * beside this binary, and the script it names) and gives pythonfmu "file://" + that folder; a
 * folder whose path pythonfmu would misread ("%20" in it, or bytes that are not UTF-8) as
 * /proc/self/fd/N of a descriptor kept open for the process's life. A NULL location, or one that
 * is neither a file URI nor an absolute path (a relative path, another scheme), means the
 * resources beside this binary. A malformed or too long file URI, or a folder without this
 * build's resources, is refused with one line. FMI 3.0 gives a path (resourcePath), not a URI:
 * an absolute path is taken as it is (no %XX decoding); a file URI is still understood.
 */
#include "loader.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

uint64_t build_identity;

static int hex_digit(char c) {
    return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10
         : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
}

/* The path of a file URI or absolute path `uri`, decoded into `out`: 0; 1 when `uri` is
 * neither (the FMU's own resources are meant); -1 with what is wrong in `wrong`. */
static int decoded_path(const char *uri, char *out, size_t size, const char **wrong) {
    const char *p = uri;
    if (strncasecmp(p, "file:", 5) == 0) {
        p += 5;
        if (p[0] == '/' && p[1] == '/') {          /* an authority: empty or localhost */
            p += 2;
            if (strncasecmp(p, "localhost", 9) == 0 && (p[9] == '/' || p[9] == '\0')) p += 9;
            if (*p != '/') {
                *wrong = "a file URI of this machine (no host name)";
                return -1;
            }
        }
        if (*p != '/') {
            *wrong = "a file URI with an absolute path";
            return -1;
        }
    } else if (*p != '/') {
        return 1;
    } else if (FMI_VERSION == 3) {             /* FMI 3.0: a path, taken as it is */
        if (strlen(p) + 1 > size) {
            *wrong = "an absolute path shorter than 4096 bytes";
            return -1;
        }
        strcpy(out, p);
        size_t n = strlen(out);
        while (n > 1 && out[n - 1] == '/') out[--n] = '\0';
        return 0;
    }
    size_t n = 0;
    for (; *p && *p != '?' && *p != '#'; p++) {
        char c = *p;
        if (c == '%') {
            if (hex_digit(p[1]) < 0 || hex_digit(p[2]) < 0
                    || (c = (char)(hex_digit(p[1]) * 16 + hex_digit(p[2]))) == '\0') {
                *wrong = "a file URI whose %-escapes are two hexadecimal digits (not %00)";
                return -1;
            }
            p += 2;
        }
        if (n + 1 >= size) {
            *wrong = "a file URI of a folder path shorter than 4096 bytes";
            return -1;
        }
        out[n++] = c;
    }
    out[n] = '\0';
    while (n > 1 && out[n - 1] == '/') out[--n] = '\0';
    return 0;
}

/* The resources folder next to this binary (binaries/linux64/ -> resources); 0 if found. */
static int own_resources(char *out, size_t size) {
    Dl_info self;
    if (dladdr((void *)own_resources, &self) == 0 || self.dli_fname == NULL) return -1;
    char *copy = realpath(self.dli_fname, NULL);
    if (copy == NULL) return -1;
    for (int up = 0; up < 3; up++) {
        char *slash = strrchr(copy, '/');
        if (slash != NULL) *slash = '\0';
    }
    int fits = snprintf(out, size, "%s/resources", copy) < (int)size;
    free(copy);
    return fits ? 0 : -1;
}

/* The first line of `folder`/slavemodule.txt (the slave script's module) into `module`; 0 if
 * it names a script that exists there. */
static int slave_module(const char *folder, char *module, size_t size) {
    char path[MAX_PATH_LENGTH + 64];
    snprintf(path, sizeof path, "%s/slavemodule.txt", folder);
    FILE *file = fopen(path, "r");
    if (file == NULL) return -1;
    int read = fgets(module, (int)size, file) != NULL;
    fclose(file);
    if (!read) return -1;
    module[strcspn(module, "\r\n")] = '\0';
    snprintf(path, sizeof path, "%s/%s.py", folder, module);
    return module[0] != '\0' && access(path, R_OK) == 0 ? 0 : -1;
}

/* Refuse `location`: one line naming it, why, and what is allowed. */
static int refused(Text *why, const char *location, const char *allowed) {
    text_printf(why, RESOURCE_ARGUMENT " = ");
    text_shown(why, location, strlen(location), 200);
    text_printf(why, " is not allowed; allowed: %s (" RESOURCE_SPELLING "; NULL for the "
                "resources beside this binary)", allowed);
    return -1;
}

int resource_uri(const char *location, char *uri, size_t size, Text *why) {
    char folder[MAX_PATH_LENGTH], own[MAX_PATH_LENGTH], module[512], own_module[512];
    const char *wrong = NULL;
    int have_own = own_resources(own, sizeof own) == 0
                   && slave_module(own, own_module, sizeof own_module) == 0;
    int kind = location == NULL ? 1 : decoded_path(location, folder, sizeof folder, &wrong);
    if (kind < 0) return refused(why, location, wrong);
    if (kind == 1) {
        if (!have_own) {
            text_printf(why, MODEL " cannot find its resources beside its binary; give their "
                        "folder as " RESOURCE_ARGUMENT " (" RESOURCE_EXAMPLE ")");
            return -1;
        }
        snprintf(folder, sizeof folder, "%s", own);
    }
    if (slave_module(folder, module, sizeof module) != 0
            || (have_own && strcmp(module, own_module) != 0))
        return refused(why, location ? location : folder,
                       "a folder holding the resources of this " MODEL " build");
    build_identity = fnv1a(fnv1a(FNV_START, MODEL, sizeof MODEL), module, strlen(module));
    int fd;
    if ((strstr(folder, "%20") != NULL || !utf8_valid(folder))
            && (fd = open(folder, O_PATH | O_DIRECTORY | O_CLOEXEC)) >= 0)
        snprintf(folder, sizeof folder, "/proc/self/fd/%d", fd);
    snprintf(uri, size, "file://%s", folder);
    return 0;
}
