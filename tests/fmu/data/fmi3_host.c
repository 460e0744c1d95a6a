/* A host with no Python in its process: loads an FMI 3.0 co-simulation FMU's binary, sets
 * Float64 values, steps it and prints one Float64 output after each step
 * (tests/fmu/test_c_host.py; fmi2_host.c is its FMI 2.0 twin).
 *
 * usage: fmi3_host BINARY RESOURCE_PATH TOKEN STEP STEPS OUTPUT_VR [VR=VALUE ...]
 * prints: one line "time value" per step, %.17g (the bits, read back by the test)
 */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>

#include "fmi3Functions.h"

static void logger(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category,
                   fmi3String message)
{
    fprintf(stderr, "%s: %s\n", category ? category : "", message ? message : "");
}

#define LOAD(name) \
    fmi3##name##TYPE *name = (fmi3##name##TYPE *)dlsym(lib, "fmi3" #name); \
    if (name == NULL) { fprintf(stderr, "no fmi3%s\n", #name); return 2; }

#define CHECK(call) \
    if ((call) > fmi3Warning) { fprintf(stderr, "%s failed\n", #call); return 3; }

int main(int argc, char *argv[])
{
    if (argc < 7) {
        fprintf(stderr, "usage: %s BINARY RESOURCE_PATH TOKEN STEP STEPS OUTPUT_VR "
                "[VR=VALUE...]\n", argv[0]);
        return 1;
    }
    void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (lib == NULL) {
        fprintf(stderr, "Loading shared object failed: %s\n", dlerror());
        return 2;
    }
    LOAD(InstantiateCoSimulation) LOAD(EnterInitializationMode) LOAD(ExitInitializationMode)
    LOAD(SetFloat64) LOAD(GetFloat64) LOAD(DoStep) LOAD(Terminate) LOAD(FreeInstance)

    fmi3Instance c = InstantiateCoSimulation("host", argv[3], argv[2], fmi3False, fmi3False,
                                             fmi3False, fmi3False, NULL, 0, NULL, logger, NULL);
    if (c == NULL) {
        fprintf(stderr, "fmi3InstantiateCoSimulation failed\n");
        return 3;
    }
    double step = atof(argv[4]);
    long steps = atol(argv[5]);
    fmi3ValueReference output = (fmi3ValueReference)atol(argv[6]);
    for (int i = 7; i < argc; i++) {
        fmi3ValueReference vr;
        double value;
        if (sscanf(argv[i], "%u=%lf", &vr, &value) != 2) {
            fprintf(stderr, "not VR=VALUE: %s\n", argv[i]);
            return 1;
        }
        CHECK(SetFloat64(c, &vr, 1, &value, 1))
    }
    CHECK(EnterInitializationMode(c, fmi3False, 0.0, 0.0, fmi3False, 0.0))
    CHECK(ExitInitializationMode(c))
    double time = 0.0, value, last;
    fmi3Boolean event, terminate, early;
    for (long k = 0; k < steps; k++) {
        CHECK(DoStep(c, time, step, fmi3True, &event, &terminate, &early, &last))
        time = (double)(k + 1) * step;  /* on the grid, as musclesim's master and FMPy step */
        CHECK(GetFloat64(c, &output, 1, &value, 1))
        printf("%.17g %.17g\n", time, value);
    }
    CHECK(Terminate(c))
    FreeInstance(c);
    return 0;
}
