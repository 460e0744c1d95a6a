/* A host with no Python in its process: loads an FMI 2.0 co-simulation FMU's binary, sets real
 * values, steps it and prints one real output after each step (tests/fmu/test_c_host.py).
 *
 * usage: fmi2_host BINARY RESOURCE_URI GUID STEP STEPS OUTPUT_VR [VR=VALUE ...]
 * prints: one line "time value" per step, %.17g (the bits, read back by the test)
 */
#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include "fmi2Functions.h"

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status,
                   fmi2String category, fmi2String message, ...)
{
    va_list args;
    va_start(args, message);
    fprintf(stderr, "[%s] %s: ", name ? name : "", category ? category : "");
    vfprintf(stderr, message, args);
    fprintf(stderr, "\n");
    va_end(args);
}

#define LOAD(name) \
    fmi2##name##TYPE *name = (fmi2##name##TYPE *)dlsym(lib, "fmi2" #name); \
    if (name == NULL) { fprintf(stderr, "no fmi2%s\n", #name); return 2; }

#define CHECK(call) \
    if ((call) > fmi2Warning) { fprintf(stderr, "%s failed\n", #call); return 3; }

int main(int argc, char *argv[])
{
    if (argc < 7) {
        fprintf(stderr, "usage: %s BINARY RESOURCE_URI GUID STEP STEPS OUTPUT_VR [VR=VALUE...]\n",
                argv[0]);
        return 1;
    }
    void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (lib == NULL) {
        fprintf(stderr, "Loading shared object failed: %s\n", dlerror());
        return 2;
    }
    LOAD(Instantiate) LOAD(SetupExperiment) LOAD(EnterInitializationMode)
    LOAD(ExitInitializationMode) LOAD(SetReal) LOAD(GetReal) LOAD(DoStep) LOAD(Terminate)
    LOAD(FreeInstance)

    fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
    fmi2Component c = Instantiate("host", fmi2CoSimulation, argv[3], argv[2], &callbacks,
                                  fmi2False, fmi2False);
    if (c == NULL) {
        fprintf(stderr, "fmi2Instantiate failed\n");
        return 3;
    }
    double step = atof(argv[4]);
    long steps = atol(argv[5]);
    fmi2ValueReference output = (fmi2ValueReference)atol(argv[6]);
    for (int i = 7; i < argc; i++) {
        fmi2ValueReference vr;
        double value;
        if (sscanf(argv[i], "%u=%lf", &vr, &value) != 2) {
            fprintf(stderr, "not VR=VALUE: %s\n", argv[i]);
            return 1;
        }
        CHECK(SetReal(c, &vr, 1, &value))
    }
    CHECK(SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0))
    CHECK(EnterInitializationMode(c))
    CHECK(ExitInitializationMode(c))
    double time = 0.0, value;
    for (long k = 0; k < steps; k++) {
        CHECK(DoStep(c, time, step, fmi2True))
        time = (double)(k + 1) * step;  /* on the grid, as musclesim's master and FMPy step */
        CHECK(GetReal(c, &output, 1, &value))
        printf("%.17g %.17g\n", time, value);
    }
    CHECK(Terminate(c))
    FreeInstance(c);
    return 0;
}
