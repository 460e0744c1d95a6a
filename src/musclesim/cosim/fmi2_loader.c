/* The Linux binary of a musclesim FMI 2.0 FMU: starts the Python interpreter the FMU was built
 * with when the host process has none, then loads pythonfmu's binary (beside this one) and
 * forwards every FMI 2.0 call to it unchanged.
 *
 * pythonfmu's binary is not linked to libpython: it expects the host to have Python in its
 * process (FMPy, libcosimpy) and fails to load elsewhere (undefined symbol _Py_NoneStruct). This
 * binary needs no libpython to load; at fmi2Instantiate, in a process without Python, it loads
 * the build interpreter's libpython with its symbols global (pythonfmu's binary and numpy's
 * extensions resolve against them) and initialises it with that interpreter's prefix as its home
 * (an embedded interpreter would otherwise look for its standard library beside the host's
 * executable) and the build environment's site-packages on its path. A process that already has
 * Python (a Python host, or another musclesim FMU loaded first) is left as it is: pythonfmu's
 * binary finds that interpreter as it always did, and every value is the same.
 *
 * The same file, compiled with MUSCLESIM_GRID_STEP, goes in front of FMPy's container runtime in
 * a scenario exported as one FMU (musclesim.export.container): no Python there (the FMUs inside
 * start their own), but a host's clock that drifted from the container's fixed-step grid is
 * put back on it (see fmi2DoStep below).
 *
 * musclesim.cosim.loader compiles this file with loader_config.h (see loader_core.h).
 */
#include "loader_core.h"

#include <math.h>

#include "fmi2Functions.h"

#define REAL_FUNCTIONS(X) \
    X(SetDebugLogging) X(Instantiate) X(FreeInstance) X(SetupExperiment) \
    X(EnterInitializationMode) X(ExitInitializationMode) X(Terminate) X(Reset) \
    X(GetReal) X(GetInteger) X(GetBoolean) X(GetString) \
    X(SetReal) X(SetInteger) X(SetBoolean) X(SetString) \
    X(GetFMUstate) X(SetFMUstate) X(FreeFMUstate) X(SerializedFMUstateSize) \
    X(SerializeFMUstate) X(DeSerializeFMUstate) X(GetDirectionalDerivative) \
    X(SetRealInputDerivatives) X(GetRealOutputDerivatives) X(DoStep) X(CancelStep) \
    X(GetStatus) X(GetRealStatus) X(GetIntegerStatus) X(GetBooleanStatus) X(GetStringStatus)

#define DECLARE(name) static fmi2##name##TYPE *real_##name;
REAL_FUNCTIONS(DECLARE)

static int resolve_real(void *lib, const char *path)
{
#define RESOLVE(name) if (!FIND(real_##name, lib, path, "fmi2" #name)) return -1;
    REAL_FUNCTIONS(RESOLVE)
    return 0;
}

#ifdef MUSCLESIM_GRID_STEP
/* The grid of each instance: its start time and the fixed steps taken, as the runtime counts
   them (its time is start + steps * fixed step). */
#define MAX_INSTANCES 64
static struct { fmi2Component c; double start; long long steps; } grid[MAX_INSTANCES];

static int grid_slot(fmi2Component c)  /* the instance's slot, a free one for a new instance */
{
    int free_slot = -1;
    for (int i = 0; i < MAX_INSTANCES; i++) {
        if (grid[i].c == c)
            return i;
        if (grid[i].c == NULL && free_slot < 0)
            free_slot = i;
    }
    if (free_slot >= 0) {
        grid[free_slot].c = c;
        grid[free_slot].start = 0.0;
        grid[free_slot].steps = 0;
    }
    return free_slot;
}
#endif

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation,
                              const fmi2CallbackFunctions *functions, fmi2Boolean visible,
                              fmi2Boolean loggingOn)
{
    if (!ready()) {
        if (functions != NULL && functions->logger != NULL)
            functions->logger(functions->componentEnvironment, instanceName, fmi2Error,
                              "logStatusError", "%s", failure);
        else
            fprintf(stderr, "%s: %s\n", instanceName ? instanceName : "FMU", failure);
        return NULL;
    }
    fmi2Component c = real_Instantiate(instanceName, fmuType, fmuGUID, fmuResourceLocation,
                                       functions, visible, loggingOn);
    if (c != NULL)
        count_instance(1);
    return c;
}

/* The other calls take an instance, so pythonfmu's binary is loaded by then. */
fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[])
{ return real_SetDebugLogging(c, loggingOn, nCategories, categories); }

void fmi2FreeInstance(fmi2Component c)
{
    if (c == NULL)
        return;
    real_FreeInstance(c);
#ifdef MUSCLESIM_GRID_STEP
    pthread_mutex_lock(&lock);
    for (int i = 0; i < MAX_INSTANCES; i++)
        if (grid[i].c == c)
            grid[i].c = NULL;
    pthread_mutex_unlock(&lock);
#endif
    count_instance(0);
}


fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined,
                               fmi2Real tolerance, fmi2Real startTime,
                               fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
#ifdef MUSCLESIM_GRID_STEP
    pthread_mutex_lock(&lock);
    int i = grid_slot(c);
    if (i >= 0) {
        grid[i].start = startTime;
        grid[i].steps = 0;
    }
    pthread_mutex_unlock(&lock);
#endif
    return real_SetupExperiment(c, toleranceDefined, tolerance, startTime, stopTimeDefined,
                                stopTime);
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) { return real_EnterInitializationMode(c); }

fmi2Status fmi2ExitInitializationMode(fmi2Component c) { return real_ExitInitializationMode(c); }

fmi2Status fmi2Terminate(fmi2Component c) { return real_Terminate(c); }

fmi2Status fmi2Reset(fmi2Component c)
{
#ifdef MUSCLESIM_GRID_STEP
    pthread_mutex_lock(&lock);
    int i = grid_slot(c);
    if (i >= 0)
        grid[i].steps = 0;
    pthread_mutex_unlock(&lock);
#endif
    return real_Reset(c);
}

#define GET_SET(type) \
    fmi2Status fmi2Get##type(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, \
                             fmi2##type value[]) \
    { return real_Get##type(c, vr, nvr, value); } \
    fmi2Status fmi2Set##type(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, \
                             const fmi2##type value[]) \
    { return real_Set##type(c, vr, nvr, value); }
GET_SET(Real)
GET_SET(Integer)
GET_SET(Boolean)
GET_SET(String)

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state)
{ return real_GetFMUstate(c, state); }

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state)
{ return real_SetFMUstate(c, state); }

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state)
{ return real_FreeFMUstate(c, state); }

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t *size)
{ return real_SerializedFMUstateSize(c, state, size); }

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state, fmi2Byte bytes[],
                                 size_t size)
{ return real_SerializeFMUstate(c, state, bytes, size); }

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size,
                                   fmi2FMUstate *state)
{ return real_DeSerializeFMUstate(c, bytes, size, state); }

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference unknown[],
                                        size_t nUnknown, const fmi2ValueReference known[],
                                        size_t nKnown, const fmi2Real dvKnown[],
                                        fmi2Real dvUnknown[])
{ return real_GetDirectionalDerivative(c, unknown, nUnknown, known, nKnown, dvKnown,
                                       dvUnknown); }

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                       size_t nvr, const fmi2Integer order[],
                                       const fmi2Real value[])
{ return real_SetRealInputDerivatives(c, vr, nvr, order, value); }

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                        size_t nvr, const fmi2Integer order[], fmi2Real value[])
{ return real_GetRealOutputDerivatives(c, vr, nvr, order, value); }

#ifdef MUSCLESIM_GRID_STEP
/* How far (a fraction of the fixed step) a host's time may be from the grid and still be taken
   as on it: far above a clock's drift (the sum of 3.6 million 1 ms steps in doubles is off by
   less than 1e-6 s) and far below half a step, so no step is taken for another. */
#define GRID_TOLERANCE 1e-3

/* FMPy's runtime refuses a step that does not start at its own time or is no whole number of
   fixed steps ("Argument communicationStepSize=4.9e-11 must be an even multiple of
   fixedStepSize=0.001"), as a host that sums its steps sends them at the end of a run. A step
   that starts and ends within the tolerance of the grid is passed on as the whole steps it
   stands for, from the runtime's own time; one that ends where the container already is (the
   drifted last step) is done without stepping. Any other is passed on as it is, for the runtime
   to refuse. */
fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                      fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{
    const double h = MUSCLESIM_GRID_STEP, tol = GRID_TOLERANCE * MUSCLESIM_GRID_STEP;
    pthread_mutex_lock(&lock);
    int i = grid_slot(c);
    double now = i < 0 ? currentCommunicationPoint : grid[i].start + (double)grid[i].steps * h;
    pthread_mutex_unlock(&lock);
    double end = currentCommunicationPoint + communicationStepSize;
    long long n = llround((end - now) / h);
    if (i < 0 || fabs(currentCommunicationPoint - now) > tol || n < 0
        || fabs(end - (now + (double)n * h)) > tol)
        return real_DoStep(c, currentCommunicationPoint, communicationStepSize,
                           noSetFMUStatePriorToCurrentPoint);
    if (n == 0)
        return fmi2OK;
    fmi2Status status = real_DoStep(c, now, (double)n * h, noSetFMUStatePriorToCurrentPoint);
    if (status <= fmi2Warning) {
        pthread_mutex_lock(&lock);
        grid[i].steps += n;
        pthread_mutex_unlock(&lock);
    }
    return status;
}
#else
fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                      fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{ return real_DoStep(c, currentCommunicationPoint, communicationStepSize,
                     noSetFMUStatePriorToCurrentPoint); }
#endif

fmi2Status fmi2CancelStep(fmi2Component c) { return real_CancelStep(c); }

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value)
{ return real_GetStatus(c, s, value); }

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value)
{ return real_GetRealStatus(c, s, value); }

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value)
{ return real_GetIntegerStatus(c, s, value); }

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value)
{ return real_GetBooleanStatus(c, s, value); }

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value)
{ return real_GetStringStatus(c, s, value); }
