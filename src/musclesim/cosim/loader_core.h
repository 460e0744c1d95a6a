/* What the FMUs' loaders share (fmi2_loader.c, fmi3_loader.c): starting the build interpreter in
 * a process without Python, and loading the binary forwarded to. A loader defines
 * resolve_real(lib, path), which looks its functions up in that binary, before including this.
 *
 * loader_config.h (written per build by musclesim.cosim.loader) defines MUSCLESIM_REAL_SUFFIX
 * (the binary forwarded to is <this binary without .so><suffix>) and either MUSCLESIM_LIBPYTHON,
 * MUSCLESIM_PYTHONHOME and MUSCLESIM_SITE_SCRIPT (Python run once after initialisation: the
 * build environment's site folders), or MUSCLESIM_GRID_STEP (no Python: fmi2_loader.c in front
 * of a container runtime).
 */
#ifndef MUSCLESIM_LOADER_CORE_H
#define MUSCLESIM_LOADER_CORE_H

#define _GNU_SOURCE
#include "loader_config.h"
#ifndef MUSCLESIM_GRID_STEP
#include <Python.h>
#endif
#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static void *real;          /* the binary forwarded to, once loaded (never unloaded) */
static char failure[8192];  /* why loading failed, for the host's logger */
static long live;           /* instances not yet freed */
/* pythonfmu 0.7 (and pythonfmu3 0.3) resets its interpreter handle at exit from an ELF
   destructor that runs after the handle's own C++ destructor: a use-after-free that aborts the
   host as it ends ("free(): corrupted unsorted chunks"). The handle never owns the interpreter
   behind a loader (Python was running before pythonfmu's binary loaded), so resetting it once
   the last instance is freed (release_instance) is safe and makes both later resets no-ops. */
static void (*real_finalize)(void);

/* Look up `name` in `lib` (`what`, for the message), or record why not. */
#define FIND(var, lib, what, name) \
    ((*(void **)&(var) = dlsym((lib), (name))) != NULL \
     || (snprintf(failure, sizeof failure, "%s has no %s", (what), (name)), 0))

static int resolve_real(void *lib, const char *path);  /* the loader's own: 0 on success */

#ifdef MUSCLESIM_GRID_STEP
static int start_python(void) { return 0; }  /* the container's FMUs start their own */
#else
/* Start the build interpreter in a process that has none; 0 on success. */
static int start_python(void)
{
    if (dlsym(RTLD_DEFAULT, "Py_IsInitialized") != NULL)
        return 0;  /* the host's (or an earlier FMU's) Python: pythonfmu uses it as it is */
    void *py = dlopen(MUSCLESIM_LIBPYTHON, RTLD_NOW | RTLD_GLOBAL);
    if (py == NULL) {
        snprintf(failure, sizeof failure, "cannot load the Python this FMU was built with "
                 "(%s): %s", MUSCLESIM_LIBPYTHON, dlerror());
        return -1;
    }
    __typeof__(PyConfig_InitPythonConfig) *init_config;
    __typeof__(PyConfig_SetBytesString) *set_string;
    __typeof__(Py_InitializeFromConfig) *initialize;
    __typeof__(PyConfig_Clear) *clear;
    __typeof__(PyStatus_Exception) *failed;
    __typeof__(PyRun_SimpleString) *run;
    __typeof__(PyEval_SaveThread) *release_gil;
    const char *lp = MUSCLESIM_LIBPYTHON;
    if (!(FIND(init_config, py, lp, "PyConfig_InitPythonConfig")
          && FIND(set_string, py, lp, "PyConfig_SetBytesString")
          && FIND(initialize, py, lp, "Py_InitializeFromConfig")
          && FIND(clear, py, lp, "PyConfig_Clear") && FIND(failed, py, lp, "PyStatus_Exception")
          && FIND(run, py, lp, "PyRun_SimpleString")
          && FIND(release_gil, py, lp, "PyEval_SaveThread")))
        return -1;
    PyConfig config;
    init_config(&config);
    config.install_signal_handlers = 0;  /* the host's signals stay the host's */
    PyStatus status = set_string(&config, &config.home, MUSCLESIM_PYTHONHOME);
    if (!failed(status))
        status = initialize(&config);
    clear(&config);
    if (failed(status)) {
        snprintf(failure, sizeof failure, "cannot start the Python at %s: %s",
                 MUSCLESIM_PYTHONHOME, status.err_msg ? status.err_msg : "no reason given");
        return -1;
    }
    if (run(MUSCLESIM_SITE_SCRIPT) != 0) {
        snprintf(failure, sizeof failure, "the Python at %s failed to add the build "
                 "environment's site-packages", MUSCLESIM_PYTHONHOME);
        return -1;
    }
    release_gil();  /* pythonfmu takes the GIL per call, from whichever thread the host calls */
    return 0;
}
#endif

/* Load pythonfmu's binary, the file beside this one named <this name without .so><suffix>. */
static int load_real(void)
{
    Dl_info self;
    if (!dladdr((void *)&load_real, &self) || self.dli_fname == NULL) {
        snprintf(failure, sizeof failure, "cannot tell where this FMU's binary is");
        return -1;
    }
    char path[4096];
    size_t stem = strlen(self.dli_fname);
    if (stem > 3 && strcmp(self.dli_fname + stem - 3, ".so") == 0)
        stem -= 3;
    if (snprintf(path, sizeof path, "%.*s%s", (int)stem, self.dli_fname, MUSCLESIM_REAL_SUFFIX)
        >= (int)sizeof path) {
        snprintf(failure, sizeof failure, "the path of this FMU's binary is too long");
        return -1;
    }
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (lib == NULL) {
        snprintf(failure, sizeof failure, "cannot load pythonfmu's binary: %s", dlerror());
        return -1;
    }
    if (resolve_real(lib, path) != 0)
        return -1;
    *(void **)&real_finalize = dlsym(lib, "finalizePythonInterpreter");
    real = lib;
    return 0;
}

static int ready(void)
{
    pthread_mutex_lock(&lock);
    int ok = real != NULL || (start_python() == 0 && load_real() == 0);
    pthread_mutex_unlock(&lock);
    return ok;
}

/* Count an instance made (`made`) or freed; the last one freed resets pythonfmu's handle. */
static void count_instance(int made)
{
    pthread_mutex_lock(&lock);
    live += made ? 1 : -1;
    if (!made && live == 0 && real_finalize != NULL)
        real_finalize();
    pthread_mutex_unlock(&lock);
}

#endif
