/* pythonfmu's binary beside the loader: loading it (once per process), and the exit guard.
 *
 * Exit guard: pythonfmu's binary releases its interpreter state (a global shared_ptr, pyState)
 * twice at exit: the C++ exit handler destroys it, then an ELF destructor resets it again,
 * writing into freed heap. An exit handler registered after that binary is loaded runs before
 * its C++ exit handler and empties the pointer, so both releases do nothing.
 */
#include "loader.h"

#include <dlfcn.h>
#include <elf.h>
#include <fcntl.h>
#include <link.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#define PYSTATE_SYMBOL "_ZN12_GLOBAL__N_17pyStateE"   /* (anonymous namespace)::pyState */
#define PYSTATE_SIZE 16                    /* a shared_ptr: object pointer, control block */

InnerFunctions inner;
static void *pystate;                      /* pythonfmu's pyState, emptied at exit */

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
/* Load pythonfmu's binary beside this one into `inner`; 0 on success, else a line in `why`. */
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

static pthread_mutex_t load_lock = PTHREAD_MUTEX_INITIALIZER;
static int loaded;                          /* inner is complete */

int inner_ready(const Instance *in) {
    Text why = {0};
    pthread_mutex_lock(&load_lock);
    int ready = loaded || (ensure_python(&why) == 0 && load_inner(&why) == 0);
    loaded = ready;
    pthread_mutex_unlock(&load_lock);
    if (!ready) host_log(in, ST_ERROR, why.data ? why.data : MODEL " cannot start");
    free(why.data);
    return ready;
}
